#include <fmt/format.h>

#include <bit>
#include <cstring>
#include <limits>
#include <vector>

#include "maxslice/core/files.hpp"
#include "maxslice/io/read_mesh.hpp"

namespace maxslice::io {
namespace {

void put_u32(char* p, std::uint32_t v) {
    if constexpr (std::endian::native == std::endian::big) v = std::byteswap(v);
    std::memcpy(p, &v, 4);
}

void put_f32(char* p, double d) {
    put_u32(p, std::bit_cast<std::uint32_t>(static_cast<float>(d)));
}

}  // namespace

core::Result<void> write_stl_binary(const std::filesystem::path& path,
                                    const mesh::TriangleMesh& mesh) {
    const std::string context = "file " + path.string();
    const std::size_t n = mesh.triangles.size();
    if (n > std::numeric_limits<std::uint32_t>::max()) {
        return core::fail(core::ErrorCode::kInvalidInput,
                          fmt::format("{} triangles do not fit a binary STL", n), context);
    }
    for (const mesh::Triangle& t : mesh.triangles) {
        for (const std::uint32_t v : t) {
            if (v >= mesh.vertices.size()) {
                return core::fail(core::ErrorCode::kInvalidInput,
                                  "a triangle refers to a vertex that does not exist", context);
            }
        }
    }
    std::vector<char> bytes;
    try {
        bytes.assign(84 + 50 * n, '\0');
    } catch (const std::bad_alloc&) {
        return core::fail(core::ErrorCode::kIo, "not enough memory to write the STL", context);
    }
    constexpr std::string_view kHeader = "binary STL written by maxslice, units mm";
    std::memcpy(bytes.data(), kHeader.data(), kHeader.size());
    put_u32(bytes.data() + 80, static_cast<std::uint32_t>(n));
    char* rec = bytes.data() + 84;
    for (std::size_t t = 0; t < n; ++t, rec += 50) {
        const core::Vec3d normal = core::normalized(mesh::area_vector(mesh, t));
        put_f32(rec, normal.x);
        put_f32(rec + 4, normal.y);
        put_f32(rec + 8, normal.z);
        for (int k = 0; k < 3; ++k) {
            const core::Vec3d p = mesh.corner(t, k);
            put_f32(rec + 12 + 12 * k, p.x);
            put_f32(rec + 16 + 12 * k, p.y);
            put_f32(rec + 20 + 12 * k, p.z);
        }
    }
    if (auto ok = core::write_file_atomic(path, {bytes.data(), bytes.size()}); !ok) {
        return std::unexpected(ok.error());
    }
    return {};
}

}  // namespace maxslice::io
