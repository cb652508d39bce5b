#include "maxslice/mesh/validation.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "maxslice/core/tolerances.hpp"
#include "mesh_builders.hpp"

namespace maxslice::mesh {
namespace {

std::size_t defect_kinds(const ValidationReport& r) {
    std::size_t n = 0;
    for (const DefectCount* d :
         {&r.nonfinite_vertices, &r.degenerate_triangles, &r.duplicate_triangles, &r.boundary_edges,
          &r.nonmanifold_edges, &r.misoriented_edges}) {
        n += d->count > 0 ? 1 : 0;
    }
    return n + (r.inside_out() ? 1 : 0);
}

void expect_clean(const ValidationReport& r) {
    EXPECT_EQ(r.nonfinite_vertices.count, 0u);
    EXPECT_EQ(r.degenerate_triangles.count, 0u);
    EXPECT_EQ(r.duplicate_triangles.count, 0u);
    EXPECT_EQ(r.boundary_edges.count, 0u);
    EXPECT_EQ(r.nonmanifold_edges.count, 0u);
    EXPECT_EQ(r.misoriented_edges.count, 0u);
    EXPECT_TRUE(r.closed_manifold());
    EXPECT_FALSE(r.inside_out());
    EXPECT_TRUE(r.defects().empty());
}

// True when p is the midpoint of one of the edges of triangle t.
bool is_edge_midpoint_of(const TriangleMesh& m, std::size_t t, const core::Vec3d& p) {
    for (int k = 0; k < 3; ++k) {
        const core::Vec3d mid = (m.corner(t, k) + m.corner(t, (k + 1) % 3)) * 0.5;
        if (core::norm(mid - p) < 1e-12) return true;
    }
    return false;
}

// True when one of the report's lines contains text.
bool has_line(const ValidationReport& r, const std::string& text) {
    const auto lines = r.defects();
    return std::any_of(lines.begin(), lines.end(),
                       [&](const std::string& l) { return l.find(text) != std::string::npos; });
}

TEST(Validate, ClosedCube) {
    const TriangleMesh m = test::unit_cube();
    const ValidationReport r = validate(m);
    EXPECT_EQ(r.triangles, 12u);
    EXPECT_EQ(r.vertices, 8u);
    EXPECT_EQ(r.bodies, 1u);
    EXPECT_NEAR(r.volume_mm3, 1.0, 1e-12);
    EXPECT_NEAR(r.area_mm2, 6.0, 1e-12);
    EXPECT_EQ(r.bounding_box.max, (core::Vec3d{1, 1, 1}));
    expect_clean(r);
}

TEST(Validate, ClosedTetrahedronAndBipyramid) {
    const ValidationReport t = validate(test::tetrahedron());
    EXPECT_EQ(t.vertices, 4u);
    EXPECT_NEAR(t.volume_mm3, 1.0 / 6.0, 1e-12);
    expect_clean(t);
    // The apexes carry long edge lists (the sort path of the edge pass).
    const int n = 200;
    const ValidationReport b = validate(test::bipyramid(n));
    EXPECT_EQ(b.triangles, static_cast<std::size_t>(2 * n));
    const double polygon_area = 0.5 * n * std::sin(2.0 * 3.14159265358979323846 / n);
    EXPECT_NEAR(b.volume_mm3, 2.0 * polygon_area / 3.0, 1e-9);
    expect_clean(b);
}

TEST(Validate, EmptyMesh) {
    const ValidationReport r = validate(TriangleMesh{});
    EXPECT_EQ(r.triangles, 0u);
    EXPECT_EQ(r.bodies, 0u);
    EXPECT_TRUE(r.bounding_box.empty());
    ASSERT_EQ(r.defects().size(), 1u);
}

TEST(Validate, UnusedVerticesAreNotCounted) {
    TriangleMesh m = test::unit_cube();
    m.vertices.push_back({50, 50, 50});
    m.vertices.push_back({std::nan(""), 0, 0});
    const ValidationReport r = validate(m);
    EXPECT_EQ(r.vertices, 8u);
    EXPECT_EQ(r.bodies, 1u);
    EXPECT_EQ(r.bounding_box.max, (core::Vec3d{1, 1, 1}));
    expect_clean(r);
}

TEST(Validate, SoupHasOneBodyPerTriangleAndOnlyBoundaryEdges) {
    const TriangleMesh m = test::unwelded(test::unit_cube());
    const ValidationReport r = validate(m);
    EXPECT_EQ(r.bodies, 12u);
    EXPECT_EQ(r.vertices, 36u);
    EXPECT_EQ(r.boundary_edges.count, 36u);
    EXPECT_EQ(r.nonmanifold_edges.count, 0u);
    EXPECT_FALSE(r.closed_manifold());
    EXPECT_NEAR(r.volume_mm3, 1.0, 1e-12);  // the soup is still a closed surface geometrically
}

TEST(Validate, TwoSeparateCubesAreTwoBodies) {
    TriangleMesh m = test::unit_cube();
    append(m, test::moved(test::unit_cube(), 3, 0, 0));
    const ValidationReport r = validate(m);
    EXPECT_EQ(r.bodies, 2u);
    EXPECT_NEAR(r.volume_mm3, 2.0, 1e-12);
    expect_clean(r);
}

TEST(Validate, MissingTriangleGivesThreeBoundaryEdgesOnIt) {
    for (std::size_t removed = 0; removed < 12; ++removed) {
        const TriangleMesh full = test::unit_cube();
        TriangleMesh m = full;
        m.triangles.erase(m.triangles.begin() + static_cast<std::ptrdiff_t>(removed));
        const ValidationReport r = validate(m);
        EXPECT_EQ(r.boundary_edges.count, 3u);
        ASSERT_TRUE(r.boundary_edges.example.has_value());
        EXPECT_TRUE(is_edge_midpoint_of(full, removed, *r.boundary_edges.example));
        EXPECT_EQ(r.nonmanifold_edges.count, 0u);
        EXPECT_EQ(r.misoriented_edges.count, 0u);
        EXPECT_FALSE(r.closed_manifold());
        EXPECT_FALSE(r.inside_out());
        ASSERT_EQ(r.defects().size(), 1u);
        EXPECT_EQ(r.defects()[0].rfind("3 open (boundary) edges", 0), 0u) << r.defects()[0];
    }
}

TEST(Validate, TwoCubesSharingAnEdge) {
    const ValidationReport r = validate(test::two_cubes_sharing_an_edge());
    EXPECT_EQ(r.bodies, 1u);
    EXPECT_EQ(r.vertices, 14u);
    EXPECT_EQ(r.boundary_edges.count, 0u);
    EXPECT_EQ(r.nonmanifold_edges.count, 1u);
    // Four triangles on the edge: each direction is used twice.
    EXPECT_EQ(r.misoriented_edges.count, 2u);
    ASSERT_TRUE(r.nonmanifold_edges.example.has_value());
    EXPECT_EQ(*r.nonmanifold_edges.example, (core::Vec3d{1, 1, 0.5}));
    EXPECT_NEAR(r.volume_mm3, 2.0, 1e-12);
    EXPECT_FALSE(r.closed_manifold());
}

TEST(Validate, TouchingClosedBodiesAreClosedWhereOrientationIsBalanced) {
    // On the shared edge each direction is used twice: misoriented for a manifold, but the
    // balance of a union of closed, consistently oriented bodies.
    const ValidationReport r = validate(test::two_cubes_sharing_an_edge());
    EXPECT_EQ(r.unbalanced_edges.count, 0u);
    EXPECT_TRUE(r.closed());
    EXPECT_FALSE(r.closed_manifold());
    EXPECT_TRUE(has_line(r, "closed bodies touch"));
}

TEST(Validate, AFlippedTriangleIsUnbalancedEvenWhereBodiesTouch) {
    TriangleMesh m = test::unit_cube();
    std::swap(m.triangles[5][0], m.triangles[5][1]);
    const ValidationReport r = validate(m);
    EXPECT_EQ(r.unbalanced_edges.count, 3u);
    EXPECT_FALSE(r.closed());
    TriangleMesh touching = test::two_cubes_sharing_an_edge();
    for (std::size_t t = 0; t < touching.triangles.size(); ++t) {
        TriangleMesh one = touching;
        std::swap(one.triangles[t][0], one.triangles[t][1]);
        const ValidationReport f = validate(one);
        EXPECT_GT(f.unbalanced_edges.count, 0u) << "triangle " << t;
        EXPECT_FALSE(f.closed());
        EXPECT_FALSE(has_line(f, "closed bodies touch"));
    }
}

// Two unit cubes welded along a shared face x = 1 (four triangles on each of its edges);
// the second one reversed when `flip_second`.
TriangleMesh two_cubes_sharing_a_face(bool flip_second) {
    std::vector<double> soup = test::cube_soup<double>();
    std::vector<double> other = test::cube_soup<double>();
    for (std::size_t i = 0; i < other.size(); i += 3) other[i] += 1.0;
    if (flip_second) {
        for (std::size_t t = 0; t < other.size(); t += 9) {
            for (std::size_t c = 0; c < 3; ++c) std::swap(other[t + 3 + c], other[t + 6 + c]);
        }
    }
    soup.insert(soup.end(), other.begin(), other.end());
    return weld_exact(std::span<const double>(soup));
}

TEST(Validate, ATouchingBodyThatFacesInwardsIsFound) {
    const ValidationReport ok = validate(two_cubes_sharing_a_face(false));
    EXPECT_GT(ok.nonmanifold_edges.count, 0u);
    EXPECT_EQ(ok.unbalanced_edges.count, 0u);
    EXPECT_EQ(ok.inward_pieces.count, 0u);
    EXPECT_NEAR(ok.volume_mm3, 2.0, 1e-12);
    const ValidationReport flipped = validate(two_cubes_sharing_a_face(true));
    EXPECT_EQ(flipped.unbalanced_edges.count, 0u) << "a reversed closed body is still balanced";
    EXPECT_NEAR(flipped.volume_mm3, 0.0, 1e-12);
    EXPECT_GE(flipped.inward_pieces.count, 1u);
    ASSERT_TRUE(flipped.inward_pieces.example.has_value());
    EXPECT_GT(flipped.inward_pieces.example->x, 1.0);  // on the reversed cube
    EXPECT_TRUE(has_line(flipped, "inside is empty"));
    EXPECT_FALSE(has_line(flipped, "are sliced as one solid"));
    // The cubes sharing an edge: nothing faces inwards.
    EXPECT_EQ(validate(test::two_cubes_sharing_an_edge()).inward_pieces.count, 0u);
}

TEST(Validate, AFlatMeshIsFlatNotAnInsideOutTouchingBody) {
    // A square written on both sides (four triangles, its diagonal shared by all four): it
    // encloses nothing. It used to be reported as pieces of a touching body facing inwards.
    // Once in the plane z = 0 and once tilted out of every axis plane.
    for (const bool tilted : {false, true}) {
        TriangleMesh m;
        m.vertices = {{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}};
        if (tilted) {
            for (core::Vec3d& v : m.vertices) v = {v.x, 0.6 * v.y, 0.8 * v.y + 0.3 * v.x};
        }
        m.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 2, 1}, {0, 3, 2}};
        const ValidationReport r = validate(m);
        EXPECT_TRUE(r.flat) << "tilted " << tilted;
        EXPECT_EQ(r.inward_pieces.count, 0u);
        EXPECT_EQ(r.inside_out_shells.count, 0u);
        EXPECT_TRUE(has_line(r, "the mesh is flat")) << "tilted " << tilted;
        EXPECT_FALSE(has_line(r, "inwards"));
        EXPECT_FALSE(has_line(r, "inside out"));
    }
    EXPECT_FALSE(validate(test::unit_cube()).flat);
    // Zero net volume is not flatness: the touching cube that faces inwards is still found.
    const ValidationReport flipped = validate(two_cubes_sharing_a_face(true));
    EXPECT_FALSE(flipped.flat);
    EXPECT_GE(flipped.inward_pieces.count, 1u);
}

TEST(Validate, AnInsideOutBodyBesideAnotherIsFoundButAVoidIsNot) {
    TriangleMesh apart = test::unit_cube();
    append(apart, test::moved(test::inside_out_cube(), 3, 0, 0));
    const ValidationReport r = validate(apart);
    EXPECT_TRUE(r.closed_manifold());
    EXPECT_EQ(r.inside_out_shells.count, 1u);
    ASSERT_TRUE(r.inside_out_shells.example.has_value());
    EXPECT_GE(r.inside_out_shells.example->x, 3.0);  // on the flipped cube
    EXPECT_TRUE(has_line(r, "1 closed shell is inside out"));

    // A 4 mm cube with a 1 mm cubic void: the void faces inwards and is right.
    TriangleMesh hollow = test::unit_cube();
    scale(hollow, 4.0);
    append(hollow, test::moved(test::inside_out_cube(), 1.5, 1.5, 1.5));
    EXPECT_EQ(validate(hollow).inside_out_shells.count, 0u);
    // Both separate cubes inside out: each one is found.
    TriangleMesh both = test::inside_out_cube();
    append(both, test::moved(test::inside_out_cube(), 3, 0, 0));
    EXPECT_EQ(validate(both).inside_out_shells.count, 2u);
}

TEST(Validate, InsideOutCube) {
    const ValidationReport r = validate(test::inside_out_cube());
    EXPECT_NEAR(r.volume_mm3, -1.0, 1e-12);
    EXPECT_TRUE(r.closed_manifold());
    EXPECT_TRUE(r.inside_out());
    ASSERT_EQ(r.defects().size(), 1u);
    EXPECT_NE(r.defects()[0].find("inside out"), std::string::npos);
}

TEST(Validate, OneFlippedTriangleGivesThreeMisorientedEdges) {
    TriangleMesh m = test::unit_cube();
    std::swap(m.triangles[5][0], m.triangles[5][1]);
    const ValidationReport r = validate(m);
    EXPECT_EQ(r.misoriented_edges.count, 3u);
    ASSERT_TRUE(r.misoriented_edges.example.has_value());
    EXPECT_TRUE(is_edge_midpoint_of(m, 5, *r.misoriented_edges.example));
    EXPECT_EQ(r.boundary_edges.count, 0u);
    EXPECT_EQ(r.nonmanifold_edges.count, 0u);
    EXPECT_FALSE(r.closed_manifold());
    EXPECT_FALSE(r.inside_out());
}

TEST(Validate, DuplicateTrianglesInEitherOrientation) {
    TriangleMesh m = test::unit_cube();
    const Triangle t = m.triangles[3];
    m.triangles.push_back(t);                   // same
    m.triangles.push_back({t[1], t[2], t[0]});  // same, rotated
    m.triangles.push_back({t[0], t[2], t[1]});  // reversed
    const ValidationReport r = validate(m);
    EXPECT_EQ(r.duplicate_triangles.count, 3u);
    ASSERT_TRUE(r.duplicate_triangles.example.has_value());
    const core::Vec3d c = (m.corner(3, 0) + m.corner(3, 1) + m.corner(3, 2)) / 3.0;
    EXPECT_LT(core::norm(*r.duplicate_triangles.example - c), 1e-12);
    // Each of its three edges is now used five times.
    EXPECT_EQ(r.nonmanifold_edges.count, 3u);
    EXPECT_EQ(r.degenerate_triangles.count, 0u);
}

TEST(Validate, DegenerateTriangles) {
    TriangleMesh m = test::unit_cube();
    const auto n = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.push_back({0.5, 0, 0});             // on the edge (0,0,0)-(1,0,0)
    m.vertices.push_back({0.25, 0, 0});            // also on it
    m.vertices.push_back({3, 3, 3});               // a lone point
    m.triangles.push_back({n, n + 1, 0});          // collinear, distinct indices
    m.triangles.push_back({n + 2, n + 2, n + 2});  // one index three times
    m.triangles.push_back({0, 1, 0});              // repeated index
    const ValidationReport r = validate(m);
    EXPECT_EQ(r.degenerate_triangles.count, 3u);
    ASSERT_TRUE(r.degenerate_triangles.example.has_value());
    EXPECT_LT(core::norm(*r.degenerate_triangles.example - core::Vec3d{0.25, 0, 0}), 1e-12);
    EXPECT_EQ(r.bodies, 2u);
}

TEST(Validate, DegenerateTestIsRelativeToTriangleSize) {
    // Well-shaped triangles whose area is below the absolute threshold (a part in metres
    // scaled down further) are not degenerate; needles are, at any size.
    const double s = 1e-7;  // area 5e-15 < kDegenerateTriangleAreaMm2
    ASSERT_LT(0.5 * s * s, core::kDegenerateTriangleAreaMm2);
    EXPECT_FALSE(is_degenerate({0, 0, 0}, {s, 0, 0}, {0, s, 0}));
    TriangleMesh tiny = test::unit_cube();
    scale(tiny, s);
    const ValidationReport r = validate(tiny);
    EXPECT_EQ(r.degenerate_triangles.count, 0u);
    EXPECT_NEAR(r.volume_mm3, s * s * s, 1e-30);
    // A needle: 1 m long, 1e-10 mm off the line (relative height 1e-13).
    EXPECT_TRUE(is_degenerate({0, 0, 0}, {1000, 0, 0}, {500, 1e-10, 0}));
    EXPECT_FALSE(is_degenerate({0, 0, 0}, {1000, 0, 0}, {500, 1e-3, 0}));
    EXPECT_TRUE(is_degenerate({1, 2, 3}, {1, 2, 3}, {1, 2, 3}));
    EXPECT_FALSE(is_degenerate({0, 0, 0}, {1, 0, 0}, {0, std::nan(""), 0}));
}

TEST(Validate, NonFiniteVertex) {
    TriangleMesh m = test::unit_cube();
    m.vertices[7] = {std::numeric_limits<double>::infinity(), 1, 1};
    const ValidationReport r = validate(m);
    EXPECT_EQ(r.nonfinite_vertices.count, 1u);
    ASSERT_TRUE(r.nonfinite_vertices.example.has_value());
    EXPECT_TRUE(core::is_finite(*r.nonfinite_vertices.example));
    EXPECT_TRUE(core::is_finite(r.bounding_box.max));
    EXPECT_EQ(r.degenerate_triangles.count, 0u);
}

TEST(Validate, CrackOfOneNanometreIsOpen) {
    const ValidationReport r = validate(test::cube_with_crack(1e-9));
    EXPECT_GT(r.boundary_edges.count, 0u);
    EXPECT_FALSE(r.closed_manifold());
    EXPECT_EQ(r.nonmanifold_edges.count, 0u);
}

TEST(Validate, DefectsGiveOneLinePerKindWithCountAndPlace) {
    TriangleMesh m = test::two_cubes_sharing_an_edge();
    m.triangles.pop_back();
    m.triangles.push_back(m.triangles.front());
    const ValidationReport r = validate(m);
    const std::vector<std::string> lines = r.defects();
    EXPECT_EQ(lines.size(), defect_kinds(r));
    EXPECT_GE(lines.size(), 3u);
    for (const std::string& line : lines) {
        EXPECT_TRUE(std::isdigit(static_cast<unsigned char>(line[0]))) << line;
        EXPECT_NE(line.find("e.g. near ("), std::string::npos) << line;
    }
    const std::string first = std::to_string(r.duplicate_triangles.count) + " duplicate";
    EXPECT_TRUE(std::any_of(lines.begin(), lines.end(),
                            [&](const std::string& l) { return l.rfind(first, 0) == 0; }));
}

TEST(Validate, SameResultWithOneThreadOrMany) {
    // A larger mesh with defects spread over it: many bodies, some open, some duplicated.
    TriangleMesh m;
    for (int i = 0; i < 3000; ++i) {
        TriangleMesh b = test::bipyramid(8 + i % 5);
        if (i % 7 == 0) b.triangles.pop_back();
        if (i % 11 == 0) b.triangles.push_back(b.triangles[2]);
        if (i % 13 == 0) std::swap(b.triangles[1][1], b.triangles[1][2]);
        append(m, test::moved(b, 3.0 * (i % 60), 3.0 * (i / 60), 0));
    }
    ValidationReport one;
    tbb::task_arena(1).execute([&] { one = validate(m); });
    const ValidationReport many = validate(m);
    EXPECT_EQ(one.bodies, 3000u);
    EXPECT_EQ(one.bodies, many.bodies);
    EXPECT_EQ(one.boundary_edges.count, many.boundary_edges.count);
    EXPECT_EQ(one.boundary_edges.example, many.boundary_edges.example);
    EXPECT_EQ(one.duplicate_triangles.count, many.duplicate_triangles.count);
    EXPECT_EQ(one.duplicate_triangles.example, many.duplicate_triangles.example);
    EXPECT_EQ(one.misoriented_edges.count, many.misoriented_edges.count);
    EXPECT_EQ(one.misoriented_edges.example, many.misoriented_edges.example);
    EXPECT_EQ(one.volume_mm3, many.volume_mm3);  // bit-identical
    EXPECT_EQ(many.volume_mm3, signed_volume(m));
    EXPECT_EQ(many.area_mm2, surface_area(m));
    EXPECT_EQ(one.area_mm2, many.area_mm2);
    EXPECT_EQ(one.defects(), many.defects());
    // 3000/7 -> 429 bodies lose a triangle (3 open edges each).
    EXPECT_EQ(one.boundary_edges.count, 3u * 429u);
    EXPECT_EQ(one.duplicate_triangles.count, 273u);
}

}  // namespace
}  // namespace maxslice::mesh
