// The placed model as voxels. Private to verify.
#pragma once

#include <cstddef>

#include "maxslice/core/vec3.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"
#include "voxel_grid.hpp"

namespace maxslice::verify::detail {

/// The voxels (centres origin + (i + 0.5) voxel) inside the mesh: along each z column through
/// the voxel centres, the mesh's triangles are crossed and a crossing counts +1 where the
/// surface faces down (entering) and -1 where it faces up; centres where the sum is positive
/// are inside. Shared edges count once (a top-left rule in the XY projection); a mesh that is
/// not closed gives columns whose sum does not return to 0, and those are cut at the last
/// crossing; they are counted. A column whose sum falls below 0 after the crossings at one
/// height (it leaves the solid before entering it: an inside-out body) is counted too.
struct ModelVoxels {
    BitGrid grid;
    std::size_t columns = 0;           ///< columns that cross the surface
    std::size_t open_columns = 0;      ///< of those, columns whose sum does not return to 0
    std::size_t inverted_columns = 0;  ///< of those, columns whose sum falls below 0
};
[[nodiscard]] ModelVoxels voxelize_model(const mesh::TriangleMesh& mesh, const core::Vec3d& origin,
                                         double voxel, int nx, int ny, int nz);

}  // namespace maxslice::verify::detail
