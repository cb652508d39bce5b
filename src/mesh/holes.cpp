// Capping the holes of an open surface (include/maxslice/mesh/holes.hpp).

#include "maxslice/mesh/holes.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace maxslice::mesh {
namespace {

// An edge of a triangle as it runs (from, to), with its undirected key for sorting.
struct Edge {
    std::uint64_t key;
    std::uint32_t from;
    std::uint32_t to;
};

std::uint64_t key_of(std::uint32_t a, std::uint32_t b) {
    return (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
}

// The root of v in a union-find forest, with path halving.
std::uint32_t root(std::vector<std::uint32_t>& parent, std::uint32_t v) {
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

}  // namespace

CappedMesh cap_holes(const TriangleMesh& mesh) {
    CappedMesh out;
    out.mesh = mesh;
    std::vector<Edge> edges;
    edges.reserve(3 * mesh.triangles.size());
    for (const Triangle& t : mesh.triangles) {
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[static_cast<std::size_t>(k)];
            const std::uint32_t b = t[static_cast<std::size_t>((k + 1) % 3)];
            if (a != b) edges.push_back({key_of(a, b), a, b});
        }
    }
    std::sort(edges.begin(), edges.end(),
              [](const Edge& x, const Edge& y) { return x.key < y.key; });
    std::vector<Edge> open;
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i + 1;
        while (j < edges.size() && edges[j].key == edges[i].key) ++j;
        if (j == i + 1) open.push_back(edges[i]);
        i = j;
    }
    out.open_edges = open.size();
    if (open.empty()) return out;
    std::vector<std::uint32_t> parent(mesh.vertices.size());
    std::iota(parent.begin(), parent.end(), 0u);
    for (const Edge& e : open) {
        const std::uint32_t a = root(parent, e.from);
        const std::uint32_t b = root(parent, e.to);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);  // the lowest vertex is the root
    }
    // One cap a group, numbered in the order of the groups' lowest vertices; its centre is the
    // mean of the group's vertices (each counted once).
    std::vector<std::uint32_t> rim;  // the open edges' vertices, each once, ascending
    for (const Edge& e : open) {
        rim.push_back(e.from);
        rim.push_back(e.to);
    }
    std::sort(rim.begin(), rim.end());
    rim.erase(std::unique(rim.begin(), rim.end()), rim.end());
    constexpr std::uint32_t kNone = ~0u;
    std::vector<std::uint32_t> cap_of(mesh.vertices.size(), kNone);  // by root
    std::vector<core::Vec3d> sum;
    std::vector<double> count;
    for (const std::uint32_t v : rim) {
        const std::uint32_t r = root(parent, v);
        if (cap_of[r] == kNone) {
            cap_of[r] = static_cast<std::uint32_t>(sum.size());
            sum.emplace_back();
            count.push_back(0.0);
        }
        sum[cap_of[r]] += mesh.vertices[v];
        count[cap_of[r]] += 1.0;
    }
    const auto first = static_cast<std::uint32_t>(out.mesh.vertices.size());
    for (std::size_t c = 0; c < sum.size(); ++c) out.mesh.vertices.push_back(sum[c] / count[c]);
    for (const Edge& e : open) {
        out.mesh.triangles.push_back({e.to, e.from, first + cap_of[root(parent, e.from)]});
    }
    out.caps = sum.size();
    return out;
}

}  // namespace maxslice::mesh
