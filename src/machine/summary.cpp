#include "maxslice/machine/summary.hpp"

#include <fmt/format.h>

#include <cmath>
#include <set>

namespace maxslice::machine {

core::Result<ProgramSummary> summarize(const Program& program, const ProcessProfile& process) {
    ProgramSummary s;
    s.move_count = program.moves.size();
    std::set<int> layers;
    bool positioned = false;
    core::Vec3d current{};
    for (std::size_t i = 0; i < program.moves.size(); ++i) {
        const Move& m = program.moves[i];
        if (!core::is_finite(m.position) || !std::isfinite(m.feed_mm_min) ||
            !std::isfinite(m.powder_g_min) || !std::isfinite(m.dwell_ms)) {
            return core::fail(core::ErrorCode::kInternal,
                              fmt::format("move {} (layer {}, region {}) holds a value that is "
                                          "not a finite number",
                                          i, m.layer, m.region),
                              "program summary");
        }
        if (m.layer >= 0) layers.insert(m.layer);
        switch (m.kind) {
            case MoveKind::kTravel:
            case MoveKind::kDeposit: {
                const double length = positioned ? core::norm(m.position - current) : 0.0;
                current = m.position;
                positioned = true;
                if (length == 0.0) break;
                if (!(m.feed_mm_min > 0.0)) {
                    return core::fail(core::ErrorCode::kInternal,
                                      fmt::format("move {} (layer {}, region {}) moves {:.3f} mm "
                                                  "at feed {} mm/min",
                                                  i, m.layer, m.region, length, m.feed_mm_min),
                                      "program summary");
                }
                const double seconds = length / m.feed_mm_min * 60.0;
                const double powder_g = m.powder_g_min * seconds / 60.0;
                s.powder_total_g += powder_g;
                if (m.kind == MoveKind::kDeposit) {
                    s.deposit_length_mm += length;
                    s.deposit_time_s += seconds;
                    s.powder_delivered_g += powder_g;
                } else {
                    s.travel_length_mm += length;
                    s.travel_time_s += seconds;
                }
                break;
            }
            case MoveKind::kLaserOn: {
                ++s.laser_on_count;
                const double seconds = m.dwell_ms / 1000.0;
                s.dwell_time_s += seconds;
                s.powder_total_g += m.powder_g_min * seconds / 60.0;
                break;
            }
            case MoveKind::kLaserOff: break;
        }
    }
    s.build_time_s = s.deposit_time_s + s.travel_time_s + s.dwell_time_s;
    s.layer_count = static_cast<int>(layers.size());
    if (process.powder_catch_efficiency) {
        s.deposited_mass_g = s.powder_delivered_g * *process.powder_catch_efficiency;
    }
    return s;
}

}  // namespace maxslice::machine
