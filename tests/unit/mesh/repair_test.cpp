#include "maxslice/mesh/repair.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "maxslice/core/tolerances.hpp"
#include "maxslice/mesh/validation.hpp"
#include "mesh_builders.hpp"

namespace maxslice::mesh {
namespace {

bool any_line_starts_with(const std::vector<std::string>& lines, const std::string& prefix) {
    return std::any_of(lines.begin(), lines.end(),
                       [&](const std::string& l) { return l.rfind(prefix, 0) == 0; });
}

void expect_clean_closed(const TriangleMesh& m, double volume) {
    const ValidationReport r = validate(m);
    EXPECT_TRUE(r.closed_manifold()) << ::testing::PrintToString(r.defects());
    EXPECT_TRUE(r.defects().empty()) << ::testing::PrintToString(r.defects());
    EXPECT_NEAR(r.volume_mm3, volume, 1e-9 * std::max(1.0, std::fabs(volume)));
    EXPECT_EQ(r.vertices, m.vertices.size());  // no unused vertices left
}

TEST(Repair, CleanMeshIsUnchanged) {
    TriangleMesh m = test::unit_cube();
    const TriangleMesh before = m;
    const RepairReport r = repair(m);
    EXPECT_FALSE(r.changed());
    EXPECT_TRUE(r.lines().empty());
    EXPECT_EQ(m.vertices, before.vertices);
    EXPECT_EQ(m.triangles, before.triangles);
}

TEST(Repair, SoupIsWeldedIntoTheCube) {
    TriangleMesh m = test::unwelded(test::unit_cube());
    const RepairReport r = repair(m);
    EXPECT_EQ(r.welded_vertices, 36u - 8u);
    EXPECT_NEAR(r.weld_distance_mm, core::kRepairWeldRelative * std::sqrt(3.0), 1e-15);
    EXPECT_EQ(m.vertices.size(), 8u);
    EXPECT_EQ(m.triangles.size(), 12u);
    EXPECT_TRUE(r.changed());
    EXPECT_TRUE(any_line_starts_with(r.lines(), "28 vertices welded")) << r.lines()[0];
    expect_clean_closed(m, 1.0);
}

TEST(Repair, CrackOfOneNanometreIsWelded) {
    TriangleMesh m = test::cube_with_crack(1e-9);
    ASSERT_GT(validate(m).boundary_edges.count, 0u);
    const RepairReport r = repair(m);
    EXPECT_EQ(r.welded_vertices, 1u);
    EXPECT_EQ(r.removed_unused_vertices, 0u);
    EXPECT_EQ(m.vertices.size(), 8u);
    expect_clean_closed(m, 1.0);
    // The lower index keeps its position: the corner is exactly at the origin again.
    EXPECT_EQ(bounding_box(m).min, (core::Vec3d{0, 0, 0}));
}

TEST(Repair, WeldDistanceOptionIsHonoured) {
    // A crack of 1e-3 mm is far beyond the default (1.7e-6 mm for a unit cube).
    TriangleMesh open = test::cube_with_crack(1e-3);
    const RepairReport defaults = repair(open);
    EXPECT_EQ(defaults.welded_vertices, 0u);
    EXPECT_GT(validate(open).boundary_edges.count, 0u);

    TriangleMesh closed = test::cube_with_crack(1e-3);
    const RepairReport wide = repair(closed, {.weld_distance_mm = 2e-3});
    EXPECT_EQ(wide.weld_distance_mm, 2e-3);
    EXPECT_EQ(wide.welded_vertices, 1u);
    expect_clean_closed(closed, 1.0);

    TriangleMesh none = test::unwelded(test::unit_cube());
    const RepairReport off = repair(none, {.weld_distance_mm = -1.0});
    EXPECT_EQ(off.welded_vertices, 0u);
    EXPECT_EQ(off.weld_distance_mm, 0.0);
    EXPECT_EQ(none.vertices.size(), 36u);
}

TEST(Repair, WeldChainsAndKeepsLowestIndex) {
    // Three points 0.6 apart along x with distance 1: 0-1 and 1-2 are close, 0-2 are not;
    // all three become vertex 0.
    TriangleMesh m;
    m.vertices = {{0, 0, 0}, {0.6, 0, 0}, {1.2, 0, 0}, {0, 10, 0}, {0, 0, 10}};
    m.triangles = {{0, 3, 4}, {1, 4, 3}, {2, 3, 4}};
    const RepairReport r = repair(m, {.weld_distance_mm = 1.0});
    EXPECT_EQ(r.welded_vertices, 2u);
    // All three triangles became one vertex set: the later two are duplicates.
    EXPECT_EQ(r.removed_duplicate_triangles, 2u);
    ASSERT_EQ(m.triangles.size(), 1u);
    EXPECT_EQ(m.vertices.size(), 3u);
    EXPECT_EQ(m.corner(0, 0), (core::Vec3d{0, 0, 0}));
}

TEST(Repair, DuplicateAndDegenerateFacesAreRemoved) {
    TriangleMesh m = test::unit_cube();
    const Triangle t = m.triangles[4];
    m.triangles.push_back(t);
    m.triangles.push_back({t[0], t[2], t[1]});
    const auto n = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.push_back({5, 5, 5});
    m.triangles.push_back({n, n, n});
    m.triangles.push_back({0, 0, 1});
    m.vertices.push_back({7, 7, 7});  // never used
    const ValidationReport before = validate(m);
    ASSERT_EQ(before.duplicate_triangles.count, 2u);
    ASSERT_EQ(before.degenerate_triangles.count, 2u);

    const RepairReport r = repair(m);
    EXPECT_EQ(r.removed_duplicate_triangles, 2u);
    EXPECT_EQ(r.removed_degenerate_triangles, 2u);
    EXPECT_EQ(r.split_triangles, 0u);
    EXPECT_EQ(r.removed_unused_vertices, 2u);
    EXPECT_TRUE(any_line_starts_with(r.lines(), "2 duplicate triangles removed"));
    EXPECT_TRUE(any_line_starts_with(r.lines(), "2 degenerate triangles removed"));
    EXPECT_TRUE(any_line_starts_with(r.lines(), "2 unused vertices removed"));
    expect_clean_closed(m, 1.0);
}

TEST(Repair, CollinearTriangleIsRemovedWithoutOpeningTheSurface) {
    // Put a vertex c in the middle of an edge a-b of the cube and fan one of the edge's two
    // triangles to it: the surface then has a zero-area triangle (a, b, c) but stays closed.
    TriangleMesh m = test::unit_cube();
    const Triangle t = m.triangles[0];
    const std::uint32_t a = t[0], b = t[1], x = t[2];
    const auto c = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.push_back((m.vertices[a] + m.vertices[b]) * 0.5);
    m.triangles[0] = {a, c, x};
    m.triangles.push_back({c, b, x});
    // (a, b, c) has zero area and closes the surface: a->b pairs with the other triangle on
    // the edge, b->c and c->a with the two halves of the fan.
    m.triangles.push_back({a, b, c});
    const ValidationReport before = validate(m);
    ASSERT_EQ(before.degenerate_triangles.count, 1u);
    ASSERT_TRUE(before.closed_manifold());
    const RepairReport r = repair(m);
    EXPECT_EQ(r.removed_degenerate_triangles, 1u);
    EXPECT_EQ(r.split_triangles, 1u);
    EXPECT_TRUE(any_line_starts_with(r.lines(), "1 degenerate triangle removed (1 neighbouring"));
    expect_clean_closed(m, 1.0);
    EXPECT_EQ(m.triangles.size(), 14u);  // one removed, one neighbour split in two
}

TEST(Repair, InsideOutCubeIsTurnedOutsideOut) {
    TriangleMesh m = test::inside_out_cube();
    ASSERT_TRUE(validate(m).inside_out());
    const RepairReport r = repair(m);
    EXPECT_EQ(r.inverted_shells, 1u);
    EXPECT_EQ(r.inverted_shell_triangles, 12u);
    EXPECT_EQ(r.reoriented_triangles, 0u);
    EXPECT_TRUE(any_line_starts_with(r.lines(), "1 inside-out shell turned outside out"));
    const ValidationReport after = validate(m);
    EXPECT_GT(after.volume_mm3, 0.0);
    EXPECT_FALSE(after.inside_out());
    expect_clean_closed(m, 1.0);
}

TEST(Repair, FlippedTrianglesFollowTheMajority) {
    for (std::size_t k = 0; k < 12; ++k) {
        TriangleMesh m = test::unit_cube();
        std::swap(m.triangles[k][0], m.triangles[k][1]);
        std::swap(m.triangles[(k + 5) % 12][0], m.triangles[(k + 5) % 12][1]);
        ASSERT_GT(validate(m).misoriented_edges.count, 0u);
        const RepairReport r = repair(m);
        EXPECT_EQ(r.reoriented_triangles, 2u) << k;
        EXPECT_EQ(r.inverted_shells, 0u);
        expect_clean_closed(m, 1.0);
    }
}

TEST(Repair, MostlyInsideOutCubeIsOrientedThenInverted) {
    TriangleMesh m = test::inside_out_cube();
    std::swap(m.triangles[3][0], m.triangles[3][1]);  // one triangle points out
    const RepairReport r = repair(m);
    EXPECT_EQ(r.reoriented_triangles, 1u);
    EXPECT_EQ(r.inverted_shells, 1u);
    expect_clean_closed(m, 1.0);
}

TEST(Repair, VoidInsideASolidStaysNegative) {
    // A 4 mm cube with a 1 mm cubic void: the void's surface faces inwards (negative volume)
    // and must stay so; the whole part is then inside out and is inverted, void included.
    TriangleMesh part = test::unit_cube();
    scale(part, 4.0);
    TriangleMesh cavity = test::moved(test::inside_out_cube(), 1.5, 1.5, 1.5);
    append(part, cavity);
    ASSERT_NEAR(signed_volume(part), 63.0, 1e-12);
    TriangleMesh ok = part;
    const RepairReport r = repair(ok);
    EXPECT_EQ(r.inverted_shells, 0u);
    EXPECT_FALSE(r.changed());
    EXPECT_NEAR(signed_volume(ok), 63.0, 1e-12);

    TriangleMesh flipped = part;
    for (Triangle& t : flipped.triangles) std::swap(t[1], t[2]);
    const RepairReport rf = repair(flipped);
    EXPECT_EQ(rf.inverted_shells, 1u);
    // The void turned positive with the rest; positive shells are never inverted.
    EXPECT_NEAR(signed_volume(flipped), 64.0 + 1.0, 1e-12);
}

TEST(Repair, SeparateInsideOutBodiesAreEachInverted) {
    TriangleMesh m = test::inside_out_cube();
    append(m, test::moved(test::unit_cube(), 3, 0, 0));
    append(m, test::moved(test::inside_out_cube(), 6, 0, 0));
    const RepairReport r = repair(m);
    EXPECT_EQ(r.inverted_shells, 2u);
    expect_clean_closed(m, 3.0);
    EXPECT_EQ(validate(m).bodies, 3u);
}

TEST(Repair, NonManifoldBodyIsNotReoriented) {
    TriangleMesh m = test::two_cubes_sharing_an_edge();
    for (std::size_t t = 12; t < 24; ++t) std::swap(m.triangles[t][1], m.triangles[t][2]);
    const TriangleMesh before = m;
    const RepairReport r = repair(m);
    EXPECT_EQ(r.unoriented_bodies, 1u);
    EXPECT_EQ(r.reoriented_triangles, 0u);
    EXPECT_EQ(r.inverted_shells, 0u);
    EXPECT_FALSE(r.changed());
    EXPECT_EQ(m.triangles, before.triangles);
    EXPECT_TRUE(any_line_starts_with(r.lines(), "1 body with non-manifold edges"));
}

TEST(Repair, OpenMeshIsOrientedButNotInverted) {
    TriangleMesh m = test::inside_out_cube();
    m.triangles.pop_back();
    std::swap(m.triangles[0][0], m.triangles[0][1]);
    const RepairReport r = repair(m);
    EXPECT_EQ(r.reoriented_triangles, 1u);
    EXPECT_EQ(r.inverted_shells, 0u);  // open: its volume sign means nothing
    const ValidationReport after = validate(m);
    EXPECT_EQ(after.misoriented_edges.count, 0u);
    EXPECT_EQ(after.boundary_edges.count, 3u);
}

TEST(Repair, NonFiniteTrianglesAreRemoved) {
    TriangleMesh m = test::unit_cube();
    const auto n = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.push_back({std::numeric_limits<double>::quiet_NaN(), 0, 0});
    m.triangles.push_back({0, 1, n});
    const RepairReport r = repair(m);
    EXPECT_EQ(r.removed_nonfinite_triangles, 1u);
    EXPECT_EQ(r.removed_unused_vertices, 1u);
    expect_clean_closed(m, 1.0);
}

TEST(Repair, RepairedMeshHasNothingLeftToRepair) {
    TriangleMesh m = test::unwelded(test::inside_out_cube());
    m.triangles.push_back(m.triangles[0]);
    (void)repair(m);
    const TriangleMesh once = m;
    const RepairReport again = repair(m);
    EXPECT_FALSE(again.changed()) << ::testing::PrintToString(again.lines());
    EXPECT_EQ(m.triangles, once.triangles);
    expect_clean_closed(m, 1.0);
}

}  // namespace
}  // namespace maxslice::mesh
