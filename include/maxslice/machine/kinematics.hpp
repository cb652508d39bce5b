#pragma once

#include <array>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "maxslice/core/result.hpp"
#include "maxslice/core/vec3.hpp"
#include "maxslice/machine/profile.hpp"

namespace maxslice::machine {

/// One set of machine axis values. x, y, z: the tool tip in machine coordinates (the program's
/// X, Y, Z), mm. a_or_b_deg: the tilt axis (A for xyzac-trt, B for xyzbc-trt), c_deg: the
/// rotary axis C, both in degrees as the controller counts them (before the profile's
/// direction signs). Both are 0 for kinematics "xyz".
struct MachinePose {
    double x = 0.0;
    double y = 0.0;
    double z = 0.0;
    double a_or_b_deg = 0.0;
    double c_deg = 0.0;
};

/// The tool as the part sees it, in part coordinates (TableProfile documents the frame).
struct ToolPose {
    core::Vec3d tip_mm;     ///< the tool tip (melt pool), mm
    core::Vec3d direction;  ///< unit build direction: from the melt pool up the tool axis
};

/// Weights of the rotary distance w_tilt |dA| + w_c |dC| (degrees) that picks, of the two
/// inverse solutions, the one nearest the previous pose. Both > 0.
struct PoseWeights {
    double tilt = 1.0;
    double c = 1.0;
};

/// Forward and inverse kinematics of a validated machine profile (METHOD.md section 11).
/// The head is fixed, its tool axis (melt pool up to the head) along machine +Z; the linear
/// axes place the tool tip; on the table-tilt machines the table turns the part about the tilt
/// axis (A about X or B about Y, through TableProfile::pivot_mm) and the C axis it carries
/// (about the table's Z, through pivot + c_offset). With R = R_tilt(s_t t) R_C(s_c C) (s_t, s_c
/// the profile's direction signs, right-hand rotations), a part point q sits at the machine
/// point pivot + R_tilt (o + R_C (q - o)), o = (c_offset, 0), and the part-frame build
/// direction the nozzle sees is R^-1 (0, 0, 1). For "xyz" R is the identity and the pivot 0:
/// part and machine coordinates coincide and the direction is always +Z.
class MachineKinematics {
public:
    /// The kinematics of `machine` (validated here; errors as validate(MachineProfile)).
    [[nodiscard]] static core::Result<MachineKinematics> create(const MachineProfile& machine);

    [[nodiscard]] Kinematics kinematics() const { return kinematics_; }
    /// The table's retract along the tool axis before a re-orientation, mm (0 for "xyz").
    [[nodiscard]] double retract_mm() const { return retract_mm_; }

    /// Tool tip and build direction in part coordinates for a pose. No limit check (see
    /// check_limits): the verifier replays whatever a program says.
    [[nodiscard]] ToolPose forward(const MachinePose& pose) const;

    /// The pose that puts the part-frame `tip_mm` under the nozzle with the part-frame
    /// `direction` (any non-zero length) along machine +Z. Of the two solutions (tilt t, C and
    /// -t, C + 180) the one nearest `previous` by `weights` is taken; each axis is turned by
    /// +-360 k to the equivalent nearest its previous value that stays within its limits (C may
    /// be continuous: this is the unwinding). At the singular direction (along the C axis:
    /// tilt 0 or 180) C stays at previous.c_deg. Errors (kInvalidInput): a zero or non-finite
    /// input; "xyz" with a direction that is not +Z; no solution within the limits, with each
    /// solution's axis and limit named ("A = 150.000 deg is outside machine.axes.A ..."). The
    /// caller adds the context (layer, region).
    [[nodiscard]] core::Result<MachinePose> inverse(const core::Vec3d& tip_mm,
                                                    const core::Vec3d& direction,
                                                    const MachinePose& previous,
                                                    const PoseWeights& weights = {}) const;

    /// Checks every axis value is finite and within its limits (a tolerance of 1e-9 mm or
    /// deg). Errors (kInvalidInput) name the axis, value and limits.
    [[nodiscard]] core::Result<void> check_limits(const MachinePose& pose) const;

    /// The pose with the rotary values `a_or_b_deg` and `c_deg` that holds the part-frame
    /// `tip_mm` under the nozzle (the linear axes of inverse() for given angles). No limit
    /// check (see check_limits). For "xyz" the rotary values are ignored (0 in the result).
    [[nodiscard]] MachinePose pose_at(const core::Vec3d& tip_mm, double a_or_b_deg,
                                      double c_deg) const;

    /// A quick test, before anything is planned, that the table can bring the part's points
    /// under the nozzle at all (a part larger than the machine is refused in milliseconds,
    /// not after planning it). Two necessary conditions on part-frame points, each with
    /// `slack_mm` (a track's width: tracks lie inside the outline): (1) every point: the
    /// rotations keep |q - o| (o = (c_offset, 0) on the C axis), so |q - o| - |o| must not
    /// exceed the largest distance from the pivot to a corner of the X, Y, Z travel; (2) the
    /// points of `plate_points` (the part's lowest layer, deposited along the table's +Z, tilt
    /// 0): their distance from the C axis must not exceed the largest distance from the C
    /// axis to a corner of the X, Y travel. For "xyz" nothing is tested (the program's limit
    /// check names the move). Errors (kInvalidInput) name the point and the distances.
    [[nodiscard]] core::Result<void> check_reach(const std::vector<core::Vec3d>& points,
                                                 const std::vector<core::Vec3d>& plate_points,
                                                 double slack_mm) const;
    /// The safe re-orientation from `from` to `to` (METHOD.md section 11,
    /// docs/program-dialects.md): the poses to pass through between them. When a rotary axis
    /// changes: retract straight up along the tool axis (+Z) to
    /// z_safe = max(from.z, to.z, clear_z_mm) + retract_mm, turn the table there, move across
    /// at z_safe over the target; the caller's next move (to `to`) is the approach along the
    /// tool axis. `clear_z_mm` is the height the tool tip must clear whatever the table does
    /// (see clear_height_mm in machine_moves.hpp; -infinity: none). The turn also keeps the
    /// head (the profile's nozzle, or NozzleProfile's defaults) above the plate's level (part
    /// z = 0) by the nozzle's clearance: where turning over `from` would sweep the head below
    /// it, the tip first moves at z_safe across the tilt axis (machine Y for A, X for B) to the
    /// nearest point, within the travel, from which the whole turn stays above by 0.5 mm more
    /// (decision 0016); when there is none and the turn passes the flat table, it is made in
    /// two halves (to the flat table, then on), each over its own such point; otherwise over
    /// `from` as before (the verifier has the last word). Empty when no rotary
    /// axis changes. Errors (kInvalidInput): z_safe above the Z limit (naming machine.axes.Z
    /// and machine.table.retract_mm).
    [[nodiscard]] core::Result<std::vector<MachinePose>> reorientation(
        const MachinePose& from, const MachinePose& to,
        double clear_z_mm = -std::numeric_limits<double>::infinity()) const;

    /// z_safe of a re-orientation between poses at heights z_from_mm and z_to_mm:
    /// max(z_from_mm, z_to_mm, clear_z_mm) + retract_mm, checked against the Z limit as in
    /// reorientation().
    [[nodiscard]] core::Result<double> safe_height(double z_from_mm, double z_to_mm,
                                                   double clear_z_mm) const;

private:
    struct Limits {
        std::string name;
        double min = 0.0;
        double max = 0.0;
    };

    MachineKinematics() = default;

    // Part <-> machine for the rotation angles (radians, signs applied).
    [[nodiscard]] core::Vec3d rotate(const core::Vec3d& v, double tilt_rad, double c_rad) const;
    [[nodiscard]] core::Vec3d unrotate(const core::Vec3d& v, double tilt_rad, double c_rad) const;
    [[nodiscard]] double tilt_rad(const MachinePose& pose) const;
    [[nodiscard]] double c_rad(const MachinePose& pose) const;
    // The lowest part-frame z the head reaches standing at machine point m with the table
    // tilted by tilt_rad (the plate's level is 0).
    [[nodiscard]] double head_floor_mm(const core::Vec3d& m, double tilt_rad) const;

    Kinematics kinematics_ = Kinematics::kXyz;
    core::Vec3d pivot_mm_;
    core::Vec3d c_offset_mm_;  // z = 0
    int tilt_sign_ = 1;
    int c_sign_ = 1;
    double retract_mm_ = 0.0;
    // The head's outline as (distance along the tool axis, radius) corners: the apex, the
    // cone's rim, the body's ends; and the clearance it keeps.
    std::vector<std::pair<double, double>> head_outline_;
    double head_clearance_mm_ = 0.0;
    std::array<Limits, 5> limits_;  // X, Y, Z, tilt, C (tilt and C unbounded for "xyz")
};

}  // namespace maxslice::machine
