#pragma once

#include <string>
#include <vector>

#include "maxslice/core/progress.hpp"
#include "maxslice/core/result.hpp"
#include "maxslice/machine/profile.hpp"
#include "maxslice/machine/program.hpp"
#include "maxslice/machine/summary.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"
#include "maxslice/path/toolpath.hpp"
#include "maxslice/pipeline/slice_job.hpp"
#include "maxslice/plan/order.hpp"
#include "maxslice/plan/planner.hpp"

namespace maxslice::pipeline {

/// Puts a part on the build plate for a planar build along `direction`: rotates it so that
/// the direction points up (+Z), then moves it so that its lowest point lies on Z = 0 (the
/// plate) and the centre of its XY bounding box on `plate_center` (X, Y in mm; the CLI uses
/// the middle of the machine's X and Y travel), docs/decisions/0006-planar-programs.md.
[[nodiscard]] mesh::TriangleMesh place_on_plate(mesh::TriangleMesh mesh,
                                                const core::Vec3d& direction,
                                                const core::Vec3d& plate_center = {});

/// The toolpath settings a process profile implies.
[[nodiscard]] path::PathSettings path_settings(const machine::ProcessProfile& process);

/// A planar deposition program and what went into it.
struct PlannedProgram {
    std::vector<path::LayerToolpath> toolpaths;  ///< one per slice, same order
    machine::Program program;
    machine::ProgramSummary summary;
    double region_area_mm2 = 0.0;   ///< sum of the slices' areas
    double uncovered_mm2 = 0.0;     ///< sum of the layers' uncovered areas
    int layers_with_uncovered = 0;  ///< layers with more than 1% of their area uncovered
};

/// Plans tracks for every slice (in build order) and turns them into moves in part
/// coordinates: per layer a lift to the layer's top, then each stroke as a deposited wire
/// (travel, laser on with the dwell, deposit moves, laser off) at the layer's top height.
/// The summary comes from machine::summarize. Errors name the layer.
[[nodiscard]] core::Result<PlannedProgram> plan_program(const SliceStack& stack,
                                                        const machine::Profiles& profiles,
                                                        const std::string& part_name,
                                                        const core::Progress* progress = nullptr);

/// Where the speed law could not lay a layer's local thickness (METHOD.md section 10).
struct ThicknessReport {
    std::size_t segments = 0;       ///< deposit moves
    std::size_t clamped = 0;        ///< of them, laid thicker or thinner than planned (> 1 um)
    double worst_error_mm = 0.0;    ///< largest |laid - planned| height
    int worst_layer = -1;           ///< where (layer id), -1 when none
    core::Vec3d worst_at;           ///< the segment's middle, part coordinates
    double thickness_min_mm = 0.0;  ///< planned local thickness range over the segments
    double thickness_max_mm = 0.0;
};

/// A multi-axis deposition program and what went into it.
struct MultiAxisProgram {
    std::vector<int> order;                      ///< layer ids in build order
    std::vector<path::LayerToolpath> toolpaths;  ///< per entry of order
    machine::Program program;
    machine::ProgramSummary summary;
    double region_area_mm2 = 0.0;
    double uncovered_mm2 = 0.0;
    int layers_with_uncovered = 0;
    ThicknessReport thickness;
    int section_changes = 0;  ///< travels over the part's top between sections
    /// Track cut away because the layer below has no bead under it (mm), and in how many layers.
    double trimmed_mm = 0.0;
    int layers_trimmed = 0;
};

/// The moves of a planned, ordered part (METHOD.md sections 9 to 11), in part coordinates
/// with each layer's build direction: tracks for every layer (path::plan_layers, in build
/// order), each stroke's points lifted onto the layer's top (a wedge layer's tilted top
/// plane), every deposit move with the feed that lays the local thickness (the process's
/// machine::SpeedLaw; wedge tracks cut into pieces of at most half a track), travel between
/// strokes at the layer's top, between layers of one section a rise along the build
/// direction then across, between sections of one direction a rise above the part's top
/// along it, across and down. Direction changes are left to the writer's re-orientation.
/// `placed` is the part as planned (for the heights above it). Errors: an incomplete order
/// (kInvalidInput, naming the first conflict), invalid settings, cancelled.
[[nodiscard]] core::Result<MultiAxisProgram> plan_multiaxis_program(
    const plan::Plan& plan, const plan::BuildOrder& order, const mesh::TriangleMesh& placed,
    const machine::Profiles& profiles, const std::string& part_name,
    const core::Progress* progress = nullptr);

}  // namespace maxslice::pipeline
