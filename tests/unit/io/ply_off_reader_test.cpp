#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "io_test_support.hpp"
#include "maxslice/io/read_mesh.hpp"

namespace maxslice::io {
namespace {

using test::contains;
using test::joined;
using test::ScratchDir;

// An L-shaped (concave) hexagon in the plane z = 1, counter-clockwise seen from +z, with
// area 3: a fan from corner 0 would put triangles outside it.
const char* kLVertices = "0 0 1\n2 0 1\n2 1 1\n1 1 1\n1 2 1\n0 2 1\n";

double area_sum(const mesh::TriangleMesh& m, core::Vec3d* vector_sum = nullptr) {
    double sum = 0.0;
    core::Vec3d v{};
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const core::Vec3d a = mesh::area_vector(m, t);
        sum += 0.5 * core::norm(a);
        v += a * 0.5;
    }
    if (vector_sum != nullptr) *vector_sum = v;
    return sum;
}

TEST(Off, ConcavePolygonIsEarClipped) {
    ScratchDir dir;
    // Rotate the corner order so that a fan from the first corner would be wrong.
    auto r =
        read_mesh(dir.write("l.off", std::string("OFF\n6 1 0\n") + kLVertices + "6 3 4 5 0 1 2\n"));
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->mesh.triangles.size(), 4u);
    core::Vec3d v{};
    EXPECT_NEAR(area_sum(r->mesh, &v), 3.0, 1e-12);
    EXPECT_NEAR(v.z, 3.0, 1e-12);  // every triangle faces +z
    EXPECT_TRUE(r->warnings.empty()) << joined(r->warnings);
}

TEST(Off, LargePolygonsCommentsAndExtraColumns) {
    // Assimp drops OFF faces with more than 9 corners; a 40-gon must come through whole.
    ScratchDir dir;
    std::string s = "OFF\n# a comment\n40 1\n";
    for (int i = 0; i < 40; ++i) {
        const double a = 2.0 * M_PI * i / 40;
        s += std::to_string(std::cos(a)) + " " + std::to_string(std::sin(a)) + " 0 0.5 0.5 0.5\n";
    }
    s += "40";
    for (int i = 0; i < 40; ++i) {
        s += ' ';
        s += std::to_string(i);
    }
    s += " 255 0 0 # colour\n";
    auto r = read_mesh(dir.write("p40.off", s));
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->mesh.triangles.size(), 38u);
}

struct Bad {
    const char* name;
    const char* ext;
    std::string text;
    const char* expected;
};

void PrintTo(const Bad& b, std::ostream* os) {
    *os << b.name;
}

class PlyOffRefusals : public ::testing::TestWithParam<Bad> {};

TEST_P(PlyOffRefusals, RefusedWithAReason) {
    ScratchDir dir;
    auto r = read_mesh(dir.write(std::string("bad.") + GetParam().ext, GetParam().text));
    ASSERT_FALSE(r) << GetParam().name;
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    EXPECT_TRUE(contains(r.error().message, GetParam().expected))
        << GetParam().name << ": " << r.error().describe();
}

const std::string kPlyHead =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
    "property float z\nelement face 2\nproperty list uchar int vertex_indices\n";
const std::string kPlyVerts = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n";

INSTANTIATE_TEST_SUITE_P(
    Cases, PlyOffRefusals,
    ::testing::Values(
        // Each of these hangs, aborts or silently changes the mesh in assimp 5.2.5.
        Bad{"ply_header_cut", "ply", kPlyHead, "no 'end_header' line"},
        Bad{"ply_header_cut_early", "ply", "ply\nformat ascii 1.0\ne", "unknown PLY header line"},
        Bad{"ply_data_cut", "ply", kPlyHead + "end_header\n" + kPlyVerts + "3 0 1 2\n",
            "ends in entry 2 of 2 of element 'face'"},
        Bad{"ply_index", "ply", kPlyHead + "end_header\n" + kPlyVerts + "3 0 1 2\n3 0 2 7\n",
            "line 15: face 2: vertex index 7 is out of range"},
        Bad{"ply_huge_count", "ply",
            "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
            "property float y\nproperty float z\nelement face 1\n"
            "property list uchar int vertex_indices\nend_header\n",
            "claims 4000000000 entries"},
        Bad{"ply_nan", "ply", kPlyHead + "end_header\n0 0 0\n1 nan 0\n1 1 0\n0 1 0\n",
            "line 11: a vertex coordinate is NaN or infinite"},
        Bad{"ply_no_faces", "ply",
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
            "property float z\nend_header\n0 0 0\n",
            "no triangles"},
        Bad{"off_cut", "off", "OFF\n4 2 0\n0 0 0\n1 0 0\n", "ends after 2 of 4 vertices"},
        Bad{"off_huge", "off", "OFF\n400000000 2 0\n0 0 0\n", "more than the file's"},
        Bad{"off_face_cut", "off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 1\n300 0 1 2\n",
            "line 7: the face has 3 of its 300 corners"},
        Bad{"off_index", "off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 1\n3 0 1 9\n",
            "line 7: vertex index 9 is out of range"},
        Bad{"off_homogeneous", "off", "4OFF\n1 1 0\n0 0 0 1\n3 0 0 0\n", "not supported"}),
    [](const auto& info) { return std::string(info.param.name); });

std::string binary_ply(bool big_endian) {
    std::string s = std::string("ply\nformat ") +
                    (big_endian ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\ncomment made in a test\nelement vertex 6\nproperty double x\n"
                    "property double y\nproperty double z\nproperty uchar red\n"
                    "element face 1\nproperty list uchar uint vertex_indices\n"
                    "property float quality\nend_header\n";
    auto put = [&](const void* p, std::size_t n) {
        std::string b(static_cast<const char*>(p), n);
        if (big_endian) std::reverse(b.begin(), b.end());
        s += b;
    };
    const double v[6][3] = {{0, 0, 1}, {2, 0, 1}, {2, 1, 1}, {1, 1, 1}, {1, 2, 1}, {0, 2, 1}};
    for (const auto& p : v) {
        for (const double c : p) put(&c, 8);
        s.push_back('\x07');
    }
    s.push_back('\x06');
    for (std::uint32_t i : {3u, 4u, 5u, 0u, 1u, 2u}) put(&i, 4);
    const float q = 1.0f;
    put(&q, 4);
    return s;
}

TEST(Ply, BinaryBothEndiannessesWithExtraProperties) {
    ScratchDir dir;
    for (const bool big : {false, true}) {
        auto r = read_mesh(dir.write("b.ply", binary_ply(big)));
        ASSERT_TRUE(r) << r.error().describe();
        EXPECT_EQ(r->format, Format::kPly);
        EXPECT_EQ(r->mesh.triangles.size(), 4u);
        core::Vec3d v{};
        EXPECT_NEAR(area_sum(r->mesh, &v), 3.0, 1e-12) << (big ? "big" : "little");
        EXPECT_NEAR(v.z, 3.0, 1e-12);
    }
    std::string cut = binary_ply(false);
    cut.resize(cut.size() - 3);
    auto r = read_mesh(dir.write("cut.ply", cut));
    ASSERT_FALSE(r);
    EXPECT_TRUE(contains(r.error().message, "ends in entry 1 of 1 of element 'face'"))
        << r.error().describe();
}

TEST(Ply, ShortFacesAreDroppedWithAWarning) {
    ScratchDir dir;
    auto r =
        read_mesh(dir.write("s.ply", kPlyHead + "end_header\n" + kPlyVerts + "4 0 1 2 3\n2 0 1\n"));
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->mesh.triangles.size(), 2u);
    ASSERT_EQ(r->warnings.size(), 1u) << joined(r->warnings);
    EXPECT_TRUE(contains(r->warnings[0], "ignored 1 face with fewer than 3 corners"));
}

}  // namespace
}  // namespace maxslice::io
