// The wire tree of loops that already bound a region: a fast path for build_wire_tree with
// the positive fill rule.
//
// A cut through a closed manifold mesh gives loops that are simple, pairwise disjoint and
// oriented with the solid on their left. Clipper's union then keeps the loops and only
// re-derives the nesting, at about 0.4 us per vertex. But "keeps" is not exact: Clipper drops
// repeated points and the middle one of three collinear points, and it sweeps the plane along
// y with edge positions rounded to whole units at every vertex height, so features narrower
// than about a unit (a crack between two loops, a sliver notch) can be merged or cut off.
// This fast path makes the same tree in linear expected time only where the result is certain
// to be the same:
//   1. each loop is cleaned as Clipper cleans it: repeated points dropped, then every vertex
//      on the line through its neighbours and between them (a straight run) dropped; a loop
//      that doubles back on itself (a spike) or keeps fewer than 3 points is refused;
//   2. no two edges meet, except consecutive edges of one loop at their shared vertex (exact
//      integer tests; candidate pairs from a uniform grid over the edges' boxes);
//   3. at every vertex height where two edges are both cut by the sweep line and at least
//      one of them has its position rounded there (the height is inside its range, not at
//      an end), their true positions are more than kGap apart. Clipper's rounded positions
//      (half a unit off at most, plus floating-point error far below 1/1024) then keep the
//      true order with no ties: it sees no false crossing or contact, and no new vertex or
//      join is made. Positions are linear in height, so a pair is checked at the lowest and
//      highest such heights of its common range only; most pairs share no height at all;
//   4. the loops are then disjoint Jordan curves: each loop's enclosing loops are those a ray
//      from its smallest point crosses an odd number of times, its parent the smallest of
//      them (enclosing loops nest, so their areas strictly decrease);
//   5. the fill must be exactly 0 or 1 everywhere: outermost loops counter-clockwise, and
//      each loop oriented opposite to its parent. Then the positive-fill union is bounded by
//      exactly these loops, outers counter-clockwise and holes clockwise as Clipper returns
//      them, and nested as found in 4.
// Any other input (crossings, touching or nearly touching loops, sliver notches, overlapping
// bodies, loops of the wrong orientation, coordinates outside the documented range, or a grid
// too crowded to be fast) is refused and goes to Clipper. tests/unit/geom2d compares the two.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>

#include "maxslice/geom2d/wire_tree.hpp"

namespace maxslice::geom2d::detail {
namespace {

// 128-bit integers (a GCC/Clang extension); __extension__ keeps -Wpedantic quiet.
__extension__ typedef __int128 Int128;

// Positions on a sweep line closer than kGap = 1 + 1/1024 units, one of them rounded, could
// be tied or swapped by Clipper's rounding (step 3). As a fraction:
constexpr std::int64_t kGapNum = 1025;
constexpr std::int64_t kGapDen = 1024;

// Differences of coordinates within kMaxCoordinateUm stay below 2^31, so the two products
// of a cross or dot product stay below 2^62 and their sum or difference fits in 64 bits.
std::int64_t cross(const Point2& o, const Point2& a, const Point2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

std::int64_t dot(const Point2& o, const Point2& a, const Point2& b) {
    return (a.x - o.x) * (b.x - o.x) + (a.y - o.y) * (b.y - o.y);
}

int sign(std::int64_t v) {
    return (v > 0) - (v < 0);
}

bool in_range(const Point2& p) {
    return p.x >= -kMaxCoordinateUm && p.x <= kMaxCoordinateUm && p.y >= -kMaxCoordinateUm &&
           p.y <= kMaxCoordinateUm;
}

// Step 1: the loop as Clipper leaves it, or false when it is degenerate (out of range,
// doubling back, or fewer than 3 points left).
bool clean_loop(const Path2& in, Path2& out) {
    Path2 dedup;
    dedup.reserve(in.size());
    for (const Point2& p : in) {
        if (!in_range(p)) return false;
        if (dedup.empty() || dedup.back() != p) dedup.push_back(p);
    }
    while (dedup.size() > 1 && dedup.front() == dedup.back()) dedup.pop_back();
    const std::size_t n = dedup.size();
    if (n < 3) return false;
    // A vertex strictly inside a straight run is dropped; since every dropped vertex lies
    // between its neighbours, a run keeps its direction and dropping them all at once
    // leaves the same corners as Clipper's one-at-a-time removal.
    out.clear();
    out.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Point2& prev = dedup[i == 0 ? n - 1 : i - 1];
        const Point2& cur = dedup[i];
        const Point2& next = dedup[i + 1 == n ? 0 : i + 1];
        if (cross(prev, cur, next) != 0) {
            out.push_back(cur);
        } else if (dot(cur, prev, next) >= 0) {
            return false;  // a spike: the loop doubles back on itself
        }
    }
    return out.size() >= 3;
}

Int128 twice_area(const Path2& p) {
    Int128 sum = 0;
    for (std::size_t i = 0, j = p.size() - 1; i < p.size(); j = i++) {
        sum += static_cast<Int128>(p[j].x) * p[i].y - static_cast<Int128>(p[j].y) * p[i].x;
    }
    return sum;
}

struct Edge {
    Point2 a, b;
    std::int64_t x0, y0, x1, y1;  // bounding box grown by one unit each way
    std::uint32_t loop;
    std::uint32_t index;  // position of a in its loop
    std::int32_t cx0;     // first grid column covered by the box
};

// Do two closed segments share a point? Exact.
bool segments_meet(const Edge& s, const Edge& t) {
    const int o1 = sign(cross(s.a, s.b, t.a)), o2 = sign(cross(s.a, s.b, t.b));
    if (o1 * o2 > 0) return false;
    const int o3 = sign(cross(t.a, t.b, s.a)), o4 = sign(cross(t.a, t.b, s.b));
    if (o3 * o4 > 0) return false;
    if (o1 != 0 || o2 != 0 || o3 != 0 || o4 != 0) return true;
    // Collinear: they meet when their ranges overlap along the line.
    return std::max(std::min(s.a.x, s.b.x), std::min(t.a.x, t.b.x)) <=
               std::min(std::max(s.a.x, s.b.x), std::max(t.a.x, t.b.x)) &&
           std::max(std::min(s.a.y, s.b.y), std::min(t.a.y, t.b.y)) <=
               std::min(std::max(s.a.y, s.b.y), std::max(t.a.y, t.b.y));
}

// The sorted distinct vertex heights: the sweep lines at which Clipper places edges.
class Heights {
public:
    explicit Heights(const std::vector<Path2>& loops) : loops_(loops) {}
    // The nearest height above y (below when down), or y when there is none.
    std::int64_t next(std::int64_t y, bool down) {
        if (sorted_.empty()) {
            for (const Path2& p : loops_) {
                for (const Point2& pt : p) sorted_.push_back(pt.y);
            }
            std::sort(sorted_.begin(), sorted_.end());
            sorted_.erase(std::unique(sorted_.begin(), sorted_.end()), sorted_.end());
        }
        if (down) {
            const auto it = std::lower_bound(sorted_.begin(), sorted_.end(), y);
            return it == sorted_.begin() ? y : *(it - 1);
        }
        const auto it = std::upper_bound(sorted_.begin(), sorted_.end(), y);
        return it == sorted_.end() ? y : *it;
    }

private:
    const std::vector<Path2>& loops_;
    std::vector<std::int64_t> sorted_;
};

// The x range [lo, hi] of an edge at height y (inside its range) as fractions over den > 0:
// one point for a sloped edge, the whole edge for a horizontal one.
struct XRange {
    Int128 lo, hi, den;
};

XRange x_at(const Point2& a, const Point2& b, std::int64_t y) {
    if (a.y == b.y) return {std::min(a.x, b.x), std::max(a.x, b.x), 1};
    const Point2& p = a.y < b.y ? a : b;
    const Point2& q = a.y < b.y ? b : a;
    const Int128 den = q.y - p.y;
    const Int128 x = static_cast<Int128>(p.x) * den + static_cast<Int128>(q.x - p.x) * (y - p.y);
    return {x, x, den};
}

// Are the edges' positions at height y more than kGap apart? (Both must span y.)
bool apart_at(const Edge& s, const Edge& t, std::int64_t y) {
    const XRange r = x_at(s.a, s.b, y), q = x_at(t.a, t.b, y);
    // gap = q.lo / q.den - r.hi / r.den (t right of s) or r.lo / r.den - q.hi / q.den.
    Int128 gap = q.lo * r.den - r.hi * q.den;
    if (gap <= 0) gap = r.lo * q.den - q.hi * r.den;
    return gap * kGapDen > kGapNum * r.den * q.den;
}

bool ends_at(const Edge& e, std::int64_t y) {
    return e.a.y == y || e.b.y == y;
}

// Steps 2 and 3 for two edges that are not consecutive in one loop.
bool pair_clear(const Edge& s, const Edge& t, Heights& heights) {
    const std::int64_t lo = std::max(std::min(s.a.y, s.b.y), std::min(t.a.y, t.b.y));
    const std::int64_t hi = std::min(std::max(s.a.y, s.b.y), std::max(t.a.y, t.b.y));
    if (lo > hi) return true;  // never on one sweep line, so they cannot meet either
    // Most pairs are further apart across than any gap that matters.
    if (std::max(s.a.x, s.b.x) + 2 < std::min(t.a.x, t.b.x) ||
        std::max(t.a.x, t.b.x) + 2 < std::min(s.a.x, s.b.x)) {
        return true;
    }
    if (segments_meet(s, t)) return false;
    // At a height where both edges end, both positions are exact (and distinct: the
    // edges do not meet); the check moves to the next sweep line inward.
    const bool exact_lo = ends_at(s, lo) && ends_at(t, lo);
    const bool exact_hi = ends_at(s, hi) && ends_at(t, hi);
    if (lo == hi) return exact_lo || apart_at(s, t, lo);
    // First a quick conservative check: sweep lines inward of an exact end are at least a
    // unit in, and over a wider range the smallest gap can only be smaller.
    const std::int64_t c0 = exact_lo ? lo + 1 : lo;
    const std::int64_t c1 = exact_hi ? hi - 1 : hi;
    if (c0 > c1) return true;
    if (apart_at(s, t, c0) && (c1 == c0 || apart_at(s, t, c1))) return true;
    const std::int64_t y0 = exact_lo ? heights.next(lo, false) : lo;
    const std::int64_t y1 = exact_hi ? heights.next(hi, true) : hi;
    if (y0 > y1) return true;
    return apart_at(s, t, y0) && (y1 == y0 || apart_at(s, t, y1));
}

// A uniform grid over the boxes of a group of edges, cells a power of two wide (no division),
// about two cells per edge; a box is listed in every cell it covers.
class Grid {
public:
    // Returns false when the edges are too crowded for the grid to beat Clipper.
    bool build(std::vector<Edge>& edges, std::int64_t x0, std::int64_t y0, std::int64_t x1,
               std::int64_t y1) {
        x0_ = x0;
        y0_ = y0;
        const std::size_t n = edges.size();
        const std::uint64_t max_cells = 2 * n + 16;
        // Coordinates are within kMaxCoordinateUm, so spans are below 2^32 and the cell
        // count below 2^64.
        const std::uint64_t w = static_cast<std::uint64_t>(x1 - x0);
        const std::uint64_t h = static_cast<std::uint64_t>(y1 - y0);
        const double cell_area = static_cast<double>(w + 1) * static_cast<double>(h + 1) /
                                 static_cast<double>(max_cells);
        shift_ = 0;
        while (static_cast<double>(std::uint64_t{1} << (2 * shift_)) < cell_area) ++shift_;
        while (((w >> shift_) + 1) * ((h >> shift_) + 1) > max_cells) ++shift_;
        nx_ = col(x1) + 1;
        ny_ = row(y1) + 1;
        start_.assign(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_) + 1, 0);
        std::size_t total = 0;
        for (Edge& e : edges) {
            e.cx0 = col(e.x0);
            const std::int32_t cx1 = col(e.x1), cy0 = row(e.y0), cy1 = row(e.y1);
            total +=
                static_cast<std::size_t>(cx1 - e.cx0 + 1) * static_cast<std::size_t>(cy1 - cy0 + 1);
            if (total > 16 * n + 1024) return false;
            for (std::int32_t cy = cy0; cy <= cy1; ++cy) {
                for (std::int32_t cx = e.cx0; cx <= cx1; ++cx) ++start_[cell(cx, cy) + 1];
            }
        }
        std::size_t pairs = 0;
        for (std::size_t c = 1; c < start_.size(); ++c) {
            pairs += static_cast<std::size_t>(start_[c]) * start_[c];
            start_[c] += start_[c - 1];
        }
        if (pairs > 64 * n + 4096) return false;
        items_.resize(total);
        fill_.assign(start_.begin(), start_.end() - 1);
        for (std::size_t i = 0; i < n; ++i) {
            const Edge& e = edges[i];
            const std::int32_t cx1 = col(e.x1), cy0 = row(e.y0), cy1 = row(e.y1);
            for (std::int32_t cy = cy0; cy <= cy1; ++cy) {
                for (std::int32_t cx = e.cx0; cx <= cx1; ++cx) {
                    items_[fill_[cell(cx, cy)]++] = static_cast<std::uint32_t>(i);
                }
            }
        }
        return true;
    }

    std::int32_t col(std::int64_t x) const {
        return static_cast<std::int32_t>(static_cast<std::uint64_t>(x - x0_) >> shift_);
    }
    std::int32_t row(std::int64_t y) const {
        return static_cast<std::int32_t>(static_cast<std::uint64_t>(y - y0_) >> shift_);
    }
    std::int32_t columns() const { return nx_; }
    std::int32_t rows() const { return ny_; }
    std::size_t cell(std::int32_t cx, std::int32_t cy) const {
        return static_cast<std::size_t>(cy) * static_cast<std::size_t>(nx_) +
               static_cast<std::size_t>(cx);
    }
    const std::uint32_t* begin(std::size_t c) const { return items_.data() + start_[c]; }
    const std::uint32_t* end(std::size_t c) const { return items_.data() + start_[c + 1]; }

private:
    std::int64_t x0_ = 0, y0_ = 0;
    int shift_ = 0;
    std::int32_t nx_ = 0, ny_ = 0;
    std::vector<std::uint32_t> start_, fill_, items_;
};

// Steps 2 and 3 for every pair of edges that are not consecutive in one loop: false when a
// pair meets or comes too close on a sweep line.
bool pairs_clear(const std::vector<Edge>& edges, const Grid& grid,
                 const std::vector<std::uint32_t>& loop_size, Heights& heights) {
    for (std::int32_t cy = 0; cy < grid.rows(); ++cy) {
        for (std::int32_t cx = 0; cx < grid.columns(); ++cx) {
            const std::size_t c = grid.cell(cx, cy);
            for (const std::uint32_t* i = grid.begin(c); i != grid.end(c); ++i) {
                const Edge& s = edges[*i];
                for (const std::uint32_t* j = i + 1; j != grid.end(c); ++j) {
                    const Edge& t = edges[*j];
                    if (s.x1 < t.x0 || t.x1 < s.x0 || s.y1 < t.y0 || t.y1 < s.y0) continue;
                    // Test each pair once: in the cell holding the low corner of the overlap
                    // of their boxes.
                    if (grid.col(std::max(s.x0, t.x0)) != cx ||
                        grid.row(std::max(s.y0, t.y0)) != cy) {
                        continue;
                    }
                    if (s.loop == t.loop) {
                        const std::uint32_t last = loop_size[s.loop] - 1;
                        const std::uint32_t i1 = s.index == last ? 0 : s.index + 1;
                        const std::uint32_t j1 = t.index == last ? 0 : t.index + 1;
                        if (i1 == t.index || j1 == s.index) continue;  // see extrema_clear
                    }
                    if (!pair_clear(s, t, heights)) return false;
                }
            }
        }
    }
    return true;
}

// A y-monotone loop's two chains from its lowest point s to its highest t (lowest: the
// smallest y, then x), each edge stored from its lower end up: chain a runs forward from s,
// chain b backward. Along a chain both ends of the edges' height ranges never decrease.
// nullopt when the loop is not y-monotone (a chain goes down somewhere).
struct Chains {
    std::vector<Edge> a, b;
};

std::optional<Chains> monotone_chains(const Path2& p) {
    const std::size_t n = p.size();
    const auto low = [](const Point2& u, const Point2& v) {
        return u.y != v.y ? u.y < v.y : u.x < v.x;
    };
    std::size_t s = 0, t = 0;
    for (std::size_t i = 1; i < n; ++i) {
        if (low(p[i], p[s])) s = i;
        if (low(p[t], p[i])) t = i;
    }
    const auto next = [n](std::size_t i) { return i + 1 == n ? 0 : i + 1; };
    const auto prev = [n](std::size_t i) { return i == 0 ? n - 1 : i - 1; };
    // x0 and x1 hold the edge's x range grown by one unit each way, as the grid's boxes.
    const auto edge = [](const Point2& u, const Point2& v) {
        return Edge{u, v, std::min(u.x, v.x) - 1, 0, std::max(u.x, v.x) + 1, 0, 0, 0, 0};
    };
    Chains c;
    c.a.reserve(n);
    c.b.reserve(n);
    for (std::size_t i = s; i != t; i = next(i)) {
        if (p[next(i)].y < p[i].y) return std::nullopt;
        c.a.push_back(edge(p[i], p[next(i)]));
    }
    for (std::size_t i = s; i != t; i = prev(i)) {
        if (p[prev(i)].y < p[i].y) return std::nullopt;
        c.b.push_back(edge(p[i], p[prev(i)]));
    }
    return c;
}

// Steps 2 and 3 for the pairs of an edge of chain c and an edge of chain d whose height
// ranges overlap (touching ranges count: a horizontal edge overlaps every edge that reaches
// its height); no other pair of them shares a sweep line, so none can meet. The d edges that
// overlap a c edge are a run that only moves forward: O(|c| + |d|) plus the pairs. With
// `one_loop` (the two chains of one loop) their first edges and their last edges are
// consecutive, at s and at t: extrema_clear checks those.
bool chains_clear(const std::vector<Edge>& c, const std::vector<Edge>& d, bool one_loop,
                  Heights& heights) {
    std::size_t j0 = 0;
    for (std::size_t i = 0; i < c.size(); ++i) {
        const Edge& e = c[i];
        while (j0 < d.size() && d[j0].b.y < e.a.y) ++j0;
        for (std::size_t j = j0; j < d.size() && d[j].a.y <= e.b.y; ++j) {
            // More than two units apart across: pair_clear's first answer, without the call.
            if (e.x1 < d[j].x0 || d[j].x1 < e.x0) continue;
            if (one_loop && ((i == 0 && j == 0) || (i + 1 == c.size() && j + 1 == d.size()))) {
                continue;
            }
            if (!pair_clear(e, d[j], heights)) return false;
        }
    }
    return true;
}

// Groups of at most this many loops, all y-monotone, are checked chain against chain: the
// cost is about (2 g - 1) times their edges, below the grid's for a lone loop (most cuts of
// struts and shafts), a ring (a tube's or a torus's cut: two loops) and a few bosses.
constexpr std::size_t kMaxMergedGroup = 4;

// Steps 2 and 3 for a group of a few loops that are all y-monotone, without a grid. Edges of
// one chain share no sweep line except at their shared vertex, or at both ends of a
// horizontal edge between them where both are exact and distinct (no two consecutive edges
// are collinear), so only pairs from different chains need a check: each loop's two chains
// against each other, and every chain against every chain of the other loops, each pair
// merged in O(n). nullopt when a loop is not y-monotone or the group is too large.
std::optional<bool> monotone_group_clear(const std::vector<Path2>& loops,
                                         const std::vector<std::uint32_t>& group,
                                         Heights& heights) {
    if (group.size() > kMaxMergedGroup) return std::nullopt;
    std::vector<Chains> chains;
    chains.reserve(group.size());
    for (const std::uint32_t l : group) {
        std::optional<Chains> c = monotone_chains(loops[l]);
        if (!c) return std::nullopt;
        chains.push_back(std::move(*c));
    }
    for (std::size_t k = 0; k < chains.size(); ++k) {
        if (!chains_clear(chains[k].a, chains[k].b, true, heights)) return false;
        for (std::size_t m = k + 1; m < chains.size(); ++m) {
            for (const std::vector<Edge>* c : {&chains[k].a, &chains[k].b}) {
                for (const std::vector<Edge>* d : {&chains[m].a, &chains[m].b}) {
                    if (!chains_clear(*c, *d, false, heights)) return false;
                }
            }
        }
    }
    return true;
}

// Step 3 for consecutive edges: they share a sweep line beyond their shared vertex only
// when both leave it upwards or both downwards; their gap grows from there, so the nearest
// sweep line on that side is the one to check (where both end, both are exact).
bool extrema_clear(const std::vector<Path2>& loops, Heights& heights) {
    for (const Path2& p : loops) {
        const std::size_t n = p.size();
        for (std::size_t i = 0; i < n; ++i) {
            const Point2& u = p[i == 0 ? n - 1 : i - 1];
            const Point2& v = p[i];
            const Point2& w = p[i + 1 == n ? 0 : i + 1];
            const bool up = u.y > v.y && w.y > v.y;
            if (!up && !(u.y < v.y && w.y < v.y)) continue;
            const Edge s{v, u, 0, 0, 0, 0, 0, 0, 0};
            const Edge t{v, w, 0, 0, 0, 0, 0, 0, 0};
            // The nearest sweep line is at least a unit away: try that first.
            if (apart_at(s, t, up ? v.y + 1 : v.y - 1)) continue;
            const std::int64_t y = heights.next(v.y, !up);
            if (y == u.y && y == w.y) continue;
            if (!apart_at(s, t, y)) return false;
        }
    }
    return true;
}

}  // namespace

std::optional<WireTree> wire_tree_of_simple_loops(const Paths2& loops) {
    std::vector<Path2> clean;
    clean.reserve(loops.size());
    for (const Path2& loop : loops) {
        if (loop.size() < 3) continue;  // as build_wire_tree: such loops contribute nothing
        if (!clean_loop(loop, clean.emplace_back())) return std::nullopt;
    }
    const std::size_t n_loops = clean.size();
    WireTree tree;
    if (n_loops == 0) return tree;
    Heights heights(clean);
    if (!extrema_clear(clean, heights)) return std::nullopt;

    // Boxes of the loops, grown by a unit each way like the edges' (pairs closer than kGap
    // have overlapping boxes), and groups of loops whose boxes overlap, transitively: edges
    // of different groups are far apart, and a loop can only enclose loops of its group.
    struct Box {
        std::int64_t x0, y0, x1, y1;
    };
    constexpr std::int64_t kGrow = 1;
    std::vector<Box> box(n_loops);
    std::vector<Int128> area(n_loops);
    std::vector<std::uint32_t> loop_size(n_loops);
    for (std::size_t l = 0; l < n_loops; ++l) {
        const Path2& p = clean[l];
        area[l] = twice_area(p);
        if (area[l] == 0) return std::nullopt;
        loop_size[l] = static_cast<std::uint32_t>(p.size());
        Box b{p[0].x, p[0].y, p[0].x, p[0].y};
        for (const Point2& q : p) {
            b.x0 = std::min(b.x0, q.x);
            b.y0 = std::min(b.y0, q.y);
            b.x1 = std::max(b.x1, q.x);
            b.y1 = std::max(b.y1, q.y);
        }
        box[l] = {b.x0 - kGrow, b.y0 - kGrow, b.x1 + kGrow, b.y1 + kGrow};
    }
    std::vector<std::uint32_t> group(n_loops);
    for (std::size_t l = 0; l < n_loops; ++l) group[l] = static_cast<std::uint32_t>(l);
    const auto find = [&](std::uint32_t l) {
        while (group[l] != l) l = group[l] = group[group[l]];
        return l;
    };
    {
        std::vector<std::uint32_t> by_x(n_loops);
        for (std::size_t l = 0; l < n_loops; ++l) by_x[l] = static_cast<std::uint32_t>(l);
        std::sort(by_x.begin(), by_x.end(),
                  [&](std::uint32_t a, std::uint32_t b) { return box[a].x0 < box[b].x0; });
        std::vector<std::uint32_t> active;
        for (const std::uint32_t l : by_x) {
            std::erase_if(active, [&](std::uint32_t k) { return box[k].x1 < box[l].x0; });
            for (const std::uint32_t k : active) {
                if (box[k].y1 >= box[l].y0 && box[l].y1 >= box[k].y0) group[find(k)] = find(l);
            }
            active.push_back(l);
        }
    }
    std::vector<std::vector<std::uint32_t>> members(n_loops);
    for (std::size_t l = 0; l < n_loops; ++l) {
        members[find(static_cast<std::uint32_t>(l))].push_back(static_cast<std::uint32_t>(l));
    }

    std::vector<int> parent(n_loops, -1);
    std::vector<int> depth(n_loops, 0);
    std::vector<std::uint8_t> parity(n_loops, 0);
    std::vector<std::uint32_t> touched;
    std::vector<Edge> edges;
    Grid grid;
    // Step 4 for loop l: the loops whose edges a ray from l's smallest point towards -x
    // crosses an odd number of times enclose it (the point is on no other loop, so the
    // half-open crossing rule counts exactly); its parent is the smallest of them.
    // `touched` lists the loops crossed, with their parity.
    const auto enclosing = [&](std::uint32_t l) {
        Int128 smallest = 0;
        for (const std::uint32_t k : touched) {
            if (parity[k] != 0) {
                ++depth[l];
                const Int128 a = area[k] < 0 ? -area[k] : area[k];
                if (parent[l] < 0 || a < smallest) {
                    smallest = a;
                    parent[l] = static_cast<int>(k);
                }
            }
            parity[k] = 0;
        }
    };
    // Whether edge (a, b) of a loop crosses the ray from p towards -x (half-open in y).
    const auto crosses_ray = [](const Point2& a, const Point2& b, const Point2& p) {
        if ((a.y > p.y) == (b.y > p.y)) return false;
        const std::int64_t o = cross(a, b, p);
        // The crossing is left of p when p is right of the edge as it runs.
        return b.y > a.y ? o < 0 : o > 0;
    };
    for (const std::vector<std::uint32_t>& g : members) {
        if (g.empty()) continue;
        if (const auto clear = monotone_group_clear(clean, g, heights)) {
            if (!*clear) return std::nullopt;
            if (g.size() == 1) continue;  // a lone loop is a root
            // A few loops: each ray against every edge of the others.
            for (const std::uint32_t l : g) {
                const Point2 p = *std::min_element(clean[l].begin(), clean[l].end());
                touched.clear();
                for (const std::uint32_t k : g) {
                    if (k == l) continue;
                    const Path2& q = clean[k];
                    std::uint8_t odd = 0;
                    for (std::size_t i = 0; i < q.size(); ++i) {
                        odd ^= crosses_ray(q[i], q[i + 1 == q.size() ? 0 : i + 1], p) ? 1 : 0;
                    }
                    if (odd != 0) {
                        touched.push_back(k);
                        parity[k] = 1;
                    }
                }
                enclosing(l);
            }
            continue;
        }
        edges.clear();
        Box gb = box[g[0]];
        for (const std::uint32_t l : g) {
            const Path2& p = clean[l];
            gb = {std::min(gb.x0, box[l].x0), std::min(gb.y0, box[l].y0),
                  std::max(gb.x1, box[l].x1), std::max(gb.y1, box[l].y1)};
            for (std::size_t i = 0; i < p.size(); ++i) {
                const Point2& a = p[i];
                const Point2& b = p[i + 1 == p.size() ? 0 : i + 1];
                edges.push_back({a, b, std::min(a.x, b.x) - kGrow, std::min(a.y, b.y) - kGrow,
                                 std::max(a.x, b.x) + kGrow, std::max(a.y, b.y) + kGrow, l,
                                 static_cast<std::uint32_t>(i), 0});
            }
        }
        if (!grid.build(edges, gb.x0, gb.y0, gb.x1, gb.y1)) return std::nullopt;
        if (!pairs_clear(edges, grid, loop_size, heights)) return std::nullopt;
        if (g.size() == 1) continue;  // a lone loop is a root

        // Step 4: nesting by ray casting from each loop's smallest point towards -x. The
        // point is on no other loop, so the half-open crossing rule counts exactly. Each
        // edge is counted in the first column of the ray's row that its box covers.
        std::size_t work = 0;
        for (const std::uint32_t l : g) {
            const Point2 p = *std::min_element(clean[l].begin(), clean[l].end());
            const std::int32_t cy = grid.row(p.y);
            const std::int32_t last = grid.col(p.x);
            touched.clear();
            for (std::int32_t cx = 0; cx <= last; ++cx) {
                const std::size_t c = grid.cell(cx, cy);
                work += static_cast<std::size_t>(grid.end(c) - grid.begin(c));
                for (const std::uint32_t* i = grid.begin(c); i != grid.end(c); ++i) {
                    const Edge& e = edges[*i];
                    if (e.cx0 != cx || e.loop == l) continue;
                    if (crosses_ray(e.a, e.b, p)) {
                        if (parity[e.loop] == 0) touched.push_back(e.loop);
                        parity[e.loop] ^= 1;
                    }
                }
            }
            if (work > 32 * edges.size() + 4096) return std::nullopt;
            enclosing(l);
        }
    }
    // Step 5: the fill is 0 or 1 everywhere only when orientations alternate.
    for (std::size_t l = 0; l < n_loops; ++l) {
        if ((depth[l] % 2 == 0) != (area[l] > 0)) return std::nullopt;
    }

    // The tree in build_wire_tree's canonical order: each loop starts at its smallest point,
    // siblings sorted by it (they are distinct: the loops share no point), all children of a
    // node created before any grandchild, subtrees in sibling order.
    for (Path2& p : clean) std::rotate(p.begin(), std::min_element(p.begin(), p.end()), p.end());
    std::vector<std::vector<int>> kids(n_loops);
    std::vector<int> top;
    for (std::size_t l = 0; l < n_loops; ++l) {
        (parent[l] < 0 ? top : kids[static_cast<std::size_t>(parent[l])])
            .push_back(static_cast<int>(l));
    }
    const auto emit = [&](auto&& self, std::vector<int>& ids, int parent_node, int level) -> void {
        std::sort(ids.begin(), ids.end(), [&](int a, int b) {
            return clean[static_cast<std::size_t>(a)].front() <
                   clean[static_cast<std::size_t>(b)].front();
        });
        const int first = static_cast<int>(tree.nodes.size());
        for (const int id : ids) {
            tree.add(std::move(clean[static_cast<std::size_t>(id)]), parent_node, level % 2 == 1,
                     level);
        }
        for (std::size_t k = 0; k < ids.size(); ++k) {
            self(self, kids[static_cast<std::size_t>(ids[k])], first + static_cast<int>(k),
                 level + 1);
        }
    };
    emit(emit, top, -1, 0);
    return tree;
}

}  // namespace maxslice::geom2d::detail
