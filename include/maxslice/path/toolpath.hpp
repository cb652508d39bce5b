#pragma once

#include <optional>
#include <span>
#include <vector>

#include "maxslice/core/progress.hpp"
#include "maxslice/core/result.hpp"
#include "maxslice/geom2d/polygon.hpp"
#include "maxslice/geom2d/wire_tree.hpp"

namespace maxslice::path {

/// How strokes are put in deposition order.
enum class StrokeOrder {
    /// Islands nearest-first from `start`; in each island its contours, then its fill, each
    /// group ordered nearest-neighbour then improved by 2-opt (direction of open strokes and
    /// start point of closed contours included).
    kShortTravel,
    /// As generated (islands in wire-tree order, contours as offset, fill lines bottom-up):
    /// a baseline to measure the ordering against.
    kGenerated,
};

/// Settings of the toolpath stage (METHOD.md section 9), in mm unless stated.
struct PathSettings {
    double track_width_mm = 2.5;  ///< bead width
    double overlap = 0.3;         ///< share of a track the next one overlaps, in [0, 1)
    int contour_passes = 1;       ///< passes along the wires before the fill (0 = fill only)
    /// Fill direction in degrees from the plane's u axis, for every island; unset = each
    /// island along the long side of its orientation whose bounding box has the largest
    /// long/short ratio.
    std::optional<double> raster_angle_deg;
    StrokeOrder order = StrokeOrder::kShortTravel;

    /// Distance between neighbouring track centres: width x (1 - overlap), in mm.
    [[nodiscard]] double pitch_mm() const { return track_width_mm * (1.0 - overlap); }
};

/// Checks ranges (width > 0, 0 <= overlap < 1, pitch >= 0.01 mm, passes >= 0, a finite raster
/// angle); errors (kInvalidInput) name the setting.
[[nodiscard]] core::Result<void> validate(const PathSettings& settings);

/// What a stroke deposits.
enum class StrokeKind { kContour, kFill };

/// A polyline deposited with the laser on from its first point to its last (a contour
/// repeats its first point at the end). Between strokes the head travels with the laser off
/// in a straight line from one stroke's last point to the next one's first.
struct Stroke {
    StrokeKind kind = StrokeKind::kFill;
    geom2d::Path2 points;  ///< in the layer plane's (u, v) frame, micrometres

    bool operator==(const Stroke&) const = default;
};

/// The toolpath of one layer, in deposition order.
struct LayerToolpath {
    std::vector<Stroke> strokes;
    double raster_angle_deg = 0.0;  ///< fill direction of the largest island, in [0, 180)
    double uncovered_mm2 = 0.0;     ///< area of the region no track covers (gaps < a track)
    double deposit_length_mm = 0.0;
    double travel_length_mm = 0.0;  ///< between strokes, from `start` to the last stroke

    bool operator==(const LayerToolpath&) const = default;
};

/// Plans the tracks of one layer's region (wires in the layer plane's frame, um): contour
/// passes (the wires offset inward by half a track, then by one pitch per further pass), a
/// zigzag fill of what is left with lines at most width x (1 - overlap) apart, neighbouring
/// lines linked along the boundary while the link stays inside (laser on), one track along
/// the medial axis of gaps between contours where no fill line fits, islands and strokes
/// ordered to keep idle
/// travel short starting from `start`. Holes are deposited around, never filled; hole wires
/// without an enclosing outer wire have no material and get no tracks. Every track lies
/// inside the region (its centre at least half a track from the boundary). Deterministic:
/// the same input gives the same output. Errors: invalid settings (kInvalidInput, naming the
/// setting). See docs/decisions/0004-toolpaths.md.
[[nodiscard]] core::Result<LayerToolpath> plan_layer(const geom2d::WireTree& region,
                                                     const PathSettings& settings,
                                                     geom2d::Point2 start);

/// The tracks plan_layer does not lay: one track along the medial axis of each island of the
/// region too narrow for a contour (its inscribed circle narrower than a track), where the
/// island is at least 5 % of a track wide. Its beads overhang the island on both sides; the
/// multi-axis job lays them under a feature that starts narrow and widens above it (the edge
/// of a slanted rib), whose layers would otherwise all rest on nothing (decision 0049).
/// Islands a contour fits get nothing here, and the uncovered area counts the narrow islands
/// only. Errors: invalid settings (kInvalidInput).
[[nodiscard]] core::Result<LayerToolpath> plan_narrow_layer(const geom2d::WireTree& region,
                                                            const PathSettings& settings,
                                                            geom2d::Point2 start);
/// plan_layer over a stack of layers: layer i starts where layer i - 1 ended (the first at
/// `start`). The tracks of all layers are planned in parallel (oneTBB), the ordering layer by
/// layer; the result does not depend on the thread count. Reports "toolpaths" progress and
/// stops with kCancelled when cancelled.
[[nodiscard]] core::Result<std::vector<LayerToolpath>> plan_layers(
    std::span<const geom2d::WireTree* const> regions, const PathSettings& settings,
    geom2d::Point2 start, const core::Progress* progress = nullptr);

}  // namespace maxslice::path
