#include "maxslice/machine/kinematics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "maxslice/core/revolution.hpp"

namespace maxslice::machine {
namespace {

using core::ErrorCode;
using core::Vec3d;

// A direction within this angle of the C axis is the singular pose: C is then free and stays
// where it was. Far below the 1e-6 rad the round trip promises, and above the rounding of a
// normalised vector (1e-16).
constexpr double kSingularTiltRad = 1e-9;
// An axis value this close outside a limit is rounding, not a violation: it is set onto the
// limit (degrees for rotary axes, mm for linear ones).
constexpr double kLimitTolerance = 1e-9;
// "xyz" cannot tilt: a direction further from +Z than this is refused.
constexpr double kXyzTiltToleranceRad = 1e-9;
// Two solutions whose weighted distances differ by less than this (deg) are a tie; the one
// with the positive tilt wins, so the choice does not depend on rounding.
constexpr double kTieDeg = 1e-9;
// Rotary values this close count as unchanged for a re-orientation (deg).
constexpr double kSameAngleDeg = 1e-9;

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
// Tilts sampled along a turn of the table when its head is kept above the plate's level.
constexpr int kTurnSamples = 32;
// The turn keeps the head this much above its clearance at the sampled tilts: between two
// samples, and at the plate's edges the verifier models, the head comes a little closer.
constexpr double kTurnSlackMm = 0.5;
// A tilt whose plate normal moves the head's floor less than this per mm across the tilt axis
// (near no tilt) cannot be helped by moving across.
constexpr double kFlatSlope = 1e-9;

// v turned by angle about the X, Y or Z axis (right-hand rule).
Vec3d rotate_x(const Vec3d& v, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return {v.x, c * v.y - s * v.z, s * v.y + c * v.z};
}
Vec3d rotate_y(const Vec3d& v, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return {c * v.x + s * v.z, v.y, -s * v.x + c * v.z};
}
Vec3d rotate_z(const Vec3d& v, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return {c * v.x - s * v.y, s * v.x + c * v.y, v.z};
}

bool finite(const MachinePose& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) &&
           std::isfinite(p.a_or_b_deg) && std::isfinite(p.c_deg);
}

// The value + 360 k nearest `previous` within [lo, hi]; nullopt when no turn fits. The
// distance |value + 360 k - previous| is convex in k, so the better of the two ks around the
// unconstrained optimum, clamped to the feasible ks, is the constrained best. Half a turn
// either way is a tie: the less wound value (smaller |value + 360 k|) wins.
std::optional<double> unwind(double value, double previous, double lo, double hi) {
    const double kmin = std::ceil((lo - kLimitTolerance - value) / 360.0);
    const double kmax = std::floor((hi + kLimitTolerance - value) / 360.0);
    if (kmin > kmax) return std::nullopt;
    const double below = std::floor((previous - value) / 360.0);
    double best_k = 0.0;
    double best_distance = INFINITY;
    for (const double k : {std::clamp(below, kmin, kmax), std::clamp(below + 1.0, kmin, kmax)}) {
        const double v = value + 360.0 * k;
        const double distance = std::abs(v - previous);
        const bool tie = std::abs(distance - best_distance) <= kTieDeg;
        if ((!tie && distance < best_distance) ||
            (tie && std::abs(v) < std::abs(value + 360.0 * best_k))) {
            best_k = k;
            best_distance = distance;
        }
    }
    return std::clamp(value + 360.0 * best_k, lo, hi);
}

std::string vec_text(const Vec3d& v, int decimals) {
    return fmt::format("({:.{}f}, {:.{}f}, {:.{}f})", v.x, decimals, v.y, decimals, v.z, decimals);
}

}  // namespace

core::Result<MachineKinematics> MachineKinematics::create(const MachineProfile& machine) {
    if (auto ok = validate(machine); !ok) return std::unexpected(ok.error());
    MachineKinematics k;
    k.kinematics_ = machine.kinematics;
    for (std::size_t i = 0; i < machine.axes.size() && i < k.limits_.size(); ++i) {
        const AxisLimits& a = machine.axes[i];
        k.limits_[i] = {a.name, a.min, a.max};
    }
    if (!is_table_tilt(machine.kinematics)) {
        k.limits_[3] = {"A", 0.0, 0.0};
        k.limits_[4] = {"C", 0.0, 0.0};
        return k;
    }
    const TableProfile& t = *machine.table;  // validate() requires it
    k.pivot_mm_ = t.pivot_mm;
    k.c_offset_mm_ = {t.c_offset_x_mm, t.c_offset_y_mm, 0.0};
    k.tilt_sign_ = t.tilt_direction;
    k.c_sign_ = t.c_direction;
    k.retract_mm_ = t.retract_mm;
    const NozzleProfile n = machine.nozzle.value_or(NozzleProfile{});
    const double rim = n.cone_length_mm * std::tan(n.half_angle_deg / kDegPerRad);
    k.head_outline_ = {{0.0, 0.0}, {n.cone_length_mm, rim}};
    if (n.body_radius_mm > 0.0) {
        k.head_outline_.push_back({n.cone_length_mm, n.body_radius_mm});
        k.head_outline_.push_back({n.cone_length_mm + n.body_length_mm, n.body_radius_mm});
    }
    k.head_clearance_mm_ = n.clearance_mm;
    return k;
}

double MachineKinematics::head_floor_mm(const Vec3d& m, double tilt) const {
    // The part's +Z in the machine frame; a machine point's part height is its distance from
    // the pivot along it (C turns about a parallel axis through the plate's level).
    const Vec3d n = rotate({0.0, 0.0, 1.0}, tilt, 0.0);
    const double lowest = std::min(0.0, core::lowest_on_revolution(head_outline_, n.z));
    return core::dot(m - pivot_mm_, n) + lowest;
}

double MachineKinematics::tilt_rad(const MachinePose& pose) const {
    return kinematics_ == Kinematics::kXyz ? 0.0 : tilt_sign_ * pose.a_or_b_deg / kDegPerRad;
}

double MachineKinematics::c_rad(const MachinePose& pose) const {
    return kinematics_ == Kinematics::kXyz ? 0.0 : c_sign_ * pose.c_deg / kDegPerRad;
}

Vec3d MachineKinematics::rotate(const Vec3d& v, double tilt, double c) const {
    const Vec3d on_table = rotate_z(v, c);
    switch (kinematics_) {
        case Kinematics::kXyz: return v;
        case Kinematics::kTableAc: return rotate_x(on_table, tilt);
        case Kinematics::kTableBc: return rotate_y(on_table, tilt);
    }
    return v;
}

Vec3d MachineKinematics::unrotate(const Vec3d& v, double tilt, double c) const {
    switch (kinematics_) {
        case Kinematics::kXyz: return v;
        case Kinematics::kTableAc: return rotate_z(rotate_x(v, -tilt), -c);
        case Kinematics::kTableBc: return rotate_z(rotate_y(v, -tilt), -c);
    }
    return v;
}

ToolPose MachineKinematics::forward(const MachinePose& pose) const {
    // The machine point is m = pivot + R_tilt (o + R_C (q - o)), so
    // q = o + R_C^-1 (R_tilt^-1 (m - pivot) - o): undo the tilt about the pivot, then C about
    // its offset axis on the table.
    const double t = tilt_rad(pose), c = c_rad(pose);
    const Vec3d m{pose.x, pose.y, pose.z};
    const Vec3d on_tilt = unrotate(m - pivot_mm_, t, 0.0);
    const Vec3d q = c_offset_mm_ + unrotate(on_tilt - c_offset_mm_, 0.0, c);
    return {q, unrotate({0.0, 0.0, 1.0}, t, c)};
}

core::Result<void> MachineKinematics::check_limits(const MachinePose& pose) const {
    const std::array<double, 5> values{pose.x, pose.y, pose.z, pose.a_or_b_deg, pose.c_deg};
    const std::size_t count = kinematics_ == Kinematics::kXyz ? 3 : 5;
    for (std::size_t i = 0; i < values.size(); ++i) {
        const bool rotary = i >= 3;
        if (!std::isfinite(values[i])) {
            return core::fail(
                ErrorCode::kInvalidInput,
                fmt::format("{} = {} is not a finite number",
                            rotary && i >= count ? "rotary axis" : limits_[i].name, values[i]));
        }
        if (i >= count) {
            if (values[i] != 0.0) {
                return core::fail(ErrorCode::kInvalidInput,
                                  fmt::format("kinematics \"xyz\" has no rotary axes, but the "
                                              "pose turns one by {} deg",
                                              values[i]));
            }
            continue;
        }
        const Limits& l = limits_[i];
        if (values[i] < l.min - kLimitTolerance || values[i] > l.max + kLimitTolerance) {
            const char* unit = rotary ? "deg" : "mm";
            return core::fail(ErrorCode::kInvalidInput,
                              fmt::format("{} = {:.6f} {} is outside machine.axes.{} [{}, {}] {}",
                                          l.name, values[i], unit, l.name, l.min, l.max, unit));
        }
    }
    return {};
}

core::Result<MachinePose> MachineKinematics::inverse(const Vec3d& tip_mm, const Vec3d& direction,
                                                     const MachinePose& previous,
                                                     const PoseWeights& weights) const {
    const double length = core::norm(direction);
    if (!core::is_finite(tip_mm) || !core::is_finite(direction) || !(length > 0.0) ||
        !std::isfinite(length)) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("no pose for tip {} and direction {}: not finite or a zero "
                                      "direction",
                                      vec_text(tip_mm, 6), vec_text(direction, 6)));
    }
    if (!finite(previous)) {
        return core::fail(ErrorCode::kInvalidInput, "the previous pose is not finite");
    }
    const Vec3d d = direction / length;
    // The tilt angle between d and the C axis, accurate at both ends (unlike acos(d.z)).
    const double r = std::hypot(d.x, d.y);
    const double theta = std::atan2(r, d.z);

    if (kinematics_ == Kinematics::kXyz) {
        if (theta > kXyzTiltToleranceRad) {
            return core::fail(ErrorCode::kInvalidInput,
                              fmt::format("direction {} is {:.6f} deg from +Z; kinematics "
                                          "\"xyz\" cannot tilt",
                                          vec_text(d, 6), theta * kDegPerRad));
        }
        const MachinePose pose{tip_mm.x, tip_mm.y, tip_mm.z, 0.0, 0.0};
        if (auto ok = check_limits(pose); !ok) {
            return core::fail(
                ErrorCode::kInvalidInput,
                fmt::format("tip {} is out of reach: {}", vec_text(tip_mm, 3), ok.error().message));
        }
        return pose;
    }

    // R = R_tilt(t) R_C(c) must map d to +Z, i.e. R_C(c) d = R_tilt(-t) (0, 0, 1).
    // A/C: R_x(-t) z = (0, sin t, cos t): cos t = d.z, and C turns (d.x, d.y) (at angle phi)
    //   onto +Y when t > 0 (c = 90 deg - phi) or onto -Y when t < 0 (c = -90 deg - phi).
    // B/C: R_y(-t) z = (-sin t, 0, cos t): C turns (d.x, d.y) onto -X when t > 0
    //   (c = 180 deg - phi) or onto +X when t < 0 (c = -phi).
    // So the two solutions are (t, c) and (-t, c + 180 deg). Machine values divide out the
    // direction signs (s = +-1: A = s_t t).
    const bool singular = theta <= kSingularTiltRad || std::numbers::pi - theta <= kSingularTiltRad;
    const double phi = std::atan2(d.y, d.x);
    const double c_pos =
        kinematics_ == Kinematics::kTableAc ? std::numbers::pi / 2.0 - phi : std::numbers::pi - phi;
    struct Candidate {
        double tilt_rad;
        double c_deg;  // machine C before unwinding
    };
    std::vector<Candidate> candidates;
    if (singular) {
        // Along the C axis C does nothing: keep it (no needless turn). Tilt 0 or +-180 deg.
        const double t = theta <= kSingularTiltRad ? 0.0 : std::numbers::pi;
        candidates.push_back({t, previous.c_deg});
        if (t != 0.0) candidates.push_back({-t, previous.c_deg});
    } else {
        candidates.push_back({theta, c_sign_ * c_pos * kDegPerRad});
        candidates.push_back({-theta, c_sign_ * (c_pos + std::numbers::pi) * kDegPerRad});
    }

    const Limits& tl = limits_[3];
    const Limits& cl = limits_[4];
    std::optional<MachinePose> best;
    double best_cost = 0.0;
    std::string reasons;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
        const Candidate& cand = candidates[i];
        const double tilt_deg = tilt_sign_ * cand.tilt_rad * kDegPerRad;
        const std::string label = fmt::format("solution {} ({} {:.3f} deg, C {:.3f} deg)", i + 1,
                                              tl.name, tilt_deg, std::remainder(cand.c_deg, 360.0));
        const auto fail_reason = [&](const std::string& why) {
            reasons += fmt::format("{}{}: {}", reasons.empty() ? "" : "; ", label, why);
        };
        const auto tilt = unwind(tilt_deg, previous.a_or_b_deg, tl.min, tl.max);
        if (!tilt) {
            fail_reason(fmt::format("{} = {:.3f} deg is outside machine.axes.{} [{}, {}] deg",
                                    tl.name, tilt_deg, tl.name, tl.min, tl.max));
            continue;
        }
        const auto c = unwind(cand.c_deg, previous.c_deg, cl.min, cl.max);
        if (!c) {
            fail_reason(
                fmt::format("no turn of C = {:.3f} deg (+-360 k) lies in machine.axes.C "
                            "[{}, {}] deg",
                            cand.c_deg, cl.min, cl.max));
            continue;
        }
        // The linear axes from the final angles.
        const MachinePose pose = pose_at(tip_mm, *tilt, *c);
        if (auto ok = check_limits(pose); !ok) {
            fail_reason(ok.error().message);
            continue;
        }
        const double cost = weights.tilt * std::abs(pose.a_or_b_deg - previous.a_or_b_deg) +
                            weights.c * std::abs(pose.c_deg - previous.c_deg);
        if (!best || cost < best_cost - kTieDeg) {
            best = pose;
            best_cost = cost;
        }
    }
    if (!best) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("no pose of kinematics \"{}\" reaches direction {} at tip "
                                      "{} mm within the axis limits: {}",
                                      kinematics_name(kinematics_), vec_text(d, 6),
                                      vec_text(tip_mm, 3), reasons));
    }
    return *best;
}

MachinePose MachineKinematics::pose_at(const Vec3d& tip_mm, double a_or_b_deg, double c_deg) const {
    if (kinematics_ == Kinematics::kXyz) return {tip_mm.x, tip_mm.y, tip_mm.z, 0.0, 0.0};
    MachinePose pose{0.0, 0.0, 0.0, a_or_b_deg, c_deg};
    // m = pivot + R_tilt (o + R_C (q - o)).
    const double t = tilt_rad(pose), c = c_rad(pose);
    const Vec3d on_tilt = c_offset_mm_ + rotate(tip_mm - c_offset_mm_, 0.0, c);
    const Vec3d m = pivot_mm_ + rotate(on_tilt, t, 0.0);
    pose.x = m.x;
    pose.y = m.y;
    pose.z = m.z;
    return pose;
}

core::Result<void> MachineKinematics::check_reach(const std::vector<Vec3d>& points,
                                                  const std::vector<Vec3d>& plate_points,
                                                  double slack_mm) const {
    if (kinematics_ == Kinematics::kXyz) return {};
    const Limits& x = limits_[0];
    const Limits& y = limits_[1];
    const Limits& z = limits_[2];
    // (1) Anywhere: the farthest corner of the travel from the pivot.
    double reach = 0.0;
    for (int k = 0; k < 8; ++k) {
        const Vec3d corner{(k & 1) != 0 ? x.max : x.min, (k & 2) != 0 ? y.max : y.min,
                           (k & 4) != 0 ? z.max : z.min};
        reach = std::max(reach, core::norm(corner - pivot_mm_));
    }
    // The first point farther than `limit` (plus the slack) by `distance`, with its distance.
    const auto beyond = [&](const std::vector<Vec3d>& pts, const auto& distance,
                            double limit) -> std::optional<std::pair<Vec3d, double>> {
        for (const Vec3d& q : pts) {
            if (const double d = distance(q); d > limit + slack_mm) return std::pair{q, d};
        }
        return std::nullopt;
    };
    const double o = core::norm(c_offset_mm_);
    const auto far = beyond(
        points, [&](const Vec3d& q) { return core::norm(q - c_offset_mm_) - o; }, reach);
    if (far) {
        const auto& [q, d] = *far;
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("the part does not fit the machine: its point ({:.3f}, {:.3f}, {:.3f}) "
                        "mm is {:.1f} mm from the table's axes, and no table pose brings a point "
                        "farther than {:.1f} mm from the pivot within the travel of {}, {} and {}",
                        q.x, q.y, q.z, d, reach, x.name, y.name, z.name),
            "machine.axes");
    }
    // (2) The lowest layer, tilt 0: the C axis sits at pivot + o in X and Y.
    const double ax = pivot_mm_.x + c_offset_mm_.x, ay = pivot_mm_.y + c_offset_mm_.y;
    double reach_xy = 0.0;
    for (const double cx : {x.min, x.max}) {
        for (const double cy : {y.min, y.max}) {
            reach_xy = std::max(reach_xy, std::hypot(cx - ax, cy - ay));
        }
    }
    const auto wide = beyond(
        plate_points,
        [&](const Vec3d& q) { return std::hypot(q.x - c_offset_mm_.x, q.y - c_offset_mm_.y); },
        reach_xy);
    if (wide) {
        const auto& [q, r] = *wide;
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("the part does not fit the machine: its point ({:.3f}, {:.3f}, {:.3f}) "
                        "mm on the plate is {:.1f} mm from the C axis, and with the table flat "
                        "no turn of C brings a point farther than {:.1f} mm from it within the "
                        "travel of {} and {}",
                        q.x, q.y, q.z, r, reach_xy, x.name, y.name),
            "machine.axes");
    }
    return {};
}

core::Result<double> MachineKinematics::safe_height(double z_from_mm, double z_to_mm,
                                                    double clear_z_mm) const {
    if (std::isnan(z_from_mm) || std::isnan(z_to_mm) || std::isnan(clear_z_mm)) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("re-orientation heights {}, {}, {} mm are not numbers",
                                      z_from_mm, z_to_mm, clear_z_mm));
    }
    const double below = std::max({z_from_mm, z_to_mm, clear_z_mm});
    const double z_safe = below + retract_mm_;
    const Limits& z = limits_[2];
    if (!std::isfinite(z_safe) || z_safe > z.max + kLimitTolerance) {
        const std::string clear = std::isfinite(clear_z_mm)
                                      ? fmt::format(", clearance height {:.3f} mm", clear_z_mm)
                                      : std::string();
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("the retract before a re-orientation needs Z = {:.3f} mm, above "
                        "machine.axes.Z.max = {} mm (the highest of Z {:.3f} mm, Z {:.3f} mm{} "
                        "+ machine.table.retract_mm = {} mm)",
                        z_safe, z.max, z_from_mm, z_to_mm, clear, retract_mm_));
    }
    return z_safe;
}

core::Result<std::vector<MachinePose>> MachineKinematics::reorientation(const MachinePose& from,
                                                                        const MachinePose& to,
                                                                        double clear_z_mm) const {
    if (!finite(from) || !finite(to) || std::isnan(clear_z_mm)) {
        return core::fail(ErrorCode::kInvalidInput, "re-orientation between non-finite poses");
    }
    std::vector<MachinePose> out;
    if (std::abs(from.a_or_b_deg - to.a_or_b_deg) <= kSameAngleDeg &&
        std::abs(from.c_deg - to.c_deg) <= kSameAngleDeg) {
        return out;
    }
    const auto z_safe = safe_height(from.z, to.z, clear_z_mm);
    if (!z_safe) return std::unexpected(z_safe.error());
    // Straight up along the tool axis, turn the table there, then across above the target.
    MachinePose turn{from.x, from.y, *z_safe, from.a_or_b_deg, from.c_deg};
    out.push_back(turn);
    // Where to turn across the tilt axis: each sampled tilt of the turn bounds that
    // coordinate on one side (the head's floor is affine in it); the nearest value to the
    // retract point within all the bounds and the travel. A turn through the flat table
    // (the tilt changes sign) whose bounds leave no room is made in two: to the flat table
    // over a point that keeps the first half clear, then on over one that keeps the second.
    const bool about_x = kinematics_ == Kinematics::kTableAc;
    const auto shift_for = [&](const MachinePose& over, double a_from, double a_to,
                               double& w) -> bool {
        const Limits& travel = limits_[about_x ? 1 : 0];
        double lo = travel.min, hi = travel.max;
        const double w0 = about_x ? over.y : over.x;
        w = w0;
        bool possible = true;  // no tilt of the turn keeps the head up wherever the tip is
        for (int k = 0; k <= kTurnSamples; ++k) {
            const double f = static_cast<double>(k) / kTurnSamples;
            const MachinePose at{over.x, over.y, over.z, a_from + f * (a_to - a_from), 0.0};
            const double tilt = tilt_rad(at);
            const Vec3d n = rotate({0.0, 0.0, 1.0}, tilt, 0.0);
            const double slope = about_x ? n.y : n.x;  // d(floor) / dw
            const double need =
                head_clearance_mm_ + kTurnSlackMm - head_floor_mm({at.x, at.y, at.z}, tilt);
            if (std::abs(slope) < kFlatSlope) {
                possible = possible && need <= 0.0;  // no w helps at this tilt
                continue;
            }
            const double bound = w0 + need / slope;
            if (slope > 0.0) {
                lo = std::max(lo, bound);
            } else {
                hi = std::min(hi, bound);
            }
        }
        if (!possible || lo > hi) return false;
        w = std::clamp(w0, lo, hi);
        return true;
    };
    const auto move_over = [&](MachinePose& over, double w) {
        double& coordinate = about_x ? over.y : over.x;
        if (std::abs(coordinate - w) > 0.0) {
            coordinate = w;
            out.push_back(over);
        }
    };
    double w = 0.0;
    const double a0 = from.a_or_b_deg, a1 = to.a_or_b_deg;
    if (shift_for(turn, a0, a1, w)) {
        move_over(turn, w);
    } else if (a0 * a1 < 0.0) {
        double w_first = 0.0;
        if (shift_for(turn, a0, 0.0, w_first)) move_over(turn, w_first);
        out.push_back({turn.x, turn.y, *z_safe, 0.0, from.c_deg});
        MachinePose flat{turn.x, turn.y, *z_safe, 0.0, from.c_deg};
        if (shift_for(flat, 0.0, a1, w)) move_over(flat, w);
        turn = flat;
    }
    out.push_back({turn.x, turn.y, *z_safe, to.a_or_b_deg, to.c_deg});
    out.push_back({to.x, to.y, *z_safe, to.a_or_b_deg, to.c_deg});
    return out;
}

}  // namespace maxslice::machine
