// Holes in an open surface, closed for whatever needs an inside: a distance field's sign
// (the near-net shape, docs/decisions/0038-open-surfaces-near-net.md).
#pragma once

#include <cstddef>

#include "maxslice/mesh/triangle_mesh.hpp"

namespace maxslice::mesh {

/// A mesh with its holes capped, and how many.
struct CappedMesh {
    TriangleMesh mesh;
    std::size_t open_edges = 0;  ///< edges of the input used by one triangle
    std::size_t caps = 0;        ///< holes capped: connected sets of open edges
};

/// Caps every hole of `mesh`: the open edges (used by exactly one triangle) are grouped by the
/// vertices they share, and each group is closed by a fan of triangles from a new vertex at the
/// mean of its vertices, each fan triangle running its open edge the other way. A hole whose
/// rim is one loop comes out closed; the fan may cross itself where the rim is far from flat,
/// which a distance field's sign does not mind. Triangles and vertices of the input keep their
/// indices; the caps come after them, in the order of their lowest vertex. Deterministic.
[[nodiscard]] CappedMesh cap_holes(const TriangleMesh& mesh);

}  // namespace maxslice::mesh
