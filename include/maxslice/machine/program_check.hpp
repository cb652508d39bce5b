#pragma once

#include "maxslice/core/result.hpp"
#include "maxslice/machine/profile.hpp"
#include "maxslice/machine/program.hpp"

namespace maxslice::machine {

/// The checks every emitted move passes before any text is written, in every build type
/// (they are not assertions and never clamp):
/// - finite numbers only (position, direction, feed, power, powder, dwell);
/// - the tool direction is a unit vector, +Z for `xyz`;
/// - for `xyz`, each axis within the machine profile's limits (table machines: the axis limits
///   apply to machine poses, which to_machine_moves() computes and checks);
/// - feeds of travel and deposit moves within the machine's feed range;
/// - laser power 0 or within the machine's power range, powder within [0, max];
/// - sequence: deposit moves only between a laser-on and a laser-off, travel moves with the
///   laser at no more than the process's off power, laser-on at the current position (after
///   a first positioning move), the laser off at the end.
/// Errors name the move index, its layer and region, and the value: kInvalidInput when the
/// program does not fit the machine (a limit), kInternal when the program itself is broken
/// (NaN, sequence). Context: "machine NAME".
[[nodiscard]] core::Result<void> check_program(const Program& program,
                                               const MachineProfile& machine,
                                               const ProcessProfile& process);

}  // namespace maxslice::machine
