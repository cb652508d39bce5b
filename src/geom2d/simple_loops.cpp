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
//      integer tests; candidate pairs from a sweep over the loops' y-monotone chains, below);
//   3. at every vertex height where two edges are both cut by the sweep line and at least
//      one of them has its position rounded there (the height is inside its range, not at
//      an end), their true positions are more than kGap apart. Clipper's rounded positions
//      (half a unit off at most, plus floating-point error far below 1/1024) then keep the
//      true order with no ties: it sees no false crossing or contact, and no new vertex or
//      join is made. Positions are linear in height, so a pair is checked at the lowest and
//      highest such heights of its common range only; most pairs share no height at all;
//   4. the loops are then disjoint Jordan curves: each loop's enclosing loops follow from the
//      chain just left of its lowest point in the same sweep, its parent the innermost;
//   5. the fill must be exactly 0 or 1 everywhere: outermost loops counter-clockwise, and
//      each loop oriented opposite to its parent. Then the positive-fill union is bounded by
//      exactly these loops, outers counter-clockwise and holes clockwise as Clipper returns
//      them, and nested as found in 4.
// Any other input (crossings, touching or nearly touching loops, sliver notches, overlapping
// bodies, loops of the wrong orientation, coordinates outside the documented range, or so many
// chains across one sweep line that the sweep would be slow) is refused and goes to Clipper.
// tests/unit/geom2d compares the two.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <tuple>

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
    out.clear();
    out.reserve(in.size());
    for (const Point2& p : in) {
        if (!in_range(p)) return false;
        if (out.empty() || out.back() != p) out.push_back(p);
    }
    while (out.size() > 1 && out.front() == out.back()) out.pop_back();
    const std::size_t n = out.size();
    if (n < 3) return false;
    // A vertex strictly inside a straight run is dropped; since every dropped vertex lies
    // between its neighbours, a run keeps its direction and dropping them all at once
    // leaves the same corners as Clipper's one-at-a-time removal. In place: the kept
    // vertices are written at or before the one being read.
    const Point2 first = out[0];
    Point2 prev = out[n - 1];
    std::size_t kept = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const Point2 cur = out[i];
        const Point2& next = i + 1 == n ? first : out[i + 1];
        if (cross(prev, cur, next) != 0) {
            out[kept++] = cur;
        } else if (dot(cur, prev, next) >= 0) {
            return false;  // a spike: the loop doubles back on itself
        }
        prev = cur;
    }
    out.resize(kept);
    return kept >= 3;
}

// What the later steps need of a cleaned loop: twice its signed area, its smallest point (x,
// then y: where the tree's copy starts, as Clipper starts it) and its lowest point (y, then x:
// where the sweep finds its parent).
struct LoopFacts {
    Int128 twice_area = 0;
    std::size_t first = 0;
    Point2 lowest;
};

// An edge of a loop: in a chain from its lower end a up to b, a horizontal one as the loop
// runs.
struct Edge {
    Point2 a, b;
    std::uint32_t loop;
    std::uint32_t index;  // the loop edge from point `index` to the next one
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

// A loop vertex whose two edges need step 3 at the nearest sweep line beyond it.
struct Extremum {
    std::uint32_t loop, index;
};

// Step 1 as a check, the loop's facts, and step 3 for consecutive edges as far as it goes
// without the other loops, in one pass: false unless p is clean as it stands (at least 3
// points, all in range, no vertex on the line through its neighbours, which rules out
// repeated points too). Two consecutive edges share a sweep line beyond their shared vertex
// only when both leave it upwards or both downwards, and their gap grows from there; the
// nearest sweep line is at least a unit away, and when they are apart there, they are apart
// on every line. Vertices where they are not go to `pending` for extrema_clear (only when
// true is returned). `loop`: p's index in the loops the pending entries refer to.
bool survey(const Path2& p, std::uint32_t loop, LoopFacts& f, std::vector<Extremum>& pending) {
    const std::size_t n = p.size();
    if (n < 3 || !in_range(p[n - 1])) return false;
    const std::size_t pending_before = pending.size();
    f = LoopFacts{};
    f.lowest = p[0];
    Point2 prev = p[n - 1];
    for (std::size_t i = 0; i < n; ++i) {
        const Point2& cur = p[i];
        const Point2& next = p[i + 1 == n ? 0 : i + 1];
        if (!in_range(next) || cross(prev, cur, next) == 0) {
            pending.resize(pending_before);
            return false;
        }
        f.twice_area += static_cast<Int128>(prev.x) * cur.y - static_cast<Int128>(prev.y) * cur.x;
        if (cur < p[f.first]) f.first = i;
        if (cur.y < f.lowest.y || (cur.y == f.lowest.y && cur.x < f.lowest.x)) f.lowest = cur;
        const bool up = prev.y > cur.y && next.y > cur.y;
        if ((up || (prev.y < cur.y && next.y < cur.y)) &&
            !apart_at(Edge{cur, prev, 0, 0}, Edge{cur, next, 0, 0}, up ? cur.y + 1 : cur.y - 1)) {
            pending.push_back({loop, static_cast<std::uint32_t>(i)});
        }
        prev = cur;
    }
    return true;
}

// Step 3 for the pending vertices, at the nearest sweep line on their edges' side (where both
// edges end, both are exact).
bool extrema_clear(const std::vector<Path2>& loops, const std::vector<Extremum>& pending,
                   Heights& heights) {
    for (const Extremum& e : pending) {
        const Path2& p = loops[e.loop];
        const std::size_t n = p.size(), i = e.index;
        const Point2& u = p[i == 0 ? n - 1 : i - 1];
        const Point2& v = p[i];
        const Point2& w = p[i + 1 == n ? 0 : i + 1];
        const std::int64_t y = heights.next(v.y, u.y < v.y);
        if (y == u.y && y == w.y) continue;
        if (!apart_at(Edge{v, u, 0, 0}, Edge{v, w, 0, 0}, y)) return false;
    }
    return true;
}

// A y-monotone chain: a maximal run of a loop's sloped edges that all rise or all fall as the
// loop runs, stored bottom up (edges[begin, end), each edge's b the next one's a), so that it
// meets every sweep line in its height range once. Horizontal edges are kept apart.
struct Chain {
    std::uint32_t begin, end;
    std::uint32_t loop;
    std::uint32_t cursor;  // the first edge whose top is at or above the sweep line
    bool down;             // the loop runs down along it
    std::int64_t x0, x1;   // its x range
};

// Steps 2 to 4 by a sweep upwards over the chains (Shamos and Hoey, 1976, on chains instead of
// segments): the chains that cross the sweep line are kept in x order, and two chains are
// merged (every pair of their edges whose height ranges touch is checked) when they become
// neighbours. Why the neighbours suffice, with the sweep line at a vertex height y, after the
// chains starting at y are placed and before those ending at y leave:
//   - the lowest point where two edges meet is shared by neighbouring chains just below it, or
//     is a chain end at y where every chain through it is a neighbour of another; two chains
//     may share an end only as the two chains of one loop vertex, whose edges are consecutive;
//   - at y, every chain of an edge Q that y crosses inside its range has a neighbour towards
//     any other edge P at y (or is P's chain), and that neighbour's edge is nearer to Q than P;
//   - a horizontal edge at y is checked against every chain within 2 units of it at y, and
//     against the previous horizontal edge at y (sorted by their left ends, any two that meet
//     imply two neighbours that meet).
// Nesting (step 4): a loop's smallest point p is the bottom of one or two of its chains; just
// above y, the loops around p other than its own are those around the point just right of
// the chain left of p, whose loop L has its point at y left of p and is placed already: L and
// L's enclosing loops when that chain is a left boundary of L (L lies to its right: it runs
// down L when L is counter-clockwise, up when clockwise), else L's enclosing loops alone.
// Returns false when an edge pair fails steps 2 or 3, or when the sweep does more than a few
// times the work of a clear set of loops (many chains across one sweep line: Clipper instead).
class Sweep {
public:
    Sweep(const std::vector<Path2>& loops, const std::vector<LoopFacts>& facts, Heights& heights)
        : loops_(loops), facts_(facts), heights_(heights) {}

    bool run(std::vector<int>& parent, std::vector<int>& depth) {
        std::size_t n_edges = 0;
        for (const Path2& p : loops_) n_edges += p.size();
        edges_.reserve(n_edges);
        for (std::uint32_t l = 0; l < loops_.size(); ++l) split(l);
        budget_ = 32 * n_edges + 4096;
        std::vector<Event> events;
        events.reserve(2 * chains_.size() + flat_.size() + loops_.size());
        for (std::uint32_t c = 0; c < chains_.size(); ++c) {
            const Point2 bottom = edges_[chains_[c].begin].a;
            const Point2 top = edges_[chains_[c].end - 1].b;
            events.push_back({bottom.y, kInsert, bottom.x, c});
            events.push_back({top.y, kRemove, top.x, c});
        }
        for (std::uint32_t h = 0; h < flat_.size(); ++h) {
            events.push_back({flat_[h].a.y, kFlat, std::min(flat_[h].a.x, flat_[h].b.x), h});
        }
        for (std::uint32_t l = 0; l < loops_.size(); ++l) {
            const Point2 p = facts_[l].lowest;
            events.push_back({p.y, kNest, p.x, l});
        }
        std::sort(events.begin(), events.end());
        std::vector<std::uint8_t> placed(loops_.size(), 0);
        const Edge* last_flat = nullptr;
        for (const Event& ev : events) {
            y_ = ev.y;
            switch (ev.kind) {
                case kInsert:
                    if (!insert(ev.id)) return false;
                    break;
                case kFlat: {
                    const Edge& h = flat_[ev.id];
                    if (last_flat != nullptr && last_flat->a.y == h.a.y &&
                        !pair_clear(*last_flat, h, heights_)) {
                        return false;
                    }
                    if (!flat_clear(h)) return false;
                    last_flat = &h;
                    break;
                }
                case kRemove:
                    if (!remove(ev.id)) return false;
                    break;
                case kNest: {
                    const Point2 p{ev.x, ev.y};
                    const std::size_t i = left_of(p);
                    parent[ev.id] = -1;
                    depth[ev.id] = 0;
                    if (i > 0) {
                        const Chain& c = chains_[status_[i - 1]];
                        if (placed[c.loop] == 0) return false;  // only when loops meet
                        const bool left_boundary = c.down == (facts_[c.loop].twice_area > 0);
                        parent[ev.id] = left_boundary ? static_cast<int>(c.loop) : parent[c.loop];
                        depth[ev.id] = depth[c.loop] + (left_boundary ? 1 : 0);
                    }
                    placed[ev.id] = 1;
                    break;
                }
            }
        }
        return true;
    }

private:
    enum Kind : std::uint8_t { kInsert, kFlat, kRemove, kNest };
    struct Event {
        std::int64_t y;
        Kind kind;
        std::int64_t x;
        std::uint32_t id;
        bool operator<(const Event& o) const {
            return std::tie(y, kind, x, id) < std::tie(o.y, o.kind, o.x, o.id);
        }
    };

    // Loop l's chains (from an edge that starts one, so none wraps around) and horizontal
    // edges. A loop of non-zero area rises and falls, so that edge exists.
    void split(std::uint32_t l) {
        const Path2& p = loops_[l];
        const std::size_t n = p.size();
        const auto rise = [&](std::size_t i) {
            const std::int64_t d = p[i + 1 == n ? 0 : i + 1].y - p[i].y;
            return (d > 0) - (d < 0);
        };
        std::size_t s = 0;
        while (s < n && (rise(s) == 0 || rise(s == 0 ? n - 1 : s - 1) == rise(s))) ++s;
        if (s == n) s = 0;  // cannot happen (area is not 0); keeps the index in range
        const std::size_t first = chains_.size();
        int run = 0;  // the rise of the open chain; 0: none is open
        for (std::size_t k = 0, i = s; k < n; ++k, i = i + 1 == n ? 0 : i + 1) {
            const Point2& u = p[i];
            const Point2& v = p[i + 1 == n ? 0 : i + 1];
            const int r = rise(i);
            const auto index = static_cast<std::uint32_t>(i);
            if (r == 0) {
                flat_.push_back({u, v, l, index});
                run = 0;
                continue;
            }
            if (r != run) {
                const auto at = static_cast<std::uint32_t>(edges_.size());
                chains_.push_back({at, at, l, at, r < 0, u.x, u.x});
                run = r;
            }
            edges_.push_back(r > 0 ? Edge{u, v, l, index} : Edge{v, u, l, index});
            Chain& c = chains_.back();
            c.end = static_cast<std::uint32_t>(edges_.size());
            c.x0 = std::min(c.x0, v.x);
            c.x1 = std::max(c.x1, v.x);
        }
        for (std::size_t c = first; c < chains_.size(); ++c) {
            if (chains_[c].down) {
                std::reverse(edges_.begin() + chains_[c].begin, edges_.begin() + chains_[c].end);
            }
        }
    }

    bool consecutive(const Edge& s, const Edge& t) const {
        if (s.loop != t.loop) return false;
        const std::size_t n = loops_[s.loop].size();
        return (s.index + 1) % n == t.index || (t.index + 1) % n == s.index;
    }

    // Chain c's edge at the sweep line (one that reaches it: the lower one at a vertex).
    const Edge& at_sweep(Chain& c) {
        while (c.cursor + 1 < c.end && edges_[c.cursor].b.y < y_) ++c.cursor;
        return edges_[c.cursor];
    }

    // Which side of chain c point q on the sweep line is: > 0 left, < 0 right, 0 on it.
    int side(Chain& c, const Point2& q) {
        const Edge& e = at_sweep(c);
        return sign(cross(e.a, e.b, q));
    }

    // The number of chains in the status left of q on the sweep line.
    std::size_t left_of(const Point2& q) {
        return static_cast<std::size_t>(
            std::partition_point(status_.begin(), status_.end(),
                                 [&](std::uint32_t d) { return side(chains_[d], q) < 0; }) -
            status_.begin());
    }

    bool spend(std::size_t work) {
        if (work > budget_) return false;
        budget_ -= work;
        return true;
    }

    // Every pair of edges of chains c and d whose height ranges touch, except consecutive
    // ones (extrema_clear checks those).
    bool merge(std::uint32_t ci, std::uint32_t di) {
        const Chain& c = chains_[ci];
        const Chain& d = chains_[di];
        if (c.x1 + 2 < d.x0 || d.x1 + 2 < c.x0) return true;  // no edge pair is close
        const std::int64_t lo = std::max(edges_[c.begin].a.y, edges_[d.begin].a.y);
        const std::int64_t hi = std::min(edges_[c.end - 1].b.y, edges_[d.end - 1].b.y);
        if (lo > hi) return true;
        const auto from = [&](const Chain& k) {
            return static_cast<std::size_t>(
                std::partition_point(edges_.begin() + k.begin, edges_.begin() + k.end,
                                     [&](const Edge& e) { return e.b.y < lo; }) -
                edges_.begin());
        };
        std::size_t j0 = from(d);
        std::size_t work = 1;
        for (std::size_t i = from(c); i < c.end && edges_[i].a.y <= hi; ++i) {
            const Edge& e = edges_[i];
            while (j0 < d.end && edges_[j0].b.y < e.a.y) ++j0;
            for (std::size_t j = j0; j < d.end && edges_[j].a.y <= e.b.y; ++j) {
                ++work;
                const Edge& f = edges_[j];
                // More than two units apart across: pair_clear's first answer, without a call.
                if (std::max(e.a.x, e.b.x) + 2 < std::min(f.a.x, f.b.x) ||
                    std::max(f.a.x, f.b.x) + 2 < std::min(e.a.x, e.b.x)) {
                    continue;
                }
                if (!consecutive(e, f) && !pair_clear(e, f, heights_)) return false;
            }
        }
        return spend(work);
    }

    // Chain ci starts at the sweep line: placed by its bottom point, and after a chain that
    // starts there too when that one's first edge is left of its own (the two chains of a
    // loop's lowest vertex); a chain through the point otherwise meets it, and lands next to
    // it or to another chain through the point (the merge then fails).
    bool insert(std::uint32_t ci) {
        const Edge& first = edges_[chains_[ci].begin];
        const Point2 p = first.a;
        const auto at = std::partition_point(status_.begin(), status_.end(), [&](std::uint32_t d) {
            const int s = side(chains_[d], p);
            if (s != 0) return s < 0;
            const Edge& g = edges_[chains_[d].begin];
            return g.a != p || cross(p, first.b, g.b) > 0;
        });
        const std::size_t i = static_cast<std::size_t>(at - status_.begin());
        status_.insert(at, ci);
        if (!spend(status_.size())) return false;
        if (i > 0 && !merge(status_[i - 1], ci)) return false;
        return i + 1 == status_.size() || merge(ci, status_[i + 1]);
    }

    bool remove(std::uint32_t ci) {
        const auto at = std::find(status_.begin(), status_.end(), ci);
        if (at == status_.end()) return false;  // cannot happen: every chain was inserted
        const std::size_t i = static_cast<std::size_t>(at - status_.begin());
        status_.erase(at);
        if (!spend(status_.size())) return false;
        return i == 0 || i == status_.size() || merge(status_[i - 1], status_[i]);
    }

    // A horizontal edge against the chains within two units of it on the sweep line.
    bool flat_clear(const Edge& h) {
        const std::int64_t x0 = std::min(h.a.x, h.b.x), x1 = std::max(h.a.x, h.b.x);
        const Point2 right{x1 + 2, y_};
        std::size_t work = 1;
        for (std::size_t k = left_of({x0 - 2, y_}); k < status_.size(); ++k, ++work) {
            Chain& c = chains_[status_[k]];
            if (side(c, right) > 0) break;  // the chain is right of the edge's reach
            const Edge& e = at_sweep(c);
            if (!consecutive(h, e) && !pair_clear(h, e, heights_)) return false;
        }
        return spend(work);
    }

    const std::vector<Path2>& loops_;
    const std::vector<LoopFacts>& facts_;
    Heights& heights_;
    std::vector<Edge> edges_, flat_;
    std::vector<Chain> chains_;
    std::vector<std::uint32_t> status_;  // chains across the sweep line, left to right
    std::int64_t y_ = 0;
    std::size_t budget_ = 0;
};

// The fast path. With `movable` (the loops themselves, not const), a loop that cleaning would
// leave as it is moves into the tree rather than being copied; such loops are moved back
// before an answer of nullopt, so the loops are then as they were.
std::optional<WireTree> simple_loops_tree(const Paths2& loops, Paths2* movable) {
    std::vector<Path2> clean;
    clean.reserve(loops.size());
    std::vector<std::pair<std::size_t, std::size_t>> moved;  // (index in loops, in clean)
    const auto refuse = [&]() -> std::optional<WireTree> {
        for (const auto& [from, to] : moved) (*movable)[from] = std::move(clean[to]);
        return std::nullopt;
    };
    std::vector<LoopFacts> facts;
    facts.reserve(loops.size());
    std::vector<Extremum> pending;
    for (std::size_t i = 0; i < loops.size(); ++i) {
        if (loops[i].size() < 3) continue;  // as build_wire_tree: such loops contribute nothing
        const auto l = static_cast<std::uint32_t>(clean.size());
        LoopFacts f;
        if (movable != nullptr && survey(loops[i], l, f, pending)) {
            moved.emplace_back(i, l);
            clean.push_back(std::move((*movable)[i]));
        } else if (!clean_loop(loops[i], clean.emplace_back()) ||
                   !survey(clean.back(), l, f, pending)) {
            return refuse();
        }
        if (f.twice_area == 0) return refuse();
        facts.push_back(f);
    }
    const std::size_t n_loops = clean.size();
    WireTree tree;
    if (n_loops == 0) return tree;
    Heights heights(clean);
    if (!extrema_clear(clean, pending, heights)) return refuse();
    std::vector<int> parent(n_loops, -1);
    std::vector<int> depth(n_loops, 0);
    if (!Sweep(clean, facts, heights).run(parent, depth)) return refuse();
    // Step 5: the fill is 0 or 1 everywhere only when orientations alternate.
    for (std::size_t l = 0; l < n_loops; ++l) {
        if ((depth[l] % 2 == 0) != (facts[l].twice_area > 0)) return refuse();
    }

    // The tree in build_wire_tree's canonical order: each loop starts at its smallest point,
    // siblings sorted by it (they are distinct: the loops share no point), all children of a
    // node created before any grandchild, subtrees in sibling order.
    for (std::size_t l = 0; l < n_loops; ++l) {
        Path2& p = clean[l];
        std::rotate(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(facts[l].first), p.end());
    }
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

}  // namespace

std::optional<WireTree> wire_tree_of_simple_loops(const Paths2& loops) {
    return simple_loops_tree(loops, nullptr);
}

std::optional<WireTree> take_wire_tree_of_simple_loops(Paths2& loops) {
    return simple_loops_tree(loops, &loops);
}

}  // namespace maxslice::geom2d::detail
