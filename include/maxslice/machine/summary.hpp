#pragma once

#include <cstddef>
#include <optional>

#include "maxslice/core/result.hpp"
#include "maxslice/machine/profile.hpp"
#include "maxslice/machine/program.hpp"

namespace maxslice::machine {

/// What a program does, for reports. Time model: every travel and deposit move runs its
/// straight length at its own feed (no acceleration, no controller look-ahead), plus the
/// laser-on dwells; switching codes take no time. The first move starts where the head is,
/// which the program does not know, so it adds no length. A lower bound on the real time.
struct ProgramSummary {
    double deposit_length_mm = 0.0;  ///< laser-on path length
    double travel_length_mm = 0.0;   ///< idle path length (laser off)
    double deposit_time_s = 0.0;
    double travel_time_s = 0.0;
    double dwell_time_s = 0.0;  ///< laser-on dwells (powder settling)
    double build_time_s = 0.0;  ///< deposit + travel + dwell
    /// Powder delivered while depositing: powder feed x deposition time, in g. This is powder
    /// that leaves the nozzle, not metal in the part: see deposited_mass_g.
    double powder_delivered_g = 0.0;
    /// All powder through the nozzle, including dwells and travel with the powder on, in g.
    double powder_total_g = 0.0;
    /// powder_delivered_g x the process's powder_catch_efficiency; unset when the profile
    /// does not give one.
    std::optional<double> deposited_mass_g;
    int layer_count = 0;     ///< distinct layer indices (>= 0) among the moves
    int laser_on_count = 0;  ///< laser-on events (one per deposited wire)
    std::size_t move_count = 0;
};

/// Sums a program up. Errors (kInternal): a non-finite value, or a move with length and no
/// positive feed.
[[nodiscard]] core::Result<ProgramSummary> summarize(const Program& program,
                                                     const ProcessProfile& process);

}  // namespace maxslice::machine
