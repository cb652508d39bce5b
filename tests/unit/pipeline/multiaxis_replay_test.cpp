// The 5-axis job of the leaning column, as the CLI runs it (place on the plate, plan, order,
// moves, write), replayed by the independent verifier: the written program puts the tool tip
// where the part-frame program meant it (within the rounding docs/program-dialects.md allows),
// and the bead the verifier derives from each deposit block's feed is as high as the plan's
// local layer thickness there (METHOD.md section 10, docs/decisions/0011-speed-law.md). The
// planned thickness is computed here from the plan's own geometry (layer planes), not taken
// from the job.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "maxslice/machine/machine_moves.hpp"
#include "maxslice/machine/profile.hpp"
#include "maxslice/machine/speed_law.hpp"
#include "maxslice/machine/writer.hpp"
#include "maxslice/pipeline/plan_job.hpp"
#include "maxslice/pipeline/program_job.hpp"
#include "maxslice/verify/replay.hpp"
#include "maxslice/verify/verify.hpp"
#include "support/planner_fixtures.hpp"

namespace maxslice::pipeline {
namespace {

using core::Vec3d;

// A rotary word is within 0.0005 deg of its value: 8.7e-6 rad (docs/program-dialects.md).
constexpr double kRotaryRoundingRad = 0.0005 * 3.14159265358979323846 / 180.0;
// Linear words are within 0.0005 mm.
constexpr double kLinearRoundingMm = 0.0005;
// Arithmetic of the kinematics' forward and inverse transforms on top of the rounding.
constexpr double kArithmeticMm = 1e-9;
// Failures listed one by one before a test only counts them.
constexpr std::size_t kShown = 5;

// The whole job for one bundled profile, run once per test process (planning the column takes
// a moment).
struct Job {
    machine::Profiles profiles;
    mesh::TriangleMesh placed;
    PlannedPart planned;
    MultiAxisProgram program;
    std::string text;
    verify::Replay replay;
    std::optional<verify::Report> report;  ///< verify::verify_program of the text
};

Job run_job(const std::string& profile,
            const mesh::TriangleMesh& part = test::leaning_column().mesh,
            const std::string& name = "leaning_column") {
    {
        Job out;
        const std::filesystem::path file =
            std::filesystem::path(MAXSLICE_SOURCE_DIR) / "examples/profiles" / profile;
        const std::array<std::filesystem::path, 1> files{file};
        auto profiles = machine::load_profiles(files);
        EXPECT_TRUE(profiles.has_value()) << (profiles ? "" : profiles.error().describe());
        if (!profiles) return out;
        out.profiles = *profiles;
        out.placed =
            place_on_plate(part, {0.0, 0.0, 1.0}, machine::plate_center(out.profiles.machine));
        PlanJobSettings ps;
        ps.plan = plan_settings(out.profiles.process);
        auto planned = plan_mesh(out.placed, ps);
        EXPECT_TRUE(planned.has_value()) << (planned ? "" : planned.error().describe());
        if (!planned) return out;
        out.planned = std::move(*planned);
        std::string source;
        const plan::Nozzle nozzle = nozzle_of(out.profiles.machine, &source);
        auto ordered = order_plan(out.planned, nozzle, source);
        EXPECT_TRUE(ordered.has_value()) << (ordered ? "" : ordered.error().describe());
        if (!ordered || !out.planned.order || !out.planned.order->complete()) {
            ADD_FAILURE() << "no complete build order";
            return out;
        }
        auto program = plan_multiaxis_program(out.planned.plan, *out.planned.order, out.placed,
                                              out.profiles, name);
        EXPECT_TRUE(program.has_value()) << (program ? "" : program.error().describe());
        if (!program) return out;
        out.program = std::move(*program);
        machine::WriteOptions wo;
        wo.clear_z_mm = machine::clear_height_mm(out.profiles.machine, out.placed.vertices);
        auto text = machine::write_program(out.program.program, out.profiles.machine,
                                           out.profiles.process, wo);
        EXPECT_TRUE(text.has_value()) << (text ? "" : text.error().describe());
        if (!text) return out;
        out.text = std::move(*text);
        auto dialect = verify::dialect_of(out.profiles.machine);
        EXPECT_TRUE(dialect.has_value());
        if (!dialect) return out;
        auto replay = verify::replay_program(out.text, out.profiles, *dialect);
        EXPECT_TRUE(replay.has_value()) << (replay ? "" : replay.error().describe());
        if (replay) out.replay = std::move(*replay);
        auto report = verify::verify_program(out.text, out.placed, out.profiles);
        EXPECT_TRUE(report.has_value()) << (report ? "" : report.error().describe());
        if (report) out.report = std::move(*report);
        return out;
    }
}

const Job& job(const std::string& profile = "reference_5axis_ac.toml") {
    static std::map<std::string, Job> jobs;
    auto it = jobs.find(profile);
    if (it == jobs.end()) it = jobs.emplace(profile, run_job(profile)).first;
    return it->second;
}

// A replayed deposit block and the part-frame move it was written from.
struct Pair {
    const verify::ReplayBlock* block = nullptr;
    Vec3d from_tip;  // the replayed tip where the block starts
    const machine::Move* move = nullptr;
};

// The replay's deposit blocks (moves with the laser on) in order, each with the program's
// kDeposit move of the same rank. Fails the test when the counts differ.
std::vector<Pair> deposit_pairs(const Job& j) {
    std::vector<const machine::Move*> deposits;
    for (const machine::Move& m : j.program.program.moves) {
        if (m.kind == machine::MoveKind::kDeposit) deposits.push_back(&m);
    }
    std::vector<Pair> pairs;
    const verify::ReplayBlock* last_move = nullptr;
    for (const verify::ReplayBlock& b : j.replay.blocks) {
        if (b.kind != verify::ReplayBlock::Kind::kMove) continue;
        if (b.laser_on) {
            if (pairs.size() < deposits.size() && last_move != nullptr) {
                pairs.push_back({&b, last_move->tip_mm, deposits[pairs.size()]});
            } else {
                ADD_FAILURE() << "line " << b.line << ": a deposit block the program does not have";
            }
        }
        last_move = &b;
    }
    EXPECT_EQ(pairs.size(), deposits.size()) << "deposit blocks in the text vs kDeposit moves";
    return pairs;
}

// The plan's local thickness under a point of a layer's top: a tilted (wedge) layer lies on the
// top plane of its parent in the same region one index lower; the distance from the point
// down to that plane along the layer's build direction (top.normal). A planar layer: its span.
// nullopt for a tilted layer without such a parent.
std::optional<double> planned_thickness(const plan::Plan& plan, const plan::Layer& layer,
                                        const Vec3d& at) {
    if (!layer.tilted) return layer.span.thickness();
    const Vec3d d = layer.top.normal;
    for (const int p : layer.parents) {
        const plan::Layer& parent = plan.layers[static_cast<std::size_t>(p)];
        if (parent.region != layer.region || parent.index_in_region + 1 != layer.index_in_region)
            continue;
        const slice::PlaneFrame& below = parent.top;
        return core::dot(at - below.origin, below.normal) / core::dot(d, below.normal);
    }
    return std::nullopt;
}

TEST(MultiAxisReplay, TheJobPlansATiltedColumn) {
    const Job& j = job();
    ASSERT_FALSE(j.text.empty());
    EXPECT_TRUE(machine::is_table_tilt(j.profiles.machine.kinematics));
    EXPECT_GT(j.planned.plan.tilted_layer_count(), 10);
    // The part stands on the plate around the C axis.
    double zmin = std::numeric_limits<double>::infinity();
    for (const Vec3d& v : j.placed.vertices) zmin = std::min(zmin, v.z);
    EXPECT_NEAR(zmin, 0.0, 1e-9);
}

// Every deposit block's replayed tip (forward kinematics of the rounded words) is the
// part-frame move's position within the documented allowance: 0.0005 mm per linear word plus
// 8.7e-6 r mm per rotary axis for a point r mm from it; the direction within the rotary
// rounding.
void expect_tips_on_moves(const Job& j) {
    ASSERT_FALSE(j.text.empty());
    const std::vector<Pair> pairs = deposit_pairs(j);
    ASSERT_GT(pairs.size(), 1000u);
    ASSERT_TRUE(j.profiles.machine.table.has_value());
    const machine::TableProfile& table = *j.profiles.machine.table;
    const Vec3d o{table.c_offset_x_mm, table.c_offset_y_mm, 0.0};
    double worst_ratio = 0.0;
    std::size_t tilted_blocks = 0, off = 0;
    for (const Pair& p : pairs) {
        const Vec3d q = p.move->position;
        // The C axis runs through o, the tilt axis through the part origin (the pivot at
        // rotary zero): distances to them are at most |q - o| and |o| + |q - o|.
        const double r_c = core::norm(q - o);
        const double r_tilt = core::norm(o) + r_c;
        const double per_axis = kLinearRoundingMm + kRotaryRoundingRad * (r_c + r_tilt);
        const double allowance = std::sqrt(3.0) * per_axis + kArithmeticMm;
        const double error = core::norm(p.block->tip_mm - q);
        worst_ratio = std::max(worst_ratio, error / allowance);
        const double turn = core::norm(p.block->direction - p.move->direction);
        if ((error > allowance || turn > 2.0 * kRotaryRoundingRad + 1e-12) && ++off <= kShown) {
            ADD_FAILURE() << "line " << p.block->line << " layer " << p.move->layer << ": tip "
                          << error << " mm from the move (allowance " << allowance
                          << "), direction " << turn << " off";
        }
        if (std::abs(p.move->direction.z) < 1.0 - 1e-9) ++tilted_blocks;
    }
    EXPECT_EQ(off, 0u) << "deposit blocks off their moves (the first " << kShown << " above)";
    // The table turns for the wedge layers: the allowance's rotary part is exercised.
    EXPECT_GT(tilted_blocks, 100u);
    ::testing::Test::RecordProperty("worst_error_over_allowance", std::to_string(worst_ratio));
}

// The verifier's bead height (the speed law applied to the written feed) is the plan's local
// thickness at the segment's middle within 5%, wherever the law's window can lay it.
void expect_planned_bead_heights(const Job& j) {
    ASSERT_FALSE(j.text.empty());
    const plan::Plan& plan = j.planned.plan;
    const machine::SpeedLaw law = machine::SpeedLaw::of(j.profiles.process);
    const std::vector<Pair> pairs = deposit_pairs(j);
    ASSERT_GT(pairs.size(), 1000u);
    std::size_t compared = 0, compared_tilted = 0, outside_window = 0, no_parent = 0, off = 0;
    double bead_min = std::numeric_limits<double>::infinity(), bead_max = 0.0;
    for (const Pair& p : pairs) {
        const double bead = law.height_mm(p.block->feed_mm_min);
        bead_min = std::min(bead_min, bead);
        bead_max = std::max(bead_max, bead);
        ASSERT_GE(p.move->layer, 0);
        const plan::Layer& layer = plan.layers[static_cast<std::size_t>(p.move->layer)];
        const Vec3d middle = (p.from_tip + p.block->tip_mm) * 0.5;
        const std::optional<double> planned = planned_thickness(plan, layer, middle);
        if (!planned) {
            if (++no_parent <= kShown) {
                ADD_FAILURE() << "tilted layer " << layer.id << " (region " << layer.region
                              << ", index " << layer.index_in_region
                              << ") has no parent one index lower in its region";
            }
            continue;
        }
        if (*planned < law.height_min_mm() || *planned > law.height_max_mm()) {
            ++outside_window;
            continue;
        }
        ++compared;
        if (layer.tilted) ++compared_tilted;
        if (std::abs(bead - *planned) > 0.05 * *planned && ++off <= kShown) {
            ADD_FAILURE() << "line " << p.block->line << " layer " << layer.id << " (tilted "
                          << layer.tilted << ") at (" << middle.x << ", " << middle.y << ", "
                          << middle.z << "): bead " << bead << " mm for F " << p.block->feed_mm_min
                          << ", planned " << *planned << " mm";
        }
    }
    EXPECT_EQ(off, 0u) << "beads off the planned thickness by more than 5% (the first " << kShown
                       << " above)";
    EXPECT_EQ(no_parent, 0u);
    EXPECT_GT(compared, 1000u);
    EXPECT_GT(compared_tilted, 500u);
    // The verifier's own report of the bead heights it laid agrees.
    const auto& report = j.report;
    ASSERT_TRUE(report.has_value());
    EXPECT_NEAR(report->bead_height_min_mm, bead_min, 1e-9);
    EXPECT_NEAR(report->bead_height_max_mm, bead_max, 1e-9);
    ::testing::Test::RecordProperty("compared", static_cast<int>(compared));
    ::testing::Test::RecordProperty("outside_window", static_cast<int>(outside_window));
}

TEST(MultiAxisReplay, ReplayedTipsAreTheProgramsPositions) {
    expect_tips_on_moves(job());
}

TEST(MultiAxisReplay, BeadHeightsAreThePlannedThickness) {
    expect_planned_bead_heights(job());
}

// The other bundled table profiles: joint space (linuxcnc, pivot below the table) and tool
// centre point control (fanuc A/C, siemens B/C) put the tips and feeds where the moves are too.
TEST(MultiAxisReplay, EveryTableDialectReplaysToTheProgramsMovesAndHeights) {
    for (const std::string profile :
         {"linuxcnc_5axis_ac.toml", "fanuc_5axis_ac.toml", "siemens_5axis_bc.toml"}) {
        SCOPED_TRACE(profile);
        const Job& j = job(profile);
        ASSERT_FALSE(j.text.empty());
        expect_tips_on_moves(j);
        expect_planned_bead_heights(j);
        ASSERT_TRUE(j.report.has_value());
        EXPECT_TRUE(j.report->passed()) << verify::report_text(*j.report);
        EXPECT_GE(j.report->coverage, 0.97);
        EXPECT_LT(j.report->excess, 0.05);
    }
}

TEST(MultiAxisReplay, TheVerifierPassesTheProgram) {
    const Job& j = job();
    ASSERT_FALSE(j.text.empty());
    const auto& report = j.report;
    ASSERT_TRUE(report.has_value());
    EXPECT_TRUE(report->passed()) << verify::report_text(*report);
    EXPECT_EQ(report->collisions.count, 0u);
    EXPECT_EQ(report->clearance.count, 0u);
    ASSERT_TRUE(j.profiles.machine.nozzle.has_value());
    EXPECT_EQ(report->clearance_mm, j.profiles.machine.nozzle->clearance_mm);
    EXPECT_EQ(report->unsupported.count, 0u);
    EXPECT_EQ(report->limit_violations.count, 0u);
    EXPECT_GE(report->coverage, 0.97);
    EXPECT_LT(report->excess, 0.05);
    EXPECT_EQ(report->deposit_moves, deposit_pairs(j).size());
}

// A wedge layer is thicker on one side than the other: its pieces get different feeds.
TEST(MultiAxisReplay, WedgeLayersVaryTheWrittenFeed) {
    const Job& j = job();
    ASSERT_FALSE(j.text.empty());
    std::set<long> feeds;        // all deposit blocks, in 0.1 mm/min as written
    std::set<long> wedge_feeds;  // of tilted layers only
    for (const Pair& p : deposit_pairs(j)) {
        const long f = std::lround(p.block->feed_mm_min * 10.0);
        feeds.insert(f);
        if (j.planned.plan.layers[static_cast<std::size_t>(p.move->layer)].tilted)
            wedge_feeds.insert(f);
    }
    EXPECT_GT(feeds.size(), 10u);
    EXPECT_GT(wedge_feeds.size(), 10u);
}

// A block with a fin on its side: 1.5 mm wide in the lower half (narrower than the 2.5 mm
// track: no track), 3 mm wide in the upper half (one track along it). The planner carries the
// upper fin on the lower one (the step is narrower than a track), but no bead lies under its
// tracks: the job leaves them out, and the verifier finds every bead resting on another.
TEST(MultiAxisReplay, TracksOverBareFeaturesBelowAreLeftOut) {
    const mesh::TriangleMesh part = test::merged(
        test::merged(test::box({0, 0, 0}, {20, 20, 8}), test::box({19, 9.25, 0}, {35, 10.75, 4})),
        test::box({19, 8.5, 4}, {35, 11.5, 8}));
    const Job j = run_job("reference_5axis_ac.toml", part, "fin");
    ASSERT_TRUE(j.report.has_value());
    EXPECT_GT(j.program.trimmed_mm, 10.0);
    EXPECT_GT(j.program.layers_trimmed, 0);
    EXPECT_EQ(j.report->unsupported.count, 0u);
    EXPECT_EQ(j.report->collisions.count, 0u);
    // Only what stands over the bare fin is left out: the block is built.
    EXPECT_GT(j.report->coverage, 0.85);
}

// A fin standing on a block: 1.5 mm wide in its lower half (narrower than the 2.5 mm track),
// 3 mm in its upper half. Its lower layers are islands of their own where no contour fits:
// without a track there, every bead of the upper fin would rest on nothing and be left out
// (above). They get one track along their middle (decision 0049), and the whole fin is built,
// every bead on another.
TEST(MultiAxisReplay, AFeatureThatStartsNarrowerThanATrackGetsATrackAlongItsMiddle) {
    const mesh::TriangleMesh part = test::merged(
        test::merged(test::box({0, 0, 0}, {40, 40, 8}), test::box({10, 19.25, 8}, {30, 20.75, 12})),
        test::box({10, 18.5, 12}, {30, 21.5, 16}));
    const Job j = run_job("reference_5axis_ac.toml", part, "fin_on_top");
    ASSERT_TRUE(j.report.has_value());
    EXPECT_LT(j.program.trimmed_mm, 1.0);
    EXPECT_EQ(j.report->unsupported.count, 0u) << verify::report_text(*j.report);
    EXPECT_EQ(j.report->collisions.count, 0u) << verify::report_text(*j.report);
    // Beads of the lower fin (above the block) and of the upper fin.
    std::size_t lower_fin = 0;
    std::size_t upper_fin = 0;
    const double bottom = mesh::bounding_box(j.placed).min.z;
    for (const Pair& p : deposit_pairs(j)) {
        const double z = p.move->position.z - bottom;
        if (z > 8.0 && z < 12.0) ++lower_fin;
        if (z > 12.0) ++upper_fin;
    }
    EXPECT_GT(lower_fin, 0u);
    EXPECT_GT(upper_fin, 0u);
    EXPECT_GE(j.report->coverage, 0.97) << verify::report_text(*j.report);
    EXPECT_LT(j.report->excess, 0.05) << verify::report_text(*j.report);
}

// The portal of issue 23 upside down (beam on the plate, the columns rising from it) with the
// LinuxCNC 5-axis cell, whose head body is 80 mm across and whose profile asks for 2 mm: while
// the tip stands at the foot of one column the body's rim reaches over the other. The job's
// order keeps the clearance from the body (the verifier, checking the profile's clearance,
// finds neither contact nor a gap below 2 mm), where an order by column left 1.35 mm.
TEST(MultiAxisReplay, ThePortalsProgramKeepsTheProfilesClearance) {
    mesh::TriangleMesh part = test::tall_portal().mesh;
    for (Vec3d& v : part.vertices) v = {v.x, -v.y, -v.z};  // a half turn about X
    const Job j = run_job("linuxcnc_5axis_ac.toml", part, "tall_portal");
    ASSERT_TRUE(j.report.has_value());
    ASSERT_TRUE(j.profiles.machine.nozzle.has_value());
    EXPECT_EQ(j.profiles.machine.nozzle->clearance_mm, 2.0);
    EXPECT_EQ(j.report->clearance_mm, 2.0);
    EXPECT_EQ(j.report->collisions.count, 0u) << verify::report_text(*j.report);
    EXPECT_EQ(j.report->clearance.count, 0u) << verify::report_text(*j.report);
    EXPECT_TRUE(j.report->passed()) << verify::report_text(*j.report);
    ASSERT_TRUE(j.planned.order.has_value());
    EXPECT_GE(j.planned.order->smallest_margin_mm(), 2.0);
    EXPECT_GT(j.planned.order->collision_edges, 0);
}

}  // namespace
}  // namespace maxslice::pipeline
