#pragma once
// Ordering of strokes to keep idle (laser-off) travel short.

#include <vector>

#include "maxslice/geom2d/polygon.hpp"
#include "maxslice/path/toolpath.hpp"

namespace maxslice::path::detail {

/// A stroke before ordering: open polylines may be run either way; closed ones (the last
/// point connects back to the first, not repeated) may start anywhere on them.
struct RouteStroke {
    StrokeKind kind = StrokeKind::kFill;
    bool closed = false;
    geom2d::Path2 points;
};

/// Strokes deposited together, in any order among themselves (one island's contours, or
/// its fill).
using RouteGroup = std::vector<RouteStroke>;

/// An island's groups, deposited one after the other.
using RouteIsland = std::vector<RouteGroup>;

/// Orders islands (nearest first), and inside each island each group in turn (nearest
/// neighbour, then windowed 2-opt with stroke directions and closed-stroke start points),
/// starting from `start`. Closed strokes come out with their first point repeated at the end.
/// Deterministic; O(n * window) per 2-opt pass and a bounded number of passes.
[[nodiscard]] std::vector<Stroke> route_short(std::vector<RouteIsland> islands,
                                              geom2d::Point2 start);

/// The strokes as generated: islands, groups and strokes in input order, forward, closed
/// strokes starting at their first point.
[[nodiscard]] std::vector<Stroke> route_generated(std::vector<RouteIsland> islands);

}  // namespace maxslice::path::detail
