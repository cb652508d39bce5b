#pragma once
// Layer regions built in code for the path tests (mm in, integer micrometres out), and
// checks of toolpath properties that do not depend on how the planner works.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "maxslice/geom2d/polygon.hpp"
#include "maxslice/geom2d/wire_tree.hpp"
#include "maxslice/path/toolpath.hpp"

namespace maxslice::path::test {

using geom2d::Path2;
using geom2d::Paths2;
using geom2d::Point2;

inline std::int64_t um(double mm) {
    return static_cast<std::int64_t>(std::llround(mm * 1000.0));
}

inline Point2 pt(double x_mm, double y_mm) {
    return {um(x_mm), um(y_mm)};
}

/// Axis-aligned rectangle [x0, x1] x [y0, y1] (mm), counter-clockwise.
inline Path2 rect(double x0, double y0, double x1, double y1) {
    return {pt(x0, y0), pt(x1, y0), pt(x1, y1), pt(x0, y1)};
}

/// Rectangle of length x width (mm) centred on (cx, cy), its length along angle_deg.
inline Path2 rotated_rect(double cx, double cy, double length, double width, double angle_deg) {
    const double a = angle_deg * std::numbers::pi / 180.0;
    const double c = std::cos(a);
    const double s = std::sin(a);
    Path2 out;
    for (const auto& [u, v] : {std::pair{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}}) {
        const double x = u * length;
        const double y = v * width;
        out.push_back(pt(cx + c * x - s * y, cy + s * x + c * y));
    }
    return out;
}

/// Regular n-gon of circumradius r (mm), counter-clockwise.
inline Path2 ngon(double cx, double cy, double r, int n) {
    Path2 out;
    for (int i = 0; i < n; ++i) {
        const double a = 2.0 * std::numbers::pi * i / n;
        out.push_back(pt(cx + r * std::cos(a), cy + r * std::sin(a)));
    }
    return out;
}

/// Loops combined even-odd: nesting decides what is a hole, not the orientation.
inline geom2d::WireTree region(const Paths2& loops) {
    return geom2d::build_wire_tree(loops, geom2d::FillRule::kEvenOdd);
}

inline geom2d::WireTree square_region(double side) {
    return region({rect(0, 0, side, side)});
}

/// 150 x 100 mm plate with five round holes of different sizes (the start corner is at the
/// origin, the holes spread so that a plain order travels back and forth).
inline geom2d::WireTree plate_with_holes(double sx = 150.0, double sy = 100.0) {
    const double kx = sx / 150.0;
    const double ky = sy / 100.0;
    return region({rect(0, 0, sx, sy), ngon(30 * kx, 30 * ky, 10 * std::min(kx, ky), 96),
                   ngon(120 * kx, 25 * ky, 8 * std::min(kx, ky), 96),
                   ngon(75 * kx, 50 * ky, 15 * std::min(kx, ky), 128),
                   ngon(30 * kx, 75 * ky, 7 * std::min(kx, ky), 64),
                   ngon(120 * kx, 75 * ky, 12 * std::min(kx, ky), 96)});
}

inline geom2d::WireTree annulus(double r_out = 30.0, double r_in = 12.0) {
    return region({ngon(0, 0, r_out, 160), ngon(0, 0, r_in, 96)});
}

inline geom2d::WireTree l_shape() {
    return region({{pt(0, 0), pt(60, 0), pt(60, 15), pt(15, 15), pt(15, 50), pt(0, 50)}});
}

inline geom2d::WireTree two_islands() {
    return region({rect(0, 0, 30, 20), ngon(70, 10, 12, 96)});
}

/// A square with a square hole holding a round island.
inline geom2d::WireTree island_in_hole() {
    return region({rect(0, 0, 60, 60), rect(10, 10, 50, 50), ngon(30, 30, 12, 96)});
}

/// The region's material as loops (outers CCW, holes CW; non-zero rule).
inline Paths2 material(const geom2d::WireTree& tree) {
    return tree.paths();
}

/// The holes of a region as regions of their own (a hole's islands are not part of it).
inline std::vector<Paths2> holes_of(const geom2d::WireTree& tree) {
    std::vector<Paths2> out;
    for (const geom2d::WireNode& n : tree.nodes) {
        if (!n.is_hole) continue;
        Paths2 hole{n.wire};
        for (const int c : n.children) hole.push_back(tree.nodes[static_cast<std::size_t>(c)].wire);
        for (Path2& p : hole) std::reverse(p.begin(), p.end());
        out.push_back(std::move(hole));
    }
    return out;
}

inline double length_mm(const Path2& path) {
    double sum = 0.0;
    for (std::size_t i = 1; i < path.size(); ++i) {
        sum += std::hypot(static_cast<double>(path[i].x - path[i - 1].x),
                          static_cast<double>(path[i].y - path[i - 1].y));
    }
    return sum / 1000.0;
}

/// Distance from p to the nearest edge of the loops, in mm.
inline double distance_to_boundary_mm(const Paths2& loops, Point2 p) {
    double best = INFINITY;
    for (const Path2& loop : loops) {
        for (std::size_t i = 0; i < loop.size(); ++i) {
            const Point2 a = loop[i];
            const Point2 b = loop[(i + 1) % loop.size()];
            const double dx = static_cast<double>(b.x - a.x);
            const double dy = static_cast<double>(b.y - a.y);
            const double len2 = dx * dx + dy * dy;
            const double px = static_cast<double>(p.x - a.x);
            const double py = static_cast<double>(p.y - a.y);
            const double t = len2 > 0 ? std::clamp((px * dx + py * dy) / len2, 0.0, 1.0) : 0.0;
            best = std::min(best, std::hypot(px - t * dx, py - t * dy));
        }
    }
    return best / 1000.0;
}

inline Paths2 stroke_paths(const LayerToolpath& tp) {
    Paths2 out;
    for (const Stroke& s : tp.strokes) out.push_back(s.points);
    return out;
}

inline double area_mm2(const Paths2& paths) {
    return geom2d::signed_area_mm2(paths);
}

/// Fraction of the region covered by tracks, measured by sampling the region on a grid and
/// asking whether a sample lies within half a track of a stroke segment (independent of the
/// planner's own Clipper-based figure). Segments are bucketed in cells of a track width.
class GridCoverage {
public:
    GridCoverage(const geom2d::WireTree& tree, const LayerToolpath& tp, double width_mm,
                 double step_mm)
        : half_(0.5 * width_mm * 1000.0), cell_(width_mm * 1000.0) {
        const Paths2 loops = material(tree);
        std::int64_t x0 = INT64_MAX, y0 = INT64_MAX, x1 = INT64_MIN, y1 = INT64_MIN;
        for (const Path2& p : loops) {
            for (const Point2& q : p) {
                x0 = std::min(x0, q.x);
                y0 = std::min(y0, q.y);
                x1 = std::max(x1, q.x);
                y1 = std::max(y1, q.y);
            }
        }
        ox_ = static_cast<double>(x0) - cell_;
        oy_ = static_cast<double>(y0) - cell_;
        nx_ = static_cast<int>((static_cast<double>(x1 - x0) + 2 * cell_) / cell_) + 1;
        ny_ = static_cast<int>((static_cast<double>(y1 - y0) + 2 * cell_) / cell_) + 1;
        cells_.assign(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_), {});
        for (const Stroke& s : tp.strokes) {
            for (std::size_t i = 0; i < s.points.size(); ++i) {
                const Point2 a = s.points[i];
                const Point2 b = s.points[std::min(i + 1, s.points.size() - 1)];
                add_segment(a, b);
            }
        }
        // One sample at a pseudo-random place in each grid cell (stratified sampling), so
        // thin strips aligned with the grid are neither always hit nor always missed. Rows
        // share a jittered y: the region's crossings with it decide which samples are inside.
        const std::int64_t step = um(step_mm);
        std::uint64_t state = 0x9E3779B97F4A7C15ull;
        const auto jitter = [&] {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            return static_cast<std::int64_t>((state >> 33) % static_cast<std::uint64_t>(step));
        };
        for (std::int64_t gy = y0; gy < y1; gy += step) {
            const std::int64_t y = gy + jitter();
            const std::vector<double> xs = crossings(loops, y);
            for (std::int64_t gx = x0; gx < x1; gx += step) {
                const Point2 p{gx + jitter(), y};
                // Inside when an odd number of crossings lie left of it (loops do not overlap).
                const auto left = std::lower_bound(xs.begin(), xs.end(), static_cast<double>(p.x));
                if ((left - xs.begin()) % 2 == 0) continue;
                ++inside_;
                if (near_track(p)) ++covered_;
            }
        }
    }

private:
    // Where the horizontal line at y crosses the loops (half-open rule), sorted.
    static std::vector<double> crossings(const Paths2& loops, std::int64_t y) {
        std::vector<double> xs;
        for (const Path2& loop : loops) {
            for (std::size_t i = 0; i < loop.size(); ++i) {
                const Point2 a = loop[i];
                const Point2 b = loop[(i + 1) % loop.size()];
                if ((a.y > y) == (b.y > y)) continue;
                const double t = static_cast<double>(y - a.y) / static_cast<double>(b.y - a.y);
                xs.push_back(static_cast<double>(a.x) + t * static_cast<double>(b.x - a.x));
            }
        }
        std::sort(xs.begin(), xs.end());
        return xs;
    }

public:
    [[nodiscard]] long inside_samples() const { return inside_; }
    [[nodiscard]] double fraction() const {
        return inside_ > 0 ? static_cast<double>(covered_) / static_cast<double>(inside_) : 0.0;
    }

private:
    struct Seg {
        Point2 a, b;
    };

    void add_segment(Point2 a, Point2 b) {
        const int cx0 = cell_x(static_cast<double>(std::min(a.x, b.x)) - half_);
        const int cx1 = cell_x(static_cast<double>(std::max(a.x, b.x)) + half_);
        const int cy0 = cell_y(static_cast<double>(std::min(a.y, b.y)) - half_);
        const int cy1 = cell_y(static_cast<double>(std::max(a.y, b.y)) + half_);
        for (int cy = cy0; cy <= cy1; ++cy) {
            for (int cx = cx0; cx <= cx1; ++cx) cells_[index(cx, cy)].push_back({a, b});
        }
    }

    [[nodiscard]] int cell_x(double x) const {
        return std::clamp(static_cast<int>((x - ox_) / cell_), 0, nx_ - 1);
    }
    [[nodiscard]] int cell_y(double y) const {
        return std::clamp(static_cast<int>((y - oy_) / cell_), 0, ny_ - 1);
    }
    [[nodiscard]] std::size_t index(int cx, int cy) const {
        return static_cast<std::size_t>(cy) * static_cast<std::size_t>(nx_) +
               static_cast<std::size_t>(cx);
    }

    [[nodiscard]] bool near_track(Point2 p) const {
        const double px = static_cast<double>(p.x);
        const double py = static_cast<double>(p.y);
        for (const Seg& s : cells_[index(cell_x(px), cell_y(py))]) {
            const double ax = static_cast<double>(s.a.x);
            const double ay = static_cast<double>(s.a.y);
            const double dx = static_cast<double>(s.b.x) - ax;
            const double dy = static_cast<double>(s.b.y) - ay;
            const double len2 = dx * dx + dy * dy;
            double t = len2 > 0 ? ((px - ax) * dx + (py - ay) * dy) / len2 : 0.0;
            t = std::clamp(t, 0.0, 1.0);
            const double ex = ax + t * dx - px;
            const double ey = ay + t * dy - py;
            if (ex * ex + ey * ey <= half_ * half_) return true;
        }
        return false;
    }

    double half_;
    double cell_;
    double ox_ = 0, oy_ = 0;
    int nx_ = 0, ny_ = 0;
    std::vector<std::vector<Seg>> cells_;
    long inside_ = 0;
    long covered_ = 0;
};

}  // namespace maxslice::path::test
