#include "maxslice/verify/replay.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "maxslice/machine/program_builder.hpp"
#include "maxslice/machine/writer.hpp"
#include "support/rs274.hpp"
#include "verify_programs.hpp"

namespace maxslice::verify {
namespace {

namespace fs = std::filesystem;
using core::Vec3d;
using testing::load;

machine::Profiles ac_table(machine::Dialect dialect) {
    machine::Profiles p = load("reference_5axis_ac.toml");
    p.machine.dialect = dialect;
    p.machine.table->pivot_mm = {10.0, 20.0, -50.0};
    p.machine.table->c_offset_x_mm = 3.0;
    p.machine.table->c_offset_y_mm = -4.0;
    p.machine.codes.laser_on.blocks = {"M68 E0 Q{power}", "M64 P0"};
    p.machine.codes.laser_off.blocks = {"M65 P0", "M68 E0 Q0"};
    p.machine.codes.powder_on.blocks = {"M64 P1"};
    p.machine.codes.powder_off.blocks = {"M65 P1"};
    return p;
}

TEST(Replay, GmColumnsSwitchTheLaserAndDwellIsInMilliseconds) {
    const machine::Profiles p = load("reference_lmd.toml");
    const std::string text =
        "0.00 0.00 G21\n0.00 0.00 G90\n0.00 0.00 G1 X0.000 Y0.000 Z0.500 F2540.0\n"
        "700.00 8.00 M8\n700.00 8.00 G4 P500\n700.00 8.00 G1 X10.000 Y0.000 Z0.500 F381.0\n"
        "0.00 0.00 M9\n0.00 0.00 G1 X10.000 Y5.000 Z1.000 F2540.0\n";
    auto r = replay_program(text, p, ProgramDialect::kGm);
    ASSERT_TRUE(r) << r.error().describe();
    ASSERT_EQ(r->blocks.size(), 4U);
    EXPECT_FALSE(r->blocks[0].laser_on);
    EXPECT_EQ(r->blocks[1].kind, ReplayBlock::Kind::kDwell);
    EXPECT_NEAR(r->blocks[1].dwell_s, 0.5, 1e-12);
    EXPECT_TRUE(r->blocks[2].laser_on);
    EXPECT_EQ(r->blocks[2].line, 6);
    EXPECT_NEAR(r->blocks[2].feed_mm_min, 381.0, 1e-12);
    EXPECT_NEAR(r->blocks[2].tip_mm.x, 10.0, 1e-12);
    EXPECT_FALSE(r->blocks[3].laser_on);
    EXPECT_EQ(r->laser_on_count, 1);
    EXPECT_EQ(r->line_count, 8);
    EXPECT_EQ(r->laser_powers_w, std::vector<double>{700.0});
}

TEST(Replay, TheProcessOfAProgramIsTheOneWhoseLaserPowerItHas) {
    const machine::Profiles p = load("reference_5axis_ac.toml");  // 700 W; finer 1: 300 W
    ASSERT_EQ(p.process.finer.size(), 1U);
    const auto process = [&](const std::string& powers) {
        std::string text = "0.00 0.00 G21\n0.00 0.00 G90\n0.00 0.00 G1 X0 Y0 Z5 A0 C0 F2000\n";
        std::istringstream in(powers);
        for (std::string w; in >> w;) text += w + " 3.00 G1 X1 Y0 Z5 F300\n0.00 0.00 M9\n";
        auto r = replay_program(text, p, ProgramDialect::kGm);
        EXPECT_TRUE(r) << r.error().describe();
        return r ? process_of(*r, p) : -2;
    };
    EXPECT_EQ(process("700.00"), 0);
    EXPECT_EQ(process("300.00 300.00"), 1);
    EXPECT_EQ(process("700.40"), 0);   // within half a watt
    EXPECT_EQ(process("450.00"), -1);  // no process has it
    EXPECT_EQ(process("700.00 300.00"), -1);
    EXPECT_EQ(process(""), -1);  // the laser never on: no power to go by
    std::string many;            // 17 distinct powers, each within half a watt of 700 W
    for (int i = 0; i <= 16; ++i) many += fmt::format("{:.2f} ", 700.0 + 0.01 * i);
    EXPECT_EQ(process(many), -1);  // more than are kept: no process is claimed
}

TEST(Replay, TheBundledGmFileReplays) {
    const machine::Profiles p = load("reference_lmd.toml");
    std::ifstream in(fs::path(MAXSLICE_SOURCE_DIR) / "tests/data/machine/tiny.gm");
    std::stringstream s;
    s << in.rdbuf();
    auto r = replay_program(s.str(), p, ProgramDialect::kGm);
    ASSERT_TRUE(r) << r.error().describe();
    int deposits = 0;
    for (const auto& b : r->blocks) deposits += b.kind == ReplayBlock::Kind::kMove && b.laser_on;
    EXPECT_EQ(deposits, 5);
    EXPECT_EQ(r->laser_on_count, 2);
}

TEST(Replay, LinuxCncCodesFromTheProfileSwitchTheLaser) {
    const machine::Profiles p = load("linuxcnc_generic.toml");
    const std::string text =
        "(comment) G21 G90 G94 G17\nG1 X1 Y1 Z1 F1000 ; trailing comment\n"
        "M68 E1 Q8.00\nM64 P1\nM68 E0 Q700.00\nM64 P0\nG4 P0.5\nG1 X2 F381\n"
        "M68 E0 Q650.00\nG1 X3\nM65 P0\nM68 E0 Q0\nM65 P1\nM68 E1 Q0\nG1 X4\nM2\n";
    auto r = replay_program(text, p, ProgramDialect::kLinuxCnc);
    ASSERT_TRUE(r) << r.error().describe();
    ASSERT_EQ(r->blocks.size(), 5U);
    EXPECT_FALSE(r->blocks[0].laser_on);
    EXPECT_NEAR(r->blocks[1].dwell_s, 0.5, 1e-12);  // P in seconds
    EXPECT_TRUE(r->blocks[2].laser_on);
    EXPECT_TRUE(r->blocks[3].laser_on);   // a new power, still on
    EXPECT_FALSE(r->blocks[4].laser_on);  // "M68 E0 Q0" is the laser_off block
    EXPECT_NEAR(r->blocks[4].pose.x, 4.0, 1e-12);
    EXPECT_NEAR(r->blocks[4].pose.y, 1.0, 1e-12);  // modal
    EXPECT_EQ(r->laser_on_count, 1);
    EXPECT_EQ(r->laser_powers_w, (std::vector<double>{700.0, 650.0}));
}

TEST(Replay, DwellWordsPerDialect) {
    const machine::Profiles p = ac_table(machine::Dialect::kLinuxCnc);
    auto fanuc = replay_program("%\nO1000 (T)\nG21 G90 G94 G17\nG4 X1.5\nM30\n%\n", p,
                                ProgramDialect::kFanuc);
    ASSERT_TRUE(fanuc) << fanuc.error().describe();
    ASSERT_EQ(fanuc->blocks.size(), 1U);
    EXPECT_NEAR(fanuc->blocks[0].dwell_s, 1.5, 1e-12);
    auto siemens =
        replay_program("; t\nG71 G90 G94 G17\nG1 X0 Y0 Z100 A0 C0 F500\nG4 F2.5\nG1 X1\nM30\n", p,
                       ProgramDialect::kSiemens);
    ASSERT_TRUE(siemens) << siemens.error().describe();
    ASSERT_EQ(siemens->blocks.size(), 3U);
    EXPECT_NEAR(siemens->blocks[1].dwell_s, 2.5, 1e-12);
    EXPECT_NEAR(siemens->blocks[2].feed_mm_min, 500.0, 1e-12);  // G4 F did not change the feed
}

TEST(Replay, ToolCentrePointBlocksAreThePartFrameTipPlusThePivot) {
    for (const ProgramDialect d : {ProgramDialect::kFanuc, ProgramDialect::kSiemens}) {
        const machine::Profiles p = ac_table(machine::Dialect::kLinuxCnc);
        const bool fanuc = d == ProgramDialect::kFanuc;
        const std::string on = fanuc ? "G43.4 H1" : "TRAORI";
        const std::string off = fanuc ? "G49" : "TRAFOOF";
        const std::string text = std::string(fanuc ? "%\nO1000\nG21" : "G71") +
                                 " G90 G94 G17\nG1 X0 Y0 Z300 A0 C0 F2000\n"
                                 "G1 A30.000 C45.000\n" +
                                 on +
                                 "\nG1 X15.000 Y22.000 Z-40.000 A30.000 C45.000 F500\n"
                                 "G1 X16.000\n" +
                                 off + "\nG1 Z300\n";
        auto r = replay_program(text, p, d);
        ASSERT_TRUE(r) << dialect_name(d) << ": " << r.error().describe();
        ASSERT_EQ(r->blocks.size(), 5U);
        const ReplayBlock& b = r->blocks[2];
        EXPECT_TRUE(b.tcp);
        // tip = programmed X Y Z - pivot.
        EXPECT_NEAR(b.tip_mm.x, 5.0, 1e-9);
        EXPECT_NEAR(b.tip_mm.y, 2.0, 1e-9);
        EXPECT_NEAR(b.tip_mm.z, 10.0, 1e-9);
        // The joint pose is where the kinematics put that tip.
        auto kin = machine::MachineKinematics::create(p.machine);
        ASSERT_TRUE(kin);
        const machine::ToolPose tp = kin->forward(b.pose);
        EXPECT_NEAR(core::norm(tp.tip_mm - b.tip_mm), 0.0, 1e-9);
        EXPECT_NEAR(b.pose.a_or_b_deg, 30.0, 1e-12);
        // The modal X change moves the part-frame tip by 1 mm along X.
        EXPECT_NEAR(r->blocks[3].tip_mm.x, 6.0, 1e-9);
        EXPECT_NEAR(r->blocks[3].tip_mm.y, 2.0, 1e-9);
        // After the control is off, Z is a machine coordinate again.
        EXPECT_FALSE(r->blocks[4].tcp);
        EXPECT_NEAR(r->blocks[4].pose.z, 300.0, 1e-12);
    }
}

std::string repeat(const std::string& s, int n) {
    std::string out;
    for (int i = 0; i < n; ++i) out += s;
    return out;
}

TEST(Replay, MalformedOrUnknownLinesNameTheLine) {
    const machine::Profiles xyz = load("linuxcnc_generic.toml");
    const machine::Profiles gm = load("reference_lmd.toml");
    struct Case {
        const machine::Profiles* p;
        ProgramDialect d;
        std::string text;
        int line;
        std::string says;
    };
    const std::vector<Case> cases = {
        {&xyz, ProgramDialect::kLinuxCnc, "G21\nG1 X1.2.3 F10\n", 2, "malformed"},
        {&xyz, ProgramDialect::kLinuxCnc, "G21\nG1 X1 F10\nG1 Q5\n", 3, "Q"},
        {&xyz, ProgramDialect::kLinuxCnc, "G21\nM7\n", 2, "M7"},
        {&xyz, ProgramDialect::kLinuxCnc, "G1 X1 A5 F10\n", 1, "A"},
        {&xyz, ProgramDialect::kLinuxCnc, "G91\n", 1, "G91"},
        {&xyz, ProgramDialect::kLinuxCnc, "G20\n", 1, "inch"},
        {&xyz, ProgramDialect::kLinuxCnc, "G21\n(open comment\n", 2, "comment"},
        {&xyz, ProgramDialect::kLinuxCnc, "X5 Y5\n", 1, "G0 / G1"},
        {&xyz, ProgramDialect::kLinuxCnc, "G1 X5 Y5\n", 1, "feed"},
        {&xyz, ProgramDialect::kLinuxCnc, "G1 X5 X6 F1\n", 1, "twice"},
        {&xyz, ProgramDialect::kLinuxCnc, "G43.4 H1\n", 1, "G43.4"},
        {&xyz, ProgramDialect::kLinuxCnc, "TRAORI\n", 1, "TRAORI"},
        {&xyz, ProgramDialect::kLinuxCnc, "G1 X1 F10\nG4 P1 X2\n", 2, "dwell"},
        {&gm, ProgramDialect::kGm, "0.00 0.00 G21\nG1 X1 Y1 Z1 F100\n", 2, "columns"},
        {&gm, ProgramDialect::kGm, "0.00 0.00 G21\n0.00 G1 X1\n", 2, "columns"},
        {&gm, ProgramDialect::kGm, "0.00 0.00 G21\n0.00 0.00 G1 X1 Y- F100\n", 2, "malformed"},
        {&gm, ProgramDialect::kGm, "0.00 0.00 G21\n0.00 0.00 G5\n", 2, "G5"},
        {&xyz, ProgramDialect::kLinuxCnc, "G21\n" + repeat("G90 ", 17) + "\n", 2,
         "more than 16 G codes"},
        {&xyz, ProgramDialect::kLinuxCnc, "G21\n" + repeat("M2 ", 17) + "\n", 2,
         "more than 16 M codes"},
        {&xyz, ProgramDialect::kLinuxCnc, "G21\nM2.2e127\n", 2, "malformed M code"},
    };
    // Sixteen codes in one block are read (RS-274 has fewer modal groups than that).
    EXPECT_TRUE(
        replay_program("G21\n" + repeat("G90 ", 16) + "\n", xyz, ProgramDialect::kLinuxCnc));
    for (const Case& c : cases) {
        auto r = replay_program(c.text, *c.p, c.d);
        ASSERT_FALSE(r) << c.text;
        const std::string msg = r.error().describe();
        EXPECT_NE(msg.find("line " + std::to_string(c.line)), std::string::npos) << msg;
        EXPECT_NE(msg.find(c.says), std::string::npos) << msg;
    }
}

TEST(Replay, GarbageNeverCrashes) {
    const machine::Profiles p = ac_table(machine::Dialect::kLinuxCnc);
    std::string text;
    unsigned seed = 12345;
    const std::string alphabet = "GXYZACFPMH0123456789.-+ ()%;\n\r\tOTRAI";
    for (int i = 0; i < 20000; ++i) {
        seed = seed * 1103515245U + 12345U;
        text += alphabet[(seed >> 16) % alphabet.size()];
    }
    for (const ProgramDialect d : {ProgramDialect::kGm, ProgramDialect::kLinuxCnc,
                                   ProgramDialect::kFanuc, ProgramDialect::kSiemens}) {
        for (std::size_t start = 0; start < text.size(); start += 997) {
            auto r = replay_program(std::string_view(text).substr(start, 400), p, d);
            if (!r) {
                EXPECT_NE(r.error().context.find("line"), std::string::npos);
            }
        }
    }
}

// LinuxCNC's interpreter on `program`: the axis values of its canonical moves (feeds and
// traverses), or nothing when it fails.
std::optional<std::vector<std::array<double, 6>>> rs274_moves(const std::string& program) {
    const auto run = test::run_rs274(program);
    if (!run || run->status != 0) return std::nullopt;
    return test::canonical_moves(run->canon, true);
}

void expect_same_poses(const std::vector<std::array<double, 6>>& moves, const Replay& r) {
    std::vector<machine::MachinePose> poses;
    for (const auto& b : r.blocks) {
        if (b.kind == ReplayBlock::Kind::kMove) poses.push_back(b.pose);
    }
    ASSERT_EQ(moves.size(), poses.size());
    for (std::size_t i = 0; i < moves.size(); ++i) {
        const auto& m = moves[i];
        const auto& q = poses[i];
        EXPECT_NEAR(q.x, m[0], 1e-3) << i;
        EXPECT_NEAR(q.y, m[1], 1e-3) << i;
        EXPECT_NEAR(q.z, m[2], 1e-3) << i;
        EXPECT_NEAR(q.a_or_b_deg, m[3], 1e-3) << i;
        EXPECT_NEAR(q.c_deg, m[5], 1e-3) << i;
    }
}

// LinuxCNC's standalone interpreter reads a hand-written 5-axis program; its canonical
// STRAIGHT_FEED / STRAIGHT_TRAVERSE calls give the axis values, which the replay must match.
TEST(Replay, MachinePosesMatchLinuxCncsInterpreter) {
    if (test::find_rs274().empty()) GTEST_SKIP() << "rs274 (linuxcnc-uspace) not installed";
    const machine::Profiles p = ac_table(machine::Dialect::kLinuxCnc);
    const std::string program =
        "(maxslice verify test)\nG21 G90 G94 G17\nG1 Z200 F2540\nG1 A0 C0\n"
        "G1 X10 Y20 F2540\nG1 X10 Y20 Z5.5 A0 C0 F2540\nM64 P1\nM68 E0 Q700.00\nM64 P0\n"
        "G4 P0.5\nG1 X20.125 Y20 Z5.5 A0 C0 F381\nG1 Y30.5 F400.0\nM65 P0\nM68 E0 Q0\n"
        "G1 Z60 F2540\nG1 A45.5 C-30.25\nG0 X-12.5 Y7.75\nG1 Z4.25\nG1 X-10 Y8 Z4.25 A45.5 "
        "C-30.25 F381\nG0 Z100 A-60 C720\nG1 X1 Y2 Z3 A4 C5 F100\nM2\n";
    const auto moves = rs274_moves(program);
    ASSERT_TRUE(moves);
    ASSERT_GE(moves->size(), 10U);
    auto r = replay_program(program, p, ProgramDialect::kLinuxCnc);
    ASSERT_TRUE(r) << r.error().describe();
    expect_same_poses(*moves, *r);
    // Forward kinematics of the replay: the tip is where the part frame says.
    auto kin = machine::MachineKinematics::create(p.machine);
    ASSERT_TRUE(kin);
    for (const auto& b : r->blocks) {
        const machine::ToolPose tp = kin->forward(b.pose);
        EXPECT_NEAR(core::norm(tp.tip_mm - b.tip_mm), 0.0, 1e-12);
    }
}

// The 5-axis linuxcnc writer's own output (a wire along +Z, a re-orientation, a wire along
// +Y): LinuxCNC's interpreter and the replay agree on every pose.
TEST(Replay, WrittenFiveAxisProgramMatchesLinuxCncsInterpreter) {
    if (test::find_rs274().empty()) GTEST_SKIP() << "rs274 (linuxcnc-uspace) not installed";
    const machine::Profiles p = load("linuxcnc_5axis_ac.toml");
    ASSERT_FALSE(p.machine.name.empty());
    machine::Program program;
    const std::vector<Vec3d> up = {{-10, -10, 0.5}, {10, -10, 0.5}, {10, 10, 0.5}};
    machine::append_wire(program, up, p.process, 0);
    const std::vector<Vec3d> side = {{-10, 10.5, 5}, {10, 10.5, 5}};
    machine::append_wire(program, side, p.process, 1, 1, {0.0, 1.0, 0.0});
    const std::vector<Vec3d> slant = {{-5, 0, 12}, {5, 0, 12}};
    machine::append_wire(program, slant, p.process, 2, 2, {0.6, 0.0, 0.8});
    auto text = machine::write_program(program, p.machine, p.process);
    ASSERT_TRUE(text) << text.error().describe();
    const auto moves = rs274_moves(*text);
    ASSERT_TRUE(moves);
    auto r = replay_program(*text, p, ProgramDialect::kLinuxCnc);
    ASSERT_TRUE(r) << r.error().describe();
    ASSERT_GE(moves->size(), 12U);
    expect_same_poses(*moves, *r);
    int depositing = 0;
    for (const auto& b : r->blocks) depositing += b.kind == ReplayBlock::Kind::kMove && b.laser_on;
    EXPECT_EQ(depositing, 4);
    int tilted = 0;  // the table turned for the side and slanted wires
    for (const auto& m : *moves) tilted += std::abs(m[3]) > 1.0;
    EXPECT_GE(tilted, 4);
}

// Issue 23: a line that matched a [machine.codes] template counted as a switch only, so the
// move of a template such as laser_on = "M8 G1 X0 Y0 Z0" was never replayed (140 plunges
// "verified"). Such a profile is refused before the replay now, naming the key; a template
// block with a move added on its line is an unknown code, not a switch. A macro call's
// arguments (fanuc's G65 P9011 A{power}) stay arguments.
TEST(Replay, MotionNextToATemplateIsNeverSkipped) {
    machine::Profiles p = load("linuxcnc_generic.toml");
    p.machine.codes.laser_on.blocks = {"M8 G1 X0 Y0 Z0"};
    p.machine.codes.laser_off.blocks = {"M9"};
    const std::string text = "G21\nG0 X10 Y20 Z30\nM8 G1 X0 Y0 Z0\nG1 X5 F381\nM9\nM2\n";
    auto r = replay_program(text, p, ProgramDialect::kLinuxCnc);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().describe().find("machine.codes.laser_on[0]"), std::string::npos)
        << r.error().describe();
    p.machine.codes.laser_on.blocks = {"M8"};
    r = replay_program(text, p, ProgramDialect::kLinuxCnc);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().describe().find("line 3"), std::string::npos) << r.error().describe();
    EXPECT_NE(r.error().describe().find("M8"), std::string::npos) << r.error().describe();

    machine::Profiles fanuc = load("fanuc_5axis_ac.toml");
    auto f = replay_program(
        "%\nO1000 (T)\nG21 G90 G94 G17\nG0 X0 Y0 Z100 A0 C0\nG65 P9010 A8.00\nM71\n"
        "G65 P9011 A700.00\nM73\nG1 X1 F381\nM74\nM72\nM30\n%\n",
        fanuc, ProgramDialect::kFanuc);
    ASSERT_TRUE(f) << f.error().describe();
    ASSERT_EQ(f->blocks.size(), 2U);
    EXPECT_NEAR(f->blocks[1].pose.a_or_b_deg, 0.0, 1e-12);  // A700 was the macro's argument
    EXPECT_TRUE(f->blocks[1].laser_on);
}

// The end of a program: the end code, a cut last line, the laser and powder state after the
// last line read, per dialect.
TEST(Replay, TheEndOfTheProgramIsNoted) {
    const machine::Profiles lc = load("linuxcnc_generic.toml");
    const std::string body =
        "G21\nG0 X1 Y1 Z1\nM68 E1 Q8.00\nM64 P1\nM68 E0 Q700.00\nM64 P0\nG1 X2 F381\n";
    const std::string off = "M65 P0\nM68 E0 Q0\nM65 P1\nM68 E1 Q0\n";
    struct Case {
        std::string text;
        bool end_code, cut, laser, powder;
    };
    const std::vector<Case> cases = {
        {body + off + "M2\n", true, false, false, false},
        {body + off + "M2", true, false, false, false},  // no break after M2: complete
        {body + off, false, false, false, false},
        {body, false, false, true, true},
        {body + "G1 X3", false, true, true, true},  // cut mid-line
        {body + "M65 P0\nM68 E0 Q0\nM2\n", true, false, false, true},
        {body + "M2\nM65 P0\n", true, false, true, true},  // lines after M2 are not run
        {"", false, false, false, false},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.text);
        auto r = replay_program(c.text, lc, ProgramDialect::kLinuxCnc);
        ASSERT_TRUE(r) << r.error().describe();
        EXPECT_EQ(r->end_code, c.end_code);
        EXPECT_EQ(r->cut, c.cut);
        EXPECT_EQ(r->laser_on_at_end, c.laser);
        EXPECT_EQ(r->powder_on_at_end, c.powder);
    }
    // gm: the columns of the last line, and its line break.
    const machine::Profiles gm = load("reference_lmd.toml");
    auto on =
        replay_program("0.00 0.00 G21\n700.00 8.00 G1 X1 Y1 Z1 F381\n", gm, ProgramDialect::kGm);
    ASSERT_TRUE(on);
    EXPECT_TRUE(on->laser_on_at_end);
    EXPECT_TRUE(on->powder_on_at_end);
    EXPECT_FALSE(on->cut);
    auto cut = replay_program("0.00 0.00 G21\n0.00 0.00 G1 X1 Y1 Z1 F3", gm, ProgramDialect::kGm);
    ASSERT_TRUE(cut);
    EXPECT_TRUE(cut->cut);
    EXPECT_FALSE(cut->laser_on_at_end);
}

// Powers, powder feeds and feeds outside the machine's ranges are noted, one per line, the
// first with its line; the values a writer rounds stay in range.
TEST(Replay, ValuesOutsideTheMachinesRangesAreNoted) {
    machine::Profiles lc = load("linuxcnc_generic.toml");
    lc.machine.laser_power_min_w = 100.0;
    const auto& m = lc.machine;
    const auto noted = [&](const std::string& line) {
        auto r =
            replay_program("G21\nG0 X1 Y1 Z1\n" + line + "\nM2\n", lc, ProgramDialect::kLinuxCnc);
        EXPECT_TRUE(r) << r.error().describe();
        return r ? r->out_of_range : ReplayFault{};
    };
    for (const std::string& line :
         {std::string("M68 E0 Q-700.00"), fmt::format("M68 E0 Q{:.2f}", m.laser_power_max_w + 1),
          std::string("M68 E0 Q50.00"), std::string("M68 E1 Q-1.00"),
          fmt::format("M68 E1 Q{:.2f}", m.powder_feed_max_g_min + 0.01),
          fmt::format("G1 X2 F{:.1f}", m.feed_max_mm_min + 1.0),
          fmt::format("G1 X2 F{:.1f}", 0.5 * m.feed_min_mm_min)}) {
        SCOPED_TRACE(line);
        const ReplayFault f = noted(line);
        EXPECT_EQ(f.count, 1U);
        EXPECT_EQ(f.line, 3);
        EXPECT_FALSE(f.detail.empty());
    }
    for (const std::string& line :
         {std::string("M68 E0 Q0"), fmt::format("M68 E0 Q{:.2f}", m.laser_power_max_w),
          std::string("M68 E0 Q100.00"), fmt::format("M68 E1 Q{:.2f}", m.powder_feed_max_g_min),
          fmt::format("G1 X2 F{:.1f}", m.feed_max_mm_min), std::string("G0 X500")}) {
        SCOPED_TRACE(line);
        EXPECT_EQ(noted(line).count, 0U);
    }
    // gm's columns: -700 W, and 800 g/min on a machine whose maximum is 30.
    const machine::Profiles gm = load("reference_lmd.toml");
    ASSERT_LT(gm.machine.powder_feed_max_g_min, 800.0);
    for (const std::string line : {"-700.00 8.00 G1 X2 F381", "700.00 800.00 G1 X2 F381"}) {
        auto r = replay_program("0.00 0.00 G21\n0.00 0.00 G0 X1 Y1 Z1\n" + line + "\n", gm,
                                ProgramDialect::kGm);
        ASSERT_TRUE(r) << r.error().describe();
        EXPECT_EQ(r->out_of_range.count, 1U) << line;
        EXPECT_EQ(r->out_of_range.line, 3) << line;
    }
}

// Issue 23: the replay's errors quoted the program's bytes raw (terminal escape sequences,
// a million-digit number as a 1 MB line). They are escaped and cut now.
TEST(Replay, ErrorsQuoteTheProgramEscapedAndShort) {
    const machine::Profiles lc = load("linuxcnc_generic.toml");
    const machine::Profiles gm = load("reference_lmd.toml");
    const std::string digits(1000000, '7');
    struct Case {
        const machine::Profiles* p;
        ProgramDialect d;
        std::string text;
    };
    const std::vector<Case> cases = {
        {&lc, ProgramDialect::kLinuxCnc, "G21\nG1 X\x1b[31mRED F10\n"},
        {&lc, ProgramDialect::kLinuxCnc, "G21\nG1 X1 \x1b]0;title\x07 F10\n"},
        {&lc, ProgramDialect::kLinuxCnc, "G21\nG1 X" + digits + " F10\n"},
        {&lc, ProgramDialect::kLinuxCnc, "G21\nG1 X1 Y1 Z1 F10\nG1 Q" + digits + "\n"},
        {&lc, ProgramDialect::kLinuxCnc, "G21\nG91 X\x1b[2J" + digits + "\n"},
        {&gm, ProgramDialect::kGm, "0.00 0.00 G21\n\x1b[31m" + digits + "\n"},
    };
    for (const Case& c : cases) {
        auto r = replay_program(c.text, *c.p, c.d);
        ASSERT_FALSE(r);
        const std::string msg = r.error().describe();
        EXPECT_NE(msg.find("line "), std::string::npos) << msg.substr(0, 300);
        EXPECT_LT(msg.size(), 400U) << msg.substr(0, 300);
        for (const char ch : msg) {
            EXPECT_TRUE(ch >= 0x20 && ch < 0x7f) << "raw byte " << static_cast<int>(ch);
        }
    }
}

}  // namespace
}  // namespace maxslice::verify
