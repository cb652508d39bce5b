// The planner's fixtures are the yardstick of its tests: each is checked here for what it
// promises (one closed outward body, its analytic volume, box and sections, and the features
// the planner relies on: overhangs that do not touch the plate, separate legs, a narrow slot).
#include "support/planner_fixtures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "maxslice/geom2d/polygon.hpp"
#include "maxslice/mesh/validation.hpp"
#include "maxslice/slice/slicer.hpp"

namespace maxslice::test {
namespace {

using core::Vec3d;
using mesh::TriangleMesh;

// As in slicer_test: 0.5% of the area, plus the change of area that rounding each boundary
// point to the micrometre grid can make (perimeter x 1 um).
constexpr double kAreaRelative = 0.005;
constexpr double kGridMm = 0.001;
constexpr double kUmPerMm = 1000.0;

const std::vector<PlannerFixture>& fixtures() {
    static const std::vector<PlannerFixture> all = all_planner_fixtures();
    return all;
}

struct Section {
    double z = 0.0;  // height of the cutting plane (mm)
    slice::Slice slice;
};

// Horizontal sections at the middle of uniform layers from the plate up.
std::vector<Section> sections(const TriangleMesh& m, double layer_mm = 0.5) {
    const slice::PlaneFrame base = slice::base_frame(m, {0, 0, 1});
    const auto [lo, hi] = slice::extent_along(m, base);
    const auto layers = slice::uniform_layers(lo, hi, layer_mm);
    auto slices = slice::slice_mesh(m, base, layers);
    EXPECT_TRUE(slices.has_value()) << (slices ? "" : slices.error().describe());
    std::vector<Section> out;
    if (!slices) return out;
    for (slice::Slice& s : *slices) {
        const double z = base.origin.z + s.span.cut;
        out.push_back({z, std::move(s)});
    }
    return out;
}

double perimeter_mm(const geom2d::Paths2& paths) {
    double sum = 0.0;
    for (const geom2d::Path2& p : paths) sum += geom2d::perimeter_mm(p);
    return sum;
}

struct Range {
    double min = std::numeric_limits<double>::infinity();
    double max = -std::numeric_limits<double>::infinity();
};

// Extent along x (mm) of each top-level outer wire of a section, sorted by its start.
std::vector<Range> outer_x_ranges(const slice::Slice& s) {
    std::vector<Range> out;
    for (const geom2d::WireNode& n : s.wires.nodes) {
        if (n.is_hole || n.parent >= 0) continue;
        Range r;
        for (const geom2d::Point2& p : n.wire) {
            r.min = std::min(r.min, static_cast<double>(p.x) / kUmPerMm);
            r.max = std::max(r.max, static_cast<double>(p.x) / kUmPerMm);
        }
        out.push_back(r);
    }
    std::ranges::sort(out, {}, &Range::min);
    return out;
}

Range x_range(const slice::Slice& s) {
    Range r;
    for (const Range& o : outer_x_ranges(s)) {
        r.min = std::min(r.min, o.min);
        r.max = std::max(r.max, o.max);
    }
    return r;
}

// Total area (mm^2) of the triangles lying in the plane z = 0 and facing down.
double footprint_mm2(const TriangleMesh& m) {
    double sum = 0.0;
    for (std::size_t i = 0; i < m.triangles.size(); ++i) {
        const auto& t = m.triangles[i];
        if (m.vertices[t[0]].z != 0.0 || m.vertices[t[1]].z != 0.0 || m.vertices[t[2]].z != 0.0) {
            continue;
        }
        sum -= 0.5 * mesh::area_vector(m, i).z;
    }
    return sum;
}

// Lowest z (mm) of the vertices that satisfy pred.
template <typename Pred>
double lowest_where(const TriangleMesh& m, Pred pred) {
    double z = std::numeric_limits<double>::infinity();
    for (const Vec3d& p : m.vertices) {
        if (pred(p)) z = std::min(z, p.z);
    }
    return z;
}

void expect_one_closed_body(const TriangleMesh& m, const std::string& what) {
    const mesh::ValidationReport r = mesh::validate(m);
    std::string defects;
    for (const std::string& d : r.defects()) defects += d + "; ";
    EXPECT_TRUE(r.closed_manifold()) << what << ": " << defects;
    EXPECT_EQ(r.boundary_edges.count, 0u) << what;
    EXPECT_EQ(r.nonmanifold_edges.count, 0u) << what;
    EXPECT_EQ(r.misoriented_edges.count, 0u) << what;
    EXPECT_EQ(r.degenerate_triangles.count, 0u) << what;
    EXPECT_EQ(r.duplicate_triangles.count, 0u) << what;
    EXPECT_EQ(r.nonfinite_vertices.count, 0u) << what;
    EXPECT_EQ(r.bodies, 1u) << what;
    EXPECT_EQ(r.vertices, m.vertices.size()) << what << ": unused vertices";
    EXPECT_GT(r.volume_mm3, 0.0) << what;
    EXPECT_FALSE(r.inside_out()) << what;
}

// ---- Properties of every fixture ---------------------------------------------------------

class PlannerFixtureTest : public ::testing::TestWithParam<std::size_t> {
protected:
    const PlannerFixture& fixture() const { return fixtures()[GetParam()]; }
};

TEST_P(PlannerFixtureTest, IsOneClosedManifoldOutwardBody) {
    const PlannerFixture& f = fixture();
    ASSERT_FALSE(f.mesh.triangles.empty());
    EXPECT_FALSE(f.description.empty());
    expect_one_closed_body(f.mesh, f.name);
}

TEST_P(PlannerFixtureTest, VolumeMatchesTheAnalyticVolume) {
    const PlannerFixture& f = fixture();
    ASSERT_GT(f.volume_mm3, 0.0);
    EXPECT_LE(f.volume_accuracy, kAreaRelative);
    EXPECT_NEAR(mesh::validate(f.mesh).volume_mm3, f.volume_mm3, f.volume_accuracy * f.volume_mm3);
}

TEST_P(PlannerFixtureTest, BoundingBoxIsAsSpecified) {
    const PlannerFixture& f = fixture();
    const core::Box3d box = mesh::validate(f.mesh).bounding_box;
    const Vec3d size = f.box.size();
    const double tol = 1e-9 * std::max({size.x, size.y, size.z});
    for (int axis = 0; axis < 3; ++axis) {
        EXPECT_NEAR(box.min[axis], f.box.min[axis], tol) << "axis " << axis;
        EXPECT_NEAR(box.max[axis], f.box.max[axis], tol) << "axis " << axis;
    }
    EXPECT_EQ(box.min.z, 0.0) << "the part stands on the plate";
}

TEST_P(PlannerFixtureTest, StandsOnThePlateOnAFace) {
    const PlannerFixture& f = fixture();
    const double footprint = footprint_mm2(f.mesh);
    EXPECT_GT(footprint, 1.0);
    if (f.area_at) {
        EXPECT_NEAR(footprint, f.area_at(0.0), 1e-9 * footprint);
        EXPECT_EQ(f.area_at(-1e-9), 0.0);
        EXPECT_EQ(f.area_at(f.box.max.z), 0.0) << "sections are taken just above z";
    }
}

TEST_P(PlannerFixtureTest, AreaFunctionIntegratesToTheVolume) {
    const PlannerFixture& f = fixture();
    if (!f.area_at) GTEST_SKIP() << f.name << " has no closed-form section area";
    const int n = 50000;
    const double dz = f.box.max.z / n;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) sum += f.area_at((i + 0.5) * dz) * dz;
    EXPECT_NEAR(sum, f.volume_mm3, 1e-4 * f.volume_mm3);
}

TEST_P(PlannerFixtureTest, SlicedSectionsMatchTheAreaFunction) {
    const PlannerFixture& f = fixture();
    if (!f.area_at) GTEST_SKIP() << f.name << " has no closed-form section area";
    const std::vector<Section> all = sections(f.mesh);
    ASSERT_GE(all.size(), 20u);
    for (const Section& s : all) {
        SCOPED_TRACE(f.name + " z " + std::to_string(s.z));
        const double expected = f.area_at(s.z);
        EXPECT_GT(expected, 0.0);
        EXPECT_NEAR(s.slice.area_mm2(), expected,
                    kAreaRelative * expected + kGridMm * perimeter_mm(s.slice.wires.paths()));
        EXPECT_EQ(s.slice.gaps_closed, 0);
        EXPECT_EQ(s.slice.open_chains, 0);
    }
}

INSTANTIATE_TEST_SUITE_P(All, PlannerFixtureTest,
                         ::testing::Range<std::size_t>(0, fixtures().size()),
                         [](const auto& info) { return fixtures()[info.param].name; });

TEST(PlannerFixtures, NamesAreUnique) {
    std::vector<std::string> names;
    for (const PlannerFixture& f : fixtures()) names.push_back(f.name);
    std::ranges::sort(names);
    EXPECT_EQ(std::ranges::adjacent_find(names), names.end());
    EXPECT_EQ(names.size(), 18u);
}

// ---- Construction helpers ----------------------------------------------------------------

TEST(PolygonCap, ConcavePolygonWithHolesIsCoveredOnce) {
    // An L with three holes of different shapes; the cap's area counts overlaps twice and
    // gaps not at all, so only an exact covering matches.
    const std::vector<CapPoint> outline{{0, 0}, {30, 0}, {30, 10}, {10, 10}, {10, 30}, {0, 30}};
    const std::vector<std::vector<CapPoint>> holes{
        regular_polygon({5, 5}, 3.0, 12),
        regular_polygon({20, 5}, 2.0, 7),
        {{3, 20}, {7, 20}, {7, 26}, {3, 26}},
    };
    const Cap cap = polygon_cap(outline, holes);
    const double expected =
        500.0 - regular_polygon_area(3.0, 12) - regular_polygon_area(2.0, 7) - 24.0;
    EXPECT_NEAR(cap_area(cap), expected, 1e-9);
    EXPECT_EQ(cap.vertices.size(), 6u + 12u + 7u + 4u) << "no points added";
    expect_one_closed_body(extrude(cap, 0.0, 2.0), "extruded L with holes");
}

TEST(PolygonCap, HolesAlignedWithOuterVerticesAreJoined) {
    // Holes whose rightmost points lie on the same lines as outer vertices and each other.
    const std::vector<CapPoint> outline = regular_polygon({0, 0}, 20.0, 16);
    std::vector<std::vector<CapPoint>> holes;
    for (int i = 0; i < 6; ++i) {
        const double a = 2.0 * std::numbers::pi * i / 6;
        holes.push_back(regular_polygon({10.0 * std::cos(a), 10.0 * std::sin(a)}, 2.0, 8));
    }
    holes.push_back(regular_polygon({0, 0}, 3.0, 16));
    const Cap cap = polygon_cap(outline, holes);
    EXPECT_NEAR(cap_area(cap),
                regular_polygon_area(20.0, 16) - 6 * regular_polygon_area(2.0, 8) -
                    regular_polygon_area(3.0, 16),
                1e-9);
}

TEST(PolygonCap, RejectsAClockwiseOutline) {
    const std::vector<CapPoint> cw{{0, 0}, {0, 1}, {1, 1}, {1, 0}};
    EXPECT_THROW((void)polygon_cap(cw), std::invalid_argument);
}

TEST(Fused, StackedExtrusionsBecomeOneBodyWithoutTheCommonFace) {
    const Cap cap = fan_cap({0, 0}, regular_polygon({0, 0}, 2.0, 12));
    const TriangleMesh pieces[] = {extrude(cap, 0.0, 1.0), extrude(cap, 1.0, 3.0)};
    const TriangleMesh m = fused(pieces);
    expect_one_closed_body(m, "stacked");
    EXPECT_NEAR(mesh::signed_volume(m), 3.0 * regular_polygon_area(2.0, 12), 1e-12);
    for (const auto& t : m.triangles) {
        EXPECT_FALSE(m.vertices[t[0]].z == 1.0 && m.vertices[t[1]].z == 1.0 &&
                     m.vertices[t[2]].z == 1.0)
            << "a face between the pieces is left inside";
    }
    EXPECT_EQ(m.vertices.size(), extrude(cap, std::vector<double>{0.0, 1.0, 3.0}).vertices.size());
}

TEST(Fused, KeepsSeparateBodiesApart) {
    const TriangleMesh pieces[] = {box({0, 0, 0}, {1, 1, 1}), box({2, 0, 0}, {3, 1, 1})};
    const mesh::ValidationReport r = mesh::validate(fused(pieces));
    EXPECT_TRUE(r.closed_manifold());
    EXPECT_EQ(r.bodies, 2u);
    EXPECT_NEAR(r.volume_mm3, 2.0, 1e-12);
}

TEST(AxisExtrusions, KeepOrientationAndMapTheProfile) {
    const Cap profile = rectangle_cap(1.0, 2.0, 4.0, 7.0);
    const mesh::ValidationReport xz = mesh::validate(extrude_xz(profile, 0.5, 3.0));
    EXPECT_NEAR(xz.volume_mm3, 15.0 * 2.5, 1e-12);
    EXPECT_EQ(xz.bounding_box.min, (Vec3d{1.0, 0.5, 2.0}));
    EXPECT_EQ(xz.bounding_box.max, (Vec3d{4.0, 3.0, 7.0}));
    const mesh::ValidationReport yz = mesh::validate(extrude_yz(profile, -1.0, 2.0));
    EXPECT_NEAR(yz.volume_mm3, 15.0 * 3.0, 1e-12);
    EXPECT_EQ(yz.bounding_box.min, (Vec3d{-1.0, 1.0, 2.0}));
    EXPECT_EQ(yz.bounding_box.max, (Vec3d{2.0, 4.0, 7.0}));
}

// ---- 1. Vertical walls -------------------------------------------------------------------

TEST(VerticalPrism, EverySectionIsTheSameLWithoutHoles) {
    const PrismSpec spec{};
    for (const Section& s : sections(vertical_prism(spec).mesh)) {
        EXPECT_EQ(s.slice.wires.outer_count(), 1u);
        EXPECT_EQ(s.slice.wires.hole_count(), 0u);
        const Range r = x_range(s.slice);
        EXPECT_NEAR(r.min, 0.0, 1e-3);
        EXPECT_NEAR(r.max, spec.leg_length, 1e-3);
    }
}

TEST(CylinderWithHoles, EverySectionHasOneOuterAndEachHole) {
    for (const HoledCylinderSpec& spec :
         {HoledCylinderSpec{}, HoledCylinderSpec{.holes = 6, .hole_circle_radius = 18.0}}) {
        const PlannerFixture f = cylinder_with_holes(spec);
        expect_one_closed_body(f.mesh, "holes " + std::to_string(spec.holes));
        EXPECT_NEAR(mesh::signed_volume(f.mesh), f.volume_mm3, 1e-9 * f.volume_mm3);
        for (const Section& s : sections(f.mesh, 2.0)) {
            EXPECT_EQ(s.slice.wires.outer_count(), 1u);
            EXPECT_EQ(s.slice.wires.hole_count(), static_cast<std::size_t>(spec.holes));
        }
    }
}

// ---- 2. Slopes ---------------------------------------------------------------------------

TEST(Ramp, SlopedFaceLeansOutOverTheBaseAtTheGivenAngle) {
    for (const double lean : {45.0, 30.0}) {
        RampSpec spec{};
        spec.lean_deg = lean;
        const PlannerFixture f = ramp_45(spec);
        expect_one_closed_body(f.mesh, "lean " + std::to_string(lean));
        const double slope = std::tan(lean * std::numbers::pi / 180.0);
        for (const Section& s : sections(f.mesh)) {
            const Range r = x_range(s.slice);
            EXPECT_NEAR(r.min, 0.0, 1e-3) << "the back face is vertical";
            EXPECT_NEAR(r.max, spec.base_length + s.z * slope, 2e-3) << "z " << s.z;
        }
        EXPECT_GT(f.area_at(spec.height - 0.1), 2.0 * f.area_at(0.0)) << "the top overhangs";
    }
}

TEST(Cone, PointedAndTruncatedConesAreClosedAndMatchTheirVolume) {
    for (const double top : {0.0, 5.0}) {
        const PlannerFixture f = cone({.top_radius = top});
        expect_one_closed_body(f.mesh, "top " + std::to_string(top));
        EXPECT_NEAR(mesh::signed_volume(f.mesh), f.volume_mm3, 1e-9 * f.volume_mm3);
        EXPECT_NEAR(f.area_at(0.0), regular_polygon_area(20.0, 64), 1e-9);
    }
}

// ---- 3. A boss sticking out sideways -----------------------------------------------------

TEST(BearingSeat, BossHangsAboveThePlate) {
    const BearingSeatSpec spec{};
    const PlannerFixture f = bearing_seat(spec);
    const double boss_bottom =
        lowest_where(f.mesh, [&](const Vec3d& p) { return p.x > spec.block_length; });
    EXPECT_NEAR(boss_bottom, 0.5 * spec.block_height - spec.boss_radius, 1e-9);
    EXPECT_GT(boss_bottom, 0.0);
    const std::vector<Section> all = sections(f.mesh);
    ASSERT_FALSE(all.empty());
    // At the plate only the block; at mid-height the boss reaches out.
    EXPECT_NEAR(x_range(all.front().slice).max, spec.block_length, 1e-3);
    EXPECT_NEAR(all.front().slice.area_mm2(), spec.block_length * spec.block_width, 1e-2);
    for (const Section& s : all) {
        const bool in_boss = std::abs(s.z - 0.5 * spec.block_height) < 0.9 * spec.boss_radius;
        EXPECT_EQ(s.slice.wires.outer_count(), 1u) << "z " << s.z;
        if (in_boss) {
            EXPECT_NEAR(x_range(s.slice).max, spec.block_length + spec.boss_length, 1e-3);
        }
    }
}

// ---- 4. Horizontal members on a column ---------------------------------------------------

TEST(CylinderOnColumn, OverhangingEndsDoNotTouchThePlate) {
    const ColumnCylinderSpec spec{};
    const PlannerFixture f = cylinder_on_column(spec);
    const double a = 0.5 * spec.column_width;
    const double zc = cylinder_on_column_axis_height(spec);
    EXPECT_NEAR(zc, spec.column_height + spec.cylinder_radius * std::sqrt(0.5), 1e-9);
    const double ends_bottom =
        lowest_where(f.mesh, [&](const Vec3d& p) { return std::abs(p.x) > a; });
    EXPECT_NEAR(ends_bottom, zc - spec.cylinder_radius, 1e-9);
    EXPECT_GT(ends_bottom, 0.0);
    EXPECT_LT(ends_bottom, spec.column_height) << "the cylinder sits in a cradle";
    for (const Section& s : sections(f.mesh)) {
        const Range r = x_range(s.slice);
        EXPECT_EQ(s.slice.wires.outer_count(), 1u) << "z " << s.z;
        if (s.z < ends_bottom) {
            EXPECT_NEAR(r.max - r.min, spec.column_width, 1e-3) << "z " << s.z;
        } else {
            EXPECT_NEAR(r.min, -a - spec.overhang_left, 1e-3) << "z " << s.z;
            EXPECT_NEAR(r.max, a + spec.overhang_right, 1e-3) << "z " << s.z;
        }
    }
}

TEST(CylinderOnColumn, OneSidedOverhangIsOneClosedBody) {
    ColumnCylinderSpec spec{};
    spec.overhang_left = 0.0;
    spec.overhang_right = 30.0;
    spec.cradle_deg = 22.5;
    const PlannerFixture f = cylinder_on_column(spec);
    expect_one_closed_body(f.mesh, "one-sided");
    EXPECT_NEAR(mesh::signed_volume(f.mesh), f.volume_mm3, 1e-9 * f.volume_mm3);
    const core::Box3d box = mesh::bounding_box(f.mesh);
    EXPECT_NEAR(box.min.x, -0.5 * spec.column_width, 1e-12);
    EXPECT_NEAR(box.max.x, 0.5 * spec.column_width + 30.0, 1e-12);
    EXPECT_THROW((void)cylinder_on_column({.cradle_deg = 40.0}), std::invalid_argument);
}

TEST(TShapeArms, ArmsDoNotTouchThePlate) {
    const TArmsSpec spec{};
    const PlannerFixture f = t_shape_arms(spec);
    const double c0 = spec.arm_length;
    const double c1 = spec.arm_length + spec.column_width;
    EXPECT_EQ(lowest_where(f.mesh, [&](const Vec3d& p) { return p.x < c0 || p.x > c1; }),
              spec.column_height);
    EXPECT_NEAR(f.box.max.x, 2.0 * spec.arm_length + spec.column_width, 1e-12);
}

TEST(LBracket, ArmReachesOutOnOneSideAboveThePlate) {
    const LBracketSpec spec{};
    const PlannerFixture f = l_bracket(spec);
    EXPECT_EQ(lowest_where(f.mesh, [&](const Vec3d& p) { return p.x > spec.column_width; }),
              spec.column_height);
    for (const Section& s : sections(f.mesh)) {
        const Range r = x_range(s.slice);
        EXPECT_NEAR(r.min, 0.0, 1e-3);
        EXPECT_NEAR(
            r.max,
            s.z < spec.column_height ? spec.column_width : spec.column_width + spec.arm_length,
            1e-3)
            << "z " << s.z;
    }
}

// ---- 5. A freeform column ----------------------------------------------------------------

double angle_from_vertical_deg(const Vec3d& d) {
    return std::acos(std::clamp(core::normalized(d).z, -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

TEST(LeaningColumn, SpineRisesLinearlyAndLeansMonotonicallyToTheGivenAngle) {
    const LeaningColumnSpec spec{};
    EXPECT_EQ(leaning_column_spine(spec, 0.0), (Vec3d{0, 0, 0}));
    EXPECT_EQ(leaning_column_axis(spec, 0.0), (Vec3d{0, 0, 1}));
    const Vec3d top = leaning_column_spine(spec, 1.0);
    EXPECT_NEAR(core::norm(top - Vec3d{spec.top_offset, 0.0, spec.height}), 0.0, 1e-12);
    EXPECT_NEAR(angle_from_vertical_deg(leaning_column_axis(spec, 1.0)), spec.lean_deg, 1e-9);
    double previous = -1.0;
    for (int i = 0; i <= 100; ++i) {
        const double t = i / 100.0;
        EXPECT_NEAR(leaning_column_spine(spec, t).z, t * spec.height, 1e-12);
        EXPECT_EQ(leaning_column_spine(spec, t).y, 0.0);
        const double lean = angle_from_vertical_deg(leaning_column_axis(spec, t));
        EXPECT_GT(lean, previous) << "t " << t;
        previous = lean;
    }
    const std::vector<Vec3d> line = leaning_column_spine_polyline(spec, 10);
    ASSERT_EQ(line.size(), 11u);
    EXPECT_EQ(line.front(), leaning_column_spine(spec, 0.0));
    EXPECT_EQ(line[5], leaning_column_spine(spec, 0.5));
    EXPECT_EQ(line.back(), top);
}

// Distance from p to the polyline (mm).
double distance_to(const std::vector<Vec3d>& line, const Vec3d& p) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i + 1 < line.size(); ++i) {
        const Vec3d d = line[i + 1] - line[i];
        const double t = std::clamp(core::dot(p - line[i], d) / core::dot(d, d), 0.0, 1.0);
        best = std::min(best, core::norm(p - (line[i] + d * t)));
    }
    return best;
}

TEST(LeaningColumn, IsATubeOfTheGivenRadiusAroundTheSpine) {
    const LeaningColumnSpec spec{};
    const PlannerFixture f = leaning_column(spec);
    const std::vector<Vec3d> line = leaning_column_spine_polyline(spec, 3000);
    int centres = 0;
    for (const Vec3d& p : f.mesh.vertices) {
        const double d = distance_to(line, p);
        if (d < 1e-9) {
            ++centres;
            continue;
        }
        EXPECT_NEAR(d, spec.radius, 1e-3) << p.x << " " << p.y << " " << p.z;
    }
    EXPECT_EQ(centres, 2) << "only the caps' centres lie on the spine";
    EXPECT_NEAR(footprint_mm2(f.mesh), regular_polygon_area(spec.radius, spec.segments), 1e-9)
        << "the bottom ring lies flat on the plate";
}

TEST(LeaningColumn, HorizontalSectionsFollowTheSpine) {
    // A horizontal plane cuts a tube leaning by theta in an ellipse-like section of area
    // A / cos(theta) centred on the spine, so the sections tell the local lean. The spine's
    // curvature kappa (< 1/70 mm) moves the centroid outwards by about kappa (r tan(theta))^2 / 8
    // (0.1 mm at the top here): a quarter of a millimetre is a tenth of a track.
    constexpr double kCurvatureShiftMm = 0.25;
    const LeaningColumnSpec spec{};
    const PlannerFixture f = leaning_column(spec);
    const double area = regular_polygon_area(spec.radius, spec.segments);
    const double below_top =
        spec.height - spec.radius * std::sin(spec.lean_deg * std::numbers::pi / 180.0) - 0.5;
    int checked = 0;
    for (const Section& s : sections(f.mesh)) {
        if (s.z > below_top) continue;
        ++checked;
        SCOPED_TRACE("z " + std::to_string(s.z));
        const double t = s.z / spec.height;
        const Vec3d c = leaning_column_spine(spec, t);
        const geom2d::Paths2 region = s.slice.wires.paths();
        EXPECT_EQ(s.slice.wires.outer_count(), 1u);
        const geom2d::Point2 spine_2d{static_cast<std::int64_t>(std::llround(c.x * kUmPerMm)),
                                      static_cast<std::int64_t>(std::llround(c.y * kUmPerMm))};
        EXPECT_EQ(geom2d::locate_point(region, spine_2d), geom2d::Containment::kInside);
        const geom2d::Centroid2 centroid = geom2d::centroid_um(region);
        EXPECT_NEAR(centroid.x / kUmPerMm, c.x, kCurvatureShiftMm);
        EXPECT_NEAR(centroid.y / kUmPerMm, c.y, 1e-3);
        const double lean = angle_from_vertical_deg(leaning_column_axis(spec, t));
        EXPECT_NEAR(s.slice.area_mm2(), area / std::cos(lean * std::numbers::pi / 180.0),
                    0.01 * area);
    }
    EXPECT_GT(checked, 100);
}

// ---- 6. Several bases, frames, narrow gaps -----------------------------------------------

TEST(Arch, LegsStandApartBelowTheSoffitAndJoinAbove) {
    const ArchSpec spec{};
    const PlannerFixture f = arch(spec);
    const double soffit = arch_soffit_height(spec);
    EXPECT_GT(soffit, 0.5 * spec.height);
    EXPECT_LT(soffit, spec.height - 2.0 * 2.5) << "the crown is several tracks thick";
    int apart = 0, joined = 0;
    for (const Section& s : sections(f.mesh)) {
        const std::vector<Range> legs = outer_x_ranges(s.slice);
        if (s.z < soffit) {
            ++apart;
            ASSERT_EQ(legs.size(), 2u) << "z " << s.z;
            // Each leg keeps its width and leans inwards.
            const double shift = (0.5 * spec.span - 0.5 * spec.crown_width) * s.z / spec.height;
            EXPECT_NEAR(legs[0].min, shift, 1e-3);
            EXPECT_NEAR(legs[0].max - legs[0].min, spec.foot_width, 2e-3);
            EXPECT_NEAR(legs[1].max, spec.span - shift, 1e-3);
        } else {
            ++joined;
            EXPECT_EQ(legs.size(), 1u) << "z " << s.z;
        }
    }
    EXPECT_GT(apart, 20);
    EXPECT_GT(joined, 10);
}

TEST(PortalFrame, ColumnsCarryABeamThatBridgesTheOpening) {
    const PortalSpec spec{};
    const PlannerFixture f = portal_frame(spec);
    for (const Section& s : sections(f.mesh)) {
        const std::vector<Range> pieces = outer_x_ranges(s.slice);
        EXPECT_EQ(s.slice.wires.hole_count(), 0u);
        if (s.z < spec.column_height) {
            ASSERT_EQ(pieces.size(), 2u) << "z " << s.z;
            EXPECT_NEAR(pieces[1].min - pieces[0].max, spec.span - 2.0 * spec.column_width, 1e-3);
        } else {
            ASSERT_EQ(pieces.size(), 1u) << "z " << s.z;
            EXPECT_NEAR(pieces[0].max - pieces[0].min, spec.span, 1e-3);
        }
    }
}

TEST(TallPortal, IsTheIssuesPortal) {
    // Two 10 x 10 x 40 columns 50 mm apart centre to centre under a 60 x 10 x 8 beam.
    const PlannerFixture f = tall_portal();
    EXPECT_NEAR(f.volume_mm3, 2.0 * 10.0 * 10.0 * 40.0 + 60.0 * 10.0 * 8.0, 1e-9);
    EXPECT_EQ(f.box.size(), (Vec3d{60.0, 10.0, 48.0}));
    for (const Section& s : sections(f.mesh)) {
        const std::vector<Range> pieces = outer_x_ranges(s.slice);
        if (s.z < 40.0) {
            ASSERT_EQ(pieces.size(), 2u) << "z " << s.z;
            EXPECT_NEAR(pieces[0].max - pieces[0].min, 10.0, 1e-3);
            EXPECT_NEAR(pieces[1].max - pieces[1].min, 10.0, 1e-3);
            EXPECT_NEAR(0.5 * (pieces[1].min + pieces[1].max - pieces[0].min - pieces[0].max), 50.0,
                        1e-3);
        } else {
            ASSERT_EQ(pieces.size(), 1u) << "z " << s.z;
        }
    }
}

TEST(Slot, WallsStandApartByTheSlotWidthAboveTheBase) {
    const SlotSpec spec{};
    const PlannerFixture f = slot(spec);
    EXPECT_GE(spec.height - spec.base_height, 4.0 * spec.slot_width) << "a deep slot";
    for (const Section& s : sections(f.mesh)) {
        const std::vector<Range> walls = outer_x_ranges(s.slice);
        if (s.z < spec.base_height) {
            EXPECT_EQ(walls.size(), 1u) << "z " << s.z;
        } else {
            ASSERT_EQ(walls.size(), 2u) << "z " << s.z;
            EXPECT_NEAR(walls[1].min - walls[0].max, spec.slot_width, 1e-3) << "z " << s.z;
        }
    }
}

// ---- 7. Parts as given, with the plate in the machine ------------------------------------

// Extent along y (mm) of a section.
Range y_range(const slice::Slice& s) {
    Range r;
    for (const geom2d::WireNode& n : s.wires.nodes) {
        if (n.is_hole) continue;
        for (const geom2d::Point2& p : n.wire) {
            r.min = std::min(r.min, static_cast<double>(p.y) / kUmPerMm);
            r.max = std::max(r.max, static_cast<double>(p.y) / kUmPerMm);
        }
    }
    return r;
}

TEST(CrossHoleBlock, TheHoleSplitsTheSectionsItCrosses) {
    const CrossHoleBlockSpec spec{};
    const PlannerFixture f = cross_hole_block(spec);
    const double r = 0.5 * spec.hole_diameter;
    const double zc = 0.5 * spec.size;
    int split = 0;
    for (const Section& s : sections(f.mesh)) {
        const std::vector<Range> pieces = outer_x_ranges(s.slice);
        EXPECT_EQ(s.slice.wires.hole_count(), 0u) << "the hole runs horizontally, z " << s.z;
        if (std::abs(s.z - zc) < r - 0.1) {
            ++split;
            ASSERT_EQ(pieces.size(), 2u) << "z " << s.z;
            EXPECT_NEAR(pieces[0].min, 0.0, 1e-3);
            EXPECT_NEAR(pieces[1].max, spec.size, 1e-3);
            EXPECT_NEAR(pieces[0].max + pieces[1].min, spec.size, 2e-3) << "centred, z " << s.z;
        } else if (std::abs(s.z - zc) > r + 0.1) {
            EXPECT_EQ(pieces.size(), 1u) << "z " << s.z;
        }
    }
    EXPECT_GT(split, 30);
}

TEST(TabWithHole, TabStandsOnThePlateAndItsHoleIsHorizontal) {
    const TabWithHoleSpec spec{};
    const PlannerFixture f = tab_with_hole(spec);
    const double top = spec.plate_thickness;
    const double zh = top + spec.hole_height;
    const double r = 0.5 * spec.hole_diameter;
    int split = 0;
    for (const Section& s : sections(f.mesh)) {
        const std::vector<Range> pieces = outer_x_ranges(s.slice);
        EXPECT_EQ(s.slice.wires.hole_count(), 0u) << "z " << s.z;
        const Range y = y_range(s.slice);
        if (s.z < top) {
            ASSERT_EQ(pieces.size(), 1u) << "z " << s.z;
            EXPECT_NEAR(pieces[0].max - pieces[0].min, spec.plate_length, 1e-3);
            EXPECT_NEAR(y.max - y.min, spec.plate_width, 1e-3);
            continue;
        }
        EXPECT_NEAR(y.max - y.min, spec.tab_thickness, 1e-3) << "z " << s.z;
        EXPECT_NEAR(y.min + y.max, spec.plate_width, 2e-3) << "centred, z " << s.z;
        if (std::abs(s.z - zh) < r - 0.1) {
            ++split;
            ASSERT_EQ(pieces.size(), 2u) << "z " << s.z;
            EXPECT_NEAR(pieces[1].max - pieces[0].min, spec.tab_width, 1e-3);
        } else if (std::abs(s.z - zh) > r + 0.1) {
            ASSERT_EQ(pieces.size(), 1u) << "z " << s.z;
            EXPECT_NEAR(pieces[0].max - pieces[0].min, spec.tab_width, 1e-3);
        }
    }
    EXPECT_GT(split, 15);
    // The hole's bottom lies above the plate: material of the tab under it.
    EXPECT_GT(zh - r, top);
}

TEST(HelicalRing, StandsOnItsGroundEndAndItsSectionsTurnWithTheHelix) {
    const HelicalRingSpec spec{};
    const PlannerFixture f = helical_ring(spec);
    const double a = spec.radius - 0.5 * spec.section;
    const double b = spec.radius + 0.5 * spec.section;
    // The footing: the ground end's chord polygon, a quarter turn with the default spec.
    const double d = 2.0 * std::numbers::pi / spec.segments_per_turn;
    const double ground = helical_ring_ground_angle(spec);
    EXPECT_NEAR(ground, 0.5 * std::numbers::pi, 1e-12);
    EXPECT_NEAR(footprint_mm2(f.mesh), 0.5 * (b * b - a * a) * std::sin(d) * std::round(ground / d),
                1e-9 * footprint_mm2(f.mesh));
    // Every horizontal section of the full-height part is one arc of the annulus, spanning
    // section / pitch of a turn, centred on the angle where the helix's centre has that height:
    // the chain of section centroids turns about the axis, pitch mm a turn.
    const double half = 0.5 * spec.section;
    const double arc = 2.0 * std::numbers::pi * spec.section / spec.pitch;
    int checked = 0;
    for (const Section& s : sections(f.mesh)) {
        if (s.z < 2.0 * half || s.z > spec.turns * spec.pitch - half) continue;
        ++checked;
        SCOPED_TRACE("z " + std::to_string(s.z));
        ASSERT_EQ(s.slice.wires.outer_count(), 1u);
        EXPECT_EQ(s.slice.wires.hole_count(), 0u);
        EXPECT_NEAR(s.slice.area_mm2(), 0.5 * (b * b - a * a) * arc, 0.01 * (b * b - a * a) * arc);
        const geom2d::Centroid2 c = geom2d::centroid_um(s.slice.wires.paths());
        const double expected = 2.0 * std::numbers::pi * s.z / spec.pitch;
        const double got = std::atan2(c.y, c.x);
        EXPECT_NEAR(std::remainder(got - expected, 2.0 * std::numbers::pi), 0.0, 0.02);
    }
    EXPECT_GE(checked, 25);
}

TEST(HelicalRing, ConstructionRejectsTurnsThatTouch) {
    EXPECT_THROW((void)helical_ring({.pitch = 6.0}), std::invalid_argument);
    EXPECT_THROW((void)helical_ring({.segments_per_turn = 70}), std::invalid_argument)
        << "the ground end must end on a step";
}

TEST(WallBoss, BossHangsAboveThePlateAtMidHeight) {
    const WallBossSpec spec{};
    const PlannerFixture f = wall_boss(spec);
    const double r = 0.5 * spec.boss_diameter;
    const double boss_bottom =
        lowest_where(f.mesh, [&](const Vec3d& p) { return p.y > spec.wall_thickness; });
    EXPECT_NEAR(boss_bottom, 0.5 * spec.wall_height - r, 1e-9);
    EXPECT_GT(boss_bottom, 0.0);
    for (const Section& s : sections(f.mesh)) {
        const Range y = y_range(s.slice);
        EXPECT_EQ(s.slice.wires.outer_count(), 1u) << "z " << s.z;
        EXPECT_NEAR(y.min, 0.0, 1e-3);
        if (std::abs(s.z - 0.5 * spec.wall_height) < 0.9 * r) {
            EXPECT_NEAR(y.max, spec.wall_thickness + spec.boss_length, 1e-3) << "z " << s.z;
        } else if (std::abs(s.z - 0.5 * spec.wall_height) > r) {
            EXPECT_NEAR(y.max, spec.wall_thickness, 1e-3) << "z " << s.z;
        }
    }
}

}  // namespace
}  // namespace maxslice::test
