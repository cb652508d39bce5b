#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "maxslice/mesh/triangle_mesh.hpp"

namespace maxslice::mesh {

/// How repair() may change a mesh.
struct RepairOptions {
    /// Vertices closer than this (mm) are merged. 0: core::kRepairWeldRelative times the
    /// bounding-box diagonal of the used vertices; negative: no welding.
    double weld_distance_mm = 0.0;
};

/// What repair() changed, counted per kind of repair.
struct RepairReport {
    double weld_distance_mm = 0.0;                 ///< the distance used (0 when not welded)
    std::size_t welded_vertices = 0;               ///< vertices merged into a lower-index one
    std::size_t removed_nonfinite_triangles = 0;   ///< with a NaN or infinite corner
    std::size_t removed_degenerate_triangles = 0;  ///< zero area (see is_degenerate())
    std::size_t split_triangles = 0;               ///< neighbours split to close the gap a removed
                                                   ///< collinear triangle left
    std::size_t removed_duplicate_triangles = 0;   ///< same vertex set as an earlier triangle
    std::size_t removed_unused_vertices = 0;       ///< not welded, but used by no triangle
    std::size_t reoriented_triangles = 0;          ///< flipped to agree with their neighbours
    std::size_t inverted_shells = 0;               ///< closed shells turned the right way out
    std::size_t inverted_shell_triangles = 0;      ///< triangles of those shells
    std::optional<core::Vec3d> first_inverted_at;  ///< on the first of those shells (mm)
    std::size_t unoriented_bodies = 0;             ///< bodies left as they were: non-manifold edges

    /// One line per kind of repair done ("welded 166 vertices closer than 1e-06 mm"), and one
    /// for bodies whose orientation could not be checked.
    [[nodiscard]] std::vector<std::string> lines() const;
    /// True when the mesh was changed.
    [[nodiscard]] bool changed() const;
};

/// Repairs the mesh in place, in this order: welds vertices closer than the weld distance
/// (each to the lowest-index vertex of its cluster, whose position it takes; clusters chain,
/// so points further apart than the distance can merge through others); removes triangles
/// with non-finite corners, then degenerate triangles (a collinear triangle's removal is
/// made watertight by splitting the neighbour across its longest edge at its middle
/// corner), then duplicate triangles (the lowest-index one of each vertex set stays);
/// orients the triangles of each edge-connected shell consistently (shells of bodies
/// without non-manifold edges; the orientation most of a shell's triangles have wins,
/// ties keep the lowest-index triangle's); turns a closed shell the right way out when its
/// volume is negative and it is not inside an odd number of other closed shells (voids
/// stay negative); drops unused vertices (the others keep their relative order).
/// Deterministic; the result does not depend on the number of threads.
[[nodiscard]] RepairReport repair(TriangleMesh& mesh, const RepairOptions& options = {});

}  // namespace maxslice::mesh
