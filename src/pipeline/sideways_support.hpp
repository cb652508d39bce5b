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

/// The parts of the parent's centre lines whose beads reach the layer's bottom plane
/// `bottom` (its normal the layer's build direction; the layer thickness_mm thick above it),
/// in the frame of `plane` (the layer's own, um): a bead is taken as a box half a track to each
/// side of its centre line and its layer's thickness deep, and a centre line is kept where that
/// box reaches from band_mm below the bottom plane up to the layer's top. Parts are projected
/// along the layer's direction.
[[nodiscard]] geom2d::Paths2 sideways_support(const slice::PlaneFrame& bottom, double thickness_mm,
                                              const slice::PlaneFrame& plane,
                                              const SidewaysParent& parent, double band_mm);

}  // namespace maxslice::pipeline::detail
