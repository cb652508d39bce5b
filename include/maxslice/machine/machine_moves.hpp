#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "maxslice/core/result.hpp"
#include "maxslice/core/vec3.hpp"
#include "maxslice/machine/kinematics.hpp"
#include "maxslice/machine/profile.hpp"
#include "maxslice/machine/program.hpp"

namespace maxslice::machine {

/// What a machine move is: a move of the part-frame program, or a step the conversion inserts
/// to turn the table safely (docs/program-dialects.md, "Re-orientation sequence").
enum class ReorientStep {
    kNone,          ///< a move of the part-frame program (the approach after a sequence too)
    kStartRetract,  ///< program start: up to z_safe; only Z is known (and written)
    kStartTurn,     ///< program start: the rotary axes to the first pose at z_safe; X, Y unknown
    kRetract,       ///< up the tool axis to z_safe: X, Y and the rotary axes unchanged
    /// across the tilt axis at z_safe, where turning over the retract would sweep the head
    /// below the plate's level (MachineKinematics::reorientation): the rotary axes unchanged
    kAside,
    kTurn,   ///< the rotary axes turn at z_safe: X, Y, Z unchanged
    kCross,  ///< across at z_safe to X, Y of the target: the rotary axes unchanged
};

/// One move in machine coordinates, as every dialect writes it.
struct MachineMove {
    /// The axis values after this move (joint space). For kStartRetract and kStartTurn, X and
    /// Y are those of the sequence's target (the head's are unknown and not written), and the
    /// rotary axes of kStartRetract are 0 (not written either).
    MachinePose pose;
    /// The program move this one comes from: kind, feed, power, powder, dwell, layer, region
    /// and the part-frame tip and direction. Inserted steps carry a kTravel copy of their
    /// target (the move that follows the sequence): its feed, power, powder, layer and region,
    /// and its part-frame tip and direction, which are not where the inserted step is.
    Move move;
    ReorientStep step = ReorientStep::kNone;
    std::size_t source = 0;  ///< index of that program move

    [[nodiscard]] bool inserted() const { return step != ReorientStep::kNone; }
};

/// The height the tool tip must reach for the table to turn freely with the part below it,
/// mm (machine Z): for a table machine the top of the sphere about the C axis point
/// o = (c_offset, 0) that holds every part point q in any table position,
/// pivot.z + |o| + max |q - o|; for "xyz" the part's top, max q.z. `part_points` are in part
/// coordinates (the placed mesh's vertices, or a program's positions). No points:
/// pivot.z + |o| for a table machine, -infinity for "xyz". The profile is assumed valid. The
/// plate and a substrate under it lie below the part: MachineKinematics::reorientation keeps
/// the head above the plate's level while the table turns.
[[nodiscard]] double clear_height_mm(const MachineProfile& machine,
                                     std::span<const core::Vec3d> part_points);

/// The part-frame program in machine coordinates, the one conversion every writer uses
/// (docs/program-dialects.md). Each positioning move (travel, deposit) gets the inverse
/// kinematics of its tip and direction, the pose nearest the previous one (the first from
/// rotary zero); a move whose direction equals the previous one's (within 1e-9 rad) keeps its
/// rotary values exactly. Laser-on and laser-off keep the current pose. Before the first
/// positioning move, and wherever the rotary values change, the re-orientation sequence is
/// inserted: (start) retract to z_safe, turn, cross, then the target move comes down, with
/// z_safe = max(Z_from, Z_to, clear_z_mm) + retract_mm (Z_from unknown at the start).
/// Every pose is checked against the axis limits. For "xyz" the conversion is the identity
/// (every direction +Z) and inserts nothing.
/// Errors (kInvalidInput), naming the move index, layer and region: no inverse solution
/// within the limits; a rotary change needed on a deposit move or while the laser is on
/// ("the build direction changes within a deposited wire"); z_safe above the Z limit.
[[nodiscard]] core::Result<std::vector<MachineMove>> to_machine_moves(
    const Program& program, const MachineKinematics& kinematics, double clear_z_mm);

}  // namespace maxslice::machine
