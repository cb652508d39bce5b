// Input checks and output files: a special file is refused before it is opened, an output is
// replaced whole or not at all, and messages are one readable line.
#include "maxslice/core/files.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;
using maxslice::core::check_input_file;
using maxslice::core::check_output_not_input;
using maxslice::core::printable;
using maxslice::core::write_file_atomic;

namespace {

fs::path temp_dir(const std::string& name) {
    const fs::path d = fs::temp_directory_path() /
                       ("maxslice_files_test_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

std::size_t entries(const fs::path& dir) {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), {}));
}

}  // namespace

TEST(Printable, EscapesControlBytesAndKeepsUtf8) {
    EXPECT_EQ(printable("plain text 1.5 mm"), "plain text 1.5 mm");
    const std::string esc = printable("G1 X\x1b[31mred\nnext\r");
    EXPECT_EQ(esc.find('\x1b'), std::string::npos);
    EXPECT_EQ(esc.find('\n'), std::string::npos);
    EXPECT_EQ(esc.find('\r'), std::string::npos);
    EXPECT_NE(esc.find("\\x1B[31mred\\x0Anext\\x0D"), std::string::npos) << esc;
    // UTF-8 letters pass; a C1 control encoded in UTF-8 (CSI, U+009B) and a stray byte do not.
    EXPECT_EQ(printable("Dübel Ø12"), "Dübel Ø12");
    EXPECT_EQ(printable("a\xC2\x9B"
                        "b"),
              "a\\xC2\\x9Bb");
    EXPECT_EQ(printable("a\xFF"), "a\\xFF");
    EXPECT_EQ(printable("\xE2\x82"), "\\xE2\\x82");  // a sequence cut short
}

TEST(Printable, CutsLongTextAndSaysHowMuchIsLeft) {
    const std::string digits(1'000'000, '7');
    const std::string line = printable(digits, 100);
    EXPECT_LT(line.size(), 140u);
    EXPECT_EQ(line.substr(0, 100), digits.substr(0, 100));
    EXPECT_NE(line.find("999900 more bytes"), std::string::npos) << line;
}

TEST(CheckInputFile, RefusesWhatIsNotARegularFileWithoutOpeningIt) {
    const fs::path d = temp_dir("input");
    const fs::path file = d / "part.stl";
    std::ofstream(file) << "solid x\nendsolid x\n";
    EXPECT_TRUE(check_input_file(file, "part file"));

    // A FIFO with no writer: opening it for reading would block forever.
    const fs::path fifo = d / "fifo.stl";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
    auto r = check_input_file(fifo, "part file");
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("FIFO"), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("part file"), std::string::npos);

    r = check_input_file(d, "part file");
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("directory"), std::string::npos) << r.error().message;

    r = check_input_file(d / "missing.stl", "profile");
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find(std::strerror(ENOENT)), std::string::npos);

    r = check_input_file("/dev/null", "program");
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("character device"), std::string::npos);
    fs::remove_all(d);
}

TEST(WriteFileAtomic, WritesAndReplacesWholeFilesKeepingTheirMode) {
    const fs::path d = temp_dir("write");
    const fs::path out = d / "part.gm";
    ASSERT_TRUE(write_file_atomic(out, "first\n"));
    EXPECT_EQ(read(out), "first\n");
    ::chmod(out.c_str(), 0640);
    ASSERT_TRUE(write_file_atomic(out, "second program\n"));
    EXPECT_EQ(read(out), "second program\n");
    struct stat st {};
    ASSERT_EQ(::stat(out.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 07777, 0640u);
    EXPECT_EQ(entries(d), 1u) << "no temporary file is left beside the output";

    // Through a link the linked file is replaced and the link stays a link.
    const fs::path link = d / "link.gm";
    fs::create_symlink(out, link);
    ASSERT_TRUE(write_file_atomic(link, "third\n"));
    EXPECT_TRUE(fs::is_symlink(link));
    EXPECT_EQ(read(out), "third\n");
    fs::remove_all(d);
}

TEST(WriteFileAtomic, RefusesEmptyPathsAndFolders) {
    const fs::path d = temp_dir("refuse");
    auto r = write_file_atomic("", "x");
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("empty"), std::string::npos);
    r = write_file_atomic(d, "x");
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("directory"), std::string::npos);
    r = write_file_atomic(d / "no_such_folder" / "x.gm", "x");
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find(std::strerror(ENOENT)), std::string::npos);
    fs::remove_all(d);
}

// A write that fails part way (here the file size limit, as a full disk would) leaves the
// previous file as it was, no temporary file behind, and names the cause.
TEST(WriteFileAtomic, AFailedWriteKeepsThePreviousFile) {
    const fs::path d = temp_dir("fail");
    const fs::path out = d / "part.gm";
    const std::string previous = "the previous program\n";
    std::ofstream(out) << previous;
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        std::signal(SIGXFSZ, SIG_IGN);
        struct rlimit lim {
            4096, 4096
        };
        ::setrlimit(RLIMIT_FSIZE, &lim);
        auto r = write_file_atomic(out, std::string(100'000, 'G'));
        const bool named = !r &&
                           r.error().message.find(std::strerror(EFBIG)) != std::string::npos &&
                           r.error().message.find("unchanged") != std::string::npos;
        ::_exit(named ? 0 : 1);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << "the write must fail and name the cause";
    EXPECT_EQ(read(out), previous);
    EXPECT_EQ(entries(d), 1u);
    fs::remove_all(d);
}

TEST(WriteFileAtomic, WritesStraightIntoDevices) {
    EXPECT_TRUE(write_file_atomic("/dev/null", "nothing"));
    auto r = write_file_atomic("/dev/full", "a program");
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find(std::strerror(ENOSPC)), std::string::npos)
        << r.error().message;
}

TEST(CheckOutputNotInput, RefusesAnyNameOfAnInput) {
    const fs::path d = temp_dir("same");
    const fs::path part = d / "part.stl", profile = d / "cell.toml";
    std::ofstream(part) << "solid\n";
    std::ofstream(profile) << "[machine]\n";
    fs::create_symlink(part, d / "alias.stl");
    const std::vector<fs::path> inputs{part, profile};
    EXPECT_FALSE(check_output_not_input(part, "-o", inputs));
    EXPECT_FALSE(check_output_not_input(d / "." / "cell.toml", "--json", inputs));
    EXPECT_FALSE(check_output_not_input(d / "alias.stl", "-o", inputs));
    EXPECT_TRUE(check_output_not_input(d / "part.gm", "-o", inputs));
    auto r = check_output_not_input(profile, "--json", inputs);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("overwrite"), std::string::npos);
    EXPECT_NE(r.error().context.find("--json"), std::string::npos);
    // An input that does not exist yet is compared by its normalised path.
    EXPECT_FALSE(check_output_not_input(d / "sub" / ".." / "new.stl", "-o", {d / "new.stl"}));
    fs::remove_all(d);
}
