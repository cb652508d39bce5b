#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>

#include "io_test_support.hpp"
#include "maxslice/io/read_mesh.hpp"
#include "maxslice/mesh/validation.hpp"

namespace maxslice::io {
namespace {

using test::contains;
using test::joined;
using test::testdata;

TEST(Cad, FinerTessellationGivesMoreTrianglesAndCloserVolume) {
    const auto path = testdata("step/nist/nist_ftc_11_asme1_rb.stp");
    ImportOptions coarse;
    coarse.chord_deviation_mm = 0.5;
    coarse.angular_deviation_deg = 30.0;
    ImportOptions fine;
    fine.chord_deviation_mm = 0.01;
    fine.angular_deviation_deg = 5.0;
    auto a = read_mesh(path, coarse);
    auto b = read_mesh(path, fine);
    ASSERT_TRUE(a && b);
    EXPECT_LT(a->mesh.triangles.size(), b->mesh.triangles.size());
    const double brep = 5129.39;  // MANIFEST, Open CASCADE vprops
    EXPECT_LT(std::abs(mesh::signed_volume(b->mesh) - brep),
              std::abs(mesh::signed_volume(a->mesh) - brep));
}

TEST(Cad, SameFileTwiceGivesIdenticalMeshes) {
    const auto path = testdata("step/trimesh/box_sides.STEP");
    auto a = read_mesh(path);
    auto b = read_mesh(path);
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->mesh.vertices, b->mesh.vertices);
    EXPECT_EQ(a->mesh.triangles, b->mesh.triangles);
}

TEST(Cad, ReversedFacesKeepTheOutsideOut) {
    // Most faces of a machined part are reversed in their shell (holes, pockets); if their
    // triangles were not flipped the volume would be far off or negative.
    auto r = read_mesh(testdata("step/nist/nist_ctc_01_asme1_rd.stp"));
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_NEAR(mesh::signed_volume(r->mesh) / 1.46428e7, 1.0, 0.01);
}

TEST(Cad, TessellationIsClosedAndConsistentlyOriented) {
    // BRepMesh puts several nodes on degenerated edges (cone apexes, sphere poles); the
    // triangles that collapse there once welded must not show up as non-manifold edges.
    for (const char* file : {"step/nist/nist_ctc_05_asme1_rd.stp",
                             "step/nist/nist_ctc_01_asme1_rd.stp", "step/trimesh/box_sides.STEP"}) {
        auto r = read_mesh(testdata(file));
        ASSERT_TRUE(r) << r.error().describe();
        const mesh::ValidationReport v = mesh::validate(r->mesh);
        EXPECT_EQ(v.boundary_edges.count, 0u) << file;
        EXPECT_EQ(v.nonmanifold_edges.count, 0u) << file;
        EXPECT_EQ(v.misoriented_edges.count, 0u) << file;
        EXPECT_EQ(v.vertices, r->mesh.vertices.size()) << file << ": unused vertices";
        EXPECT_GT(v.volume_mm3, 0.0) << file;
    }
}

TEST(Cad, IgesSurfacesWithoutSolidAreRefused) {
    auto r = read_mesh(test::local_data("box_faces_mm.igs"));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    EXPECT_TRUE(contains(r.error().message, "no solid: the IGES file holds 6 faces"))
        << r.error().describe();
}

TEST(Cad, IgesFromOpenCascadeSamples) {
    // Debian's occt-misc ships two IGES surface models (no solids).
    const std::filesystem::path bearing = "/usr/share/opencascade/data/iges/bearing.iges";
    if (!std::filesystem::exists(bearing)) GTEST_SKIP() << "occt-misc not installed";
    auto r = read_mesh(bearing);
    ASSERT_FALSE(r);
    EXPECT_TRUE(contains(r.error().message, "no solid")) << r.error().describe();
}

TEST(Cad, OpenCascadeCrashRefusesTheFileAndWeLive) {
    // Every AXIS2_PLACEMENT_3D of a valid part pointed at a DIRECTION instead of a point:
    // Open CASCADE 7.6 dereferences a null handle (SIGSEGV) while transferring it. The
    // reader runs in a child process, so this is a refusal, not the end of the test.
    std::ifstream in(testdata("step/nist/nist_ftc_11_asme1_rb.stp"));
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::smatch direction;
    ASSERT_TRUE(std::regex_search(text, direction, std::regex(R"(#(\d+)\s*=\s*DIRECTION)")));
    const std::string broken =
        std::regex_replace(text, std::regex(R"((AXIS2_PLACEMENT_3D\s*\(\s*'[^']*'\s*,\s*)#\d+)"),
                           "$1#" + direction[1].str());
    test::ScratchDir dir;
    auto r = read_mesh(dir.write("crash.stp", broken));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    EXPECT_TRUE(contains(r.error().message, "Open CASCADE")) << r.error().describe();
    // And the next file reads normally.
    EXPECT_TRUE(read_mesh(testdata("step/oasis/Subminiature_Tensile_Bar_Blank_1.stp")));
}

TEST(Cad, TimeLimitStopsTheReader) {
    ImportOptions o;
    o.library_time_limit_s = 0.01;
    auto r = read_mesh(testdata("step/nist/nist_ctc_02_asme1_rc.stp"), o);
    ASSERT_FALSE(r);
    EXPECT_TRUE(contains(r.error().message,
                         "Open CASCADE did not finish reading the file within the 0.01 s limit"))
        << r.error().describe();
    // STEP and IGES are tessellated: the tolerance is the one thing that can help.
    EXPECT_TRUE(contains(r.error().message, "--chord-deviation")) << r.error().describe();
}

bool open_cascade_is_mapped() {
    std::ifstream maps("/proc/self/maps");
    const std::string text{std::istreambuf_iterator<char>(maps), {}};
    return text.find("libTKernel") != std::string::npos;
}

TEST(Cad, OpenCascadeIsLoadedOnlyInTheChildThatReadsTheFile) {
    // It takes ~30 ms to load (cad_plugin.cpp): a program that reads a STEP file must not
    // map it, nor must one that never reads such a file.
    EXPECT_FALSE(open_cascade_is_mapped());
    auto r = read_mesh(testdata("step/nist/nist_ftc_11_asme1_rb.stp"));
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_GT(r->mesh.triangles.size(), 1000u);
    EXPECT_FALSE(open_cascade_is_mapped());
}

// Sets an environment variable for one scope.
class ScopedEnv {
public:
    ScopedEnv(const char* name, const std::string& value) : name_(name) {
        ::setenv(name, value.c_str(), 1);
    }
    ScopedEnv(const ScopedEnv&) = delete;
    ScopedEnv& operator=(const ScopedEnv&) = delete;
    ~ScopedEnv() { ::unsetenv(name_); }

private:
    const char* name_;
};

TEST(Cad, AMissingOrForeignReaderModuleIsAClearRefusal) {
    const auto step = testdata("step/nist/nist_ftc_11_asme1_rb.stp");
    {
        const ScopedEnv env("MAXSLICE_CAD_PLUGIN", "/nonexistent/libmaxslice_cad.so");
        auto r = read_mesh(step);
        ASSERT_FALSE(r);
        EXPECT_EQ(r.error().code, core::ErrorCode::kUnsupported);
        EXPECT_TRUE(contains(r.error().message, "is not installed")) << r.error().message;
        EXPECT_TRUE(contains(r.error().message, "/nonexistent/libmaxslice_cad.so"));
    }
    {
        const ScopedEnv env("MAXSLICE_CAD_PLUGIN", step.string());  // not a shared library
        auto r = read_mesh(step);
        ASSERT_FALSE(r);
        EXPECT_EQ(r.error().code, core::ErrorCode::kUnsupported);
        EXPECT_TRUE(contains(r.error().message, "cannot load")) << r.error().message;
    }
    EXPECT_TRUE(read_mesh(step));  // and the module found by itself again
}

TEST(Cad, GarbageAfterStepSignatureIsRefused) {
    test::ScratchDir dir;
    auto r = read_mesh(dir.write("x.step", "ISO-10303-21;\nHEADER;\nthis is not step\n"));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    EXPECT_TRUE(contains(r.error().message, "STEP")) << r.error().describe();
}

TEST(Cad, NotAZipIsRefusedAs3mf) {
    test::ScratchDir dir;
    auto r = read_mesh(dir.write("x.3mf", "this is not a zip file"));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    EXPECT_TRUE(contains(r.error().message, "3MF")) << r.error().describe();
    r = read_mesh(dir.write("y.3mf", std::string("PK\x03\x04", 4) + std::string(100, '\0')));
    ASSERT_FALSE(r);
    EXPECT_TRUE(contains(r.error().message, "3MF")) << r.error().describe();
}

}  // namespace
}  // namespace maxslice::io
