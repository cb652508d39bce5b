#include "maxslice/mesh/validation.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <limits>

#include "maxslice/core/assert.hpp"
#include "maxslice/core/tolerances.hpp"
#include "mesh_detail.hpp"

namespace maxslice::mesh {
namespace {

constexpr std::uint64_t kNoEdge = std::numeric_limits<std::uint64_t>::max();
constexpr std::size_t kNoTriangle = std::numeric_limits<std::size_t>::max();
using Triple = std::array<std::uint32_t, 3>;
// How many triangles ahead the passes over triangles prefetch per-vertex data.
constexpr std::size_t kPrefetchAhead = 8;
constexpr Triple kNoTriple = {std::numeric_limits<std::uint32_t>::max(),
                              std::numeric_limits<std::uint32_t>::max(),
                              std::numeric_limits<std::uint32_t>::max()};

// A defect count with the smallest key of its instances (keys order the instances
// deterministically, whatever the thread schedule).
template <class Key>
struct Tally {
    std::size_t count = 0;
    Key first;

    void add(const Key& k) {
        ++count;
        first = std::min(first, k);
    }
    void join(const Tally& o) {
        count += o.count;
        first = std::min(first, o.first);
    }
};

struct EdgeTallies {
    Tally<std::uint64_t> boundary{0, kNoEdge};
    Tally<std::uint64_t> nonmanifold{0, kNoEdge};
    Tally<std::uint64_t> misoriented{0, kNoEdge};
    Tally<std::uint64_t> unbalanced{0, kNoEdge};
    Tally<Triple> duplicate{0, kNoTriple};

    void join(const EdgeTallies& o) {
        boundary.join(o.boundary);
        nonmanifold.join(o.nonmanifold);
        misoriented.join(o.misoriented);
        unbalanced.join(o.unbalanced);
        duplicate.join(o.duplicate);
    }
};

struct TriangleTallies {
    Tally<std::size_t> degenerate{0, kNoTriangle};
    Tally<std::size_t> nonfinite{0, kNoTriangle};  // triangles with a non-finite corner
    double six_volume = 0.0;
    double twice_area = 0.0;

    void join(const TriangleTallies& o) {
        degenerate.join(o.degenerate);
        nonfinite.join(o.nonfinite);
        six_volume += o.six_volume;
        twice_area += o.twice_area;
    }
};

core::Vec3d midpoint(const TriangleMesh& mesh, std::uint64_t edge) {
    const auto lo = static_cast<std::uint32_t>(edge >> 32);
    const auto hi = static_cast<std::uint32_t>(edge & 0xffffffffu);
    return (mesh.vertices[lo] + mesh.vertices[hi]) * 0.5;
}

core::Vec3d centroid(const TriangleMesh& mesh, const Triple& t) {
    return (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0;
}

// Edge analysis. Every edge u-v (u != v) of every triangle is filed under its smaller vertex
// lo = min(u, v) (counting sort into CSR arrays: linear time, no hashing), as a 64-bit entry
//   hi (31 bits) | third vertex of the triangle (32 bits) | direction (1 bit: 1 when v < u).
// Sorting each vertex's short list (six entries on average) groups the uses of each
// undirected edge (lo, hi); within a group the direction bits give the misoriented count and
// equal third vertices give duplicate triangles. A triangle with three distinct vertices
// s0 < s1 < s2 is looked at for duplicates only on its edge (s0, s1), the one edge whose
// third vertex is larger than both ends, so each duplicate is counted once.
EdgeTallies analyse_edges(const TriangleMesh& mesh) {
    const std::size_t nv = mesh.vertices.size();
    MAXSLICE_ASSERT(nv < (std::size_t{1} << 31));
    // Both passes over the triangles run in parallel with relaxed atomic counters; the order
    // of the entries within a vertex's list then depends on the schedule, but each list is
    // sorted before use, so the result does not. The vertex arrays are accessed at random
    // when the vertex order does not follow the triangle order, so the slots of a triangle
    // some way ahead are prefetched.
    const std::size_t nt = mesh.triangles.size();
    const tbb::blocked_range<std::size_t> all(0, nt, 1u << 14);
    std::vector<std::uint32_t> start(nv + 1, 0);
    tbb::parallel_for(all, [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            if (i + kPrefetchAhead < nt) {
                for (std::uint32_t w : mesh.triangles[i + kPrefetchAhead]) {
                    __builtin_prefetch(&start[w + 1], 1);
                }
            }
            const Triangle& t = mesh.triangles[i];
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t u = t[k];
                const std::uint32_t v = t[(k + 1) % 3];
                if (u == v) continue;
                std::atomic_ref<std::uint32_t>(start[std::min(u, v) + 1])
                    .fetch_add(1, std::memory_order_relaxed);
            }
        }
    });
    for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
    std::vector<std::uint64_t> entries(start[nv]);
    {
        std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
        tbb::parallel_for(all, [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                if (i + 2 * kPrefetchAhead < nt) {
                    for (std::uint32_t w : mesh.triangles[i + 2 * kPrefetchAhead]) {
                        __builtin_prefetch(&fill[w], 1);
                    }
                }
                if (i + kPrefetchAhead < nt) {
                    for (std::uint32_t w : mesh.triangles[i + kPrefetchAhead]) {
                        const std::size_t at = std::min<std::size_t>(
                            std::atomic_ref<std::uint32_t>(fill[w]).load(std::memory_order_relaxed),
                            entries.size() - 1);
                        __builtin_prefetch(entries.data() + at, 1);
                    }
                }
                const Triangle& t = mesh.triangles[i];
                for (int k = 0; k < 3; ++k) {
                    const std::uint32_t u = t[k];
                    const std::uint32_t v = t[(k + 1) % 3];
                    if (u == v) continue;
                    const std::uint32_t third = t[(k + 2) % 3];
                    const std::uint32_t lo = std::min(u, v);
                    const std::uint64_t hi = std::max(u, v);
                    const std::uint32_t at = std::atomic_ref<std::uint32_t>(fill[lo]).fetch_add(
                        1, std::memory_order_relaxed);
                    entries[at] = (hi << 33) | (std::uint64_t{third} << 1) | (v < u ? 1u : 0u);
                }
            }
        });
    }

    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, nv, 4096), EdgeTallies{},
        [&](const tbb::blocked_range<std::size_t>& r, EdgeTallies acc) {
            for (std::size_t lo = r.begin(); lo != r.end(); ++lo) {
                std::uint64_t* b = entries.data() + start[lo];
                std::uint64_t* e = entries.data() + start[lo + 1];
                if (e - b > 24) {
                    std::sort(b, e);
                } else {
                    for (std::uint64_t* i = b + 1; i < e; ++i) {
                        const std::uint64_t x = *i;
                        std::uint64_t* j = i;
                        for (; j > b && *(j - 1) > x; --j) *j = *(j - 1);
                        *j = x;
                    }
                }
                for (std::uint64_t* g = b; g < e;) {
                    const std::uint64_t hi = *g >> 33;
                    std::uint64_t* ge = g + 1;
                    while (ge < e && (*ge >> 33) == hi) ++ge;
                    const std::uint64_t key = (std::uint64_t{lo} << 32) | hi;
                    const auto uses = static_cast<std::size_t>(ge - g);
                    std::size_t backward = 0;
                    for (std::uint64_t* i = g; i < ge; ++i) backward += *i & 1u;
                    const std::size_t forward = uses - backward;
                    if (uses == 1) acc.boundary.add(key);
                    if (uses > 2) acc.nonmanifold.add(key);
                    // Each direction used more than once is one misoriented (directed) edge.
                    if (forward > 1) acc.misoriented.add(key);
                    if (backward > 1) acc.misoriented.add(key);
                    if (uses > 1 && forward != backward) acc.unbalanced.add(key);
                    for (std::uint64_t* i = g + 1; i < ge; ++i) {
                        const std::uint64_t third = (*i >> 1) & 0xffffffffu;
                        if (third > hi && third == ((*(i - 1) >> 1) & 0xffffffffu)) {
                            acc.duplicate.add({static_cast<std::uint32_t>(lo),
                                               static_cast<std::uint32_t>(hi),
                                               static_cast<std::uint32_t>(third)});
                        }
                    }
                    g = ge;
                }
            }
            return acc;
        },
        [](EdgeTallies a, const EdgeTallies& b) {
            a.join(b);
            return a;
        });
}

// Duplicates among triangles with a repeated vertex index (they have at most one edge, so
// the edge pass does not see them); there are few of these, so sorting is fine.
Tally<Triple> repeated_index_duplicates(const TriangleMesh& mesh) {
    std::vector<Triple> keys;
    for (const Triangle& t : mesh.triangles) {
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
            Triple k = t;
            std::sort(k.begin(), k.end());
            keys.push_back(k);
        }
    }
    std::sort(keys.begin(), keys.end());
    Tally<Triple> tally{0, kNoTriple};
    for (std::size_t i = 1; i < keys.size(); ++i) {
        if (keys[i] == keys[i - 1]) tally.add(keys[i]);
    }
    return tally;
}

// Bodies: the connected components among used vertices (vertex_bodies).
std::size_t count_bodies(const TriangleMesh& mesh, std::vector<std::uint8_t>& used) {
    const std::vector<std::uint32_t> body = vertex_bodies(mesh);  // checks the indices
    used.assign(mesh.vertices.size(), 0);
    for (const Triangle& t : mesh.triangles) used[t[0]] = used[t[1]] = used[t[2]] = 1;
    std::size_t bodies = 0;
    for (std::size_t v = 0; v < body.size(); ++v) {
        if (used[v] && body[v] == v) ++bodies;
    }
    return bodies;
}

// One pass over the triangles for everything that needs their corners: degenerate and
// non-finite triangles, volume and area. Volume and area use the same terms, blocks and
// summation order as signed_volume() and surface_area(), so they equal those exactly; one
// pass instead of three matters when the vertices are not in triangle order (cache misses).
TriangleTallies analyse_triangles(const TriangleMesh& mesh) {
    const core::Vec3d o = mesh.vertices[mesh.triangles.front()[0]];
    const auto partials = detail::block_partials(
        mesh.triangles.size(), TriangleTallies{}, [&](TriangleTallies& acc, std::size_t i) {
            if (i + kPrefetchAhead < mesh.triangles.size()) {
                for (std::uint32_t w : mesh.triangles[i + kPrefetchAhead]) {
                    __builtin_prefetch(&mesh.vertices[w]);
                }
            }
            const Triangle& t = mesh.triangles[i];
            const core::Vec3d& a = mesh.vertices[t[0]];
            const core::Vec3d& b = mesh.vertices[t[1]];
            const core::Vec3d& c = mesh.vertices[t[2]];
            const double twice_area = detail::twice_area_term(a, b, c);
            acc.six_volume += detail::six_volume_term(o, a, b, c);
            acc.twice_area += twice_area;
            if (!core::is_finite(a) || !core::is_finite(b) || !core::is_finite(c)) {
                acc.nonfinite.add(i);
            } else if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] ||
                       detail::degenerate_with_area(twice_area, a, b, c,
                                                    core::kDegenerateTriangleAreaMm2)) {
                acc.degenerate.add(i);
            }
        });
    TriangleTallies total;
    for (const TriangleTallies& p : partials) total.join(p);
    return total;
}

// True when every used vertex lies within kFlatFraction of the diagonal of the plane of the
// largest triangle (any triangle of a flat mesh spans its plane; the largest is the least
// sensitive to rounding). A mesh without a triangle of positive area is flat too.
bool is_flat(const TriangleMesh& mesh, const std::vector<std::uint8_t>& used,
             const core::Box3d& box) {
    if (box.empty()) return true;
    core::Vec3d normal{};
    double largest = 0.0;
    std::size_t at = 0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const core::Vec3d n = area_vector(mesh, t);
        const double a = core::dot(n, n);
        if (a > largest) {
            largest = a;
            normal = n;
            at = t;
        }
    }
    if (!(largest > 0.0)) return true;
    normal = normal / std::sqrt(largest);
    const core::Vec3d origin = mesh.corner(at, 0);
    const double tolerance = ValidationReport::kFlatFraction * core::norm(box.size());
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        if (!used[v] || !core::is_finite(mesh.vertices[v])) continue;
        if (!(std::abs(core::dot(mesh.vertices[v] - origin, normal)) <= tolerance)) return false;
    }
    return true;
}

std::string plural(std::size_t n, const char* one, const char* many) {
    return fmt::format("{} {}", n, n == 1 ? one : many);
}

}  // namespace

bool is_degenerate(const core::Vec3d& a, const core::Vec3d& b, const core::Vec3d& c) {
    // Relative test: area <= kDegenerateTriangleAreaMm2 * (longest edge / 1 mm)^2. For a
    // triangle with a 1 mm longest edge this is the absolute threshold; scaling the part
    // scales both sides alike, so a well-shaped triangle of a part in metres (edges of
    // 1e-4) is not degenerate, while collinear corners (area 0, or rounding noise far
    // below the longest edge squared) are at any size. Corners at one point (longest
    // edge 0) are degenerate.
    if (!core::is_finite(a) || !core::is_finite(b) || !core::is_finite(c)) return false;
    return detail::degenerate_with_area(detail::twice_area_term(a, b, c), a, b, c,
                                        core::kDegenerateTriangleAreaMm2);
}

bool ValidationReport::closed_manifold() const {
    return boundary_edges.count == 0 && nonmanifold_edges.count == 0 &&
           misoriented_edges.count == 0;
}

bool ValidationReport::closed() const {
    return boundary_edges.count == 0 && unbalanced_edges.count == 0;
}

bool ValidationReport::bodies_touch() const {
    return closed() && misoriented_edges.count > 0;
}

bool ValidationReport::inside_out() const {
    return closed_manifold() && volume_mm3 < 0.0;
}

std::vector<std::string> ValidationReport::defects() const {
    std::vector<std::string> lines;
    if (triangles == 0) {
        lines.emplace_back("no triangles");
        return lines;
    }
    auto line = [&](const DefectCount& d, const char* one, const char* many) {
        if (d.count == 0) return;
        std::string s = plural(d.count, one, many);
        if (d.example) {
            s += fmt::format(", e.g. near ({:.3f}, {:.3f}, {:.3f}) mm", d.example->x, d.example->y,
                             d.example->z);
        }
        lines.push_back(std::move(s));
    };
    line(nonfinite_vertices, "vertex with a NaN or infinite coordinate",
         "vertices with NaN or infinite coordinates");
    line(degenerate_triangles, "degenerate (zero-area) triangle",
         "degenerate (zero-area) triangles");
    line(duplicate_triangles, "duplicate triangle", "duplicate triangles");
    line(boundary_edges, "open (boundary) edge", "open (boundary) edges");
    line(nonmanifold_edges, "non-manifold edge (shared by more than two triangles)",
         "non-manifold edges (shared by more than two triangles)");
    line(misoriented_edges, "misoriented edge (its two triangles disagree on the outside)",
         "misoriented edges (their triangles disagree on the outside)");
    line(inside_out_shells,
         "closed shell is inside out (it faces inwards but is not a void in another shell)",
         "closed shells are inside out (they face inwards but are not voids in other shells)");
    line(inward_pieces,
         "piece of surface where closed bodies touch faces inwards (its inside is empty)",
         "pieces of surface where closed bodies touch face inwards (their inside is empty)");
    if (flat) {
        lines.push_back(fmt::format(
            "the mesh is flat: every vertex lies in one plane, so it encloses no volume "
            "({:.3g} mm^3) and is a surface, not a solid",
            volume_mm3));
    } else if (bodies_touch() && inward_pieces.count == 0) {
        lines.emplace_back(
            "every edge is used as often one way as the other: closed bodies touch along those "
            "edges, and are sliced as one solid");
    }
    if (inside_out() && !flat) {
        lines.push_back(fmt::format("the surface is inside out (volume {:.3f} mm^3)", volume_mm3));
    }
    return lines;
}

ValidationReport validate(const TriangleMesh& mesh) {
    ValidationReport report;
    report.triangles = mesh.triangles.size();
    if (mesh.triangles.empty()) return report;

    std::vector<std::uint8_t> used;
    EdgeTallies edges;
    Tally<Triple> repeated_duplicates;
    TriangleTallies tris;
    tbb::parallel_invoke([&] { edges = analyse_edges(mesh); },
                         [&] {
                             report.bodies = count_bodies(mesh, used);
                             repeated_duplicates = repeated_index_duplicates(mesh);
                         },
                         [&] { tris = analyse_triangles(mesh); });
    report.volume_mm3 = tris.six_volume / 6.0;
    report.area_mm2 = 0.5 * tris.twice_area;
    edges.duplicate.join(repeated_duplicates);

    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        if (!used[v]) continue;
        ++report.vertices;
        if (core::is_finite(mesh.vertices[v])) {
            report.bounding_box.add(mesh.vertices[v]);
        } else {
            ++report.nonfinite_vertices.count;
        }
    }
    if (tris.nonfinite.count > 0) {
        // The place of a non-finite vertex is given by the finite corners of the first
        // triangle that uses one (none when all three are non-finite).
        const Triangle& t = mesh.triangles[tris.nonfinite.first];
        core::Vec3d sum;
        int finite = 0;
        for (std::uint32_t v : t) {
            if (core::is_finite(mesh.vertices[v])) {
                sum += mesh.vertices[v];
                ++finite;
            }
        }
        if (finite > 0) report.nonfinite_vertices.example = sum / finite;
    }

    auto fill_edge = [&](DefectCount& d, const Tally<std::uint64_t>& t) {
        d.count = t.count;
        if (t.count > 0) d.example = midpoint(mesh, t.first);
    };
    fill_edge(report.boundary_edges, edges.boundary);
    fill_edge(report.nonmanifold_edges, edges.nonmanifold);
    fill_edge(report.misoriented_edges, edges.misoriented);
    fill_edge(report.unbalanced_edges, edges.unbalanced);
    // A flat mesh has no inside: every piece of it would look inside out.
    report.flat = is_flat(mesh, used, report.bounding_box);
    const bool flat = report.flat;
    if (!flat && report.bodies > 1 && report.boundary_edges.count == 0 &&
        report.nonmanifold_edges.count == 0 && report.misoriented_edges.count == 0) {
        const detail::InsideOutShells inverted = detail::inside_out_shells(mesh);
        report.inside_out_shells.count = inverted.count;
        report.inside_out_shells.example = inverted.example;
    }
    if (!flat && report.bodies_touch()) {
        const detail::InsideOutShells inward = detail::inward_pieces(mesh);
        report.inward_pieces.count = inward.count;
        report.inward_pieces.example = inward.example;
    }
    report.duplicate_triangles.count = edges.duplicate.count;
    if (edges.duplicate.count > 0) {
        report.duplicate_triangles.example = centroid(mesh, edges.duplicate.first);
    }
    report.degenerate_triangles.count = tris.degenerate.count;
    if (tris.degenerate.count > 0) {
        report.degenerate_triangles.example = centroid(mesh, mesh.triangles[tris.degenerate.first]);
    }
    return report;
}

}  // namespace maxslice::mesh
