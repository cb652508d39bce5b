#pragma once
// The deposition head as the build order sees it (METHOD.md section 7, decisions 0008 and
// 0023): a solid of revolution about the build direction with its apex at the melt pool.
// Everything here works in the head's (t, r) half plane: t the height above the apex along
// the axis, r the distance from the axis (mm).

#include "maxslice/core/result.hpp"
#include "maxslice/core/vec3.hpp"

namespace maxslice::plan {

/// The nozzle together with its powder stream: a cone with its apex at the melt pool, its
/// axis along the layer's build direction, half-angle theta/2 and length H, and optionally a
/// cylinder for the head body above it (METHOD.md section 7). mm and degrees. The cone below
/// the nozzle tip (t <= standoff) is the powder stream; the cone above it and the body are
/// the hardware.
struct Nozzle {
    double half_angle_deg = 30.0;  ///< theta/2, in (0, 85]
    double cone_length_mm = 40.0;  ///< H, > 0
    double standoff_mm = 10.0;     ///< melt pool to nozzle tip, in (0, H]
    double body_radius_mm = 0.0;   ///< head body above the cone (0: no body)
    double body_length_mm = 0.0;   ///< its length, >= 0
    /// The smallest gap accepted between the hardware (the cone above the standoff and the
    /// body, its rim and underside included) and deposited material, >= 0. The powder stream
    /// needs only to stay clear of material (gap 0).
    double clearance_mm = 1.0;
};

/// Checks ranges; errors (kInvalidInput) name the setting ("nozzle.half_angle_deg").
[[nodiscard]] core::Result<void> validate(const Nozzle& nozzle);

/// Signed distance (mm) from the point (t, r) of the head's half plane (r >= 0) to the whole
/// head (stream, nozzle cone and body): negative inside (minus the depth in the piece it lies
/// deepest in), the Euclidean distance to the solid outside, its caps and rims included.
[[nodiscard]] double head_distance_mm(const Nozzle& nozzle, double t, double r);

/// The margin of material at (t, r), what the build order asks to be at least clearance_mm:
/// min(distance to the hardware, distance to the powder stream + clearance_mm). So material
/// near the cone above the nozzle tip or near the body (under its rim too) needs the
/// clearance, material beside the stream needs only to stay out of it. Never below
/// head_distance_mm; non-decreasing in r (the closest apex gives the smallest margin).
[[nodiscard]] double nozzle_margin_mm(const Nozzle& nozzle, double t, double r);

/// A lower bound of head_distance_mm (hence of nozzle_margin_mm) over t in [t_lo, t_hi] and
/// every r >= r_lo, from the pieces' supporting lines only (no square roots). For pruning.
[[nodiscard]] double head_distance_bound_mm(const Nozzle& nozzle, double t_lo, double t_hi,
                                            double r_lo);

/// Signed distance (mm) between the head standing with its apex at `apex` and axis `axis`
/// (unit) and the point x, head_distance_mm of its (t, r). Points at or below the apex's plane
/// (material under the melt pool) are out of reach: +inf.
[[nodiscard]] double nozzle_clearance(const Nozzle& nozzle, const core::Vec3d& apex,
                                      const core::Vec3d& axis, const core::Vec3d& x);

}  // namespace maxslice::plan
