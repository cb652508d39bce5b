#pragma once

// Profiles and programs built in code for the machine tests, and a small reader of the
// written text that is independent of the writers.

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "maxslice/machine/kinematics.hpp"
#include "maxslice/machine/profile.hpp"
#include "maxslice/machine/program.hpp"
#include "maxslice/machine/program_builder.hpp"

namespace maxslice::machine::testing {

/// The reference process of METHOD.md, with a 500 ms dwell.
inline ProcessProfile reference_process() {
    ProcessProfile p;
    p.track_width_mm = 2.5;
    p.layer_height_mm = 0.5;
    p.h_min_mm = 0.3;
    p.h_max_mm = 0.7;
    p.overlap = 0.3;
    p.contour_passes = 1;
    p.laser_power_w = 700.0;
    p.laser_power_off_w = 0.0;
    p.powder_feed_g_min = 8.0;
    p.deposition_feed_mm_min = 381.0;
    p.travel_feed_mm_min = 2540.0;
    p.dwell_after_laser_on_ms = 500.0;
    p.self_supporting_angle_deg = 20.0;
    return p;
}

inline MachineProfile gm_machine() {
    MachineProfile m;
    m.name = "test gm cell";
    m.kinematics = Kinematics::kXyz;
    m.dialect = Dialect::kGm;
    m.axes = {{"X", -100.0, 100.0}, {"Y", -100.0, 100.0}, {"Z", -10.0, 200.0}};
    m.feed_min_mm_min = 1.0;
    m.feed_max_mm_min = 5000.0;
    m.laser_power_min_w = 0.0;
    m.laser_power_max_w = 1000.0;
    m.powder_feed_max_g_min = 20.0;
    m.codes.laser_on.blocks = {"M8"};
    m.codes.laser_off.blocks = {"M9"};
    return m;
}

inline MachineProfile linuxcnc_machine() {
    MachineProfile m = gm_machine();
    m.name = "test linuxcnc (gantry)";
    m.dialect = Dialect::kLinuxCnc;
    m.codes.powder_on.blocks = {"M68 E1 Q{powder}", "M64 P1"};
    m.codes.laser_on.blocks = {"M68 E0 Q{power}", "M64 P0"};
    m.codes.laser_off.blocks = {"M65 P0", "M68 E0 Q0"};
    m.codes.powder_off.blocks = {"M65 P1", "M68 E1 Q0"};
    return m;
}

/// A closed square wire of side `side` at height z, starting at (x0, y0).
/// The lowest part-frame z (the plate's level is 0) of the head standing vertically at the
/// joint pose: forward kinematics of the tip and of 64 machine points on each circle of the
/// nozzle outline's corners (the cone's rim, the body's ends), in the tests' own terms.
inline double head_floor(const MachineKinematics& k, const NozzleProfile& n,
                         const MachinePose& pose) {
    const double rim = n.cone_length_mm * std::tan(n.half_angle_deg * std::numbers::pi / 180.0);
    double lowest = k.forward(pose).tip_mm.z;
    for (const auto& [along, radius] :
         {std::pair{n.cone_length_mm, rim}, std::pair{n.cone_length_mm, n.body_radius_mm},
          std::pair{n.cone_length_mm + n.body_length_mm, n.body_radius_mm}}) {
        for (int j = 0; j < 64; ++j) {
            const double phi = 2.0 * std::numbers::pi * j / 64.0;
            const MachinePose q{pose.x + radius * std::cos(phi), pose.y + radius * std::sin(phi),
                                pose.z + along, pose.a_or_b_deg, pose.c_deg};
            lowest = std::min(lowest, k.forward(q).tip_mm.z);
        }
    }
    return lowest;
}

inline std::vector<core::Vec3d> square(double x0, double y0, double side, double z) {
    return {{x0, y0, z},
            {x0 + side, y0, z},
            {x0 + side, y0 + side, z},
            {x0, y0 + side, z},
            {x0, y0, z}};
}

/// A planar build: per layer a square contour and a zigzag fill inside it, each fill line its
/// own wire (so there are many laser-on events and travels).
inline Program planar_block(const ProcessProfile& process, int layers, double side = 20.0) {
    Program program;
    program.part_name = "planar block";
    const double pitch = process.track_width_mm * (1.0 - process.overlap);
    for (int l = 0; l < layers; ++l) {
        const double z = process.layer_height_mm * (l + 1);
        const auto contour = square(0.0, 0.0, side, z);
        append_wire(program, contour, process, l);
        int line = 0;
        for (double y = pitch; y < side - pitch / 2; y += pitch, ++line) {
            const double a = process.track_width_mm;
            const double b = side - process.track_width_mm;
            const std::vector<core::Vec3d> wire =
                line % 2 == 0 ? std::vector<core::Vec3d>{{a, y, z}, {b, y, z}}
                              : std::vector<core::Vec3d>{{b, y, z}, {a, y, z}};
            append_wire(program, wire, process, l);
        }
    }
    return program;
}

/// Random wires inside [-90, 90]^2 x (0, 150], with random feeds per deposit move inside
/// the machine range when `vary_feed` is set. Deterministic for a seed.
inline Program random_program(const ProcessProfile& process, unsigned seed, bool vary_feed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> xy(-90.0, 90.0);
    std::uniform_int_distribution<int> count(2, 12);
    Program program;
    program.part_name = "random " + std::to_string(seed);
    const int layers = count(rng);
    for (int l = 0; l < layers; ++l) {
        const double z = 0.5 * (l + 1);
        const int wires = count(rng);
        for (int w = 0; w < wires; ++w) {
            std::vector<core::Vec3d> points;
            const int n = count(rng);
            for (int i = 0; i < n; ++i) points.push_back({xy(rng), xy(rng), z});
            append_wire(program, points, process, l, l / 4);
        }
    }
    if (vary_feed) {
        std::uniform_real_distribution<double> feed(100.0, 900.0);
        for (Move& m : program.moves) {
            if (m.kind == MoveKind::kDeposit) m.feed_mm_min = feed(rng);
        }
    }
    return program;
}

/// One G1 line read back from written text.
struct ReadMove {
    double x = NAN, y = NAN, z = NAN, f = NAN;
    bool laser_on = false;      ///< between a laser-on and a laser-off block
    double power_w = NAN;       ///< gm: the power column
    double powder_g_min = NAN;  ///< gm: the powder column
    int line = 0;
};

/// What the reader found; `problems` lists every line it could not accept.
struct ReadProgram {
    std::vector<ReadMove> moves;
    std::vector<double> dwells;  ///< G4 P values as written
    int laser_on_events = 0;
    std::vector<std::string> comments;
    std::vector<std::string> problems;
    std::vector<std::string> blocks;  ///< every block (gm: without the columns)
};

/// Moves that position the head (travel and deposit), in order.
inline std::vector<const Move*> positioning(const Program& p) {
    std::vector<const Move*> out;
    for (const Move& m : p.moves) {
        if (m.kind == MoveKind::kTravel || m.kind == MoveKind::kDeposit) out.push_back(&m);
    }
    return out;
}

inline std::optional<double> word(const std::string& block, char letter) {
    std::istringstream in(block);
    std::string token;
    while (in >> token) {
        if (token.size() > 1 && token[0] == letter) {
            char* end = nullptr;
            const double v = std::strtod(token.c_str() + 1, &end);
            if (end != nullptr && *end == '\0') return v;
        }
    }
    return std::nullopt;
}

/// Reads gm (`columns` = true) or RS-274 text. The laser counts as on after a block equal to
/// `on_block` and off after `off_block`. Columns with power must only occur while it is on.
inline ReadProgram read_text(const std::string& text, bool columns, const std::string& on_block,
                             const std::string& off_block) {
    ReadProgram out;
    std::istringstream in(text);
    std::string line;
    bool on = false;
    int number = 0;
    while (std::getline(in, line)) {
        ++number;
        const auto problem = [&](const std::string& what) {
            out.problems.push_back("line " + std::to_string(number) + ": " + what + ": " + line);
        };
        double power = NAN, powder = NAN;
        std::string block = line;
        if (columns) {
            std::istringstream cols(line);
            if (!(cols >> power >> powder)) {
                problem("no power and powder columns");
                continue;
            }
            cols >> std::ws;
            std::getline(cols, block);
        }
        out.blocks.push_back(block);
        if (block == on_block) {
            if (on) problem("laser on twice");
            on = true;
            ++out.laser_on_events;
        }
        if (block == off_block) {
            if (!on) problem("laser off twice");
            on = false;
        }
        if (columns && power > 0.0 && !on) problem("power column while the laser is off");
        if (block.starts_with("(")) {
            out.comments.push_back(block);
        } else if (block.starts_with("G4 ")) {
            if (const auto p = word(block, 'P')) {
                out.dwells.push_back(*p);
            } else {
                problem("G4 without P");
            }
        } else if (block.starts_with("G1 ")) {
            ReadMove m;
            const auto x = word(block, 'X'), y = word(block, 'Y'), z = word(block, 'Z'),
                       f = word(block, 'F');
            if (!x || !y || !z || !f) {
                problem("G1 without X Y Z F");
                continue;
            }
            m.x = *x;
            m.y = *y;
            m.z = *z;
            m.f = *f;
            m.laser_on = on;
            m.power_w = power;
            m.powder_g_min = powder;
            m.line = number;
            out.moves.push_back(m);
        }
    }
    if (on) out.problems.push_back("the text ends with the laser on");
    return out;
}

}  // namespace maxslice::machine::testing
