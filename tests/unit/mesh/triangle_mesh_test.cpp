#include "maxslice/mesh/triangle_mesh.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "mesh_builders.hpp"

namespace maxslice::mesh {
namespace {

using test::cube_soup;
using test::tetrahedron_soup;

TEST(WeldExact, CubeSoupBecomesEightVertices) {
    const std::vector<float> soup = cube_soup<float>();
    ASSERT_EQ(soup.size(), 12u * 9u);
    const TriangleMesh m = weld_exact(std::span<const float>(soup));
    EXPECT_EQ(m.triangles.size(), 12u);
    EXPECT_EQ(m.vertices.size(), 8u);
    const std::vector<double> soupd = cube_soup<double>();
    const TriangleMesh md = weld_exact(std::span<const double>(soupd));
    EXPECT_EQ(md.vertices.size(), 8u);
    EXPECT_EQ(md.triangles, m.triangles);
}

TEST(WeldExact, FirstOccurrenceOrderAndPositionsKept) {
    const std::vector<double> soup = tetrahedron_soup<double>();
    const TriangleMesh m = weld_exact(std::span<const double>(soup));
    ASSERT_EQ(m.vertices.size(), 4u);
    // Vertex k is the k-th distinct position met while reading the soup in order.
    std::vector<core::Vec3d> distinct;
    for (std::size_t c = 0; c < soup.size() / 3; ++c) {
        const core::Vec3d p{soup[3 * c], soup[3 * c + 1], soup[3 * c + 2]};
        if (std::find(distinct.begin(), distinct.end(), p) == distinct.end()) distinct.push_back(p);
    }
    EXPECT_EQ(m.vertices, distinct);
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const std::size_t c = 3 * t + static_cast<std::size_t>(k);
            EXPECT_EQ(m.corner(t, k), (core::Vec3d{soup[3 * c], soup[3 * c + 1], soup[3 * c + 2]}));
        }
    }
}

TEST(WeldExact, NegativeZeroIsZeroAndNearbyIsNot) {
    const std::vector<float> soup = {
        0.0f, 0.0f,  0.0f,  1.0f, 0.0f, 0.0f, 0.0f, 1.0f,
        0.0f, -0.0f, -0.0f, 0.0f, 0.0f, 1.0f, 0.0f, std::nextafter(1.0f, 2.0f),
        0.0f, 0.0f};
    const TriangleMesh m = weld_exact(std::span<const float>(soup));
    EXPECT_EQ(m.vertices.size(), 4u);
    EXPECT_EQ(m.triangles[1][0], m.triangles[0][0]);
    EXPECT_EQ(m.triangles[1][1], m.triangles[0][2]);
    EXPECT_FALSE(std::signbit(m.vertices[m.triangles[1][0]].x));
}

TEST(WeldExact, DegenerateTrianglesAreKept) {
    const std::vector<double> soup = {0, 0, 0, 1, 0, 0, 0, 0, 0, 2, 2, 2, 2, 2, 2, 2, 2, 2};
    const TriangleMesh m = weld_exact(std::span<const double>(soup));
    ASSERT_EQ(m.triangles.size(), 2u);
    EXPECT_EQ(m.vertices.size(), 3u);
    EXPECT_EQ(m.triangles[0][0], m.triangles[0][2]);
    EXPECT_EQ(m.triangles[1][0], m.triangles[1][1]);
}

TEST(WeldExact, ManyTrianglesGrowTheTableAndStayExact) {
    // A grid of quads as a soup: (n+1)^2 distinct points, far more than the first table size.
    constexpr int n = 300;
    std::vector<float> soup;
    auto put = [&](int i, int j) {
        soup.insert(soup.end(), {static_cast<float>(i) * 0.1f, static_cast<float>(j) * 0.1f,
                                 std::sin(static_cast<float>(i + j))});
    };
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            put(i, j), put(i + 1, j), put(i + 1, j + 1);
            put(i, j), put(i + 1, j + 1), put(i, j + 1);
        }
    }
    const TriangleMesh m = weld_exact(std::span<const float>(soup));
    EXPECT_EQ(m.triangles.size(), static_cast<std::size_t>(2 * n * n));
    EXPECT_EQ(m.vertices.size(), static_cast<std::size_t>((n + 1) * (n + 1)));
}

TEST(WeldExact, AllDistinctCornersGrowTheTable) {
    // A soup of 30000 triangles with no shared corner: the table, sized for a closed mesh,
    // has to grow several times, and every corner must keep its own position.
    std::vector<double> soup;
    for (int i = 0; i < 3 * 30000; ++i) {
        soup.insert(soup.end(), {0.5 * i, std::sqrt(static_cast<double>(i)), -1.0 * (i % 7)});
    }
    const TriangleMesh m = weld_exact(std::span<const double>(soup));
    ASSERT_EQ(m.vertices.size(), 90000u);
    for (std::size_t c = 0; c < 90000; ++c) {
        EXPECT_EQ(m.triangles[c / 3][c % 3], c);
        EXPECT_EQ(m.vertices[c].y, soup[3 * c + 1]);
    }
    // Welding the same soup twice over gives the same vertices, each used twice.
    std::vector<double> twice = soup;
    twice.insert(twice.end(), soup.begin(), soup.end());
    const TriangleMesh m2 = weld_exact(std::span<const double>(twice));
    EXPECT_EQ(m2.vertices, m.vertices);
    EXPECT_EQ(m2.triangles[30000], m2.triangles[0]);
}

TEST(BlockWelder, BlocksGiveTheWeldOfTheWholeSoup) {
    // A grid soup whose second half repeats corners of the first and whose table grows in
    // the middle of a block: any block split must give weld_exact's mesh, index for index.
    std::vector<float> soup;
    auto put = [&](int i, int j) {
        soup.insert(soup.end(), {static_cast<float>(i) * 0.25f, static_cast<float>(j) * 0.5f,
                                 i % 3 == 0 ? -0.0f : std::cos(static_cast<float>(i * j))});
    };
    constexpr int n = 70;
    for (int pass = 0; pass < 2; ++pass) {
        for (int i = 0; i < n; ++i) {
            for (int j = 0; j < n; ++j) {
                if (pass == 1 && (i + j) % 2 == 0) continue;
                put(i, j), put(i + 1, j), put(i + 1, j + 1);
                put(i, j + 1), put(i, j), put(i + 1, j + 1);
            }
        }
    }
    const std::size_t tris = soup.size() / 9;
    const TriangleMesh whole = weld_exact(std::span<const float>(soup));
    for (const std::size_t block : {std::size_t{1}, std::size_t{7}, std::size_t{4096}, tris}) {
        BlockWelder welder(tris);
        for (std::size_t first = 0; first < tris; first += block) {
            const std::size_t count = std::min(block, tris - first);
            welder.add(std::span<const float>(soup).subspan(9 * first, 9 * count));
        }
        const TriangleMesh m = std::move(welder).finish();
        EXPECT_EQ(m.vertices, whole.vertices) << "blocks of " << block;
        EXPECT_EQ(m.triangles, whole.triangles) << "blocks of " << block;
    }
    EXPECT_EQ(whole.vertices.size(), static_cast<std::size_t>((n + 1) * (n + 1)));

    // Fewer triangles than announced: the mesh of those added.
    BlockWelder partial(tris);
    partial.add(std::span<const float>(soup).first(9 * 10));
    const TriangleMesh first_ten = std::move(partial).finish();
    EXPECT_EQ(first_ten.triangles,
              std::vector<Triangle>(whole.triangles.begin(), whole.triangles.begin() + 10));

    // No triangles announced and an empty block: an empty mesh.
    BlockWelder none(0);
    none.add({});
    const TriangleMesh nothing = std::move(none).finish();
    EXPECT_TRUE(nothing.triangles.empty());
    EXPECT_TRUE(nothing.vertices.empty());
}

TEST(Measures, UnitCubeVolumeAreaAndBox) {
    const TriangleMesh m = test::unit_cube();
    EXPECT_NEAR(signed_volume(m), 1.0, 1e-12);
    EXPECT_NEAR(surface_area(m), 6.0, 1e-12);
    const core::Box3d b = bounding_box(m);
    EXPECT_EQ(b.min, (core::Vec3d{0, 0, 0}));
    EXPECT_EQ(b.max, (core::Vec3d{1, 1, 1}));
}

TEST(Measures, BoundingBoxIgnoresUnusedVertices) {
    TriangleMesh m = test::unit_cube();
    m.vertices.push_back({100, -100, 5});
    const core::Box3d b = bounding_box(m);
    EXPECT_EQ(b.max, (core::Vec3d{1, 1, 1}));
    EXPECT_TRUE(bounding_box(TriangleMesh{}).empty());
}

TEST(Measures, AreaVectorIsTwiceTheAreaAlongTheNormal) {
    const TriangleMesh m = test::unit_cube();
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const core::Vec3d n = area_vector(m, t);
        EXPECT_NEAR(core::norm(n), 1.0, 1e-12);
        // Outward: from the cube centre towards the triangle.
        const core::Vec3d c = (m.corner(t, 0) + m.corner(t, 1) + m.corner(t, 2)) / 3.0;
        EXPECT_GT(core::dot(n, c - core::Vec3d{0.5, 0.5, 0.5}), 0.0);
    }
}

TEST(Measures, InsideOutCubeHasNegativeVolume) {
    TriangleMesh m = test::unit_cube();
    for (Triangle& t : m.triangles) std::swap(t[0], t[1]);
    EXPECT_NEAR(signed_volume(m), -1.0, 1e-12);
}

TEST(Measures, VolumeIndependentOfPlacement) {
    TriangleMesh m = test::unit_cube();
    transform(m, {1, 0, 0, 1e4, 0, 1, 0, -3e4, 0, 0, 1, 7e3});
    EXPECT_NEAR(signed_volume(m), 1.0, 1e-9);
}

TEST(Transforms, ScaleMultipliesVolumeByCube) {
    TriangleMesh m = test::unit_cube();
    scale(m, 25.4);
    EXPECT_NEAR(signed_volume(m), 25.4 * 25.4 * 25.4, 1e-9);
    EXPECT_NEAR(surface_area(m), 6 * 25.4 * 25.4, 1e-9);
}

TEST(Transforms, RotationAndTranslationKeepVolume) {
    TriangleMesh m = test::unit_cube();
    const double c = std::cos(0.3), s = std::sin(0.3);
    transform(m, {c, -s, 0, 10, s, c, 0, 20, 0, 0, 1, 30});
    EXPECT_NEAR(signed_volume(m), 1.0, 1e-12);
    const core::Box3d b = bounding_box(m);
    EXPECT_NEAR(b.min.z, 30.0, 1e-12);
    EXPECT_NEAR(b.max.z, 31.0, 1e-12);
}

TEST(Transforms, NonUniformScaleMultipliesVolumeByDeterminant) {
    TriangleMesh m = test::unit_cube();
    transform(m, {2, 0, 0, 0, 0, 3, 0, 0, 0, 0, 0.5, 0});
    EXPECT_NEAR(signed_volume(m), 3.0, 1e-12);
}

TEST(Transforms, MirrorKeepsPositiveVolume) {
    TriangleMesh m = test::unit_cube();
    transform(m, {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0});
    EXPECT_NEAR(signed_volume(m), 1.0, 1e-12);
    EXPECT_NEAR(bounding_box(m).min.x, -1.0, 1e-12);
}

TEST(Transforms, AppendKeepsBothAndOffsetsIndices) {
    TriangleMesh a = test::unit_cube();
    TriangleMesh b = test::unit_cube();
    transform(b, {1, 0, 0, 5, 0, 1, 0, 0, 0, 0, 1, 0});
    append(a, b);
    EXPECT_EQ(a.triangles.size(), 24u);
    EXPECT_EQ(a.vertices.size(), 16u);
    EXPECT_NEAR(signed_volume(a), 2.0, 1e-12);
    EXPECT_EQ(bounding_box(a).max.x, 6.0);
}

}  // namespace
}  // namespace maxslice::mesh
