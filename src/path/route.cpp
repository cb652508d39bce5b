#include "route.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace maxslice::path::detail {
namespace {

using geom2d::Path2;
using geom2d::Point2;

// 2-opt looks this many positions ahead of each position: O(n * window) per pass instead
// of O(n^2), which keeps layers with thousands of strokes cheap; strokes that belong next
// to each other are found by the nearest-neighbour tour already, so the window mostly
// repairs local crossings.
constexpr std::size_t kTwoOptWindow = 48;
// Upper bound on 2-opt passes over a group (each pass is O(n * window)).
constexpr int kTwoOptMaxPasses = 30;
// Rounds of (choose closed-stroke start points, 2-opt) per group.
constexpr int kStartPointRounds = 3;
// A move is applied only when it shortens travel by more than this (um): rounding noise
// must not make the improvement loop cycle.
constexpr double kMinGainUm = 0.5;
// A closed stroke's start point snaps to a vertex this close (um), so no tiny first edge.
constexpr double kStartSnapUm = 20.0;

constexpr double kInf = std::numeric_limits<double>::infinity();

double distance(Point2 a, Point2 b) {
    const double dx = static_cast<double>(b.x - a.x);
    const double dy = static_cast<double>(b.y - a.y);
    return std::sqrt(dx * dx + dy * dy);
}

std::int64_t round_half_away(double v) {
    return static_cast<std::int64_t>(v >= 0.0 ? v + 0.5 : v - 0.5);
}

struct Box {
    std::int64_t x0 = std::numeric_limits<std::int64_t>::max();
    std::int64_t y0 = std::numeric_limits<std::int64_t>::max();
    std::int64_t x1 = std::numeric_limits<std::int64_t>::min();
    std::int64_t y1 = std::numeric_limits<std::int64_t>::min();

    void add(const Path2& path) {
        for (const Point2& p : path) {
            x0 = std::min(x0, p.x);
            y0 = std::min(y0, p.y);
            x1 = std::max(x1, p.x);
            y1 = std::max(y1, p.y);
        }
    }
    // A lower bound of the distance from p to anything inside the box.
    [[nodiscard]] double distance_to(Point2 p) const {
        const double dx = static_cast<double>(std::max({x0 - p.x, std::int64_t{0}, p.x - x1}));
        const double dy = static_cast<double>(std::max({y0 - p.y, std::int64_t{0}, p.y - y1}));
        return std::sqrt(dx * dx + dy * dy);
    }
};

// A point on a closed stroke, on the edge from vertex `edge` to the next one.
struct OnLoop {
    Point2 point;
    std::size_t edge = 0;
    double cost = kInf;
};

// The point q of edge (p, q) given by parameter t, snapped to an end when close to it.
Point2 point_on_edge(Point2 p, Point2 q, double t) {
    const Point2 r{round_half_away(static_cast<double>(p.x) + t * static_cast<double>(q.x - p.x)),
                   round_half_away(static_cast<double>(p.y) + t * static_cast<double>(q.y - p.y))};
    if (distance(r, p) <= kStartSnapUm) return p;
    if (distance(r, q) <= kStartSnapUm) return q;
    return r;
}

// The point q of a closed polyline minimising |a q| + |q b| (|a q| alone without b). On each
// edge the sum is convex, and its minimiser on the edge's line is where the segment from a
// to b (or to b's mirror image, when both lie on the same side) meets the line: the
// parameter t_a + (t_b - t_a) |s_a| / (|s_a| + |s_b|) with t the projections and s the
// distances to the line; clamped to the edge, it is the minimiser on the edge.
OnLoop best_on_loop(const Path2& loop, Point2 a, const Point2* b) {
    OnLoop best;
    const std::size_t m = loop.size();
    for (std::size_t i = 0; i < m; ++i) {
        const Point2 p = loop[i];
        const Point2 q = loop[(i + 1) % m];
        const double dx = static_cast<double>(q.x - p.x);
        const double dy = static_cast<double>(q.y - p.y);
        const double len2 = dx * dx + dy * dy;
        double t = 0.0;
        if (len2 > 0.0) {
            const double ax = static_cast<double>(a.x - p.x);
            const double ay = static_cast<double>(a.y - p.y);
            const double ta = (ax * dx + ay * dy) / len2;
            if (b == nullptr) {
                t = ta;
            } else {
                const double bx = static_cast<double>(b->x - p.x);
                const double by = static_cast<double>(b->y - p.y);
                const double tb = (bx * dx + by * dy) / len2;
                const double sa = std::abs(dx * ay - dy * ax);
                const double sb = std::abs(dx * by - dy * bx);
                t = sa + sb > 0.0 ? ta + (tb - ta) * sa / (sa + sb) : ta;
            }
            t = std::clamp(t, 0.0, 1.0);
        }
        const Point2 r = point_on_edge(p, q, t);
        const double cost = distance(a, r) + (b != nullptr ? distance(r, *b) : 0.0);
        if (cost < best.cost) best = {r, i, cost};
    }
    return best;
}

// A stroke in a tour: open strokes may be reversed, closed ones start at `entry`.
struct Visit {
    std::size_t stroke = 0;
    bool reversed = false;
    Point2 entry;
    Point2 exit;
    std::size_t edge = 0;  // closed: the edge the start point lies on
};

class GroupRouter {
public:
    explicit GroupRouter(const std::vector<RouteStroke>& strokes) : strokes_(strokes) {
        boxes_.resize(strokes.size());
        for (std::size_t i = 0; i < strokes.size(); ++i) boxes_[i].add(strokes[i].points);
    }

    // Nearest neighbour from start, then rounds of 2-opt and closed-stroke start points.
    std::vector<Visit> run(Point2 start) {
        start_ = start;
        nearest_neighbour();
        for (int round = 0; round < kStartPointRounds; ++round) {
            two_opt();
            if (!improve_start_points()) break;
        }
        return std::move(tour_);
    }

    // The best way to enter stroke i from p.
    [[nodiscard]] Visit entry_from(std::size_t i, Point2 p, double* cost) const {
        const RouteStroke& s = strokes_[i];
        Visit v;
        v.stroke = i;
        if (s.closed) {
            const OnLoop on = best_on_loop(s.points, p, nullptr);
            v.entry = v.exit = on.point;
            v.edge = on.edge;
            *cost = on.cost;
        } else {
            const double forward = distance(p, s.points.front());
            const double backward = distance(p, s.points.back());
            v.reversed = backward < forward;
            v.entry = v.reversed ? s.points.back() : s.points.front();
            v.exit = v.reversed ? s.points.front() : s.points.back();
            *cost = std::min(forward, backward);
        }
        return v;
    }

    // The nearest stroke to p not used yet (used may be empty: none is): lowest cost, lowest
    // index among equals.
    [[nodiscard]] Visit nearest(Point2 p, const std::vector<bool>& used, double* cost) const {
        Visit best;
        double best_cost = kInf;
        for (std::size_t i = 0; i < strokes_.size(); ++i) {
            if ((!used.empty() && used[i]) || boxes_[i].distance_to(p) >= best_cost) continue;
            double c = kInf;
            const Visit v = entry_from(i, p, &c);
            if (c < best_cost) {
                best_cost = c;
                best = v;
            }
        }
        *cost = best_cost;
        return best;
    }

private:
    void nearest_neighbour() {
        std::vector<bool> used(strokes_.size(), false);
        Point2 p = start_;
        tour_.clear();
        for (std::size_t k = 0; k < strokes_.size(); ++k) {
            double cost = kInf;
            const Visit v = nearest(p, used, &cost);
            used[v.stroke] = true;
            tour_.push_back(v);
            p = v.exit;
        }
    }

    [[nodiscard]] Point2 exit_before(std::size_t i) const {
        return i == 0 ? start_ : tour_[i - 1].exit;
    }

    // Reversing tour positions i..j (which also reverses each stroke in it) changes travel
    // only at the two ends; the end of the tour is free.
    void two_opt() {
        const std::size_t n = tour_.size();
        for (int pass = 0; pass < kTwoOptMaxPasses; ++pass) {
            bool improved = false;
            for (std::size_t i = 0; i < n; ++i) {
                for (std::size_t j = i; j < n && j <= i + kTwoOptWindow; ++j) {
                    const Point2 before = exit_before(i);
                    double old_cost = distance(before, tour_[i].entry);
                    double new_cost = distance(before, tour_[j].exit);
                    if (j + 1 < n) {
                        old_cost += distance(tour_[j].exit, tour_[j + 1].entry);
                        new_cost += distance(tour_[i].entry, tour_[j + 1].entry);
                    }
                    if (new_cost < old_cost - kMinGainUm) {
                        std::reverse(tour_.begin() + static_cast<std::ptrdiff_t>(i),
                                     tour_.begin() + static_cast<std::ptrdiff_t>(j) + 1);
                        for (std::size_t k = i; k <= j; ++k) {
                            Visit& v = tour_[k];
                            if (!strokes_[v.stroke].closed) v.reversed = !v.reversed;
                            std::swap(v.entry, v.exit);
                        }
                        improved = true;
                    }
                }
            }
            if (!improved) break;
        }
    }

    // Moves each closed stroke's start point to where it shortens the travel from the
    // previous stroke plus the travel to the next. True when something moved.
    bool improve_start_points() {
        bool moved = false;
        for (std::size_t i = 0; i < tour_.size(); ++i) {
            Visit& v = tour_[i];
            const RouteStroke& s = strokes_[v.stroke];
            if (!s.closed) continue;
            const Point2 before = exit_before(i);
            const Point2* after = i + 1 < tour_.size() ? &tour_[i + 1].entry : nullptr;
            const double old_cost =
                distance(before, v.entry) + (after != nullptr ? distance(v.entry, *after) : 0.0);
            const OnLoop on = best_on_loop(s.points, before, after);
            if (on.cost < old_cost - kMinGainUm) {
                v.entry = v.exit = on.point;
                v.edge = on.edge;
                moved = true;
            }
        }
        return moved;
    }

    const std::vector<RouteStroke>& strokes_;
    Point2 start_{};
    std::vector<Box> boxes_;
    std::vector<Visit> tour_;
};

// The deposited polyline of a visit: a closed stroke starts (and ends) at its entry point.
Stroke materialize(RouteStroke&& s, const Visit& v) {
    Stroke out;
    out.kind = s.kind;
    if (!s.closed) {
        out.points = std::move(s.points);
        if (v.reversed) std::reverse(out.points.begin(), out.points.end());
        return out;
    }
    const std::size_t m = s.points.size();
    out.points.reserve(m + 2);
    const auto append = [&](Point2 p) {
        if (out.points.empty() || out.points.back() != p) out.points.push_back(p);
    };
    append(v.entry);
    for (std::size_t j = 0; j < m; ++j) append(s.points[(v.edge + 1 + j) % m]);
    append(v.entry);
    return out;
}

}  // namespace

std::vector<Stroke> route_short(std::vector<RouteIsland> islands, Point2 start) {
    std::vector<Stroke> out;
    // Drop empty groups and islands so every island has a group to enter by.
    for (RouteIsland& island : islands) {
        std::erase_if(island, [](const RouteGroup& g) { return g.empty(); });
    }
    std::erase_if(islands, [](const RouteIsland& island) { return island.empty(); });
    std::vector<Box> boxes(islands.size());
    std::vector<GroupRouter> entries;  // each island's first group
    entries.reserve(islands.size());
    for (std::size_t i = 0; i < islands.size(); ++i) {
        for (const RouteStroke& s : islands[i].front()) boxes[i].add(s.points);
        entries.emplace_back(islands[i].front());
    }
    std::vector<bool> done(islands.size(), false);
    Point2 p = start;
    for (std::size_t k = 0; k < islands.size(); ++k) {
        // Nearest island: the one whose first group is entered after the least travel.
        std::size_t next = islands.size();
        double best = kInf;
        for (std::size_t i = 0; i < islands.size(); ++i) {
            if (done[i] || boxes[i].distance_to(p) >= best) continue;
            double cost = kInf;
            (void)entries[i].nearest(p, {}, &cost);
            if (cost < best) {
                best = cost;
                next = i;
            }
        }
        done[next] = true;
        for (std::size_t g = 0; g < islands[next].size(); ++g) {
            RouteGroup& group = islands[next][g];
            const std::vector<Visit> tour =
                g == 0 ? entries[next].run(p) : GroupRouter(group).run(p);
            for (const Visit& v : tour) {
                out.push_back(materialize(std::move(group[v.stroke]), v));
                p = out.back().points.back();
            }
        }
    }
    return out;
}

std::vector<Stroke> route_generated(std::vector<RouteIsland> islands) {
    std::vector<Stroke> out;
    for (RouteIsland& island : islands) {
        for (RouteGroup& group : island) {
            for (RouteStroke& s : group) {
                Visit v;
                if (s.closed) {
                    v.entry = v.exit = s.points.front();
                    v.edge = 0;
                }
                out.push_back(materialize(std::move(s), v));
            }
        }
    }
    return out;
}

}  // namespace maxslice::path::detail
