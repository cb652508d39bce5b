// The part a job deposits: the finished part as read, or its near-net shape when the process
// asks for one (docs/decisions/0025-near-net-shape.md).
#pragma once

#include <optional>
#include <string>

#include "maxslice/core/progress.hpp"
#include "maxslice/core/result.hpp"
#include "maxslice/machine/profile.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"
#include "maxslice/nearnet/near_net.hpp"
#include "maxslice/pipeline/slice_job.hpp"

namespace maxslice::pipeline {

/// The process's near-net settings: its machining_stock_mm and fill_below_mm.
[[nodiscard]] nearnet::NearNetSettings near_net_settings(const machine::ProcessProfile& process);

/// A job that deposits a near-net shape: what it builds and the finished part it keeps.
struct NearNetPart {
    /// The part read, its mesh replaced by the near-net shape and its reports by that mesh's
    /// (repairs and warnings are the part's as read).
    PreparedPart built;
    mesh::TriangleMesh finished;  ///< the part as read (file frame): what machining leaves
    nearnet::NearNetSettings settings;
    nearnet::NearNetReport report;
};

/// The near-net shape of `part` for `process`; nullopt when its stock and fill are both 0
/// (the part is built as it is). Errors: nearnet::near_net's. `times->near_net_s` gets the
/// time taken.
[[nodiscard]] core::Result<std::optional<NearNetPart>> near_net_part(
    const PreparedPart& part, const machine::ProcessProfile& process,
    const core::Progress* progress = nullptr, StageTimes* times = nullptr);

/// The summary line of a job that deposits a near-net shape: "near-net shape  1.00 mm stock,
/// holes and slots under 4.00 mm filled: +18.2% volume (0.250 mm voxels)\n".
[[nodiscard]] std::string near_net_line(const NearNetPart& part);

}  // namespace maxslice::pipeline
