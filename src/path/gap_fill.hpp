#pragma once
// Tracks along gaps the contour passes leave where no fill line fits.

#include <cstdint>
#include <vector>

#include "maxslice/geom2d/polygon.hpp"
#include "route.hpp"

namespace maxslice::path::detail {

/// Tracks for the gaps of one island (any frame): the parts inside the contour tracks that
/// neither a deeper contour pass nor the fill reaches (region paths, outers CCW). Each gap piece of
/// mean width g (2 x area / perimeter) gets:
/// - nothing when g < min_width_um (a track would pile material onto its neighbours);
/// - one track along its medial axis where it is at least min_width_um wide, when g <= the
///   track width: a closed stroke around a ring-shaped gap, open ones along strips and the
///   branches of a network;
/// - else the loops of the piece offset inward by g/4 (two tracks across it).
[[nodiscard]] std::vector<RouteStroke> gap_fill(const geom2d::Paths2& gaps,
                                                std::int64_t track_width_um,
                                                std::int64_t min_width_um);

}  // namespace maxslice::path::detail
