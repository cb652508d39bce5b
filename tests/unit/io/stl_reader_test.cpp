#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <future>
#include <limits>
#include <string>
#include <vector>

#include "io_test_support.hpp"
#include "maxslice/io/read_mesh.hpp"
#include "support/fixtures.hpp"

namespace maxslice::io {
namespace {

using test::contains;
using test::joined;
using test::ScratchDir;

using Corners = std::array<float, 9>;

// A unit tetrahedron, outward winding.
const std::vector<Corners> kTetra = {
    Corners{0, 0, 0, 0, 1, 0, 1, 0, 0}, Corners{0, 0, 0, 1, 0, 0, 0, 0, 1},
    Corners{0, 0, 0, 0, 0, 1, 0, 1, 0}, Corners{1, 0, 0, 0, 1, 0, 0, 0, 1}};

std::string binary_stl(const std::vector<Corners>& tris, std::string_view header,
                       std::uint32_t declared) {
    std::string bytes(84, '\0');
    std::memcpy(bytes.data(), header.data(), std::min<std::size_t>(header.size(), 80));
    std::memcpy(bytes.data() + 80, &declared, 4);
    for (const Corners& t : tris) {
        char rec[50] = {};
        std::memcpy(rec + 12, t.data(), 36);
        bytes.append(rec, 50);
    }
    return bytes;
}

std::string binary_stl(const std::vector<Corners>& tris) {
    return binary_stl(tris, "maxslice test", static_cast<std::uint32_t>(tris.size()));
}

std::string ascii_stl(const std::vector<Corners>& tris, std::string_view eol = "\n") {
    std::string s = "solid test";
    s += eol;
    for (const Corners& t : tris) {
        s += "facet normal 0 0 0";
        s += eol;
        s += " outer loop";
        s += eol;
        for (int k = 0; k < 3; ++k) {
            s += "  vertex " + std::to_string(t[3 * k]) + " " + std::to_string(t[3 * k + 1]) + " " +
                 std::to_string(t[3 * k + 2]);
            s += eol;
        }
        s += " endloop";
        s += eol;
        s += "endfacet";
        s += eol;
    }
    s += "endsolid test";
    s += eol;
    return s;
}

TEST(StlBinary, ReadsTrianglesAndWeldsExactly) {
    ScratchDir dir;
    auto r = read_mesh(dir.write("t.stl", binary_stl(kTetra)));
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->format, Format::kStlBinary);
    EXPECT_EQ(r->mesh.triangles.size(), 4u);
    EXPECT_EQ(r->mesh.vertices.size(), 4u);
    EXPECT_NEAR(mesh::signed_volume(r->mesh), 1.0 / 6.0, 1e-12);
    EXPECT_TRUE(r->warnings.empty()) << joined(r->warnings);
}

TEST(StlBinary, HeaderStartingWithSolidIsStillBinary) {
    ScratchDir dir;
    auto r = read_mesh(dir.write("t.stl", binary_stl(kTetra, "solid looks like ascii", 4)));
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->format, Format::kStlBinary);
    EXPECT_EQ(r->mesh.triangles.size(), 4u);
}

TEST(StlBinary, CountDisagreeingWithSizeUsesWhatTheFileHolds) {
    ScratchDir dir;
    for (const std::uint32_t declared : {1u, 66u, 0xFFFFFFFFu}) {
        auto r = read_mesh(dir.write("t.stl", binary_stl(kTetra, "x", declared)));
        ASSERT_TRUE(r) << r.error().describe();
        EXPECT_EQ(r->mesh.triangles.size(), 4u);
        ASSERT_EQ(r->warnings.size(), 1u) << joined(r->warnings);
        EXPECT_TRUE(contains(r->warnings[0], "header says " + std::to_string(declared)));
        EXPECT_TRUE(contains(r->warnings[0], "holds 4"));
    }
}

TEST(StlBinary, PartialTrailingRecordIsRefused) {
    ScratchDir dir;
    std::string bytes = binary_stl(kTetra);
    bytes.resize(bytes.size() - 7);
    auto r = read_mesh(dir.write("t.stl", bytes));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    EXPECT_TRUE(contains(r.error().message, "damaged binary STL")) << r.error().describe();
    EXPECT_TRUE(contains(r.error().message, "43 bytes are left")) << r.error().describe();
    EXPECT_TRUE(contains(r.error().context, "t.stl"));
}

TEST(StlBinary, NanCoordinateIsRefusedNamingTheTriangle) {
    ScratchDir dir;
    std::vector<Corners> tris = kTetra;
    tris[2][4] = std::numeric_limits<float>::quiet_NaN();
    auto r = read_mesh(dir.write("t.stl", binary_stl(tris)));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    EXPECT_TRUE(contains(r.error().message, "triangle 3")) << r.error().describe();
    tris = kTetra;
    tris[0][0] = std::numeric_limits<float>::infinity();
    r = read_mesh(dir.write("t.stl", binary_stl(tris)));
    ASSERT_FALSE(r);
    EXPECT_TRUE(contains(r.error().message, "triangle 1")) << r.error().describe();
}

TEST(StlBinary, TooShortAndHeaderOnly) {
    ScratchDir dir;
    auto r = read_mesh(dir.write("short.stl", std::string(40, '\x01')));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    EXPECT_TRUE(contains(r.error().message, "at least 84 bytes")) << r.error().describe();
    r = read_mesh(dir.write("empty_body.stl", binary_stl({})));
    ASSERT_FALSE(r);
    EXPECT_TRUE(contains(r.error().message, "no triangles")) << r.error().describe();
}

TEST(StlAscii, SameTrianglesAsBinary) {
    ScratchDir dir;
    auto a = read_mesh(dir.write("a.stl", ascii_stl(kTetra)));
    auto b = read_mesh(dir.write("b.stl", binary_stl(kTetra)));
    ASSERT_TRUE(a) << a.error().describe();
    ASSERT_TRUE(b) << b.error().describe();
    EXPECT_EQ(a->format, Format::kStlAscii);
    EXPECT_EQ(a->mesh.vertices, b->mesh.vertices);
    EXPECT_EQ(a->mesh.triangles, b->mesh.triangles);
}

TEST(StlAscii, KeywordsAnyCaseCrlfAndOneLine) {
    ScratchDir dir;
    const std::string upper =
        "SOLID X\r\nFACET NORMAL 0 0 -1\r\nOUTER LOOP\r\nVERTEX 0 0 0\r\nVERTEX 0 1 0\r\n"
        "VERTEX 1 0 0\r\nENDLOOP\r\nENDFACET\r\nENDSOLID X\r\n";
    auto r = read_mesh(dir.write("upper.stl", upper));
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->mesh.triangles.size(), 1u);
    const std::string one_line =
        "solid s facet normal 0 0 1 outer loop vertex +0 0 0 vertex 1. 0 0 vertex 0 1e0 0 "
        "endloop endfacet endsolid s";
    r = read_mesh(dir.write("one_line.stl", one_line));
    // On one line, "solid s ..." names the solid with the whole line: no facets.
    ASSERT_FALSE(r);
    const std::string mixed =
        "  solid s\n\tFacet Normal 0 0 1 Outer Loop vertex +0 0 0 vertex 1. 0 0 vertex 0 1e0 0 "
        "EndLoop EndFacet\nendsolid";
    r = read_mesh(dir.write("mixed.stl", mixed));
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->mesh.triangles.size(), 1u);
    EXPECT_EQ(r->mesh.vertices[1], (core::Vec3d{1, 0, 0}));
}

TEST(StlAscii, NormalsMayBeMissingNanZeroOrWrong) {
    ScratchDir dir;
    const std::string text =
        "solid s\nfacet normal\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\n"
        "endfacet\nfacet normal NaN nan -inf\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
        "vertex 0 0 1\nendloop\nendfacet\nfacet\nouter loop\nvertex 0 0 0\nvertex 0 0 1\n"
        "vertex 0 1 0\nendloop\nendfacet\nfacet normal -1 -1 -1\nouter loop\nvertex 1 0 0\n"
        "vertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\nendsolid s\n";
    auto r = read_mesh(dir.write("n.stl", text));
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->mesh.triangles.size(), 4u);
    EXPECT_NEAR(mesh::signed_volume(r->mesh), 1.0 / 6.0, 1e-12);  // winding, not normals
    ASSERT_EQ(r->warnings.size(), 1u) << joined(r->warnings);
    EXPECT_TRUE(contains(r->warnings[0], "1 of 4 stored facet normals")) << joined(r->warnings);
}

struct AsciiError {
    const char* name;
    std::string text;
    const char* expected;
};

void PrintTo(const AsciiError& e, std::ostream* os) {
    *os << e.name;
}

class StlAsciiErrors : public ::testing::TestWithParam<AsciiError> {};

TEST_P(StlAsciiErrors, NamesTheLine) {
    ScratchDir dir;
    auto r = read_mesh(dir.write("e.stl", GetParam().text));
    ASSERT_FALSE(r) << GetParam().name;
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    EXPECT_TRUE(contains(r.error().message, GetParam().expected))
        << GetParam().name << ": " << r.error().describe();
}

const std::string kHead = "solid s\nfacet normal 0 0 1\nouter loop\n";
const std::string kTail = "endloop\nendfacet\nendsolid s\n";

INSTANTIATE_TEST_SUITE_P(
    Cases, StlAsciiErrors,
    ::testing::Values(
        AsciiError{"nan_vertex", kHead + "vertex 0 0 0\nvertex NaN 1 0\nvertex 1 0 0\n" + kTail,
                   "line 5: vertex coordinate 'NaN' is not finite"},
        AsciiError{"inf_vertex", kHead + "vertex 0 0 0\nvertex 0 1 0\nvertex 1 0 inf\n" + kTail,
                   "line 6: vertex coordinate 'inf' is not finite"},
        AsciiError{"overflow", kHead + "vertex 0 0 0\nvertex 0 1 0\nvertex 1 0 1e999\n" + kTail,
                   "line 6: vertex coordinate '1e999' is out of range"},
        // A double, but beyond what the 32-bit floats of an STL hold: out of range, with the
        // value, not "not a number".
        AsciiError{"beyond_float", kHead + "vertex 0 0 0\nvertex 0 1e300 0\nvertex 1 0 0\n" + kTail,
                   "line 5: vertex coordinate '1e300' is out of range: its magnitude is above "
                   "3.40282e+38"},
        AsciiError{"garbage", kHead + "vertex 0 0 0\nvertex 0 1x 0\nvertex 1 0 0\n" + kTail,
                   "line 5: a vertex needs 3 numbers; found '1x'"},
        AsciiError{"two_numbers", kHead + "vertex 0 0\nvertex 0 1 0\nvertex 1 0 0\n" + kTail,
                   "line 4: a vertex needs 3 numbers; found 'vertex'"},
        AsciiError{"quad",
                   kHead + "vertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nvertex 1 1 0\n" + kTail,
                   "line 2: facet has 4 vertices"},
        AsciiError{"bad_normal", "solid s\nfacet normal 0 zero 1\nouter loop\n",
                   "line 2: facet normal component 'zero' is not a number"},
        AsciiError{"truncated", kHead + "vertex 0 0 0\nvertex 0 1 0\n",
                   "the file ends inside the facet that starts at line 2"},
        AsciiError{"no_outer", "solid s\nfacet normal 0 0 1\nvertex 0 0 0\n",
                   "line 3: expected 'outer loop'"},
        AsciiError{"junk", "solid s\nhello\n", "line 2: expected 'facet' or 'endsolid'"},
        AsciiError{"no_facets", "solid s\nendsolid s\n", "no triangles"}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(StlAscii, MissingEndsolidAndSeveralSolidsAreWarnings) {
    ScratchDir dir;
    std::string text = ascii_stl(kTetra);
    text.resize(text.find("endsolid"));
    auto r = read_mesh(dir.write("open.stl", text));
    ASSERT_TRUE(r) << r.error().describe();
    ASSERT_EQ(r->warnings.size(), 1u) << joined(r->warnings);
    EXPECT_TRUE(contains(r->warnings[0], "no 'endsolid'"));

    r = read_mesh(dir.write("two.stl", ascii_stl(kTetra) + ascii_stl({kTetra[0]})));
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->mesh.triangles.size(), 5u);
    EXPECT_EQ(r->solids, 2u);
    ASSERT_EQ(r->warnings.size(), 1u) << joined(r->warnings);
    EXPECT_TRUE(contains(r->warnings[0], "2 'solid' blocks"));
}

// The line and column of byte `at` in `text`, as the reader counts them (1-based).
std::string line_and_column(std::string_view text, std::size_t at) {
    const std::size_t line = 1 + static_cast<std::size_t>(std::count(
                                     text.begin(), text.begin() + static_cast<long>(at), '\n'));
    const std::size_t line_start = text.rfind('\n', at - 1);
    return "line " + std::to_string(line) + ", column " + std::to_string(at - line_start);
}

TEST(StlAscii, StrayControlByteIsReportedAsAsciiWithItsPlace) {
    // A text STL with one stray control byte is a damaged ASCII file: the message says so
    // and where the byte is, instead of measuring the text against the binary layout
    // ("damaged binary STL: ... truncated").
    ScratchDir dir;
    std::string bytes = ascii_stl(kTetra);
    const std::size_t at = bytes.find("vertex", bytes.find("facet", 30));
    ASSERT_NE(at, std::string::npos);
    bytes.insert(at, 1, '\x01');
    // Once as it is, once padded so that its size also fits 84 + 50 n (which used to read
    // the text as binary triangles).
    for (int padded = 0; padded < 2; ++padded) {
        std::string file = bytes;
        if (padded == 1) {
            const std::size_t pad = (50 - (file.size() - 84) % 50) % 50;
            file.insert(file.find('\n'), pad, ' ');
            ASSERT_EQ((file.size() - 84) % 50, 0u);
        }
        const std::size_t byte_at = file.find('\x01');
        auto r = read_mesh(dir.write("x.stl", file));
        ASSERT_FALSE(r) << "padded " << padded;
        EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
        const std::string& m = r.error().message;
        EXPECT_TRUE(contains(m, line_and_column(file, byte_at) + ": control byte \\x01 in an "
                                                                 "ASCII STL"))
            << r.error().describe();
        EXPECT_FALSE(contains(m, "binary")) << r.error().describe();
        auto format = detect_format(dir.path() / "x.stl");
        ASSERT_TRUE(format);
        EXPECT_EQ(*format, Format::kStlAscii);
    }
}

TEST(StlBinary, SolidHeaderWithoutTextFacetStaysBinary) {
    // A binary header that starts with "solid " and a text-looking first line is still
    // binary when the next word is not "facet" or "endsolid".
    ScratchDir dir;
    auto r = read_mesh(dir.write("b.stl", binary_stl(kTetra, "solid part\nmade by cad", 4)));
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->format, Format::kStlBinary);
    EXPECT_EQ(r->mesh.triangles.size(), 4u);
}

TEST(StlWrite, RoundTripKeepsTrianglesAndVolume) {
    ScratchDir dir;
    const mesh::TriangleMesh cyl = maxslice::test::cylinder(5.0, 12.0, 48);
    const auto path = dir.path() / "cyl.stl";
    ASSERT_TRUE(write_stl_binary(path, cyl));
    auto r = read_mesh(path);
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->mesh.triangles.size(), cyl.triangles.size());
    EXPECT_EQ(r->mesh.vertices.size(), cyl.vertices.size());
    EXPECT_NEAR(mesh::signed_volume(r->mesh), mesh::signed_volume(cyl), 1e-4);
    EXPECT_TRUE(r->warnings.empty()) << joined(r->warnings);

    auto bad = write_stl_binary(dir.path() / "no_such_dir" / "x.stl", cyl);
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error().code, core::ErrorCode::kIo);
}

TEST(StlRead, DeterministicTwice) {
    const auto path = test::testdata("meshes/oasis/Spiral_lattice_cone_1.stl");
    auto a = read_mesh(path);
    auto b = read_mesh(path);
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->mesh.vertices, b->mesh.vertices);
    EXPECT_EQ(a->mesh.triangles, b->mesh.triangles);
}

TEST(ReadMesh, MissingFileDirectoryAndUnknownFormat) {
    ScratchDir dir;
    auto r = read_mesh(dir.path() / "nope.stl");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kIo);
    EXPECT_TRUE(contains(r.error().context, "nope.stl"));
    r = read_mesh(dir.path());
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kIo);
    EXPECT_TRUE(contains(r.error().message, "directory"));
    r = read_mesh(dir.write("notes.txt", "hello world\n"));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    EXPECT_TRUE(contains(r.error().message, "unrecognised file format"));
    r = read_mesh(dir.write("empty.stl", ""));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    EXPECT_TRUE(contains(r.error().message, "empty"));
}

TEST(ReadMesh, FifoIsRefusedWithoutBlocking) {
    // Opening a FIFO for reading waits for a writer; the reader must refuse it at once. The
    // read runs on another thread so that a regression fails here instead of hanging: on a
    // time-out the test opens the write end itself, which releases the blocked open.
    ScratchDir dir;
    const auto fifo = dir.path() / "part.stl";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    auto pending = std::async(std::launch::async, [&] { return read_mesh(fifo); });
    if (pending.wait_for(std::chrono::seconds(30)) != std::future_status::ready) {
        ADD_FAILURE() << "read_mesh blocked on a FIFO";
        const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
        if (fd >= 0) ::close(fd);
    }
    auto r = pending.get();
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kIo);
    EXPECT_TRUE(contains(r.error().message, "not a regular file")) << r.error().describe();
    EXPECT_FALSE(detect_format(fifo));
}

TEST(ReadMesh, ContentWinsOverExtension) {
    ScratchDir dir;
    auto r = read_mesh(dir.write("part.obj", ascii_stl(kTetra)));
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->format, Format::kStlAscii);
    ASSERT_EQ(r->warnings.size(), 1u) << joined(r->warnings);
    EXPECT_TRUE(contains(r->warnings[0], "ends in '.obj' but the content is stl-ascii"));
    const auto stl_as_dat = dir.write("part.dat", binary_stl(kTetra));
    r = read_mesh(stl_as_dat);
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->format, Format::kStlBinary);
    auto f = detect_format(stl_as_dat);
    ASSERT_TRUE(f);
    EXPECT_EQ(*f, Format::kStlBinary);
    const auto step_as_stl = dir.path() / "featuretype.stl";
    std::filesystem::copy_file(test::testdata("step/trimesh/featuretype.STEP"), step_as_stl);
    r = read_mesh(step_as_stl);
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->format, Format::kStep);
    ASSERT_FALSE(r->warnings.empty());
    EXPECT_TRUE(contains(r->warnings[0], "ends in '.stl' but the content is step"))
        << joined(r->warnings);
}

TEST(ReadMesh, RejectsBadTessellationOptions) {
    ImportOptions o;
    o.chord_deviation_mm = 0.0;
    auto r = read_mesh(test::testdata("meshes/cura/nozzle.stl"), o);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    o = {};
    o.angular_deviation_deg = std::nan("");
    r = read_mesh(test::testdata("meshes/cura/nozzle.stl"), o);
    ASSERT_FALSE(r);
}

}  // namespace
}  // namespace maxslice::io
