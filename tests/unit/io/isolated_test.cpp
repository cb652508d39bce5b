// The child process that runs a third-party reader (src/io/isolated.cpp): it dies with its
// parent, and its time-out names the reader and the cause.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <memory>
#include <string>
#include <thread>

#include "io_test_support.hpp"
#include "readers.hpp"

namespace maxslice::io {
namespace {

using test::contains;

// True once process `pid` has ended: gone, or a zombie nobody has reaped yet.
bool has_ended(pid_t pid) {
    std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
    if (!stat) return true;
    std::string text((std::istreambuf_iterator<char>(stat)), {});
    const std::size_t close = text.rfind(')');
    return close == std::string::npos || close + 2 >= text.size() || text[close + 2] == 'Z' ||
           text[close + 2] == 'X';
}

TEST(Isolated, ReaderChildDiesWithItsParent) {
    // A parent process runs a reader that never finishes, with no time limit, and is killed:
    // the reader child must end too (it used to run on with no limit). This test process
    // becomes a subreaper so that the orphaned child is its own to wait for.
    ASSERT_EQ(::prctl(PR_SET_CHILD_SUBREAPER, 1), 0);
    int fds[2];
    ASSERT_EQ(::pipe(fds), 0);
    const pid_t parent = ::fork();
    ASSERT_GE(parent, 0);
    if (parent == 0) {
        ::close(fds[0]);
        const int out = fds[1];
        auto ignored = detail::run_isolated(
            [out]() -> core::Result<detail::RawImport> {
                const pid_t me = ::getpid();
                if (::write(out, &me, sizeof me) != sizeof me) ::_exit(3);
                while (true) ::pause();
            },
            0.0, "test reader", "test");
        (void)ignored;
        ::_exit(0);
    }
    ::close(fds[1]);
    pid_t child = -1;
    ASSERT_EQ(::read(fds[0], &child, sizeof child), static_cast<ssize_t>(sizeof child));
    ::close(fds[0]);
    ASSERT_GT(child, 0);
    ASSERT_EQ(::kill(parent, SIGKILL), 0);
    int status = 0;
    ASSERT_EQ(::waitpid(parent, &status, 0), parent);

    // The death signal is immediate; 30 s only bounds a failing run.
    bool ended = false;
    for (int i = 0; i < 3000 && !ended; ++i) {
        ended = has_ended(child);
        if (!ended) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    EXPECT_TRUE(ended) << "the reader child outlived its parent";
    if (!ended) ::kill(child, SIGKILL);
    ::waitpid(child, &status, 0);  // reaped here: this process is the subreaper
    ::prctl(PR_SET_CHILD_SUBREAPER, 0);
}

TEST(Isolated, TimeOutNamesTheReaderAndTheCause) {
    auto r = detail::run_isolated(
        []() -> core::Result<detail::RawImport> {
            while (true) ::pause();
        },
        0.05, "lib3mf", "the reader took too long on this file");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    EXPECT_TRUE(contains(r.error().message,
                         "lib3mf did not finish reading the file within the 0.05 s limit for a "
                         "part reader and was stopped: the reader took too long on this file"))
        << r.error().describe();
    EXPECT_FALSE(contains(r.error().message, "chord")) << r.error().describe();
}

// A reader that needs more memory than its share (a 3MF that inflates to gigabytes) is
// refused with that cause, not left to swap or the OOM killer. Only the allocation's first
// page is touched: without the bound it succeeds (and the test fails) without using the
// memory.
TEST(Isolated, AReaderThatExceedsItsMemoryShareIsRefused) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "AddressSanitizer needs the address space; the bound is left out there";
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
    GTEST_SKIP() << "AddressSanitizer needs the address space; the bound is left out there";
#endif
#endif
    const double machine = static_cast<double>(::sysconf(_SC_PHYS_PAGES)) *
                           static_cast<double>(::sysconf(_SC_PAGESIZE));
    const auto too_much =
        static_cast<std::size_t>(detail::kReaderMemoryShare * machine) + (std::size_t{1} << 30);
    auto r = detail::run_isolated(
        [too_much]() -> core::Result<detail::RawImport> {
            std::unique_ptr<char[]> block(new char[too_much]);
            volatile char* first = block.get();  // one page used: the allocation stays
            *first = 1;
            return detail::RawImport{};
        },
        60.0, "lib3mf", "test");
    ASSERT_FALSE(r) << "a reader was given more than its share of the memory";
    EXPECT_TRUE(contains(r.error().message, "lib3mf ran out of the memory a part reader may use"))
        << r.error().describe();
}

}  // namespace
}  // namespace maxslice::io
