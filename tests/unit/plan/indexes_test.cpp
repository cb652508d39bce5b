// The planner's and the build order's private indexes give the answers of the plain
// functions they stand in for, bit for bit: RegionDistance against
// geom2d::closest_region_point, SectionIndex against slice::slice_mesh of the whole mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <span>
#include <vector>

#include "box_tree.hpp"
#include "maxslice/geom2d/polygon.hpp"
#include "maxslice/slice/slicer.hpp"
#include "region_distance.hpp"
#include "section_index.hpp"
#include "support/fixtures.hpp"

namespace maxslice::plan::detail {
namespace {

using geom2d::Path2;
using geom2d::Paths2;

// A star with holes and a separate island: concave corners, collinear and repeated points,
// a one-point path, edges of every direction (um).
Paths2 star_region() {
    Paths2 out;
    Path2 star;
    for (int k = 0; k < 24; ++k) {
        const double a = 2.0 * 3.14159265358979 * k / 24.0;
        const double r = (k % 2 == 0) ? 40000.0 : 15000.0;
        star.push_back({std::llround(r * std::cos(a)), std::llround(r * std::sin(a))});
    }
    star.push_back(star.back());  // a repeated point: a zero-length edge
    out.push_back(star);
    out.push_back({{-3000, -3000}, {-3000, 3000}, {3000, 3000}, {3000, -3000}});  // hole (CW)
    out.push_back({{60000, 0}, {70000, 0}, {80000, 0}, {80000, 10000}, {60000, 10000}});
    out.push_back({{100000, 100000}});  // a single point
    return out;
}

TEST(RegionDistance, SameAsClosestRegionPointEverywhere) {
    const Paths2 region = star_region();
    const RegionDistance index(region);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> coord(-60000.0, 120000.0);
    int inside = 0, checked = 0;
    const auto check = [&](geom2d::Centroid2 p) {
        const geom2d::ClosestPoint want = geom2d::closest_region_point(region, p);
        const auto got = index.closest(p, INFINITY);
        ASSERT_TRUE(got.has_value());
        EXPECT_EQ(got->point, want.point) << p.x << ", " << p.y;
        EXPECT_EQ(got->distance_um, want.distance_um) << p.x << ", " << p.y;
        // With a limit: the same answer below it, nothing (and truly not closer) above it.
        const auto limited = index.closest(p, 5000.0);
        if (want.distance_um < 5000.0) {
            ASSERT_TRUE(limited.has_value());
            EXPECT_EQ(limited->point, want.point);
            EXPECT_EQ(limited->distance_um, want.distance_um);
        } else {
            EXPECT_FALSE(limited.has_value());
        }
        inside += want.distance_um == 0.0 ? 1 : 0;
        ++checked;
    };
    for (int i = 0; i < 20000; ++i) check({coord(rng), coord(rng)});
    // On vertices, on edges, on the rows' boundaries and on the symmetry lines (ties).
    for (const Path2& path : region) {
        for (std::size_t i = 0; i < path.size(); ++i) {
            const geom2d::Point2 a = path[i], b = path[(i + 1) % path.size()];
            check({static_cast<double>(a.x), static_cast<double>(a.y)});
            check({0.5 * static_cast<double>(a.x + b.x), 0.5 * static_cast<double>(a.y + b.y)});
        }
    }
    for (double x = -50000.0; x <= 110000.0; x += 2500.0) {
        check({x, 0.0});
        check({x, 5000.0});
        check({0.0, x});
    }
    EXPECT_GT(inside, 100);
    EXPECT_GT(checked, 20000);
}

TEST(RegionDistance, EmptyRegionFindsNothing) {
    const RegionDistance index(Paths2{});
    EXPECT_FALSE(index.closest({0.0, 0.0}, INFINITY).has_value());
}

TEST(BoxTree, VisitsEveryBoxTheTestAccepts) {
    std::vector<core::Vec3d> lo, hi;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> c(0.0, 100.0), s(0.0, 10.0);
    for (int i = 0; i < 500; ++i) {
        const core::Vec3d a{c(rng), c(rng), c(rng)};
        lo.push_back(a);
        hi.push_back(a + core::Vec3d{s(rng), s(rng), s(rng)});
    }
    lo.push_back({1, 1, 1});  // an empty box: never reported
    hi.push_back({0, 0, 0});
    const BoxTree tree(lo, hi);
    const core::Vec3d qlo{20, 30, 40}, qhi{45, 50, 90};
    const auto meets = [&](const core::Vec3d& a, const core::Vec3d& b) {
        return a.x <= qhi.x && qlo.x <= b.x && a.y <= qhi.y && qlo.y <= b.y && a.z <= qhi.z &&
               qlo.z <= b.z;
    };
    std::vector<int> seen(lo.size(), 0);
    tree.visit(meets, [&](std::uint32_t i) {
        if (meets(lo[i], hi[i])) ++seen[i];
    });
    for (std::size_t i = 0; i < lo.size(); ++i) {
        const bool want = i + 1 < lo.size() && meets(lo[i], hi[i]);
        EXPECT_EQ(seen[i], want ? 1 : 0) << i;
    }
}

TEST(SectionIndex, SameSectionsAsSlicingTheWholeMesh) {
    // A tilted holed plate and a tilted cylinder, cut by planes of many directions, some
    // through vertices.
    mesh::TriangleMesh m =
        test::merged(test::rotated(test::plate_with_holes(), {1, 1, 0}, 30.0),
                     test::translated(test::rotated(test::cylinder(8.0, 30.0, 40), {0, 1, 1}, 50.0),
                                      {40, 0, 0}));
    SectionIndex index(m);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> dir(-1.0, 1.0), pos(-10.0, 60.0);
    int non_empty = 0;
    for (int i = 0; i < 200; ++i) {
        core::Vec3d n{dir(rng), dir(rng), dir(rng)};
        if (core::norm(n) < 0.1) continue;
        if (i % 10 == 0) n = {0, 0, 1};
        core::Vec3d o{pos(rng), pos(rng) - 20.0, pos(rng) / 3.0};
        if (i % 7 == 0) o = m.vertices[static_cast<std::size_t>(i) * 13 % m.vertices.size()];
        const slice::PlaneFrame plane = slice::PlaneFrame::from_normal(o, n);
        const slice::LayerSpan span{-0.25, 0.25, 0.0};
        auto whole = slice::slice_mesh(m, plane, std::span(&span, 1));
        ASSERT_TRUE(whole.has_value());
        auto part = index.section(plane, 0.5);
        ASSERT_TRUE(part.has_value());
        EXPECT_EQ(*part, whole->front().wires.paths()) << "plane " << i;
        non_empty += part->empty() ? 0 : 1;
    }
    EXPECT_GT(non_empty, 50);
}

}  // namespace
}  // namespace maxslice::plan::detail
