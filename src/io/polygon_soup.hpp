#pragma once

// Private to src/io: turns indexed polygons (PLY, OFF) into the triangle soup that
// mesh::weld_exact takes, cutting each polygon by ear clipping in its own plane.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "maxslice/core/vec3.hpp"

namespace maxslice::io::detail {

/// Polygons with more corners than this are refused by the readers: ear clipping is
/// quadratic (convex polygons of any size are fanned and do not count).
inline constexpr std::size_t kMaxPolygonCorners = 8192;

class PolygonSoup {
public:
    explicit PolygonSoup(std::span<const core::Vec3d> vertices) : vertices_(vertices) {}

    /// Adds one polygon (indices already checked against the vertex count), counter-clockwise
    /// seen from outside. Fewer than 3 corners are counted and skipped.
    void add(std::span<const std::uint32_t> polygon);

    [[nodiscard]] const std::vector<double>& xyz() const { return xyz_; }
    [[nodiscard]] std::vector<double>& xyz() { return xyz_; }
    [[nodiscard]] std::size_t short_faces() const { return short_faces_; }
    /// Polygons ear clipping could not cut cleanly (self-intersecting or degenerate); the
    /// rest of such a polygon is fanned.
    [[nodiscard]] std::size_t fanned_faces() const { return fanned_faces_; }

private:
    void emit(std::uint32_t a, std::uint32_t b, std::uint32_t c);

    std::span<const core::Vec3d> vertices_;
    std::vector<double> xyz_;
    std::size_t short_faces_ = 0;
    std::size_t fanned_faces_ = 0;
    // Scratch space reused between polygons.
    std::vector<double> u_, v_;
    std::vector<std::uint32_t> prev_, next_;
};

}  // namespace maxslice::io::detail
