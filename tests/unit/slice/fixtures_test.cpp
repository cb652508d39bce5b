// The fixtures are the yardstick of the slicer tests, so they are checked here with code of
// their own (no dependency on the mesh module's validation).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <tuple>
#include <utility>

#include "support/fixtures.hpp"

namespace maxslice::test {
namespace {

using core::Vec3d;
using mesh::TriangleMesh;

struct EdgeUse {
    int forward = 0;   // used as (low index -> high index)
    int backward = 0;  // used as (high -> low)
};

std::map<std::pair<std::uint32_t, std::uint32_t>, EdgeUse> edge_uses(const TriangleMesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, EdgeUse> uses;
    for (const auto& t : m.triangles) {
        for (int i = 0; i < 3; ++i) {
            const std::uint32_t a = t[static_cast<std::size_t>(i)];
            const std::uint32_t b = t[static_cast<std::size_t>((i + 1) % 3)];
            auto& use = uses[std::minmax(a, b)];
            (a < b ? use.forward : use.backward) += 1;
        }
    }
    return uses;
}

// Closed, manifold and consistently oriented: every undirected edge is used exactly twice,
// once in each direction.
int bad_edges(const TriangleMesh& m) {
    int bad = 0;
    for (const auto& [edge, use] : edge_uses(m)) {
        if (use.forward != 1 || use.backward != 1) ++bad;
    }
    return bad;
}

double own_signed_volume(const TriangleMesh& m) {
    double six = 0.0;
    for (const auto& t : m.triangles) {
        six += core::dot(m.vertices[t[0]], core::cross(m.vertices[t[1]], m.vertices[t[2]]));
    }
    return six / 6.0;
}

double triangle_area(const TriangleMesh& m, std::size_t i) {
    const auto& t = m.triangles[i];
    const Vec3d a = m.vertices[t[0]];
    return 0.5 * core::norm(core::cross(m.vertices[t[1]] - a, m.vertices[t[2]] - a));
}

// V - E + F: 2 per sphere-like shell, minus 2 per handle (hole through the part).
long euler_characteristic(const TriangleMesh& m) {
    return static_cast<long>(m.vertices.size()) - static_cast<long>(edge_uses(m).size()) +
           static_cast<long>(m.triangles.size());
}

long expected_euler(const std::string& name) {
    if (name == "cylinder_with_hole" || name == "thin_tube") return 0;
    if (name == "plate_with_holes") return 2 - 2 * PlateSpec{}.n_holes;
    if (name == "nested_boxes") return 6;
    return 2;
}

class FixtureTest : public ::testing::TestWithParam<std::size_t> {
protected:
    Fixture fixture() const { return all_fixtures()[GetParam()]; }
};

TEST_P(FixtureTest, IsClosedManifoldAndConsistentlyOriented) {
    const Fixture f = fixture();
    ASSERT_FALSE(f.mesh.triangles.empty());
    EXPECT_EQ(bad_edges(f.mesh), 0);
    EXPECT_EQ(euler_characteristic(f.mesh), expected_euler(f.name));
}

TEST_P(FixtureTest, HasNoDegenerateTrianglesUnusedOrDuplicateVertices) {
    const Fixture f = fixture();
    std::vector<bool> used(f.mesh.vertices.size(), false);
    for (std::size_t i = 0; i < f.mesh.triangles.size(); ++i) {
        EXPECT_GT(triangle_area(f.mesh, i), 1e-9) << "triangle " << i;
        for (auto v : f.mesh.triangles[i]) {
            ASSERT_LT(v, f.mesh.vertices.size());
            used[v] = true;
        }
    }
    EXPECT_EQ(std::count(used.begin(), used.end(), false), 0);
    // Shared vertices: no two vertices at the same place (a crack would duplicate them).
    std::set<std::tuple<double, double, double>> positions;
    for (const Vec3d& p : f.mesh.vertices) positions.insert({p.x, p.y, p.z});
    EXPECT_EQ(positions.size(), f.mesh.vertices.size());
}

TEST_P(FixtureTest, SignedVolumeMatchesAnalyticVolume) {
    const Fixture f = fixture();
    EXPECT_GT(f.volume_mm3, 0.0);
    EXPECT_NEAR(own_signed_volume(f.mesh), f.volume_mm3, 1e-9 * f.volume_mm3);
}

TEST_P(FixtureTest, AreaFunctionIntegratesToVolume) {
    const Fixture f = fixture();
    const double top = f.vertex_heights.back();
    ASSERT_EQ(f.vertex_heights.front(), 0.0) << "fixtures stand on z = 0";
    const int n = 20000;
    const double dz = top / n;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) sum += f.area_at((i + 0.5) * dz) * dz;
    EXPECT_NEAR(sum, f.volume_mm3, 1e-4 * f.volume_mm3);
    EXPECT_EQ(f.area_at(-1e-9), 0.0);
    EXPECT_EQ(f.area_at(top), 0.0) << "sections are taken just above z";
}

TEST_P(FixtureTest, ShapeIsEmptyExactlyWhereAreaIsZero) {
    const Fixture f = fixture();
    const double top = f.vertex_heights.back();
    std::vector<double> zs = f.vertex_heights;
    for (int i = 0; i <= 200; ++i) zs.push_back(-0.1 + (top + 0.2) * i / 200.0);
    for (const double z : zs) {
        const SectionShape s = f.shape_at(z);
        EXPECT_EQ(s.outers == 0, f.area_at(z) == 0.0) << f.name << " z " << z;
        EXPECT_LE(s.holes == 0 ? 0 : 1, s.max_depth);
    }
}

INSTANTIATE_TEST_SUITE_P(All, FixtureTest, ::testing::Range<std::size_t>(0, all_fixtures().size()),
                         [](const auto& info) { return all_fixtures()[info.param].name; });

TEST(FixtureChecks, DetectAnOpenMesh) {
    TriangleMesh m = unit_cube();
    m.triangles.pop_back();
    EXPECT_GT(bad_edges(m), 0);
}

TEST(FixtureChecks, DetectAFlippedTriangle) {
    TriangleMesh m = unit_cube();
    std::swap(m.triangles[3][1], m.triangles[3][2]);
    EXPECT_GT(bad_edges(m), 0);
}

TEST(FixtureChecks, InvertedMeshHasNegativeVolume) {
    EXPECT_NEAR(own_signed_volume(inverted(cylinder(2.0, 3.0, 16))), -cylinder_volume(2.0, 3.0, 16),
                1e-12);
}

TEST(CapPieces, HoledCellAreaIsSquareMinusPolygon) {
    for (int n : {8, 16, 32, 64}) {
        const Cap cap = holed_cell_cap(1.0, 2.0, 11.0, 3.0, n);
        EXPECT_NEAR(cap_area(cap), 100.0 - regular_polygon_area(3.0, n), 1e-10) << n;
    }
}

TEST(CapPieces, NeighbouringCellsShareTheirCommonSide) {
    CapBuilder b;
    b.add(holed_cell_cap(0.0, 0.0, 10.0, 3.0, 32));
    const std::size_t alone = b.cap().vertices.size();
    b.add(holed_cell_cap(10.0, 0.0, 20.0, 3.0, 32));
    // The second cell adds its own circle (32) and square points (32) minus the 9 points of
    // the shared side (4 per half side plus the two corners and the middle).
    EXPECT_EQ(b.cap().vertices.size(), alone + 64 - 9);
}

TEST(CapPieces, AnnulusAndFanAreas) {
    EXPECT_NEAR(cap_area(annulus_cap({1, 1}, 5.0, 2.0, 24)),
                regular_polygon_area(5.0, 24) - regular_polygon_area(2.0, 24), 1e-10);
    const auto rim = regular_polygon({0, 0}, 4.0, 10);
    EXPECT_NEAR(cap_area(fan_cap({0, 0}, rim)), regular_polygon_area(4.0, 10), 1e-10);
    EXPECT_NEAR(regular_polygon_area(1.0, 4), 2.0, 1e-15);
    EXPECT_NEAR(regular_polygon_area(1.0, 100000), std::numbers::pi, 1e-8);
}

TEST(CapPieces, ChordIsTakenJustAboveTheLine) {
    const Cap square = rectangle_cap(0, 0, 2, 3);
    EXPECT_DOUBLE_EQ(cap_chord(square, 0.0), 2.0);
    EXPECT_DOUBLE_EQ(cap_chord(square, 1.7), 2.0);
    EXPECT_DOUBLE_EQ(cap_chord(square, 3.0), 0.0);
    EXPECT_NEAR(cap_chord(annulus_cap({0, 0}, 5.0, 2.0, 4), 0.0), 2.0 * 3.0, 1e-12);
}

TEST(Transforms, QuarterTurnsAreExact) {
    TriangleMesh m;
    m.vertices = {{1, 2, 3}};
    EXPECT_EQ(rotated(m, {0, 0, 1}, 90.0).vertices[0], (Vec3d{-2, 1, 3}));
    EXPECT_EQ(rotated(m, {1, 0, 0}, 90.0).vertices[0], (Vec3d{1, -3, 2}));
    EXPECT_EQ(rotated(m, {0, 1, 0}, -270.0).vertices[0], (Vec3d{3, 2, -1}));
    EXPECT_EQ(rotated(m, {0, 0, 1}, 360.0).vertices[0], (Vec3d{1, 2, 3}));
    EXPECT_EQ(translated(m, {1, 1, 1}).vertices[0], (Vec3d{2, 3, 4}));
}

TEST(Transforms, RotationKeepsVolumeAndClosedness) {
    const TriangleMesh m = rotated(tube(5, 4, 7, 32), {1, 2, 3}, 33.3, {1, 1, 1});
    EXPECT_EQ(bad_edges(m), 0);
    EXPECT_NEAR(own_signed_volume(m), tube_volume(5, 4, 7, 32), 1e-9);
    const TriangleMesh back = rotated(m, {1, 2, 3}, -33.3, {1, 1, 1});
    const TriangleMesh orig = tube(5, 4, 7, 32);
    for (std::size_t i = 0; i < orig.vertices.size(); ++i) {
        EXPECT_NEAR(core::norm(back.vertices[i] - orig.vertices[i]), 0.0, 1e-12);
    }
}

TEST(Fixtures, TiltedCubeStandsOnAnEdge) {
    const TriangleMesh m = cube_tilted_45(10.0);
    int on_floor = 0;
    double top = 0.0;
    for (const Vec3d& p : m.vertices) {
        EXPECT_GE(p.z, 0.0);
        if (p.z == 0.0) ++on_floor;
        top = std::max(top, p.z);
    }
    EXPECT_EQ(on_floor, 2);
    EXPECT_NEAR(top, 10.0 * std::sqrt(2.0), 1e-12);
}

TEST(Fixtures, TShapeBarIsAboveTheStem) {
    const TSpec spec{};
    const TriangleMesh m = t_shape(spec);
    for (const Vec3d& p : m.vertices) {
        EXPECT_GE(p.y, 0.0);
        EXPECT_LE(p.y, spec.depth);
        if (p.z < spec.stem_height) {
            EXPECT_NEAR(std::abs(p.x - spec.bar_width / 2), spec.stem_width / 2, 1e-12);
        }
    }
    EXPECT_EQ(t_shape_area_at(spec, spec.stem_height), spec.bar_width * spec.depth);
}

TEST(Fixtures, NestedBoxesSectionsChangeAtTheShells) {
    const NestedSpec s{};
    const Fixture f = nested_boxes_fixture();
    EXPECT_EQ(f.shape_at(1.0), (SectionShape{1, 0, 0}));
    EXPECT_EQ(f.shape_at(4.0), (SectionShape{1, 1, 1}));
    EXPECT_EQ(f.shape_at(10.0), (SectionShape{2, 1, 2}));
    EXPECT_DOUBLE_EQ(f.area_at(10.0), 400.0 - 196.0 + 64.0);
    EXPECT_DOUBLE_EQ(f.area_at(s.size - s.wall), 400.0);
}

}  // namespace
}  // namespace maxslice::test
