#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "machine_fixtures.hpp"
#include "maxslice/machine/program_check.hpp"
#include "maxslice/machine/writer.hpp"
#include "support/rs274.hpp"

namespace maxslice::machine {
namespace {

namespace fs = std::filesystem;
using testing::gm_machine;
using testing::linuxcnc_machine;
using testing::read_text;
using testing::reference_process;

/// Write-back tolerance: 3 decimals round to within half a micrometre.
constexpr double kRoundTripMm = 1e-3;
/// Feeds are written with one decimal.
constexpr double kFeedRoundTrip = 0.05;

std::string read_file(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// The tiny hand-built program of the golden test: a 10 mm square on layer 0, one line on
// layer 1 (with a coordinate that rounds to -0.000), a travel away at the end.
Program tiny_program(const ProcessProfile& process) {
    Program p;
    p.part_name = "tiny";
    const auto sq = testing::square(0.0, 0.0, 10.0, 0.5);
    append_wire(p, sq, process, 0);
    const std::vector<core::Vec3d> line{{-0.0001, 5.0, 1.0}, {-12.3456, 5.0, 1.0}};
    append_wire(p, line, process, 1);
    append_travel(p, {-12.3456, 5.0, 11.0}, process, -1);
    return p;
}

using testing::positioning;

TEST(GmWriter, GoldenTinyProgram) {
    const auto text =
        write_program(tiny_program(reference_process()), gm_machine(), reference_process());
    ASSERT_TRUE(text.has_value()) << text.error().describe();
    const fs::path golden = fs::path(MAXSLICE_TEST_LOCAL_DATA_DIR) / "machine" / "tiny.gm";
    if (std::getenv("MAXSLICE_UPDATE_GOLDEN") != nullptr) {
        std::ofstream(golden, std::ios::binary) << *text;
        GTEST_SKIP() << "wrote " << golden;
    }
    ASSERT_TRUE(fs::exists(golden)) << golden << " (run with MAXSLICE_UPDATE_GOLDEN=1)";
    EXPECT_EQ(*text, read_file(golden));
}

// Parse-back properties shared by both dialects.
void expect_round_trip(const Program& program, const ProcessProfile& process,
                       const testing::ReadProgram& read, bool same_feeds) {
    EXPECT_TRUE(read.problems.empty()) << read.problems.front();
    const auto expected = positioning(program);
    ASSERT_EQ(read.moves.size(), expected.size());
    int laser_ons = 0;
    for (const Move& m : program.moves) laser_ons += m.kind == MoveKind::kLaserOn ? 1 : 0;
    EXPECT_EQ(read.laser_on_events, laser_ons);
    for (std::size_t i = 0; i < expected.size(); ++i) {
        const Move& m = *expected[i];
        const auto& r = read.moves[i];
        EXPECT_NEAR(r.x, m.position.x, kRoundTripMm) << "line " << r.line;
        EXPECT_NEAR(r.y, m.position.y, kRoundTripMm) << "line " << r.line;
        EXPECT_NEAR(r.z, m.position.z, kRoundTripMm) << "line " << r.line;
        EXPECT_NEAR(r.f, m.feed_mm_min, kFeedRoundTrip) << "line " << r.line;
        // The laser is on exactly for the deposit moves.
        EXPECT_EQ(r.laser_on, m.kind == MoveKind::kDeposit) << "line " << r.line;
        if (same_feeds) {
            EXPECT_NEAR(r.f,
                        r.laser_on ? process.deposition_feed_mm_min : process.travel_feed_mm_min,
                        kFeedRoundTrip)
                << "line " << r.line;
        }
    }
}

TEST(GmWriter, ParsesBackToTheProgram) {
    const ProcessProfile process = reference_process();
    const Program program = testing::planar_block(process, 4);
    const auto text = write_program(program, gm_machine(), process);
    ASSERT_TRUE(text.has_value()) << text.error().describe();
    const auto read = read_text(*text, true, "M8", "M9");
    expect_round_trip(program, process, read, true);
    ASSERT_GE(read.blocks.size(), 2u);
    EXPECT_EQ(read.blocks[0], "G21");
    EXPECT_EQ(read.blocks[1], "G90");
    for (const auto& m : read.moves) {
        EXPECT_DOUBLE_EQ(m.power_w, m.laser_on ? 700.0 : 0.0) << "line " << m.line;
        EXPECT_DOUBLE_EQ(m.powder_g_min, m.laser_on ? 8.0 : 0.0) << "line " << m.line;
    }
    // A 500 ms dwell after every laser-on, written in milliseconds.
    ASSERT_EQ(static_cast<int>(read.dwells.size()), read.laser_on_events);
    for (double d : read.dwells) EXPECT_DOUBLE_EQ(d, 500.0);
    for (std::size_t i = 0; i < read.blocks.size(); ++i) {
        if (read.blocks[i] == "M8") {
            ASSERT_LT(i + 1, read.blocks.size());
            EXPECT_EQ(read.blocks[i + 1], "G4 P500");
        }
    }
}

TEST(GmWriter, ColumnsHaveTwoDecimals) {
    const auto text =
        write_program(tiny_program(reference_process()), gm_machine(), reference_process());
    ASSERT_TRUE(text.has_value());
    EXPECT_NE(text->find("\n700.00 8.00 G1 X10.000 Y0.000 Z0.500 F381.0\n"), std::string::npos);
    EXPECT_NE(text->find("\n0.00 0.00 G1 X0.000 Y5.000 Z1.000 F2540.0\n"), std::string::npos)
        << "-0.0001 must be written as 0.000";
    EXPECT_EQ(text->find("-0.000"), std::string::npos);
}

TEST(LinuxCncWriter, ParsesBackToTheProgram) {
    const ProcessProfile process = reference_process();
    const Program program = testing::planar_block(process, 4);
    const auto text = write_program(program, linuxcnc_machine(), process);
    ASSERT_TRUE(text.has_value()) << text.error().describe();
    const auto read = read_text(*text, false, "M64 P0", "M65 P0");
    expect_round_trip(program, process, read, true);
    // G4 P is in seconds for LinuxCNC.
    ASSERT_EQ(static_cast<int>(read.dwells.size()), read.laser_on_events);
    for (double d : read.dwells) EXPECT_DOUBLE_EQ(d, 0.5);
    EXPECT_NE(text->find("\nG21 G90 G94 G17\n"), std::string::npos);
    EXPECT_TRUE(text->ends_with("\nM2\n"));
    EXPECT_EQ(text->find('%'), std::string::npos);
    EXPECT_EQ(text->find('\t'), std::string::npos);
    for (int l = 0; l < 4; ++l) {
        EXPECT_NE(text->find("(layer " + std::to_string(l) + " region 0)"), std::string::npos);
    }
    std::istringstream lines(*text);
    std::string line;
    while (std::getline(lines, line)) EXPECT_LE(line.size(), 80u) << line;
    // Names in comments cannot open or close a comment.
    EXPECT_NE(text->find("(machine test linuxcnc _gantry_, dialect linuxcnc)"), std::string::npos);
    EXPECT_NE(text->find("M68 E0 Q700.00\nM64 P0\nG4 P0.500\n"), std::string::npos);
}

TEST(Writers, RandomProgramsRoundTrip) {
    const ProcessProfile process = reference_process();
    for (unsigned seed = 1; seed <= 20; ++seed) {
        SCOPED_TRACE(seed);
        const bool vary = seed % 2 == 0;
        const Program program = testing::random_program(process, seed, vary);
        ASSERT_TRUE(check_program(program, gm_machine(), process).has_value());
        const auto gm = write_program(program, gm_machine(), process);
        ASSERT_TRUE(gm.has_value()) << gm.error().describe();
        expect_round_trip(program, process, read_text(*gm, true, "M8", "M9"), !vary);
        const auto cnc = write_program(program, linuxcnc_machine(), process);
        ASSERT_TRUE(cnc.has_value()) << cnc.error().describe();
        expect_round_trip(program, process, read_text(*cnc, false, "M64 P0", "M65 P0"), !vary);
    }
}

TEST(Writers, PowerChangeWithinAWireIsWritten) {
    const ProcessProfile process = reference_process();
    Program program = tiny_program(process);
    for (Move& m : program.moves) {
        if (m.kind == MoveKind::kDeposit && m.layer == 0 && m.position.x == 10.0 &&
            m.position.y == 10.0) {
            m.laser_w = 650.0;
        }
    }
    const auto cnc = write_program(program, linuxcnc_machine(), process);
    ASSERT_TRUE(cnc.has_value());
    EXPECT_NE(cnc->find("M68 E0 Q650.00\nG1 X10.000 Y10.000"), std::string::npos) << *cnc;
    const auto gm = write_program(program, gm_machine(), process);
    ASSERT_TRUE(gm.has_value());
    EXPECT_NE(gm->find("650.00 8.00 G1 X10.000 Y10.000"), std::string::npos);
}

TEST(Writers, Deterministic) {
    const ProcessProfile process = reference_process();
    for (const MachineProfile& machine : {gm_machine(), linuxcnc_machine()}) {
        const auto a = write_program(testing::planar_block(process, 3), machine, process);
        const auto b = write_program(testing::planar_block(process, 3), machine, process);
        ASSERT_TRUE(a.has_value() && b.has_value());
        EXPECT_EQ(*a, *b);
    }
}

TEST(Writers, EmptyProgram) {
    const ProcessProfile process = reference_process();
    const auto gm = write_program(Program{}, gm_machine(), process);
    ASSERT_TRUE(gm.has_value());
    EXPECT_EQ(*gm, "0.00 0.00 G21\n0.00 0.00 G90\n");
    const auto cnc = write_program(Program{}, linuxcnc_machine(), process);
    ASSERT_TRUE(cnc.has_value());
    EXPECT_TRUE(cnc->ends_with("G21 G90 G94 G17\nM2\n"));
}

// A limit violation returns an error naming the move, its layer and the value, and no text.
void expect_rejected(const Program& program, const std::vector<std::string>& fragments,
                     core::ErrorCode code = core::ErrorCode::kInvalidInput,
                     const MachineProfile& machine = gm_machine()) {
    const auto text = write_program(program, machine, reference_process());
    ASSERT_FALSE(text.has_value()) << "written, expected " << fragments.front();
    EXPECT_EQ(text.error().code, code) << text.error().describe();
    EXPECT_EQ(text.error().context, "machine " + machine.name);
    for (const auto& f : fragments) {
        EXPECT_NE(text.error().message.find(f), std::string::npos)
            << "`" << f << "` not in: " << text.error().describe();
    }
}

// Index of the first deposit move of layer 1 in the tiny program.
std::size_t first_deposit_of_layer_1(const Program& p) {
    for (std::size_t i = 0; i < p.moves.size(); ++i) {
        if (p.moves[i].kind == MoveKind::kDeposit && p.moves[i].layer == 1) return i;
    }
    return p.moves.size();
}

TEST(LimitCheck, MoveOverAnAxisLimit) {
    Program p = tiny_program(reference_process());
    const std::size_t i = first_deposit_of_layer_1(p);
    p.moves[i].position.x = -112.5;
    expect_rejected(
        p, {"move " + std::to_string(i), "layer 1", "X = -112.500 mm", "[-100.000, 100.000]"});
    Program q = tiny_program(reference_process());
    q.moves.back().position.z = 200.001;
    expect_rejected(q, {"Z = 200.001 mm"});
    // Exactly on the limit is fine.
    Program r = tiny_program(reference_process());
    r.moves.back().position.z = 200.0;
    EXPECT_TRUE(write_program(r, gm_machine(), reference_process()).has_value());
}

TEST(LimitCheck, NotANumber) {
    Program p = tiny_program(reference_process());
    const std::size_t i = first_deposit_of_layer_1(p);
    p.moves[i].position.y = NAN;
    expect_rejected(p, {"move " + std::to_string(i), "layer 1", "Y = nan", "not a finite"},
                    core::ErrorCode::kInternal);
    Program q = tiny_program(reference_process());
    q.moves[i].feed_mm_min = INFINITY;
    expect_rejected(q, {"feed = inf"}, core::ErrorCode::kInternal);
}

TEST(LimitCheck, FeedOutOfRange) {
    Program p = tiny_program(reference_process());
    const std::size_t i = first_deposit_of_layer_1(p);
    p.moves[i].feed_mm_min = 6000.0;
    expect_rejected(p, {"move " + std::to_string(i), "layer 1", "F = 6000 mm/min", "[1, 5000]"});
    p.moves[i].feed_mm_min = 0.0;
    expect_rejected(p, {"F = 0 mm/min"});
}

TEST(LimitCheck, PowerAndPowderOutOfRange) {
    Program p = tiny_program(reference_process());
    const std::size_t i = first_deposit_of_layer_1(p);
    p.moves[i].laser_w = 1200.0;
    expect_rejected(p, {"move " + std::to_string(i), "laser power 1200 W", "[0, 1000]"});
    Program q = tiny_program(reference_process());
    q.moves[i].powder_g_min = 25.0;
    expect_rejected(q, {"powder feed 25 g/min"});
}

TEST(LimitCheck, TiltedToolNeedsRotaryAxes) {
    Program p = tiny_program(reference_process());
    p.moves[2].direction = core::normalized({0.0, 1.0, 1.0});
    expect_rejected(p, {"move 2", "tilted 45.0000 deg", "xyz"});
}

TEST(LimitCheck, Sequence) {
    const ProcessProfile process = reference_process();
    Program deposit_off = tiny_program(process);
    deposit_off.moves.erase(deposit_off.moves.begin() + 1);  // the first laser-on
    expect_rejected(deposit_off, {"move 1", "deposit move while the laser is off"},
                    core::ErrorCode::kInternal);

    Program ends_on = tiny_program(process);
    ends_on.moves.pop_back();  // the final travel
    ends_on.moves.pop_back();  // the last laser-off
    expect_rejected(ends_on, {"ends with the laser on"}, core::ErrorCode::kInternal);

    Program hot_travel = tiny_program(process);
    hot_travel.moves.back().laser_w = 700.0;
    expect_rejected(hot_travel, {"travel move with the laser at 700 W"},
                    core::ErrorCode::kInternal);

    Program on_first;
    Move on;
    on.kind = MoveKind::kLaserOn;
    on.laser_w = 700.0;
    on_first.moves.push_back(on);
    expect_rejected(on_first, {"move 0", "before any move"}, core::ErrorCode::kInternal);
}

TEST(LimitCheck, ProfilesAreValidatedToo) {
    MachineProfile bad = gm_machine();
    bad.axes[0].min = 200.0;
    const auto r = write_program(tiny_program(reference_process()), bad, reference_process());
    ASSERT_FALSE(r.has_value());
    EXPECT_NE(r.error().message.find("machine.axes.X.min"), std::string::npos);
}

// LinuxCNC's own interpreter (package linuxcnc-uspace) must accept the written program.
std::size_t count(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) {
        ++n;
    }
    return n;
}

TEST(LinuxCncWriter, Rs274AcceptsTheProgram) {
    if (test::find_rs274().empty()) {
        GTEST_SKIP() << "rs274 not installed (Debian package linuxcnc-uspace)";
    }
    const ProcessProfile process = reference_process();
    const Program program = testing::random_program(process, 7, true);
    const auto text = write_program(program, linuxcnc_machine(), process);
    ASSERT_TRUE(text.has_value()) << text.error().describe();

    const auto run = test::run_rs274(*text);
    ASSERT_TRUE(run);
    ASSERT_EQ(run->status, 0) << run->errors;
    EXPECT_TRUE(test::only_executing(run->errors)) << run->errors;

    // What it understood: one STRAIGHT_FEED per G1, one DWELL per laser-on, the outputs.
    const std::string& calls = run->canon;
    std::size_t laser_ons = 0;
    for (const Move& m : program.moves) laser_ons += m.kind == MoveKind::kLaserOn ? 1 : 0;
    EXPECT_EQ(count(calls, "STRAIGHT_FEED("), positioning(program).size());
    EXPECT_EQ(count(calls, "DWELL(0.5000)"), laser_ons);
    EXPECT_EQ(count(calls, "SET_AUX_OUTPUT_BIT(0)"), laser_ons);
    EXPECT_EQ(count(calls, "CLEAR_AUX_OUTPUT_BIT(0)"), laser_ons);
    EXPECT_EQ(count(calls, "SET_AUX_OUTPUT_VALUE(0,700.000000)"), laser_ons);
    EXPECT_EQ(count(calls, "PROGRAM_END()"), 1u);
}

}  // namespace
}  // namespace maxslice::machine
