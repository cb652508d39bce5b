#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "io_test_support.hpp"
#include "maxslice/io/read_mesh.hpp"

namespace maxslice::io {
namespace {

using test::contains;
using test::joined;
using test::ScratchDir;

// A unit cube as 6 quads, outward winding; OBJ/OFF/PLY all use this vertex order.
constexpr const char* kCubeVertices[] = {"0 0 0", "1 0 0", "1 1 0", "0 1 0",
                                         "0 0 1", "1 0 1", "1 1 1", "0 1 1"};
constexpr int kCubeQuads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                  {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

std::string cube_obj() {
    std::string s = "# cube\no cube\n";
    for (const char* v : kCubeVertices) {
        s += "v ";
        s += v;
        s += '\n';
    }
    for (const auto& q : kCubeQuads) {
        s += "f";
        for (int i : q) {
            s += ' ';
            s += std::to_string(i + 1);
        }
        s += "\n";
    }
    return s;
}

std::string cube_off() {
    std::string s = "OFF\n8 6 0\n";
    for (const char* v : kCubeVertices) {
        s += v;
        s += '\n';
    }
    for (const auto& q : kCubeQuads) {
        s += "4";
        for (int i : q) {
            s += ' ';
            s += std::to_string(i);
        }
        s += "\n";
    }
    return s;
}

std::string cube_ply_ascii(int bad_index = -1) {
    std::string s =
        "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
        "property float z\nelement face 6\nproperty list uchar int vertex_indices\nend_header\n";
    for (const char* v : kCubeVertices) {
        s += v;
        s += '\n';
    }
    for (const auto& q : kCubeQuads) {
        s += "4";
        for (int i : q) {
            s += ' ';
            s += std::to_string(bad_index >= 0 && i == 6 ? bad_index : i);
        }
        s += "\n";
    }
    return s;
}

std::string cube_ply_binary() {
    std::string s =
        "ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty float x\n"
        "property float y\nproperty float z\nelement face 6\n"
        "property list uchar int vertex_indices\nend_header\n";
    const float v[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                           {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    s.append(reinterpret_cast<const char*>(v), sizeof(v));
    for (const auto& q : kCubeQuads) {
        s.push_back('\x04');
        for (int i : q) {
            const std::int32_t idx = i;
            s.append(reinterpret_cast<const char*>(&idx), 4);
        }
    }
    return s;
}

void expect_unit_cube(const core::Result<ImportedMesh>& r, Format format) {
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->format, format);
    EXPECT_EQ(r->mesh.triangles.size(), 12u);
    EXPECT_EQ(r->mesh.vertices.size(), 8u);
    EXPECT_NEAR(mesh::signed_volume(r->mesh), 1.0, 1e-12);
    EXPECT_TRUE(r->warnings.empty()) << joined(r->warnings);
}

TEST(Assimp, ObjOffPlyCubes) {
    ScratchDir dir;
    expect_unit_cube(read_mesh(dir.write("c.obj", cube_obj())), Format::kObj);
    expect_unit_cube(read_mesh(dir.write("c.off", cube_off())), Format::kOff);
    expect_unit_cube(read_mesh(dir.write("c.ply", cube_ply_ascii())), Format::kPly);
    expect_unit_cube(read_mesh(dir.write("cb.ply", cube_ply_binary())), Format::kPly);
    // Content decides when the name says nothing.
    expect_unit_cube(read_mesh(dir.write("c.mesh", cube_off())), Format::kOff);
}

TEST(Assimp, PlyFaceIndexOutOfRangeIsRefused) {
    ScratchDir dir;
    auto r = read_mesh(dir.write("bad.ply", cube_ply_ascii(99)));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
}

TEST(Assimp, ObjIndexChecksNameTheLine) {
    ScratchDir dir;
    const std::string base = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    auto r = read_mesh(dir.write("a.obj", base + "f 1 2 4\n"));
    ASSERT_FALSE(r);
    EXPECT_TRUE(contains(r.error().message, "line 4: vertex index 4 but the file has only 3"))
        << r.error().describe();
    r = read_mesh(dir.write("b.obj", base + "f 0 1 2\n"));
    ASSERT_FALSE(r);
    EXPECT_TRUE(contains(r.error().message, "line 4: vertex index 0")) << r.error().describe();
    r = read_mesh(dir.write("c.obj", base + "f -1 -2 -4\n"));
    ASSERT_FALSE(r);
    EXPECT_TRUE(contains(r.error().message, "line 4: relative vertex index -4"))
        << r.error().describe();
    r = read_mesh(dir.write("d.obj", base + "f 1/x 2 3\n"));
    ASSERT_FALSE(r);
    EXPECT_TRUE(contains(r.error().message, "line 4: face corner '1/x'")) << r.error().describe();
    r = read_mesh(dir.write("g.obj", base + "vn 0 0 1\nf 1//1 2//1 3//2\n"));
    ASSERT_FALSE(r);
    EXPECT_TRUE(
        contains(r.error().message, "line 5: normal index 2 but the file has only 1 normals"))
        << r.error().describe();
    r = read_mesh(dir.write("h.obj", base + "vt 0 0\nf 1/1 2/0 3/1\n"));
    ASSERT_FALSE(r);
    EXPECT_TRUE(contains(r.error().message, "line 5: texture index 0")) << r.error().describe();
    r = read_mesh(dir.write("e.obj", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n"));
    ASSERT_FALSE(r);
    EXPECT_TRUE(contains(r.error().message, "line 2: a vertex needs 3 coordinates"))
        << r.error().describe();
    // Negative (relative) indices, texture/normal references and forward references are fine.
    r = read_mesh(dir.write("f.obj", "f 1//1 2//1 3//1\nvn 0 0 1\n" + base + "f -3 -2 -1\n"));
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->mesh.triangles.size(), 2u);
}

TEST(Assimp, ObjLineContinuation) {
    ScratchDir dir;
    auto r = read_mesh(dir.write("c.obj",
                                 "v 0 0 0\nv 1 \\\n 0 0\nv 0 1 0\nv 1 1 0\n"
                                 "f 1 2 \\\n 4 3\n"));
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->mesh.triangles.size(), 2u);
}

TEST(Assimp, Utf16LittleEndianObj) {
    ScratchDir dir;
    const std::string utf8 = cube_obj();
    std::string utf16 = "\xFF\xFE";
    for (const char c : utf8) {
        utf16.push_back(c);
        utf16.push_back('\0');
    }
    auto r = read_mesh(dir.write("c16.obj", utf16));
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->mesh.triangles.size(), 12u);
    ASSERT_EQ(r->warnings.size(), 1u) << joined(r->warnings);
    EXPECT_TRUE(contains(r->warnings[0], "UTF-16"));
    // UTF-16 is only taken for OBJ.
    auto s = read_mesh(dir.write("c16.stl", utf16));
    ASSERT_FALSE(s);
    EXPECT_TRUE(contains(s.error().message, "UTF-16")) << s.error().describe();
}

TEST(Assimp, ConcavePolygonIsEarClippedNotFanned) {
    // A fan over a concave polygon makes triangles that overlap and face the other way, so
    // the sum of the triangle areas exceeds the polygon's area. Ear clipping keeps every
    // triangle inside with the polygon's orientation: the two sums are equal.
    auto r = read_mesh(test::testdata("malformed/assimp/concave_polygon.obj"));
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->mesh.triangles.size(), 64u);
    core::Vec3d sum{};
    double abs_sum = 0.0;
    for (std::size_t t = 0; t < r->mesh.triangles.size(); ++t) {
        const core::Vec3d a = mesh::area_vector(r->mesh, t);
        sum += a;
        abs_sum += core::norm(a);
    }
    EXPECT_GT(abs_sum, 0.0);
    EXPECT_NEAR(core::norm(sum), abs_sum, 1e-9 * abs_sum);
}

}  // namespace
}  // namespace maxslice::io
