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

namespace maxslice::pipeline {

/// Puts a part on the build plate for a planar build along `direction`: rotates it so that
/// the direction points up (+Z), then moves it so that its lowest point lies on Z = 0 (the
/// plate) and the centre of its XY bounding box on `plate_center` (X, Y in mm; the CLI uses
/// the middle of the machine's X and Y travel), docs/decisions/0006-planar-programs.md.
[[nodiscard]] mesh::TriangleMesh place_on_plate(mesh::TriangleMesh mesh,
                                                const core::Vec3d& direction,
                                                const core::Vec3d& plate_center = {});

/// The middle of a machine's X and Y travel (Z = 0): where place_on_plate puts a part.
[[nodiscard]] core::Vec3d plate_center(const machine::MachineProfile& machine);

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

}  // namespace maxslice::pipeline
