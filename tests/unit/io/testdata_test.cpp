// Every model of the shared test data (testdata/MANIFEST.md) loads with the MANIFEST's
// triangle count and bounding box (meshes) or solid count, bounding box and volume (STEP).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "io_test_support.hpp"
#include "maxslice/io/read_mesh.hpp"

namespace maxslice::io {
namespace {

using test::joined;
using test::testdata;

struct Box {
    double min[3];
    double max[3];
};

// The MANIFEST prints 4 significant digits: allow 1e-3 of the value or of the part size.
void expect_box(const mesh::TriangleMesh& m, const Box& want, double scale, double slack,
                const std::string& name) {
    const core::Box3d got = mesh::bounding_box(m);
    const core::Vec3d size = got.size();
    const double extent = std::max({size.x, size.y, size.z});
    for (int a = 0; a < 3; ++a) {
        const double lo = want.min[a] * scale;
        const double hi = want.max[a] * scale;
        EXPECT_NEAR(got.min[a], lo, 1e-3 * std::max(std::abs(lo), extent) + slack)
            << name << " axis " << a;
        EXPECT_NEAR(got.max[a], hi, 1e-3 * std::max(std::abs(hi), extent) + slack)
            << name << " axis " << a;
    }
}

struct MeshCase {
    const char* path;
    Format format;
    std::size_t triangles;
    Box box;                   // file units
    double mm_per_unit = 1.0;  // 3MF files declaring inch come out in mm
    std::size_t warnings = 0;  // only the units hint is expected, for parts in metres/inches
};

const MeshCase kMeshes[] = {
    {"meshes/cura/nozzle.stl", Format::kStlBinary, 4204, {{-3.874, -3.5, 0}, {3.874, 3.5, 17}}},
    {"meshes/netgen/part1.stl",
     Format::kStlAscii,
     380,
     {{0.8052, 2.528, 3.333}, {6.805, 7.528, 6.333}}},
    {"meshes/oasis/NIST_Test_Artifact_ver3b.stl",
     Format::kStlBinary,
     7392,
     {{0, 0, 0}, {141.4, 141.4, 17}}},
    {"meshes/oasis/Parameter_quality_nut_1.stl",
     Format::kStlBinary,
     414,
     {{34.29, -39.95, 0}, {46.99, -17.47, 22.23}}},
    {"meshes/oasis/SingleStripe_markings.stl",
     Format::kStlBinary,
     10048,
     {{-36.31, -98.9, 0}, {36.07, 99.01, 0.05}}},
    {"meshes/oasis/Spiral_lattice_cone_1.stl",
     Format::kStlBinary,
     56458,
     {{9.373, -21.92, 0}, {30.01, -1.283, 64.3}}},
    {"meshes/occt/propeller.stl", Format::kStlAscii, 7375, {{-475, -475, -127.5}, {475, 475, 75}}},
    {"meshes/openscad/adns2610_dev_circuit_inv.stl",
     Format::kStlBinary,
     900,
     {{-5, -7, 0}, {10, 21, 3.2}}},
    {"meshes/prusaslicer/M3x10_screw.stl",
     Format::kStlBinary,
     15532,
     {{-2.75, -2.75, 0}, {2.75, 2.75, 13}}},
    {"meshes/prusaslicer/PLA_recycling_symbol.stl",
     Format::kStlBinary,
     1244,
     {{169.5, 72.43, 0.5}, {192.5, 102, 0.9}}},
    {"meshes/stl-models/bunny.bin.stl",
     Format::kStlBinary,
     69451,
     {{-0.0947, 0.033, -0.0619}, {0.061, 0.1873, 0.0588}},
     1.0,
     1},
    {"meshes/stl-models/gearwheel.ascii.stl",
     Format::kStlAscii,
     2444,
     {{-20.86, -20.86, 0}, {20.86, 20.86, 8}}},
    {"meshes/stl-models/gearwheel.bin.stl",
     Format::kStlBinary,
     2444,
     {{-20.86, -20.86, 0}, {20.86, 20.86, 8}}},
    {"meshes/trimesh/1002_tray_bottom.STL",
     Format::kStlAscii,
     4520,
     {{0, 0, -355.6}, {355.6, 3.175, 0}}},
    {"meshes/trimesh/angle_block.STL",
     Format::kStlBinary,
     704,
     {{-0.6693, 0, -1.352}, {0.6693, 1, 0}}},
    {"meshes/trimesh/counterXP.3MF",
     Format::k3mf,
     83750,
     {{-111.5, 5.779, 255.9}, {193.3, 310.2, 281.7}},
     1.0,
     1},  // + lib3mf conformance note
    {"meshes/trimesh/cube_and_sphere_same_name.3mf",
     Format::k3mf,
     5132,
     {{-20, -20, 0}, {72.8, 20, 40}}},
    {"meshes/trimesh/fandisk.obj",
     Format::kObj,
     5750,
     {{-0.8727, -0.4537, -0.7904}, {0.8181, 0.4104, 0.7662}}},
    {"meshes/trimesh/featuretype.3MF",
     Format::k3mf,
     2208,
     {{-2.5, -1.25, 0}, {2.5, 1.25, 1.375}},
     25.4},
    {"meshes/trimesh/featuretype.STL",
     Format::kStlBinary,
     3476,
     {{-2.5, -1.25, 0}, {2.5, 1.25, 1.375}}},
    {"meshes/trimesh/idler_riser.STL",
     Format::kStlBinary,
     1572,
     {{-0.078, 0, 0}, {2.578, 2.953, 0.625}}},
    {"meshes/trimesh/plate_holes.STL", Format::kStlBinary, 1252, {{0, 0, 0}, {203.2, 304.8, 12.7}}},
    {"meshes/trimesh/pyramids.3mf",
     Format::k3mf,
     3276,
     {{5.012, 5.024, 10.03}, {351.7, 168.1, 35.02}}},
    {"meshes/trimesh/round.stl",
     Format::kStlBinary,
     1120,
     {{-2.54, -2.54, 0}, {2.54, 2.54, 60.96}}},
    {"meshes/trimesh/tube.obj",
     Format::kObj,
     120,
     {{-0.8325, 0, -0.8325}, {0.8325, 11.84, 0.8325}}},
    {"large/Spiral_lattice_cone_2_occt.stl",
     Format::kStlBinary,
     511378,
     {{17.37, 1.283, 0}, {38.01, 21.92, 64.3}}},
};

// gtest prints parameters by name rather than as bytes.
void PrintTo(const MeshCase& c, std::ostream* os) {
    *os << c.path;
}

class TestdataMeshes : public ::testing::TestWithParam<MeshCase> {};

TEST_P(TestdataMeshes, LoadWithManifestCountsAndBox) {
    const MeshCase& c = GetParam();
    auto r = read_mesh(testdata(c.path));
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->format, c.format);
    EXPECT_EQ(r->mesh.triangles.size(), c.triangles);
    EXPECT_EQ(r->warnings.size(), c.warnings) << c.path << joined(r->warnings);
    expect_box(r->mesh, c.box, c.mm_per_unit, 0.0, c.path);
    for (const mesh::Triangle& t : r->mesh.triangles) {
        for (const std::uint32_t v : t) ASSERT_LT(v, r->mesh.vertices.size());
    }
}

std::string case_name(const std::string& path) {
    std::string s;
    for (const char ch : path) s += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
    return s;
}

INSTANTIATE_TEST_SUITE_P(Manifest, TestdataMeshes, ::testing::ValuesIn(kMeshes),
                         [](const auto& info) { return case_name(info.param.path); });

struct StepCase {
    const char* path;
    std::size_t solids;
    Box box;        // solids only, mm
    double volume;  // mm^3
    const char* note = "";
};

// Volumes and boxes from the MANIFEST (Open CASCADE vprops / bounding), except where the
// note says otherwise.
const StepCase kSteps[] = {
    {"step/nist/nist_ctc_01_asme1_ap242-e1.stp",
     1,
     {{-400, -225, -100}, {400, 225, 50}},
     1.46448e7},
    {"step/nist/nist_ctc_01_asme1_rd.stp", 1, {{-400, -225, -100}, {400, 225, 50}}, 1.46428e7},
    // The MANIFEST's 4.7848e7 includes a closed shell outside the solid, which maxslice does
    // not read (solids only); Open CASCADE gives the solid alone 4.71005e7.
    {"step/nist/nist_ctc_02_asme1_rc.stp",
     1,
     {{-340, -40, -360}, {340, 820, 40}},
     4.71005e7,
     "solid only"},
    {"step/nist/nist_ctc_03_asme1_rc.stp", 1, {{-249.6, 0, 0}, {53.4, 485.4, 162.7}}, 331938},
    {"step/nist/nist_ctc_04_asme1_rd.stp", 1, {{-250, 0, -100.6}, {250, 780, 30}}, 1.75186e7},
    // As CTC-2: MANIFEST 1.2829e7 with the extra shell, 1.26949e7 for the solid.
    {"step/nist/nist_ctc_05_asme1_rd.stp",
     1,
     {{-263.5, -279.4, 0}, {263.5, 279.4, 482.6}},
     1.26949e7,
     "solid only"},
    {"step/nist/nist_ftc_06_asme1_rd.stp", 1, {{-152.4, 0, -247.7}, {152.4, 97.79, 0}}, 3.32355e6},
    {"step/nist/nist_ftc_07_asme1_rd.stp",
     1,
     {{-155.8, -123.2, -111.4}, {155.8, 12.7, 111.4}},
     1.72625e6},
    {"step/nist/nist_ftc_08_asme1_rc.stp", 1, {{-155.8, -111.3, 0}, {155.8, 111.3, 48.26}}, 503592},
    {"step/nist/nist_ftc_09_asme1_rd.stp", 1, {{-95.25, 0, -139.7}, {95.25, 3.038, 139.7}}, 136445},
    {"step/nist/nist_ftc_10_asme1_rb.stp", 1, {{-79, 0, -37.5}, {79, 31, 37.5}}, 188318},
    {"step/nist/nist_ftc_11_asme1_rb.stp", 1, {{-31.5, -31.5, -1.5}, {31.5, 31.5, 1.5}}, 5129.39},
    {"step/oasis/NIST_Test_Artifact_ver3b.step",
     1,
     {{-70.71, -70.71, -10}, {70.71, 70.71, 7}},
     100987},
    {"step/oasis/Parameter_quality_nut_1.stp",
     1,
     {{34.29, -39.95, 0}, {46.99, -17.47, 22.23}},
     4423.15},
    {"step/oasis/Subminiature_Tensile_Bar_Blank_1.stp",
     1,
     {{44.26, -76.6, 0}, {49.98, -42.95, 5.715}},
     1099.21},
    {"step/trimesh/base_interface_AP203.STEP",
     1,
     {{-299.7, -319.3, -2.381}, {299.7, 319.3, 2.381}},
     1.25799e6},
    // The MANIFEST counts 6 distinct solid shapes (nbshapes); placed in the assembly they
    // are 10 solids, and the MANIFEST's volume is that of all 10.
    {"step/trimesh/box_sides.STEP",
     10,
     {{-18.45, 46.72, 112.6}, {165.7, 161, 207.8}},
     263542,
     "10 placed instances of 6 shapes"},
    {"step/trimesh/featuretype.STEP", 1, {{-63.5, -31.75, 0}, {63.5, 31.75, 34.92}}, 190532},
};

void expect_step(const StepCase& c, const ImportOptions& options) {
    auto r = read_mesh(testdata(c.path), options);
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->format, Format::kStep);
    EXPECT_EQ(r->solids, c.solids) << c.note;
    EXPECT_TRUE(r->unit_declared);
    EXPECT_NEAR(mesh::signed_volume(r->mesh) / c.volume, 1.0, 0.01) << c.path << " " << c.note;
    expect_box(r->mesh, c.box, 1.0, options.chord_deviation_mm, c.path);
    for (const std::string& w : r->warnings) {
        EXPECT_TRUE(test::contains(w, "not part of a solid")) << c.path << ": " << w;
    }
}

// gtest prints parameters by name rather than as bytes.
void PrintTo(const StepCase& c, std::ostream* os) {
    *os << c.path;
}

class TestdataSteps : public ::testing::TestWithParam<StepCase> {};

TEST_P(TestdataSteps, SolidsBoxAndVolumeMatchManifest) {
    expect_step(GetParam(), {});
}

INSTANTIATE_TEST_SUITE_P(Manifest, TestdataSteps, ::testing::ValuesIn(kSteps),
                         [](const auto& info) { return case_name(info.param.path); });

// The spiral lattice's struts are thin: at 15 degrees their polygons lose about 1.7 % of
// the volume; at the default 10 degrees about 0.7 % (like the MANIFEST's own 0.02 mm /
// 10 degree tessellation). Slow (3.7 MB of STEP, 0.5 M triangles): about 30 s.
TEST(TestdataStepsSlow, SpiralLatticeCone2) {
    expect_step({"step/oasis/Spiral_lattice_cone_2.stp",
                 1,
                 {{17.37, 1.283, 0}, {38.01, 21.92, 64.31}},
                 831.633},
                {});
}

TEST(Testdata, EveryModelFileIsInTheTables) {
    std::set<std::string> listed;
    for (const MeshCase& c : kMeshes) listed.insert(c.path);
    for (const StepCase& c : kSteps) listed.insert(c.path);
    listed.insert("step/oasis/Spiral_lattice_cone_2.stp");
    for (const char* dir : {"meshes", "step", "large"}) {
        for (const auto& e : std::filesystem::recursive_directory_iterator(testdata(dir))) {
            if (!e.is_regular_file()) continue;
            const std::string rel =
                std::filesystem::relative(e.path(), testdata("")).generic_string();
            EXPECT_TRUE(listed.count(rel)) << rel << " is not tested";
        }
    }
}

TEST(Testdata, GearwheelAsciiAndBinaryHoldTheSameTriangles) {
    auto a = read_mesh(testdata("meshes/stl-models/gearwheel.ascii.stl"));
    auto b = read_mesh(testdata("meshes/stl-models/gearwheel.bin.stl"));
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->format, Format::kStlAscii);
    EXPECT_EQ(b->format, Format::kStlBinary);
    // The ASCII copy prints 7 significant digits of the binary copy's floats, so the two
    // weld to the same triangles over vertices that agree to that precision.
    EXPECT_EQ(a->mesh.triangles, b->mesh.triangles);
    ASSERT_EQ(a->mesh.vertices.size(), b->mesh.vertices.size());
    for (std::size_t v = 0; v < a->mesh.vertices.size(); ++v) {
        for (int k = 0; k < 3; ++k) {
            const double x = a->mesh.vertices[v][k];
            const double y = b->mesh.vertices[v][k];
            ASSERT_NEAR(x, y, 1e-6 * std::max(1.0, std::abs(y))) << "vertex " << v;
        }
    }
}

TEST(Testdata, FeaturetypeStlThreeMfAndStepAgree) {
    ImportOptions inch;
    inch.units = core::LengthUnit::kInch;
    auto stl = read_mesh(testdata("meshes/trimesh/featuretype.STL"), inch);
    auto tmf = read_mesh(testdata("meshes/trimesh/featuretype.3MF"));
    auto step = read_mesh(testdata("step/trimesh/featuretype.STEP"));
    ASSERT_TRUE(stl && tmf && step);
    const double v_stl = mesh::signed_volume(stl->mesh);
    const double v_3mf = mesh::signed_volume(tmf->mesh);
    const double v_step = mesh::signed_volume(step->mesh);
    EXPECT_NEAR(v_stl / v_step, 1.0, 0.01);
    EXPECT_NEAR(v_3mf / v_step, 1.0, 0.01);
    EXPECT_NEAR(v_stl / v_3mf, 1.0, 0.01);
    EXPECT_NEAR(v_step / 190532.0, 1.0, 0.01);
}

}  // namespace
}  // namespace maxslice::io
