#include "raster.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

#include "maxslice/core/assert.hpp"
#include "maxslice/geom2d/wire_tree.hpp"

namespace maxslice::path::detail {
namespace {

using geom2d::Path2;
using geom2d::Paths2;
using geom2d::Point2;

// Scan lines keep this far inside the fill region's lowest and highest points, so that the
// extreme lines cross its boundary instead of running along a horizontal edge or touching a
// single vertex.
constexpr std::int64_t kLineInsetUm = 5;

// 128-bit integers (a GCC/Clang extension) for exact orientation tests and products of
// coordinates; __extension__ keeps -Wpedantic quiet.
__extension__ typedef __int128 Int128;

std::int64_t round_half_away(double v) {
    return static_cast<std::int64_t>(v >= 0.0 ? v + 0.5 : v - 0.5);
}

Int128 cross(Point2 o, Point2 a, Point2 b) {
    return static_cast<Int128>(a.x - o.x) * (b.y - o.y) -
           static_cast<Int128>(a.y - o.y) * (b.x - o.x);
}

double distance(Point2 a, Point2 b) {
    const double dx = static_cast<double>(b.x - a.x);
    const double dy = static_cast<double>(b.y - a.y);
    return std::sqrt(dx * dx + dy * dy);
}

// floor(a / b) for b > 0.
std::int64_t floor_div(std::int64_t a, std::int64_t b) {
    const std::int64_t q = a / b;
    return (a % b != 0 && a < 0) ? q - 1 : q;
}

// a / b rounded to nearest (halves up), b > 0, exact.
std::int64_t round_div(Int128 a, Int128 b) {
    const Int128 n = 2 * a + b;
    const Int128 d = 2 * b;
    Int128 q = n / d;
    if (n % d != 0 && n < 0) --q;
    return static_cast<std::int64_t>(q);
}

// Where a scan line meets a loop of the fill region.
struct Crossing {
    std::int64_t x = 0;
    int line = 0;
    int loop = 0;
    int edge = 0;            // the edge from vertex `edge` to vertex `edge + 1`
    std::int64_t along = 0;  // position along the edge, increasing in the edge's direction
    int order = 0;           // index in its loop's crossing order
    int seg = -1;            // the segment it ends, -1 when none
    bool right = false;      // the segment's right (exit) end
};

struct Segment {
    int line = 0;
    int left = 0;  // crossing ids
    int right = 0;
};

// A link found from the end of one segment to the entry of the next line's segment.
struct Link {
    int seg = -1;
    bool entry_right = false;  // enters the next segment at its right end
    Path2 via;                 // points after the exit point, ending at the entry point
};

// The scan lines of a fill region: count lines y0, y0 + spacing, ...
struct Lines {
    std::int64_t y0 = 0;
    std::int64_t spacing = 0;
    int count = 0;
};

// The region's lowest and highest points (ymin >= ymax: no area).
std::pair<std::int64_t, std::int64_t> y_extent(const Paths2& loops) {
    std::int64_t ymin = INT64_MAX;
    std::int64_t ymax = INT64_MIN;
    for (const Path2& loop : loops) {
        if (loop.size() < 3) continue;
        for (const Point2& p : loop) {
            ymin = std::min(ymin, p.y);
            ymax = std::max(ymax, p.y);
        }
    }
    return {ymin, ymax};
}

// As few lines as keep every spacing at most the pitch p with the extreme lines at most m
// inside the region's extremes ymin and ymax: at the pitch and centred when the leftover fits in
// the two margins, else spread evenly from extreme to extreme (a little closer than the pitch). A
// region thinner than 2 m gets one line along its middle.
std::optional<Lines> place_lines(std::int64_t ymin, std::int64_t ymax, std::int64_t p,
                                 std::int64_t m) {
    if (ymin >= ymax) return std::nullopt;
    const std::int64_t lo = ymin + kLineInsetUm;
    const std::int64_t hi = ymax - kLineInsetUm;
    const std::int64_t range = hi - lo;
    const std::int64_t gaps = range > 2 * m ? (range - 2 * m + p - 1) / p : 0;
    Lines out;
    if (gaps == 0) {
        out.y0 = ymin + (ymax - ymin) / 2;
        out.spacing = p;
    } else if (gaps * p >= range) {
        out.y0 = lo;
        out.spacing = range / gaps;  // rounded down: the last line is < gaps um short of hi
    } else {
        out.y0 = lo + (range - gaps * p) / 2;
        out.spacing = p;
    }
    out.count = static_cast<int>(gaps) + 1;
    return out;
}

// Shelves of the fill region where its lines leave a sliver: a run of edges at least a pitch
// long, level within a quarter of the margin m, strictly between the region's extremes (the
// top of a wall beside a boss standing on it, a step), whose nearest line on the region's
// side lies more than m from it. A line there runs up to a pitch short of the contour's
// track along the shelf, and a gap narrower than the gap fill takes is left bare. Returns
// the heights to cut at (a run's lowest point where the region lies below it, its highest
// where above), sorted, at most max_cuts of them (the longest runs).
std::vector<std::int64_t> sliver_shelves(const Paths2& loops, std::int64_t ymin, std::int64_t ymax,
                                         const Lines& lines, std::int64_t p, std::int64_t m,
                                         std::size_t max_cuts) {
    const std::int64_t level = std::max<std::int64_t>(m / 4, 1);
    std::vector<std::pair<std::int64_t, std::int64_t>> found;  // (length, y)
    const auto consider = [&](std::int64_t length, std::int64_t lo, std::int64_t hi, bool below) {
        const std::int64_t y = below ? lo : hi;
        if (length < p || lo <= ymin + m || hi >= ymax - m) return;
        const std::int64_t k = floor_div(y - lines.y0, lines.spacing);
        const std::int64_t line =
            below ? lines.y0 + k * lines.spacing : lines.y0 + (k + 1) * lines.spacing;
        if (std::abs(y - line) > m + kLineInsetUm) found.emplace_back(length, y);
    };
    for (const Path2& loop : loops) {
        const std::size_t n = loop.size();
        if (n < 3) continue;
        // Runs of consecutive edges all heading one way along x within the level band. The
        // region lies left of its edges (outer loops counter-clockwise, holes clockwise): a
        // run heading towards -x has it below.
        std::int64_t x0 = 0, lo = 0, hi = 0, length = 0;
        int heading = 0;
        for (std::size_t e = 0; e < n; ++e) {
            const Point2 a = loop[e];
            const Point2 b = loop[(e + 1) % n];
            const int h = b.x > a.x ? 1 : (b.x < a.x ? -1 : 0);
            const bool extends =
                heading != 0 && h == heading && std::max(hi, b.y) - std::min(lo, b.y) <= level;
            if (extends) {
                lo = std::min(lo, b.y);
                hi = std::max(hi, b.y);
                length = std::abs(b.x - x0);
                continue;
            }
            if (heading != 0) consider(length, lo, hi, heading < 0);
            heading = (h != 0 && std::abs(b.y - a.y) <= level) ? h : 0;
            x0 = a.x;
            lo = std::min(a.y, b.y);
            hi = std::max(a.y, b.y);
            length = std::abs(b.x - a.x);
        }
        if (heading != 0) consider(length, lo, hi, heading < 0);
    }
    std::sort(found.begin(), found.end(), std::greater<>());
    std::vector<std::int64_t> ys;
    for (const auto& [length, y] : found) {
        if (ys.size() >= max_cuts) break;
        if (std::find(ys.begin(), ys.end(), y) == ys.end()) ys.push_back(y);
    }
    std::sort(ys.begin(), ys.end());
    return ys;
}

class Zigzag {
public:
    // The fill of in's region along `lines` (place_lines of it).
    Zigzag(const ZigzagInput& in, const Lines& lines)
        : in_(in),
          loops_(*in.fill_region),
          y0_(lines.y0),
          spacing_(lines.spacing),
          line_count_(lines.count) {}

    Paths2 run() {
        cross_lines();
        make_segments();
        order_along_loops();
        index_link_region();
        return chain();
    }

private:
    [[nodiscard]] std::int64_t line_y(int k) const { return y0_ + k * spacing_; }

    void cross_lines() {
        const std::int64_t p = spacing_;
        for (int l = 0; l < static_cast<int>(loops_.size()); ++l) {
            const Path2& loop = loops_[static_cast<std::size_t>(l)];
            const std::size_t m = loop.size();
            if (m < 3) continue;
            for (std::size_t e = 0; e < m; ++e) {
                const Point2 a = loop[e];
                const Point2 b = loop[(e + 1) % m];
                if (a.y == b.y) continue;
                // Half-open rule: the edge crosses line y when min <= y < max, so a vertex on
                // a line counts once for a crossing and never for a touch.
                const std::int64_t lo = std::min(a.y, b.y);
                const std::int64_t hi = std::max(a.y, b.y);
                const std::int64_t k0 = std::max<std::int64_t>(0, -floor_div(y0_ - lo, p));
                const std::int64_t k1 =
                    std::min<std::int64_t>(line_count_ - 1, -floor_div(y0_ - hi, p) - 1);
                for (std::int64_t k = k0; k <= k1; ++k) {
                    const std::int64_t y = line_y(static_cast<int>(k));
                    Int128 num = static_cast<Int128>(y - a.y) * (b.x - a.x);
                    Int128 den = b.y - a.y;
                    if (den < 0) {
                        num = -num;
                        den = -den;
                    }
                    Crossing c;
                    c.x = a.x + round_div(num, den);
                    c.line = static_cast<int>(k);
                    c.loop = l;
                    c.edge = static_cast<int>(e);
                    c.along = a.y < b.y ? y : -y;
                    crossings_.push_back(c);
                }
            }
        }
    }

    void make_segments() {
        // Counting sort by line, then by x (loop and edge break ties deterministically).
        std::vector<int> start(static_cast<std::size_t>(line_count_) + 1, 0);
        for (const Crossing& c : crossings_) ++start[static_cast<std::size_t>(c.line) + 1];
        for (std::size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
        std::vector<int> by_line(crossings_.size());
        {
            std::vector<int> fill(start.begin(), start.end() - 1);
            for (int i = 0; i < static_cast<int>(crossings_.size()); ++i) {
                by_line[static_cast<std::size_t>(fill[static_cast<std::size_t>(
                    crossings_[static_cast<std::size_t>(i)].line)]++)] = i;
            }
        }
        line_segments_.assign(static_cast<std::size_t>(line_count_) + 1, 0);
        for (int k = 0; k < line_count_; ++k) {
            line_segments_[static_cast<std::size_t>(k)] = static_cast<int>(segments_.size());
            const auto b = by_line.begin() + start[static_cast<std::size_t>(k)];
            const auto e = by_line.begin() + start[static_cast<std::size_t>(k) + 1];
            std::sort(b, e, [&](int i, int j) {
                const Crossing& ci = crossings_[static_cast<std::size_t>(i)];
                const Crossing& cj = crossings_[static_cast<std::size_t>(j)];
                if (ci.x != cj.x) return ci.x < cj.x;
                if (ci.loop != cj.loop) return ci.loop < cj.loop;
                return ci.edge < cj.edge;
            });
            // Closed loops cross every line an even number of times.
            MAXSLICE_ASSERT((e - b) % 2 == 0);
            for (auto it = b; it + 1 < e; it += 2) {
                Crossing& l = crossings_[static_cast<std::size_t>(*it)];
                Crossing& r = crossings_[static_cast<std::size_t>(*(it + 1))];
                if (r.x <= l.x) continue;
                const int id = static_cast<int>(segments_.size());
                segments_.push_back({k, *it, *(it + 1)});
                l.seg = id;
                r.seg = id;
                r.right = true;
            }
        }
        line_segments_[static_cast<std::size_t>(line_count_)] = static_cast<int>(segments_.size());
    }

    void order_along_loops() {
        loop_order_.assign(loops_.size(), {});
        for (int i = 0; i < static_cast<int>(crossings_.size()); ++i) {
            loop_order_[static_cast<std::size_t>(crossings_[static_cast<std::size_t>(i)].loop)]
                .push_back(i);
        }
        for (auto& order : loop_order_) {
            std::sort(order.begin(), order.end(), [&](int i, int j) {
                const Crossing& ci = crossings_[static_cast<std::size_t>(i)];
                const Crossing& cj = crossings_[static_cast<std::size_t>(j)];
                if (ci.edge != cj.edge) return ci.edge < cj.edge;
                return ci.along < cj.along;
            });
            for (int k = 0; k < static_cast<int>(order.size()); ++k) {
                crossings_[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])].order = k;
            }
        }
    }

    [[nodiscard]] Point2 point(int crossing) const {
        const Crossing& c = crossings_[static_cast<std::size_t>(crossing)];
        return {c.x, line_y(c.line)};
    }

    [[nodiscard]] const Crossing& crossing(int id) const {
        return crossings_[static_cast<std::size_t>(id)];
    }

    [[nodiscard]] const Segment& segment(int id) const {
        return segments_[static_cast<std::size_t>(id)];
    }

    // The boundary of the crossings' loop from crossing `from` to its neighbour `to` in the
    // loop order (forward or backward), if not longer than the link limit.
    std::optional<Path2> boundary_arc(int from, int to, bool forward) const {
        const Crossing& a = crossing(from);
        const Crossing& b = crossing(to);
        const Path2& loop = loops_[static_cast<std::size_t>(a.loop)];
        const int m = static_cast<int>(loop.size());
        int count = forward ? b.edge - a.edge : a.edge - b.edge;
        if (forward ? b.order < a.order : b.order > a.order) count += m;
        Path2 via;
        Point2 last = point(from);
        double length = 0.0;
        const auto add = [&](Point2 p) {
            length += distance(last, p);
            if (p != last) via.push_back(p);
            last = p;
        };
        for (int j = 0; j < count; ++j) {
            const int v = forward ? (a.edge + 1 + j) % m : ((a.edge - j) % m + m) % m;
            add(loop[static_cast<std::size_t>(v)]);
            if (length > static_cast<double>(in_.max_link_um)) return std::nullopt;
        }
        add(point(to));
        if (length > static_cast<double>(in_.max_link_um)) return std::nullopt;
        return via;
    }

    // Buckets the link region's edges by the band between two neighbouring lines they touch,
    // so that checking a straight link looks at its band's edges only.
    void index_link_region() {
        band_edges_.assign(static_cast<std::size_t>(std::max(line_count_ - 1, 0)), {});
        if (band_edges_.empty()) return;
        const std::int64_t s = spacing_;
        const std::int64_t last = line_count_ - 2;
        for (const Path2& loop : *in_.link_region) {
            const std::size_t m = loop.size();
            for (std::size_t i = 0; i < m; ++i) {
                const Point2 p = loop[i];
                const Point2 q = loop[(i + 1) % m];
                const std::int64_t lo = std::min(p.y, q.y);
                const std::int64_t hi = std::max(p.y, q.y);
                // Bands k with y_k <= hi and y_{k+1} >= lo.
                const std::int64_t k0 = std::max<std::int64_t>(0, -floor_div(y0_ - lo, s) - 1);
                const std::int64_t k1 = std::min(last, floor_div(hi - y0_, s));
                for (std::int64_t k = k0; k <= k1; ++k) {
                    band_edges_[static_cast<std::size_t>(k)].push_back({p, q});
                }
            }
        }
    }

    // True when the straight segment from a (on line k) to b (on line k + 1) stays inside the
    // link region (boundary included). a and b are inside or on it; without a proper crossing
    // of (or a vertex strictly on) the segment, the whole segment is on one side, which its
    // midpoint tells (winding number over the band's edges: the others cannot cross its y).
    [[nodiscard]] bool straight_inside(Point2 a, Point2 b, int k) const {
        const std::int64_t x0 = std::min(a.x, b.x);
        const std::int64_t x1 = std::max(a.x, b.x);
        const std::int64_t y0 = std::min(a.y, b.y);
        const std::int64_t y1 = std::max(a.y, b.y);
        const auto& edges = band_edges_[static_cast<std::size_t>(k)];
        for (const auto& [p, q] : edges) {
            if (std::max(p.x, q.x) < x0 || std::min(p.x, q.x) > x1 || std::max(p.y, q.y) < y0 ||
                std::min(p.y, q.y) > y1) {
                continue;
            }
            const Int128 o1 = cross(a, b, p);
            const Int128 o2 = cross(a, b, q);
            const Int128 o3 = cross(p, q, a);
            const Int128 o4 = cross(p, q, b);
            if (((o1 < 0 && o2 > 0) || (o1 > 0 && o2 < 0)) &&
                ((o3 < 0 && o4 > 0) || (o3 > 0 && o4 < 0))) {
                return false;
            }
            if (o1 == 0 && p != a && p != b && p.x >= x0 && p.x <= x1 && p.y >= y0 && p.y <= y1) {
                return false;
            }
        }
        const Point2 mid{a.x + (b.x - a.x) / 2, a.y + (b.y - a.y) / 2};
        long winding = 0;
        for (const auto& [p, q] : edges) {
            const Int128 c = cross(p, q, mid);
            if (c == 0 && std::min(p.x, q.x) <= mid.x && mid.x <= std::max(p.x, q.x) &&
                std::min(p.y, q.y) <= mid.y && mid.y <= std::max(p.y, q.y)) {
                return true;  // on the boundary
            }
            if (p.y <= mid.y) {
                if (q.y > mid.y && c > 0) ++winding;
            } else if (q.y <= mid.y && c < 0) {
                --winding;
            }
        }
        return winding != 0;
    }

    // A link from segment s's exit end (right or left) to an unclaimed segment of the next
    // line: along the boundary when the exit's loop neighbour is the same-side end of such a
    // segment, else straight to the extreme overlapping segment on the exit side when that
    // stays inside the link region. Links longer than the limit are refused.
    std::optional<Link> find_link(int s, bool exit_right) const {
        const Segment& seg = segment(s);
        if (seg.line + 1 >= line_count_) return std::nullopt;
        const int exit = exit_right ? seg.right : seg.left;
        const Crossing& e = crossing(exit);
        const auto& order = loop_order_[static_cast<std::size_t>(e.loop)];
        const int n = static_cast<int>(order.size());
        for (const bool forward : {true, false}) {
            const int nb = order[static_cast<std::size_t>((e.order + (forward ? 1 : n - 1)) % n)];
            const Crossing& c = crossing(nb);
            if (c.line != seg.line + 1 || c.seg < 0 || claimed_[static_cast<std::size_t>(c.seg)] ||
                c.right != exit_right) {
                continue;
            }
            if (auto via = boundary_arc(exit, nb, forward)) {
                return Link{c.seg, exit_right, std::move(*via)};
            }
        }
        // Straight: the overlapping segment of the next line furthest on the exit side.
        const int b = line_segments_[static_cast<std::size_t>(seg.line) + 1];
        const int end = line_segments_[static_cast<std::size_t>(seg.line) + 2];
        const std::int64_t sx0 = crossing(seg.left).x;
        const std::int64_t sx1 = crossing(seg.right).x;
        int t = -1;
        if (exit_right) {
            // Last segment starting left of s's right end.
            int lo = b;
            int hi = end;
            while (lo < hi) {
                const int mid = (lo + hi) / 2;
                if (crossing(segment(mid).left).x < sx1) {
                    lo = mid + 1;
                } else {
                    hi = mid;
                }
            }
            if (lo > b && crossing(segment(lo - 1).right).x > sx0) t = lo - 1;
        } else {
            // First segment ending right of s's left end.
            int lo = b;
            int hi = end;
            while (lo < hi) {
                const int mid = (lo + hi) / 2;
                if (crossing(segment(mid).right).x > sx0) {
                    hi = mid;
                } else {
                    lo = mid + 1;
                }
            }
            if (lo < end && crossing(segment(lo).left).x < sx1) t = lo;
        }
        if (t < 0 || claimed_[static_cast<std::size_t>(t)]) return std::nullopt;
        const Point2 from = point(exit);
        const Point2 to = point(exit_right ? segment(t).right : segment(t).left);
        if (distance(from, to) > static_cast<double>(in_.max_link_um)) return std::nullopt;
        if (!straight_inside(from, to, seg.line)) return std::nullopt;
        return Link{t, exit_right, Path2{to}};
    }

    Paths2 chain() {
        claimed_.assign(segments_.size(), false);
        Paths2 out;
        const auto append = [](Path2& path, Point2 p) {
            if (path.empty() || path.back() != p) path.push_back(p);
        };
        for (int s = 0; s < static_cast<int>(segments_.size()); ++s) {
            if (claimed_[static_cast<std::size_t>(s)]) continue;
            claimed_[static_cast<std::size_t>(s)] = true;
            bool exit_right = true;
            std::optional<Link> link = find_link(s, true);
            if (!link) {
                link = find_link(s, false);
                if (link) exit_right = false;
            }
            Path2 path;
            const Segment& first = segment(s);
            append(path, point(exit_right ? first.left : first.right));
            append(path, point(exit_right ? first.right : first.left));
            while (link) {
                claimed_[static_cast<std::size_t>(link->seg)] = true;
                for (const Point2& p : link->via) append(path, p);
                const Segment& t = segment(link->seg);
                exit_right = !link->entry_right;
                append(path, point(exit_right ? t.right : t.left));
                link = find_link(link->seg, exit_right);
            }
            out.push_back(std::move(path));
        }
        return out;
    }

    const ZigzagInput& in_;
    const Paths2& loops_;
    std::int64_t y0_ = 0;
    std::int64_t spacing_ = 1;
    int line_count_ = 0;
    std::vector<Crossing> crossings_;
    std::vector<Segment> segments_;
    std::vector<int> line_segments_;  // first segment of each line, then the total
    std::vector<std::vector<int>> loop_order_;
    std::vector<bool> claimed_;
    std::vector<std::vector<std::pair<Point2, Point2>>> band_edges_;  // per band between lines
};

}  // namespace

RasterFrame::RasterFrame(double angle_rad) {
    const geom2d::PlaneTurn turn = geom2d::plane_turn(angle_rad);
    c_ = turn.c;
    s_ = turn.s;
}

Point2 RasterFrame::to_raster(Point2 p) const {
    const double x = static_cast<double>(p.x);
    const double y = static_cast<double>(p.y);
    return {round_half_away(c_ * x + s_ * y), round_half_away(-s_ * x + c_ * y)};
}

Point2 RasterFrame::from_raster(Point2 p) const {
    const double x = static_cast<double>(p.x);
    const double y = static_cast<double>(p.y);
    return {round_half_away(c_ * x - s_ * y), round_half_away(s_ * x + c_ * y)};
}

Paths2 RasterFrame::to_raster(const Paths2& paths) const {
    Paths2 out;
    out.reserve(paths.size());
    for (const Path2& path : paths) {
        Path2& o = out.emplace_back();
        o.reserve(path.size());
        for (const Point2& p : path) o.push_back(to_raster(p));
    }
    return out;
}

Path2 RasterFrame::from_raster(const Path2& path) const {
    Path2 out;
    out.reserve(path.size());
    for (const Point2& p : path) out.push_back(from_raster(p));
    return out;
}

namespace {

// Shelves cut per band, and how many times a band is cut again (each cut band places its
// lines afresh, which may leave a sliver at another shelf).
constexpr std::size_t kMaxShelfCuts = 4;
constexpr int kMaxShelfDepth = 2;

Paths2 zigzag_bands(const ZigzagInput& in, int depth) {
    const auto [ymin, ymax] = y_extent(*in.fill_region);
    const std::optional<Lines> lines = place_lines(ymin, ymax, in.pitch_um, in.max_margin_um);
    if (!lines) return {};
    const std::vector<std::int64_t> cuts =
        depth > 0 ? sliver_shelves(*in.fill_region, ymin, ymax, *lines, in.pitch_um,
                                   in.max_margin_um, kMaxShelfCuts)
                  : std::vector<std::int64_t>{};
    if (cuts.empty()) return Zigzag(in, *lines).run();
    // Band by band, bottom up: each places its lines between its own extremes, so the
    // shelf is one of them and its line lies within the margin.
    std::int64_t xmin = INT64_MAX;
    std::int64_t xmax = INT64_MIN;
    for (const Path2& loop : *in.fill_region) {
        for (const Point2& q : loop) {
            xmin = std::min(xmin, q.x);
            xmax = std::max(xmax, q.x);
        }
    }
    Paths2 out;
    std::int64_t lo = ymin - 1;
    for (std::size_t k = 0; k <= cuts.size(); ++k) {
        const std::int64_t hi = k < cuts.size() ? cuts[k] : ymax + 1;
        const Paths2 band = geom2d::intersection_of(
            *in.fill_region,
            {Path2{{xmin - 1, lo}, {xmax + 1, lo}, {xmax + 1, hi}, {xmin - 1, hi}}});
        lo = hi;
        if (band.empty()) continue;
        ZigzagInput sub = in;
        sub.fill_region = &band;
        for (Path2& line : zigzag_bands(sub, depth - 1)) out.push_back(std::move(line));
    }
    return out;
}

}  // namespace

Paths2 zigzag_fill(const ZigzagInput& in) {
    MAXSLICE_ASSERT(in.fill_region != nullptr && in.link_region != nullptr && in.pitch_um > 0);
    return zigzag_bands(in, kMaxShelfDepth);
}

}  // namespace maxslice::path::detail
