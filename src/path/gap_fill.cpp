#include "gap_fill.hpp"

#include <algorithm>
#include <cmath>

#include "maxslice/geom2d/wire_tree.hpp"

namespace maxslice::path::detail {
namespace {

using geom2d::Path2;
using geom2d::Paths2;
using geom2d::Point2;

// The middle of a ring-shaped gap is found by shrinking it by this share of its mean width:
// what is left is a thin band around its middle line (where the gap is about its mean width)
// whose outer loop stands in for that line, 5% of the width off.
constexpr double kMiddleShrink = 0.45;

double squared_distance(Point2 a, Point2 b) {
    const double dx = static_cast<double>(b.x - a.x);
    const double dy = static_cast<double>(b.y - a.y);
    return dx * dx + dy * dy;
}

std::size_t farthest_from(const Path2& loop, Point2 p) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < loop.size(); ++i) {
        if (squared_distance(loop[i], p) > squared_distance(loop[best], p)) best = i;
    }
    return best;
}

// The boundary of a loop from vertex a forward to vertex b.
Path2 forward(const Path2& loop, std::size_t a, std::size_t b) {
    Path2 out;
    for (std::size_t i = a;; i = (i + 1) % loop.size()) {
        out.push_back(loop[i]);
        if (i == b) break;
    }
    return out;
}

// The point at arc-length fraction t in [0, 1] of a polyline with cumulative lengths cum.
Point2 at_fraction(const Path2& line, const std::vector<double>& cum, double t) {
    const double target = t * cum.back();
    const auto it = std::lower_bound(cum.begin(), cum.end(), target);
    const std::size_t j = std::min<std::size_t>(
        static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - cum.begin(), 1)), line.size() - 1);
    const double seg = cum[j] - cum[j - 1];
    const double u = seg > 0.0 ? (target - cum[j - 1]) / seg : 0.0;
    return {std::llround(static_cast<double>(line[j - 1].x) +
                         u * static_cast<double>(line[j].x - line[j - 1].x)),
            std::llround(static_cast<double>(line[j - 1].y) +
                         u * static_cast<double>(line[j].y - line[j - 1].y))};
}

std::vector<double> cumulative(const Path2& line) {
    std::vector<double> cum(line.size(), 0.0);
    for (std::size_t i = 1; i < line.size(); ++i) {
        cum[i] = cum[i - 1] + std::sqrt(squared_distance(line[i - 1], line[i]));
    }
    return cum;
}

// The middle line of a strip: its boundary is split at its two far ends into two sides, and
// points at the same arc-length fraction along both are averaged (a medial line for strips
// whose sides are alike, as those between two contour tracks are). step_um: sample spacing.
Path2 middle_of_strip(const Path2& loop, double step_um) {
    const std::size_t a = farthest_from(loop, loop.front());
    const std::size_t b = farthest_from(loop, loop[a]);
    const Path2 one = forward(loop, a, b);
    Path2 other = forward(loop, b, a);
    std::reverse(other.begin(), other.end());
    const std::vector<double> c1 = cumulative(one);
    const std::vector<double> c2 = cumulative(other);
    const double length = 0.5 * (c1.back() + c2.back());
    const std::size_t n = std::max<std::size_t>(1, static_cast<std::size_t>(length / step_um));
    Path2 middle;
    for (std::size_t i = 0; i <= n; ++i) {
        const double t = static_cast<double>(i) / static_cast<double>(n);
        const Point2 p = at_fraction(one, c1, t);
        const Point2 q = at_fraction(other, c2, t);
        const Point2 m{(p.x + q.x) / 2, (p.y + q.y) / 2};
        if (middle.empty() || middle.back() != m) middle.push_back(m);
    }
    return middle;
}

double perimeter_um(const Path2& loop) {
    double sum = 0.0;
    for (std::size_t i = 0; i < loop.size(); ++i) {
        sum += std::sqrt(squared_distance(loop[i], loop[(i + 1) % loop.size()]));
    }
    return sum;
}

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
            perimeter += perimeter_um(loop);
        }
        const double width = 2.0 * area / perimeter;
        if (width < static_cast<double>(min_width_um)) continue;
        if (width > static_cast<double>(track_width_um)) {
            for (Path2& loop : geom2d::offset_of(piece, -std::llround(0.25 * width))) {
                out.push_back({StrokeKind::kFill, true, std::move(loop)});
            }
            continue;
        }
        const double step = 0.25 * static_cast<double>(track_width_um);
        // Averaged sides can leave a piece that is not a plain strip (bent, branched): only
        // the parts of a middle line inside its piece are kept.
        const auto add_middle = [&](const Path2& strip) {
            for (Path2& part : geom2d::clip_polylines({middle_of_strip(strip, step)}, piece)) {
                if (part.size() >= 2) out.push_back({StrokeKind::kFill, false, std::move(part)});
            }
        };
        if (piece.size() == 1) {
            add_middle(node.wire);
            continue;
        }
        // A ring: shrunk to a thin band around its middle, whose outer loop follows the
        // middle all round. Where the ring is narrower than the band, the band breaks into
        // strips: their middles.
        const Paths2 band = geom2d::offset_of(piece, -std::llround(kMiddleShrink * width));
        const geom2d::WireTree bands = geom2d::build_wire_tree(band, geom2d::FillRule::kNonZero);
        for (const geom2d::WireNode& b : bands.nodes) {
            if (b.is_hole) continue;
            if (b.children.empty()) {
                add_middle(b.wire);
            } else {
                out.push_back({StrokeKind::kFill, true, b.wire});
            }
        }
    }
    return out;
}

}  // namespace maxslice::path::detail
