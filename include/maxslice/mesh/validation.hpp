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
    std::size_t vertices = 0;          ///< vertices used by at least one triangle
    std::size_t bodies = 0;            ///< connected components (sharing an edge or vertex)
    DefectCount nonfinite_vertices;    ///< NaN or infinite coordinates
    DefectCount degenerate_triangles;  ///< zero area (repeated index or collinear corners)
    DefectCount duplicate_triangles;   ///< same three vertices as an earlier triangle
    DefectCount boundary_edges;        ///< used by one triangle: the surface is open
    DefectCount nonmanifold_edges;     ///< used by more than two triangles
    DefectCount misoriented_edges;     ///< the same directed edge used twice
    /// Misoriented edges whose triangles do not use them as often one way as the other (a
    /// closed, consistently oriented surface uses every edge equally often both ways, and
    /// so do closed bodies that touch along an edge or a face: two cubes sharing a face have
    /// four triangles on each of its edges, two each way). Only these make the orientation
    /// inconsistent; the others are where closed bodies touch.
    DefectCount unbalanced_edges;
    /// Closed shells that enclose material but face inwards: negative volume, and not a
    /// void (not inside an odd number of other closed shells). Checked when the mesh has
    /// several bodies, is closed and no body has a non-manifold edge (a single body's
    /// orientation is the sign of the volume). The slicer's positive fill rule would leave
    /// such a body out of every layer.
    DefectCount inside_out_shells;
    /// Where closed bodies touch (every misoriented edge balanced): pieces of surface whose
    /// inside is empty, i.e. a touching body that faces inwards (repair does not reorient
    /// bodies with non-manifold edges). Among the 64 largest pieces. Not looked for in a flat
    /// mesh.
    DefectCount inward_pieces;
    /// Every used vertex lies in one plane (within kFlatFraction of the bounding box
    /// diagonal): the mesh encloses no volume and has no inside, so neither
    /// inside_out_shells nor inward_pieces are looked for (they would find every piece).
    bool flat = false;
    static constexpr double kFlatFraction = 1e-9;
    core::Box3d bounding_box;  ///< of the used vertices with finite coordinates (mm)
    double volume_mm3 = 0.0;   ///< signed; negative means inside-out
    double area_mm2 = 0.0;

    /// No open, non-manifold or misoriented edges.
    [[nodiscard]] bool closed_manifold() const;
    /// No open edge and every edge used equally often both ways: one or more closed,
    /// consistently oriented bodies, which may touch (their volume is the sum of theirs).
    [[nodiscard]] bool closed() const;
    /// Closed, with misoriented edges that are all balanced: closed bodies that touch along
    /// edges or faces.
    [[nodiscard]] bool bodies_touch() const;
    /// Closed, consistently oriented, and with negative volume.
    [[nodiscard]] bool inside_out() const;

    /// One human-readable line per defect present ("12 open edges, e.g. at (1, 2, 3)").
    [[nodiscard]] std::vector<std::string> defects() const;
};

/// Measures the mesh without changing it. Linear expected time; the result does not depend
/// on the number of threads. Examples are taken from the first instance in vertex-index
/// order (edges by their smaller, then larger vertex index; triangles by index).
/// Precondition: every triangle index is below mesh.vertices.size().
[[nodiscard]] ValidationReport validate(const TriangleMesh& mesh);

/// True when the triangle (a, b, c) has zero area for practical purposes: its area is at most
/// core::kDegenerateTriangleAreaMm2 times the square of its longest edge in mm, a test that
/// does not depend on the unit the part is in. Corners at one point count as degenerate;
/// a triangle with a non-finite corner does not.
[[nodiscard]] bool is_degenerate(const core::Vec3d& a, const core::Vec3d& b, const core::Vec3d& c);

}  // namespace maxslice::mesh
