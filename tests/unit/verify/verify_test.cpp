#include "maxslice/verify/verify.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>

#include "maxslice/machine/machine_moves.hpp"
#include "maxslice/machine/program_builder.hpp"
#include "maxslice/machine/summary.hpp"
#include "maxslice/machine/writer.hpp"
#include "support/fixtures.hpp"
#include "verify_programs.hpp"

namespace maxslice::verify {
namespace {

using core::Vec3d;
using testing::load;
using testing::ProgramText;
using testing::zigzag_block;

using testing::kHalf;
using testing::kLayers;
using testing::placed_block;

Vec3d plate_centre(const machine::Profiles& p) {
    const mesh::TriangleMesh m = placed_block(p);
    return mesh::bounding_box(m).center();
}

Report verified(const std::string& text, const machine::Profiles& p, const VerifySettings& s = {}) {
    auto r = verify_program(text, placed_block(p), p, s);
    EXPECT_TRUE(r.has_value()) << r.error().describe();
    return r.value_or(Report{});
}

TEST(Verify, CleanZigzagBlockPassesGm) {
    const machine::Profiles p = load("reference_lmd.toml");
    ProgramText prog(p, ProgramDialect::kGm, false);
    const Vec3d c = plate_centre(p);
    const double length = zigzag_block(prog, p, c.x, c.y, kHalf, kLayers);
    const Report r = verified(prog.text(), p);
    EXPECT_TRUE(r.passed()) << report_text(r);
    EXPECT_GE(r.coverage, 0.97) << report_text(r);
    EXPECT_LT(r.excess, 0.05) << report_text(r);
    EXPECT_NEAR(r.deposition_length_mm, length, 1e-6 * length);
    EXPECT_NEAR(r.bead_height_min_mm, 0.5, 1e-9);
    EXPECT_NEAR(r.bead_height_max_mm, 0.5, 1e-9);
    EXPECT_EQ(r.laser_on_count, kLayers);
    // Deposit time: the length at the deposition feed.
    EXPECT_NEAR(r.deposit_time_s, 60.0 * length / p.process.deposition_feed_mm_min, 1e-6);
    EXPECT_GT(r.poses_checked, 1000U);
    EXPECT_EQ(r.below_plate.count, 0U);
}

TEST(Verify, CleanZigzagBlockPassesLinuxCnc) {
    const machine::Profiles p = load("linuxcnc_generic.toml");
    ProgramText prog(p, ProgramDialect::kLinuxCnc, false);
    const Vec3d c = plate_centre(p);
    EXPECT_NEAR(c.x, 250.0, 1e-9);  // the middle of the X travel
    zigzag_block(prog, p, c.x, c.y, kHalf, kLayers);
    prog.raw("M2");
    const Report r = verified(prog.text(), p);
    EXPECT_TRUE(r.passed()) << report_text(r);
    EXPECT_GE(r.coverage, 0.97) << report_text(r);
    EXPECT_LT(r.excess, 0.05) << report_text(r);
    EXPECT_EQ(r.laser_on_count, kLayers);
}

TEST(Verify, TravelThroughDepositedMaterialCollides) {
    for (const auto& [file, dialect] :
         {std::pair{"reference_lmd.toml", ProgramDialect::kGm},
          std::pair{"linuxcnc_generic.toml", ProgramDialect::kLinuxCnc}}) {
        SCOPED_TRACE(file);
        const machine::Profiles p = load(file);
        ProgramText prog(p, dialect, false);
        const Vec3d c = plate_centre(p);
        zigzag_block(prog, p, c.x, c.y, kHalf, kLayers);
        prog.move(c.x - kHalf - 20.0, c.y, 30.0, p.process.travel_feed_mm_min);  // up and aside
        prog.move(c.x - kHalf - 20.0, c.y, 3.0, p.process.travel_feed_mm_min);   // half-way down
        const int through = prog.move(c.x + kHalf + 20.0, c.y, 3.0, p.process.travel_feed_mm_min);
        const Report r = verified(prog.text(), p);
        EXPECT_FALSE(r.passed());
        EXPECT_EQ(r.collisions.count, 1U) << report_text(r);
        ASSERT_TRUE(r.collisions.first);
        EXPECT_EQ(r.collisions.first->line, through);
        // The material met lies in the block.
        EXPECT_LE(std::abs(r.collisions.first->point_mm.x - c.x), kHalf + r.voxel_mm);
        // A travel: where it ends is listed for the job to take it over the part (decision
        // 0048), beyond the block on the side it went to.
        ASSERT_EQ(r.travel_fault_ends.size(), 1U);
        EXPECT_GT(r.travel_fault_ends.front().x - r.collisions.first->point_mm.x, 20.0);
        EXPECT_EQ(r.unsupported.count, 0U);
        EXPECT_EQ(r.limit_violations.count, 0U);
    }
}

TEST(Verify, TravelDownOntoTheBlockSideCollides) {
    // Approaching beside the block at the plate: the cone's side meets the block's wall.
    const machine::Profiles p = load("reference_lmd.toml");
    ProgramText prog(p, ProgramDialect::kGm, false);
    const Vec3d c = plate_centre(p);
    zigzag_block(prog, p, c.x, c.y, kHalf, kLayers);
    prog.move(c.x + kHalf + 2.0, c.y, 30.0, p.process.travel_feed_mm_min);
    const int down = prog.move(c.x + kHalf + 2.0, c.y, 1.0, p.process.travel_feed_mm_min);
    const Report r = verified(prog.text(), p);
    EXPECT_EQ(r.collisions.count, 1U) << report_text(r);
    ASSERT_TRUE(r.collisions.first);
    EXPECT_EQ(r.collisions.first->line, down);
}

TEST(Verify, BeadInMidAirIsUnsupported) {
    const machine::Profiles p = load("reference_lmd.toml");
    ProgramText prog(p, ProgramDialect::kGm, false);
    const Vec3d c = plate_centre(p);
    zigzag_block(prog, p, c.x, c.y, kHalf, kLayers);
    // 10 mm above the block's top: a track that rests on nothing.
    prog.move(c.x - 5.0, c.y, 16.0, p.process.travel_feed_mm_min);
    prog.laser(true);
    const int air = prog.move(c.x + 5.0, c.y, 16.0, p.process.deposition_feed_mm_min);
    prog.laser(false);
    const Report r = verified(prog.text(), p);
    EXPECT_FALSE(r.passed());
    EXPECT_EQ(r.unsupported.count, 1U) << report_text(r);
    ASSERT_TRUE(r.unsupported.first);
    EXPECT_EQ(r.unsupported.first->line, air);
    EXPECT_NEAR(r.unsupported.first->point_mm.z, 15.5, 1e-6);  // bead bottom = tip - h
    EXPECT_NEAR(r.unsupported_length_mm, 10.0, 1.0);
    EXPECT_EQ(r.collisions.count, 0U) << report_text(r);
    EXPECT_GT(r.excess, 0.0);
}

TEST(Verify, TrackOnTheTopLayerIsSupported) {
    // The same track one layer above the top rests on the block: no finding.
    const machine::Profiles p = load("reference_lmd.toml");
    ProgramText prog(p, ProgramDialect::kGm, false);
    const Vec3d c = plate_centre(p);
    zigzag_block(prog, p, c.x, c.y, kHalf, kLayers);
    prog.move(c.x - 5.0, c.y, kLayers * 0.5 + 0.5, p.process.travel_feed_mm_min);
    prog.laser(true);
    prog.move(c.x + 5.0, c.y, kLayers * 0.5 + 0.5, p.process.deposition_feed_mm_min);
    prog.laser(false);
    const Report r = verified(prog.text(), p);
    EXPECT_TRUE(r.passed()) << report_text(r);
}

TEST(Verify, AxisOverItsLimitIsReported) {
    const machine::Profiles p = load("reference_lmd.toml");
    ProgramText prog(p, ProgramDialect::kGm, false);
    const Vec3d c = plate_centre(p);
    zigzag_block(prog, p, c.x, c.y, kHalf, 2);
    prog.move(c.x, c.y, 50.0, p.process.travel_feed_mm_min);
    const int over = prog.move(450.0, c.y, 50.0, p.process.travel_feed_mm_min);  // X max 400
    prog.move(c.x, c.y, 50.0, p.process.travel_feed_mm_min);
    const Report r = verified(prog.text(), p);
    EXPECT_FALSE(r.passed());
    EXPECT_EQ(r.limit_violations.count, 1U) << report_text(r);
    ASSERT_TRUE(r.limit_violations.first);
    EXPECT_EQ(r.limit_violations.first->line, over);
    EXPECT_NE(r.limit_violations.first->detail.find("machine.axes.X"), std::string::npos);
    EXPECT_EQ(r.collisions.count, 0U);
}

TEST(Verify, RotaryAxisOverItsLimitIsReported) {
    const machine::Profiles p = load("reference_5axis_ac.toml");
    ProgramText prog(p, ProgramDialect::kGm, true);
    prog.move(0.0, 0.0, 100.0, p.process.travel_feed_mm_min);
    const int over = prog.move(0.0, 0.0, 100.0, p.process.travel_feed_mm_min, 130.0, 0.0);
    const Report r = verified(prog.text(), p);
    EXPECT_EQ(r.limit_violations.count, 1U) << report_text(r);
    ASSERT_TRUE(r.limit_violations.first);
    EXPECT_EQ(r.limit_violations.first->line, over);
    EXPECT_NE(r.limit_violations.first->detail.find("machine.axes.A"), std::string::npos);
}

TEST(Verify, FiveAxisBlockWithSafeReorientationPasses) {
    const machine::Profiles p = load("reference_5axis_ac.toml");
    ProgramText prog(p, ProgramDialect::kGm, true);
    const Vec3d c = plate_centre(p);
    EXPECT_NEAR(c.x, 0.0, 1e-9);  // the C axis
    const double travel = p.process.travel_feed_mm_min;
    zigzag_block(prog, p, c.x, c.y, kHalf, kLayers);
    // Retract above the sphere about the pivot that holds the part and its substrate plate
    // (the profile's 300 x 300 x 20 mm, decision 0028: turned 90 degrees it stands 150 mm
    // high), turn, cross, stay there: every point of the head is then higher than any point
    // of the plate whatever the table does.
    ASSERT_TRUE(p.machine.substrate.has_value());
    const machine::SubstrateProfile& plate = *p.machine.substrate;
    const double safe =
        std::hypot(0.5 * plate.size_x_mm, 0.5 * plate.size_y_mm, plate.thickness_mm) + 10.0;
    const machine::AxisLimits* z = p.machine.find_axis("Z");
    ASSERT_NE(z, nullptr);
    ASSERT_LT(safe, z->max);
    prog.move(c.x - kHalf + 1.25, c.y + kHalf - 1.25, safe, travel);
    prog.move(c.x - kHalf + 1.25, c.y + kHalf - 1.25, safe, travel, 90.0, 0.0);
    prog.move(0.0, 0.0, safe, travel, 90.0, 0.0);
    const Report r = verified(prog.text(), p);
    EXPECT_TRUE(r.passed()) << report_text(r);
    EXPECT_GE(r.coverage, 0.97);
    EXPECT_NEAR(r.rotary_travel_deg, 90.0, 1e-9);
}

TEST(Verify, RotationWithTheNozzleDownCollides) {
    const machine::Profiles p = load("reference_5axis_ac.toml");
    ProgramText prog(p, ProgramDialect::kGm, true);
    const Vec3d c = plate_centre(p);
    zigzag_block(prog, p, c.x, c.y, kHalf, kLayers);
    // Laser off at the last layer's end, the nozzle still on the block: turn A.
    const double top = kLayers * 0.5;
    prog.move(c.x, c.y, top, p.process.travel_feed_mm_min);
    const int turn = prog.move(c.x, c.y, top, p.process.travel_feed_mm_min, 30.0, 0.0);
    const Report r = verified(prog.text(), p);
    EXPECT_FALSE(r.passed());
    EXPECT_EQ(r.collisions.count, 1U) << report_text(r);
    ASSERT_TRUE(r.collisions.first);
    EXPECT_EQ(r.collisions.first->line, turn);
    EXPECT_EQ(r.limit_violations.count, 0U);
    EXPECT_EQ(r.travel_fault_ends.size(), 1U);
}

// A fanuc program under tool centre point control builds the block with the table turned by
// C = 45 and an offset pivot: X Y Z are pivot + the part-frame tip, so the beads land on the
// model whatever C is; read as joint space the same text lays the block turned by 45 deg
// about the C axis (the model's centre), which covers about 83% of it.
TEST(Verify, ToolCentrePointProgramBuildsTheBlockAtAnyC) {
    machine::Profiles p = load("reference_5axis_ac.toml");
    p.machine.table->pivot_mm = {10.0, 20.0, -50.0};
    p.machine.table->c_offset_x_mm = 3.0;
    p.machine.table->c_offset_y_mm = -4.0;
    const Vec3d c = plate_centre(p);
    EXPECT_NEAR(c.x, 3.0, 1e-9);
    EXPECT_NEAR(c.y, -4.0, 1e-9);
    ProgramText prog(p, ProgramDialect::kFanuc, true);
    prog.raw("G49");
    prog.move(0.0, 0.0, 300.0, p.process.travel_feed_mm_min, 0.0, 0.0);
    prog.move(0.0, 0.0, 300.0, p.process.travel_feed_mm_min, 0.0, 45.0);
    prog.raw("G43.4 H1");
    prog.set_frame(p.machine.table->pivot_mm, 0.0, 45.0);
    zigzag_block(prog, p, c.x, c.y, kHalf, kLayers);
    prog.raw("G49");
    prog.raw("M30");
    prog.raw("%");
    VerifySettings s;
    s.dialect = ProgramDialect::kFanuc;
    const Report r = verified(prog.text(), p, s);
    EXPECT_TRUE(r.passed()) << report_text(r);
    EXPECT_GE(r.coverage, 0.97) << report_text(r);
    EXPECT_LT(r.excess, 0.05) << report_text(r);
    std::string joint = prog.text();
    for (const std::string word : {"G43.4 H1\n", "G49\n"}) {
        for (auto pos = joint.find(word); pos != std::string::npos; pos = joint.find(word)) {
            joint.erase(pos, word.size());
        }
    }
    const Report j = verified(joint, p, s);
    EXPECT_LT(j.coverage, 0.9) << report_text(j);
    EXPECT_GT(j.coverage, 0.75) << report_text(j);
}

TEST(Verify, ClearanceWidensTheHead) {
    // A travel 4 mm beside the block's wall at half its height: the cone (30 deg) reaches the
    // wall's radius 6.9 mm above the tip, above the block's top (3 mm up): no contact; the
    // wall's top edge is 2 mm from the cone. With the nozzle's tip 1 mm above the melt pool
    // that is hardware: a 3 mm clearance meets it (a clearance finding, not a contact), the
    // profile's 1 mm does not. With the reference's 10 mm standoff it is the powder stream,
    // which needs only to stay clear (decision 0023).
    machine::Profiles p = load("reference_lmd.toml");
    ASSERT_TRUE(p.machine.nozzle.has_value());
    ProgramText prog(p, ProgramDialect::kGm, false);
    const Vec3d c = plate_centre(p);
    zigzag_block(prog, p, c.x, c.y, kHalf, kLayers);
    prog.move(c.x + kHalf + 4.0, c.y - 30.0, 30.0, p.process.travel_feed_mm_min);
    prog.move(c.x + kHalf + 4.0, c.y - 30.0, 3.0, p.process.travel_feed_mm_min);
    prog.move(c.x + kHalf + 4.0, c.y + 30.0, 3.0, p.process.travel_feed_mm_min);
    VerifySettings s;
    s.clearance_mm = 3.0;
    const Report stream = verified(prog.text(), p, s);
    EXPECT_EQ(stream.collisions.count, 0U) << report_text(stream);
    EXPECT_EQ(stream.clearance.count, 0U) << report_text(stream);
    p.machine.nozzle->standoff_mm = 1.0;
    const Report profile = verified(prog.text(), p);
    EXPECT_EQ(profile.clearance_mm, p.machine.nozzle->clearance_mm);
    EXPECT_EQ(profile.collisions.count, 0U) << report_text(profile);
    EXPECT_EQ(profile.clearance.count, 0U) << report_text(profile);
    const Report wide = verified(prog.text(), p, s);
    EXPECT_EQ(wide.collisions.count, 0U) << report_text(wide);
    EXPECT_GE(wide.clearance.count, 1U) << report_text(wide);
    EXPECT_FALSE(wide.passed());
    EXPECT_NE(report_text(wide).find("\nclearance 3.00  "), std::string::npos) << report_text(wide);
    EXPECT_NE(report_json(wide).find("\"clearance\": {\"count\": "), std::string::npos);
}

TEST(Verify, SameInputSameReportBytes) {
    const machine::Profiles p = load("reference_5axis_ac.toml");
    ProgramText prog(p, ProgramDialect::kGm, true);
    const Vec3d c = plate_centre(p);
    zigzag_block(prog, p, c.x, c.y, kHalf, 4);
    prog.move(c.x, c.y, 2.0, p.process.travel_feed_mm_min, 20.0, 10.0);
    const std::string a = report_json(verified(prog.text(), p));
    const std::string b = report_json(verified(prog.text(), p));
    EXPECT_EQ(a, b);
    EXPECT_NE(a.find("\"passed\": false"), std::string::npos);
}

// A block's poses are checked side by side: the findings, their counts and which pose each
// names first are those of one pose after another, whatever the thread count. One program with
// a pass within the clearance of the block's wall, a bead in mid-air and a travel through the
// block, each a move of many poses.
TEST(Verify, TheFindingsDoNotDependOnTheThreads) {
    machine::Profiles p = load("reference_lmd.toml");
    ASSERT_TRUE(p.machine.nozzle.has_value());
    p.machine.nozzle->standoff_mm = 1.0;
    ProgramText prog(p, ProgramDialect::kGm, false);
    const Vec3d c = plate_centre(p);
    zigzag_block(prog, p, c.x, c.y, kHalf, kLayers);
    prog.move(c.x + kHalf + 4.0, c.y - 30.0, 30.0, p.process.travel_feed_mm_min);
    prog.move(c.x + kHalf + 4.0, c.y - 30.0, 3.0, p.process.travel_feed_mm_min);
    const int near = prog.move(c.x + kHalf + 4.0, c.y + 30.0, 3.0, p.process.travel_feed_mm_min);
    prog.move(c.x - 5.0, c.y, 16.0, p.process.travel_feed_mm_min);
    prog.laser(true);
    const int air = prog.move(c.x + 5.0, c.y, 16.0, p.process.deposition_feed_mm_min);
    prog.laser(false);
    prog.move(c.x - kHalf - 20.0, c.y, 30.0, p.process.travel_feed_mm_min);
    prog.move(c.x - kHalf - 20.0, c.y, 3.0, p.process.travel_feed_mm_min);
    const int through = prog.move(c.x + kHalf + 20.0, c.y, 3.0, p.process.travel_feed_mm_min);
    VerifySettings s;
    s.clearance_mm = 3.0;
    const Report many = verified(prog.text(), p, s);
    Report one;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = verified(prog.text(), p, s);
    }
    EXPECT_EQ(report_json(many), report_json(one));
    ASSERT_TRUE(many.clearance.first && many.unsupported.first && many.collisions.first)
        << report_text(many);
    EXPECT_LE(many.clearance.first->line, near);  // the 1 mm standoff: the block itself too
    EXPECT_EQ(many.unsupported.first->line, air);
    EXPECT_EQ(many.collisions.first->line, through);
    EXPECT_NEAR(many.unsupported_length_mm, 10.0, 1.0);
}

TEST(Verify, JsonReportParsesAndCarriesTheFindings) {
    const machine::Profiles p = load("reference_lmd.toml");
    ProgramText prog(p, ProgramDialect::kGm, false);
    const Vec3d c = plate_centre(p);
    zigzag_block(prog, p, c.x, c.y, kHalf, 4);
    prog.move(c.x, c.y, 30.0, p.process.travel_feed_mm_min);
    const int over = prog.move(c.x, 450.0, 30.0, p.process.travel_feed_mm_min);
    const Report r = verified(prog.text(), p);
    const auto j = nlohmann::json::parse(report_json(r));
    EXPECT_FALSE(j.at("passed").get<bool>());
    EXPECT_EQ(j.at("limit_violations").at("count").get<int>(), 1);
    EXPECT_EQ(j.at("limit_violations").at("first").at("line").get<int>(), over);
    EXPECT_EQ(j.at("contact").at("count").get<int>(), 0);
    EXPECT_FALSE(j.at("contact").contains("first"));
    EXPECT_NEAR(j.at("coverage").get<double>(), r.coverage, 1e-6);
    EXPECT_NEAR(j.at("build_time_s").get<double>(), r.build_time_s, 1e-3);
    EXPECT_EQ(j.at("dialect").get<std::string>(), "gm");
    EXPECT_NE(report_text(r).find("FAILED"), std::string::npos);
}

// The writers' own output (3-axis gm and linuxcnc): the replay's lengths, times and laser
// count agree with machine::summarize of the program written.
TEST(Verify, AgreesWithTheWritersSummary) {
    for (const char* file : {"reference_lmd.toml", "linuxcnc_generic.toml"}) {
        SCOPED_TRACE(file);
        const machine::Profiles p = load(file);
        const Vec3d c = plate_centre(p);
        machine::Program program;
        for (int k = 1; k <= 8; ++k) {
            const double z = 0.5 * k;
            for (const double r : {13.75, 11.5, 9.25}) {
                const std::vector<Vec3d> loop = {{c.x - r, c.y - r, z},
                                                 {c.x + r, c.y - r, z},
                                                 {c.x + r, c.y + r, z},
                                                 {c.x - r, c.y + r, z},
                                                 {c.x - r, c.y - r, z}};
                machine::append_wire(program, loop, p.process, k);
            }
        }
        auto text = machine::write_program(program, p.machine, p.process);
        ASSERT_TRUE(text) << text.error().describe();
        auto sum = machine::summarize(program, p.process);
        ASSERT_TRUE(sum);
        const Report r = verified(*text, p);
        EXPECT_NEAR(r.deposition_length_mm, sum->deposit_length_mm, 1e-4 * sum->deposit_length_mm);
        EXPECT_NEAR(r.idle_length_mm, sum->travel_length_mm, 1e-4 * sum->travel_length_mm);
        EXPECT_NEAR(r.deposit_time_s, sum->deposit_time_s, 1e-4 * sum->deposit_time_s);
        EXPECT_NEAR(r.idle_time_s, sum->travel_time_s, 1e-4 * sum->travel_time_s);
        EXPECT_NEAR(r.dwell_time_s, sum->dwell_time_s, 1e-9);
        EXPECT_NEAR(r.build_time_s, sum->build_time_s, 1e-4 * sum->build_time_s);
        EXPECT_EQ(r.laser_on_count, sum->laser_on_count);
        EXPECT_TRUE(r.passed()) << report_text(r);
    }
}

// The block as a part-frame program built along +Z: kLayers zigzag layers of 17 tracks
// around the block's centre c.
machine::Program block_program(const machine::Profiles& p, const Vec3d& c) {
    const double w = p.process.track_width_mm, h = p.process.layer_height_mm;
    const int tracks = 17;
    const double pitch = (2 * kHalf - w) / (tracks - 1);
    machine::Program program;
    for (int layer = 1; layer <= kLayers; ++layer) {
        std::vector<Vec3d> wire;
        for (int i = 0; i < tracks; ++i) {
            const double y = c.y - kHalf + 0.5 * w + i * pitch;
            const double xa = c.x - kHalf + 0.5 * w, xb = c.x + kHalf - 0.5 * w;
            wire.push_back({i % 2 == 0 ? xa : xb, y, layer * h});
            wire.push_back({i % 2 == 0 ? xb : xa, y, layer * h});
        }
        machine::append_wire(program, wire, p.process, layer - 1);
    }
    return program;
}

// The 5-axis writers' output in every dialect (joint space for gm and linuxcnc, tool centre
// point control for fanuc and siemens): a block built along +Z, then, after a re-orientation,
// one wire laid along +Y against the block's +Y wall. It replays clean, covers the block,
// and the one sideways wire rests on the wall (supported) and is the only excess.
// The machine's plate is the block's size plus 2 mm: the sideways wire lies 3 mm above the
// plate, where the horizontal head's 30 mm body meets the profiles' 300 x 300 mm plate
// (decision 0028; TheHeadMeetsTheSubstrateOnlyWhereThePlateIs checks that) but passes beside
// this one. The dialects are under test here, with a plate modelled.
TEST(Verify, FiveAxisWritersOutputReplaysCleanInEveryDialect) {
    for (const char* file : {"reference_5axis_ac.toml", "linuxcnc_5axis_ac.toml",
                             "fanuc_5axis_ac.toml", "siemens_5axis_bc.toml"}) {
        SCOPED_TRACE(file);
        machine::Profiles p = load(file);
        ASSERT_FALSE(p.machine.name.empty());
        ASSERT_TRUE(p.machine.substrate.has_value());
        const double fit = 2 * kHalf + 2.0;
        p.machine.substrate =
            machine::SubstrateProfile{fit, fit, p.machine.substrate->thickness_mm};
        const mesh::TriangleMesh model = placed_block(p);
        const Vec3d c = mesh::bounding_box(model).center();
        const double h = p.process.layer_height_mm;
        machine::Program program = block_program(p, c);
        // One track on the +Y wall, built along +Y: its top edge centre h out of the wall.
        const Vec3d side{0.0, 1.0, 0.0};
        const double yw = c.y + kHalf + h;
        const std::vector<Vec3d> along = {{c.x - 10.0, yw, 3.0}, {c.x + 10.0, yw, 3.0}};
        const std::size_t block_moves = program.moves.size();
        machine::append_wire(program, along, p.process, kLayers, 1, side);
        machine::WriteOptions wo;
        wo.clear_z_mm = machine::clear_height_mm(p.machine, model.vertices);
        auto text = machine::write_program(program, p.machine, p.process, wo);
        ASSERT_TRUE(text) << text.error().describe();
        auto r = verify_program(*text, model, p);
        ASSERT_TRUE(r) << r.error().describe();
        EXPECT_TRUE(r->passed()) << report_text(*r);
        EXPECT_GE(r->coverage, 0.97) << report_text(*r);
        EXPECT_GT(r->rotary_travel_deg, 80.0) << report_text(*r);
        // The sideways bead (20 x 2.5 x 0.5 mm3 and its round ends, 27.5 mm3) is outside.
        EXPECT_NEAR(r->excess_volume_mm3, 27.5, 5.0) << report_text(*r);
        EXPECT_EQ(r->laser_on_count, kLayers + 1);
        // The same wire 2.5 mm off the wall rests on nothing.
        const std::vector<Vec3d> off = {{c.x - 10.0, yw + 2.5, 3.0}, {c.x + 10.0, yw + 2.5, 3.0}};
        program.moves.resize(block_moves);
        machine::append_wire(program, off, p.process, kLayers, 1, side);
        text = machine::write_program(program, p.machine, p.process, wo);
        ASSERT_TRUE(text) << text.error().describe();
        r = verify_program(*text, model, p);
        ASSERT_TRUE(r) << r.error().describe();
        EXPECT_EQ(r->unsupported.count, 1U) << report_text(*r);
        EXPECT_EQ(r->collisions.count, 0U) << report_text(*r);
    }
}

// The block and one track on its +Y wall built along +Y at 3 mm height: the head lies
// horizontal there, its 30 mm body reaching 27 mm below the plate's level. A substrate plate
// under the block stops it only where the plate is: a 300 x 300 mm plate is hit, a plate the
// block's size plus 2 mm is not (the head ends its cone and starts its body beyond the plate's
// edge), nor a plate that is long in X but short in Y; one long in Y is hit again. A plate
// smaller than the block leaves the first layer's outer beads on nothing.
// The program is written for the machine without a plate (the bundled profile's own plate
// is taken out, decision 0028); each plate under test is then put in for the replay.
TEST(Verify, TheHeadMeetsTheSubstrateOnlyWhereThePlateIs) {
    machine::Profiles p = load("reference_5axis_ac.toml");
    ASSERT_TRUE(p.machine.substrate.has_value());
    p.machine.substrate.reset();
    const mesh::TriangleMesh model = placed_block(p);
    const Vec3d c = mesh::bounding_box(model).center();
    const double h = p.process.layer_height_mm;
    machine::Program program = block_program(p, c);
    const double yw = c.y + kHalf + h;
    const std::vector<Vec3d> along = {{c.x - 10.0, yw, 3.0}, {c.x + 10.0, yw, 3.0}};
    machine::append_wire(program, along, p.process, kLayers, 1, {0.0, 1.0, 0.0});
    machine::WriteOptions wo;
    wo.clear_z_mm = machine::clear_height_mm(p.machine, model.vertices);
    const auto text = machine::write_program(program, p.machine, p.process, wo);
    ASSERT_TRUE(text) << text.error().describe();
    const auto with = [&](std::optional<machine::SubstrateProfile> plate) {
        p.machine.substrate = plate;
        auto r = verify_program(*text, model, p);
        EXPECT_TRUE(r) << r.error().describe();
        return r.value_or(Report{});
    };
    const Report none = with(std::nullopt);
    EXPECT_TRUE(none.passed()) << report_text(none);
    // Without a substrate the reach below the plate's level is a note: at least the body's
    // lowest line, its radius below the tip at 3 mm (the table's turn sweeps the head lower).
    EXPECT_FALSE(none.substrate);
    EXPECT_GE(none.below_plate.count, 1U);
    EXPECT_GE(none.below_plate_mm, p.machine.nozzle->body_radius_mm - 3.0 - 1e-6);
    ASSERT_TRUE(none.below_plate.first);
    EXPECT_LT(none.below_plate.first->point_mm.z, 0.0);
    EXPECT_NE(report_text(none).find("below the plate's level"), std::string::npos);

    const Report large = with(machine::SubstrateProfile{300.0, 300.0, 10.0});
    EXPECT_TRUE(large.substrate);
    EXPECT_EQ(large.below_plate.count, 0U);
    EXPECT_GE(large.collisions.count, 1U) << report_text(large);
    ASSERT_TRUE(large.collisions.first);
    EXPECT_NE(large.collisions.first->detail.find("substrate"), std::string::npos);
    EXPECT_LE(large.collisions.first->point_mm.z, 0.0);
    EXPECT_GE(large.collisions.first->point_mm.z, -10.0);
    EXPECT_GT(large.collisions.first->point_mm.y, yw);  // beside the wall, under the head
    EXPECT_EQ(large.unsupported.count, 0U) << report_text(large);

    const double fit = 2 * kHalf + 2.0;
    const Report snug = with(machine::SubstrateProfile{fit, fit, 10.0});
    EXPECT_TRUE(snug.passed()) << report_text(snug);
    const Report long_x = with(machine::SubstrateProfile{300.0, fit, 10.0});
    EXPECT_TRUE(long_x.passed()) << report_text(long_x);
    const Report long_y = with(machine::SubstrateProfile{fit, 300.0, 10.0});
    EXPECT_GE(long_y.collisions.count, 1U) << report_text(long_y);

    const Report small = with(machine::SubstrateProfile{20.0, 20.0, 10.0});
    EXPECT_EQ(small.collisions.count, 0U) << report_text(small);
    EXPECT_GE(small.unsupported.count, 1U) << report_text(small);
    ASSERT_TRUE(small.unsupported.first);
    EXPECT_GT(std::max(std::abs(small.unsupported.first->point_mm.x - c.x),
                       std::abs(small.unsupported.first->point_mm.y - c.y)),
              10.0 - 1e-9);
}

// A track built along +Y 40 mm up (where the horizontal head clears the plate by 10 mm) after
// the block: the table turns A by 90 deg between them. Turned over the block's last point
// (13.75 mm off the A axis), the tip would end the turn 13.75 mm under the plate's level, the
// head inside any plate under it; the writer turns where the head stays above the plate's
// level (decision 0016), so the replay finds the head never below it, and nothing hit in a
// 300 x 300 x 20 mm substrate.
TEST(Verify, TheTableTurnsWithTheHeadAboveThePlate) {
    machine::Profiles p = load("reference_5axis_ac.toml");
    const mesh::TriangleMesh model = placed_block(p);
    const Vec3d c = mesh::bounding_box(model).center();
    machine::Program program;
    const double w = p.process.track_width_mm, h = p.process.layer_height_mm;
    for (int layer = 1; layer <= kLayers; ++layer) {
        const std::vector<Vec3d> wire = {{c.x - kHalf + 0.5 * w, c.y + kHalf - 0.5 * w, layer * h},
                                         {c.x + kHalf - 0.5 * w, c.y + kHalf - 0.5 * w, layer * h}};
        machine::append_wire(program, wire, p.process, layer - 1);
    }
    const std::vector<Vec3d> high = {{c.x - 10.0, c.y + kHalf + h, 40.0},
                                     {c.x + 10.0, c.y + kHalf + h, 40.0}};
    machine::append_wire(program, high, p.process, kLayers, 1, {0.0, 1.0, 0.0});
    machine::WriteOptions wo;
    wo.clear_z_mm = machine::clear_height_mm(p.machine, model.vertices);
    const auto text = machine::write_program(program, p.machine, p.process, wo);
    ASSERT_TRUE(text) << text.error().describe();
    auto r = verify_program(*text, model, p);
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->collisions.count, 0U) << report_text(*r);
    EXPECT_EQ(r->below_plate.count, 0U) << report_text(*r);
    EXPECT_NEAR(r->rotary_travel_deg, 90.0, 1e-9);
    p.machine.substrate = machine::SubstrateProfile{300.0, 300.0, 20.0};
    r = verify_program(*text, model, p);
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->collisions.count, 0U) << report_text(*r);
    EXPECT_EQ(r->limit_violations.count, 0U) << report_text(*r);
}

TEST(Verify, CoverageFallsWhenLayersAreMissing) {
    const machine::Profiles p = load("reference_lmd.toml");
    ProgramText prog(p, ProgramDialect::kGm, false);
    const Vec3d c = plate_centre(p);
    zigzag_block(prog, p, c.x, c.y, kHalf, kLayers / 2);
    const Report r = verified(prog.text(), p);
    EXPECT_TRUE(r.passed());
    EXPECT_NEAR(r.coverage, 0.5, 0.03) << report_text(r);
}

TEST(Verify, AnOpenModelIsFlaggedAndItsCoverageMarkedAsAnEstimate) {
    const machine::Profiles p = load("reference_lmd.toml");
    ProgramText prog(p, ProgramDialect::kGm, false);
    const Vec3d c = plate_centre(p);
    zigzag_block(prog, p, c.x, c.y, kHalf, kLayers);
    const Report closed = verified(prog.text(), p);
    EXPECT_EQ(closed.model_open_columns, 0U);
    EXPECT_GT(closed.model_columns, 1000U);
    EXPECT_EQ(report_text(closed).find("not closed"), std::string::npos);
    // The block without its top: every column through the top stays open.
    mesh::TriangleMesh open = placed_block(p);
    const mesh::TriangleMesh whole = open;
    open.triangles.clear();
    for (std::size_t t = 0; t < whole.triangles.size(); ++t) {
        const bool top = whole.corner(t, 0).z == whole.corner(t, 1).z &&
                         whole.corner(t, 1).z == whole.corner(t, 2).z &&
                         whole.corner(t, 0).z > mesh::bounding_box(whole).center().z;
        if (!top) open.triangles.push_back(whole.triangles[t]);
    }
    ASSERT_LT(open.triangles.size(), whole.triangles.size());
    auto r = verify_program(prog.text(), open, p);
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->model_open_columns, r->model_columns);
    EXPECT_NE(report_text(*r).find("not closed"), std::string::npos) << report_text(*r);
    EXPECT_TRUE(r->passed());  // the checks of the program do not depend on the model
}

// One track on the plate at `feed`: its report (fine voxels: a 0.3 mm bead is two of the
// automatic 0.15 mm voxels, 0.5 mm three or four).
Report single_track(const machine::Profiles& p, double feed) {
    VerifySettings s;
    s.voxel_mm = 0.05;
    ProgramText prog(p, ProgramDialect::kGm, false);
    const Vec3d c = plate_centre(p);
    prog.move(c.x - 10.0, c.y, 0.5, p.process.travel_feed_mm_min);
    prog.laser(true);
    prog.move(c.x + 10.0, c.y, 0.5, feed);
    prog.laser(false);
    // A small model around the track keeps the fine grid small.
    auto model = place_model(test::box({0, 0, 0}, {24, 6, 1}), {0, 0, 1}, p.machine);
    EXPECT_TRUE(model);
    auto r = verify_program(prog.text(), model.value_or(mesh::TriangleMesh{}), p, s);
    EXPECT_TRUE(r) << r.error().describe();
    return r.value_or(Report{});
}

TEST(Verify, BeadHeightFollowsTheSpeedLaw) {
    machine::Profiles p = load("reference_lmd.toml");
    // Constant mass through the nominal point: 0.5 mm at 381 mm/min, 0.3 mm at 635 mm/min.
    const Report nominal = single_track(p, 381.0);
    const Report fast = single_track(p, 635.0);
    EXPECT_NEAR(nominal.bead_height_max_mm, 0.5, 1e-9);
    EXPECT_NEAR(fast.bead_height_max_mm, 0.3, 1e-9);
    EXPECT_NEAR(fast.deposited_volume_mm3 / nominal.deposited_volume_mm3, 0.3 / 0.5, 0.06);
    // 20 mm of track and its two round ends (a disc of the track's width).
    const double disc = std::numbers::pi * 1.25 * 1.25;
    EXPECT_NEAR(nominal.deposited_volume_mm3, (20.0 * 2.5 + disc) * 0.5, 0.04 * 27.5);
    // Measured pairs take over.
    p.process.speed_height = {
        {250.0, 0.72}, {300.0, 0.62}, {381.0, 0.5}, {500.0, 0.4}, {650.0, 0.3}};
    EXPECT_NEAR(single_track(p, 300.0).bead_height_max_mm, 0.62, 1e-9);
}

TEST(Verify, PlaceModelPutsTheBaseDirectionUpOnThePlateCentre) {
    const machine::Profiles p = load("linuxcnc_generic.toml");
    // A 10 x 20 x 30 box built along +X: after placement it stands 10 mm high.
    auto placed = place_model(test::box({5, 5, 5}, {15, 25, 35}), {1, 0, 0}, p.machine);
    ASSERT_TRUE(placed);
    const core::Box3d b = mesh::bounding_box(*placed);
    EXPECT_NEAR(b.min.z, 0.0, 1e-9);
    EXPECT_NEAR(b.max.z, 10.0, 1e-9);
    EXPECT_NEAR(b.center().x, 250.0, 1e-9);
    EXPECT_NEAR(b.center().y, 250.0, 1e-9);
    EXPECT_NEAR(b.size().y * b.size().x, 600.0, 1e-6);
    EXPECT_FALSE(place_model(test::box({0, 0, 0}, {1, 1, 1}), {0, 0, 0}, p.machine));
}

TEST(Verify, ProgramErrorsAreErrorsNotReports) {
    const machine::Profiles p = load("reference_lmd.toml");
    auto r = verify_program("0.00 0.00 G21\n0.00 0.00 G1 X1 Y2 Z3 Q4 F100\n", placed_block(p), p);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().describe().find("line 2"), std::string::npos) << r.error().describe();
}

}  // namespace
}  // namespace maxslice::verify
