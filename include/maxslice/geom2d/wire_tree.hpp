#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "maxslice/geom2d/polygon.hpp"

namespace maxslice::geom2d {

/// One closed boundary curve of a region. Outer wires run counter-clockwise, holes
/// clockwise.
struct WireNode {
    Path2 wire;
    int parent = -1;            ///< index of the enclosing wire, -1 for a top-level wire
    std::vector<int> children;  ///< wires directly inside this one
    bool is_hole = false;       ///< true for a hole (its parent is an outer wire)
    int depth = 0;              ///< 0 for top-level outers, 1 for their holes, 2 for islands...
};

/// The containment tree of a region's wires: outers -> holes -> islands in holes -> ...
/// Nodes are stored in a deterministic order (parents before children).
struct WireTree {
    std::vector<WireNode> nodes;
    std::vector<int> roots;  ///< top-level wires (outers, or holes when a slice has only those)

    [[nodiscard]] bool empty() const { return nodes.empty(); }
    [[nodiscard]] std::size_t outer_count() const;
    [[nodiscard]] std::size_t hole_count() const;
    /// Net area (outers minus holes) in mm^2.
    [[nodiscard]] double area_mm2() const;
    /// All wires as paths, in node order.
    [[nodiscard]] Paths2 paths() const;
    /// The islands: each outer wire with its holes (islands inside holes are islands of
    /// their own), in node order. Hole wires without an outer wire are left out.
    [[nodiscard]] std::vector<Paths2> islands() const;
    /// Appends a node under `parent` (-1: a root) and returns its index.
    int add(Path2 wire, int parent, bool is_hole, int depth);
};

/// Combines raw closed loops into a region (Clipper union with the given fill rule) and
/// returns its wires as a containment tree. Degenerate loops contribute nothing.
/// With the positive rule, loops that already bound a region (simple, disjoint, alternately
/// oriented: a cut through a closed mesh) take a fast path with the same result.
[[nodiscard]] WireTree build_wire_tree(const Paths2& loops, FillRule rule);
/// The same tree, made from the loops' own storage where it can (the fast path then copies
/// no points of a loop it keeps as it is).
[[nodiscard]] WireTree build_wire_tree(Paths2&& loops, FillRule rule);

namespace detail {
/// build_wire_tree's two ways, for tests that compare them. The fast path: the positive-rule
/// wire tree of loops that are simple, pairwise disjoint (not even touching), outermost
/// counter-clockwise and each oriented opposite to its parent; nullopt for any other input
/// (or when checking would be slow). Equal to the Clipper union's tree whenever it answers.
[[nodiscard]] std::optional<WireTree> wire_tree_of_simple_loops(const Paths2& loops);
/// The same answer, moving the points of loops that need no cleaning into the tree: after an
/// answer, loops holds moved-from paths; after nullopt it is unchanged.
[[nodiscard]] std::optional<WireTree> take_wire_tree_of_simple_loops(Paths2& loops);
/// The Clipper union alone.
[[nodiscard]] WireTree clipper_wire_tree(const Paths2& loops, FillRule rule);
}  // namespace detail

/// Region booleans on closed paths (results as flat paths, outers CCW, holes CW).
[[nodiscard]] Paths2 union_of(const Paths2& a, FillRule rule = FillRule::kNonZero);
[[nodiscard]] Paths2 intersection_of(const Paths2& a, const Paths2& b);
[[nodiscard]] Paths2 difference_of(const Paths2& a, const Paths2& b);

/// Grows (delta > 0) or shrinks (delta < 0) a region by delta micrometres, mitred joins
/// limited to 2 x delta, round where sharper.
[[nodiscard]] Paths2 offset_of(const Paths2& region, std::int64_t delta_um);

/// Drops vertices that change a region by less than tolerance_um: those within that distance
/// of a neighbouring vertex or of the line through their neighbours (Clipper's
/// CleanPolygons). Loops left with fewer than 3 points are dropped.
[[nodiscard]] Paths2 simplify(const Paths2& region, std::int64_t tolerance_um);

/// The area a disc of radius half_width_um sweeps along open polylines (round joins and round
/// ends; a polyline of one point gives a disc): the deposit of tracks 2 x half_width wide.
/// Result as region paths (outers CCW, holes CW); arcs deviate by at most 1% of the radius.
[[nodiscard]] Paths2 sweep_polylines(const Paths2& polylines, std::int64_t half_width_um);

/// Like sweep_polylines with squares for discs: each segment's rectangle 2 x half_width wide,
/// the polylines' ends extended by half_width, turns joined with squared corners (Clipper's
/// square joins). A little more than the disc's sweep at the ends and most corners, a sliver
/// less at the outer corners of sharp turns; far cheaper to make (few vertices, no arcs).
[[nodiscard]] Paths2 sweep_polylines_square(const Paths2& polylines, std::int64_t half_width_um);

/// The pieces of open polylines inside a region (closed loops, non-zero rule), as open
/// polylines. Pieces running along the region's boundary may be kept or dropped.
[[nodiscard]] Paths2 clip_polylines(const Paths2& polylines, const Paths2& region);

}  // namespace maxslice::geom2d
