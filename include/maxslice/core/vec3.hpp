#pragma once

#include <cmath>

namespace maxslice::core {

/// A 3D point or vector in double millimetres (the frame is the caller's: part or plane).
struct Vec3d {
    double x = 0.0;
    double y = 0.0;
    double z = 0.0;

    constexpr Vec3d operator+(const Vec3d& o) const { return {x + o.x, y + o.y, z + o.z}; }
    constexpr Vec3d operator-(const Vec3d& o) const { return {x - o.x, y - o.y, z - o.z}; }
    constexpr Vec3d operator-() const { return {-x, -y, -z}; }
    constexpr Vec3d operator*(double s) const { return {x * s, y * s, z * s}; }
    constexpr Vec3d operator/(double s) const { return {x / s, y / s, z / s}; }
    constexpr Vec3d& operator+=(const Vec3d& o) {
        x += o.x;
        y += o.y;
        z += o.z;
        return *this;
    }
    constexpr bool operator==(const Vec3d&) const = default;
    constexpr double operator[](int axis) const { return axis == 0 ? x : (axis == 1 ? y : z); }
};

[[nodiscard]] constexpr double dot(const Vec3d& a, const Vec3d& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
[[nodiscard]] constexpr Vec3d cross(const Vec3d& a, const Vec3d& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
[[nodiscard]] inline double norm(const Vec3d& a) {
    return std::sqrt(dot(a, a));
}
/// The unit vector along a; a zero vector stays zero.
[[nodiscard]] inline Vec3d normalized(const Vec3d& a) {
    const double n = norm(a);
    return n > 0.0 ? a / n : a;
}
[[nodiscard]] inline bool is_finite(const Vec3d& a) {
    return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

/// std::fmin / std::fmax (a NaN argument is ignored; of two equal values the second is
/// returned, as glibc's minsd / maxsd do on x86-64) written out: at the baseline x86-64 ISA
/// GCC calls into libm for std::fmin, and boxes are grown once per corner in hot loops.
[[nodiscard]] inline double fmin_inline(double a, double b) {
    return (a < b || b != b) ? a : b;
}
[[nodiscard]] inline double fmax_inline(double a, double b) {
    return (a > b || b != b) ? a : b;
}

/// An axis-aligned box; empty until a point is added.
struct Box3d {
    Vec3d min{INFINITY, INFINITY, INFINITY};
    Vec3d max{-INFINITY, -INFINITY, -INFINITY};

    [[nodiscard]] bool empty() const { return min.x > max.x; }
    void add(const Vec3d& p) {
        min = {fmin_inline(min.x, p.x), fmin_inline(min.y, p.y), fmin_inline(min.z, p.z)};
        max = {fmax_inline(max.x, p.x), fmax_inline(max.y, p.y), fmax_inline(max.z, p.z)};
    }
    void add(const Box3d& b) {
        if (!b.empty()) {
            add(b.min);
            add(b.max);
        }
    }
    [[nodiscard]] Vec3d size() const { return empty() ? Vec3d{} : max - min; }
    [[nodiscard]] Vec3d center() const { return (min + max) * 0.5; }
};

}  // namespace maxslice::core
