// The program job's base orientation: the part as given, and when that cannot be built
// another way to stand it on the plate (docs/decisions/0015-orientation-fallback.md).
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "maxslice/core/progress.hpp"
#include "maxslice/core/result.hpp"
#include "maxslice/core/vec3.hpp"
#include "maxslice/machine/profile.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"
#include "maxslice/pipeline/plan_job.hpp"
#include "maxslice/pipeline/slice_job.hpp"
#include "maxslice/plan/planner.hpp"

namespace maxslice::pipeline {

/// Which base orientations a program job may use.
enum class OrientPolicy {
    kGiven,     ///< only the given direction
    kFallback,  ///< the given direction; the candidates when it cannot be built
    kAuto,      ///< the candidates from the start (the given direction is not preferred)
    kOthers,    ///< the candidates but the given direction (a base other than the given one)
};

/// One base direction the job tried, in the part file's frame.
struct OrientTry {
    core::Vec3d direction;
    std::string source;   ///< "as given", "+Y", "largest flat face 1" ...
    std::string refusal;  ///< why it cannot be built; empty when it can
};

/// "; other orientations tried: -Z (14 layers rest on nothing), ..." for the tries but
/// `chosen` and the part as given (empty without others).
std::string other_tries(const std::vector<OrientTry>& tries, int chosen);

/// Refuses at once a part the table-tilt machine cannot bring under the nozzle along any
/// direction `policy` lets the job try (kGiven: `given`; kFallback: `given`, then the
/// orientation_candidates of `part`; kAuto: the candidates), before anything is planned or a
/// near-net shape made: MachineKinematics::check_reach of the part standing on the plate along
/// each, as deposited grown by `grown_mm` (the profile's machining stock: the near-net shape's
/// box is the part's grown by it, and its farthest point from the table's axes a vertex's
/// grown by it), with the widest track of the profile's processes as slack. It passes when one
/// direction fits; orient_multiaxis checks the mesh it is given again, direction by direction.
/// Nothing is tested for a 3-axis machine. Errors (kInvalidInput): the first direction's
/// ("the part does not fit the machine: ..."), saying the stock was added, then "; other
/// orientations tried: ..." as orient_multiaxis words it; the kinematics' own errors.
[[nodiscard]] core::Result<void> check_fits_machine(const mesh::TriangleMesh& part,
                                                    const core::Vec3d& given, OrientPolicy policy,
                                                    const machine::Profiles& profiles,
                                                    double grown_mm);

/// A multi-axis plan of the part standing on the plate along a chosen direction.
struct OrientedPlan {
    mesh::TriangleMesh placed;  ///< the part on the plate, the chosen direction up
    PlannedPart planned;        ///< planned along +Z of `placed`, with its build order
    /// Layers on the plate where no track fits (a part standing on an edge or a tip): nothing
    /// is laid there, and what stands on them would rest on nothing.
    std::vector<int> bare_plate_layers;
    std::vector<OrientTry> tries;
    int chosen = 0;  ///< index into tries: the direction kept
};

/// What a program check says of a plan: `refusal` "" keeps it, anything else is why not;
/// `build_time_s` the build time of its program (s; NaN when the check does not know it);
/// `short_of_figures`: a program kept that misses the job's coverage figures (another base
/// that meets them is preferred, however long).
struct ProgramVerdict {
    ProgramVerdict(std::string why = {}, double seconds = std::numeric_limits<double>::quiet_NaN(),
                   bool short_of = false)
        : refusal(std::move(why)), build_time_s(seconds), short_of_figures(short_of) {}
    std::string refusal;
    double build_time_s;
    bool short_of_figures;
};

/// A further judgement of a plan the search would keep (the program job writes its program and
/// replays it in the verifier, whose build time it gives): "" keeps it, anything else is why
/// not, and the search goes on as for a plan that cannot be built. Errors end the search,
/// except a kInvalidInput one (a program the machine cannot run along that base) outside
/// kGiven: that base is refused. `direction`: the part file's direction the plan builds
/// upwards. The same signature serves the estimate of orient_multiaxis: the build time of the
/// program a plan gives, before it is written and verified.
using ProgramCheck = std::function<core::Result<ProgramVerdict>(
    const core::Vec3d& direction, const mesh::TriangleMesh& placed, const PlannedPart& planned)>;

/// Plans and orders the part for a table-tilt machine. kGiven: along `given` only. kFallback:
/// along `given`; when that plan leaves layers resting on nothing, stands on a piece where no
/// track fits, or has no collision-free order, the candidates of orientation_candidates are
/// planned, ranked by buildable plan first, then fewest splits, then fewest tilts wanted, then the
/// order tried, and ordered in that rank until one is buildable. kAuto: the same without trying
/// `given` first. When none is buildable the given direction's plan is returned (kAuto: the best
/// ranked), with every try and its refusal. Errors: those of plan_mesh and order_plan for the given
/// direction; with kFallback a plan the planner refuses as invalid input along the given direction
/// is recorded as a try like the candidates' and its error returned only when nothing builds.
/// `check`, when given, is asked about every plan before it is kept (kGiven: its answer is
/// recorded and the given plan kept). `candidates_of`, when not empty, replaces
/// orientation_candidates(part) (a near-net shape is searched along its finished part's).
/// `estimate`, when given with `check`, makes the search of the candidates keep the base with
/// the shortest verified build time among those that meet the figures (decision 0015): every
/// candidate that can be built is ordered and estimated, they are checked from the shortest
/// estimate up, and the search stops once one meets the figures and the next estimate is no
/// shorter than its verified time (the check's own build time, else the estimate); when none
/// meets them, the shortest of those that verify. The caller's last check is of the plan kept.
/// Bases that build but take longer carry that as their refusal. The part as given, when it builds,
/// is still kept first (kFallback).
[[nodiscard]] core::Result<OrientedPlan> orient_multiaxis(
    const mesh::TriangleMesh& part, const core::Vec3d& given, OrientPolicy policy,
    const machine::Profiles& profiles, const core::Progress* progress = nullptr,
    const ProgramCheck& check = {}, const std::vector<OrientCandidate>& candidates_of = {},
    const ProgramCheck& estimate = {});

/// A planar stack of the part standing on the plate along a chosen direction.
struct OrientedStack {
    core::Vec3d direction;  ///< the part file's direction built upwards
    mesh::TriangleMesh placed;
    SliceStack stack;  ///< sliced along +Z of `placed`
    plan::PlanarCheck check;
    std::vector<OrientTry> tries;
    int chosen = 0;  ///< index into tries: the direction kept
};

/// Slices the part for a 3-axis machine and checks the stack with plan::check_planar.
/// kFallback: along `given`; when the stack has overhangs a planar build cannot hold, every
/// candidate is sliced and checked, and of those without overhangs the one with the fewest
/// tilts wanted is kept, then the first tried (plan --orient auto's ranking). kAuto: the same
/// without preferring `given`. kGiven: `given` only. When none passes the given direction's
/// stack is returned. Errors: those of slice_part and check_planar for the given direction.
/// `times` gets the given direction's slicing only (as without the search: the `slice` stage
/// the benchmarks compare). `check`, when given, is asked about every stack before it is kept,
/// in the search's order; one it refuses is a refused try (kGiven: recorded, the given kept).
/// `candidates_of` as for orient_multiaxis. `estimate`, when given with `check`: the candidates
/// without overhangs are kept by the shortest verified build time, as orient_multiaxis does.
using StackCheck = std::function<core::Result<ProgramVerdict>(
    const core::Vec3d& direction, const mesh::TriangleMesh& placed, const SliceStack& stack)>;
[[nodiscard]] core::Result<OrientedStack> orient_planar(
    const mesh::TriangleMesh& part, const core::Vec3d& given, OrientPolicy policy,
    const SliceSettings& settings, const machine::Profiles& profiles,
    const core::Progress* progress = nullptr, StageTimes* times = nullptr,
    const StackCheck& check = {}, const std::vector<OrientCandidate>& candidates_of = {},
    const StackCheck& estimate = {});

}  // namespace maxslice::pipeline
