#pragma once

#include "maxslice/core/vec3.hpp"
#include "maxslice/geom2d/polygon.hpp"

namespace maxslice::slice {

/// A plane with its own right-handed 2D frame: origin on the plane, unit normal (the
/// slicing / building direction) and unit in-plane axes u, v with u x v = normal, so a
/// loop that runs counter-clockwise seen from +normal is counter-clockwise in (u, v).
/// 2D coordinates are integer micrometres.
struct PlaneFrame {
    core::Vec3d origin{};
    core::Vec3d normal{0.0, 0.0, 1.0};
    core::Vec3d u{1.0, 0.0, 0.0};
    core::Vec3d v{0.0, 1.0, 0.0};

    /// A frame for a plane through origin with the given normal (normalised here; must not
    /// be zero). u is the projection of +X (or of +Y when the normal is close to X), so the
    /// horizontal frame (normal +Z) has u = +X, v = +Y and the frame for -Z is its mirror.
    [[nodiscard]] static PlaneFrame from_normal(const core::Vec3d& origin,
                                                const core::Vec3d& normal);

    /// Signed distance of p above the plane along the normal (mm).
    [[nodiscard]] double height(const core::Vec3d& p) const {
        return core::dot(p - origin, normal);
    }
    /// The same frame moved along its normal by distance (mm).
    [[nodiscard]] PlaneFrame shifted(double distance) const;
    /// Projects p onto the plane and returns its (u, v) coordinates in micrometres.
    [[nodiscard]] geom2d::Point2 to_2d(const core::Vec3d& p) const;
    /// The 3D point (mm) of 2D point q, lifted by height along the normal.
    [[nodiscard]] core::Vec3d to_3d(const geom2d::Point2& q, double height = 0.0) const;
};

}  // namespace maxslice::slice
