// 3MF files built in the test: a zip of stored (uncompressed) entries holding the three
// parts lib3mf needs, with a model whose components nest.

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "io_test_support.hpp"
#include "maxslice/io/read_mesh.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"
#include "support/three_mf_package.hpp"

namespace maxslice::io {
namespace {

using test::contains;
using test::joined;
using test::ScratchDir;

std::string three_mf(std::string_view resources, std::string_view build) {
    return maxslice::test::three_mf_package(
        fmt::format(R"(<?xml version="1.0" encoding="UTF-8"?><model unit="millimeter" )"
                    R"(xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02">)"
                    R"(<resources>{}</resources><build>{}</build></model>)",
                    resources, build));
}

// Object 1 is a unit tetrahedron (volume 1/6, outward); objects 2 .. levels + 1 each place
// the one below twice, the second copy moved along x by twice the first's width, so that
// no copies overlap. The build places the top once.
std::string nested_tetrahedra(int levels, std::string_view leaf_type = "model",
                              std::string_view before = {}) {
    std::string resources =
        std::string(before) +
        fmt::format(R"(<object id="1" type="{}"><mesh><vertices>)", leaf_type) +
        R"(<vertex x="0" y="0" z="0"/><vertex x="1" y="0" z="0"/>)"
        R"(<vertex x="0" y="1" z="0"/><vertex x="0" y="0" z="1"/></vertices><triangles>)"
        R"(<triangle v1="0" v2="2" v3="1"/><triangle v1="0" v2="1" v3="3"/>)"
        R"(<triangle v1="1" v2="2" v3="3"/><triangle v1="0" v2="3" v3="2"/>)"
        R"(</triangles></mesh></object>)";
    double width = 1.0;
    for (int i = 2; i <= levels + 1; ++i) {
        resources +=
            fmt::format(R"(<object id="{}" type="model"><components><component objectid="{}"/>)"
                        R"(<component objectid="{}" transform="1 0 0 0 1 0 0 0 1 {} 0 0"/>)"
                        R"(</components></object>)",
                        i, i - 1, i - 1, 2.0 * width);
        width = 3.0 * width;
    }
    return three_mf(resources, fmt::format(R"(<item objectid="{}"/>)", levels + 1));
}

TEST(ThreeMf, NestedComponentsArePlacedOncePerPath) {
    ScratchDir dir;
    const int levels = 6;
    auto r = read_mesh(dir.write("nested.3mf", nested_tetrahedra(levels)));
    ASSERT_TRUE(r) << r.error().describe();
    const std::size_t copies = std::size_t{1} << levels;
    EXPECT_EQ(r->format, Format::k3mf);
    EXPECT_EQ(r->solids, copies);
    EXPECT_EQ(r->mesh.triangles.size(), 4 * copies);
    EXPECT_NEAR(mesh::signed_volume(r->mesh), static_cast<double>(copies) / 6.0, 1e-9);
}

TEST(ThreeMf, ExponentialComponentTreeIsRefusedNamingTheCount) {
    // 30 levels that each place the next twice: a 6 KB file (stored, not compressed) that
    // expands to 2^30 tetrahedra. It is refused before anything is placed and before lib3mf
    // reads it (the reader used to copy its growing soup once per placement, and lib3mf
    // walks every path of the tree while it reads), with the expanded count and the limit.
    ScratchDir dir;
    const int levels = 30;
    const std::string file = nested_tetrahedra(levels);
    ASSERT_LT(file.size(), 8192u);
    auto r = read_mesh(dir.write("bomb.3mf", file));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    const std::uint64_t triangles = std::uint64_t{4} << levels;
    EXPECT_TRUE(contains(r.error().message, fmt::format("{} triangles", triangles)))
        << r.error().describe();
    EXPECT_TRUE(contains(r.error().message, "components")) << r.error().describe();
    EXPECT_TRUE(contains(r.error().message, "at most 20000000")) << r.error().describe();
}

TEST(ThreeMf, ALongCommentDoesNotHideTheTree) {
    // The check before lib3mf keeps only the start of a long tag; a comment longer than
    // that, full of '>', must still end where it ends.
    ScratchDir dir;
    std::string comment = "<!-- ";
    for (int i = 0; i < 5000; ++i) comment += "a> -";
    comment += " -->";
    auto r = read_mesh(dir.write("hidden.3mf", nested_tetrahedra(30, "model", comment)));
    ASSERT_FALSE(r);
    EXPECT_TRUE(contains(r.error().message, "4294967296 triangles")) << r.error().describe();
}

TEST(ThreeMf, ExponentialTreeOfObjectsThatAreNotPartsIsRefusedToo) {
    // The same tree over a support object places no triangle, but reading it still walks
    // 2^30 placements: the placement count is bounded as well.
    ScratchDir dir;
    auto r = read_mesh(dir.write("bomb.3mf", nested_tetrahedra(30, "support")));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    EXPECT_TRUE(contains(r.error().message, "placements")) << r.error().describe();
    // A small tree of support objects is read, and holds no part.
    r = read_mesh(dir.write("small.3mf", nested_tetrahedra(3, "support")));
    ASSERT_FALSE(r);
    EXPECT_TRUE(contains(r.error().message, "no triangles")) << r.error().describe();
}

}  // namespace
}  // namespace maxslice::io
