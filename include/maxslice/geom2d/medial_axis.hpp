#pragma once

#include <cstdint>
#include <vector>

#include "maxslice/geom2d/polygon.hpp"

namespace maxslice::geom2d {

/// A piece of a region's medial axis: a polyline of points equally far from two or more
/// places of the region's boundary, with that distance (the radius of the largest disc
/// centred there that fits in the region: half the local width).
struct MedialLine {
    Path2 points;                   ///< um; a closed line repeats its first point at the end
    std::vector<double> radius_um;  ///< one per point
    bool closed = false;            ///< a ring (the middle of an annulus)

    bool operator==(const MedialLine&) const = default;
};

/// The medial axis of a region (closed loops, outers counter-clockwise, holes clockwise, as
/// the booleans of wire_tree.hpp return them: simple, touching at most at vertices), from
/// the Voronoi diagram of its boundary segments (Boost.Polygon): the diagram's edges inside
/// the region, without those where the region is narrower than 2 x min_radius_um (the
/// branches running into convex corners end there) and without side branches shorter than
/// the radius where they join (corner spurs). The lines are chained between branch points
/// and ends, in a deterministic order (by their smallest point). Curved edges (between a
/// reflex vertex and a segment) are replaced by their chord. Coordinates must lie within
/// +-2^31 um (geom2d's range is far inside).
[[nodiscard]] std::vector<MedialLine> medial_axis(const Paths2& region, std::int64_t min_radius_um);

}  // namespace maxslice::geom2d
