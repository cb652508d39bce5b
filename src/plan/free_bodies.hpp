#pragma once
// Bodies that float free of the rest of the part and of the plate (decision 0036). Private to
// plan.

#include <vector>

#include "maxslice/mesh/triangle_mesh.hpp"
#include "maxslice/plan/planner.hpp"

namespace maxslice::plan::detail {

struct FreeBodies {
    std::vector<FreeBody> bodies;  ///< in the order of their first triangles
    mesh::TriangleMesh rest;       ///< the mesh without them (empty when there are none)
};

/// The bodies of `mesh` that stand neither on the plate (their lowest point along `direction`
/// more than half a layer, and more than the footing's height, above the part's) nor touch
/// another body (no other body's triangle
/// within 0.05 mm of their bounding box).
[[nodiscard]] FreeBodies free_bodies(const mesh::TriangleMesh& mesh, const core::Vec3d& direction,
                                     const PlanSettings& s);

}  // namespace maxslice::plan::detail
