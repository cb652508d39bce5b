// A reader program for isolated_test.cpp: serve_isolated (src/io/isolated.cpp) around
// readers that behave as a library can on a hostile file. The first argument picks one:
//   mesh            one triangle
//   error           a refusal
//   pid FILE        writes its pid to FILE, then never finishes
//   pause           never finishes
//   allocate BYTES  allocates BYTES (touching one page) and returns nothing
//   kill            ends by an uncatchable signal, as a crash does
//   overflow        reads past a heap block (a sanitizer report in sanitizer builds)
#include <signal.h>
#include <unistd.h>

#include <charconv>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "readers.hpp"

namespace {

using maxslice::core::Result;
using maxslice::io::detail::RawImport;

Result<RawImport> read_part(std::span<const std::string_view> args) {
    const std::string_view mode = args.empty() ? "" : args[0];
    if (mode == "mesh") {
        RawImport out;
        out.mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
        out.mesh.triangles = {{0, 1, 2}};
        out.warnings = {"read by the test reader"};
        return out;
    }
    if (mode == "pid" && args.size() == 2) {
        const std::string file(args[1]);
        { std::ofstream(file + ".part") << ::getpid() << '\n'; }
        std::filesystem::rename(file + ".part", file);  // whole, or not there
        while (true) ::pause();
    }
    if (mode == "pause") {
        while (true) ::pause();
    }
    if (mode == "allocate" && args.size() == 2) {
        std::size_t bytes = 0;
        std::from_chars(args[1].data(), args[1].data() + args[1].size(), bytes);
        std::unique_ptr<char[]> block(new char[bytes]);
        volatile char* first = block.get();  // one page used: the allocation stays
        *first = 1;
        return RawImport{};
    }
    if (mode == "kill") ::raise(SIGKILL);
    if (mode == "overflow") {
        // A heap overflow in the reader's own code: a sanitizer report in sanitizer builds
        // (isolated_test.cpp runs this mode only there).
        std::unique_ptr<char[]> block(new char[16]);
        volatile char* p = block.get();
        const std::size_t past = args.size() + 15;  // 16 with the mode alone
        return maxslice::core::fail(maxslice::core::ErrorCode::kInvalidInput,
                                    std::string(1, p[past]));
    }
    return maxslice::core::fail(maxslice::core::ErrorCode::kInvalidInput,
                                "the test reader refuses this");
}

}  // namespace

int main(int argc, char** argv) {
    maxslice::io::detail::serve_isolated(argc, argv, read_part);
}
