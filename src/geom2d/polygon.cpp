#include "maxslice/geom2d/polygon.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "maxslice/core/units.hpp"

namespace maxslice::geom2d {

double signed_area_um2(const Path2& path) {
    const std::size_t n = path.size();
    if (n < 3) return 0.0;
    // Shoelace formula relative to the first point keeps the products small.
    const Point2 o = path[0];
    double twice = 0.0;
    for (std::size_t i = 1; i + 1 < n; ++i) {
        const double ax = static_cast<double>(path[i].x - o.x);
        const double ay = static_cast<double>(path[i].y - o.y);
        const double bx = static_cast<double>(path[i + 1].x - o.x);
        const double by = static_cast<double>(path[i + 1].y - o.y);
        twice += ax * by - ay * bx;
    }
    return 0.5 * twice;
}

double signed_area_mm2(const Paths2& paths) {
    double sum = 0.0;
    for (const auto& p : paths) sum += signed_area_um2(p);
    return core::um2_to_mm2(sum);
}

double perimeter_mm(const Path2& path) {
    double len = 0.0;
    for (std::size_t i = 0; i < path.size(); ++i) {
        const Point2& a = path[i];
        const Point2& b = path[(i + 1) % path.size()];
        len += std::hypot(static_cast<double>(b.x - a.x), static_cast<double>(b.y - a.y));
    }
    return len / core::kMicronsPerMm;
}

double length_um(const Path2& path) {
    double sum = 0.0;
    for (std::size_t i = 1; i < path.size(); ++i) {
        const double dx = static_cast<double>(path[i].x - path[i - 1].x);
        const double dy = static_cast<double>(path[i].y - path[i - 1].y);
        sum += std::sqrt(dx * dx + dy * dy);
    }
    return sum;
}

namespace {

// 128-bit integers (a GCC/Clang extension); __extension__ keeps -Wpedantic quiet.
__extension__ typedef __int128 Int128;

// Twice the signed area of the triangle (o, a, b); exact for coordinates within
// kMaxCoordinateUm (differences < 2^31, products < 2^62, the sum needs 128 bits).
Int128 cross(const Point2& o, const Point2& a, const Point2& b) {
    return static_cast<Int128>(a.x - o.x) * (b.y - o.y) -
           static_cast<Int128>(a.y - o.y) * (b.x - o.x);
}

}  // namespace

Path2 convex_hull(const Paths2& paths) {
    // Andrew's monotone chain: O(n log n), exact integer orientation tests.
    Path2 pts;
    for (const Path2& p : paths) pts.insert(pts.end(), p.begin(), p.end());
    std::sort(pts.begin(), pts.end());
    pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
    if (pts.size() < 3) return pts;
    Path2 hull(2 * pts.size());
    std::size_t k = 0;
    for (const Point2& p : pts) {
        while (k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 0) --k;
        hull[k++] = p;
    }
    const std::size_t lower = k + 1;
    for (std::size_t i = pts.size() - 1; i-- > 0;) {
        while (k >= lower && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
        hull[k++] = pts[i];
    }
    hull.resize(k - 1);  // the last point repeats the first
    return hull;
}

namespace {

double normalize_half_turn(double a) {
    if (a < 0.0) a += std::numbers::pi;
    if (a >= std::numbers::pi) a -= std::numbers::pi;
    return a;
}

}  // namespace

double long_side_angle(const Paths2& outer_wires) {
    const Path2 hull = convex_hull(outer_wires);
    const std::size_t n = hull.size();
    if (n < 2) return 0.0;
    if (n == 2) {
        return normalize_half_turn(std::atan2(static_cast<double>(hull[1].y - hull[0].y),
                                              static_cast<double>(hull[1].x - hull[0].x)));
    }
    const auto at = [&](std::size_t j) -> const Point2& { return hull[j % n]; };
    // Rotating calipers: for each hull edge, the extreme points along the edge (max and min
    // projection) and across it (farthest from its line) move forward monotonically, so the
    // whole sweep is O(n). All measures are exact integers in the edge's unnormalised
    // direction; the ratio does not depend on its length.
    std::size_t jmax = 1;
    std::size_t jfar = 1;
    std::size_t jmin = 1;
    double best_ratio = -1.0;
    double best_angle = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const Point2 a = hull[i];
        const Point2 b = at(i + 1);
        const std::int64_t ex = b.x - a.x;
        const std::int64_t ey = b.y - a.y;
        const auto proj = [&](const Point2& p) {
            return static_cast<Int128>(ex) * (p.x - a.x) + static_cast<Int128>(ey) * (p.y - a.y);
        };
        const auto height = [&](const Point2& p) { return cross(a, b, p); };
        jmax = std::max(jmax, i + 1);
        for (std::size_t steps = 0; steps < n && proj(at(jmax + 1)) > proj(at(jmax)); ++steps) {
            ++jmax;
        }
        jfar = std::max(jfar, jmax);
        for (std::size_t steps = 0; steps < n && height(at(jfar + 1)) > height(at(jfar)); ++steps) {
            ++jfar;
        }
        jmin = std::max(jmin, jfar);
        for (std::size_t steps = 0; steps < n && proj(at(jmin + 1)) < proj(at(jmin)); ++steps) {
            ++jmin;
        }
        const double along = static_cast<double>(proj(at(jmax)) - proj(at(jmin)));
        const double across = static_cast<double>(height(at(jfar)));
        if (along <= 0.0 || across <= 0.0) continue;
        const double ratio = std::max(along, across) / std::min(along, across);
        const double angle = along >= across
                                 ? std::atan2(static_cast<double>(ey), static_cast<double>(ex))
                                 : std::atan2(static_cast<double>(ex), static_cast<double>(-ey));
        const double normalized = normalize_half_turn(angle);
        constexpr double kTie = 1e-12;
        if (ratio > best_ratio * (1.0 + kTie) ||
            (ratio >= best_ratio * (1.0 - kTie) && normalized < best_angle)) {
            best_ratio = ratio;
            best_angle = normalized;
        }
    }
    return best_angle;
}

PlaneTurn plane_turn(double angle_rad) {
    constexpr double kSnap = 1e-12;
    const auto snapped = [](double v) {
        if (std::abs(v) < kSnap) return 0.0;
        if (std::abs(std::abs(v) - 1.0) < kSnap) return std::copysign(1.0, v);
        return v;
    };
    return {snapped(std::cos(angle_rad)), snapped(std::sin(angle_rad))};
}

Containment locate_point(const Paths2& region, Point2 p) {
    // Winding number (Sunday's crossing rule, half-open in y), with an exact on-edge test.
    long winding = 0;
    for (const Path2& path : region) {
        const std::size_t n = path.size();
        for (std::size_t i = 0; i < n; ++i) {
            const Point2& a = path[i];
            const Point2& b = path[(i + 1) % n];
            const Int128 c = cross(a, b, p);
            if (c == 0 && std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) &&
                std::min(a.y, b.y) <= p.y && p.y <= std::max(a.y, b.y)) {
                return Containment::kBoundary;
            }
            if (a.y <= p.y) {
                if (b.y > p.y && c > 0) ++winding;
            } else if (b.y <= p.y && c < 0) {
                --winding;
            }
        }
    }
    return winding != 0 ? Containment::kInside : Containment::kOutside;
}

Centroid2 centroid_um(const Paths2& region) {
    // Sum over triangles (p0, p_i, p_i+1) of each loop, relative to the loop's first point.
    double a_sum = 0.0, cx = 0.0, cy = 0.0;
    double px = 0.0, py = 0.0;
    std::size_t count = 0;
    for (const Path2& path : region) {
        for (const Point2& q : path) {
            px += static_cast<double>(q.x);
            py += static_cast<double>(q.y);
            ++count;
        }
        if (path.size() < 3) continue;
        const double ox = static_cast<double>(path[0].x), oy = static_cast<double>(path[0].y);
        for (std::size_t i = 1; i + 1 < path.size(); ++i) {
            const double ax = static_cast<double>(path[i].x) - ox;
            const double ay = static_cast<double>(path[i].y) - oy;
            const double bx = static_cast<double>(path[i + 1].x) - ox;
            const double by = static_cast<double>(path[i + 1].y) - oy;
            const double a = 0.5 * (ax * by - ay * bx);
            a_sum += a;
            cx += a * (ox + (ax + bx) / 3.0);
            cy += a * (oy + (ay + by) / 3.0);
        }
    }
    if (count == 0) return {};
    if (std::abs(a_sum) <= 0.0) {
        return {px / static_cast<double>(count), py / static_cast<double>(count)};
    }
    return {cx / a_sum, cy / a_sum};
}

namespace {

// The boundary point closest to p (squared distance), and with `winding` the winding number
// of p (crossing rule in doubles, half-open in y): one pass over the edges.
struct BoundaryScan {
    double best2 = INFINITY;
    double bx = 0.0, by = 0.0;
    long winding = 0;
};

BoundaryScan scan_boundary(const Paths2& region, Centroid2 p, bool winding) {
    BoundaryScan out;
    for (const Path2& path : region) {
        for (std::size_t i = 0; i < path.size(); ++i) {
            const double ax = static_cast<double>(path[i].x), ay = static_cast<double>(path[i].y);
            const Point2 q = path[(i + 1) % path.size()];
            const double dx = static_cast<double>(q.x) - ax, dy = static_cast<double>(q.y) - ay;
            if (winding) {
                const double c = dx * (p.y - ay) - (p.x - ax) * dy;
                if (ay <= p.y) {
                    if (ay + dy > p.y && c > 0.0) ++out.winding;
                } else if (ay + dy <= p.y && c < 0.0) {
                    --out.winding;
                }
            }
            const double len2 = dx * dx + dy * dy;
            double t = len2 > 0.0 ? ((p.x - ax) * dx + (p.y - ay) * dy) / len2 : 0.0;
            t = std::clamp(t, 0.0, 1.0);
            const double cx = ax + t * dx, cy = ay + t * dy;
            const double d2 = (p.x - cx) * (p.x - cx) + (p.y - cy) * (p.y - cy);
            if (d2 < out.best2) {
                out.best2 = d2;
                out.bx = cx;
                out.by = cy;
            }
        }
    }
    return out;
}

}  // namespace

ClosestPoint closest_boundary_point(const Paths2& region, Centroid2 p) {
    const BoundaryScan s = scan_boundary(region, p, false);
    return {{std::llround(s.bx), std::llround(s.by)}, std::sqrt(s.best2)};
}

ClosestPoint closest_region_point(const Paths2& region, Centroid2 p) {
    const BoundaryScan s = scan_boundary(region, p, true);
    if (s.winding != 0) return {{std::llround(p.x), std::llround(p.y)}, 0.0};
    return {{std::llround(s.bx), std::llround(s.by)}, std::sqrt(s.best2)};
}

}  // namespace maxslice::geom2d
