// The only translation unit that includes the clipping library (Clipper 6, Debian's
// libpolyclipping). Swapping it for another library touches this file alone.
#include "maxslice/geom2d/wire_tree.hpp"

#include <clipper.hpp>

#include <algorithm>

#include "maxslice/core/units.hpp"

namespace maxslice::geom2d {
namespace {

ClipperLib::Path to_clipper(const Path2& path) {
    ClipperLib::Path out;
    out.reserve(path.size());
    for (const Point2& p : path) out.emplace_back(p.x, p.y);
    return out;
}

ClipperLib::Paths to_clipper(const Paths2& paths) {
    ClipperLib::Paths out;
    out.reserve(paths.size());
    for (const Path2& p : paths) {
        if (p.size() >= 3) out.push_back(to_clipper(p));
    }
    return out;
}

Path2 from_clipper(const ClipperLib::Path& path) {
    Path2 out;
    out.reserve(path.size());
    for (const ClipperLib::IntPoint& p : path) out.push_back({p.X, p.Y});
    return out;
}

Paths2 from_clipper(const ClipperLib::Paths& paths) {
    Paths2 out;
    out.reserve(paths.size());
    for (const auto& p : paths) out.push_back(from_clipper(p));
    return out;
}

ClipperLib::PolyFillType to_clipper(FillRule rule) {
    switch (rule) {
        case FillRule::kEvenOdd: return ClipperLib::pftEvenOdd;
        case FillRule::kNonZero: return ClipperLib::pftNonZero;
        case FillRule::kPositive: return ClipperLib::pftPositive;
    }
    return ClipperLib::pftNonZero;
}

// Rotates a closed path so that it starts at its smallest point: Clipper's start points
// depend on input order, this makes the output canonical for a given region.
void canonical_start(Path2& path) {
    if (path.empty()) return;
    auto it = std::min_element(path.begin(), path.end());
    std::rotate(path.begin(), it, path.end());
}

void add_subtree(const ClipperLib::PolyNode& node, int parent, int depth, WireTree& tree) {
    // Sort siblings by their first (smallest) point so the order does not depend on the
    // order Clipper found them in.
    std::vector<std::pair<Path2, const ClipperLib::PolyNode*>> kids;
    kids.reserve(node.Childs.size());
    for (const ClipperLib::PolyNode* child : node.Childs) {
        Path2 p = from_clipper(child->Contour);
        canonical_start(p);
        kids.emplace_back(std::move(p), child);
    }
    std::sort(kids.begin(), kids.end(),
              [](const auto& a, const auto& b) { return a.first.front() < b.first.front(); });
    std::vector<std::pair<int, const ClipperLib::PolyNode*>> created;
    for (auto& [path, child] : kids) {
        if (path.size() < 3) continue;
        created.emplace_back(tree.add(std::move(path), parent, child->IsHole(), depth), child);
    }
    for (const auto& [id, child] : created) add_subtree(*child, id, depth + 1, tree);
}

}  // namespace

int WireTree::add(Path2 wire, int parent, bool is_hole, int depth) {
    const int id = static_cast<int>(nodes.size());
    WireNode wn;
    wn.wire = std::move(wire);
    wn.parent = parent;
    wn.is_hole = is_hole;
    wn.depth = depth;
    nodes.push_back(std::move(wn));
    if (parent >= 0) {
        nodes[static_cast<std::size_t>(parent)].children.push_back(id);
    } else {
        roots.push_back(id);
    }
    return id;
}

std::size_t WireTree::outer_count() const {
    return static_cast<std::size_t>(
        std::count_if(nodes.begin(), nodes.end(), [](const WireNode& n) { return !n.is_hole; }));
}

std::size_t WireTree::hole_count() const {
    return nodes.size() - outer_count();
}

double WireTree::area_mm2() const {
    double sum = 0.0;
    for (const WireNode& n : nodes) sum += signed_area_um2(n.wire);
    return core::um2_to_mm2(sum);
}

std::vector<Paths2> WireTree::islands() const {
    std::vector<Paths2> out;
    for (const WireNode& node : nodes) {
        if (node.is_hole) continue;
        Paths2& island = out.emplace_back();
        island.push_back(node.wire);
        for (const int child : node.children) {
            const WireNode& hole = nodes[static_cast<std::size_t>(child)];
            if (hole.is_hole) island.push_back(hole.wire);
        }
    }
    return out;
}

Paths2 WireTree::paths() const {
    Paths2 out;
    out.reserve(nodes.size());
    for (const WireNode& n : nodes) out.push_back(n.wire);
    return out;
}

WireTree build_wire_tree(const Paths2& loops, FillRule rule) {
    if (rule == FillRule::kPositive) {
        if (auto tree = detail::wire_tree_of_simple_loops(loops)) return std::move(*tree);
    }
    return detail::clipper_wire_tree(loops, rule);
}

WireTree build_wire_tree(Paths2&& loops, FillRule rule) {
    if (rule == FillRule::kPositive) {
        if (auto tree = detail::take_wire_tree_of_simple_loops(loops)) return std::move(*tree);
    }
    return detail::clipper_wire_tree(loops, rule);
}

WireTree detail::clipper_wire_tree(const Paths2& loops, FillRule rule) {
    ClipperLib::Clipper clipper;
    clipper.AddPaths(to_clipper(loops), ClipperLib::ptSubject, true);
    ClipperLib::PolyTree solution;
    clipper.Execute(ClipperLib::ctUnion, solution, to_clipper(rule), to_clipper(rule));
    WireTree tree;
    add_subtree(solution, -1, 0, tree);
    return tree;
}

Paths2 union_of(const Paths2& a, FillRule rule) {
    ClipperLib::Clipper clipper;
    clipper.AddPaths(to_clipper(a), ClipperLib::ptSubject, true);
    ClipperLib::Paths out;
    clipper.Execute(ClipperLib::ctUnion, out, to_clipper(rule), to_clipper(rule));
    return from_clipper(out);
}

namespace {

Paths2 boolean(const Paths2& a, const Paths2& b, ClipperLib::ClipType op) {
    ClipperLib::Clipper clipper;
    clipper.AddPaths(to_clipper(a), ClipperLib::ptSubject, true);
    clipper.AddPaths(to_clipper(b), ClipperLib::ptClip, true);
    ClipperLib::Paths out;
    clipper.Execute(op, out, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
    return from_clipper(out);
}

}  // namespace

Paths2 intersection_of(const Paths2& a, const Paths2& b) {
    return boolean(a, b, ClipperLib::ctIntersection);
}

Paths2 difference_of(const Paths2& a, const Paths2& b) {
    return boolean(a, b, ClipperLib::ctDifference);
}

namespace {

// True when shrinking by shrink_um leaves nothing: no outer loop (counter-clockwise) has a
// bounding box wider than 2 * shrink_um both ways, so no disc of that radius fits inside.
// Clipper would get there too, but only after resolving the O(n^2) self-intersections of
// every loop pushed past its own centre.
bool vanishes_when_shrunk(const Paths2& region, std::int64_t shrink_um) {
    for (const Path2& path : region) {
        if (path.size() < 3 || signed_area_um2(path) <= 0.0) continue;
        const auto [x0, x1] = std::minmax_element(path.begin(), path.end(),
                                                  [](Point2 a, Point2 b) { return a.x < b.x; });
        const auto [y0, y1] = std::minmax_element(path.begin(), path.end(),
                                                  [](Point2 a, Point2 b) { return a.y < b.y; });
        if (x1->x - x0->x > 2 * shrink_um && y1->y - y0->y > 2 * shrink_um) return false;
    }
    return true;
}

}  // namespace

Paths2 offset_of(const Paths2& region, std::int64_t delta_um) {
    if (delta_um < 0 && vanishes_when_shrunk(region, -delta_um)) return {};
    ClipperLib::ClipperOffset offset(2.0, 0.25 * core::kMicronsPerMm * 0.01);
    offset.AddPaths(to_clipper(region), ClipperLib::jtMiter, ClipperLib::etClosedPolygon);
    ClipperLib::Paths out;
    offset.Execute(out, static_cast<double>(delta_um));
    return from_clipper(out);
}

Paths2 simplify(const Paths2& region, std::int64_t tolerance_um) {
    ClipperLib::Paths paths = to_clipper(region);
    if (tolerance_um > 0) ClipperLib::CleanPolygons(paths, static_cast<double>(tolerance_um));
    Paths2 out;
    out.reserve(paths.size());
    for (const ClipperLib::Path& p : paths) {
        if (p.size() >= 3) out.push_back(from_clipper(p));
    }
    return out;
}

namespace {

// Open polylines keep every point count (a closed path needs 3, a polyline 1).
ClipperLib::Paths polylines_to_clipper(const Paths2& polylines) {
    ClipperLib::Paths out;
    out.reserve(polylines.size());
    for (const Path2& p : polylines) {
        if (!p.empty()) out.push_back(to_clipper(p));
    }
    return out;
}

}  // namespace

namespace {

// The polylines offset by half_width_um with Clipper's joins and ends of one kind.
Paths2 sweep(const Paths2& polylines, std::int64_t half_width_um, ClipperLib::JoinType join,
             ClipperLib::EndType end, double arc_tolerance) {
    if (half_width_um <= 0) return {};
    ClipperLib::ClipperOffset offset(2.0, arc_tolerance);
    offset.AddPaths(polylines_to_clipper(polylines), join, end);
    ClipperLib::Paths out;
    offset.Execute(out, static_cast<double>(half_width_um));
    return from_clipper(out);
}

}  // namespace

Paths2 sweep_polylines(const Paths2& polylines, std::int64_t half_width_um) {
    return sweep(polylines, half_width_um, ClipperLib::jtRound, ClipperLib::etOpenRound,
                 std::max(1.0, 0.01 * static_cast<double>(half_width_um)));
}

Paths2 sweep_polylines_square(const Paths2& polylines, std::int64_t half_width_um) {
    // The arc tolerance does not apply to square joins.
    return sweep(polylines, half_width_um, ClipperLib::jtSquare, ClipperLib::etOpenSquare,
                 0.25 * static_cast<double>(half_width_um));
}

Paths2 clip_polylines(const Paths2& polylines, const Paths2& region) {
    ClipperLib::Clipper clipper;
    for (const Path2& p : polylines) {
        // Clipper refuses open paths of fewer than two distinct points.
        if (p.size() >= 2) clipper.AddPath(to_clipper(p), ClipperLib::ptSubject, false);
    }
    clipper.AddPaths(to_clipper(region), ClipperLib::ptClip, true);
    ClipperLib::PolyTree tree;
    clipper.Execute(ClipperLib::ctIntersection, tree, ClipperLib::pftNonZero,
                    ClipperLib::pftNonZero);
    ClipperLib::Paths open;
    ClipperLib::OpenPathsFromPolyTree(tree, open);
    return from_clipper(open);
}

}  // namespace maxslice::geom2d
