// The reader program that runs a third-party reader (src/io/isolated.cpp), here a test
// program around readers that misbehave (isolated_test_reader.cpp): it dies with its
// caller, its time-out, crash and memory refusals name the reader and the cause, and a
// caller whose other threads are busy starts it safely.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "io_test_support.hpp"
#include "readers.hpp"

namespace maxslice::io {
namespace {

using test::contains;

detail::ReaderCommand test_reader(std::vector<std::string> args) {
    return {MAXSLICE_ISOLATED_TEST_READER, std::move(args)};
}

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
    // the reader program must end too (it used to run on with no limit). This test process
    // becomes a subreaper so that the orphaned reader is its own to wait for.
    ASSERT_EQ(::prctl(PR_SET_CHILD_SUBREAPER, 1), 0);
    test::ScratchDir dir;
    const std::string pid_file = (dir.path() / "reader.pid").string();
    const pid_t parent = ::fork();
    ASSERT_GE(parent, 0);
    if (parent == 0) {
        auto ignored =
            detail::run_isolated(test_reader({"pid", pid_file}), 0.0, "test reader", "test");
        (void)ignored;
        ::_exit(0);
    }
    pid_t child = -1;
    for (int i = 0; i < 3000 && child <= 0; ++i) {
        std::ifstream in(pid_file);
        if (!(in >> child)) {
            child = -1;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    }
    ASSERT_GT(child, 0) << "the reader program did not start";
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
    auto r = detail::run_isolated(test_reader({"pause"}), 0.05, "lib3mf",
                                  "the reader took too long on this file");
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
    if (MAXSLICE_ADDRESS_SANITIZER) {
        GTEST_SKIP() << "AddressSanitizer needs the address space; the bound is left out there";
    }
    const double machine = static_cast<double>(::sysconf(_SC_PHYS_PAGES)) *
                           static_cast<double>(::sysconf(_SC_PAGESIZE));
    const auto too_much =
        static_cast<std::size_t>(detail::kReaderMemoryShare * machine) + (std::size_t{1} << 30);
    auto r = detail::run_isolated(test_reader({"allocate", std::to_string(too_much)}), 60.0,
                                  "lib3mf", "test");
    ASSERT_FALSE(r) << "a reader was given more than its share of the memory";
    EXPECT_TRUE(contains(r.error().message, "lib3mf ran out of the memory a part reader may use"))
        << r.error().describe();
}

TEST(Isolated, TheMeshAndTheRefusalCrossIntact) {
    auto r = detail::run_isolated(test_reader({"mesh"}), 60.0, "test reader", "test");
    ASSERT_TRUE(r) << r.error().describe();
    ASSERT_EQ(r->mesh.triangles.size(), 1u);
    ASSERT_EQ(r->mesh.vertices.size(), 3u);
    EXPECT_EQ(r->mesh.vertices[1].x, 1.0);
    EXPECT_EQ(r->mesh.vertices[2].y, 1.0);
    ASSERT_EQ(r->warnings.size(), 1u);
    EXPECT_EQ(r->warnings[0], "read by the test reader");

    auto refused = detail::run_isolated(test_reader({"error"}), 60.0, "test reader", "test");
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.error().code, core::ErrorCode::kInvalidInput);
    EXPECT_EQ(refused.error().message, "the test reader refuses this");
}

TEST(Isolated, AReaderKilledBySignalIsACrashOfTheLibrary) {
    auto r = detail::run_isolated(test_reader({"kill"}), 60.0, "Open CASCADE", "test");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    EXPECT_TRUE(contains(r.error().message, "Open CASCADE crashed reading the file (signal 9"))
        << r.error().describe();
}

// A sanitizer report on maxslice's own code in the reader is a bug to fix, not a damaged file:
// it must not pass for a refusal (the fuzzers and the sanitizer tests would miss it).
TEST(Isolated, ASanitizerReportInTheReaderIsAnInternalError) {
    if (!MAXSLICE_ADDRESS_SANITIZER) GTEST_SKIP() << "only a sanitizer build reports the overflow";
    auto r = detail::run_isolated(test_reader({"overflow"}), 60.0, "lib3mf", "test");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kInternal) << r.error().describe();
    EXPECT_TRUE(contains(r.error().message, "lib3mf reader program stopped on a sanitizer report"))
        << r.error().describe();
}

TEST(Isolated, AMissingReaderProgramCannotBeStarted) {
    auto r = detail::run_isolated({"/nonexistent/maxslice-read-part", {}}, 60.0, "assimp", "t");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kIo);
    EXPECT_TRUE(contains(r.error().message, "cannot start the assimp reader")) << r.error().message;
}

// The reader used to be a fork of the caller: a child holds only the forking thread, and a
// lock another thread held at that moment (the allocator's) stayed held in the child for
// ever; maxslice has such threads from its start (a library's thread pool). Here two threads
// allocate without pause while readers are started: each must finish, well within the limit.
TEST(Isolated, ReadersStartCleanlyWhileOtherThreadsAllocate) {
    std::atomic<bool> stop{false};
    std::vector<std::thread> busy;
    for (int t = 0; t < 2; ++t) {
        busy.emplace_back([&stop] {
            std::vector<std::unique_ptr<char[]>> blocks(64);
            std::size_t i = 0;
            while (!stop.load(std::memory_order_relaxed)) {
                blocks[i % blocks.size()] = std::make_unique<char[]>(16 + (i * 7919) % 4096);
                ++i;
            }
        });
    }
    int read = 0;
    for (int i = 0; i < 40; ++i) {
        auto r = detail::run_isolated(test_reader({"mesh"}), 60.0, "test reader", "test");
        if (!r) {
            ADD_FAILURE() << r.error().describe();
            break;
        }
        read += r->mesh.triangles.size() == 1 ? 1 : 0;
    }
    stop = true;
    for (std::thread& t : busy) t.join();
    EXPECT_EQ(read, 40);
}

}  // namespace
}  // namespace maxslice::io
