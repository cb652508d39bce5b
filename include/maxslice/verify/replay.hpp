#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "maxslice/core/result.hpp"
#include "maxslice/core/vec3.hpp"
#include "maxslice/machine/kinematics.hpp"
#include "maxslice/machine/profile.hpp"

namespace maxslice::verify {

/// The program dialects the verifier reads (docs/program-dialects.md, docs/profiles.md).
enum class ProgramDialect {
    kGm,        ///< power and powder columns, then one block; G4 P in ms
    kLinuxCnc,  ///< RS-274 (LinuxCNC 2.9); `( )` and `;` comments; G4 P in s
    kFanuc,     ///< `%`, `O` number, `( )` comments, G43.4 H1 / G49 tool centre point (G43 H1:
                ///< tool length only, X Y Z stay the tip); G4 X in s
    kSiemens,   ///< `;` comments, G71, TRAORI / TRAFOOF tool centre point; G4 F in s
};

/// "gm", "linuxcnc", "fanuc", "siemens".
[[nodiscard]] std::string_view dialect_name(ProgramDialect dialect);

/// The dialect of a name as above; kInvalidInput for any other name.
[[nodiscard]] core::Result<ProgramDialect> parse_dialect(std::string_view name);

/// The dialect a machine profile names (through machine::dialect_name, so profile dialects
/// added later are read by name).
[[nodiscard]] core::Result<ProgramDialect> dialect_of(const machine::MachineProfile& machine);

/// One replayed block that moves or waits.
struct ReplayBlock {
    enum class Kind {
        kMove,   ///< G0 / G1 positioning
        kDwell,  ///< G4
    };
    Kind kind = Kind::kMove;
    int line = 0;               ///< 1-based line number in the program text
    bool rapid = false;         ///< G0 (timed at the machine's feed_max_mm_min)
    bool tcp = false;           ///< written under tool centre point control (X Y Z = pivot + tip)
    bool pose_known = false;    ///< every axis of the machine has been programmed by now
    machine::MachinePose from;  ///< machine pose at the start of the block
    machine::MachinePose pose;  ///< machine pose at the end (program X Y Z, A|B, C)
    core::Vec3d tip_mm;         ///< part-frame tool tip at the end (MachineKinematics::forward)
    core::Vec3d direction;      ///< part-frame build direction at the end (unit)
    double feed_mm_min = 0.0;   ///< modal feed (mm/min; deg/min for a rotary-only block)
    bool laser_on = false;      ///< the laser is on during this block (a move with it on deposits)
    double dwell_s = 0.0;       ///< kDwell: seconds
};

/// A fault the replay found in the program's values or its end: how many lines have it and the
/// first one.
struct ReplayFault {
    std::size_t count = 0;
    int line = 0;        ///< 1-based line of the first one
    core::Vec3d tip_mm;  ///< part-frame tool tip there
    std::string detail;  ///< what was found, for a person (program bytes escaped and cut)
};

/// A parsed program: its blocks that move or wait, in order.
struct Replay {
    ProgramDialect dialect = ProgramDialect::kGm;
    int line_count = 0;               ///< lines in the text
    int laser_on_count = 0;           ///< off -> on switches
    std::vector<ReplayBlock> blocks;  ///< moves and dwells only
    /// The distinct laser powers (W) the program deposits with, in order of first appearance:
    /// gm's power column where it is above the off power, else the value of a laser_on
    /// template's {power} or {power_pct}. Empty when the program names none; after 16
    /// distinct ones, a NaN stands for the rest.
    std::vector<double> laser_powers_w;
    /// Lines that set a laser power, a powder feed or a G1 feed outside the machine's ranges:
    /// a power below 0 or above machine.laser_power_max_w, or one that switches the laser on
    /// below laser_power_min_w; a powder feed below 0 or above powder_feed_max_g_min; the feed
    /// of a G1 block outside [feed_min_mm_min, feed_max_mm_min] (deg/min for a rotary-only
    /// block, as the controller reads F). Values within the written rounding pass.
    ReplayFault out_of_range;
    bool end_code = false;  ///< M2 or M30 was read (lines after it are not)
    /// The text does not end with a line break and no end code came before its last line: the
    /// program was cut off in the middle of a line (that line, when it does not parse, is not
    /// read).
    bool cut = false;
    bool laser_on_at_end = false;   ///< the laser is on after the last line read
    bool powder_on_at_end = false;  ///< the powder is on after the last line read
    int last_line = 0;              ///< the last line read (the end code's, else the last one)
    core::Vec3d end_tip_mm;         ///< part-frame tool tip after the last line read
};

/// Which of the profile's processes made a program, by the laser powers it deposits with:
/// 0 for the main process ([process]), N for its finer process N ([[process.finer]], decision
/// 0019), -1 when the program names no power or a power no single process has. A process
/// matches when every power is its laser_power_w within half a watt (programs round it); the
/// first matching process counts (the main one before the finer ones).
[[nodiscard]] int process_of(const Replay& replay, const machine::Profiles& profiles);

/// The linear axes (machine X, Y, Z) that put the part-frame `tip` under the tool with the
/// rotary values of `pose`, from the forward kinematics alone: forward is affine in X Y Z for
/// fixed rotary values, tip = M p + t0 with M a rotation, so p = M^T (tip - t0). Used for
/// blocks written under tool centre point control.
[[nodiscard]] core::Vec3d linear_axes_for_tip(const machine::MachineKinematics& kinematics,
                                              const core::Vec3d& tip, machine::MachinePose pose);

/// Parses a program of `dialect` for the machine and process of `profiles` and replays it
/// through machine::MachineKinematics::forward (docs/program-dialects.md). Axis words are modal
/// (an axis not yet programmed counts as 0, as LinuxCNC's interpreter does, and the block is
/// marked pose_known = false). The laser is on: gm, when a line's power column exceeds
/// process.laser_power_off_w; other dialects, after a line matching a block of the profile's
/// `[machine.codes]` laser_on template (placeholders stand for numbers; a `{power}` at or below
/// the off power counts as off) until one matching laser_off; powder likewise (gm's powder
/// column above 0, or the powder_on / powder_off templates, a `{powder}` of 0 counting as
/// off). Literal template blocks win over ones with placeholders. A line that matches a
/// template is a switch and nothing else: the profile's templates hold no motion
/// (machine::motion_word; the profiles are validated first, decision 0022), and a template
/// block with other words on its line is an unknown code. Errors
/// (kInvalidInput, kUnsupported for G20, G91, G93 ...), with context "line N": malformed numbers,
/// unknown words or codes, axis words the machine lacks, a motion block before any G0 / G1, tool
/// centre point words in a joint-space dialect. The program's bytes quoted in a message are escaped
/// and cut (core::printable). Out-of-range values and the end of the program are not errors: they
/// are noted in the Replay.
[[nodiscard]] core::Result<Replay> replay_program(std::string_view program_text,
                                                  const machine::Profiles& profiles,
                                                  ProgramDialect dialect);

}  // namespace maxslice::verify
