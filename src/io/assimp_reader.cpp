// OBJ through assimp (PLY and OFF have their own reader: ply_off_reader.cpp says why).
// Only aiProcess_Triangulate runs (it cuts concave polygons by ear clipping, not by a fan);
// vertices are welded by mesh::weld_exact like every other format. Assimp reads from our copy
// of the bytes so that the text can be checked first (scan_obj) and UTF-16 converted; every
// index assimp hands back is checked again before use, and every exception it might throw is
// caught here.

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>
#include <assimp/Importer.hpp>

#include <cmath>
#include <exception>
#include <string>
#include <vector>

#include "readers.hpp"

namespace maxslice::io::detail {
namespace {

struct Collected {
    std::vector<double> xyz;
    std::size_t meshes_with_triangles = 0;
    std::size_t non_triangles = 0;  // points and lines assimp kept as primitives
    std::size_t bad_indices = 0;
};

// Walks the node tree so node transforms are applied (OBJ, PLY and OFF put every mesh
// under the identity root, but nothing stops a file from nesting them).
void collect(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, int depth,
             Collected& out) {
    if (depth > 64) return;
    const aiMatrix4x4 world = parent * node.mTransformation;
    const bool identity = world.IsIdentity();
    const bool mirrored = world.Determinant() < 0.0f;
    for (unsigned m = 0; m < node.mNumMeshes; ++m) {
        if (node.mMeshes == nullptr || node.mMeshes[m] >= scene.mNumMeshes) {
            ++out.bad_indices;
            continue;
        }
        const aiMesh* mesh = scene.mMeshes[node.mMeshes[m]];
        if (mesh == nullptr || mesh->mVertices == nullptr || mesh->mFaces == nullptr) continue;
        std::size_t triangles = 0;
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
            const aiFace& face = mesh->mFaces[f];
            if (face.mNumIndices != 3 || face.mIndices == nullptr) {
                ++out.non_triangles;
                continue;
            }
            const unsigned order[3] = {0, mirrored ? 2u : 1u, mirrored ? 1u : 2u};
            bool ok = true;
            for (unsigned k : order) ok = ok && face.mIndices[k] < mesh->mNumVertices;
            if (!ok) {
                ++out.bad_indices;
                continue;
            }
            for (unsigned k : order) {
                aiVector3D p = mesh->mVertices[face.mIndices[k]];
                if (!identity) p = world * p;
                out.xyz.insert(out.xyz.end(), {static_cast<double>(p.x), static_cast<double>(p.y),
                                               static_cast<double>(p.z)});
            }
            ++triangles;
        }
        if (triangles > 0) ++out.meshes_with_triangles;
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
    const aiScene* scene =
        importer.ReadFileFromMemory(bytes.data(), bytes.size(), aiProcess_Triangulate, "obj");
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
