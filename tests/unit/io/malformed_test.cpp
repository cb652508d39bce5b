// Every file under testdata/malformed is either accepted with exactly the expected warnings
// or refused with kInvalidInput/kIo and the expected message: the decision table of
// docs/input-files.md.

#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "io_test_support.hpp"
#include "maxslice/io/read_mesh.hpp"

namespace maxslice::io {
namespace {

using test::contains;
using test::joined;
using test::testdata;

struct Decision {
    const char* path;
    bool accepted;
    std::size_t triangles;              // accepted: the count read
    std::vector<const char*> expected;  // accepted: one substring per warning, in order;
                                        // refused: substrings of the message
    core::ErrorCode code = core::ErrorCode::kInvalidInput;
};

Decision accept(const char* path, std::size_t triangles, std::vector<const char*> warnings = {}) {
    return {path, true, triangles, std::move(warnings)};
}

Decision refuse(const char* path, std::vector<const char*> message) {
    return {path, false, 0, std::move(message)};
}

const std::vector<Decision>& decisions() {
    static const std::vector<Decision> table = {
        accept("malformed/assimp/Spider_binary.stl", 1368,
               {"1312 of 1368 stored facet normals point against the vertex winding"}),
        accept("malformed/assimp/box_UTF16BE.obj", 12, {"UTF-16 text; it was converted"}),
        accept("malformed/assimp/concave_polygon.obj", 64),
        refuse("malformed/assimp/empty.obj", {"the file is empty (0 bytes)"}),
        refuse("malformed/assimp/malformed.obj",
               {"line 23: vertex index 12 but the file has only 8 vertices"}),
        refuse("malformed/assimp/number_formats.obj",
               {"line 11: vertex coordinate '3.1+e2' is not a number"}),
        accept("malformed/assimp/sphereWithHole.stl", 285),
        refuse("malformed/assimp/testpoints.obj", {"no triangles", "24 points"}),
        accept("malformed/assimp/triangle_with_two_solids.stl", 2, {"2 'solid' blocks"}),
        refuse("malformed/dodgy-step-files/Ad005.stp",
               {"damaged STEP file: 2 syntax errors (first: line 22:",
                "5 references to missing entities", "no solid could be read"}),
        refuse("malformed/dodgy-step-files/Ad014.stp",
               {"damaged STEP file: 2 syntax errors (first: line 22:"}),
        refuse("malformed/dodgy-step-files/Ad049.stp",
               {"damaged STEP file: 3 syntax errors (first: line 40:"}),
        refuse("malformed/dodgy-step-files/Ad097.stp",
               {"not a readable STEP file: line 4: Incorrect syntax"}),
        accept("malformed/dodgy-step-files/Ps001.stp", 12),
        refuse("malformed/dodgy-step-files/Tsh001.stp",
               {"no solid: the STEP file holds 6 faces in 6 shells but no closed solid"}),
        refuse("malformed/nist/nist_ftc_08_asme1_ap242-e1-tg.stp",
               {"no solid: the STEP file holds only tessellated geometry"}),
        accept("malformed/oasis/column.stl", 12),
        refuse("malformed/stl-models/empty.stl", {"the file is empty (0 bytes)"}),
        refuse("malformed/stl-models/faceless.ascii.stl", {"no triangles"}),
        refuse("malformed/stl-models/fourVertices.ascii.stl",
               {"line 2: facet has 4 vertices; STL facets must be triangles"}),
        accept("malformed/stl-models/incorrectFaceCounter.bin.stl", 4,
               {"header says 66 triangles but the file holds 4"}),
        accept("malformed/stl-models/missingEndsolid.ascii.stl", 4, {"no 'endsolid'"}),
        accept("malformed/stl-models/missingFace.ascii.stl", 3),
        accept("malformed/stl-models/missingNormal.ascii.stl", 4),
        refuse("malformed/stl-models/multiWordName.bin.stl",
               {"damaged binary STL: 333 bytes is not 84 + 50 x n", "EF BF BD"}),
        accept("malformed/stl-models/notANumberNormal.ascii.stl", 4),
        refuse("malformed/stl-models/quad.ascii.stl", {"line 2: facet has 4 vertices"}),
        accept("malformed/stl-models/singleFace.ascii.stl", 1),
        accept("malformed/stl-models/solidNameMismatch.ascii.stl", 4),
        refuse("malformed/stl-models/twoVertices.ascii.stl", {"line 2: facet has 2 vertices"}),
        accept("malformed/stl-models/wrongHeader.bin.stl", 12),
        accept("malformed/stl-models/wrongNormal.ascii.stl", 4,
               {"1 of 4 stored facet normals point against the vertex winding"}),
        accept("malformed/stl-models/wrongNormals.ascii.stl", 4),
        accept("malformed/trimesh/joined_tetrahedra.obj", 8),
        accept("malformed/trimesh/multibody.stl", 32, {"2 'solid' blocks"}),
        accept("malformed/trimesh/negative_indices.obj", 12),
        accept("malformed/trimesh/notenoughindices.obj", 1,
               {"ignored 1 face with fewer than 3 corners (the first at line 9)"}),
        accept("malformed/trimesh/polygonfaces.obj", 3),
        accept("malformed/trimesh/shared.STL", 24),
        accept("malformed/trimesh/soup.stl", 100, {"only 0.997"}),
        refuse("malformed/trimesh/stl_empty_bin.stl", {"no triangles"}),
        accept("malformed/trimesh/wallhole.obj", 66),
    };
    return table;
}

// gtest prints parameters by name rather than as bytes.
void PrintTo(const Decision& d, std::ostream* os) {
    *os << d.path;
}

class Malformed : public ::testing::TestWithParam<Decision> {};

TEST_P(Malformed, AcceptedWithWarningsOrRefused) {
    const Decision& d = GetParam();
    auto r = read_mesh(testdata(d.path));
    if (d.accepted) {
        ASSERT_TRUE(r) << d.path << ": " << r.error().describe();
        EXPECT_EQ(r->mesh.triangles.size(), d.triangles) << d.path;
        ASSERT_EQ(r->warnings.size(), d.expected.size()) << d.path << joined(r->warnings);
        for (std::size_t i = 0; i < d.expected.size(); ++i) {
            EXPECT_TRUE(contains(r->warnings[i], d.expected[i]))
                << d.path << ": warning " << i << " is '" << r->warnings[i] << "'";
        }
    } else {
        ASSERT_FALSE(r) << d.path << " was accepted" << joined(r->warnings);
        EXPECT_EQ(r.error().code, d.code) << d.path;
        EXPECT_TRUE(contains(r.error().context, d.path)) << r.error().context;
        for (const char* part : d.expected) {
            EXPECT_TRUE(contains(r.error().message, part))
                << d.path << ": '" << r.error().message << "' lacks '" << part << "'";
        }
    }
}

std::string case_name(const std::string& path) {
    std::string s;
    for (const char ch : path.substr(std::string("malformed/").size())) {
        s += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
    }
    return s;
}

INSTANTIATE_TEST_SUITE_P(DecisionTable, Malformed, ::testing::ValuesIn(decisions()),
                         [](const auto& info) { return case_name(info.param.path); });

TEST(MalformedTable, CoversEveryFile) {
    std::set<std::string> listed;
    for (const Decision& d : decisions()) listed.insert(d.path);
    std::size_t files = 0;
    for (const auto& e : std::filesystem::recursive_directory_iterator(testdata("malformed"))) {
        if (!e.is_regular_file()) continue;
        ++files;
        const std::string rel = std::filesystem::relative(e.path(), testdata("")).generic_string();
        EXPECT_TRUE(listed.count(rel)) << rel << " has no decision";
    }
    EXPECT_EQ(files, listed.size());
}

TEST(MalformedTable, Ps001InwardPlanesStillGivePositiveVolume) {
    auto r = read_mesh(testdata("malformed/dodgy-step-files/Ps001.stp"));
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->solids, 1u);
    EXPECT_NEAR(mesh::signed_volume(r->mesh), 1.0, 1e-9);
}

}  // namespace
}  // namespace maxslice::io
