#pragma once
// Traces of convex cells on slicing planes: a region's section is the mesh's section
// clipped by the half-planes its cell's half-spaces leave on the plane (METHOD.md section 5;
// no 3D mesh booleans).

#include <optional>
#include <span>

#include "maxslice/geom2d/polygon.hpp"
#include "maxslice/plan/planner.hpp"
#include "maxslice/slice/plane_frame.hpp"

namespace maxslice::plan::detail {

/// The trace of the intersection of half-spaces on a plane, as one convex polygon in the
/// plane's frame (um, counter-clockwise): nullopt when the cell covers the whole plane (no
/// half-space, or all of them contain the plane), an empty path when it misses the plane.
[[nodiscard]] std::optional<geom2d::Path2> cell_trace(std::span<const HalfSpace> cell,
                                                      const slice::PlaneFrame& plane);

/// The region's part inside the cell (positive winding rule).
[[nodiscard]] geom2d::Paths2 clip_to_cell(const geom2d::Paths2& region,
                                          std::span<const HalfSpace> cell,
                                          const slice::PlaneFrame& plane);

}  // namespace maxslice::plan::detail
