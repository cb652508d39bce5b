#include "cell.hpp"

#include <cmath>
#include <vector>

#include "maxslice/core/units.hpp"
#include "maxslice/geom2d/wire_tree.hpp"

namespace maxslice::plan::detail {
namespace {

// Half the side of the square standing in for the whole plane (um): far beyond any part,
// well inside geom2d's coordinate range.
constexpr double kPlaneHalfUm = static_cast<double>(geom2d::kMaxCoordinateUm) / 4.0;
// A half-space whose boundary is parallel to the plane within this (|u.n|, |v.n|) contains
// the plane entirely or not at all.
constexpr double kParallelCos = 1e-9;
// ... decided with this slack (mm): a plane lying on the half-space's boundary is inside.
constexpr double kOnBoundaryMm = 1e-6;

struct P2 {
    double x, y;
};

}  // namespace

std::optional<geom2d::Path2> cell_trace(std::span<const HalfSpace> cell,
                                        const slice::PlaneFrame& plane) {
    std::vector<P2> poly{{-kPlaneHalfUm, -kPlaneHalfUm},
                         {kPlaneHalfUm, -kPlaneHalfUm},
                         {kPlaneHalfUm, kPlaneHalfUm},
                         {-kPlaneHalfUm, kPlaneHalfUm}};
    bool clipped = false;
    for (const HalfSpace& hs : cell) {
        // Inside where a * A + b * B + C >= 0 for (a, b) in um.
        const double A = core::dot(plane.u, hs.normal) / core::kMicronsPerMm;
        const double B = core::dot(plane.v, hs.normal) / core::kMicronsPerMm;
        const double C = core::dot(plane.origin - hs.point, hs.normal);
        if (std::hypot(A, B) * core::kMicronsPerMm < kParallelCos) {
            if (C >= -kOnBoundaryMm) continue;
            return geom2d::Path2{};
        }
        clipped = true;
        // Sutherland-Hodgman against one line.
        std::vector<P2> out;
        for (std::size_t i = 0; i < poly.size(); ++i) {
            const P2 p = poly[i], q = poly[(i + 1) % poly.size()];
            const double fp = p.x * A + p.y * B + C, fq = q.x * A + q.y * B + C;
            if (fp >= 0.0) out.push_back(p);
            if ((fp >= 0.0) != (fq >= 0.0)) {
                const double t = fp / (fp - fq);
                out.push_back({p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)});
            }
        }
        poly = std::move(out);
        if (poly.size() < 3) return geom2d::Path2{};
    }
    if (!clipped) return std::nullopt;
    geom2d::Path2 path;
    path.reserve(poly.size());
    for (const P2& p : poly) {
        const geom2d::Point2 q{std::llround(p.x), std::llround(p.y)};
        if (path.empty() || path.back() != q) path.push_back(q);
    }
    if (path.size() > 1 && path.front() == path.back()) path.pop_back();
    if (path.size() < 3) return geom2d::Path2{};
    return path;
}

geom2d::Paths2 clip_to_cell(const geom2d::Paths2& region, std::span<const HalfSpace> cell,
                            const slice::PlaneFrame& plane) {
    const std::optional<geom2d::Path2> trace = cell_trace(cell, plane);
    if (!trace) return region;
    if (trace->empty()) return {};
    return geom2d::intersection_of(region, {*trace});
}

}  // namespace maxslice::plan::detail
