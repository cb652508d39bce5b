#include "region_distance.hpp"

#include <algorithm>
#include <cmath>

namespace maxslice::plan::detail {
namespace {

// Rows of edges for the winding number: about this many edges per row on average.
constexpr double kEdgesPerRow = 4.0;
constexpr std::size_t kMaxRows = 4096;

}  // namespace

RegionDistance::RegionDistance(const geom2d::Paths2& region) {
    for (const geom2d::Path2& path : region) {
        for (std::size_t i = 0; i < path.size(); ++i) {
            const double ax = static_cast<double>(path[i].x), ay = static_cast<double>(path[i].y);
            const geom2d::Point2 q = path[(i + 1) % path.size()];
            edges_.push_back(
                {ax, ay, static_cast<double>(q.x) - ax, static_cast<double>(q.y) - ay});
        }
    }
    if (edges_.empty()) return;
    std::vector<core::Vec3d> lo(edges_.size()), hi(edges_.size());
    double y_lo = INFINITY, y_hi = -INFINITY;
    for (std::size_t i = 0; i < edges_.size(); ++i) {
        const Edge& e = edges_[i];
        const double bx = e.ax + e.dx, by = e.ay + e.dy;
        lo[i] = {std::min(e.ax, bx), std::min(e.ay, by), 0.0};
        hi[i] = {std::max(e.ax, bx), std::max(e.ay, by), 0.0};
        y_lo = std::min(y_lo, lo[i].y);
        y_hi = std::max(y_hi, hi[i].y);
    }
    tree_ = BoxTree(lo, hi);
    // Rows: an edge is listed in every row its y range touches; a point's row then lists
    // every edge that can cross the horizontal line through it.
    const auto rows = std::clamp<std::size_t>(
        static_cast<std::size_t>(static_cast<double>(edges_.size()) / kEdgesPerRow), 1, kMaxRows);
    y0_ = y_lo;
    row_ = std::max((y_hi - y_lo) / static_cast<double>(rows), 1.0);
    const auto row_of = [&](double y) {
        const double r = std::floor((y - y0_) / row_);
        return static_cast<std::size_t>(std::clamp(r, 0.0, static_cast<double>(rows - 1)));
    };
    row_begin_.assign(rows + 1, 0);
    for (std::size_t i = 0; i < edges_.size(); ++i) {
        for (std::size_t r = row_of(lo[i].y); r <= row_of(hi[i].y); ++r) ++row_begin_[r + 1];
    }
    for (std::size_t r = 0; r < rows; ++r) row_begin_[r + 1] += row_begin_[r];
    row_edges_.resize(row_begin_[rows]);
    std::vector<std::uint32_t> fill(row_begin_.begin(), row_begin_.end() - 1);
    for (std::size_t i = 0; i < edges_.size(); ++i) {
        for (std::size_t r = row_of(lo[i].y); r <= row_of(hi[i].y); ++r) {
            row_edges_[fill[r]++] = static_cast<std::uint32_t>(i);
        }
    }
}

std::optional<geom2d::ClosestPoint> RegionDistance::closest(geom2d::Centroid2 p,
                                                            double limit_um) const {
    if (edges_.empty()) return std::nullopt;
    // The winding number (geom2d's crossing rule): only edges whose y range holds p.y count,
    // and all of them are in p's row.
    const double r = std::floor((p.y - y0_) / row_);
    const auto rows = row_begin_.size() - 1;
    const auto row = static_cast<std::size_t>(std::clamp(r, 0.0, static_cast<double>(rows - 1)));
    long winding = 0;
    for (std::uint32_t k = row_begin_[row]; k < row_begin_[row + 1]; ++k) {
        const Edge& e = edges_[row_edges_[k]];
        const double c = e.dx * (p.y - e.ay) - (p.x - e.ax) * e.dy;
        if (e.ay <= p.y) {
            if (e.ay + e.dy > p.y && c > 0.0) ++winding;
        } else if (e.ay + e.dy <= p.y && c < 0.0) {
            --winding;
        }
    }
    if (winding != 0) return geom2d::ClosestPoint{{std::llround(p.x), std::llround(p.y)}, 0.0};

    // The nearest edge: (squared distance, edge index) smallest, as the scan's first strict
    // minimum in path order. A box farther than the best so far, or than the limit, is
    // skipped (its edges are at least that far).
    double best2 = INFINITY;
    std::uint32_t best = 0;
    double bx = 0.0, by = 0.0;
    const double limit2 = limit_um * limit_um;
    tree_.visit(
        [&](const core::Vec3d& lo, const core::Vec3d& hi) {
            const double gx = std::max({lo.x - p.x, 0.0, p.x - hi.x});
            const double gy = std::max({lo.y - p.y, 0.0, p.y - hi.y});
            const double g2 = gx * gx + gy * gy;
            return g2 <= best2 && g2 < limit2;
        },
        [&](std::uint32_t i) {
            const Edge& e = edges_[i];
            const double len2 = e.dx * e.dx + e.dy * e.dy;
            double t = len2 > 0.0 ? ((p.x - e.ax) * e.dx + (p.y - e.ay) * e.dy) / len2 : 0.0;
            t = std::clamp(t, 0.0, 1.0);
            const double cx = e.ax + t * e.dx, cy = e.ay + t * e.dy;
            const double d2 = (p.x - cx) * (p.x - cx) + (p.y - cy) * (p.y - cy);
            if (d2 < best2 || (d2 == best2 && i < best)) {
                best2 = d2;
                best = i;
                bx = cx;
                by = cy;
            }
        });
    if (!(best2 < limit2)) return std::nullopt;
    return geom2d::ClosestPoint{{std::llround(bx), std::llround(by)}, std::sqrt(best2)};
}

}  // namespace maxslice::plan::detail
