#include "maxslice/machine/program_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace maxslice::machine {
namespace {

using core::ErrorCode;

/// A tool direction counts as +Z when it is within this angle (rad): a Cartesian machine
/// cannot tilt at all, so anything more is a planner bug or needs rotary axes.
constexpr double kVerticalToolToleranceRad = 1e-6;
/// A direction is a unit vector when its length is 1 within this.
constexpr double kUnitLengthTolerance = 1e-6;
/// Laser-on switches at the current position: its position may differ by this (mm).
constexpr double kSamePositionMm = 1e-6;

std::string where(std::size_t index, const Move& m) {
    return fmt::format("move {} (layer {}, region {})", index, m.layer, m.region);
}

std::string_view kind_name(MoveKind kind) {
    switch (kind) {
        case MoveKind::kTravel: return "travel";
        case MoveKind::kLaserOn: return "laser-on";
        case MoveKind::kDeposit: return "deposit";
        case MoveKind::kLaserOff: return "laser-off";
    }
    return "?";
}

core::Result<void> check_finite(std::size_t i, const Move& m) {
    const std::pair<std::string_view, double> values[] = {
        {"X", m.position.x},
        {"Y", m.position.y},
        {"Z", m.position.z},
        {"direction x", m.direction.x},
        {"direction y", m.direction.y},
        {"direction z", m.direction.z},
        {"feed", m.feed_mm_min},
        {"laser power", m.laser_w},
        {"powder feed", m.powder_g_min},
        {"dwell", m.dwell_ms},
    };
    for (const auto& [name, v] : values) {
        if (!std::isfinite(v)) {
            return core::fail(
                ErrorCode::kInternal,
                fmt::format("{}: {} = {} is not a finite number", where(i, m), name, v));
        }
    }
    return {};
}

}  // namespace

core::Result<void> check_program(const Program& program, const MachineProfile& machine,
                                 const ProcessProfile& process) {
    const std::string context = "machine " + machine.name;
    const auto fail = [&](ErrorCode code, std::string message) {
        return core::fail(code, std::move(message), context);
    };
    bool laser_on = false;
    bool positioned = false;
    core::Vec3d current{};
    for (std::size_t i = 0; i < program.moves.size(); ++i) {
        const Move& m = program.moves[i];
        if (auto ok = check_finite(i, m); !ok) {
            return std::unexpected(core::with_context(ok.error(), context));
        }

        if (std::abs(core::norm(m.direction) - 1.0) > kUnitLengthTolerance) {
            return fail(ErrorCode::kInternal,
                        fmt::format("{}: tool direction ({}, {}, {}) is not a unit vector",
                                    where(i, m), m.direction.x, m.direction.y, m.direction.z));
        }
        // Table machines take any unit direction: whether the inverse exists within the limits,
        // and the limits of every machine pose (the inserted re-orientation steps too), is
        // what to_machine_moves checks.
        if (machine.kinematics == Kinematics::kXyz) {
            const double angle =
                std::acos(std::clamp(m.direction.z / core::norm(m.direction), -1.0, 1.0));
            if (angle > kVerticalToolToleranceRad) {
                return fail(ErrorCode::kInvalidInput,
                            fmt::format("{}: tool direction ({:.6f}, {:.6f}, {:.6f}) is tilted "
                                        "{:.4f} deg from +Z; kinematics \"xyz\" cannot tilt "
                                        "(rotary tables come later)",
                                        where(i, m), m.direction.x, m.direction.y, m.direction.z,
                                        angle * 180.0 / std::numbers::pi));
            }
            for (std::size_t a = 0; a < machine.axes.size() && a < 3; ++a) {
                const AxisLimits& axis = machine.axes[a];
                const double v = m.position[static_cast<int>(a)];
                if (v < axis.min || v > axis.max) {
                    return fail(
                        ErrorCode::kInvalidInput,
                        fmt::format("{}: {} = {:.3f} mm is outside the machine's {} "
                                    "limits [{:.3f}, {:.3f}] mm",
                                    where(i, m), axis.name, v, axis.name, axis.min, axis.max));
                }
            }
        }

        const bool moves_axes = m.kind == MoveKind::kTravel || m.kind == MoveKind::kDeposit;
        if (moves_axes &&
            (m.feed_mm_min < machine.feed_min_mm_min || m.feed_mm_min > machine.feed_max_mm_min)) {
            return fail(ErrorCode::kInvalidInput,
                        fmt::format("{}: {} feed F = {} mm/min is outside the machine's feed "
                                    "range [{}, {}] mm/min",
                                    where(i, m), kind_name(m.kind), m.feed_mm_min,
                                    machine.feed_min_mm_min, machine.feed_max_mm_min));
        }
        if (m.laser_w != 0.0 &&
            (m.laser_w < machine.laser_power_min_w || m.laser_w > machine.laser_power_max_w)) {
            return fail(ErrorCode::kInvalidInput,
                        fmt::format("{}: laser power {} W is outside the machine's power range "
                                    "[{}, {}] W (or 0)",
                                    where(i, m), m.laser_w, machine.laser_power_min_w,
                                    machine.laser_power_max_w));
        }
        if (m.powder_g_min < 0.0 || m.powder_g_min > machine.powder_feed_max_g_min) {
            return fail(ErrorCode::kInvalidInput,
                        fmt::format("{}: powder feed {} g/min is outside the machine's range "
                                    "[0, {}] g/min",
                                    where(i, m), m.powder_g_min, machine.powder_feed_max_g_min));
        }
        if (m.dwell_ms < 0.0) {
            return fail(ErrorCode::kInternal,
                        fmt::format("{}: dwell {} ms is negative", where(i, m), m.dwell_ms));
        }

        const bool powered = m.laser_w > process.laser_power_off_w;
        switch (m.kind) {
            case MoveKind::kTravel:
                if (laser_on) {
                    return fail(ErrorCode::kInternal,
                                fmt::format("{}: travel move while the laser is on (no laser-off "
                                            "before it)",
                                            where(i, m)));
                }
                if (powered) {
                    return fail(ErrorCode::kInternal,
                                fmt::format("{}: travel move with the laser at {} W (the "
                                            "process's off power is {} W)",
                                            where(i, m), m.laser_w, process.laser_power_off_w));
                }
                break;
            case MoveKind::kLaserOn:
                if (laser_on) {
                    return fail(
                        ErrorCode::kInternal,
                        fmt::format("{}: laser-on while the laser is already on", where(i, m)));
                }
                if (!positioned) {
                    return fail(ErrorCode::kInternal,
                                fmt::format("{}: laser-on before any move has positioned the "
                                            "head",
                                            where(i, m)));
                }
                if (core::norm(m.position - current) > kSamePositionMm) {
                    return fail(ErrorCode::kInternal,
                                fmt::format("{}: laser-on at ({:.3f}, {:.3f}, {:.3f}) but the "
                                            "head is at ({:.3f}, {:.3f}, {:.3f})",
                                            where(i, m), m.position.x, m.position.y, m.position.z,
                                            current.x, current.y, current.z));
                }
                if (!powered) {
                    return fail(ErrorCode::kInternal,
                                fmt::format("{}: laser-on with {} W, not above the process's off "
                                            "power {} W",
                                            where(i, m), m.laser_w, process.laser_power_off_w));
                }
                laser_on = true;
                break;
            case MoveKind::kDeposit:
                if (!laser_on) {
                    return fail(ErrorCode::kInternal,
                                fmt::format("{}: deposit move while the laser is off (no "
                                            "laser-on before it)",
                                            where(i, m)));
                }
                if (!powered) {
                    return fail(ErrorCode::kInternal,
                                fmt::format("{}: deposit move with {} W, not above the process's "
                                            "off power {} W",
                                            where(i, m), m.laser_w, process.laser_power_off_w));
                }
                break;
            case MoveKind::kLaserOff:
                if (!laser_on) {
                    return fail(ErrorCode::kInternal,
                                fmt::format("{}: laser-off while the laser is off", where(i, m)));
                }
                if (core::norm(m.position - current) > kSamePositionMm) {
                    return fail(ErrorCode::kInternal,
                                fmt::format("{}: laser-off at ({:.3f}, {:.3f}, {:.3f}) but the "
                                            "head is at ({:.3f}, {:.3f}, {:.3f})",
                                            where(i, m), m.position.x, m.position.y, m.position.z,
                                            current.x, current.y, current.z));
                }
                if (powered) {
                    return fail(ErrorCode::kInternal,
                                fmt::format("{}: laser-off with {} W, above the process's off "
                                            "power {} W",
                                            where(i, m), m.laser_w, process.laser_power_off_w));
                }
                laser_on = false;
                break;
        }
        if (moves_axes) {
            current = m.position;
            positioned = true;
        }
    }
    if (laser_on) {
        return fail(ErrorCode::kInternal, "the program ends with the laser on");
    }
    return {};
}

}  // namespace maxslice::machine
