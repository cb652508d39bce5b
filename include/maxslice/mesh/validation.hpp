#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "maxslice/core/vec3.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"

namespace maxslice::mesh {

/// One kind of defect: how many, and one place where it is (for the message).
struct DefectCount {
    std::size_t count = 0;
    std::optional<core::Vec3d> example;  ///< a coordinate (mm) on the first instance
};

/// What is wrong (or unusual) with a mesh, measured without changing it.
struct ValidationReport {
    std::size_t triangles = 0;
    std::size_t vertices = 0;           ///< vertices used by at least one triangle
    std::size_t bodies = 0;             ///< connected components (sharing an edge or vertex)
    DefectCount nonfinite_vertices;     ///< NaN or infinite coordinates
    DefectCount degenerate_triangles;   ///< zero area (repeated index or collinear corners)
    DefectCount duplicate_triangles;    ///< same three vertices as an earlier triangle
    DefectCount boundary_edges;         ///< used by one triangle: the surface is open
    DefectCount nonmanifold_edges;      ///< used by more than two triangles
    DefectCount misoriented_edges;      ///< the same directed edge used twice
    core::Box3d bounding_box;
    double volume_mm3 = 0.0;            ///< signed; negative means inside-out
    double area_mm2 = 0.0;

    /// No open, non-manifold or misoriented edges.
    [[nodiscard]] bool closed_manifold() const;
    /// Closed, consistently oriented, and with negative volume.
    [[nodiscard]] bool inside_out() const;
    /// One human-readable line per defect present ("12 open edges, e.g. at (1, 2, 3)").
    [[nodiscard]] std::vector<std::string> defects() const;
};

[[nodiscard]] ValidationReport validate(const TriangleMesh& mesh);

}  // namespace maxslice::mesh
