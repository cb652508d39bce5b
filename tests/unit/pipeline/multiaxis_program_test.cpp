// The moves of a multi-axis plan (METHOD.md sections 9 to 11): checked for what the cell
// needs, from the plan's own reported geometry: every deposit on its layer's top along its
// layer's direction, layers in build order, no turn within a wire, feeds inside the speed
// law's window that lay the planned thickness, travel between sections above the part.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "maxslice/machine/speed_law.hpp"
#include "maxslice/mesh/validation.hpp"
#include "maxslice/pipeline/plan_job.hpp"
#include "maxslice/pipeline/program_job.hpp"
#include "support/fixtures.hpp"
#include "support/planner_fixtures.hpp"

namespace maxslice::pipeline {
namespace {

using core::Vec3d;
using machine::MoveKind;

machine::Profiles reference_profiles() {
    machine::Profiles p;
    p.machine.name = "test table";
    p.process.track_width_mm = 2.5;
    p.process.layer_height_mm = 0.5;
    p.process.h_min_mm = 0.3;
    p.process.h_max_mm = 0.7;
    p.process.overlap = 0.3;
    p.process.contour_passes = 1;
    p.process.laser_power_w = 700.0;
    p.process.powder_feed_g_min = 8.0;
    p.process.deposition_feed_mm_min = 381.0;
    p.process.travel_feed_mm_min = 2540.0;
    p.process.self_supporting_angle_deg = 20.0;
    return p;
}

struct Built {
    PlannedPart planned;
    MultiAxisProgram program;
};

Built build(const mesh::TriangleMesh& mesh, const machine::Profiles& profiles) {
    Built b;
    PlanJobSettings ps;
    ps.plan = plan_settings(profiles.process);
    auto planned = plan_mesh(mesh, ps);
    EXPECT_TRUE(planned.has_value()) << (planned ? "" : planned.error().describe());
    if (!planned) return b;
    b.planned = std::move(*planned);
    auto ok = order_plan(b.planned, plan::Nozzle{}, "defaults");
    EXPECT_TRUE(ok.has_value());
    EXPECT_TRUE(b.planned.order->complete());
    auto p = plan_multiaxis_program(b.planned.plan, *b.planned.order, mesh, profiles, "part");
    EXPECT_TRUE(p.has_value()) << (p ? "" : p.error().describe());
    if (p) b.program = std::move(*p);
    return b;
}

double highest_along(const mesh::TriangleMesh& m, const Vec3d& d) {
    double h = -std::numeric_limits<double>::infinity();
    for (const Vec3d& v : m.vertices) h = std::max(h, core::dot(v, d));
    return h;
}

// The properties every multi-axis program must have.
void expect_sound(const mesh::TriangleMesh& mesh, const Built& b,
                  const machine::Profiles& profiles) {
    const plan::Plan& plan = b.planned.plan;
    const plan::BuildOrder& order = *b.planned.order;
    const auto& moves = b.program.program.moves;
    ASSERT_FALSE(moves.empty());
    std::vector<int> rank(plan.layers.size(), -1);
    for (std::size_t i = 0; i < order.order.size(); ++i) {
        rank[static_cast<std::size_t>(order.order[i])] = static_cast<int>(i);
    }
    const machine::SpeedLaw law = machine::SpeedLaw::of(profiles.process);
    int last_rank = -1;
    bool laser = false;
    Vec3d wire_dir;
    std::set<int> deposited;
    for (std::size_t i = 0; i < moves.size(); ++i) {
        const machine::Move& m = moves[i];
        ASSERT_GE(m.layer, 0);
        const plan::Layer& l = plan.layers[static_cast<std::size_t>(m.layer)];
        // Layers come in build order.
        ASSERT_GE(rank[static_cast<std::size_t>(m.layer)], last_rank) << "move " << i;
        last_rank = rank[static_cast<std::size_t>(m.layer)];
        EXPECT_NEAR(core::norm(m.direction), 1.0, 1e-12);
        if (m.kind == MoveKind::kLaserOn) {
            laser = true;
            wire_dir = m.direction;
        }
        if (m.kind == MoveKind::kLaserOff) laser = false;
        if (laser) {
            // No turn within a wire.
            EXPECT_LT(core::norm(m.direction - wire_dir), 1e-12) << "move " << i;
        }
        if (m.kind != MoveKind::kDeposit) continue;
        deposited.insert(m.layer);
        EXPECT_LT(core::norm(m.direction - l.top.normal), 1e-12) << "move " << i;
        EXPECT_LT(std::abs(l.top.height(m.position)), 1e-6) << "move " << i;
        EXPECT_GE(m.feed_mm_min, law.feed_min_mm_min() - 1e-9);
        EXPECT_LE(m.feed_mm_min, law.feed_max_mm_min() + 1e-9);
        // The laid height lies in the layer's planned thickness range, as far as the window
        // reaches (a part's last layer may be thinner than the window lays).
        const double laid = law.height_mm(m.feed_mm_min);
        const double lo = std::clamp(l.thickness_min_mm, law.height_min_mm(), law.height_max_mm());
        const double hi = std::clamp(l.thickness_max_mm, law.height_min_mm(), law.height_max_mm());
        EXPECT_GE(laid, lo - 1e-6) << "layer " << l.id;
        EXPECT_LE(laid, hi + 1e-6) << "layer " << l.id;
    }
    // Every layer with tracks is deposited.
    for (std::size_t i = 0; i < b.program.order.size(); ++i) {
        if (!b.program.toolpaths[i].strokes.empty()) {
            EXPECT_TRUE(deposited.contains(b.program.order[i])) << "layer " << b.program.order[i];
        }
    }
    // Between wires of different sections built along one direction, the head passes above
    // the whole part.
    int last_section = -1;
    Vec3d last_dir;
    double travel_top = -std::numeric_limits<double>::infinity();
    for (const machine::Move& m : moves) {
        if (m.kind == MoveKind::kTravel) {
            travel_top = std::max(travel_top, core::dot(m.position, m.direction));
            continue;
        }
        if (m.kind != MoveKind::kLaserOn) continue;
        const int section = order.section_of[static_cast<std::size_t>(m.layer)];
        if (last_section >= 0 && section != last_section &&
            core::norm(m.direction - last_dir) < 1e-12) {
            EXPECT_GE(travel_top, highest_along(mesh, m.direction)) << "layer " << m.layer;
        }
        last_section = section;
        last_dir = m.direction;
        travel_top = -std::numeric_limits<double>::infinity();
    }
}

TEST(MultiAxisProgram, FixturesGiveSoundMoves) {
    const machine::Profiles profiles = reference_profiles();
    for (const auto& f : {test::bearing_seat(), test::arch(), test::t_shape_arms(),
                          test::l_bracket(), test::leaning_column()}) {
        SCOPED_TRACE(f.name);
        const Built b = build(f.mesh, profiles);
        expect_sound(f.mesh, b, profiles);
        EXPECT_EQ(b.program.order, b.planned.order->order);
    }
}

TEST(MultiAxisProgram, WedgeLayersGetTheirOwnFeeds) {
    const machine::Profiles profiles = reference_profiles();
    const auto f = test::leaning_column();
    const Built b = build(f.mesh, profiles);
    ASSERT_GT(b.planned.plan.tilted_layer_count(), 0);
    std::set<long> feeds;
    for (const machine::Move& m : b.program.program.moves) {
        if (m.kind == MoveKind::kDeposit) feeds.insert(std::lround(m.feed_mm_min * 10.0));
    }
    EXPECT_GT(feeds.size(), 10u);
    EXPECT_GT(b.program.thickness.thickness_max_mm, b.program.thickness.thickness_min_mm);
    // Within [h_min, h_max] the window lays every thickness: nothing is clamped.
    EXPECT_EQ(b.program.thickness.clamped, 0u);
    EXPECT_GT(b.program.thickness.segments, 0u);
}

TEST(MultiAxisProgram, PlanarLayersRunAtTheNominalFeed) {
    const machine::Profiles profiles = reference_profiles();
    const auto f = test::vertical_prism();
    const Built b = build(f.mesh, profiles);
    std::size_t deposits = 0;
    for (const machine::Move& m : b.program.program.moves) {
        if (m.kind != MoveKind::kDeposit) continue;
        ++deposits;
        EXPECT_NEAR(m.feed_mm_min, profiles.process.deposition_feed_mm_min, 1e-9);
    }
    EXPECT_GT(deposits, 100u);
}

TEST(MultiAxisProgram, ANarrowWindowIsReported) {
    machine::Profiles profiles = reference_profiles();
    // A measured law that cannot lay above 0.55 mm or below 0.45 mm.
    profiles.process.speed_height = {{346.0, 0.55}, {381.0, 0.5}, {423.0, 0.45}};
    const auto f = test::leaning_column();
    const Built b = build(f.mesh, profiles);
    const ThicknessReport& t = b.program.thickness;
    EXPECT_GT(t.clamped, 0u);
    EXPECT_GT(t.worst_error_mm, 0.0);
    EXPECT_GE(t.worst_layer, 0);
    const double worst_planned = std::max(t.thickness_max_mm - 0.55, 0.45 - t.thickness_min_mm);
    EXPECT_NEAR(t.worst_error_mm, worst_planned, 1e-6);
}

TEST(MultiAxisProgram, AnIncompleteOrderIsRefused) {
    const machine::Profiles profiles = reference_profiles();
    const auto f = test::bearing_seat();
    Built b = build(f.mesh, profiles);
    plan::BuildOrder order = *b.planned.order;
    order.conflicts.push_back({0, 1, {}, {}, 0.1, "layer 0 meets layer 1"});
    auto p = plan_multiaxis_program(b.planned.plan, order, f.mesh, profiles, "part");
    ASSERT_FALSE(p.has_value());
    EXPECT_EQ(p.error().code, core::ErrorCode::kInvalidInput);
    EXPECT_NE(p.error().message.find("no collision-free build order"), std::string::npos);
}

TEST(MultiAxisProgram, SameInputSameMoves) {
    const machine::Profiles profiles = reference_profiles();
    const auto f = test::arch();
    const Built a = build(f.mesh, profiles);
    const Built b = build(f.mesh, profiles);
    ASSERT_EQ(a.program.program.moves.size(), b.program.program.moves.size());
    for (std::size_t i = 0; i < a.program.program.moves.size(); ++i) {
        const auto& x = a.program.program.moves[i];
        const auto& y = b.program.program.moves[i];
        ASSERT_EQ(x.position, y.position);
        ASSERT_EQ(x.feed_mm_min, y.feed_mm_min);
        ASSERT_EQ(x.kind, y.kind);
    }
}

// A closed mesh is compared with its volume; an open one has none (its signed volume moves with
// the origin), so the summary says so instead of printing a misleading difference.
TEST(VolumeAgainstMesh, ComparesOnlyWithAClosedMesh) {
    const mesh::TriangleMesh cube = test::box({0, 0, 0}, {10, 20, 5});
    const mesh::ValidationReport closed = mesh::validate(cube);
    ASSERT_TRUE(closed.closed_manifold());
    EXPECT_EQ(volume_against_mesh(1010.0, closed), "(mesh 1000 mm3, +1.000%)");
    EXPECT_EQ(volume_against_mesh(995.0, closed), "(mesh 1000 mm3, -0.500%)");

    mesh::TriangleMesh open = cube;
    open.triangles.pop_back();
    const mesh::ValidationReport report = mesh::validate(open);
    ASSERT_FALSE(report.closed_manifold());
    const std::string text = volume_against_mesh(1000.0, report);
    EXPECT_NE(text.find("not closed"), std::string::npos) << text;
    EXPECT_EQ(text.find('%'), std::string::npos) << text;
}

}  // namespace
}  // namespace maxslice::pipeline
