#pragma once
// Shared by the reader harnesses: the input goes to a file (read_mesh reads paths, and the
// libraries behind it read files), read_mesh runs, and the result is checked. Any refusal is
// fine; a crash, hang, leak, sanitizer report, an error code other than kInvalidInput/kIo, or
// a mesh that breaks its invariants is a bug.

#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

#include "maxslice/io/read_mesh.hpp"

// Leaks inside Open CASCADE (one-time controller set-up) and lib3mf/libzip (about 160 bytes
// per zip entry) that maxslice cannot free: see tests/unit/io/lsan_suppressions.cpp.
// Each harness is a single translation unit, so this is defined once per program.
extern "C" const char* __lsan_default_suppressions() {
    return "leak:libTKernel.so\nleak:libTKXSBase.so\nleak:libTKSTEP.so\nleak:libTKIGES.so\n"
           "leak:libzip.so\n";
}

namespace maxslice::fuzz {

/// A directory of this process's own, created once and removed at exit.
inline const std::filesystem::path& scratch_dir() {
    static const std::filesystem::path dir = [] {
        std::string tmpl = (std::filesystem::temp_directory_path() / "maxslice_fuzz_XXXXXX");
        if (::mkdtemp(tmpl.data()) == nullptr) std::abort();
        std::atexit([] {
            std::error_code ec;
            std::filesystem::remove_all(scratch_dir(), ec);
        });
        return std::filesystem::path(tmpl);
    }();
    return dir;
}

inline void check(bool ok, const char* what) {
    if (!ok) {
        std::fprintf(stderr, "maxslice fuzz: invariant broken: %s\n", what);
        std::abort();
    }
}

/// Writes the bytes to scratch_dir()/input<extension> and reads it back with read_mesh.
inline int read_as(const std::uint8_t* data, std::size_t size, std::string_view extension) {
    const std::filesystem::path path = scratch_dir() / ("input" + std::string(extension));
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) std::abort();
    if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
    std::fclose(f);

    io::ImportOptions options;
    // Coarse tessellation keeps CAD inputs fast; the readers' logic is the same.
    options.chord_deviation_mm = 0.5;
    options.angular_deviation_deg = 30.0;
    const auto result = io::read_mesh(path, options);
    if (!result) {
        const core::Error& e = result.error();
        check(e.code == core::ErrorCode::kInvalidInput || e.code == core::ErrorCode::kIo,
              "refusal code is kInvalidInput or kIo");
        check(!e.message.empty(), "refusal has a message");
        check(e.context.find("input") != std::string::npos, "refusal names the file");
        return 0;
    }
    const mesh::TriangleMesh& m = result->mesh;
    check(!m.triangles.empty(), "an accepted mesh has triangles");
    for (const mesh::Triangle& t : m.triangles) {
        for (const std::uint32_t v : t) check(v < m.vertices.size(), "indices point at vertices");
    }
    for (const core::Vec3d& v : m.vertices) check(core::is_finite(v), "vertices are finite");
    return 0;
}

}  // namespace maxslice::fuzz
