#pragma once
// Zigzag (raster) fill of one island: orientation, scan lines, linking into strokes.

#include <cstdint>
#include <vector>

#include "maxslice/geom2d/polygon.hpp"

namespace maxslice::path::detail {

/// A rotation of the layer plane that turns the raster direction into +x ("raster frame").
/// Points are rounded to whole micrometres after rotating (at most 0.71 um off); the
/// rotations by multiples of 90 degrees are exact.
class RasterFrame {
public:
    explicit RasterFrame(double angle_rad);
    [[nodiscard]] geom2d::Point2 to_raster(geom2d::Point2 p) const;
    [[nodiscard]] geom2d::Point2 from_raster(geom2d::Point2 p) const;
    [[nodiscard]] geom2d::Paths2 to_raster(const geom2d::Paths2& paths) const;
    [[nodiscard]] geom2d::Path2 from_raster(const geom2d::Path2& path) const;

private:
    double c_ = 1.0;
    double s_ = 0.0;
};

/// Inputs of the zigzag fill, in the raster frame.
struct ZigzagInput {
    const geom2d::Paths2* fill_region = nullptr;  ///< where fill line centres may run
    const geom2d::Paths2* link_region = nullptr;  ///< where a straight link may run
    std::int64_t pitch_um = 0;                    ///< largest distance between lines
    /// Largest distance from the region's lowest and highest points to the extreme lines.
    std::int64_t max_margin_um = 0;
    std::int64_t max_link_um = 0;  ///< longest link between two lines
};

/// Horizontal lines at most a pitch apart, the extreme ones at most max_margin inside the fill
/// region's extremes, clipped to the fill region (holes split them) and linked end to start
/// into zigzag polylines, in generation order (bottom-up). Raster frame.
[[nodiscard]] geom2d::Paths2 zigzag_fill(const ZigzagInput& in);

}  // namespace maxslice::path::detail
