#include "sideways_support.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "maxslice/core/units.hpp"

namespace maxslice::pipeline::detail {

geom2d::Paths2 sideways_support(const slice::PlaneFrame& bottom, double thickness_mm,
                                const slice::PlaneFrame& plane, const SidewaysParent& parent,
                                double band_mm) {
    const double c = std::abs(core::dot(parent.direction, bottom.normal));
    // How far the bead's box reaches above its centre line's tip towards the layer, and below.
    const double across = parent.half_track_mm * std::sqrt(std::max(0.0, 1.0 - c * c));
    const double lo = -band_mm - across;
    const double hi = thickness_mm + across + parent.thickness_mm * c;
    const auto to_2d = [&](const core::Vec3d& x) {
        const core::Vec3d d = x - plane.origin;
        return geom2d::Point2{core::mm_to_um(core::dot(d, plane.u)),
                              core::mm_to_um(core::dot(d, plane.v))};
    };
    geom2d::Paths2 out;
    for (const std::vector<core::Vec3d>& tips : parent.tips) {
        geom2d::Path2 line;
        const auto flush = [&] {
            if (line.size() >= 2) out.push_back(std::move(line));
            line.clear();
        };
        for (std::size_t i = 0; i + 1 < tips.size(); ++i) {
            const core::Vec3d& a = tips[i];
            const core::Vec3d& b = tips[i + 1];
            const double ta = bottom.height(a);
            const double tb = bottom.height(b);
            // The part of the segment with heights in [lo, hi].
            double u0 = 0.0;
            double u1 = 1.0;
            if (ta == tb) {
                if (ta < lo || ta > hi) u1 = -1.0;
            } else {
                const double ulo = (lo - ta) / (tb - ta);
                const double uhi = (hi - ta) / (tb - ta);
                u0 = std::max(0.0, std::min(ulo, uhi));
                u1 = std::min(1.0, std::max(ulo, uhi));
            }
            if (u0 > u1) {
                flush();
                continue;
            }
            const geom2d::Point2 p0 = to_2d(a + (b - a) * u0);
            const geom2d::Point2 p1 = to_2d(a + (b - a) * u1);
            if (line.empty() || line.back() != p0) {
                flush();
                line.push_back(p0);
            }
            line.push_back(p1);
            if (u1 < 1.0) flush();
        }
        flush();
    }
    return out;
}

}  // namespace maxslice::pipeline::detail
