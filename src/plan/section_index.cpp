#include "section_index.hpp"

#include <algorithm>
#include <cmath>
#include <span>

#include "maxslice/slice/slicer.hpp"

namespace maxslice::plan::detail {
namespace {

// Boxes and triangles this close to the plane (mm) are kept: a superset of the triangles
// the slicer finds crossing it is harmless, a triangle missed is not.
constexpr double kPlaneSlackMm = 1e-6;

BoxTree triangle_tree(const mesh::TriangleMesh& mesh) {
    const std::size_t nt = mesh.triangles.size();
    std::vector<core::Vec3d> lo(nt), hi(nt);
    for (std::size_t t = 0; t < nt; ++t) {
        core::Box3d b;
        for (int k = 0; k < 3; ++k) b.add(mesh.corner(t, k));
        lo[t] = b.min;
        hi[t] = b.max;
    }
    return BoxTree(lo, hi);
}

}  // namespace

SectionIndex::SectionIndex(const mesh::TriangleMesh& mesh)
    : mesh_(mesh), tree_(triangle_tree(mesh)), vertex_map_(mesh.vertices.size(), 0) {}

void SectionIndex::collect(const slice::PlaneFrame& plane) {
    hits_.clear();
    const core::Vec3d n = plane.normal;
    const core::Vec3d an{std::abs(n.x), std::abs(n.y), std::abs(n.z)};
    tree_.visit(
        [&](const core::Vec3d& lo, const core::Vec3d& hi) {
            const core::Vec3d c = (lo + hi) * 0.5;
            const core::Vec3d e = (hi - lo) * 0.5;
            return std::abs(core::dot(c - plane.origin, n)) <= core::dot(e, an) + kPlaneSlackMm;
        },
        [&](std::uint32_t t) {
            double h_lo = INFINITY, h_hi = -INFINITY;
            for (int k = 0; k < 3; ++k) {
                const double h = core::dot(mesh_.corner(t, k) - plane.origin, n);
                h_lo = std::min(h_lo, h);
                h_hi = std::max(h_hi, h);
            }
            // The slicer cuts a triangle with min height <= 0 < max height.
            if (h_lo <= kPlaneSlackMm && h_hi > -kPlaneSlackMm) hits_.push_back(t);
        });
}

core::Result<geom2d::Paths2> SectionIndex::section(const slice::PlaneFrame& plane,
                                                   double thickness) {
    collect(plane);
    // The sub-mesh of the triangles found, with triangles and vertices in the mesh's order.
    std::sort(hits_.begin(), hits_.end());
    std::vector<std::uint32_t> used;
    used.reserve(3 * hits_.size());
    for (const std::uint32_t t : hits_) {
        for (const std::uint32_t v : mesh_.triangles[t]) {
            if (vertex_map_[v] == 0) {
                vertex_map_[v] = 1;
                used.push_back(v);
            }
        }
    }
    std::sort(used.begin(), used.end());
    sub_.vertices.clear();
    sub_.triangles.clear();
    for (const std::uint32_t v : used) {
        sub_.vertices.push_back(mesh_.vertices[v]);
        vertex_map_[v] = static_cast<std::uint32_t>(sub_.vertices.size());
    }
    for (const std::uint32_t t : hits_) {
        const mesh::Triangle& tri = mesh_.triangles[t];
        sub_.triangles.push_back(
            {vertex_map_[tri[0]] - 1, vertex_map_[tri[1]] - 1, vertex_map_[tri[2]] - 1});
    }
    for (const std::uint32_t v : used) vertex_map_[v] = 0;

    const slice::LayerSpan span{-thickness / 2, thickness / 2, 0.0};
    auto slices = slice::slice_mesh(sub_, plane, std::span(&span, 1));
    if (!slices) return std::unexpected(slices.error());
    return slices->front().wires.paths();
}

}  // namespace maxslice::plan::detail
