#pragma once
// Which beads of a parent built along another direction carry a layer (private to pipeline;
// used by multiaxis_job.cpp, tested in tests/unit/pipeline/sideways_support_test.cpp).

#include <vector>

#include "maxslice/core/vec3.hpp"
#include "maxslice/geom2d/polygon.hpp"
#include "maxslice/slice/plane_frame.hpp"

namespace maxslice::pipeline::detail {

/// A parent layer's beads seen from a layer built along another direction.
struct SidewaysParent {
    /// Its tracks' centre lines lifted onto its top (tool tips, part frame, mm).
    std::vector<std::vector<core::Vec3d>> tips;
    core::Vec3d direction;       ///< its build direction (unit)
    double thickness_mm = 0.0;   ///< its layer's thickness
    double half_track_mm = 0.0;  ///< half its bead's width
};

/// Where the parent's beads lie just below the layer's bottom plane `bottom` (its normal the
/// layer's build direction), in the frame of `plane` (the layer's own, um): each bead is taken
/// as the verifier lays it, a box half a track to each side of its centre line and its layer's
/// thickness deep below it, and each segment's box is cut to the slab from depth_mm to gap_mm
/// below the bottom plane and projected along the layer's direction (one convex polygon per
/// segment that reaches the slab; two points where the cut is flat seen along it).
[[nodiscard]] geom2d::Paths2 sideways_support(const slice::PlaneFrame& bottom,
                                              const slice::PlaneFrame& plane,
                                              const SidewaysParent& parent, double depth_mm,
                                              double gap_mm);

}  // namespace maxslice::pipeline::detail
