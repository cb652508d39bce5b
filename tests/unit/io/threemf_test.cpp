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

namespace maxslice::io {
namespace {

using test::contains;
using test::joined;
using test::ScratchDir;

std::uint32_t crc32(std::string_view bytes) {
    std::uint32_t crc = 0xFFFFFFFFu;
    for (const char ch : bytes) {
        crc ^= static_cast<unsigned char>(ch);
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

void put16(std::string& out, std::uint32_t v) {
    out.push_back(static_cast<char>(v & 0xFF));
    out.push_back(static_cast<char>((v >> 8) & 0xFF));
}
void put32(std::string& out, std::uint32_t v) {
    put16(out, v & 0xFFFF);
    put16(out, v >> 16);
}

// A zip archive of stored entries (method 0), enough for lib3mf.
std::string zip(const std::vector<std::pair<std::string, std::string>>& entries) {
    std::string out;
    std::string directory;
    for (const auto& [name, data] : entries) {
        const auto offset = static_cast<std::uint32_t>(out.size());
        const std::uint32_t crc = crc32(data);
        const auto size = static_cast<std::uint32_t>(data.size());
        put32(out, 0x04034b50);
        put16(out, 20);  // version needed
        put16(out, 0);   // flags
        put16(out, 0);   // stored
        put32(out, 0);   // time, date
        put32(out, crc);
        put32(out, size);
        put32(out, size);
        put16(out, static_cast<std::uint32_t>(name.size()));
        put16(out, 0);
        out += name;
        out += data;
        put32(directory, 0x02014b50);
        put16(directory, 20);
        put16(directory, 20);
        put16(directory, 0);
        put16(directory, 0);
        put32(directory, 0);
        put32(directory, crc);
        put32(directory, size);
        put32(directory, size);
        put16(directory, static_cast<std::uint32_t>(name.size()));
        put16(directory, 0);  // extra
        put16(directory, 0);  // comment
        put16(directory, 0);  // disk
        put16(directory, 0);  // internal attributes
        put32(directory, 0);  // external attributes
        put32(directory, offset);
        directory += name;
    }
    const auto directory_at = static_cast<std::uint32_t>(out.size());
    out += directory;
    put32(out, 0x06054b50);
    put16(out, 0);
    put16(out, 0);
    put16(out, static_cast<std::uint32_t>(entries.size()));
    put16(out, static_cast<std::uint32_t>(entries.size()));
    put32(out, static_cast<std::uint32_t>(directory.size()));
    put32(out, directory_at);
    put16(out, 0);
    return out;
}

std::string three_mf(std::string_view resources, std::string_view build) {
    const std::string types =
        R"(<?xml version="1.0" encoding="UTF-8"?>)"
        R"(<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">)"
        R"(<Default Extension="rels" )"
        R"(ContentType="application/vnd.openxmlformats-package.relationships+xml"/>)"
        R"(<Default Extension="model" )"
        R"(ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/></Types>)";
    const std::string rels =
        R"(<?xml version="1.0" encoding="UTF-8"?>)"
        R"(<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">)"
        R"(<Relationship Target="/3D/3dmodel.model" Id="rel0" )"
        R"(Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>)";
    const std::string model =
        fmt::format(R"(<?xml version="1.0" encoding="UTF-8"?><model unit="millimeter" )"
                    R"(xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02">)"
                    R"(<resources>{}</resources><build>{}</build></model>)",
                    resources, build);
    return zip(
        {{"[Content_Types].xml", types}, {"_rels/.rels", rels}, {"3D/3dmodel.model", model}});
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
