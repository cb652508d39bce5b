#include "section_index.hpp"

#include <algorithm>
#include <cmath>
#include <span>

#include "maxslice/slice/slicer.hpp"

namespace maxslice::plan::detail {
namespace {

// Triangles per leaf of the hierarchy.
constexpr std::uint32_t kLeafSize = 8;
// Boxes and triangles this close to the plane (mm) are kept: a superset of the triangles
// the slicer finds crossing it is harmless, a triangle missed is not.
constexpr double kPlaneSlackMm = 1e-6;

double axis(const core::Vec3d& p, int k) {
    return k == 0 ? p.x : k == 1 ? p.y : p.z;
}

}  // namespace

SectionIndex::SectionIndex(const mesh::TriangleMesh& mesh)
    : mesh_(mesh), vertex_map_(mesh.vertices.size(), 0) {
    const std::size_t nt = mesh.triangles.size();
    std::vector<core::Vec3d> lo(nt), hi(nt), mid(nt);
    for (std::size_t t = 0; t < nt; ++t) {
        core::Box3d b;
        for (int k = 0; k < 3; ++k) b.add(mesh.corner(t, k));
        lo[t] = b.min;
        hi[t] = b.max;
        mid[t] = b.center();
    }
    order_.resize(nt);
    for (std::size_t t = 0; t < nt; ++t) order_[t] = static_cast<std::uint32_t>(t);
    if (nt == 0) return;
    // Top-down: split at the median of the triangles' box centres along the widest axis of
    // the centres' box. Children of a node are stored next to each other.
    struct Job {
        std::size_t node;
        std::uint32_t begin, end;
    };
    nodes_.reserve(2 * (nt / kLeafSize + 1));
    nodes_.push_back({});
    std::vector<Job> stack{{0, 0, static_cast<std::uint32_t>(nt)}};
    while (!stack.empty()) {
        const Job job = stack.back();
        stack.pop_back();
        core::Box3d box, centres;
        for (std::uint32_t i = job.begin; i < job.end; ++i) {
            box.add(lo[order_[i]]);
            box.add(hi[order_[i]]);
            centres.add(mid[order_[i]]);
        }
        nodes_[job.node].lo = box.min;
        nodes_[job.node].hi = box.max;
        if (job.end - job.begin <= kLeafSize) {
            nodes_[job.node].first = job.begin;
            nodes_[job.node].count = job.end - job.begin;
            continue;
        }
        const core::Vec3d ext = centres.size();
        const int k = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
        const std::uint32_t m = job.begin + (job.end - job.begin) / 2;
        std::nth_element(order_.begin() + job.begin, order_.begin() + m, order_.begin() + job.end,
                         [&](std::uint32_t a, std::uint32_t b) {
                             const double ca = axis(mid[a], k), cb = axis(mid[b], k);
                             return ca < cb || (ca == cb && a < b);
                         });
        const auto child = static_cast<std::uint32_t>(nodes_.size());
        nodes_[job.node].first = child;
        nodes_[job.node].count = 0;
        nodes_.push_back({});
        nodes_.push_back({});
        stack.push_back({child, job.begin, m});
        stack.push_back({child + 1, m, job.end});
    }
}

void SectionIndex::collect(const slice::PlaneFrame& plane) {
    hits_.clear();
    if (nodes_.empty()) return;
    const core::Vec3d n = plane.normal;
    const core::Vec3d an{std::abs(n.x), std::abs(n.y), std::abs(n.z)};
    std::vector<std::uint32_t> stack{0};
    while (!stack.empty()) {
        const Node& node = nodes_[stack.back()];
        stack.pop_back();
        const core::Vec3d c = (node.lo + node.hi) * 0.5;
        const core::Vec3d e = (node.hi - node.lo) * 0.5;
        if (std::abs(core::dot(c - plane.origin, n)) > core::dot(e, an) + kPlaneSlackMm) continue;
        if (node.count == 0) {
            stack.push_back(node.first);
            stack.push_back(node.first + 1);
            continue;
        }
        for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
            const std::uint32_t t = order_[i];
            double h_lo = INFINITY, h_hi = -INFINITY;
            for (int k = 0; k < 3; ++k) {
                const double h = core::dot(mesh_.corner(t, k) - plane.origin, n);
                h_lo = std::min(h_lo, h);
                h_hi = std::max(h_hi, h);
            }
            // The slicer cuts a triangle with min height <= 0 < max height.
            if (h_lo <= kPlaneSlackMm && h_hi > -kPlaneSlackMm) hits_.push_back(t);
        }
    }
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
