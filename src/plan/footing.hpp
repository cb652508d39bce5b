#pragma once
// The footing at the plate (decision 0017): the pads the planner's walk and the planar check
// lay over a stack's first layers. Private to plan.

#include <cstddef>
#include <functional>
#include <vector>

#include "maxslice/core/result.hpp"
#include "maxslice/geom2d/polygon.hpp"
#include "maxslice/plan/planner.hpp"

namespace maxslice::plan::detail {

/// Rounding room (mm) when comparing a layer's top with the footing's height.
constexpr double kFootingSlackMm = 1e-6;

/// Splits and overhangs on a layer that ends (or the one above starts) at most this high
/// above the plate are where the footing is tried: the footing and a look-back above (mm).
[[nodiscard]] double footing_zone_mm(const PlanSettings& s);

/// The footing from section `first` of a stack of n parallel sections (in-plane axes
/// shared), whose layers' tops lie at top(j) above the plate (mm): for each section from
/// first whose top lies within footing_mm, the union of it and every later section up to and
/// with the first whose top lies above that height, or up to an empty section (a gap). Each
/// such layer then carries the next, and the first layer above the footing stands on it
/// whole. section(j) gives section j (um, positive winding); its errors are returned.
[[nodiscard]] core::Result<std::vector<geom2d::Paths2>> footing_pads(
    std::size_t first, std::size_t n, double footing_mm,
    const std::function<core::Result<geom2d::Paths2>(std::size_t)>& section,
    const std::function<double(std::size_t)>& top);

}  // namespace maxslice::plan::detail
