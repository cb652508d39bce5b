#pragma once

#include <optional>
#include <string>
#include <vector>

#include "maxslice/core/vec3.hpp"

namespace maxslice::machine {

/// What a move does.
enum class MoveKind {
    kTravel,    ///< feed move with the laser off (written as G1 at its feed, never a rapid)
    kLaserOn,   ///< switch laser and powder on at the current position, then dwell
    kDeposit,   ///< feed move with the laser on, depositing a bead
    kLaserOff,  ///< switch laser and powder off at the current position
};

/// One step of a program, in part coordinates (mm), with the tool direction (unit vector
/// from the melt pool towards the head; +Z for a planar build).
struct Move {
    MoveKind kind = MoveKind::kTravel;
    core::Vec3d position{};
    core::Vec3d direction{0.0, 0.0, 1.0};
    double feed_mm_min = 0.0;   ///< kTravel, kDeposit
    double laser_w = 0.0;       ///< power while this move runs
    double powder_g_min = 0.0;  ///< powder feed while this move runs
    double dwell_ms = 0.0;      ///< kLaserOn: wait for the powder stream to settle
    int layer = -1;             ///< 0-based layer index, -1 outside layers
    int region = 0;             ///< region (build direction) the layer belongs to
};

/// A deposition program before it is written in a dialect.
struct Program {
    std::string part_name;
    /// The part file's direction built upwards (the base the job stood it on); written in
    /// the header of the dialects with comments, where `maxslice verify` reads it.
    std::optional<core::Vec3d> base_direction;
    std::vector<Move> moves;
};

}  // namespace maxslice::machine
