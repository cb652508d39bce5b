// What maxslice promises a user about their files and its own bounds: an output never
// overwrites an input, a failed write leaves the previous output as it was, a report that
// cannot be printed is an error, absurd layer heights are refused before any work, and an
// error message is one readable line whatever bytes it quotes.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"

namespace fs = std::filesystem;
using maxslice::test::CliRun;
using maxslice::test::kExample;
using maxslice::test::kSource;
using maxslice::test::run_cli;
using maxslice::test::shell_quote;
using maxslice::test::slurp;

namespace {

fs::path temp_dir(const std::string& name) {
    return maxslice::test::fresh_temp_dir("safety_test", name);
}

// A refusal: exit 2 and one "maxslice: error:" line that contains `words`.
void expect_refusal(const CliRun& r, const std::string& words, const std::string& what) {
    EXPECT_EQ(r.exit_code, 2) << what << "\n" << r.err;
    const auto at = r.err.find("maxslice: error: ");
    ASSERT_NE(at, std::string::npos) << what << "\n" << r.err;
    const std::string line = r.err.substr(at);
    EXPECT_EQ(std::count(line.begin(), line.end(), '\n'), 1) << what << "\n" << r.err;
    EXPECT_NE(line.find(words), std::string::npos) << what << "\n" << r.err;
}

std::vector<std::string> names_in(const fs::path& dir) {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

TEST(Safety, AnEmptyOutputPathIsRefused) {
    expect_refusal(run_cli({"slice", kExample.string(), "-o", ""}), "empty", "-o ''");
    expect_refusal(run_cli({"plan", kExample.string(), "--plan", ""}), "empty", "--plan ''");
}

TEST(Safety, AnOutputThatNamesAnInputIsRefusedAndTheInputKept) {
    const fs::path d = temp_dir("same");
    const fs::path part = d / "part.stl", profile = d / "cell.toml";
    fs::copy_file(kExample, part);
    fs::copy_file(kSource / "examples/profiles/reference_lmd.toml", profile);
    fs::create_symlink(part, d / "alias.stl");
    const std::string part_bytes = slurp(part), profile_bytes = slurp(profile);
    const std::vector<std::vector<std::string>> runs = {
        {"slice", part.string(), "-o", part.string()},
        {"slice", part.string(), "-o", (d / "." / "part.stl").string()},
        {"slice", (d / "alias.stl").string(), "-o", part.string()},
        {"slice", part.string(), "-o", (d / "p.gm").string(), "--profile", profile.string(),
         "--json", profile.string()},
        {"slice", part.string(), "--contact-sheet", part.string()},
        {"plan", part.string(), "--plan", part.string()},
        {"plan", part.string(), "--profile", profile.string(), "--dot", profile.string()},
    };
    for (const auto& args : runs) {
        expect_refusal(run_cli(args), "would overwrite the input", args[0] + " " + args[3]);
    }
    EXPECT_EQ(slurp(part), part_bytes);
    EXPECT_EQ(slurp(profile), profile_bytes);
    EXPECT_FALSE(fs::exists(d / "p.gm")) << "refused before any work";
}

// A full disk, injected as the file size limit (the write fails with EFBIG as it would with
// ENOSPC): the run fails naming the cause, the previous program is left whole, and no
// temporary file stays behind.
TEST(Safety, AFailedWriteKeepsThePreviousProgram) {
    const fs::path d = temp_dir("full");
    const fs::path out = d / "part.gm";
    const CliRun first = run_cli({"slice", kExample.string(), "-o", out.string()});
    ASSERT_EQ(first.exit_code, 0) << first.err;
    const std::string previous = slurp(out);
    ASSERT_GT(previous.size(), 200'000u);
    // 100 blocks of 1 KiB: less than the program, more than the printed summary.
    const CliRun r = run_cli({"slice", kExample.string(), "-o", out.string(), "--layer", "0.4"},
                             300, "ulimit -f 100; trap '' XFSZ; ");
    expect_refusal(r, "File too large", "write under a 100 KiB file limit");
    EXPECT_NE(r.err.find("unchanged"), std::string::npos) << r.err;
    EXPECT_EQ(slurp(out), previous);
    EXPECT_EQ(names_in(d), std::vector<std::string>{"part.gm"});
}

TEST(Safety, AFullDeviceOrStdoutIsAnError) {
    expect_refusal(run_cli({"slice", kExample.string(), "-o", "/dev/full"}),
                   "No space left on device", "-o /dev/full");
    // Small previews too (they used to come out empty with exit 0).
    expect_refusal(run_cli({"slice", kExample.string(), "--json", "/dev/full"}),
                   "No space left on device", "--json /dev/full");
    expect_refusal(run_cli({"slice", kExample.string(), "--contact-sheet", "/dev/full"}),
                   "No space left on device", "--contact-sheet /dev/full");
    const std::string cmd = shell_quote(MAXSLICE_CLI) + " info " + shell_quote(kExample.string()) +
                            " >/dev/full 2>/dev/null";
    const int status = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 2) << "info printed into a full device";
}

// Layer heights that would make millions of layers are refused at once, naming the flag and
// a thickness that fits, on the planar slicer, the adaptive slicer, the planar program job
// and the 5-axis planner (a profile whose process allows 10 um layers).
TEST(Safety, AbsurdLayerHeightsAreRefusedBeforeAnyWork) {
    const fs::path d = temp_dir("layers");
    const auto tiny_profile = [&](const std::string& name) {
        std::string text = slurp(kSource / "examples/profiles" / name);
        for (const std::string key : {"layer_height_mm = ", "h_min_mm = "}) {
            const auto at = text.find("\n" + key);
            EXPECT_NE(at, std::string::npos) << key;
            const auto end = text.find('\n', at + 1);
            text.replace(at, end - at, "\n" + key + "0.00001");
        }
        const fs::path file = d / ("tiny_" + name);
        std::ofstream(file) << text;
        return file.string();
    };
    const std::string part = kExample.string(), out = (d / "x.gm").string();
    const std::string planar = tiny_profile("reference_lmd.toml");
    const std::string five_axis = tiny_profile("reference_5axis_ac.toml");
    const struct {
        std::vector<std::string> args;
        std::string flag;
    } cases[] = {
        {{"slice", part, "--layer", "1e-6"}, "(--layer)"},
        {{"slice", part, "--layer", "1e-5"}, "(--layer)"},
        {{"slice", part, "--adaptive", "--min-layer", "1e-9"}, "(--min-layer)"},
        {{"slice", part, "-o", out, "--profile", planar}, "(--layer)"},
        {{"slice", part, "-o", out, "--profile", five_axis}, "process.h_min_mm"},
        {{"plan", part, "--profile", five_axis}, "process.h_min_mm"},
    };
    for (const auto& c : cases) {
        const CliRun r = run_cli(c.args, 120);
        expect_refusal(r, c.flag, c.args[2] + " " + c.args[3] + " " + c.args.back());
        EXPECT_NE(r.err.find("more than the 100000 a job may cut"), std::string::npos) << r.err;
    }
    EXPECT_FALSE(fs::exists(out));
}

// A file name or a file's bytes quoted in a message cannot drive the terminal, and a message
// stays one line.
TEST(Safety, MessagesEscapeControlBytes) {
    const fs::path d = temp_dir("escape");
    const std::string name = (d / "part\x1b[2J\nmore.stl").string();
    const CliRun r = run_cli({"info", name});
    expect_refusal(r, "\\x1B[2J\\x0Amore.stl", "a name with an escape sequence");
    EXPECT_EQ(r.err.find('\x1b'), std::string::npos);
}

// A FIFO (no writer: opening it to read would block forever) or a device given as an input
// is refused before anything opens it.
TEST(Safety, AnInputThatIsNotARegularFileIsRefusedAtOnce) {
    const fs::path d = temp_dir("fifo");
    const fs::path fifo = d / "part.stl";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const std::string out = (d / "x.gm").string();
    expect_refusal(run_cli({"info", fifo.string()}, 30), "FIFO", "info FIFO");
    expect_refusal(run_cli({"slice", fifo.string(), "-o", out}, 30), "FIFO", "slice FIFO");
    expect_refusal(run_cli({"plan", kExample.string(), "--profile", fifo.string()}, 30), "FIFO",
                   "plan --profile FIFO");
    expect_refusal(run_cli({"slice", "/dev/zero", "-o", out}, 30), "not a regular file",
                   "slice /dev/zero");
}
