#pragma once
// Sections of a mesh by single planes of any direction, without touching the triangles the
// plane cannot cross: the planner's tilted layers cut one plane at a time (METHOD.md section
// 4), and slicing the whole mesh for each is O(n) per plane.

#include <cstdint>
#include <vector>

#include "box_tree.hpp"
#include "maxslice/core/result.hpp"
#include "maxslice/core/vec3.hpp"
#include "maxslice/geom2d/polygon.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"
#include "maxslice/slice/plane_frame.hpp"

namespace maxslice::plan::detail {

/// A bounding volume hierarchy of a mesh's triangles (axis-aligned boxes) that finds the
/// triangles a plane may cross, and cuts the plane through them alone. The section is the
/// same, bit for bit, as slice::slice_mesh of the whole mesh with that one plane: every
/// triangle that crosses the plane is kept, triangles and vertices keep their relative
/// order (the slicer's chaining and crossing points depend on both), and a triangle that
/// does not cross the plane contributes nothing to a cut anyway.
class SectionIndex {
public:
    explicit SectionIndex(const mesh::TriangleMesh& mesh);

    /// The raw section (wires' paths, positive winding) of the mesh by `plane`, cut between
    /// heights -thickness / 2 and thickness / 2 (as slice_mesh with one layer whose cut is
    /// at the plane).
    [[nodiscard]] core::Result<geom2d::Paths2> section(const slice::PlaneFrame& plane,
                                                       double thickness);

private:
    void collect(const slice::PlaneFrame& plane);

    const mesh::TriangleMesh& mesh_;
    BoxTree tree_;  // over the triangles' boxes
    // Scratch of a query.
    std::vector<std::uint32_t> hits_;
    std::vector<std::uint32_t> vertex_map_;  // mesh vertex -> sub-mesh vertex + 1 (0: none)
    mesh::TriangleMesh sub_;
};

}  // namespace maxslice::plan::detail
