#include "maxslice/geom2d/medial_axis.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "maxslice/geom2d/polygon.hpp"
#include "maxslice/geom2d/wire_tree.hpp"

namespace maxslice::geom2d {
namespace {

std::int64_t um(double mm) {
    return std::llround(mm * 1000.0);
}

// Rectangle [x0, x1] x [y0, y1] in mm, counter-clockwise.
Path2 rect(double x0, double y0, double x1, double y1) {
    return {{um(x0), um(y0)}, {um(x1), um(y0)}, {um(x1), um(y1)}, {um(x0), um(y1)}};
}

// Circle of radius r (mm) as a regular n-gon, counter-clockwise (clockwise when hole).
Path2 circle(double cx, double cy, double r, int n, bool hole = false) {
    Path2 p;
    for (int i = 0; i < n; ++i) {
        const double a = 2.0 * std::numbers::pi * i / n;
        p.push_back({um(cx + r * std::cos(a)), um(cy + r * std::sin(a))});
    }
    if (hole) std::reverse(p.begin(), p.end());
    return p;
}

double length_mm(const Path2& line) {
    double sum = 0.0;
    for (std::size_t i = 1; i < line.size(); ++i) {
        sum += std::hypot(static_cast<double>(line[i].x - line[i - 1].x),
                          static_cast<double>(line[i].y - line[i - 1].y));
    }
    return sum / 1000.0;
}

// The properties every medial line has: its points lie inside the region, the radius
// given for each is its distance to the boundary, and no radius is under the minimum.
void expect_medial(const Paths2& region, const std::vector<MedialLine>& lines,
                   std::int64_t min_radius_um) {
    for (const MedialLine& line : lines) {
        ASSERT_GE(line.points.size(), 2u);
        ASSERT_EQ(line.points.size(), line.radius_um.size());
        if (line.closed) {
            EXPECT_EQ(line.points.front(), line.points.back());
        }
        for (std::size_t i = 0; i < line.points.size(); ++i) {
            const Point2 p = line.points[i];
            EXPECT_NE(locate_point(region, p), Containment::kOutside)
                << "(" << p.x << ", " << p.y << ")";
            const double d =
                closest_boundary_point(region, {static_cast<double>(p.x), static_cast<double>(p.y)})
                    .distance_um;
            // The region is shrunk by 2 um before the diagram, points are rounded to 1 um.
            EXPECT_NEAR(line.radius_um[i], d, 5.0) << "(" << p.x << ", " << p.y << ")";
            EXPECT_GE(line.radius_um[i], static_cast<double>(min_radius_um) - 5.0);
        }
    }
}

TEST(MedialAxis, StripGivesOneLineAlongItsMiddle) {
    const Paths2 strip{rect(0, 0, 20, 2)};
    const auto lines = medial_axis(strip, um(0.2));
    expect_medial(strip, lines, um(0.2));
    // The spurs into the four corners are pruned: one line along y = 1 mm.
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_FALSE(lines[0].closed);
    for (const Point2& p : lines[0].points) EXPECT_NEAR(p.y, um(1.0), 2);
    EXPECT_NEAR(length_mm(lines[0].points), 18.0, 0.05);  // from x = 1 to x = 19
}

TEST(MedialAxis, AnnulusGivesOneRingAtItsMiddle) {
    const Paths2 ring{circle(0, 0, 12, 180), circle(0, 0, 10, 180, true)};
    const auto lines = medial_axis(ring, um(0.2));
    expect_medial(ring, lines, um(0.2));
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_TRUE(lines[0].closed);
    for (std::size_t i = 0; i < lines[0].points.size(); ++i) {
        const Point2 p = lines[0].points[i];
        EXPECT_NEAR(std::hypot(static_cast<double>(p.x), static_cast<double>(p.y)), um(11.0), 20);
        EXPECT_NEAR(lines[0].radius_um[i], 1000.0, 20.0);
    }
}

TEST(MedialAxis, TeeGivesThreeBranches) {
    // A bar 30 x 2 mm with a stem 2 x 15 mm under its middle.
    const Paths2 tee = union_of({rect(0, 15, 30, 17), rect(14, 0, 16, 16)});
    const auto lines = medial_axis(tee, um(0.2));
    expect_medial(tee, lines, um(0.2));
    ASSERT_EQ(lines.size(), 3u);
    double total = 0.0;
    for (const MedialLine& l : lines) total += length_mm(l.points);
    // They meet at (15, 16), 1 mm from the bar's top and the stem's sides: arms of 15 - 1 mm
    // (to the bar's ends less the end radius), the stem from y = 1 mm up to 16 mm.
    EXPECT_NEAR(total, 14.0 + 14.0 + 15.0, 0.5);
}

TEST(MedialAxis, NarrowerThanTheMinimumGivesNothing) {
    const Paths2 strip{rect(0, 0, 20, 2)};
    EXPECT_TRUE(medial_axis(strip, um(1.2)).empty());
    EXPECT_TRUE(medial_axis({}, 0).empty());
    EXPECT_TRUE(medial_axis({rect(0, 0, 1, 1)}, um(0.6)).empty());
}

TEST(MedialAxis, HoleTouchingItsOuterWireStaysInside) {
    // A hole whose corner touches the outer wire in the middle of its right edge: input
    // Boost's diagram does not accept as is (the contact is taken apart first).
    const Path2 outer = rect(0, 0, 10, 6);
    const Path2 hole{
        {um(4), um(2)}, {um(4), um(4)}, {um(7), um(4)}, {um(10), um(3)}, {um(7), um(2)}};
    const Paths2 region{outer, hole};
    const auto lines = medial_axis(region, um(0.2));
    ASSERT_FALSE(lines.empty());
    expect_medial(region, lines, um(0.2));
}

TEST(MedialAxis, RandomRegionsKeepTheProperties) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(0.6, 1.0);
    for (int k = 0; k < 20; ++k) {
        SCOPED_TRACE(k);
        // A star-shaped outer wire with a jittered radius and a round hole near its centre.
        Path2 outer;
        const int n = 12 + k;
        for (int i = 0; i < n; ++i) {
            const double a = 2.0 * std::numbers::pi * i / n;
            const double r = 10.0 * jitter(rng);
            outer.push_back({um(r * std::cos(a)), um(r * std::sin(a))});
        }
        const Paths2 region =
            difference_of({outer}, {circle(0.3 * (k % 3), 0.2 * (k % 4), 2.5, 40)});
        const auto lines = medial_axis(region, um(0.3));
        EXPECT_FALSE(lines.empty());
        expect_medial(region, lines, um(0.3));
        // Deterministic.
        EXPECT_EQ(lines, medial_axis(region, um(0.3)));
    }
}

}  // namespace
}  // namespace maxslice::geom2d
