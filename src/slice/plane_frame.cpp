#include "maxslice/slice/plane_frame.hpp"

#include <cmath>

#include "maxslice/core/assert.hpp"
#include "maxslice/core/units.hpp"

namespace maxslice::slice {

using core::Vec3d;

PlaneFrame PlaneFrame::from_normal(const Vec3d& origin, const Vec3d& normal) {
    PlaneFrame f;
    f.origin = origin;
    f.normal = core::normalized(normal);
    MAXSLICE_ASSERT(core::norm(f.normal) > 0.5);
    // Project +X onto the plane unless the normal is close to X; then use +Y. This keeps the
    // horizontal frame aligned with the part's own X and Y.
    const Vec3d ref = std::abs(f.normal.x) < 0.9 ? Vec3d{1.0, 0.0, 0.0} : Vec3d{0.0, 1.0, 0.0};
    f.u = core::normalized(ref - f.normal * core::dot(ref, f.normal));
    f.v = core::cross(f.normal, f.u);
    return f;
}

PlaneFrame PlaneFrame::shifted(double distance) const {
    PlaneFrame f = *this;
    f.origin = origin + normal * distance;
    return f;
}

geom2d::Point2 PlaneFrame::to_2d(const Vec3d& p) const {
    const Vec3d d = p - origin;
    return {core::mm_to_um(core::dot(d, u)), core::mm_to_um(core::dot(d, v))};
}

Vec3d PlaneFrame::to_3d(const geom2d::Point2& q, double height) const {
    return origin + u * core::um_to_mm(q.x) + v * core::um_to_mm(q.y) + normal * height;
}

}  // namespace maxslice::slice
