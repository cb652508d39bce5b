#pragma once
// Distance queries to one region, many times: the build order asks, for every sample of
// deposited material near a nozzle, how far it lies from the footprint the apexes cover
// (METHOD.md section 7). geom2d::closest_region_point scans every edge per query; this index
// gives the same answers, bit for bit, from the edges near the point.

#include <cstdint>
#include <optional>
#include <vector>

#include "box_tree.hpp"
#include "maxslice/geom2d/polygon.hpp"

namespace maxslice::plan::detail {

/// A region (outers counter-clockwise, holes clockwise, non-zero winding; um) with its edges
/// in a box tree (nearest edge) and in rows (winding number). Immutable after construction;
/// queries may run concurrently.
class RegionDistance {
public:
    RegionDistance() = default;
    explicit RegionDistance(const geom2d::Paths2& region);

    /// closest_region_point(region, p) when the region's distance from p is below limit_um;
    /// nullopt when it is certainly not (then the distance is at least limit_um). Exactly
    /// the same point and distance as geom2d::closest_region_point: the same winding rule
    /// and per-edge arithmetic, ties broken towards the first edge in path order.
    [[nodiscard]] std::optional<geom2d::ClosestPoint> closest(geom2d::Centroid2 p,
                                                              double limit_um) const;

private:
    struct Edge {
        double ax, ay, dx, dy;  // start and direction (um), as the scan computes them
    };
    std::vector<Edge> edges_;  // in path order
    BoxTree tree_;             // the edges' boxes (z = 0)
    double y0_ = 0.0;          // rows of height row_ from y0_
    double row_ = 1.0;
    std::vector<std::uint32_t> row_begin_;  // per row: its edges in row_edges_
    std::vector<std::uint32_t> row_edges_;
};

}  // namespace maxslice::plan::detail
