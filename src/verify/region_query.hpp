// Region queries and convex fills on the verifier's voxel pyramid. Private to verify.
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "maxslice/core/vec3.hpp"
#include "voxel_grid.hpp"

namespace maxslice::verify::detail {

/// A point of the (a, r) half plane of a solid of revolution: a along its axis, r across.
struct AxialPoint {
    double a = 0.0;
    double r = 0.0;
};

/// A solid of revolution about an axis, as a union of convex polygons in the (a, r) plane,
/// each symmetric about r = 0 and counter-clockwise (a to the right, r up): a cone is a
/// trapezoid, a cylinder a rectangle.
struct Region {
    /// An edge's outward unit normal and offset: (a, r) . n - offset is the signed distance
    /// to its line.
    struct Edge {
        double na = 0.0, nr = 0.0, offset = 0.0;
    };
    std::vector<std::array<AxialPoint, 4>> polygons;
    std::vector<std::array<Edge, 4>> edges;
    double a_min = 0.0;  ///< axial extent of the union
    double a_max = 0.0;
    double r_max = 0.0;  ///< radial extent

    void add(const std::array<AxialPoint, 4>& p);
    /// Distance from (a, r) to the union, negative inside (exact for convex parts; for a point
    /// inside one part, minus its depth in that part).
    [[nodiscard]] double distance(double a, double r) const;
    /// A lower bound of distance() outside the region (the largest edge-line distance of the
    /// nearest polygon), exact inside; no square roots.
    [[nodiscard]] double distance_bound(double a, double r) const;
    /// distance_bound(a, r) <= limit, decided with the fewest edges: the first polygon within
    /// it answers, and a polygon is left at its first edge line beyond it.
    [[nodiscard]] bool bound_within(double a, double r, double limit) const;
};

/// Looks for a set voxel whose centre lies within `margin` of the region placed with its axis
/// origin at `apex` along the unit `axis` (world mm), and not below the region's a_min (the
/// margin widens the region across and beyond its far end, never below its floor). Returns at
/// once when no set voxel reaches the floor; otherwise looks at the voxel in the middle of the
/// region's axis, then descends the pyramid only through set cells the region may reach. The
/// first hit in that fixed order is returned (deterministic).
[[nodiscard]] bool find_occupied(const OccupancyPyramid& grid, const core::Vec3d& origin,
                                 double voxel, const core::Vec3d& apex, const core::Vec3d& axis,
                                 const Region& region, double margin, core::Vec3d* hit);

/// A convex solid as at most kMax slabs lo <= n . p <= hi, with at most kMaxCorners corners
/// that bound it (a bead box has 3 and 8, a round joint 5 and 16). Fixed capacity: one is laid
/// for every bead piece, so it allocates nothing.
struct Slabs {
    struct Slab {
        core::Vec3d n;
        double lo = 0.0;
        double hi = 0.0;
    };
    static constexpr std::size_t kMax = 8;
    static constexpr std::size_t kMaxCorners = 16;
    std::array<Slab, kMax> slab{};
    std::size_t slab_count = 0;
    std::array<core::Vec3d, kMaxCorners> corner{};
    std::size_t corner_count = 0;
    /// Precondition: fewer than kMax slabs so far.
    void add(const core::Vec3d& n, double lo, double hi) { slab[slab_count++] = {n, lo, hi}; }
    /// Precondition: fewer than kMaxCorners corners so far.
    void add_corner(const core::Vec3d& c) { corner[corner_count++] = c; }
    [[nodiscard]] std::span<const Slab> slabs() const { return {slab.data(), slab_count}; }
    [[nodiscard]] std::span<const core::Vec3d> corners() const {
        return {corner.data(), corner_count};
    }
};

/// Sets every voxel whose centre lies inside the convex solid (z columns, one interval each).
void fill(OccupancyPyramid& grid, const core::Vec3d& origin, double voxel, const Slabs& solid);

}  // namespace maxslice::verify::detail
