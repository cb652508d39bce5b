#pragma once
// Shared by the mesh reader harnesses. Any refusal is fine; a crash, hang, leak, sanitizer
// report, an error code other than kInvalidInput/kIo/kUnsupported, an empty message, or a
// mesh that breaks its invariants (an index past the vertices, a non-finite vertex) is a bug.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

#include "maxslice/io/read_mesh.hpp"
#include "readers.hpp"

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

/// The bytes as scratch_dir()/input<extension>, for the readers that take a path.
inline std::filesystem::path write_input(const std::uint8_t* data, std::size_t size,
                                         std::string_view extension) {
    const std::filesystem::path path = scratch_dir() / ("input" + std::string(extension));
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) std::abort();
    if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
    std::fclose(f);
    return path;
}

inline void check_error(const core::Error& e) {
    check(e.code == core::ErrorCode::kInvalidInput || e.code == core::ErrorCode::kIo ||
              e.code == core::ErrorCode::kUnsupported,
          "refusal code is kInvalidInput, kIo or kUnsupported");
    check(!e.message.empty(), "refusal has a message");
}

inline void check_mesh(const mesh::TriangleMesh& m) {
    for (const mesh::Triangle& t : m.triangles) {
        for (const std::uint32_t v : t) check(v < m.vertices.size(), "indices point at vertices");
    }
    for (const core::Vec3d& v : m.vertices) check(core::is_finite(v), "vertices are finite");
}

/// A format reader's result (the readers behind read_mesh, called in this process).
inline int check_raw(const core::Result<io::detail::RawImport>& raw) {
    if (!raw) {
        check_error(raw.error());
        return 0;
    }
    check_mesh(raw->mesh);
    return 0;
}

/// Writes the bytes to scratch_dir()/input<extension> and reads it back with read_mesh (the
/// whole path a user's file takes: sniffing, the reader, units, the finite check).
inline int read_as(const std::uint8_t* data, std::size_t size, std::string_view extension) {
    const std::filesystem::path path = write_input(data, size, extension);
    io::ImportOptions options;
    // Coarse tessellation keeps CAD inputs fast; the readers' logic is the same.
    options.chord_deviation_mm = 0.5;
    options.angular_deviation_deg = 30.0;
    options.library_time_limit_s = 10.0;
    const auto result = io::read_mesh(path, options);
    if (!result) {
        check_error(result.error());
        check(result.error().context.find("input") != std::string::npos, "refusal names the file");
        return 0;
    }
    check(!result->mesh.triangles.empty(), "an accepted mesh has triangles");
    check_mesh(result->mesh);
    return 0;
}

}  // namespace maxslice::fuzz
