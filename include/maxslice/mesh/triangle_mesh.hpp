#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "maxslice/core/vec3.hpp"

namespace maxslice::mesh {

/// Three vertex indices, counter-clockwise seen from outside the solid.
using Triangle = std::array<std::uint32_t, 3>;

/// An indexed triangle mesh in double millimetres (part frame). Outward normals follow
/// the right-hand rule on each triangle's vertex order.
struct TriangleMesh {
    std::vector<core::Vec3d> vertices;
    std::vector<Triangle> triangles;

    [[nodiscard]] bool empty() const { return triangles.empty(); }
    [[nodiscard]] core::Vec3d corner(std::size_t tri, int k) const {
        return vertices[triangles[tri][static_cast<std::size_t>(k)]];
    }
};

/// Bounding box of the vertices used by triangles (unused vertices are ignored).
[[nodiscard]] core::Box3d bounding_box(const TriangleMesh& mesh);
/// Signed enclosed volume in mm^3 (divergence theorem); negative when inside-out.
[[nodiscard]] double signed_volume(const TriangleMesh& mesh);
/// Total triangle area in mm^2.
[[nodiscard]] double surface_area(const TriangleMesh& mesh);
/// Unnormalised normal (twice the area vector) of one triangle.
[[nodiscard]] core::Vec3d area_vector(const TriangleMesh& mesh, std::size_t tri);

/// Scales every vertex by s (unit conversion) in place.
void scale(TriangleMesh& mesh, double s);
/// Applies a 3x4 row-major affine transform [R | t] to every vertex in place; a transform
/// with a negative determinant also flips every triangle to keep normals outward.
void transform(TriangleMesh& mesh, const std::array<double, 12>& affine);
/// Puts a part on a build plate (docs/program-dialects.md, "Frames and placement"): rotates
/// it so that `direction` (non-zero) points to +Z (Rodrigues about d x Z, a half turn about X
/// when d points down), then moves it so that its lowest point lies on Z = 0 and the centre of
/// its XY bounding box on (plate_center.x, plate_center.y).
[[nodiscard]] TriangleMesh placed_on_plate(TriangleMesh mesh, const core::Vec3d& direction,
                                           const core::Vec3d& plate_center);
/// Appends b's triangles to a (vertices are not shared).
void append(TriangleMesh& a, const TriangleMesh& b);

/// Points on every triangle of the mesh, no two neighbours further apart than spacing_mm
/// (the corners, and a grid over the triangle's barycentric coordinates). Deterministic.
[[nodiscard]] std::vector<core::Vec3d> surface_samples(const TriangleMesh& mesh, double spacing_mm);

/// The body of every vertex: the smallest vertex index of its connected component (triangles
/// that share a vertex are connected); a vertex no triangle uses is its own body.
[[nodiscard]] std::vector<std::uint32_t> vertex_bodies(const TriangleMesh& mesh);

/// Builds an indexed mesh from a triangle soup (9 coordinates per triangle, corners in
/// order), merging corners with bit-identical coordinates (-0.0 counts as 0.0). Linear
/// expected time. The first occurrence of a position fixes its vertex index, so the result is
/// deterministic. Every triangle is kept, also one whose corners merge (validate() reports
/// it, repair() removes it); numbers after the last whole triangle are ignored.
[[nodiscard]] TriangleMesh weld_exact(std::span<const float> xyz);
[[nodiscard]] TriangleMesh weld_exact(std::span<const double> xyz);

/// weld_exact over a float soup handed over in blocks of whole triangles (a binary STL read a
/// piece at a time, so that the whole soup never sits in memory): finish() gives the mesh
/// weld_exact gives for the blocks' concatenation.
class BlockWelder {
public:
    /// `triangles`: how many will be added in all (sizes the table and the mesh).
    explicit BlockWelder(std::size_t triangles);
    ~BlockWelder();
    BlockWelder(BlockWelder&&) noexcept;
    BlockWelder& operator=(BlockWelder&&) noexcept;

    /// Adds xyz's whole triangles (9 numbers each) after those added before; no more than
    /// announced in all.
    void add(std::span<const float> xyz);
    /// The mesh of the triangles added.
    [[nodiscard]] TriangleMesh finish() &&;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace maxslice::mesh
