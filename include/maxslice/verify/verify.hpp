#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "maxslice/core/result.hpp"
#include "maxslice/core/vec3.hpp"
#include "maxslice/machine/profile.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"
#include "maxslice/verify/replay.hpp"

namespace maxslice::verify {

/// The coverage a program must reach and the excess it must stay under to match its part: the
/// figures `maxslice slice` builds to (docs/verifier.md, decision 0022).
inline constexpr double kMinCoverage = 0.97;
inline constexpr double kMaxExcess = 0.05;
/// The share of the finished part a job's program is meant to hold inside its beads (issue 24,
/// decision 0026): a goal the report shows, not a verdict (the verdict is kMinCoverage).
inline constexpr double kFinishedInsideTarget = 0.995;

/// How to verify a program (docs/verifier.md).
struct VerifySettings {
    /// Voxel edge in mm; 0 = automatic: min(track / 4, h_min / 2), coarsened by 1.25x until
    /// the grid holds at most 4e8 voxels, but never beyond the thinnest bead / 1.25 (then up
    /// to max_voxels). Either is refused when coarser than that: the support check could not
    /// see the layer under a bead.
    double voxel_mm = 0.0;
    /// Largest number of voxels of the grid (a given voxel_mm is refused above it): about
    /// 0.4 bytes each, 2.4 GB at the bound.
    double max_voxels = 6.0e9;
    /// Largest distance (mm) the tool tip, or the far end of the nozzle, moves between two
    /// checked poses; 0 = automatic: half a track, at most 1 mm, at least one voxel.
    double sample_mm = 0.0;
    /// Gap (mm) the hardware (the nozzle cone above its standoff and the head body) must keep
    /// from deposited material and the substrate; closer without touching is a clearance
    /// violation. Unset = the profile's [machine.nozzle] clearance_mm (0 without that table);
    /// 0 checks contact only. Contact of any part of the head (the powder stream too) is a
    /// collision whatever this is (decision 0023).
    std::optional<double> clearance_mm;
    /// The program's dialect; unset = the machine profile's.
    std::optional<ProgramDialect> dialect;
    /// Report::matches_part(): coverage at least this, [0, 1] ...
    double min_coverage = kMinCoverage;
    /// ... and excess below this, >= 0.
    double max_excess = kMaxExcess;
};

/// Where a finding first happened.
struct Location {
    int line = 0;          ///< 1-based program line
    core::Vec3d point_mm;  ///< part frame: the contact / bead / tip point
    std::string detail;    ///< what was found, for a person
};

/// A kind of fault: how many program blocks have it and the first one.
struct Finding {
    std::size_t count = 0;
    std::optional<Location> first;
};

/// What the verifier found (docs/verifier.md). Volumes in mm^3, lengths in mm, times in s.
struct Report {
    std::string dialect;
    std::string machine_kinematics;
    int lines = 0;
    std::size_t moves = 0;  ///< positioning blocks
    std::size_t deposit_moves = 0;
    int laser_on_count = 0;
    double voxel_mm = 0.0;
    double sample_mm = 0.0;
    std::size_t poses_checked = 0;  ///< sampled poses the nozzle was checked at
    bool default_nozzle = false;    ///< the profile has no [machine.nozzle]: defaults used
    double clearance_mm = 0.0;      ///< the clearance checked (VerifySettings::clearance_mm)

    /// Contact: blocks where the head (stream, nozzle or body) meets material of earlier
    /// blocks or the substrate.
    Finding collisions;
    /// Clearance: blocks without contact where the nozzle above its standoff or the body
    /// comes closer than clearance_mm to that material or the substrate.
    Finding clearance;
    Finding unsupported;  ///< deposit blocks with a bead piece resting on nothing
    double unsupported_length_mm = 0.0;
    /// The tool tips (part frame) of the poses whose bead rests on nothing, in program order,
    /// at most kMaxUnsupportedTips: where a job leaves beads out (decision 0039).
    std::vector<core::Vec3d> unsupported_tips;
    static constexpr std::size_t kMaxUnsupportedTips = 100'000;
    /// Where the travel blocks among the collisions and the clearance findings end (their
    /// last pose's tool tip, part frame), in program order, at most kMaxUnsupportedTips: the
    /// travels a job takes over the part instead (decision 0048).
    std::vector<core::Vec3d> travel_fault_ends;
    Finding limit_violations;  ///< blocks with a pose outside machine.axes
    /// The profile has a [machine.substrate]: the head is checked against the plate too
    /// (a hit counts as a collision).
    bool substrate = false;
    /// Without a substrate: blocks where the head reaches below the plate's level (part
    /// z = 0), where a plate, clamps or the table may be; a warning, not a failure.
    Finding below_plate;
    double below_plate_mm = 0.0;  ///< the deepest such reach (mm below the plate's level)

    /// Lines with a laser power, powder feed or G1 feed outside the machine's ranges
    /// (Replay::out_of_range).
    Finding out_of_range;
    /// 1 when the program is cut off in the middle of a line, or (linuxcnc, fanuc, siemens)
    /// ends without M2 / M30: a program that does not end as written was cut or lost its end.
    Finding unfinished;
    /// 1 when the laser or the powder is still on after the program's last line.
    Finding left_on;

    double model_volume_mm3 = 0.0;      ///< voxelized model
    double deposited_volume_mm3 = 0.0;  ///< voxelized beads
    double covered_volume_mm3 = 0.0;    ///< model inside beads
    double excess_volume_mm3 = 0.0;     ///< beads outside the model
    double coverage = 0.0;              ///< covered / model, [0, 1]
    double excess = 0.0;                ///< excess / model
    /// Columns of the model's voxelization that cross its surface unevenly (an open mesh):
    /// when non-zero, coverage and excess are estimates (docs/verifier.md).
    std::size_t model_open_columns = 0;
    std::size_t model_columns = 0;  ///< columns that cross the model's surface
    /// Columns where the model's surface is crossed leaving before entering (a body inside
    /// out, or facing inwards where bodies touch): what it encloses is not the part.
    std::size_t model_inverted_columns = 0;
    double min_coverage = kMinCoverage;  ///< the thresholds matches_part() applies
    double max_excess = kMaxExcess;

    /// The finished part (decision 0026): the part after machining, which the deposited model
    /// (a near-net shape: the finished part grown by a machining stock) must hold. Given to
    /// verify_program, or (finished_given false) the model itself. The model's figures above
    /// (coverage, excess) stay measured against the model.
    bool finished_given = false;
    double finished_volume_mm3 = 0.0;         ///< voxelized finished part
    double finished_inside_volume_mm3 = 0.0;  ///< of it, inside beads
    double finished_inside = 0.0;             ///< inside / finished volume, [0, 1]; goal 1
    /// The smallest machining stock (mm): where every voxel of the finished part lies inside
    /// beads, the smallest distance from its surface to the outside of the beads (>= 0); where
    /// some does not, minus the farthest the finished part reaches out of the beads (< 0; 0 or
    /// less whenever finished_inside < 1). Distances between voxel centres, Euclidean, less one
    /// voxel inside (each surface lies half a voxel beyond the last centre on average): within
    /// one voxel (voxel_mm) of the true figure. Searched up to stock_limit_mm either way; a
    /// figure of +-stock_limit_mm means at least that far.
    double smallest_stock_mm = 0.0;
    core::Vec3d smallest_stock_at_mm;  ///< part frame: the finished part's voxel it was found at
    double stock_limit_mm = 0.0;       ///< how far the stock was searched (mm)
    /// As model_columns / model_open_columns / model_inverted_columns, for the finished part.
    std::size_t finished_columns = 0;
    std::size_t finished_open_columns = 0;
    std::size_t finished_inverted_columns = 0;

    double deposition_length_mm = 0.0;  ///< tool tip path with the laser on (part frame)
    double idle_length_mm = 0.0;        ///< linear axes' path with the laser off (machine)
    double rotary_travel_deg = 0.0;     ///< sum of |dA|+|dC| (or B)
    double deposit_time_s = 0.0;
    double idle_time_s = 0.0;  ///< laser-off moves (G0 at machine.feed_max_mm_min)
    double dwell_time_s = 0.0;
    double build_time_s = 0.0;  ///< sum of the above (no acceleration: a lower bound)
    double bead_height_min_mm = 0.0;
    double bead_height_max_mm = 0.0;

    /// The program is safe to run: no collisions, no unsupported beads, no axis-limit
    /// violations, no out-of-range values, it ends as written with the laser and powder off.
    /// `maxslice slice` keeps a program on this verdict.
    [[nodiscard]] bool passed() const {
        return unsupported.count == 0 && passed_apart_from_support();
    }

    /// passed() but for unsupported beads (what `maxslice slice --allow-overhangs` keeps).
    [[nodiscard]] bool passed_apart_from_support() const {
        return collisions.count == 0 && clearance.count == 0 && limit_violations.count == 0 &&
               out_of_range.count == 0 && unfinished.count == 0 && left_on.count == 0;
    }

    /// The program lays no bead the voxel grid holds (no deposit, or beads finer than the
    /// voxels: a model read in the wrong unit makes the automatic voxel coarse).
    [[nodiscard]] bool deposits_nothing() const { return deposited_volume_mm3 <= 0.0; }

    /// Coverage and excess describe the part: the model is closed and no body of it is
    /// inside out. Otherwise they are estimates and matches_part() does not judge them.
    [[nodiscard]] bool coverage_judged() const {
        return model_open_columns == 0 && model_inverted_columns == 0;
    }
    [[nodiscard]] bool coverage_low() const { return coverage_judged() && coverage < min_coverage; }
    [[nodiscard]] bool excess_high() const { return coverage_judged() && excess >= max_excess; }
    /// finished_inside describes the finished part: it is closed, no body inside out.
    [[nodiscard]] bool finished_judged() const {
        return finished_open_columns == 0 && finished_inverted_columns == 0;
    }
    /// Less than min_coverage of the finished part inside beads (where judged): the program
    /// does not build it, whatever the model's figures (decision 0026).
    [[nodiscard]] bool finished_low() const {
        return finished_judged() && finished_inside < min_coverage;
    }

    /// The program builds the part it was checked against: it deposits, and (where judged)
    /// covers at least min_coverage of the model with excess below max_excess, and holds at
    /// least min_coverage of the finished part inside its beads.
    [[nodiscard]] bool matches_part() const {
        return !deposits_nothing() && !coverage_low() && !excess_high() && !finished_low();
    }

    /// What `maxslice verify` accepts (exit 0): passed() and matches_part().
    [[nodiscard]] bool accepted() const { return passed() && matches_part(); }
};

/// The names of the checks the report fails, in a fixed order: "contact" (collisions),
/// "clearance", "unsupported", "limit_violations", "out_of_range", "unfinished", "left_on"
/// (passed()), then "nothing_deposited", "coverage", "excess", "finished_inside" (the last
/// only with a finished part given; matches_part()). Empty when accepted().
[[nodiscard]] std::vector<std::string_view> failed_checks(const Report& report);

/// The model placed as the job places a part on the plate (docs/program-dialects.md): rotated
/// so that `base_direction` points to +Z (Rodrigues about d x Z, a half turn about X for -Z),
/// lowest point at Z = 0, the centre of its XY bounding box on the plate centre (the middle of
/// the X and Y travel for "xyz" machines, (c_offset) for table machines). Part frame, mm.
/// Errors (kInvalidInput): empty mesh, zero or non-finite direction.
[[nodiscard]] core::Result<mesh::TriangleMesh> place_model(mesh::TriangleMesh model,
                                                           const core::Vec3d& base_direction,
                                                           const machine::MachineProfile& machine);

/// `other` (in the same file frame as `model`) moved as place_model moves `model`: the same
/// rotation and the same shift, whatever other's own bounding box. Places the finished part
/// with its near-net shape's placement. Errors as place_model's (also for an empty `other`).
[[nodiscard]] core::Result<mesh::TriangleMesh> place_like(mesh::TriangleMesh other,
                                                          const mesh::TriangleMesh& model,
                                                          const core::Vec3d& base_direction,
                                                          const machine::MachineProfile& machine);

/// Verifies a program against the placed model (part frame) and the profiles: replays it
/// (replay_program), lays beads in a voxel grid and checks collisions, support and axis limits
/// and measures coverage, excess, lengths and time; notes out-of-range values and how the
/// program ends. `placed_finished`, when given, is the finished part placed as the model (the
/// model being its near-net shape): the report's finished_inside and smallest_stock_mm are
/// measured against it (otherwise against the model). A program that fails the checks is a
/// Report with passed() or matches_part() false, not an error. Errors: the program does not
/// parse (context "line N"), invalid profiles or settings (min_coverage outside [0, 1], a
/// negative max_excess), a grid too large for max_voxels.
[[nodiscard]] core::Result<Report> verify_program(
    std::string_view program_text, const mesh::TriangleMesh& placed_model,
    const machine::Profiles& profiles, const VerifySettings& settings = {},
    const mesh::TriangleMesh* placed_finished = nullptr);

/// The report as JSON (fixed key order and number formats: same report, same bytes).
[[nodiscard]] std::string report_json(const Report& report);

/// "99.87% inside beads, smallest stock 0.61 mm" (2 decimals; the stock negative where the
/// finished part reaches out of the beads): the finished part's figures, as the verify report
/// and the slice job's summary print them after "finished part" (scripts parse this line).
[[nodiscard]] std::string finished_text(const Report& report);

/// The report as text for a person, one finding per line.
[[nodiscard]] std::string report_text(const Report& report);

}  // namespace maxslice::verify
