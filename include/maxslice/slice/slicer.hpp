#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "maxslice/core/progress.hpp"
#include "maxslice/core/result.hpp"
#include "maxslice/core/tolerances.hpp"
#include "maxslice/geom2d/wire_tree.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"
#include "maxslice/slice/layers.hpp"
#include "maxslice/slice/plane_frame.hpp"

namespace maxslice::slice {

/// One cross-section of the solid: METHOD.md section 1.
struct Slice {
    int index = 0;           ///< position in its sequence, from the base up
    PlaneFrame plane;        ///< the cutting plane (origin on it, normal = build dir.)
    LayerSpan span;          ///< heights above the sequence's base plane (mm)
    geom2d::WireTree wires;  ///< boundary curves as a containment tree
    int gaps_closed = 0;     ///< gaps in open chains the slicer bridged (open meshes)
    int open_chains = 0;     ///< chains that could not be closed and were dropped

    [[nodiscard]] double thickness() const { return span.thickness(); }
    [[nodiscard]] double area_mm2() const { return wires.area_mm2(); }
};

/// Raw cut of a mesh by one plane: closed loops, oriented (solid on the left), before
/// any union. `gaps_closed` counts gaps bridged in open chains (open meshes), `open_chains`
/// the chains still open after bridging (they are dropped).
struct PlaneCut {
    geom2d::Paths2 loops;
    int open_chains = 0;
    int gaps_closed = 0;
};

/// Cuts the mesh with the planes base.shifted(h) for every h in heights (any order) and
/// returns the raw loops, one PlaneCut per height in the order given. A plane through a
/// vertex, edge or face cuts the solid just above it (symbolic perturbation), so a cube cut
/// at its bottom face yields its full square and at its top face yields nothing.
/// Open chains (open meshes) are bridged end to start, nearest first, across gaps up to
/// max_gap_mm (infinity bridges every gap). Work: O(n log n + k) for n triangles and k
/// triangle-plane crossings; parallel over planes, identical results for any thread count.
[[nodiscard]] core::Result<std::vector<PlaneCut>> cut_mesh(
    const mesh::TriangleMesh& mesh, const PlaneFrame& base, std::span<const double> heights,
    const core::Progress* progress = nullptr, double max_gap_mm = core::kSliceGapCloseMm);

/// Slices the mesh into the given layers along base.normal and builds each slice's wire
/// tree (union of the oriented loops with the positive fill rule, so overlapping bodies
/// merge). Errors name the layer when a slice cannot be built.
[[nodiscard]] core::Result<std::vector<Slice>> slice_mesh(
    const mesh::TriangleMesh& mesh, const PlaneFrame& base, std::span<const LayerSpan> layers,
    const core::Progress* progress = nullptr, double max_gap_mm = core::kSliceGapCloseMm);

/// The base frame for slicing a mesh along direction: normal = direction, origin at the
/// point d * (lowest height of the mesh along d), so heights run from 0 to the part's extent.
[[nodiscard]] PlaneFrame base_frame(const mesh::TriangleMesh& mesh, const core::Vec3d& direction);
/// The mesh's extent along the frame's normal: [min height, max height].
[[nodiscard]] std::pair<double, double> extent_along(const mesh::TriangleMesh& mesh,
                                                     const PlaneFrame& frame);

/// base_frame(mesh, direction) and extent_along(mesh, that frame), the same values, with one
/// look at which vertices the triangles use; with every vertex's height above the frame
/// (frame.height(v), unused vertices too), which slice_mesh then need not compute again.
struct FrameExtent {
    PlaneFrame frame;
    double lo = 0.0, hi = 0.0;
    std::shared_ptr<const double[]> heights;  ///< one per vertex of the mesh it was made for
    std::size_t vertices = 0;                 ///< that mesh's vertex count
};
/// Whether every vertex of a mesh is known to be used by a triangle, as in a mesh welded from
/// its triangles (every mesh io::read_mesh returns) or returned by mesh::repair, or must be
/// checked (unused vertices do not count in the frame or the extent).
enum class VertexUse : std::uint8_t { kCheck, kAllUsed };
[[nodiscard]] FrameExtent base_frame_and_extent(const mesh::TriangleMesh& mesh,
                                                const core::Vec3d& direction,
                                                VertexUse use = VertexUse::kCheck);
/// slice_mesh(mesh, base.frame, layers, ...) for the mesh base was made for (the same
/// result), using its vertex heights.
[[nodiscard]] core::Result<std::vector<Slice>> slice_mesh(
    const mesh::TriangleMesh& mesh, const FrameExtent& base, std::span<const LayerSpan> layers,
    const core::Progress* progress = nullptr, double max_gap_mm = core::kSliceGapCloseMm);

}  // namespace maxslice::slice
