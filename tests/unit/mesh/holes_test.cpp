#include "maxslice/mesh/holes.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "maxslice/mesh/validation.hpp"
#include "support/fixtures.hpp"

namespace maxslice::mesh {
namespace {

// `m` without the triangles whose corners all satisfy `drop` (a face taken out: a hole).
template <class Drop>
TriangleMesh without(const TriangleMesh& m, Drop drop) {
    TriangleMesh out = m;
    std::erase_if(out.triangles, [&](const Triangle& t) {
        return std::all_of(t.begin(), t.end(),
                           [&](std::uint32_t v) { return drop(m.vertices[v]); });
    });
    return out;
}

TEST(CapHoles, AClosedMeshComesBackUnchanged) {
    const TriangleMesh box = test::box({0, 0, 0}, {3, 4, 5});
    const CappedMesh c = cap_holes(box);
    EXPECT_EQ(c.open_edges, 0u);
    EXPECT_EQ(c.caps, 0u);
    EXPECT_EQ(c.mesh.vertices, box.vertices);
    EXPECT_EQ(c.mesh.triangles, box.triangles);
}

TEST(CapHoles, EachHoleOfABoxIsClosedAndTheVolumeIsTheBoxs) {
    const TriangleMesh box = test::box({0, 0, 0}, {3, 4, 5});
    // The top face out (one hole), then the bottom too (two holes apart).
    const TriangleMesh one = without(box, [](const core::Vec3d& p) { return p.z == 5.0; });
    const TriangleMesh two = without(one, [](const core::Vec3d& p) { return p.z == 0.0; });
    const std::pair<const TriangleMesh*, std::size_t> cases[] = {{&one, 1}, {&two, 2}};
    for (const auto& [open, holes] : cases) {
        ASSERT_GT(validate(*open).boundary_edges.count, 0u);
        const CappedMesh c = cap_holes(*open);
        EXPECT_EQ(c.caps, holes);
        EXPECT_EQ(c.open_edges, validate(*open).boundary_edges.count);
        EXPECT_EQ(c.mesh.vertices.size(), open->vertices.size() + holes);
        EXPECT_EQ(c.mesh.triangles.size(), open->triangles.size() + c.open_edges);
        // The input's triangles keep their place; the caps come after them.
        EXPECT_TRUE(
            std::equal(open->triangles.begin(), open->triangles.end(), c.mesh.triangles.begin()));
        const ValidationReport v = validate(c.mesh);
        EXPECT_TRUE(v.closed_manifold()) << testing::PrintToString(v.defects());
        EXPECT_EQ(v.misoriented_edges.count, 0u);
        EXPECT_NEAR(v.volume_mm3, 60.0, 1e-9);  // flat rims: the caps are the faces taken out
    }
}

}  // namespace
}  // namespace maxslice::mesh
