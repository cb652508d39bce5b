// Uncovered area by row integration: see uncovered_area_mm2 in polygon.hpp.
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "maxslice/core/units.hpp"
#include "maxslice/geom2d/polygon.hpp"

namespace maxslice::geom2d {
namespace {

using Interval = std::pair<double, double>;

// A straight piece of boundary or of a track centre line, in doubles.
struct Segment {
    double ax, ay, bx, by;
};

// The x-interval where the row y = yc meets the disc of radius r swept along segment s (a
// convex capsule, so the meeting is one interval); false when it misses.
bool capsule_row(const Segment& s, double r, double yc, Interval& out) {
    double lo = 1e300, hi = -1e300;
    const auto disc = [&](double cx, double cy) {
        const double dy = yc - cy;
        if (std::abs(dy) > r) return;
        const double half = std::sqrt(r * r - dy * dy);
        lo = std::min(lo, cx - half);
        hi = std::max(hi, cx + half);
    };
    disc(s.ax, s.ay);
    disc(s.bx, s.by);
    // The rectangle between the two end discs: points whose projection falls inside the
    // segment and whose distance to its line is at most r. On the row its trace is the
    // intersection of two slabs along x.
    const double dx = s.bx - s.ax, dy = s.by - s.ay;
    const double len2 = dx * dx + dy * dy;
    if (len2 > 0.0) {
        // Slab 1: 0 <= (p - a) . d <= len2, with p = (x, yc); slab 2: |(p - a) x d| <= r |d|.
        double x0 = -1e300, x1 = 1e300;
        const auto slab = [&](double coef, double rest, double lower, double upper) {
            // lower <= coef * x + rest <= upper
            if (coef == 0.0) {
                if (rest < lower || rest > upper) x1 = -1e300;
                return;
            }
            double u = (lower - rest) / coef, v = (upper - rest) / coef;
            if (u > v) std::swap(u, v);
            x0 = std::max(x0, u);
            x1 = std::min(x1, v);
        };
        const double py = yc - s.ay;
        slab(dx, -s.ax * dx + py * dy, 0.0, len2);
        const double rl = r * std::sqrt(len2);
        slab(-dy, s.ax * dy + py * dx, -rl, rl);
        if (x0 <= x1) {
            lo = std::min(lo, x0);
            hi = std::max(hi, x1);
        }
    }
    if (lo > hi) return false;
    out = {lo, hi};
    return true;
}

// Sorts and merges intervals in place.
void merge(std::vector<Interval>& v) {
    std::sort(v.begin(), v.end());
    std::size_t n = 0;
    for (const Interval& i : v) {
        if (n > 0 && i.first <= v[n - 1].second) {
            v[n - 1].second = std::max(v[n - 1].second, i.second);
        } else {
            v[n++] = i;
        }
    }
    v.resize(n);
}

// Length of a minus b, both merged.
double difference_length(const std::vector<Interval>& a, const std::vector<Interval>& b) {
    double sum = 0.0;
    std::size_t j = 0;
    for (const Interval& i : a) {
        double at = i.first;
        while (j < b.size() && b[j].second <= at) ++j;
        for (std::size_t k = j; k < b.size() && b[k].first < i.second; ++k) {
            if (b[k].first > at) sum += b[k].first - at;
            at = std::max(at, b[k].second);
            if (at >= i.second) break;
        }
        if (at < i.second) sum += i.second - at;
    }
    return sum;
}

}  // namespace

double uncovered_area_mm2(const Paths2& region, const Paths2& polylines, std::int64_t radius_um,
                          std::int64_t row_um) {
    if (row_um <= 0) row_um = 1;
    // Rows span the region's y range.
    std::int64_t ymin = INT64_MAX, ymax = INT64_MIN;
    for (const Path2& p : region) {
        if (p.size() < 3) continue;
        for (const Point2& q : p) {
            ymin = std::min(ymin, q.y);
            ymax = std::max(ymax, q.y);
        }
    }
    if (ymin >= ymax) return 0.0;
    // Rows of at most row_um that divide the y range evenly (no partial row at the top).
    const double range = static_cast<double>(ymax - ymin);
    const auto rows = static_cast<std::size_t>(std::ceil(range / static_cast<double>(row_um)));
    const double step = range / static_cast<double>(rows);
    const double y0 = static_cast<double>(ymin);
    const auto row_y = [&](std::size_t k) { return y0 + (static_cast<double>(k) + 0.5) * step; };
    // Rows whose centre lies in [lo, hi].
    const auto row_range = [&](double lo, double hi) -> std::pair<std::size_t, std::size_t> {
        const double a = std::ceil((lo - y0) / step - 0.5);
        const double b = std::floor((hi - y0) / step - 0.5);
        const double last = static_cast<double>(rows) - 1.0;
        return {static_cast<std::size_t>(std::clamp(a, 0.0, last + 1.0)),
                static_cast<std::size_t>(std::clamp(b + 1.0, 0.0, last + 1.0))};
    };

    // Bucket boundary edges and track segments by the rows they meet.
    std::vector<std::vector<std::pair<Segment, int>>> edges(rows);  // edge, winding +-1
    for (const Path2& p : region) {
        if (p.size() < 3) continue;
        for (std::size_t i = 0; i < p.size(); ++i) {
            const Point2 a = p[i], b = p[(i + 1) % p.size()];
            if (a.y == b.y) continue;
            const Segment s{static_cast<double>(a.x), static_cast<double>(a.y),
                            static_cast<double>(b.x), static_cast<double>(b.y)};
            const auto [k0, k1] = row_range(std::min(s.ay, s.by), std::max(s.ay, s.by));
            // Left to right, a counter-clockwise loop is entered across an edge going down.
            for (std::size_t k = k0; k < k1; ++k) edges[k].push_back({s, b.y < a.y ? 1 : -1});
        }
    }
    const double r = static_cast<double>(radius_um);
    std::vector<std::vector<Segment>> tracks(rows);
    for (const Path2& p : polylines) {
        for (std::size_t i = 0; i < p.size(); ++i) {
            const Point2 a = p[i], b = p[std::min(i + 1, p.size() - 1)];
            if (i + 1 == p.size() && p.size() > 1) break;  // the last point ends a segment
            const Segment s{static_cast<double>(a.x), static_cast<double>(a.y),
                            static_cast<double>(b.x), static_cast<double>(b.y)};
            const auto [k0, k1] = row_range(std::min(s.ay, s.by) - r, std::max(s.ay, s.by) + r);
            for (std::size_t k = k0; k < k1; ++k) tracks[k].push_back(s);
        }
    }

    double uncovered = 0.0;
    std::vector<std::pair<double, int>> crossings;
    std::vector<Interval> inside, covered;
    for (std::size_t k = 0; k < rows; ++k) {
        const double y = row_y(k);
        crossings.clear();
        for (const auto& [s, w] : edges[k]) {
            if ((s.ay <= y) == (s.by <= y)) continue;
            const double t = (y - s.ay) / (s.by - s.ay);
            crossings.push_back({s.ax + t * (s.bx - s.ax), w});
        }
        if (crossings.empty()) continue;
        std::sort(crossings.begin(), crossings.end());
        inside.clear();
        int winding = 0;
        for (std::size_t i = 0; i < crossings.size(); ++i) {
            const int before = winding;
            winding += crossings[i].second;
            if (before <= 0 && winding > 0) inside.push_back({crossings[i].first, 0.0});
            if (before > 0 && winding <= 0) inside.back().second = crossings[i].first;
        }
        if (!inside.empty() && winding > 0) inside.pop_back();  // unbalanced input
        covered.clear();
        Interval iv;
        for (const Segment& s : tracks[k]) {
            if (capsule_row(s, r, y, iv)) covered.push_back(iv);
        }
        merge(covered);
        uncovered += difference_length(inside, covered);
    }
    return uncovered * step / (core::kMicronsPerMm * core::kMicronsPerMm);
}

}  // namespace maxslice::geom2d
