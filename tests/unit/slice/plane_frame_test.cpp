#include "maxslice/slice/plane_frame.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "maxslice/geom2d/polygon.hpp"

namespace maxslice::slice {
namespace {

using core::Vec3d;

constexpr double kRoundTripMm = 0.001;  // 1 um: the 2D grid rounds to the nearest micrometre

Vec3d random_unit(std::mt19937_64& rng) {
    std::normal_distribution<double> g(0.0, 1.0);
    while (true) {
        const Vec3d d{g(rng), g(rng), g(rng)};
        if (core::norm(d) > 1e-3) return core::normalized(d);
    }
}

void expect_near(const Vec3d& a, const Vec3d& b, double tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

TEST(PlaneFrame, HorizontalFrameUsesPartAxes) {
    const PlaneFrame f = PlaneFrame::from_normal({1, 2, 3}, {0, 0, 5});
    expect_near(f.normal, {0, 0, 1}, 1e-15);
    expect_near(f.u, {1, 0, 0}, 1e-15);
    expect_near(f.v, {0, 1, 0}, 1e-15);
    EXPECT_EQ(f.origin, (Vec3d{1, 2, 3}));
}

TEST(PlaneFrame, DownwardFrameIsTheMirrorOfTheUpwardOne) {
    const PlaneFrame up = PlaneFrame::from_normal({}, {0, 0, 1});
    const PlaneFrame down = PlaneFrame::from_normal({}, {0, 0, -1});
    expect_near(down.u, up.u, 1e-15);
    expect_near(down.v, -up.v, 1e-15);
    const geom2d::Point2 q = down.to_2d({3, 4, 0});
    EXPECT_EQ(q, (geom2d::Point2{3000, -4000}));
}

TEST(PlaneFrame, FrameAlongXUsesY) {
    const PlaneFrame f = PlaneFrame::from_normal({}, {1, 0, 0});
    expect_near(f.u, {0, 1, 0}, 1e-15);
    expect_near(f.v, {0, 0, 1}, 1e-15);
}

TEST(PlaneFrame, RandomFramesAreRightHandedOrthonormal) {
    std::mt19937_64 rng(12345);
    for (int i = 0; i < 1000; ++i) {
        const Vec3d d = random_unit(rng);
        const PlaneFrame f = PlaneFrame::from_normal({}, d * 3.7);
        SCOPED_TRACE(i);
        expect_near(f.normal, d, 1e-12);
        EXPECT_NEAR(core::norm(f.u), 1.0, 1e-12);
        EXPECT_NEAR(core::norm(f.v), 1.0, 1e-12);
        EXPECT_NEAR(core::dot(f.u, f.v), 0.0, 1e-12);
        EXPECT_NEAR(core::dot(f.u, f.normal), 0.0, 1e-12);
        expect_near(core::cross(f.u, f.v), f.normal, 1e-12);
    }
}

TEST(PlaneFrame, RoundTripWithinOneMicrometre) {
    std::mt19937_64 rng(777);
    std::uniform_real_distribution<double> coord(-500.0, 500.0);
    for (int i = 0; i < 2000; ++i) {
        const Vec3d origin{coord(rng), coord(rng), coord(rng)};
        const PlaneFrame f = PlaneFrame::from_normal(origin, random_unit(rng));
        const Vec3d p{coord(rng), coord(rng), coord(rng)};
        const double h = f.height(p);
        SCOPED_TRACE(i);
        // A point off the plane comes back when lifted by its height ...
        EXPECT_LE(core::norm(f.to_3d(f.to_2d(p), h) - p), kRoundTripMm);
        // ... and its projection lies on the plane.
        EXPECT_NEAR(f.height(f.to_3d(f.to_2d(p))), 0.0, 1e-9);
        // Grid points survive exactly.
        const geom2d::Point2 q{static_cast<std::int64_t>(coord(rng) * 1000),
                               static_cast<std::int64_t>(coord(rng) * 1000)};
        EXPECT_EQ(f.to_2d(f.to_3d(q, coord(rng))), q);
    }
}

TEST(PlaneFrame, HeightAndShift) {
    const PlaneFrame f = PlaneFrame::from_normal({1, 1, 1}, {1, 1, 0});
    EXPECT_NEAR(f.height({1 + 3, 1 + 3, 7}), 3.0 * std::sqrt(2.0), 1e-12);
    const PlaneFrame g = f.shifted(2.5);
    EXPECT_NEAR(g.height(f.origin), -2.5, 1e-12);
    EXPECT_EQ(g.u, f.u);
    EXPECT_EQ(g.v, f.v);
    EXPECT_EQ(g.normal, f.normal);
    // The same point has the same 2D coordinates in both (the shift is along the normal).
    EXPECT_EQ(g.to_2d({5, -2, 4}), f.to_2d({5, -2, 4}));
}

TEST(PlaneFrame, CounterClockwiseSeenFromNormalIsCounterClockwiseIn2d) {
    std::mt19937_64 rng(99);
    for (int i = 0; i < 200; ++i) {
        const PlaneFrame f = PlaneFrame::from_normal({}, random_unit(rng));
        // A triangle in the plane, counter-clockwise about the normal by construction.
        const Vec3d a = f.u * 10.0;
        const Vec3d b = core::normalized(core::cross(f.normal, a)) * 10.0;
        const Vec3d c = -a - b;
        ASSERT_GT(core::dot(core::cross(b - a, c - a), f.normal), 0.0);
        const geom2d::Path2 path{f.to_2d(a), f.to_2d(b), f.to_2d(c)};
        EXPECT_GT(geom2d::signed_area_um2(path), 0.0) << i;
    }
}

}  // namespace
}  // namespace maxslice::slice
