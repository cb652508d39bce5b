#pragma once

#include <cstdint>
#include <vector>

namespace maxslice::geom2d {

/// A point in a plane's own 2D frame, in integer micrometres. Coordinates stay within
/// +-1e9 um (1 km) so that Clipper works in its fast 64-bit range and squared lengths fit.
struct Point2 {
    std::int64_t x = 0;
    std::int64_t y = 0;
    constexpr bool operator==(const Point2&) const = default;
    constexpr auto operator<=>(const Point2&) const = default;
};

/// The largest coordinate magnitude geom2d accepts, in micrometres.
inline constexpr std::int64_t kMaxCoordinateUm = 1'000'000'000;

/// A closed polygon: the last point connects back to the first (it is not repeated).
using Path2 = std::vector<Point2>;
using Paths2 = std::vector<Path2>;

/// Signed area in um^2: positive when counter-clockwise (y up).
[[nodiscard]] double signed_area_um2(const Path2& path);
/// Sum of signed areas in mm^2.
[[nodiscard]] double signed_area_mm2(const Paths2& paths);
/// Total length of a closed path, in mm.
[[nodiscard]] double perimeter_mm(const Path2& path);
/// Length of the path read as an open polyline (first to last point, not closed), in um.
[[nodiscard]] double length_um(const Path2& path);

/// Area-weighted centroid of a region (outers CCW, holes CW) in um, as doubles; the mean of
/// the points when the region has no area; (0, 0) when it has no points.
struct Centroid2 {
    double x = 0.0;
    double y = 0.0;
};
[[nodiscard]] Centroid2 centroid_um(const Paths2& region);

/// The point of the region's boundary closest to p (um, rounded), and its distance (um).
/// Requires at least one point.
struct ClosestPoint {
    Point2 point;
    double distance_um = 0.0;
};
[[nodiscard]] ClosestPoint closest_boundary_point(const Paths2& region, Centroid2 p);
/// The point of the region (outers counter-clockwise, holes clockwise, non-zero winding)
/// closest to p and its distance (um): p itself (rounded) and 0 inside, else as
/// closest_boundary_point. One pass over the edges, in doubles (points on the boundary may
/// count either way, at distance 0 both ways).
[[nodiscard]] ClosestPoint closest_region_point(const Paths2& region, Centroid2 p);

/// How overlapping loops combine into a region.
enum class FillRule {
    kEvenOdd,   ///< inside where an odd number of loops cover the point
    kNonZero,   ///< inside where the winding number is not zero
    kPositive,  ///< inside where the winding number is positive (oriented loops)
};

/// The convex hull of all points of the paths: counter-clockwise, without collinear or
/// repeated points, starting at its smallest point. Fewer than 3 points when all the points
/// are collinear (2: the extreme points) or there is only one distinct point.
[[nodiscard]] Path2 convex_hull(const Paths2& paths);

/// The direction (radians in [0, pi)) along the long side of the orientation whose bounding
/// box has the largest long/short ratio, over the orientations of the convex hull's edges
/// (rotating calipers, O(n) after the hull). Ties go to the smaller angle; 0 for an empty or
/// single-point input.
[[nodiscard]] double long_side_angle(const Paths2& outer_wires);

/// A turn in the plane: the cosine and sine of its angle, exact (0 and +-1) at quarter turns,
/// so that a frame along the axes stays exactly along them.
struct PlaneTurn {
    double c = 1.0;
    double s = 0.0;
};
[[nodiscard]] PlaneTurn plane_turn(double angle_rad);

/// Where a point lies relative to a region.
enum class Containment { kOutside, kBoundary, kInside };

/// Locates a point in a region given as closed loops combined with the non-zero winding rule
/// (outers counter-clockwise and holes clockwise, as a WireTree gives them). Exact integer
/// arithmetic; O(total points).
[[nodiscard]] Containment locate_point(const Paths2& region, Point2 p);

/// The area (mm^2) of a region (closed loops, positive winding: outers counter-clockwise,
/// holes clockwise) that a disc of radius radius_um swept along open polylines does not
/// cover: what a set of tracks of width 2 * radius leaves bare. Integrated over rows at most
/// row_um apart that divide the region's height evenly (midpoint rule: the covered and inside
/// lengths of each row are exact, so the error comes only from how the lengths vary inside a row,
/// O(row^2) per boundary vertex or track end). O(row crossings), no polygon booleans: fast where a
/// union of thousands of strokes is not. A polyline of one point covers a disc.
[[nodiscard]] double uncovered_area_mm2(const Paths2& region, const Paths2& polylines,
                                        std::int64_t radius_um, std::int64_t row_um);

}  // namespace maxslice::geom2d
