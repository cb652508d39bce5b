#pragma once

#include <string>

#include "maxslice/core/result.hpp"
#include "maxslice/machine/profile.hpp"
#include "maxslice/machine/program.hpp"

namespace maxslice::machine {

/// Writes a program as text in the machine profile's dialect (docs/profiles.md,
/// docs/decisions/0005). Lines end in '\n'; numbers have fixed decimals (3 for mm, 1 for
/// feeds, 2 for power and powder), so the same program gives the same bytes on any machine.
/// - `gm`: every line starts with the laser power (W) and powder feed (g/min) columns
///   ("700.00 8.00"), then one block: G21, G90, the codes' laser/powder blocks around each
///   deposited wire (M8 / M9 in the reference profile), `G4 P<ms>` after laser-on, and
///   `G1 X Y Z F` for every move (travel too, at its own feed).
/// - `linuxcnc`: RS-274 for LinuxCNC: G21 G90 G94 G17, a comment on each layer change,
///   laser and powder through the profile's codes, `G4 P<seconds>`, `G1` at the travel feed
///   for idle moves, M2 at the end.
/// Before writing, the profiles are validated and check_program() runs: any violation
/// returns its error and no text.
[[nodiscard]] core::Result<std::string> write_program(const Program& program,
                                                      const MachineProfile& machine,
                                                      const ProcessProfile& process);

}  // namespace maxslice::machine
