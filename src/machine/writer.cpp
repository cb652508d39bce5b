#include "maxslice/machine/writer.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <optional>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "maxslice/machine/kinematics.hpp"
#include "maxslice/machine/machine_moves.hpp"
#include "maxslice/machine/program_check.hpp"

namespace maxslice::machine {
namespace {

// Fixed decimals for every number: mm and deg 3, feed 1, power and powder 2, so the text depends
// only on the values (fmt formats without the locale). "-0.000" is written as "0.000".
constexpr int kMmDecimals = 3;
constexpr int kDegDecimals = 3;
constexpr int kFeedDecimals = 1;
constexpr int kPowerDecimals = 2;
constexpr int kDwellMsDecimals = 0;
constexpr int kDwellSDecimals = 3;
/// Part and machine names in comments are cut to this many characters.
constexpr std::size_t kMaxNameInComment = 60;

// Numbers are written as a rounded integer count of 10^-decimals with std::to_chars (about
// ten times faster than a formatted float: programs run to millions of numbers); values
// too large for that exactness fall back to fmt.
void append_fixed(std::string& out, double value, int decimals) {
    static constexpr double kScale[] = {1.0, 10.0, 100.0, 1e3, 1e4, 1e5, 1e6};
    static constexpr std::int64_t kScaleInt[] = {1, 10, 100, 1000, 10000, 100000, 1000000};
    if (decimals >= 0 && decimals <= 6 && std::abs(value) < 1e9) {
        const auto n = static_cast<std::int64_t>(std::llround(value * kScale[decimals]));
        const std::int64_t mag = n < 0 ? -n : n;
        char buf[40];
        char* p = buf;
        if (n < 0) *p++ = '-';
        p = std::to_chars(p, buf + sizeof buf, mag / kScaleInt[decimals]).ptr;
        if (decimals > 0) {
            *p++ = '.';
            std::int64_t frac = mag % kScaleInt[decimals];
            for (int d = decimals - 1; d >= 0; --d) {
                p[d] = static_cast<char>('0' + frac % 10);
                frac /= 10;
            }
            p += decimals;
        }
        out.append(buf, p);
        return;
    }
    const std::size_t start = out.size();
    fmt::format_to(std::back_inserter(out), "{:.{}f}", value, decimals);
    if (out[start] == '-' && out.find_first_not_of("0.", start + 1) == std::string::npos) {
        out.erase(start, 1);
    }
}

// RS-274 comments end at the first ')' and may not nest: keep names to plain characters.
std::string comment_text(std::string_view text) {
    std::string out;
    for (char c : text.substr(0, kMaxNameInComment)) {
        const bool plain = c >= 0x20 && c <= 0x7e && c != '(' && c != ')' && c != ';';
        out += plain ? c : '_';
    }
    return out;
}

std::string mm_text(double value) {
    std::string out;
    append_fixed(out, value, kMmDecimals);
    return out;
}

bool has_placeholder(std::string_view block) {
    return block.find('{') != std::string_view::npos;
}

// How the axis words of a positioning block are written.
struct AxisWords {
    bool rotary = false;  // a table machine: A|B and C after X Y Z
    char tilt = 'A';
    core::Vec3d pivot{};  // under tool centre point control X Y Z = pivot + the part tip
};

// One positioning block: `G1 X Y Z [A|B C] F`. The first two steps of the program start know
// only Z (and then the rotary axes): they carry no X Y. `tcp`: the block is written under tool
// centre point control (program moves only).
void append_positioning(std::string& out, const MachineMove& mm, const AxisWords& w, bool tcp) {
    const MachinePose& p = mm.pose;
    const bool start =
        mm.step == ReorientStep::kStartRetract || mm.step == ReorientStep::kStartTurn;
    out += "G1";
    if (!start) {
        const core::Vec3d xyz = tcp ? w.pivot + mm.move.position : core::Vec3d{p.x, p.y, p.z};
        out += " X";
        append_fixed(out, xyz.x, kMmDecimals);
        out += " Y";
        append_fixed(out, xyz.y, kMmDecimals);
        out += " Z";
        append_fixed(out, xyz.z, kMmDecimals);
    } else {
        out += " Z";
        append_fixed(out, p.z, kMmDecimals);
    }
    if (w.rotary && mm.step != ReorientStep::kStartRetract) {
        out += ' ';
        out += w.tilt;
        append_fixed(out, p.a_or_b_deg, kDegDecimals);
        out += " C";
        append_fixed(out, p.c_deg, kDegDecimals);
    }
    out += " F";
    append_fixed(out, mm.move.feed_mm_min, kFeedDecimals);
}

AxisWords axis_words(const MachineProfile& machine) {
    AxisWords w;
    w.rotary = is_table_tilt(machine.kinematics);
    w.tilt = machine.kinematics == Kinematics::kTableBc ? 'B' : 'A';
    if (machine.table) w.pivot = machine.table->pivot_mm;
    return w;
}

class GmWriter {
public:
    GmWriter(const MachineProfile& machine, const ProcessProfile& process)
        : machine_(machine), words_(axis_words(machine)), off_w_(process.laser_power_off_w) {}

    std::string write(std::span<const MachineMove> moves) {
        line(off_w_, 0.0, "G21");
        line(off_w_, 0.0, "G90");
        blocks(machine_.codes.program_start, off_w_, 0.0);
        for (const MachineMove& mm : moves) {
            const Move& m = mm.move;
            switch (m.kind) {
                case MoveKind::kTravel:
                case MoveKind::kDeposit:
                    columns(m.laser_w, m.powder_g_min);
                    append_positioning(out_, mm, words_, false);
                    out_ += '\n';
                    break;
                case MoveKind::kLaserOn:
                    blocks(machine_.codes.powder_on, m.laser_w, m.powder_g_min);
                    blocks(machine_.codes.laser_on, m.laser_w, m.powder_g_min);
                    if (m.dwell_ms > 0.0) {
                        columns(m.laser_w, m.powder_g_min);
                        out_ += "G4 P";
                        append_fixed(out_, m.dwell_ms, kDwellMsDecimals);
                        out_ += '\n';
                    }
                    break;
                case MoveKind::kLaserOff:
                    blocks(machine_.codes.laser_off, m.laser_w, m.powder_g_min);
                    blocks(machine_.codes.powder_off, m.laser_w, m.powder_g_min);
                    break;
            }
        }
        blocks(machine_.codes.program_end, off_w_, 0.0);
        return std::move(out_);
    }

private:
    void columns(double power_w, double powder_g_min) {
        append_fixed(out_, power_w, kPowerDecimals);
        out_ += ' ';
        append_fixed(out_, powder_g_min, kPowerDecimals);
        out_ += ' ';
    }
    void line(double power_w, double powder_g_min, std::string_view block) {
        columns(power_w, powder_g_min);
        out_ += block;
        out_ += '\n';
    }
    void blocks(const CodeTemplate& t, double power_w, double powder_g_min) {
        for (const auto& b : t.blocks) {
            line(power_w, powder_g_min,
                 expand_block(b, power_w, powder_g_min, machine_.laser_power_max_w));
        }
    }

    const MachineProfile& machine_;
    AxisWords words_;
    double off_w_;
    std::string out_;
};

// What tells the RS-274 dialects apart (docs/program-dialects.md, "Dialect details").
struct RsStyle {
    std::string_view name;
    std::vector<std::string_view> opening;  // before the header comments
    std::string_view comment_open;
    std::string_view comment_close;
    std::string_view modes;
    std::string_view dwell;   // followed by seconds
    std::string_view tcp_on;  // empty: no tool centre point control (joint space)
    std::string_view tcp_off;
    // Tool length compensation alone, so that X Y Z are the tool tip also with TCP off: after
    // the modes on an xyz machine, after tcp_off in every re-orientation; tcp_off cancels it.
    std::string_view length_on;
    std::vector<std::string_view> closing;  // after program_end and tcp_off
};

RsStyle rs_style(Dialect dialect) {
    switch (dialect) {
        case Dialect::kFanuc:
            return {"fanuc",
                    {"%", "O1000 (MAXSLICE)"},
                    "(",
                    ")",
                    "G21 G90 G94 G17",
                    "G4 X",
                    "G43.4 H1",
                    "G49",
                    "G43 H1",
                    {"M30", "%"}};
        case Dialect::kSiemens:
            // TRAFOOF keeps the tool offset: X Y Z stay the tool tip without a length word.
            return {"siemens", {},       "; ",      "", "G71 G90 G94 G17",
                    "G4 F",    "TRAORI", "TRAFOOF", "", {"M30"}};
        case Dialect::kGm:
        case Dialect::kLinuxCnc: break;
    }
    return {"linuxcnc", {}, "(", ")", "G21 G90 G94 G17", "G4 P", "", "", "", {"M2"}};
}

// linuxcnc, fanuc and siemens: one block per line, comments, codes for laser and powder.
class RsWriter {
public:
    RsWriter(const MachineProfile& machine, const ProcessProfile& process, double clear_z_mm)
        : machine_(machine),
          process_(process),
          style_(rs_style(machine.dialect)),
          words_(axis_words(machine)),
          tcp_(words_.rotary && !style_.tcp_on.empty()),
          clear_z_mm_(clear_z_mm) {}

    std::string write(std::string_view part_name, const std::optional<core::Vec3d>& base,
                      std::span<const MachineMove> moves) {
        for (const auto& l : style_.opening) line(l);
        comment(fmt::format("maxslice program, part {}",
                            comment_text(part_name.empty() ? "unnamed" : part_name)));
        if (base) {
            // Shortest round-trip digits: `maxslice verify` places the model bit for bit.
            comment(fmt::format("{}{},{},{}", kBaseDirectionTag, base->x, base->y, base->z));
        }
        comment(fmt::format("machine {}, dialect {}", comment_text(machine_.name), style_.name));
        comment(fmt::format("process: track {:.3f} mm, layer {:.3f} mm, {:.2f} W, {:.2f} g/min",
                            process_.track_width_mm, process_.layer_height_mm,
                            process_.laser_power_w, process_.powder_feed_g_min));
        if (words_.rotary) {
            comment(fmt::format("kinematics {}, {}", kinematics_name(machine_.kinematics),
                                tcp_ ? "tool centre point control" : "joint space"));
            comment(fmt::format("pivot {} {} {} mm, clearance height {} mm",
                                mm_text(words_.pivot.x), mm_text(words_.pivot.y),
                                mm_text(words_.pivot.z), mm_text(clear_z_mm_)));
        }
        line(style_.modes);
        if (!tcp_ && !style_.length_on.empty()) line(style_.length_on);
        blocks(machine_.codes.program_start, process_.laser_power_off_w, 0.0, false);
        std::optional<std::pair<int, int>> layer;
        double power_w = 0.0;
        double powder_g_min = 0.0;
        bool tcp_on = false;
        for (const MachineMove& mm : moves) {
            const Move& m = mm.move;
            if (m.layer >= 0 && layer != std::pair{m.layer, m.region}) {
                layer = std::pair{m.layer, m.region};
                comment(fmt::format("layer {} region {}", m.layer, m.region));
            }
            // Re-orientations run in joint space: the control goes off at the start of each
            // sequence (the first one too: the controller's state is unknown), with the tool
            // length still applied (fanuc: G49 cancels both, G43 H1 restores the length, or
            // the tip would be the tool length below z_safe), and on again before the
            // approach.
            if (tcp_ &&
                (mm.step == ReorientStep::kStartRetract || mm.step == ReorientStep::kRetract)) {
                line(style_.tcp_off);
                if (!style_.length_on.empty()) line(style_.length_on);
                tcp_on = false;
            }
            const bool positioning = m.kind == MoveKind::kTravel || m.kind == MoveKind::kDeposit;
            if (tcp_ && positioning && !mm.inserted() && !tcp_on) {
                line(style_.tcp_on);
                tcp_on = true;
            }
            switch (m.kind) {
                case MoveKind::kTravel:
                    append_positioning(out_, mm, words_, tcp_on);
                    out_ += '\n';
                    break;
                case MoveKind::kDeposit:
                    // No power column: a change within a wire re-sends the blocks that carry
                    // the value.
                    if (m.powder_g_min != powder_g_min) {
                        blocks(machine_.codes.powder_on, m.laser_w, m.powder_g_min, true);
                    }
                    if (m.laser_w != power_w) {
                        blocks(machine_.codes.laser_on, m.laser_w, m.powder_g_min, true);
                    }
                    power_w = m.laser_w;
                    powder_g_min = m.powder_g_min;
                    append_positioning(out_, mm, words_, tcp_on);
                    out_ += '\n';
                    break;
                case MoveKind::kLaserOn:
                    blocks(machine_.codes.powder_on, m.laser_w, m.powder_g_min, false);
                    blocks(machine_.codes.laser_on, m.laser_w, m.powder_g_min, false);
                    power_w = m.laser_w;
                    powder_g_min = m.powder_g_min;
                    if (m.dwell_ms > 0.0) {
                        out_ += style_.dwell;  // seconds in all three
                        append_fixed(out_, m.dwell_ms / 1000.0, kDwellSDecimals);
                        out_ += '\n';
                    }
                    break;
                case MoveKind::kLaserOff:
                    blocks(machine_.codes.laser_off, m.laser_w, m.powder_g_min, false);
                    blocks(machine_.codes.powder_off, m.laser_w, m.powder_g_min, false);
                    power_w = 0.0;
                    powder_g_min = 0.0;
                    break;
            }
        }
        blocks(machine_.codes.program_end, process_.laser_power_off_w, 0.0, false);
        if (tcp_ || !style_.length_on.empty()) line(style_.tcp_off);
        for (const auto& l : style_.closing) line(l);
        return std::move(out_);
    }

private:
    void line(std::string_view text) {
        out_ += text;
        out_ += '\n';
    }
    void comment(std::string_view text) {
        out_ += style_.comment_open;
        out_ += text;
        out_ += style_.comment_close;
        out_ += '\n';
    }
    void blocks(const CodeTemplate& t, double power_w, double powder_g_min, bool only_with_values) {
        for (const auto& b : t.blocks) {
            if (only_with_values && !has_placeholder(b)) continue;
            out_ += expand_block(b, power_w, powder_g_min, machine_.laser_power_max_w);
            out_ += '\n';
        }
    }

    const MachineProfile& machine_;
    const ProcessProfile& process_;
    RsStyle style_;
    AxisWords words_;
    bool tcp_;
    double clear_z_mm_;
    std::string out_;
};

}  // namespace

core::Result<std::string> write_program(const Program& program, const MachineProfile& machine,
                                        const ProcessProfile& process,
                                        const WriteOptions& options) {
    const std::string context = "machine " + machine.name;
    const auto fail = [&](const core::Error& e) {
        return std::unexpected(core::with_context(e, context));
    };
    if (auto ok = validate(machine); !ok) return fail(ok.error());
    if (auto ok = validate(process); !ok) return fail(ok.error());
    if (auto ok = check_compatible(machine, process); !ok) return fail(ok.error());
    if (auto ok = check_program(program, machine, process); !ok) {
        return std::unexpected(ok.error());
    }
    const auto kinematics = MachineKinematics::create(machine);
    if (!kinematics) return fail(kinematics.error());
    double clear_z_mm = 0.0;
    if (options.clear_z_mm) {
        clear_z_mm = *options.clear_z_mm;
        if (!std::isfinite(clear_z_mm)) {
            return core::fail(
                core::ErrorCode::kInvalidInput,
                fmt::format("the clearance height {} mm is not a finite number", clear_z_mm),
                context);
        }
    } else if (is_table_tilt(machine.kinematics)) {
        // The program's own positions stand for the part (the job passes the placed mesh's).
        std::vector<core::Vec3d> points;
        points.reserve(program.moves.size());
        for (const Move& m : program.moves) {
            if (m.kind == MoveKind::kTravel || m.kind == MoveKind::kDeposit) {
                points.push_back(m.position);
            }
        }
        clear_z_mm = clear_height_mm(machine, points);
    }
    const auto moves = to_machine_moves(program, *kinematics, clear_z_mm);
    if (!moves) return fail(moves.error());
    switch (machine.dialect) {
        case Dialect::kGm: return GmWriter(machine, process).write(*moves);
        case Dialect::kLinuxCnc:
        case Dialect::kFanuc:
        case Dialect::kSiemens:
            return RsWriter(machine, process, clear_z_mm)
                .write(program.part_name, program.base_direction, *moves);
    }
    return core::fail(core::ErrorCode::kInternal, "unknown dialect", context);
}

}  // namespace maxslice::machine
