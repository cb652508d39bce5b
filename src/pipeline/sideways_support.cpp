#include "sideways_support.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "maxslice/core/units.hpp"

namespace maxslice::pipeline::detail {

geom2d::Paths2 sideways_support(const slice::PlaneFrame& bottom, const slice::PlaneFrame& plane,
                                const SidewaysParent& parent, double depth_mm, double gap_mm) {
    const double lo = -depth_mm;
    const double hi = -gap_mm;
    const core::Vec3d& d = parent.direction;
    const auto to_2d = [&](const core::Vec3d& x) {
        const core::Vec3d r = x - plane.origin;
        return geom2d::Point2{core::mm_to_um(core::dot(r, plane.u)),
                              core::mm_to_um(core::dot(r, plane.v))};
    };
    geom2d::Paths2 out;
    std::array<core::Vec3d, 8> corner;
    std::array<double, 8> height;
    // The box's edges: the two end rectangles (corners 0-3 and 4-7) and the four along it.
    static constexpr std::array<std::pair<int, int>, 12> kEdges{{{0, 1},
                                                                 {1, 2},
                                                                 {2, 3},
                                                                 {3, 0},
                                                                 {4, 5},
                                                                 {5, 6},
                                                                 {6, 7},
                                                                 {7, 4},
                                                                 {0, 4},
                                                                 {1, 5},
                                                                 {2, 6},
                                                                 {3, 7}}};
    for (const std::vector<core::Vec3d>& tips : parent.tips) {
        for (std::size_t i = 0; i + 1 < tips.size(); ++i) {
            const core::Vec3d& a = tips[i];
            const core::Vec3d& b = tips[i + 1];
            core::Vec3d along = b - a;
            along = along - d * core::dot(along, d);
            if (core::norm(along) < 1e-9) continue;
            const core::Vec3d side = core::normalized(core::cross(d, along)) * parent.half_track_mm;
            const core::Vec3d down = d * parent.thickness_mm;
            int n = 0;
            for (const core::Vec3d& end : {a, b}) {
                corner[static_cast<std::size_t>(n++)] = end + side;
                corner[static_cast<std::size_t>(n++)] = end - side;
                corner[static_cast<std::size_t>(n++)] = end - side - down;
                corner[static_cast<std::size_t>(n++)] = end + side - down;
            }
            for (std::size_t k = 0; k < corner.size(); ++k) height[k] = bottom.height(corner[k]);
            const auto [least, most] = std::minmax_element(height.begin(), height.end());
            if (*most < lo || *least > hi) continue;
            // The cut box's corners: the box's own within the slab, and where its edges cross
            // the slab's two planes.
            geom2d::Paths2 points(1);
            geom2d::Path2& p = points[0];
            for (std::size_t k = 0; k < corner.size(); ++k) {
                if (height[k] >= lo && height[k] <= hi) p.push_back(to_2d(corner[k]));
            }
            for (const auto& [e0, e1] : kEdges) {
                const double h0 = height[static_cast<std::size_t>(e0)];
                const double h1 = height[static_cast<std::size_t>(e1)];
                for (const double level : {lo, hi}) {
                    if ((h0 - level) * (h1 - level) >= 0.0) continue;
                    const double u = (level - h0) / (h1 - h0);
                    const core::Vec3d& c0 = corner[static_cast<std::size_t>(e0)];
                    const core::Vec3d& c1 = corner[static_cast<std::size_t>(e1)];
                    p.push_back(to_2d(c0 + (c1 - c0) * u));
                }
            }
            if (p.empty()) continue;
            geom2d::Path2 hull = geom2d::convex_hull(points);
            if (hull.size() == 1) hull.push_back(hull.front());
            out.push_back(std::move(hull));
        }
    }
    return out;
}

}  // namespace maxslice::pipeline::detail
