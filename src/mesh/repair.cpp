#include "maxslice/mesh/repair.hpp"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <unordered_map>
#include <utility>

#include "maxslice/core/assert.hpp"
#include "maxslice/core/tolerances.hpp"
#include "maxslice/core/union_find.hpp"
#include "maxslice/mesh/validation.hpp"
#include "mesh_detail.hpp"

namespace maxslice::mesh {
namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

using core::UnionFind;

std::vector<std::uint8_t> used_vertices(const TriangleMesh& mesh) {
    std::vector<std::uint8_t> used(mesh.vertices.size(), 0);
    for (const Triangle& t : mesh.triangles) {
        for (std::uint32_t v : t) {
            MAXSLICE_ASSERT(v < used.size());
            used[v] = 1;
        }
    }
    return used;
}

// Near weld. Points go into a hash grid of cells kCellsPerDistance * d wide. A point closer
// than d to p lies in p's cell, or in the neighbour across a cell face that p is within d
// of; as cells are much wider than d, most points need only their own cell (found again
// through the slot remembered from insertion), and a few look at up to seven neighbours. The
// cell map is open addressing (cell -> last vertex inserted) with the vertices of a cell
// chained through `next`. The clusters are the connected components of the "closer than d"
// graph, which do not depend on the processing order; union-find makes the lowest index of
// each the representative. Returns the number of vertices merged.
std::size_t weld_near(TriangleMesh& mesh, double d, const std::vector<std::uint8_t>& used) {
    constexpr double kCellsPerDistance = 16.0;
    const std::size_t nv = mesh.vertices.size();
    const double cell = kCellsPerDistance * d;
    // Beyond this many cells from the origin the cell index would overflow; such vertices
    // (garbage coordinates, or a weld distance absurdly small for the part) are not welded.
    constexpr double kMaxCell = 4e18;
    struct Cell {
        std::int64_t key[3];
        std::uint32_t head;  // kNone when the slot is free
    };
    auto cell_of = [&](const core::Vec3d& p, std::int64_t(&key)[3], int(&side)[3]) {
        for (int a = 0; a < 3; ++a) {
            const double c = p[a] / cell;
            const double f = std::floor(c);
            if (!(std::fabs(f) < kMaxCell)) return false;
            key[a] = static_cast<std::int64_t>(f);
            const double within = (c - f) * cell;  // distance from the lower face
            side[a] = within <= d ? -1 : (cell - within <= d ? 1 : 0);
        }
        return true;
    };
    auto hash = [](const std::int64_t(&key)[3]) {
        std::uint64_t h = static_cast<std::uint64_t>(key[0]) * 0x9e3779b97f4a7c15ULL;
        h = (h ^ (h >> 32)) + static_cast<std::uint64_t>(key[1]) * 0xc2b2ae3d27d4eb4fULL;
        h = (h ^ (h >> 29)) + static_cast<std::uint64_t>(key[2]) * 0x165667b19e3779f9ULL;
        h ^= h >> 32;
        h *= 0xbf58476d1ce4e5b9ULL;
        return h ^ (h >> 29);
    };

    std::size_t points = 0;
    for (std::size_t v = 0; v < nv; ++v) points += used[v];
    std::vector<std::uint32_t> next(nv, kNone);
    std::vector<std::uint32_t> slot_of_vertex(nv, kNone);
    const std::size_t capacity = std::bit_ceil(std::max<std::size_t>(16, 2 * points));
    const std::size_t mask = capacity - 1;
    std::vector<Cell> cells(capacity, Cell{{0, 0, 0}, kNone});
    auto find_slot = [&](const std::int64_t(&key)[3]) {
        std::size_t i = hash(key) & mask;
        while (cells[i].head != kNone && (cells[i].key[0] != key[0] || cells[i].key[1] != key[1] ||
                                          cells[i].key[2] != key[2])) {
            i = (i + 1) & mask;
        }
        return i;
    };

    for (std::size_t v = 0; v < nv; ++v) {
        if (!used[v] || !core::is_finite(mesh.vertices[v])) continue;
        std::int64_t key[3] = {0, 0, 0};
        int side[3] = {0, 0, 0};
        if (!cell_of(mesh.vertices[v], key, side)) continue;
        const std::size_t slot = find_slot(key);
        Cell& c = cells[slot];
        if (c.head == kNone) std::copy(key, key + 3, c.key);
        next[v] = c.head;
        c.head = static_cast<std::uint32_t>(v);
        slot_of_vertex[v] = static_cast<std::uint32_t>(slot);
    }

    UnionFind clusters(nv);
    const double d2 = d * d;
    auto compare_with_cell = [&](std::uint32_t head, std::uint32_t v) {
        const core::Vec3d& p = mesh.vertices[v];
        for (std::uint32_t u = head; u != kNone; u = next[u]) {
            if (u >= v) continue;  // each pair once
            const core::Vec3d diff = mesh.vertices[u] - p;
            if (core::dot(diff, diff) <= d2) clusters.unite(u, v);
        }
    };
    for (std::size_t v = 0; v < nv; ++v) {
        if (slot_of_vertex[v] == kNone) continue;
        const auto vi = static_cast<std::uint32_t>(v);
        compare_with_cell(cells[slot_of_vertex[v]].head, vi);
        std::int64_t key[3] = {0, 0, 0};
        int side[3] = {0, 0, 0};
        cell_of(mesh.vertices[v], key, side);
        if (side[0] == 0 && side[1] == 0 && side[2] == 0) continue;
        for (int corner = 1; corner < 8; ++corner) {
            std::int64_t probe[3];
            bool valid = true;
            for (int a = 0; a < 3; ++a) {
                const bool step = ((corner >> a) & 1) != 0;
                if (step && side[a] == 0) valid = false;
                probe[a] = key[a] + (step ? side[a] : 0);
            }
            if (!valid) continue;
            const Cell& c = cells[find_slot(probe)];
            if (c.head != kNone) compare_with_cell(c.head, vi);
        }
    }

    std::size_t welded = 0;
    std::vector<std::uint32_t> rep(nv);
    for (std::size_t v = 0; v < nv; ++v) {
        rep[v] = clusters.find(static_cast<std::uint32_t>(v));
        if (rep[v] != v) ++welded;
    }
    for (Triangle& t : mesh.triangles) {
        for (std::uint32_t& v : t) v = rep[v];
    }
    return welded;
}

bool has_repeated_index(const Triangle& t) {
    return t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
}

template <class Keep>
std::size_t remove_triangles_if_not(TriangleMesh& mesh, Keep&& keep) {
    std::size_t kept = 0;
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        if (keep(i)) mesh.triangles[kept++] = mesh.triangles[i];
    }
    const std::size_t removed = mesh.triangles.size() - kept;
    mesh.triangles.resize(kept);
    return removed;
}

std::size_t remove_duplicates(TriangleMesh& mesh) {
    const std::size_t nt = mesh.triangles.size();
    std::vector<std::pair<Triangle, std::uint32_t>> keys(nt);
    for (std::size_t i = 0; i < nt; ++i) {
        Triangle k = mesh.triangles[i];
        std::sort(k.begin(), k.end());
        keys[i] = {k, static_cast<std::uint32_t>(i)};
    }
    std::sort(keys.begin(), keys.end());
    std::vector<std::uint8_t> keep(nt, 1);
    for (std::size_t i = 1; i < nt; ++i) {
        if (keys[i].first == keys[i - 1].first) keep[keys[i].second] = 0;
    }
    return remove_triangles_if_not(mesh, [&](std::size_t i) { return keep[i] != 0; });
}

std::uint64_t directed_key(std::uint32_t u, std::uint32_t v) {
    return (std::uint64_t{u} << 32) | v;
}

// Removes collinear (zero-area, distinct corners) triangles. Removing a triangle whose corner c
// lies on its longest edge a-b alone would leave a slit: the neighbour across a-b still uses
// the whole edge while the neighbours across b-c and c-a lose their partner. Splitting that
// neighbour (b, a, x) at c into (b, c, x) and (c, a, x) closes it with the same orientation
// and area. This needs exactly one neighbour across a-b, itself not degenerate and not
// already changed in this round; triangles that wait for a neighbour get another round, and
// the rest are removed without a split.
void remove_collinear(TriangleMesh& mesh, RepairReport& report) {
    constexpr int kRounds = 4;
    for (int round = 0; round < kRounds; ++round) {
        const bool last = round + 1 == kRounds;
        std::vector<std::uint32_t> degenerate;
        for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
            const Triangle& t = mesh.triangles[i];
            if (is_degenerate(mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]])) {
                degenerate.push_back(static_cast<std::uint32_t>(i));
            }
        }
        if (degenerate.empty()) return;

        // Longest edge (a, b) and middle corner c of each, and who uses a-b in either direction.
        auto split_of = [&](std::uint32_t i) {
            const Triangle& t = mesh.triangles[i];
            int best = 0;
            double best_len = -1.0;
            for (int k = 0; k < 3; ++k) {
                const core::Vec3d e = mesh.vertices[t[(k + 1) % 3]] - mesh.vertices[t[k]];
                if (core::dot(e, e) > best_len) {
                    best_len = core::dot(e, e);
                    best = k;
                }
            }
            return std::array<std::uint32_t, 3>{t[best], t[(best + 1) % 3], t[(best + 2) % 3]};
        };
        std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> users;
        for (std::uint32_t i : degenerate) {
            const auto [a, b, c] = split_of(i);
            users.try_emplace(directed_key(a, b));
            users.try_emplace(directed_key(b, a));
        }
        for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
            const Triangle& t = mesh.triangles[i];
            for (int k = 0; k < 3; ++k) {
                auto it = users.find(directed_key(t[k], t[(k + 1) % 3]));
                if (it != users.end()) it->second.push_back(static_cast<std::uint32_t>(i));
            }
        }

        std::vector<std::uint8_t> is_degenerate_now(mesh.triangles.size(), 0);
        for (std::uint32_t i : degenerate) is_degenerate_now[i] = 1;
        std::vector<std::uint8_t> touched(mesh.triangles.size(), 0);
        std::vector<std::uint8_t> remove(mesh.triangles.size(), 0);
        bool deferred = false;
        for (std::uint32_t i : degenerate) {
            if (touched[i]) {
                deferred = true;
                continue;
            }
            const auto [a, b, c] = split_of(i);
            const std::vector<std::uint32_t>& same = users[directed_key(a, b)];
            const std::vector<std::uint32_t>& opposite = users[directed_key(b, a)];
            if (same.size() == 1 && opposite.size() == 1) {
                const std::uint32_t n = opposite.front();
                if (is_degenerate_now[n] || touched[n]) {
                    if (!last) {
                        deferred = true;
                        continue;
                    }
                } else {
                    Triangle& nt = mesh.triangles[n];
                    while (!(nt[0] == b && nt[1] == a))
                        std::rotate(nt.begin(), nt.begin() + 1, nt.end());
                    const std::uint32_t x = nt[2];
                    nt = {b, c, x};
                    mesh.triangles.push_back({c, a, x});
                    touched[n] = 1;
                    touched.push_back(1);
                    remove.push_back(0);
                    is_degenerate_now.push_back(0);
                    ++report.split_triangles;
                }
            }
            remove[i] = 1;
            touched[i] = 1;
        }
        report.removed_degenerate_triangles +=
            remove_triangles_if_not(mesh, [&](std::size_t i) { return remove[i] == 0; });
        if (!deferred) return;
    }
}

// Per-half-edge neighbours: across[3t + k] is the half-edge on the other side of edge k of
// triangle t (from t[k] to t[k+1]) when exactly two half-edges use that edge, else kNone.
// Built like the validation pass: half-edges filed under their smaller vertex, sorted.
struct Adjacency {
    std::vector<std::uint32_t> across;
    std::vector<std::uint8_t> nonmanifold_vertex;  // touches an edge used more than twice
};

Adjacency build_adjacency(const TriangleMesh& mesh) {
    const std::size_t nv = mesh.vertices.size();
    const std::size_t nt = mesh.triangles.size();
    Adjacency adj{std::vector<std::uint32_t>(3 * nt, kNone), std::vector<std::uint8_t>(nv, 0)};
    std::vector<std::uint32_t> start(nv + 1, 0);
    for (const Triangle& t : mesh.triangles) {
        for (int k = 0; k < 3; ++k) ++start[std::min(t[k], t[(k + 1) % 3]) + 1];
    }
    for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
    std::vector<std::uint64_t> entries(start[nv]);
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < nt; ++i) {
        const Triangle& t = mesh.triangles[i];
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t u = t[k];
            const std::uint32_t v = t[(k + 1) % 3];
            const std::uint64_t hi = std::max(u, v);
            entries[fill[std::min(u, v)]++] = (hi << 32) | (3 * i + static_cast<std::size_t>(k));
        }
    }
    for (std::size_t lo = 0; lo < nv; ++lo) {
        auto* b = entries.data() + start[lo];
        auto* e = entries.data() + start[lo + 1];
        std::sort(b, e);
        for (auto* g = b; g < e;) {
            auto* ge = g + 1;
            while (ge < e && (*ge >> 32) == (*g >> 32)) ++ge;
            if (ge - g == 2) {
                const auto h0 = static_cast<std::uint32_t>(g[0] & 0xffffffffu);
                const auto h1 = static_cast<std::uint32_t>(g[1] & 0xffffffffu);
                adj.across[h0] = h1;
                adj.across[h1] = h0;
            } else if (ge - g > 2) {
                adj.nonmanifold_vertex[lo] = 1;
                adj.nonmanifold_vertex[*g >> 32] = 1;
            }
            g = ge;
        }
    }
    return adj;
}

// The winding number of a closed shell around p: the sum of the solid angles of its triangles
// seen from p (Van Oosterom and Strackee, 1983) over 4 pi; about +-1 inside, 0 outside,
// whichever way the shell is oriented. Robust for points off the surface, unlike ray parity.
double winding_number(const TriangleMesh& mesh, const std::vector<std::uint32_t>& shell,
                      const core::Vec3d& p) {
    double sum = 0.0;
    for (std::uint32_t i : shell) {
        const Triangle& t = mesh.triangles[i];
        const core::Vec3d a = mesh.vertices[t[0]] - p;
        const core::Vec3d b = mesh.vertices[t[1]] - p;
        const core::Vec3d c = mesh.vertices[t[2]] - p;
        const double la = core::norm(a);
        const double lb = core::norm(b);
        const double lc = core::norm(c);
        const double num = core::dot(a, core::cross(b, c));
        const double den =
            la * lb * lc + core::dot(a, b) * lc + core::dot(a, c) * lb + core::dot(b, c) * la;
        sum += 2.0 * std::atan2(num, den);
    }
    return sum / (4.0 * std::numbers::pi);
}

bool box_contains(const core::Box3d& outer, const core::Box3d& inner) {
    return outer.min.x <= inner.min.x && outer.min.y <= inner.min.y && outer.min.z <= inner.min.z &&
           inner.max.x <= outer.max.x && inner.max.y <= outer.max.y && inner.max.z <= outer.max.z;
}

// Orientation. Bodies (vertex-connected) with a non-manifold edge are left alone: across such
// an edge "the other side" is ambiguous. In the others, a breadth-first search from the
// lowest-index triangle of each shell (the triangles connected through two-sided edges)
// decides for every triangle whether it agrees with the seed; the minority is flipped. A closed
// shell (no boundary edge) with negative volume is then inverted unless it is nested in an
// odd number of other closed shells (then it bounds a void, and negative is right).
void orient(TriangleMesh& mesh, RepairReport& report) {
    const std::size_t nt = mesh.triangles.size();
    if (nt == 0) return;
    const Adjacency adj = build_adjacency(mesh);

    const std::vector<std::uint32_t> body = vertex_bodies(mesh);
    std::vector<std::uint8_t> body_nonmanifold(mesh.vertices.size(), 0);
    std::vector<std::uint8_t> body_seen(mesh.vertices.size(), 0);
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        if (adj.nonmanifold_vertex[v]) body_nonmanifold[body[v]] = 1;
    }
    for (const Triangle& t : mesh.triangles) {
        const std::uint32_t root = body[t[0]];
        if (body_nonmanifold[root] && !body_seen[root]) ++report.unoriented_bodies;
        body_seen[root] = 1;
    }

    struct Shell {
        std::vector<std::uint32_t> triangles;
        bool closed = true;
    };
    std::vector<Shell> shells;
    std::vector<std::uint8_t> visited(nt, 0);
    std::vector<std::uint8_t> flip(nt, 0);
    std::vector<std::uint32_t> queue;
    for (std::size_t seed = 0; seed < nt; ++seed) {
        if (visited[seed] || body_nonmanifold[body[mesh.triangles[seed][0]]]) continue;
        Shell shell;
        queue.assign(1, static_cast<std::uint32_t>(seed));
        visited[seed] = 1;
        std::size_t flipped = 0;
        for (std::size_t q = 0; q < queue.size(); ++q) {
            const std::uint32_t t = queue[q];
            shell.triangles.push_back(t);
            flipped += flip[t];
            for (std::uint32_t k = 0; k < 3; ++k) {
                const std::uint32_t other = adj.across[3 * t + k];
                if (other == kNone) {
                    shell.closed = false;
                    continue;
                }
                const std::uint32_t n = other / 3;
                if (visited[n]) continue;  // a conflict here means a non-orientable shell
                // Consistent neighbours traverse the shared edge in opposite directions.
                const bool same_direction = mesh.triangles[t][k] == mesh.triangles[n][other % 3];
                flip[n] = flip[t] ^ (same_direction ? 1 : 0);
                visited[n] = 1;
                queue.push_back(n);
            }
        }
        if (2 * flipped > shell.triangles.size()) {
            for (std::uint32_t t : shell.triangles) flip[t] ^= 1;
        }
        shells.push_back(std::move(shell));
    }
    for (std::size_t t = 0; t < nt; ++t) {
        if (flip[t]) {
            std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
            ++report.reoriented_triangles;
        }
    }

    // Volumes and boxes of the closed shells.
    struct ClosedShell {
        std::size_t shell;
        double six_volume;
        core::Box3d box;
    };
    std::vector<ClosedShell> closed;
    for (std::size_t s = 0; s < shells.size(); ++s) {
        if (!shells[s].closed) continue;
        const std::vector<std::uint32_t>& tris = shells[s].triangles;
        const core::Vec3d o = mesh.vertices[mesh.triangles[tris.front()][0]];
        ClosedShell c{s, 0.0, {}};
        for (std::uint32_t i : tris) {
            const Triangle& t = mesh.triangles[i];
            c.six_volume += detail::six_volume_term(o, mesh.vertices[t[0]], mesh.vertices[t[1]],
                                                    mesh.vertices[t[2]]);
            for (std::uint32_t v : t) c.box.add(mesh.vertices[v]);
        }
        closed.push_back(c);
    }
    for (const ClosedShell& c : closed) {
        if (!(c.six_volume < 0.0)) continue;
        const Shell& shell = shells[c.shell];
        const Triangle& probe_tri = mesh.triangles[shell.triangles.front()];
        const core::Vec3d probe = (mesh.vertices[probe_tri[0]] + mesh.vertices[probe_tri[1]] +
                                   mesh.vertices[probe_tri[2]]) /
                                  3.0;
        std::size_t depth = 0;
        for (const ClosedShell& other : closed) {
            if (other.shell == c.shell || !box_contains(other.box, c.box)) continue;
            if (std::fabs(winding_number(mesh, shells[other.shell].triangles, probe)) > 0.5) {
                ++depth;
            }
        }
        if (depth % 2 == 1) continue;
        for (std::uint32_t i : shell.triangles)
            std::swap(mesh.triangles[i][1], mesh.triangles[i][2]);
        if (!report.first_inverted_at) report.first_inverted_at = probe;
        ++report.inverted_shells;
        report.inverted_shell_triangles += shell.triangles.size();
    }
}

}  // namespace

std::vector<std::string> RepairReport::lines() const {
    std::vector<std::string> out;
    auto add = [&](std::size_t n, const char* one, const char* many, const std::string& tail = {}) {
        if (n > 0) out.push_back(fmt::format("{} {}{}", n, n == 1 ? one : many, tail));
    };
    add(welded_vertices, "vertex welded", "vertices welded",
        fmt::format(" (closer than {:.3g} mm)", weld_distance_mm));
    add(removed_nonfinite_triangles, "triangle with a NaN or infinite corner removed",
        "triangles with NaN or infinite corners removed");
    add(removed_degenerate_triangles, "degenerate triangle removed", "degenerate triangles removed",
        split_triangles > 0
            ? fmt::format(" ({} neighbouring {} split to keep the surface closed)", split_triangles,
                          split_triangles == 1 ? "triangle" : "triangles")
            : std::string{});
    add(removed_duplicate_triangles, "duplicate triangle removed", "duplicate triangles removed");
    add(reoriented_triangles, "triangle flipped to match its neighbours",
        "triangles flipped to match their neighbours");
    add(inverted_shells, "inside-out shell turned outside out",
        "inside-out shells turned outside out",
        fmt::format(" ({} triangles)", inverted_shell_triangles));
    add(removed_unused_vertices, "unused vertex removed", "unused vertices removed");
    add(unoriented_bodies, "body with non-manifold edges left unoriented",
        "bodies with non-manifold edges left unoriented");
    return out;
}

bool RepairReport::changed() const {
    return welded_vertices + removed_nonfinite_triangles + removed_degenerate_triangles +
               split_triangles + removed_duplicate_triangles + removed_unused_vertices +
               reoriented_triangles + inverted_shells >
           0;
}

namespace detail {

InsideOutShells inward_pieces(const TriangleMesh& mesh) {
    InsideOutShells out;
    const std::size_t nt = mesh.triangles.size();
    if (nt == 0) return out;
    const Adjacency adj = build_adjacency(mesh);
    // Pieces: triangles connected through two-sided edges; each keeps its largest triangle.
    struct Piece {
        std::uint32_t largest = 0;
        double largest_area = -1.0;
        double area = 0.0;
    };
    std::vector<Piece> pieces;
    std::vector<std::uint8_t> seen(nt, 0);
    std::vector<std::uint32_t> queue;
    for (std::size_t seed = 0; seed < nt; ++seed) {
        if (seen[seed]) continue;
        Piece piece;
        queue.assign(1, static_cast<std::uint32_t>(seed));
        seen[seed] = 1;
        for (std::size_t q = 0; q < queue.size(); ++q) {
            const std::uint32_t t = queue[q];
            const Triangle& tri = mesh.triangles[t];
            const double a = twice_area_term(mesh.vertices[tri[0]], mesh.vertices[tri[1]],
                                             mesh.vertices[tri[2]]);
            piece.area += a;
            if (a > piece.largest_area) piece.largest_area = a, piece.largest = t;
            for (std::uint32_t k = 0; k < 3; ++k) {
                const std::uint32_t other = adj.across[3 * t + k];
                if (other == kNone || seen[other / 3]) continue;
                seen[other / 3] = 1;
                queue.push_back(other / 3);
            }
        }
        pieces.push_back(piece);
    }
    // Each test is a pass over the whole mesh: the largest pieces first, at most 64.
    std::stable_sort(pieces.begin(), pieces.end(),
                     [](const Piece& a, const Piece& b) { return a.area > b.area; });
    pieces.resize(std::min<std::size_t>(pieces.size(), 64));
    std::vector<std::uint32_t> all(nt);
    for (std::size_t i = 0; i < nt; ++i) all[i] = static_cast<std::uint32_t>(i);
    std::vector<std::uint8_t> inward(pieces.size(), 0);
    std::vector<core::Vec3d> probe(pieces.size());
    tbb::parallel_for(std::size_t{0}, pieces.size(), [&](std::size_t i) {
        const Triangle& t = mesh.triangles[pieces[i].largest];
        const core::Vec3d& a = mesh.vertices[t[0]];
        const core::Vec3d& b = mesh.vertices[t[1]];
        const core::Vec3d& c = mesh.vertices[t[2]];
        const core::Vec3d n = core::cross(b - a, c - a);
        const double twice_area = core::norm(n);
        const double perimeter = core::norm(b - a) + core::norm(c - b) + core::norm(a - c);
        if (!(twice_area > 0.0) || !(perimeter > 0.0)) return;
        // A hundredth of the inradius behind the centroid, on the side the winding calls
        // inside: nearer to this triangle than to any other part of the surface.
        const double eps = 0.01 * twice_area / perimeter;
        probe[i] = (a + b + c) / 3.0;
        const core::Vec3d p = probe[i] - n * (eps / twice_area);
        inward[i] = winding_number(mesh, all, p) < 0.5 ? 1 : 0;
    });
    for (std::size_t i = 0; i < pieces.size(); ++i) {
        if (!inward[i]) continue;
        if (!out.example) out.example = probe[i];
        ++out.count;
    }
    return out;
}

InsideOutShells inside_out_shells(const TriangleMesh& mesh) {
    TriangleMesh copy = mesh;  // orient works in place; only its verdict is wanted here
    RepairReport report;
    orient(copy, report);
    return {report.inverted_shells, report.first_inverted_at};
}

}  // namespace detail

RepairReport repair(TriangleMesh& mesh, const RepairOptions& options) {
    RepairReport report;
    const std::size_t original_vertices = mesh.vertices.size();

    // 1. Weld.
    {
        const std::vector<std::uint8_t> used = used_vertices(mesh);
        double d = options.weld_distance_mm;
        if (d == 0.0) {
            core::Box3d box;
            for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
                if (used[v] && core::is_finite(mesh.vertices[v])) box.add(mesh.vertices[v]);
            }
            d = core::kRepairWeldRelative * core::norm(box.size());
        }
        if (d > 0.0 && std::isfinite(d)) {
            report.weld_distance_mm = d;
            report.welded_vertices = weld_near(mesh, d, used);
        }
    }

    // 2. Triangles that cannot be part of a surface.
    report.removed_nonfinite_triangles = remove_triangles_if_not(mesh, [&](std::size_t i) {
        const Triangle& t = mesh.triangles[i];
        return core::is_finite(mesh.vertices[t[0]]) && core::is_finite(mesh.vertices[t[1]]) &&
               core::is_finite(mesh.vertices[t[2]]);
    });
    // A triangle with a repeated index uses one edge in both directions; removing it leaves its
    // two neighbours facing each other, so no split is needed.
    report.removed_degenerate_triangles = remove_triangles_if_not(
        mesh, [&](std::size_t i) { return !has_repeated_index(mesh.triangles[i]); });
    report.removed_duplicate_triangles = remove_duplicates(mesh);
    remove_collinear(mesh, report);

    // 3. Orientation.
    orient(mesh, report);

    // 4. Unused vertices (including those welded away), keeping the order of the others.
    {
        const std::vector<std::uint8_t> used = used_vertices(mesh);
        std::vector<std::uint32_t> index(mesh.vertices.size(), kNone);
        std::size_t kept = 0;
        for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
            if (!used[v]) continue;
            index[v] = static_cast<std::uint32_t>(kept);
            mesh.vertices[kept++] = mesh.vertices[v];
        }
        mesh.vertices.resize(kept);
        for (Triangle& t : mesh.triangles) {
            for (std::uint32_t& v : t) v = index[v];
        }
        report.removed_unused_vertices = original_vertices - kept - report.welded_vertices;
    }
    return report;
}

}  // namespace maxslice::mesh
