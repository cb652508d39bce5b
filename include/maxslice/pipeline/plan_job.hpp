#pragma once
// The planning job: base orientation, the multi-axis plan, and its exports (plan JSON,
// Graphviz DOT, per-region SVG, a PLY of the layers coloured by region).

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include "maxslice/core/progress.hpp"
#include "maxslice/core/result.hpp"
#include "maxslice/machine/profile.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"
#include "maxslice/mesh/validation.hpp"
#include "maxslice/path/toolpath.hpp"
#include "maxslice/pipeline/slice_job.hpp"
#include "maxslice/plan/order.hpp"
#include "maxslice/plan/planner.hpp"

namespace maxslice::pipeline {

/// How the base direction is chosen.
enum class Orient {
    kGiven,  ///< the part stands as given: build along `direction` (default +Z)
    kAuto,   ///< no layer on nothing, then the fewest splits, then the fewest tilts wanted
};

/// The planner's settings for a process profile: its layer height, h_min and h_max (widened
/// to hold the layer height), track width and self-supporting angle; alpha and beta at
/// their defaults.
[[nodiscard]] plan::PlanSettings plan_settings(const machine::ProcessProfile& process);

/// plan_settings(profiles.process) with the machine's head (nozzle_of): a region split off
/// sideways is then built along a direction the head reaches (decision 0029).
[[nodiscard]] plan::PlanSettings plan_settings(const machine::Profiles& profiles);

/// One base direction tried by --orient auto.
struct OrientCandidate {
    core::Vec3d direction;
    std::string source;  ///< "+Z", "-X", "largest flat face 2" ...
    int splits = 0;
    int tilts_wanted = 0;
    int regions = 0;
    int unsupported_layers = 0;  ///< layers its plan leaves resting on nothing
    bool planned = false;        ///< false when planning failed for it (error below)
    std::string error;
};

struct PlanJobSettings {
    plan::PlanSettings plan;
    Orient orient = Orient::kGiven;
    core::Vec3d direction{0.0, 0.0, 1.0};  ///< the base direction when given
    /// The toolpath settings of the process: when set, every plan's layers on nothing where
    /// no track fits are moved to plan::Plan::bare_unsupported_layers (before candidates are
    /// ranked).
    std::optional<path::PathSettings> tracks;
    /// The base directions --orient auto tries; empty: orientation_candidates of the mesh
    /// planned. A job that plans a near-net shape gives the finished part's (its flat faces
    /// are the near-net shape's, which is meshed from voxels and has none exactly flat).
    std::vector<OrientCandidate> candidates;
    /// When set (a table machine), each direction's plan is made as a program job makes it:
    /// on the part placed on the plate along that direction (place_on_plate, centred here),
    /// built along +Z in the table's part frame. Unset: the part as the file has it, built
    /// along the direction.
    std::optional<core::Vec3d> plate_center;
};

struct PlannedPart {
    plan::Plan plan;
    std::vector<OrientCandidate> candidates;  ///< with --orient auto, in the order tried
    int chosen = -1;                          ///< index into candidates (-1: given)
    double seconds = 0.0;                     ///< planning time (all candidates)
    /// The build order with collision control (order_plan), when made.
    std::optional<plan::BuildOrder> order;
    plan::Nozzle nozzle;        ///< the nozzle the order was checked with
    std::string nozzle_source;  ///< where its values came from
    double order_seconds = 0.0;
};

/// The nozzle of a machine profile's [machine.nozzle] table; without one, plan::Nozzle's
/// defaults (the source then says so).
[[nodiscard]] plan::Nozzle nozzle_of(const machine::MachineProfile& machine, std::string* source);

/// Orders the plan's layers with collision control (plan::order_layers) and keeps the result
/// in planned.order, also when it has conflicts. Errors: those of order_layers.
[[nodiscard]] core::Result<void> order_plan(PlannedPart& planned, const plan::Nozzle& nozzle,
                                            std::string nozzle_source,
                                            const core::Progress* progress = nullptr);

/// Whether two base directions (not necessarily unit) are one for the orientation search.
[[nodiscard]] bool same_direction(const core::Vec3d& a, const core::Vec3d& b);

/// A candidate plan's rank in the orientation search, lower first: no layer resting on nothing,
/// then the fewest splits, then the fewest tilts wanted (plan --orient auto and the program
/// job's search, decision 0015).
[[nodiscard]] std::tuple<bool, int, int> orientation_rank(const plan::Plan& plan);

/// The candidate base directions of --orient auto: the 6 axis directions and the directions
/// that stand the part on each of its largest flat faces (up to 4 faces of at least 5% of
/// the surface, coplanar facets grouped); duplicates removed. Deterministic.
[[nodiscard]] std::vector<OrientCandidate> orientation_candidates(const mesh::TriangleMesh& mesh);

/// The layers among `ids` whose toolpaths have no track (every feature narrower than the
/// track), in the order of `ids`.
[[nodiscard]] core::Result<std::vector<int>> trackless_layers(const plan::Plan& plan,
                                                              std::span<const int> ids,
                                                              const path::PathSettings& tracks);

/// What hangs from the layers `bare` (sorted; layers without a track): up from them, a
/// generation of children at a time, a child hangs when all its parents do, and the walk goes
/// on through hanging children without a track. `hangs` (per layer id) marks the bare layers
/// and every hanging child; returns the hanging children with a track, sorted per generation.
[[nodiscard]] core::Result<std::vector<int>> laden_hanging(const plan::Plan& plan,
                                                           std::span<const int> bare,
                                                           const path::PathSettings& tracks,
                                                           std::vector<char>& hangs);

/// Plans the part (see plan::plan_part); with Orient::kAuto plans every candidate and keeps
/// the one whose plan leaves no layer resting on nothing, then the fewest splits, then the
/// fewest tilts wanted, then the first tried. With `tracks` set, each plan's layers on
/// nothing where no track fits are set aside first (plan::Plan::bare_unsupported_layers).
/// Errors: those of plan_part; with kAuto, the first candidate's error when none plans.
[[nodiscard]] core::Result<PlannedPart> plan_mesh(const mesh::TriangleMesh& mesh,
                                                  const PlanJobSettings& settings,
                                                  const core::Progress* progress = nullptr);

/// The plan as JSON (docs/plan-format.md, "format": "maxslice-plan", "version": 1).
[[nodiscard]] std::string plan_json(const PlannedPart& planned, const PreparedPart& part);
/// The hierarchy graph in Graphviz DOT: one cluster per region, nodes are layers.
[[nodiscard]] std::string plan_dot(const plan::Plan& plan);
/// What the colours of a plan preview show.
enum class PlanColour {
    kRegion,   ///< a fixed colour per region
    kOrder,    ///< the build order: blue (first) to red (last); grey when not ordered
    kSection,  ///< a fixed colour per section of the build order
};

/// The layers' boundary walls (each wire swept over its layer's thickness) as an ASCII PLY
/// with per-vertex colours: opens in MeshLab, CloudCompare, Blender, ParaView. kOrder and
/// kSection need an order (without one they fall back to regions).
[[nodiscard]] std::string plan_ply(const plan::Plan& plan, PlanColour colour = PlanColour::kRegion,
                                   const plan::BuildOrder* order = nullptr);
/// One SVG per region (region_NNN.svg) in dir: its layers' wires in its base frame,
/// coloured from the first layer (blue) to the last (red). Creates dir.
[[nodiscard]] core::Result<void> write_plan_svgs(const std::filesystem::path& dir,
                                                 const plan::Plan& plan);
/// Side views of the plan coloured by build order (order_xz.svg, order_yz.svg: blue first,
/// red last) and by section (sections_xz.svg, sections_yz.svg): every layer's wires projected
/// on the XZ and YZ planes. Creates dir.
[[nodiscard]] core::Result<void> write_order_svgs(const std::filesystem::path& dir,
                                                  const plan::Plan& plan,
                                                  const plan::BuildOrder& order);
/// "(mesh V mm3, +x.xxx%)" comparing a sliced or planned volume with the mesh's, or, when the
/// mesh is not closed, a note that it has no volume to compare with (an open surface's
/// signed volume depends on where the origin is).
[[nodiscard]] std::string volume_against_mesh(double volume_mm3,
                                              const mesh::ValidationReport& report);
/// The summary line of a footing at the plate (decision 0017), newline-terminated; "" when
/// none was laid.
[[nodiscard]] std::string footing_line(const plan::Footing& footing);
/// A short human summary (regions, splits, tilts wanted, layers, volume, time).
[[nodiscard]] std::string plan_summary(const PlannedPart& planned,
                                       const mesh::ValidationReport& report);

}  // namespace maxslice::pipeline
