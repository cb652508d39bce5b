#include "maxslice/machine/writer.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <optional>
#include <utility>

#include "maxslice/machine/program_check.hpp"

namespace maxslice::machine {
namespace {

// Fixed decimals for every number: mm 3, feed 1, power and powder 2, so the text depends only
// on the values (fmt formats without the locale). "-0.000" is written as "0.000".
constexpr int kMmDecimals = 3;
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

void append_move(std::string& out, const Move& m) {
    out += "G1 X";
    append_fixed(out, m.position.x, kMmDecimals);
    out += " Y";
    append_fixed(out, m.position.y, kMmDecimals);
    out += " Z";
    append_fixed(out, m.position.z, kMmDecimals);
    out += " F";
    append_fixed(out, m.feed_mm_min, kFeedDecimals);
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

bool has_placeholder(std::string_view block) {
    return block.find('{') != std::string_view::npos;
}

class GmWriter {
public:
    GmWriter(const MachineProfile& machine, const ProcessProfile& process)
        : machine_(machine), off_w_(process.laser_power_off_w) {}

    std::string write(const Program& program) {
        line(off_w_, 0.0, "G21");
        line(off_w_, 0.0, "G90");
        blocks(machine_.codes.program_start, off_w_, 0.0);
        for (const Move& m : program.moves) {
            switch (m.kind) {
                case MoveKind::kTravel:
                case MoveKind::kDeposit:
                    columns(m.laser_w, m.powder_g_min);
                    append_move(out_, m);
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
    double off_w_;
    std::string out_;
};

class LinuxCncWriter {
public:
    LinuxCncWriter(const MachineProfile& machine, const ProcessProfile& process)
        : machine_(machine), process_(process) {}

    std::string write(const Program& program) {
        fmt::format_to(std::back_inserter(out_), "(maxslice program, part {})\n",
                       comment_text(program.part_name.empty() ? "unnamed" : program.part_name));
        fmt::format_to(std::back_inserter(out_), "(machine {}, dialect linuxcnc)\n",
                       comment_text(machine_.name));
        fmt::format_to(std::back_inserter(out_),
                       "(process: track {:.3f} mm, layer {:.3f} mm, {:.2f} W, {:.2f} g/min)\n",
                       process_.track_width_mm, process_.layer_height_mm, process_.laser_power_w,
                       process_.powder_feed_g_min);
        out_ += "G21 G90 G94 G17\n";
        blocks(machine_.codes.program_start, process_.laser_power_off_w, 0.0, false);
        std::optional<std::pair<int, int>> layer;
        double power_w = 0.0;
        double powder_g_min = 0.0;
        for (const Move& m : program.moves) {
            if (m.layer >= 0 && layer != std::pair{m.layer, m.region}) {
                layer = std::pair{m.layer, m.region};
                fmt::format_to(std::back_inserter(out_), "(layer {} region {})\n", m.layer,
                               m.region);
            }
            switch (m.kind) {
                case MoveKind::kTravel:
                    append_move(out_, m);
                    out_ += '\n';
                    break;
                case MoveKind::kDeposit:
                    // LinuxCNC has no power column: a change within a wire re-sends the blocks
                    // that carry the value.
                    if (m.powder_g_min != powder_g_min) {
                        blocks(machine_.codes.powder_on, m.laser_w, m.powder_g_min, true);
                    }
                    if (m.laser_w != power_w) {
                        blocks(machine_.codes.laser_on, m.laser_w, m.powder_g_min, true);
                    }
                    power_w = m.laser_w;
                    powder_g_min = m.powder_g_min;
                    append_move(out_, m);
                    out_ += '\n';
                    break;
                case MoveKind::kLaserOn:
                    blocks(machine_.codes.powder_on, m.laser_w, m.powder_g_min, false);
                    blocks(machine_.codes.laser_on, m.laser_w, m.powder_g_min, false);
                    power_w = m.laser_w;
                    powder_g_min = m.powder_g_min;
                    if (m.dwell_ms > 0.0) {
                        out_ += "G4 P";  // LinuxCNC's P is in seconds
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
        out_ += "M2\n";
        return std::move(out_);
    }

private:
    void blocks(const CodeTemplate& t, double power_w, double powder_g_min, bool only_with_values) {
        for (const auto& b : t.blocks) {
            if (only_with_values && !has_placeholder(b)) continue;
            out_ += expand_block(b, power_w, powder_g_min, machine_.laser_power_max_w);
            out_ += '\n';
        }
    }

    const MachineProfile& machine_;
    const ProcessProfile& process_;
    std::string out_;
};

}  // namespace

core::Result<std::string> write_program(const Program& program, const MachineProfile& machine,
                                        const ProcessProfile& process) {
    const std::string context = "machine " + machine.name;
    if (auto ok = validate(machine); !ok) {
        return std::unexpected(core::with_context(ok.error(), context));
    }
    // The writers emit X Y Z only: a table-tilt machine needs rotary words and the moves
    // turned into machine axes, which come with the 5-axis dialects (issue 6).
    if (is_table_tilt(machine.kinematics)) {
        return core::fail(core::ErrorCode::kUnsupported,
                          fmt::format("kinematics \"{}\": 5-axis programs are not written yet "
                                      "(the program writers are 3-axis, kinematics \"xyz\")",
                                      kinematics_name(machine.kinematics)),
                          context);
    }
    if (auto ok = validate(process); !ok) {
        return std::unexpected(core::with_context(ok.error(), context));
    }
    if (auto ok = check_compatible(machine, process); !ok) {
        return std::unexpected(core::with_context(ok.error(), context));
    }
    if (auto ok = check_program(program, machine, process); !ok) {
        return std::unexpected(ok.error());
    }
    switch (machine.dialect) {
        case Dialect::kGm: return GmWriter(machine, process).write(program);
        case Dialect::kLinuxCnc: return LinuxCncWriter(machine, process).write(program);
    }
    return core::fail(core::ErrorCode::kInternal, "unknown dialect", context);
}

}  // namespace maxslice::machine
