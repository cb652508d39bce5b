// Five-axis programs (docs/program-dialects.md): every dialect on table machines, read back by
// a reader that knows only the contract, replayed through the forward kinematics.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "machine_fixtures.hpp"
#include "maxslice/machine/kinematics.hpp"
#include "maxslice/machine/machine_moves.hpp"
#include "maxslice/machine/profile.hpp"
#include "maxslice/machine/program_builder.hpp"
#include "maxslice/machine/writer.hpp"
#include "support/rs274.hpp"

namespace maxslice::machine {
namespace {

namespace fs = std::filesystem;
using core::Vec3d;

/// Written values round to 3 decimals: half a micrometre per linear axis, 0.0005 deg per
/// rotary axis. The tip then lies within 1e-3 mm plus the rotary rounding's lever arm (see
/// tip_tolerance), the direction within 1e-3 rad.
constexpr double kRoundMm = 1e-3;
constexpr double kDirectionRad = 1e-3;
constexpr double kRotaryRoundRad = 0.0005 * std::numbers::pi / 180.0;
constexpr double kFeedRound = 0.05;

const fs::path kAcProfile =
    fs::path(MAXSLICE_SOURCE_DIR) / "examples/profiles/reference_5axis_ac.toml";

// ---- machines -------------------------------------------------------------------------------

Profiles reference_ac() {
    const fs::path files[] = {kAcProfile};
    auto p = load_profiles(files);
    EXPECT_TRUE(p.has_value()) << p.error().describe();
    return *p;
}

// Laser and powder through codes with placeholders (needed by every dialect but gm).
void set_codes(MachineProfile& m) {
    if (m.dialect == Dialect::kGm) return;
    m.codes.powder_on.blocks = {"M68 E1 Q{powder}", "M64 P1"};
    m.codes.laser_on.blocks = {"M68 E0 Q{power}", "M64 P0"};
    m.codes.laser_off.blocks = {"M65 P0", "M68 E0 Q0"};
    m.codes.powder_off.blocks = {"M65 P1", "M68 E1 Q0"};
}

// The reference A/C machine as it is shipped.
MachineProfile ac_machine(Dialect dialect) {
    MachineProfile m = reference_ac().machine;
    m.dialect = dialect;
    set_codes(m);
    return m;
}

// An A/C table with a pivot off the origin, a C axis offset and a reversed A.
MachineProfile ac_offset_machine(Dialect dialect) {
    MachineProfile m = ac_machine(dialect);
    m.name = "offset A/C table";
    m.table->pivot_mm = {10.0, 20.0, -50.0};
    m.table->c_offset_x_mm = 4.0;
    m.table->c_offset_y_mm = -6.0;
    m.table->tilt_direction = -1;
    return m;
}

// The B/C variant: B about Y, a pivot off the origin, a reversed C.
MachineProfile bc_machine(Dialect dialect) {
    MachineProfile m = ac_machine(dialect);
    m.name = "B/C table";
    m.kinematics = Kinematics::kTableBc;
    m.axes[3].name = "B";
    m.table->pivot_mm = {-15.0, 5.0, -40.0};
    m.table->c_offset_x_mm = -3.0;
    m.table->c_offset_y_mm = 2.0;
    m.table->c_direction = -1;
    return m;
}

constexpr Dialect kDialects[] = {Dialect::kGm, Dialect::kLinuxCnc, Dialect::kFanuc,
                                 Dialect::kSiemens};

std::vector<MachineProfile> table_machines(Dialect dialect) {
    return {ac_machine(dialect), ac_offset_machine(dialect), bc_machine(dialect)};
}

// ---- the part-frame program -----------------------------------------------------------------

// A square wire of half-side `r` about `centre` in the plane perpendicular to `d`.
std::vector<Vec3d> square_across(const Vec3d& centre, const Vec3d& d, double r) {
    const Vec3d helper = std::abs(d.z) < 0.9 ? Vec3d{0, 0, 1} : Vec3d{1, 0, 0};
    const Vec3d u = core::normalized(core::cross(d, helper));
    const Vec3d v = core::cross(d, u);
    return {centre + (u + v) * r, centre + (-u + v) * r, centre + (-u - v) * r,
            centre + (u - v) * r, centre + (u + v) * r};
}

// Regions with different build directions, two wires per layer, ending again along +Z (the
// singular direction, where C stays).
Program five_axis_program(const ProcessProfile& process) {
    struct Region {
        Vec3d direction;
        Vec3d base;
        int layers;
    };
    const Region regions[] = {
        {{0, 0, 1}, {0, 0, 0}, 3},
        {core::normalized({1, 0, 1}), {6, 0, 12}, 2},
        {core::normalized({0, -1, 0.5}), {0, -8, 10}, 2},
        {core::normalized({-1, 1, 0.2}), {-6, 6, 8}, 2},
        {{0, 0, 1}, {0, 0, 20}, 2},
    };
    Program p;
    p.part_name = "five-axis test part";
    int layer = 0;
    for (int r = 0; r < static_cast<int>(std::size(regions)); ++r) {
        const Region& reg = regions[r];
        for (int l = 0; l < reg.layers; ++l, ++layer) {
            const Vec3d centre = reg.base + reg.direction * (process.layer_height_mm * (l + 1));
            append_wire(p, square_across(centre, reg.direction, 8.0), process, layer, r,
                        reg.direction);
            append_wire(p, square_across(centre, reg.direction, 5.0), process, layer, r,
                        reg.direction);
        }
    }
    append_travel(p, {0, 0, 40}, process, -1, 4, {0, 0, 1});
    return p;
}

using testing::positioning;

// The clearance height as docs/program-dialects.md defines it, from the program's positions.
double contract_clear_z(const MachineProfile& m, const Program& p) {
    const Vec3d o{m.table->c_offset_x_mm, m.table->c_offset_y_mm, 0.0};
    double radius = 0.0;
    for (const Move* mv : positioning(p)) radius = std::max(radius, core::norm(mv->position - o));
    return m.table->pivot_mm.z + core::norm(o) + radius;
}

// ---- a reader that knows only the contract --------------------------------------------------

struct Block {
    std::optional<double> x, y, z, tilt, c, f;                   // the words written in this block
    double mx = NAN, my = NAN, mz = NAN, mtilt = NAN, mc = NAN;  // modal values after it
    bool tcp = false;                                            // tool centre point control on
    bool laser_on = false;             // between the laser-on and laser-off codes
    double power = NAN, powder = NAN;  // gm columns
    int line = 0;
    std::string text;
};

struct Read {
    std::vector<Block> g1;
    std::vector<std::string> lines;  // every line (gm: without the columns)
    std::vector<std::string> problems;
    int tcp_switches = 0;
};

using testing::word;

Read read_program(const std::string& text, Dialect dialect, char tilt) {
    Read out;
    const bool gm = dialect == Dialect::kGm;
    const std::string on = gm ? "M8" : "M64 P0";
    const std::string off = gm ? "M9" : "M65 P0";
    const std::string tcp_on = dialect == Dialect::kFanuc     ? "G43.4 H1"
                               : dialect == Dialect::kSiemens ? "TRAORI"
                                                              : "";
    const std::string tcp_off = dialect == Dialect::kFanuc     ? "G49"
                                : dialect == Dialect::kSiemens ? "TRAFOOF"
                                                               : "";
    std::istringstream in(text);
    std::string line;
    bool laser = false, tcp = false;
    double mx = NAN, my = NAN, mz = NAN, mtilt = NAN, mc = NAN;
    int number = 0;
    while (std::getline(in, line)) {
        ++number;
        double power = NAN, powder = NAN;
        std::string block = line;
        if (gm) {
            std::istringstream cols(line);
            if (!(cols >> power >> powder)) {
                out.problems.push_back("no columns: " + line);
                continue;
            }
            cols >> std::ws;
            std::getline(cols, block);
        }
        out.lines.push_back(block);
        if (block.find("-0.000") != std::string::npos) out.problems.push_back("-0.000: " + line);
        if (block == on) laser = true;
        if (block == off) laser = false;
        if (!tcp_on.empty() && block == tcp_on) {
            tcp = true;
            ++out.tcp_switches;
        }
        if (!tcp_off.empty() && block == tcp_off) tcp = false;
        if (!block.starts_with("G1 ")) continue;
        Block b;
        b.x = word(block, 'X');
        b.y = word(block, 'Y');
        b.z = word(block, 'Z');
        b.tilt = word(block, tilt);
        b.c = word(block, 'C');
        b.f = word(block, 'F');
        if (b.x) mx = *b.x;
        if (b.y) my = *b.y;
        if (b.z) mz = *b.z;
        if (b.tilt) mtilt = *b.tilt;
        if (b.c) mc = *b.c;
        b.mx = mx;
        b.my = my;
        b.mz = mz;
        b.mtilt = mtilt;
        b.mc = mc;
        b.tcp = tcp;
        b.laser_on = laser;
        b.power = power;
        b.powder = powder;
        b.line = number;
        b.text = block;
        if (!b.f) out.problems.push_back("G1 without F: " + line);
        out.g1.push_back(b);
    }
    return out;
}

MachinePose pose_of(const Block& b) {
    return {b.mx, b.my, b.mz, b.mtilt, b.mc};
}

// The joint-space linear axes of a block written under tool centre point control: the machine
// point whose forward kinematics at the block's rotary values is the part tip X Y Z - pivot.
// forward() is affine in X Y Z with a rotation as its linear part, so three probes invert it.
Vec3d joint_xyz(const MachineKinematics& k, const MachineProfile& m, const Block& b) {
    const Vec3d q = Vec3d{b.mx, b.my, b.mz} - m.table->pivot_mm;
    const auto tip = [&](const Vec3d& p) {
        return k.forward({p.x, p.y, p.z, b.mtilt, b.mc}).tip_mm;
    };
    const Vec3d t0 = tip({0, 0, 0});
    const Vec3d cx = tip({1, 0, 0}) - t0, cy = tip({0, 1, 0}) - t0, cz = tip({0, 0, 1}) - t0;
    const Vec3d r = q - t0;  // = L p, L orthogonal with columns cx, cy, cz: p = L^T r
    return {core::dot(cx, r), core::dot(cy, r), core::dot(cz, r)};
}

// Bound on the tip error of a joint-space block from the rounding of its words: the linear
// words' half micrometre, and each rotary word's 0.0005 deg acting on the part point's
// distance from the tilt axis (at most its distance from the pivot) and from the C axis.
double tip_tolerance(const MachineProfile& m, const Vec3d& part_tip) {
    const Vec3d o{m.table->c_offset_x_mm, m.table->c_offset_y_mm, 0.0};
    const double lever = core::norm(part_tip) + core::norm(part_tip - o) + core::norm(o);
    return kRoundMm + 2.0 * kRotaryRoundRad * lever;
}

double angle_between(const Vec3d& a, const Vec3d& b) {
    return std::atan2(core::norm(core::cross(a, b)), core::dot(a, b));
}

// The properties every dialect's 5-axis program must have.
void check_program_text(const Program& program, const MachineProfile& machine,
                        const ProcessProfile& process, const std::string& text, double clear_z) {
    const auto k = MachineKinematics::create(machine);
    ASSERT_TRUE(k.has_value());
    const char tilt = machine.kinematics == Kinematics::kTableBc ? 'B' : 'A';
    const bool tcp = machine.dialect == Dialect::kFanuc || machine.dialect == Dialect::kSiemens;
    const Read read = read_program(text, machine.dialect, tilt);
    ASSERT_TRUE(read.problems.empty()) << read.problems.front();
    const double retract = machine.table->retract_mm;

    // Where re-orientations must be: before the first positioning move and wherever the
    // direction changes (every direction change in this program needs a turn).
    const auto expected = positioning(program);
    std::vector<bool> turns(expected.size());
    std::size_t turn_count = 0;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        turns[i] = i == 0 || expected[i]->direction != expected[i - 1]->direction;
        turn_count += turns[i] ? 1 : 0;
    }
    // Each turn inserts a retract, the turn and the cross, and where turning over the retract
    // would sweep the head below the plate's level a move across the tilt axis before it.
    ASSERT_GE(read.g1.size(), expected.size() + 3 * turn_count);
    ASSERT_LE(read.g1.size(), expected.size() + 4 * turn_count);
    const bool about_x = machine.kinematics == Kinematics::kTableAc;

    // The joint pose of every block, and whether it is a program move.
    std::size_t b = 0;
    MachinePose previous_joint{};
    for (std::size_t i = 0; i < expected.size(); ++i) {
        const Move& m = *expected[i];
        SCOPED_TRACE(::testing::Message() << "program move " << i << " (layer " << m.layer
                                          << ", region " << m.region << ")");
        if (turns[i]) {
            ASSERT_LT(b + 3, read.g1.size());
            const Block& retract_b = read.g1[b];
            // A block at the retract's rotary values after it moves across before the turn.
            const bool across = read.g1[b + 1].mtilt == retract_b.mtilt &&
                                read.g1[b + 1].mc == retract_b.mc && i > 0;
            ASSERT_LT(b + (across ? 4 : 3), read.g1.size());
            const Block& before_b = read.g1[b + (across ? 1 : 0)];
            const Block& turn_b = read.g1[b + (across ? 2 : 1)];
            const Block& cross_b = read.g1[b + (across ? 3 : 2)];
            const Block& target_b = read.g1[b + (across ? 4 : 3)];
            SCOPED_TRACE(::testing::Message() << "re-orientation at line " << retract_b.line);
            if (across) {
                // Only the coordinate across the tilt axis changes; from there the turn keeps
                // the head above the plate's level (its lowest outline corner, sampled).
                EXPECT_EQ(before_b.mz, retract_b.mz);
                EXPECT_NEAR(about_x ? before_b.mx : before_b.my,
                            about_x ? retract_b.mx : retract_b.my, 1e-9);
                EXPECT_NE(about_x ? before_b.my : before_b.mx,
                          about_x ? retract_b.my : retract_b.mx);
                for (int q = 0; q <= 64; ++q) {
                    const double f = q / 64.0;
                    const MachinePose at{before_b.mx, before_b.my, before_b.mz,
                                         before_b.mtilt + f * (turn_b.mtilt - before_b.mtilt),
                                         before_b.mc};
                    EXPECT_GT(testing::head_floor(*k, machine.nozzle.value_or(NozzleProfile{}), at),
                              0.0)
                        << f;
                }
            }
            for (const Block* s : {&retract_b, &before_b, &turn_b, &cross_b}) {
                EXPECT_FALSE(s->tcp) << "joint space: line " << s->line;
                EXPECT_FALSE(s->laser_on) << "line " << s->line;
                EXPECT_NEAR(*s->f, process.travel_feed_mm_min, kFeedRound) << s->line;
                if (machine.dialect == Dialect::kGm) {
                    EXPECT_EQ(s->power, 0.0);
                    EXPECT_EQ(s->powder, 0.0);
                }
            }
            EXPECT_TRUE(target_b.tcp == tcp) << "line " << target_b.line;
            // Joint values of the target (from TCP words when the control is on).
            const Vec3d target_xyz = tcp ? joint_xyz(*k, machine, target_b)
                                         : Vec3d{target_b.mx, target_b.my, target_b.mz};
            const double z_safe = retract_b.mz;
            if (i == 0) {
                // Program start: `G1 Z F` alone, then the turn with no X Y.
                EXPECT_TRUE(!retract_b.x && !retract_b.y && retract_b.z && !retract_b.tilt &&
                            !retract_b.c)
                    << retract_b.text;
                EXPECT_TRUE(!turn_b.x && !turn_b.y && turn_b.tilt && turn_b.c) << turn_b.text;
                EXPECT_NEAR(z_safe, std::max(target_xyz.z, clear_z) + retract, kRoundMm);
            } else {
                // Retract: X Y and the rotary axes unchanged, Z up.
                EXPECT_NEAR(retract_b.mx, previous_joint.x, kRoundMm);
                EXPECT_NEAR(retract_b.my, previous_joint.y, kRoundMm);
                EXPECT_NEAR(retract_b.mtilt, previous_joint.a_or_b_deg, 1e-9);
                EXPECT_NEAR(retract_b.mc, previous_joint.c_deg, 1e-9);
                EXPECT_GT(z_safe, previous_joint.z);
                EXPECT_NEAR(z_safe, std::max({previous_joint.z, target_xyz.z, clear_z}) + retract,
                            kRoundMm);
                // The turn at z_safe with X Y Z unchanged.
                EXPECT_EQ(turn_b.mx, before_b.mx);
                EXPECT_EQ(turn_b.my, before_b.my);
            }
            EXPECT_TRUE(retract_b.z && turn_b.z && cross_b.z);
            EXPECT_EQ(turn_b.mz, z_safe);
            EXPECT_EQ(cross_b.mz, z_safe);
            // The turn reaches the target's rotary values; the cross keeps them.
            EXPECT_EQ(turn_b.mtilt, target_b.mtilt);
            EXPECT_EQ(turn_b.mc, target_b.mc);
            EXPECT_EQ(cross_b.mtilt, target_b.mtilt);
            EXPECT_EQ(cross_b.mc, target_b.mc);
            // Across to X Y of the target, which then comes down the tool axis.
            EXPECT_NEAR(cross_b.mx, target_xyz.x, kRoundMm);
            EXPECT_NEAR(cross_b.my, target_xyz.y, kRoundMm);
            EXPECT_LT(target_xyz.z, z_safe);
            EXPECT_GE(z_safe, clear_z + retract - kRoundMm);
            b += across ? 4 : 3;
        }
        const Block& blk = read.g1[b++];
        SCOPED_TRACE(::testing::Message() << "line " << blk.line << ": " << blk.text);
        EXPECT_EQ(blk.tcp, tcp);
        EXPECT_EQ(blk.laser_on, m.kind == MoveKind::kDeposit);
        EXPECT_TRUE(blk.x && blk.y && blk.z && blk.tilt && blk.c && blk.f)
            << "every positioning block carries X Y Z " << tilt << " C F";
        EXPECT_NEAR(*blk.f, m.feed_mm_min, kFeedRound);
        MachinePose joint = pose_of(blk);
        if (tcp) {
            // Under tool centre point control X Y Z is pivot + the part tip.
            EXPECT_NEAR(blk.mx - machine.table->pivot_mm.x, m.position.x, kRoundMm);
            EXPECT_NEAR(blk.my - machine.table->pivot_mm.y, m.position.y, kRoundMm);
            EXPECT_NEAR(blk.mz - machine.table->pivot_mm.z, m.position.z, kRoundMm);
            const Vec3d j = joint_xyz(*k, machine, blk);
            joint.x = j.x;
            joint.y = j.y;
            joint.z = j.z;
        }
        const ToolPose f = k->forward(joint);
        EXPECT_LE(core::norm(f.tip_mm - m.position), tip_tolerance(machine, m.position));
        EXPECT_LE(angle_between(f.direction, m.direction), kDirectionRad);
        EXPECT_TRUE(k->check_limits(joint).has_value());
        previous_joint = joint;
    }
    EXPECT_EQ(b, read.g1.size());
    // Nothing rotates while the laser is on.
    for (std::size_t i = 1; i < read.g1.size(); ++i) {
        if (!read.g1[i].laser_on) continue;
        EXPECT_EQ(read.g1[i].mtilt, read.g1[i - 1].mtilt) << "line " << read.g1[i].line;
        EXPECT_EQ(read.g1[i].mc, read.g1[i - 1].mc) << "line " << read.g1[i].line;
    }
    if (tcp) {
        // One switch-on per re-orientation sequence.
        EXPECT_EQ(static_cast<std::size_t>(read.tcp_switches), turn_count);
    }
}

TEST(FiveAxis, EveryDialectReplaysToTheProgram) {
    const ProcessProfile process = reference_ac().process;
    const Program program = five_axis_program(process);
    for (const Dialect dialect : kDialects) {
        for (const MachineProfile& machine : table_machines(dialect)) {
            SCOPED_TRACE(std::string(dialect_name(dialect)) + " on " + machine.name);
            const auto text = write_program(program, machine, process);
            ASSERT_TRUE(text.has_value()) << text.error().describe();
            check_program_text(program, machine, process, *text,
                               contract_clear_z(machine, program));
            // A clearance height from the caller (the placed mesh) replaces the program's own.
            const double clear = contract_clear_z(machine, program) + 37.5;
            const auto raised = write_program(program, machine, process, {.clear_z_mm = clear});
            ASSERT_TRUE(raised.has_value()) << raised.error().describe();
            check_program_text(program, machine, process, *raised, clear);
        }
    }
}

TEST(FiveAxis, DialectFraming) {
    const ProcessProfile process = reference_ac().process;
    const Program program = five_axis_program(process);
    const auto fanuc = write_program(program, ac_machine(Dialect::kFanuc), process);
    ASSERT_TRUE(fanuc.has_value()) << fanuc.error().describe();
    EXPECT_TRUE(fanuc->starts_with("%\nO1000 (MAXSLICE)\n(")) << fanuc->substr(0, 80);
    EXPECT_NE(fanuc->find("\nG21 G90 G94 G17\n"), std::string::npos);
    EXPECT_NE(fanuc->find("\nG4 X0.500\n"), std::string::npos);
    EXPECT_NE(fanuc->find("\n(layer 3 region 1)\n"), std::string::npos);
    EXPECT_TRUE(fanuc->ends_with("\nG49\nM30\n%\n"));
    // Every re-orientation: TCP off, the tool length back on (X Y Z stay the tool tip), and
    // G43.4 H1 again right before the approach.
    std::size_t sequences = 0;
    for (std::size_t at = fanuc->find("\nG49\n"); at != std::string::npos;
         at = fanuc->find("\nG49\n", at + 1)) {
        const std::string_view rest = std::string_view(*fanuc).substr(at);
        if (rest == "\nG49\nM30\n%\n") continue;
        ++sequences;
        EXPECT_TRUE(rest.starts_with("\nG49\nG43 H1\nG1 ")) << rest.substr(0, 40);
    }
    EXPECT_EQ(sequences, 5u);  // the start and the four direction changes

    const auto siemens = write_program(program, ac_machine(Dialect::kSiemens), process);
    ASSERT_TRUE(siemens.has_value()) << siemens.error().describe();
    EXPECT_TRUE(siemens->starts_with("; maxslice program")) << siemens->substr(0, 80);
    EXPECT_NE(siemens->find("\nG71 G90 G94 G17\n"), std::string::npos);
    EXPECT_NE(siemens->find("\nG4 F0.500\n"), std::string::npos);
    EXPECT_NE(siemens->find("\n; layer 3 region 1\n"), std::string::npos);
    EXPECT_EQ(siemens->find('('), std::string::npos);
    EXPECT_TRUE(siemens->ends_with("\nTRAFOOF\nM30\n"));
    EXPECT_EQ(siemens->find("G43"), std::string::npos);

    const auto cnc = write_program(program, ac_machine(Dialect::kLinuxCnc), process);
    ASSERT_TRUE(cnc.has_value());
    EXPECT_NE(cnc->find("\nG4 P0.500\n"), std::string::npos);
    EXPECT_TRUE(cnc->ends_with("\nM2\n"));
    EXPECT_EQ(cnc->find("G43.4"), std::string::npos);

    const auto gm = write_program(program, ac_machine(Dialect::kGm), process);
    ASSERT_TRUE(gm.has_value());
    EXPECT_TRUE(gm->starts_with("0.00 0.00 G21\n0.00 0.00 G90\n"));
    EXPECT_NE(gm->find(" G4 P500\n"), std::string::npos);
    EXPECT_EQ(gm->find('('), std::string::npos);
}

TEST(FiveAxis, FanucAndSiemensOnACartesianMachineWritePlainXyz) {
    const ProcessProfile process = testing::reference_process();
    const Program program = testing::planar_block(process, 2);
    for (const Dialect dialect : {Dialect::kFanuc, Dialect::kSiemens}) {
        MachineProfile m = testing::linuxcnc_machine();
        m.dialect = dialect;
        const auto text = write_program(program, m, process);
        ASSERT_TRUE(text.has_value()) << text.error().describe();
        for (const char* absent : {" A", " B", " C", "G43.4", "TRAORI", "TRAFOOF"}) {
            EXPECT_EQ(text->find(absent), std::string::npos) << absent;
        }
        // Fanuc: X Y Z are the tool tip through the tool length compensation H1.
        if (dialect == Dialect::kFanuc) {
            EXPECT_NE(text->find("\nG21 G90 G94 G17\nG43 H1\n"), std::string::npos);
        } else {
            EXPECT_EQ(text->find("G43"), std::string::npos);
        }
        const auto read = testing::read_text(*text, false, "M64 P0", "M65 P0");
        ASSERT_EQ(read.moves.size(), positioning(program).size());
        for (std::size_t i = 0; i < read.moves.size(); ++i) {
            EXPECT_NEAR(read.moves[i].x, positioning(program)[i]->position.x, kRoundMm);
            EXPECT_NEAR(read.moves[i].z, positioning(program)[i]->position.z, kRoundMm);
        }
        EXPECT_TRUE(text->ends_with(dialect == Dialect::kFanuc ? "\nG49\nM30\n%\n" : "\nM30\n"));
    }
}

TEST(FiveAxis, Deterministic) {
    const ProcessProfile process = reference_ac().process;
    for (const Dialect dialect : kDialects) {
        for (const MachineProfile& machine : table_machines(dialect)) {
            const auto a = write_program(five_axis_program(process), machine, process);
            const auto b = write_program(five_axis_program(process), machine, process);
            ASSERT_TRUE(a.has_value() && b.has_value());
            EXPECT_EQ(*a, *b);
        }
    }
}

// ---- refusals --------------------------------------------------------------------------------

void expect_refused(const Program& program, const MachineProfile& machine,
                    const std::vector<std::string>& fragments, const WriteOptions& options = {}) {
    const auto text = write_program(program, machine, reference_ac().process, options);
    ASSERT_FALSE(text.has_value()) << "written, expected " << fragments.front();
    EXPECT_EQ(text.error().code, core::ErrorCode::kInvalidInput) << text.error().describe();
    EXPECT_EQ(text.error().context, "machine " + machine.name);
    for (const auto& f : fragments) {
        EXPECT_NE(text.error().message.find(f), std::string::npos)
            << "`" << f << "` not in: " << text.error().describe();
    }
}

TEST(FiveAxis, DirectionChangeInsideAWireIsRefused) {
    const ProcessProfile process = reference_ac().process;
    Program program = five_axis_program(process);
    std::size_t i = 0;
    while (!(program.moves[i].kind == MoveKind::kDeposit && program.moves[i].region == 2)) ++i;
    ++i;  // the second deposit move of the wire
    ASSERT_EQ(program.moves[i].kind, MoveKind::kDeposit);
    program.moves[i].direction = core::normalized({1, 0, 1});
    for (const Dialect dialect : kDialects) {
        expect_refused(
            program, ac_machine(dialect),
            {"move " + std::to_string(i), "layer " + std::to_string(program.moves[i].layer),
             "region 2", "the build direction changes within a deposited wire"});
    }
}

TEST(FiveAxis, UnreachableDirectionIsRefused) {
    const ProcessProfile process = reference_ac().process;
    Program program = five_axis_program(process);
    const std::size_t first = program.moves.size();
    // 163 deg from +Z: |A| would be 163 deg, beyond the reference table's +-120 deg.
    const Vec3d down = core::normalized({0, 0.3, -1});
    append_wire(program, square_across({0, 0, -5}, down, 4.0), process, 20, 5, down);
    expect_refused(program, ac_machine(Dialect::kGm),
                   {"move " + std::to_string(first), "layer 20", "region 5", "machine.axes.A"});
}

TEST(FiveAxis, SafeHeightAboveTheZLimitIsRefused) {
    const ProcessProfile process = reference_ac().process;
    const Program program = five_axis_program(process);
    // Z max 600 mm, retract 20 mm: a clearance of 590 mm needs Z = 610 mm.
    expect_refused(program, ac_machine(Dialect::kLinuxCnc),
                   {"move 0", "layer 0", "region 0", "machine.axes.Z", "machine.table.retract_mm"},
                   {.clear_z_mm = 590.0});
    const auto ok =
        write_program(program, ac_machine(Dialect::kLinuxCnc), process, {.clear_z_mm = 580.0});
    EXPECT_TRUE(ok.has_value()) << ok.error().describe();
}

TEST(FiveAxis, ClearanceHeightMustBeFinite) {
    const ProcessProfile process = reference_ac().process;
    expect_refused(five_axis_program(process), ac_machine(Dialect::kGm),
                   {"clearance height", "not a finite number"}, {.clear_z_mm = NAN});
}

TEST(FiveAxis, EmptyProgramIsTheFrameAlone) {
    const ProcessProfile process = reference_ac().process;
    const auto gm = write_program(Program{}, ac_machine(Dialect::kGm), process);
    ASSERT_TRUE(gm.has_value()) << gm.error().describe();
    EXPECT_EQ(*gm, "0.00 0.00 G21\n0.00 0.00 G90\n");
    const auto fanuc = write_program(Program{}, ac_machine(Dialect::kFanuc), process);
    ASSERT_TRUE(fanuc.has_value()) << fanuc.error().describe();
    EXPECT_TRUE(fanuc->ends_with("\nG21 G90 G94 G17\nG49\nM30\n%\n")) << *fanuc;
    EXPECT_EQ(fanuc->find("G1 "), std::string::npos);
}

// ---- the conversion ---------------------------------------------------------------------------

TEST(MachineMoves, XyzIsTheIdentity) {
    const ProcessProfile process = testing::reference_process();
    const Program program = testing::planar_block(process, 2);
    const auto k = MachineKinematics::create(testing::gm_machine());
    ASSERT_TRUE(k.has_value());
    const auto moves = to_machine_moves(program, *k, 1000.0);
    ASSERT_TRUE(moves.has_value()) << moves.error().describe();
    ASSERT_EQ(moves->size(), program.moves.size());
    for (std::size_t i = 0; i < moves->size(); ++i) {
        const MachineMove& mm = (*moves)[i];
        EXPECT_FALSE(mm.inserted());
        EXPECT_EQ(mm.source, i);
        if (mm.move.kind == MoveKind::kTravel || mm.move.kind == MoveKind::kDeposit) {
            EXPECT_EQ(mm.pose.x, program.moves[i].position.x);
            EXPECT_EQ(mm.pose.y, program.moves[i].position.y);
            EXPECT_EQ(mm.pose.z, program.moves[i].position.z);
        }
    }
}

TEST(MachineMoves, SequencesStandBeforeTheirTargets) {
    const Profiles p = reference_ac();
    const Program program = five_axis_program(p.process);
    const auto k = MachineKinematics::create(bc_machine(Dialect::kGm));
    ASSERT_TRUE(k.has_value());
    const auto moves = to_machine_moves(program, *k, 30.0);
    ASSERT_TRUE(moves.has_value()) << moves.error().describe();
    const auto& v = *moves;
    ASSERT_GE(v.size(), 3u);
    EXPECT_EQ(v[0].step, ReorientStep::kStartRetract);
    EXPECT_EQ(v[1].step, ReorientStep::kStartTurn);
    EXPECT_EQ(v[2].step, ReorientStep::kCross);
    EXPECT_EQ(v[0].pose.a_or_b_deg, 0.0);
    EXPECT_EQ(v[0].pose.c_deg, 0.0);
    std::size_t program_moves = 0;
    for (std::size_t i = 0; i < v.size(); ++i) {
        if (!v[i].inserted()) {
            EXPECT_EQ(v[i].source, program_moves++);
            continue;
        }
        // Every inserted step leads to the program move that follows its sequence.
        std::size_t j = i;
        while (v[j].inserted()) ++j;
        EXPECT_EQ(v[i].source, v[j].source);
        EXPECT_EQ(v[i].move.kind, MoveKind::kTravel);
    }
    EXPECT_EQ(program_moves, program.moves.size());
}

// With the pivot and C axis at 0 the two solutions of one direction are half a turn of each
// other about Z: (x, y, z) and (-x, -y, z). Direction (0, 1, 1): A 45, C 0 from rotary zero,
// the tip (10, 0, 0) at X 10. The tip (-60, 0, 0) is at X -60 with those values, beyond
// X min -50; the other solution (A -45, C 180) puts it at X 60. A travel there turns the table
// (a sequence is inserted); a deposit move there is refused.
TEST(MachineMoves, ATipOutOfReachTakesTheOtherSolution) {
    MachineProfile m = ac_machine(Dialect::kGm);
    m.axes[0].min = -50.0;
    const auto k = MachineKinematics::create(m);
    ASSERT_TRUE(k.has_value());
    const ProcessProfile process = reference_ac().process;
    const Vec3d d = core::normalized({0, 1, 1});
    Program travel;
    append_travel(travel, {10, 0, 0}, process, 0, 0, d);
    append_travel(travel, {-60, 0, 0}, process, 0, 0, d);
    const auto moves = to_machine_moves(travel, *k, 0.0);
    ASSERT_TRUE(moves.has_value()) << moves.error().describe();
    ASSERT_EQ(moves->size(), 8u);  // start sequence, move 0, sequence, move 1
    EXPECT_NEAR((*moves)[3].pose.x, 10.0, 1e-9);
    EXPECT_NEAR((*moves)[3].pose.a_or_b_deg, 45.0, 1e-9);
    EXPECT_EQ((*moves)[4].step, ReorientStep::kRetract);
    EXPECT_NEAR((*moves)[7].pose.x, 60.0, 1e-9);
    EXPECT_NEAR((*moves)[7].pose.a_or_b_deg, -45.0, 1e-9);
    EXPECT_NEAR(std::remainder((*moves)[7].pose.c_deg - 180.0, 360.0), 0.0, 1e-9);

    Program wire;
    const std::vector<Vec3d> points{{10, 0, 0}, {-60, 0, 0}};
    append_wire(wire, points, process, 0, 0, d);
    const auto refused = to_machine_moves(wire, *k, 0.0);
    ASSERT_FALSE(refused.has_value());
    EXPECT_NE(refused.error().message.find("move 2 (layer 0, region 0)"), std::string::npos)
        << refused.error().message;
    EXPECT_NE(refused.error().message.find("turn within a deposited wire"), std::string::npos)
        << refused.error().message;
    EXPECT_NE(refused.error().message.find("machine.axes.X"), std::string::npos)
        << refused.error().message;
}

// The sphere of clear_height_mm holds the part in any table position.
TEST(MachineMoves, ClearHeightIsAboveThePartInEveryTablePosition) {
    for (const MachineProfile& m :
         {ac_offset_machine(Dialect::kGm), bc_machine(Dialect::kGm), ac_machine(Dialect::kGm)}) {
        const auto k = MachineKinematics::create(m);
        ASSERT_TRUE(k.has_value());
        std::vector<Vec3d> points;
        for (const Vec3d& q : square_across({3, -2, 15}, core::normalized({1, 2, 3}), 12.0)) {
            points.push_back(q);
        }
        points.push_back({-20, 10, 0});
        const double clear = clear_height_mm(m, points);
        double highest = -INFINITY;
        for (double tilt = -120.0; tilt <= 120.0; tilt += 7.5) {
            for (double c = -180.0; c < 180.0; c += 7.5) {
                for (const Vec3d& q : points) {
                    highest = std::max(highest, k->pose_at(q, tilt, c).z);
                }
            }
        }
        EXPECT_LE(highest, clear + 1e-9) << m.name;
    }
    EXPECT_EQ(clear_height_mm(testing::gm_machine(),
                              std::vector<Vec3d>{{0, 0, 3}, {1, 1, 7.5}, {2, 0, -1}}),
              7.5);
}

// ---- LinuxCNC's interpreter -------------------------------------------------------------------

TEST(FiveAxis, Rs274ReadsTheJointValuesWritten) {
    if (test::find_rs274().empty()) {
        GTEST_SKIP() << "rs274 not installed (Debian package linuxcnc-uspace)";
    }
    const ProcessProfile process = reference_ac().process;
    const Program program = five_axis_program(process);
    for (const MachineProfile& machine :
         {ac_machine(Dialect::kLinuxCnc), bc_machine(Dialect::kLinuxCnc)}) {
        SCOPED_TRACE(machine.name);
        const auto text = write_program(program, machine, process);
        ASSERT_TRUE(text.has_value()) << text.error().describe();
        const auto run = test::run_rs274(*text);
        ASSERT_TRUE(run);
        ASSERT_EQ(run->status, 0) << run->errors;
        EXPECT_TRUE(test::only_executing(run->errors)) << run->errors;

        // STRAIGHT_FEED(x, y, z, a, b, c), one per G1, in order.
        const bool bc = machine.kinematics == Kinematics::kTableBc;
        const Read read = read_program(*text, Dialect::kLinuxCnc, bc ? 'B' : 'A');
        std::size_t n = 0;
        for (const std::array<double, 6>& v : test::canonical_moves(run->canon, false)) {
            ASSERT_FALSE(std::isnan(v[0]));
            ASSERT_LT(n, read.g1.size()) << "more STRAIGHT_FEED calls than G1 blocks";
            const Block& b = read.g1[n++];
            // rs274 starts at 0 on every axis: words not written yet read as 0.
            const auto same = [&](double canon_value, double written, const char* axis) {
                EXPECT_NEAR(canon_value, std::isnan(written) ? 0.0 : written, 1e-3)
                    << axis << ", line " << b.line << ": " << b.text;
            };
            same(v[0], b.mx, "X");
            same(v[1], b.my, "Y");
            same(v[2], b.mz, "Z");
            same(v[bc ? 4 : 3], b.mtilt, bc ? "B" : "A");
            same(v[bc ? 3 : 4], 0.0, bc ? "A" : "B");
            same(v[5], b.mc, "C");
        }
        EXPECT_EQ(n, read.g1.size());
        EXPECT_NE(run->canon.find("PROGRAM_END()"), std::string::npos);
    }
}

}  // namespace
}  // namespace maxslice::machine
