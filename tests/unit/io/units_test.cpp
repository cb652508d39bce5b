#include <gtest/gtest.h>

#include <algorithm>

#include "io_test_support.hpp"
#include "maxslice/core/tolerances.hpp"
#include "maxslice/io/read_mesh.hpp"
#include "support/fixtures.hpp"

namespace maxslice::io {
namespace {

using test::contains;
using test::joined;
using test::testdata;

double largest_extent(const mesh::TriangleMesh& m) {
    const core::Vec3d s = mesh::bounding_box(m).size();
    return std::max({s.x, s.y, s.z});
}

ImportOptions in_units(core::LengthUnit u) {
    ImportOptions o;
    o.units = u;
    return o;
}

bool has_units_hint(const ImportedMesh& m) {
    return std::any_of(m.warnings.begin(), m.warnings.end(),
                       [](const std::string& w) { return contains(w, "--units"); });
}

TEST(Units, StlIsMillimetresUnlessOverridden) {
    const auto path = testdata("meshes/trimesh/featuretype.STL");
    auto mm = read_mesh(path);
    ASSERT_TRUE(mm) << mm.error().describe();
    EXPECT_EQ(mm->source_unit, core::LengthUnit::kMillimetre);
    EXPECT_FALSE(mm->unit_declared);
    EXPECT_NEAR(largest_extent(mm->mesh), 5.0, 1e-6);
    auto inch = read_mesh(path, in_units(core::LengthUnit::kInch));
    ASSERT_TRUE(inch) << inch.error().describe();
    EXPECT_EQ(inch->source_unit, core::LengthUnit::kInch);
    EXPECT_NEAR(largest_extent(inch->mesh), 127.0, 1e-4);
    EXPECT_TRUE(inch->warnings.empty()) << joined(inch->warnings);
}

TEST(Units, BunnyInMetresGetsAHintUntilOverridden) {
    const auto path = testdata("meshes/stl-models/bunny.bin.stl");
    auto plain = read_mesh(path);
    ASSERT_TRUE(plain) << plain.error().describe();
    EXPECT_LT(largest_extent(plain->mesh), core::kImplausiblySmallPartMm);
    ASSERT_EQ(plain->warnings.size(), 1u) << joined(plain->warnings);
    EXPECT_TRUE(contains(plain->warnings[0], "--units m")) << joined(plain->warnings);
    auto metres = read_mesh(path, in_units(core::LengthUnit::kMetre));
    ASSERT_TRUE(metres) << metres.error().describe();
    EXPECT_NEAR(largest_extent(metres->mesh), 155.7, 0.1);
    EXPECT_FALSE(has_units_hint(*metres)) << joined(metres->warnings);
}

TEST(Units, ImplausiblyLargePartGetsAHint) {
    test::ScratchDir dir;
    const auto path = dir.path() / "huge.stl";
    ASSERT_TRUE(write_stl_binary(path, maxslice::test::box({0, 0, 0}, {20000, 500, 500})));
    auto r = read_mesh(path);
    ASSERT_TRUE(r) << r.error().describe();
    ASSERT_EQ(r->warnings.size(), 1u) << joined(r->warnings);
    EXPECT_TRUE(contains(r->warnings[0], "20000 mm across")) << joined(r->warnings);
    auto um = read_mesh(path, in_units(core::LengthUnit::kMicron));
    ASSERT_TRUE(um) << um.error().describe();
    EXPECT_NEAR(largest_extent(um->mesh), 20.0, 1e-9);
    EXPECT_TRUE(um->warnings.empty()) << joined(um->warnings);
}

TEST(Units, ThreeMfDeclaredUnitAndOverride) {
    const auto path = testdata("meshes/trimesh/featuretype.3MF");
    auto declared = read_mesh(path);
    ASSERT_TRUE(declared) << declared.error().describe();
    EXPECT_TRUE(declared->unit_declared);
    EXPECT_EQ(declared->source_unit, core::LengthUnit::kInch);
    EXPECT_NEAR(largest_extent(declared->mesh), 127.0, 1e-4);
    // --units says what the numbers are, whatever the file declares.
    auto mm = read_mesh(path, in_units(core::LengthUnit::kMillimetre));
    ASSERT_TRUE(mm) << mm.error().describe();
    EXPECT_EQ(mm->source_unit, core::LengthUnit::kMillimetre);
    EXPECT_NEAR(largest_extent(mm->mesh), 5.0, 1e-6);
    EXPECT_TRUE(std::any_of(mm->warnings.begin(), mm->warnings.end(), [](const std::string& w) {
        return contains(w, "declares 'in'; --units mm overrides it");
    })) << joined(mm->warnings);
}

TEST(Units, StepDeclaredUnitAndOverride) {
    const auto path = testdata("step/trimesh/featuretype.STEP");
    auto declared = read_mesh(path);
    ASSERT_TRUE(declared) << declared.error().describe();
    EXPECT_TRUE(declared->unit_declared);
    EXPECT_EQ(declared->source_unit, core::LengthUnit::kInch);
    EXPECT_NEAR(largest_extent(declared->mesh), 127.0, 1e-3);
    // Open CASCADE converted inch to mm; --units mm takes the file's numbers as mm.
    auto mm = read_mesh(path, in_units(core::LengthUnit::kMillimetre));
    ASSERT_TRUE(mm) << mm.error().describe();
    EXPECT_NEAR(largest_extent(mm->mesh), 5.0, 1e-4);
    auto same = read_mesh(path, in_units(core::LengthUnit::kInch));
    ASSERT_TRUE(same) << same.error().describe();
    EXPECT_EQ(same->mesh.vertices, declared->mesh.vertices);
}

TEST(Units, IgesDeclaredUnit) {
    // The same 10 x 20 x 5 mm box written by Open CASCADE in mm and in inches.
    for (const char* name : {"box_brep_mm.igs", "box_brep_inch.igs"}) {
        auto r = read_mesh(test::local_data(name));
        ASSERT_TRUE(r) << r.error().describe();
        EXPECT_EQ(r->format, Format::kIges);
        EXPECT_EQ(r->solids, 1u);
        EXPECT_TRUE(r->unit_declared);
        EXPECT_NEAR(mesh::signed_volume(r->mesh), 1000.0, 1e-6) << name;
        EXPECT_NEAR(largest_extent(r->mesh), 20.0, 1e-6) << name;
    }
    auto inch = read_mesh(test::local_data("box_brep_inch.igs"));
    ASSERT_TRUE(inch);
    EXPECT_EQ(inch->source_unit, core::LengthUnit::kInch);
}

}  // namespace
}  // namespace maxslice::io
