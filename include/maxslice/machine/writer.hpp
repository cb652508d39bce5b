#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "maxslice/core/result.hpp"
#include "maxslice/machine/profile.hpp"
#include "maxslice/machine/program.hpp"

namespace maxslice::machine {

/// Options of write_program.
/// The header comment of the dialects with comments (linuxcnc, fanuc, siemens) that names the
/// part file's direction the program builds upwards, followed by "X,Y,Z" in shortest
/// round-trip digits (Program::base_direction); `maxslice verify` places the model by it. No
/// parentheses: they end a comment in the RS-274 dialects.
inline constexpr std::string_view kBaseDirectionTag = "part file direction built upwards ";

struct WriteOptions {
    /// The height the tool tip must clear for the table to turn with the part on it, mm
    /// (machine Z; clear_height_mm() of the placed part, docs/program-dialects.md). Unset: the
    /// writer computes it from the program's own part-frame positions. Not used for "xyz".
    std::optional<double> clear_z_mm;
};

/// Writes a program as text in the machine profile's dialect (docs/profiles.md "Dialects",
/// docs/program-dialects.md, docs/decisions/0005 and 0009). Lines end in '\n'; numbers have
/// fixed decimals (3 for mm and degrees, 1 for feeds, 2 for power and powder), never -0.000,
/// so the same program gives the same bytes on any machine.
/// - `gm`: every line starts with the laser power (W) and powder feed (g/min) columns
///   ("700.00 8.00"), then one block: G21, G90, the codes' laser/powder blocks around each
///   deposited wire (M8 / M9 in the reference profile), `G4 P<ms>` after laser-on, and
///   `G1 X Y Z F` for every move (travel too, at its own feed).
/// - `linuxcnc`: RS-274 for LinuxCNC: G21 G90 G94 G17, a comment on each layer change,
///   laser and powder through the profile's codes, `G4 P<seconds>`, `G1` at the travel feed
///   for idle moves, M2 at the end.
/// - `fanuc`: the same blocks framed by `%`, `O1000 (MAXSLICE)`, `G4 X<seconds>`, G49 M30 %;
///   X Y Z are the tool tip through `G43 H1` (tool length) outside tool centre point control.
/// - `siemens`: `;` comments, G71 G90 G94 G17, `G4 F<seconds>`, M30.
/// On a table-tilt machine every positioning block carries X Y Z A|B C F; the moves come from
/// to_machine_moves() (one conversion for all dialects) with the re-orientation sequences it
/// inserts. `gm` and `linuxcnc` write joint space; `fanuc` (G43.4 H1 / G49 G43 H1) and `siemens`
/// (TRAORI / TRAFOOF) write the program moves under tool centre point control, X Y Z =
/// pivot + part tip, and the re-orientation steps in joint space with the control off.
/// Before writing, the profiles are validated, check_program() runs and the conversion checks
/// every machine pose: any violation returns its error (context "machine NAME") and no text.
[[nodiscard]] core::Result<std::string> write_program(const Program& program,
                                                      const MachineProfile& machine,
                                                      const ProcessProfile& process,
                                                      const WriteOptions& options = {});

}  // namespace maxslice::machine
