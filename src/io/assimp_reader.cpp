// OBJ through assimp (PLY and OFF have their own reader: ply_off_reader.cpp says why).
// Assimp parses; polygons are cut here by the same ear clipping as PLY and OFF
// (polygon_soup.cpp), not by aiProcess_Triangulate, which took minutes on a face of many
// corners and left degenerate triangles in concave ones (a comb of 8192 corners: 4092).
// Vertices are welded by mesh::weld_exact like every other format. Assimp reads from our copy
// of the bytes so that the text can be checked first (scan_obj) and UTF-16 converted; every
// index assimp hands back is checked again before use, and every exception it might throw is
// caught here.

#include <assimp/scene.h>
#include <fmt/format.h>
#include <assimp/Importer.hpp>

#include <cmath>
#include <exception>
#include <string>
#include <vector>

#include "polygon_soup.hpp"
#include "readers.hpp"

namespace maxslice::io::detail {
namespace {

struct Collected {
    std::vector<double> xyz;
    std::size_t meshes_with_triangles = 0;
    std::size_t non_triangles = 0;  // points and lines assimp kept as primitives
    std::size_t bad_indices = 0;
    std::size_t polygons = 0;
    std::size_t fanned = 0;  // polygons ear clipping could not cut cleanly
    std::size_t too_large = 0;
};

// Walks the node tree so node transforms are applied (OBJ puts every mesh under the
// identity root, but nothing stops a file from nesting them).
void collect(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, int depth,
             Collected& out) {
    if (depth > 64) return;
    const aiMatrix4x4 world = parent * node.mTransformation;
    const bool identity = world.IsIdentity();
    const bool mirrored = world.Determinant() < 0.0f;
    std::vector<core::Vec3d> vertices;
    std::vector<std::uint32_t> polygon;
    for (unsigned m = 0; m < node.mNumMeshes; ++m) {
        if (node.mMeshes == nullptr || node.mMeshes[m] >= scene.mNumMeshes) {
            ++out.bad_indices;
            continue;
        }
        const aiMesh* mesh = scene.mMeshes[node.mMeshes[m]];
        if (mesh == nullptr || mesh->mVertices == nullptr || mesh->mFaces == nullptr) continue;
        vertices.resize(mesh->mNumVertices);
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
            aiVector3D p = mesh->mVertices[v];
            if (!identity) p = world * p;
            vertices[v] = {static_cast<double>(p.x), static_cast<double>(p.y),
                           static_cast<double>(p.z)};
        }
        PolygonSoup soup(vertices);
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
            const aiFace& face = mesh->mFaces[f];
            if (face.mNumIndices < 3 || face.mIndices == nullptr) {
                ++out.non_triangles;
                continue;
            }
            if (face.mNumIndices > kMaxPolygonCorners) {  // scan_obj refuses these first
                ++out.too_large;
                continue;
            }
            bool ok = true;
            polygon.resize(face.mNumIndices);
            for (unsigned k = 0; k < face.mNumIndices; ++k) {
                // Reversed order for a mirroring transform keeps the outside outside.
                const unsigned at = mirrored ? face.mNumIndices - 1 - k : k;
                ok = ok && face.mIndices[at] < mesh->mNumVertices;
                polygon[k] = face.mIndices[at];
            }
            if (!ok) {
                ++out.bad_indices;
                continue;
            }
            if (face.mNumIndices > 3) ++out.polygons;
            soup.add(polygon);
        }
        out.fanned += soup.fanned_faces();
        if (!soup.xyz().empty()) {
            ++out.meshes_with_triangles;
            out.xyz.insert(out.xyz.end(), soup.xyz().begin(), soup.xyz().end());
        }
    }
    for (unsigned c = 0; c < node.mNumChildren; ++c) {
        if (node.mChildren != nullptr && node.mChildren[c] != nullptr) {
            collect(scene, *node.mChildren[c], world, depth + 1, out);
        }
    }
}

core::Result<RawImport> read_impl(std::string_view bytes, Format format) {
    RawImport out;
    out.format = format;
    std::string converted;
    if (auto utf8 = utf16_to_utf8(bytes)) {
        converted = std::move(*utf8);
        bytes = converted;
        out.warnings.push_back("the file is UTF-16 text; it was converted to UTF-8 to read it");
    }
    if (bytes.size() >= 3 && bytes.substr(0, 3) == "\xEF\xBB\xBF") bytes.remove_prefix(3);

    ObjScan scan;
    if (format == Format::kObj) {
        auto scanned = scan_obj(bytes);
        if (!scanned) return std::unexpected(scanned.error());
        scan = *scanned;
        if (scan.faces == 0) {
            std::string what =
                "no triangles: the OBJ file has no faces ('f' with 3 or more corners)";
            std::vector<std::string> found;
            if (scan.points > 0) found.push_back(count_of(scan.points, "point"));
            if (scan.lines > 0) found.push_back(count_of(scan.lines, "line"));
            if (scan.short_faces > 0) {
                found.push_back(count_of(scan.short_faces, "face with fewer than 3 corners",
                                         "faces with fewer than 3 corners"));
            }
            for (std::size_t i = 0; i < found.size(); ++i) {
                what += (i == 0 ? ", only " : (i + 1 == found.size() ? " and " : ", ")) + found[i];
            }
            return core::fail(core::ErrorCode::kInvalidInput, what);
        }
    }

    Assimp::Importer importer;
    const std::string_view text = format == Format::kObj ? std::string_view(scan.geometry) : bytes;
    const aiScene* scene = importer.ReadFileFromMemory(text.data(), text.size(), 0, "obj");
    if (scene == nullptr) {
        const std::string why = importer.GetErrorString();
        return core::fail(core::ErrorCode::kInvalidInput,
                          fmt::format("cannot read the {} file: {}", format_name(format),
                                      why.empty() ? "assimp gave no reason" : why));
    }
    Collected got;
    if (scene->mRootNode != nullptr) {
        collect(*scene, *scene->mRootNode, aiMatrix4x4(), 0, got);
    }
    if (got.too_large > 0) {
        return core::fail(core::ErrorCode::kInvalidInput,
                          fmt::format("{} more than {} corners; maxslice reads at most {} per "
                                      "polygon",
                                      count_of(got.too_large, "face has", "faces have"),
                                      kMaxPolygonCorners, kMaxPolygonCorners));
    }
    if (got.bad_indices > 0) {
        return core::fail(core::ErrorCode::kInvalidInput,
                          fmt::format("{} point at vertices that do not exist",
                                      count_of(got.bad_indices, "face")));
    }
    const std::size_t triangles = got.xyz.size() / 9;
    if (triangles == 0) {
        return core::fail(
            core::ErrorCode::kInvalidInput,
            fmt::format("no triangles: the {} file has no faces{}", format_name(format),
                        got.non_triangles > 0
                            ? fmt::format(" ({} points or lines only)", got.non_triangles)
                            : std::string()));
    }
    for (const double v : got.xyz) {
        if (!std::isfinite(v)) {
            return core::fail(core::ErrorCode::kInvalidInput,
                              "a vertex has a NaN or infinite coordinate");
        }
    }
    if (got.fanned > 0) {
        out.warnings.push_back(fmt::format(
            "{} of {} polygons cross themselves or have no area; they were fanned from a corner",
            got.fanned, got.polygons));
    }
    if (format == Format::kObj) {
        if (scan.short_faces > 0) {
            out.warnings.push_back(
                fmt::format("ignored {} with fewer than 3 corners (the first at line {})",
                            count_of(scan.short_faces, "face"), scan.first_short_face_line));
        }
        if (scan.points > 0 || scan.lines > 0) {
            out.warnings.push_back(fmt::format("ignored {} and {} (only faces are read)",
                                               count_of(scan.points, "point"),
                                               count_of(scan.lines, "line")));
        }
    } else if (got.non_triangles > 0) {
        out.warnings.push_back(fmt::format(
            "ignored {} (only faces are read)",
            count_of(got.non_triangles, "point or line element", "point and line elements")));
    }
    out.solids = got.meshes_with_triangles;
    out.mesh = mesh::weld_exact(std::span<const double>(got.xyz));
    return out;
}

}  // namespace

core::Result<RawImport> read_with_assimp(std::string_view bytes, Format format) {
    try {
        return read_impl(bytes, format);
    } catch (const std::bad_alloc&) {
        return core::fail(core::ErrorCode::kInvalidInput, "not enough memory for the mesh");
    } catch (const std::exception& e) {
        return core::fail(
            core::ErrorCode::kInvalidInput,
            fmt::format("cannot read the {} file: {}", format_name(format), e.what()));
    } catch (...) {
        return core::fail(
            core::ErrorCode::kInvalidInput,
            fmt::format("cannot read the {} file: the reader failed", format_name(format)));
    }
}

}  // namespace maxslice::io::detail
