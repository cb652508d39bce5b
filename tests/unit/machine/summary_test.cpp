#include <gtest/gtest.h>

#include "machine_fixtures.hpp"
#include "maxslice/machine/program_builder.hpp"
#include "maxslice/machine/program_check.hpp"
#include "maxslice/machine/summary.hpp"

namespace maxslice::machine {
namespace {

using testing::reference_process;

TEST(Summary, TwoWires) {
    const ProcessProfile process = reference_process();
    Program p;
    append_travel(p, {0.0, 0.0, 10.0}, process, -1);
    append_wire(p, testing::square(0.0, 0.0, 10.0, 0.5), process, 0);  // travel 9.5, dep. 40
    const std::vector<core::Vec3d> line{{0.0, 10.0, 1.0}, {30.0, 10.0, 1.0}};
    append_wire(p, line, process, 1);  // travel sqrt(100 + 0.25), deposit 30

    const auto s = summarize(p, process);
    ASSERT_TRUE(s.has_value()) << s.error().describe();
    const double travel = 9.5 + std::sqrt(100.25);
    EXPECT_NEAR(s->deposit_length_mm, 70.0, 1e-9);
    EXPECT_NEAR(s->travel_length_mm, travel, 1e-9);
    EXPECT_NEAR(s->deposit_time_s, 70.0 / 381.0 * 60.0, 1e-9);
    EXPECT_NEAR(s->travel_time_s, travel / 2540.0 * 60.0, 1e-9);
    EXPECT_NEAR(s->dwell_time_s, 1.0, 1e-12);
    EXPECT_NEAR(s->build_time_s, s->deposit_time_s + s->travel_time_s + 1.0, 1e-9);
    EXPECT_NEAR(s->powder_delivered_g, 8.0 * 70.0 / 381.0, 1e-9);
    EXPECT_NEAR(s->powder_total_g, s->powder_delivered_g + 2 * 8.0 * 0.5 / 60.0, 1e-9);
    EXPECT_FALSE(s->deposited_mass_g.has_value());
    EXPECT_EQ(s->layer_count, 2);
    EXPECT_EQ(s->laser_on_count, 2);
    EXPECT_EQ(s->move_count, p.moves.size());

    ProcessProfile with_efficiency = process;
    with_efficiency.powder_catch_efficiency = 0.5;
    const auto e = summarize(p, with_efficiency);
    ASSERT_TRUE(e.has_value() && e->deposited_mass_g.has_value());
    EXPECT_NEAR(*e->deposited_mass_g, 0.5 * s->powder_delivered_g, 1e-12);
}

TEST(Summary, PlanarBlockCounts) {
    const ProcessProfile process = reference_process();
    const auto s = summarize(testing::planar_block(process, 5), process);
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(s->layer_count, 5);
    EXPECT_GT(s->laser_on_count, 5);
    EXPECT_GT(s->deposit_length_mm, 5 * 80.0);
}

TEST(Summary, Empty) {
    const auto s = summarize(Program{}, reference_process());
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(s->build_time_s, 0.0);
    EXPECT_EQ(s->layer_count, 0);
}

TEST(Summary, RefusesBrokenMoves) {
    const ProcessProfile process = reference_process();
    Program p = testing::planar_block(process, 1);
    p.moves[3].feed_mm_min = 0.0;
    EXPECT_FALSE(summarize(p, process).has_value());
    p.moves[3].feed_mm_min = NAN;
    EXPECT_FALSE(summarize(p, process).has_value());
}

// The beads the verifier finds on nothing are left out (decision 0039): the deposit moves
// they lie on become travels, the laser off over them and on again (with its dwell) before
// the next bead; the rest of the program stays as it was.
TEST(LeaveOut, TheMovesATipLiesOnBecomeTravelsWithTheLaserSwitchedAroundThem) {
    const ProcessProfile process = reference_process();
    Program p;
    const std::vector<core::Vec3d> wire{
        {0.0, 0.0, 1.0}, {10.0, 0.0, 1.0}, {20.0, 0.0, 1.0}, {30.0, 0.0, 1.0}};
    append_wire(p, wire, process, 0);
    const std::vector<core::Vec3d> other{{0.0, 5.0, 1.0}, {30.0, 5.0, 1.0}};
    append_wire(p, other, process, 0);
    const Program before = p;
    // Nothing near a track: the program is left as it was.
    const std::vector<core::Vec3d> far{{15.0, 2.5, 1.0}};
    EXPECT_EQ(leave_out_deposits(p, far, process, 0.01), 0.0);
    ASSERT_EQ(p.moves.size(), before.moves.size());
    for (std::size_t i = 0; i < p.moves.size(); ++i) {
        EXPECT_EQ(p.moves[i].kind, before.moves[i].kind);
        EXPECT_EQ(p.moves[i].position, before.moves[i].position);
    }
    // A tip on the middle segment of the first wire, one at the start of the second's only one.
    const std::vector<core::Vec3d> tips{{14.0, 0.004, 1.0}, {0.0, 5.0, 1.0}};
    EXPECT_NEAR(leave_out_deposits(p, tips, process, 0.01), 40.0, 1e-9);
    ASSERT_TRUE(check_program(p, testing::gm_machine(), process).has_value());
    const auto s = summarize(p, process);
    ASSERT_TRUE(s.has_value()) << s.error().describe();
    EXPECT_NEAR(s->deposit_length_mm, 20.0, 1e-9);
    EXPECT_EQ(s->laser_on_count, 2);  // the first wire in two pieces, the second left out
    // The laser is off on every travel and on for every deposit move.
    bool on = false;
    for (const Move& m : p.moves) {
        if (m.kind == MoveKind::kLaserOn) on = true;
        if (m.kind == MoveKind::kLaserOff) on = false;
        if (m.kind == MoveKind::kDeposit) {
            EXPECT_TRUE(on);
        }
        if (m.kind == MoveKind::kTravel) {
            EXPECT_FALSE(on);
        }
    }
}

// The travels the verifier finds meeting the part are taken over it (decision 0048): up along
// the head's direction to the top it is given, across, down to where the travel ended; other
// travels, and a travel on which the head turns, stay as they were.
TEST(LiftTravels, ATravelEndingAtAFaultGoesUpAcrossAndDown) {
    const ProcessProfile process = reference_process();
    const core::Vec3d tilted = core::normalized(core::Vec3d{1.0, 0.0, 1.0});
    Program p;
    append_wire(p, std::vector<core::Vec3d>{{0.0, 0.0, 1.0}, {10.0, 0.0, 1.0}}, process, 0);
    append_wire(p, std::vector<core::Vec3d>{{40.0, 0.0, 1.0}, {50.0, 0.0, 1.0}}, process, 0);
    append_wire(p, std::vector<core::Vec3d>{{50.0, 20.0, 1.0}, {60.0, 20.0, 1.0}}, process, 0);
    append_wire(p, std::vector<core::Vec3d>{{0.0, 40.0, 1.0}, {5.0, 40.0, 1.0}}, process, 1, 1,
                tilted);
    const Program before = p;
    const auto top = [](const core::Vec3d& d) { return d.z > 0.99 ? 30.0 : 1e3; };
    // No fault near a travel's end: nothing changes.
    const std::vector<core::Vec3d> none{{25.0, 0.0, 1.0}};
    EXPECT_EQ(lift_travels(p, none, 0.01, top), 0U);
    ASSERT_EQ(p.moves.size(), before.moves.size());
    // The travel to (40, 0, 1) and the turning one to (0, 40, 1).
    const std::vector<core::Vec3d> ends{{40.0, 0.004, 1.0}, {0.0, 40.0, 1.0}};
    EXPECT_EQ(lift_travels(p, ends, 0.01, top), 1U);
    ASSERT_EQ(p.moves.size(), before.moves.size() + 2);
    std::size_t k = 0;
    for (std::size_t i = 0; i < before.moves.size(); ++i, ++k) {
        const Move& m = before.moves[i];
        if (m.kind == MoveKind::kTravel && m.position == core::Vec3d{40.0, 0.0, 1.0}) {
            // Up from the end of the first wire, across at the top, down to the travel's end.
            EXPECT_EQ(p.moves[k].kind, MoveKind::kTravel);
            EXPECT_NEAR(core::norm(p.moves[k].position - core::Vec3d{10.0, 0.0, 30.0}), 0.0, 1e-9);
            EXPECT_EQ(p.moves[k + 1].kind, MoveKind::kTravel);
            EXPECT_NEAR(core::norm(p.moves[k + 1].position - core::Vec3d{40.0, 0.0, 30.0}), 0.0,
                        1e-9);
            EXPECT_EQ(p.moves[k + 1].feed_mm_min, m.feed_mm_min);
            EXPECT_EQ(p.moves[k + 1].laser_w, m.laser_w);
            k += 2;
        }
        EXPECT_EQ(p.moves[k].kind, m.kind);
        EXPECT_EQ(p.moves[k].position, m.position);
        EXPECT_EQ(p.moves[k].direction, m.direction);
    }
}

}  // namespace
}  // namespace maxslice::machine
