#include "gap_fill.hpp"

#include <algorithm>
#include <cmath>

#include "maxslice/core/units.hpp"
#include "maxslice/geom2d/medial_axis.hpp"
#include "maxslice/geom2d/wire_tree.hpp"

namespace maxslice::path::detail {
namespace {

using geom2d::Path2;
using geom2d::Paths2;

}  // namespace

std::vector<RouteStroke> gap_fill(const Paths2& gaps, std::int64_t track_width_um,
                                  std::int64_t min_width_um) {
    std::vector<RouteStroke> out;
    if (gaps.empty()) return out;
    const geom2d::WireTree tree = geom2d::build_wire_tree(gaps, geom2d::FillRule::kNonZero);
    for (const geom2d::WireNode& node : tree.nodes) {
        if (node.is_hole) continue;
        Paths2 piece{node.wire};
        for (const int c : node.children)
            piece.push_back(tree.nodes[static_cast<std::size_t>(c)].wire);
        double area = 0.0;
        double perimeter = 0.0;
        for (const Path2& loop : piece) {
            area += geom2d::signed_area_um2(loop);
            perimeter += geom2d::perimeter_mm(loop) * core::kMicronsPerMm;
        }
        const double width = 2.0 * area / perimeter;
        if (width < static_cast<double>(min_width_um)) continue;
        if (width > static_cast<double>(track_width_um)) {
            for (Path2& loop : geom2d::offset_of(piece, -std::llround(0.25 * width))) {
                out.push_back({StrokeKind::kFill, true, std::move(loop)});
            }
            continue;
        }
        // One track along the piece's medial axis, where the piece is at least the narrowest
        // width filled (rings, strips, and networks of them alike).
        for (geom2d::MedialLine& line : geom2d::medial_axis(piece, min_width_um / 2)) {
            if (line.closed) line.points.pop_back();
            if (line.points.size() < 2) continue;
            out.push_back({StrokeKind::kFill, line.closed, std::move(line.points)});
        }
    }
    return out;
}

}  // namespace maxslice::path::detail
