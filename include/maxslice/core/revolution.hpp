#pragma once
// The lowest point of a solid of revolution (a nozzle, a head body): the machine's head
// check and the planner's reach check both ask how low the head reaches.

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <utility>

namespace maxslice::core {

/// How far a solid of revolution reaches below its apex along a unit direction "up": its
/// outline is (t, r) points, t along its unit axis from the apex and r the radius there, and
/// cos_up = dot(axis, up). The solid is lowest on the rim of one of its circles, at
/// t * cos_up - r * sin_up; returns the least of those (+infinity for an empty outline).
[[nodiscard]] inline double lowest_on_revolution(std::span<const std::pair<double, double>> outline,
                                                 double cos_up) {
    const double sin_up = std::sqrt(std::max(0.0, 1.0 - cos_up * cos_up));
    double lowest = std::numeric_limits<double>::infinity();
    for (const auto& [t, r] : outline) lowest = std::min(lowest, t * cos_up - r * sin_up);
    return lowest;
}

}  // namespace maxslice::core
