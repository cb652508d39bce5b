#include "maxslice/machine/machine_moves.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>

namespace maxslice::machine {
namespace {

using core::ErrorCode;
using core::Vec3d;

// Two directions this close (rad, as unit vectors) are the same build direction: the move
// keeps the previous rotary values exactly instead of a fresh inverse, so one layer (which the
// planner gives one direction) never shows rotary noise. Far below the 1e-3 deg the
// controller sees.
constexpr double kSameDirectionRad = 1e-9;
// Rotary values this close (deg) are unchanged: no re-orientation (as in kinematics.cpp).
constexpr double kSameAngleDeg = 1e-9;
// "xyz" cannot tilt: the same tolerance as check_program (rad).
constexpr double kXyzVerticalRad = 1e-6;

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

std::string where(std::size_t index, const Move& m) {
    return fmt::format("move {} (layer {}, region {})", index, m.layer, m.region);
}

bool same_direction(const Vec3d& a, const Vec3d& b) {
    const double la = core::norm(a), lb = core::norm(b);
    return la > 0.0 && lb > 0.0 && core::norm(a / la - b / lb) <= kSameDirectionRad;
}

bool same_rotary(const MachinePose& a, const MachinePose& b) {
    return std::abs(a.a_or_b_deg - b.a_or_b_deg) <= kSameAngleDeg &&
           std::abs(a.c_deg - b.c_deg) <= kSameAngleDeg;
}

std::string direction_text(const Vec3d& d) {
    return fmt::format("({:.6f}, {:.6f}, {:.6f})", d.x, d.y, d.z);
}

}  // namespace

double clear_height_mm(const MachineProfile& machine, std::span<const Vec3d> part_points) {
    if (!is_table_tilt(machine.kinematics) || !machine.table) {
        double top = -std::numeric_limits<double>::infinity();
        for (const Vec3d& q : part_points) top = std::max(top, q.z);
        return top;
    }
    // A part point q sits at pivot + R_tilt (o + R_C (q - o)); rotations keep lengths, so its
    // distance from the pivot is at most |o| + |q - o| whatever A/B and C are.
    const TableProfile& t = *machine.table;
    const Vec3d o{t.c_offset_x_mm, t.c_offset_y_mm, 0.0};
    double radius = 0.0;
    for (const Vec3d& q : part_points) radius = std::max(radius, core::norm(q - o));
    return t.pivot_mm.z + core::norm(o) + radius;
}

core::Result<std::vector<MachineMove>> to_machine_moves(const Program& program,
                                                        const MachineKinematics& kinematics,
                                                        double clear_z_mm) {
    const bool table = is_table_tilt(kinematics.kinematics());
    std::vector<MachineMove> out;
    out.reserve(program.moves.size() + (table ? 16 : 0));
    MachinePose current{};  // rotary zero: where the first inverse starts from
    Vec3d current_direction{};
    bool positioned = false;
    bool laser_on = false;
    for (std::size_t i = 0; i < program.moves.size(); ++i) {
        const Move& m = program.moves[i];
        const auto fail = [&](const std::string& what) {
            return core::fail(ErrorCode::kInvalidInput, fmt::format("{}: {}", where(i, m), what));
        };
        if (m.kind == MoveKind::kLaserOn || m.kind == MoveKind::kLaserOff) {
            laser_on = m.kind == MoveKind::kLaserOn;
            out.push_back({current, m, ReorientStep::kNone, i});
            continue;
        }

        MachinePose pose;
        std::string out_of_reach;  // why the previous rotary values do not reach this tip
        if (!table) {
            const double length = core::norm(m.direction);
            const double tilt =
                length > 0.0 ? std::atan2(std::hypot(m.direction.x, m.direction.y), m.direction.z)
                             : std::numbers::pi;
            if (!(tilt <= kXyzVerticalRad)) {
                return fail(
                    fmt::format("tool direction {} is tilted {:.4f} deg from +Z; "
                                "kinematics \"xyz\" cannot tilt",
                                direction_text(m.direction), tilt * kDegPerRad));
            }
            pose = {m.position.x, m.position.y, m.position.z, 0.0, 0.0};
            if (auto ok = kinematics.check_limits(pose); !ok) return fail(ok.error().message);
        } else {
            // The same direction keeps the rotary values exactly, as long as the tip stays
            // within reach with them; otherwise the inverse looks for a pose (perhaps the other
            // solution, which needs a turn).
            const bool same = positioned && same_direction(m.direction, current_direction);
            std::optional<MachinePose> kept;
            if (same) {
                const MachinePose p =
                    kinematics.pose_at(m.position, current.a_or_b_deg, current.c_deg);
                if (auto ok = kinematics.check_limits(p); ok) {
                    kept = p;
                } else {
                    out_of_reach = ok.error().message;
                }
            }
            if (kept) {
                pose = *kept;
            } else {
                const auto solved = kinematics.inverse(m.position, m.direction, current);
                if (!solved) return fail(solved.error().message);
                pose = *solved;
                // The same rotary values within rounding: keep them exactly.
                if (positioned && same_rotary(pose, current)) {
                    const MachinePose p =
                        kinematics.pose_at(m.position, current.a_or_b_deg, current.c_deg);
                    if (kinematics.check_limits(p)) pose = p;
                }
            }
        }

        const bool turns = table && (!positioned || !same_rotary(pose, current));
        if (turns && (m.kind == MoveKind::kDeposit || laser_on) && !out_of_reach.empty()) {
            return fail(fmt::format(
                "the table would have to turn within a deposited wire: with the wire's rotary "
                "values ({} {:.3f} deg, C {:.3f} deg) the tip ({:.3f}, {:.3f}, {:.3f}) mm is out "
                "of reach ({})",
                kinematics.kinematics() == Kinematics::kTableBc ? "B" : "A", current.a_or_b_deg,
                current.c_deg, m.position.x, m.position.y, m.position.z, out_of_reach));
        }
        if (turns && (m.kind == MoveKind::kDeposit || laser_on)) {
            return fail(fmt::format(
                "the build direction changes within a deposited wire (from {} to {}: {} "
                "{:.3f} -> {:.3f} deg, C {:.3f} -> {:.3f} deg); the table turns only with the "
                "laser off, between wires",
                positioned ? direction_text(current_direction) : std::string("rotary zero"),
                direction_text(m.direction),
                kinematics.kinematics() == Kinematics::kTableBc ? "B" : "A", current.a_or_b_deg,
                pose.a_or_b_deg, current.c_deg, pose.c_deg));
        }
        if (turns) {
            Move step_move = m;
            step_move.kind = MoveKind::kTravel;
            std::vector<std::pair<MachinePose, ReorientStep>> steps;
            if (!positioned) {
                // Nothing is known about the head at the start: straight up first, then turn
                // from rotary zero and cross (docs/program-dialects.md).
                const auto z_safe = kinematics.safe_height(pose.z, pose.z, clear_z_mm);
                if (!z_safe) return fail(z_safe.error().message);
                steps = {
                    {{pose.x, pose.y, *z_safe, 0.0, 0.0}, ReorientStep::kStartRetract},
                    {{pose.x, pose.y, *z_safe, pose.a_or_b_deg, pose.c_deg},
                     ReorientStep::kStartTurn},
                    {{pose.x, pose.y, *z_safe, pose.a_or_b_deg, pose.c_deg}, ReorientStep::kCross}};
            } else {
                const auto path = kinematics.reorientation(current, pose, clear_z_mm);
                if (!path) return fail(path.error().message);
                // Retract, (aside,) turn, cross.
                for (std::size_t s = 0; s < path->size(); ++s) {
                    const ReorientStep role = s == 0                  ? ReorientStep::kRetract
                                              : s + 2 == path->size() ? ReorientStep::kTurn
                                              : s + 1 == path->size() ? ReorientStep::kCross
                                                                      : ReorientStep::kAside;
                    steps.emplace_back((*path)[s], role);
                }
            }
            for (const auto& [step_pose, role] : steps) {
                if (auto ok = kinematics.check_limits(step_pose); !ok) {
                    return fail("the re-orientation before this move: " + ok.error().message);
                }
                out.push_back({step_pose, step_move, role, i});
            }
        }
        out.push_back({pose, m, ReorientStep::kNone, i});
        current = pose;
        current_direction = m.direction;
        positioned = true;
    }
    return out;
}

}  // namespace maxslice::machine
