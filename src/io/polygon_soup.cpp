// Ear clipping in the polygon's plane. The plane comes from Newell's normal (robust for
// non-planar and concave polygons); the polygon is projected on the coordinate plane most
// perpendicular to it, oriented so that it runs counter-clockwise there. An ear is a convex
// corner whose triangle contains no other corner; clipping ears one by one keeps every
// triangle inside the polygon with the polygon's orientation, which a fan does not do for
// concave polygons. Collinear corners (a vertex on a straight edge) are clipped only when
// no strictly convex ear is left. A polygon with no ear at all (self-intersecting) has its
// remainder fanned and is counted.

#include "polygon_soup.hpp"

#include <cmath>

namespace maxslice::io::detail {
namespace {

double cross2(double ax, double ay, double bx, double by, double cx, double cy) {
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

}  // namespace

void PolygonSoup::emit(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    for (const std::uint32_t i : {a, b, c}) {
        const core::Vec3d& p = vertices_[i];
        xyz_.insert(xyz_.end(), {p.x, p.y, p.z});
    }
}

void PolygonSoup::add(std::span<const std::uint32_t> poly) {
    const std::size_t n = poly.size();
    if (n < 3) {
        ++short_faces_;
        return;
    }
    if (n == 3) {
        emit(poly[0], poly[1], poly[2]);
        return;
    }
    // Newell's normal picks the projection plane and its orientation.
    core::Vec3d normal{};
    for (std::size_t i = 0; i < n; ++i) {
        const core::Vec3d& a = vertices_[poly[i]];
        const core::Vec3d& b = vertices_[poly[(i + 1) % n]];
        normal.x += (a.y - b.y) * (a.z + b.z);
        normal.y += (a.z - b.z) * (a.x + b.x);
        normal.z += (a.x - b.x) * (a.y + b.y);
    }
    const double ax = std::fabs(normal.x), ay = std::fabs(normal.y), az = std::fabs(normal.z);
    const int drop = (ax >= ay && ax >= az) ? 0 : (ay >= az ? 1 : 2);
    const double sign = normal[drop] < 0.0 ? -1.0 : 1.0;
    u_.resize(n);
    v_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const core::Vec3d& p = vertices_[poly[i]];
        // (y, z), (z, x), (x, y): right-handed about the dropped axis.
        const double a = drop == 0 ? p.y : (drop == 1 ? p.z : p.x);
        const double b = drop == 0 ? p.z : (drop == 1 ? p.x : p.y);
        u_[i] = a;
        v_[i] = b * sign;  // mirrored when the normal points down the axis: now CCW
    }
    if (!(ax + ay + az > 0.0)) {  // no area at all: nothing better than a fan
        for (std::size_t i = 1; i + 1 < n; ++i) emit(poly[0], poly[i], poly[i + 1]);
        ++fanned_faces_;
        return;
    }
    // Convex polygons (most PLY/OFF faces, however many corners) are fanned directly.
    bool convex = true;
    for (std::size_t i = 0; i < n && convex; ++i) {
        const std::size_t p = (i + n - 1) % n, q = (i + 1) % n;
        convex = cross2(u_[p], v_[p], u_[i], v_[i], u_[q], v_[q]) > 0.0;
    }
    if (convex) {
        for (std::size_t i = 1; i + 1 < n; ++i) emit(poly[0], poly[i], poly[i + 1]);
        return;
    }
    prev_.resize(n);
    next_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        prev_[i] = static_cast<std::uint32_t>((i + n - 1) % n);
        next_[i] = static_cast<std::uint32_t>((i + 1) % n);
    }
    auto is_ear = [&](std::uint32_t i, bool allow_flat) {
        const std::uint32_t p = prev_[i], q = next_[i];
        const double turn = cross2(u_[p], v_[p], u_[i], v_[i], u_[q], v_[q]);
        if (turn < 0.0 || (turn == 0.0 && !allow_flat)) return false;
        for (std::uint32_t j = next_[q]; j != p; j = next_[j]) {
            const double x = u_[j], y = v_[j];
            const bool at_corner = (x == u_[p] && y == v_[p]) || (x == u_[i] && y == v_[i]) ||
                                   (x == u_[q] && y == v_[q]);
            if (at_corner) continue;
            if (cross2(u_[p], v_[p], u_[i], v_[i], x, y) >= 0.0 &&
                cross2(u_[i], v_[i], u_[q], v_[q], x, y) >= 0.0 &&
                cross2(u_[q], v_[q], u_[p], v_[p], x, y) >= 0.0) {
                return false;
            }
        }
        return true;
    };
    std::size_t left = n;
    std::uint32_t i = 0;
    std::size_t misses = 0;
    bool allow_flat = false;
    while (left > 3) {
        if (is_ear(i, allow_flat)) {
            const std::uint32_t p = prev_[i], q = next_[i];
            emit(poly[p], poly[i], poly[q]);
            next_[p] = q;
            prev_[q] = p;
            --left;
            i = p;
            misses = 0;
            allow_flat = false;
            continue;
        }
        i = next_[i];
        if (++misses <= left) continue;
        if (!allow_flat) {
            allow_flat = true;
            misses = 0;
            continue;
        }
        // No ear anywhere: the polygon crosses itself. Fan what is left.
        ++fanned_faces_;
        const std::uint32_t first = i;
        for (std::uint32_t j = next_[first]; next_[j] != first; j = next_[j]) {
            emit(poly[first], poly[j], poly[next_[j]]);
        }
        return;
    }
    emit(poly[prev_[i]], poly[i], poly[next_[i]]);
}

}  // namespace maxslice::io::detail
