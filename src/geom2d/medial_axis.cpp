// The only translation unit that includes Boost.Polygon's Voronoi diagram.
#include "maxslice/geom2d/medial_axis.hpp"

#include <boost/polygon/point_data.hpp>
#include <boost/polygon/segment_data.hpp>
#include <boost/polygon/voronoi.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "maxslice/geom2d/wire_tree.hpp"

namespace maxslice::geom2d {
namespace {

namespace bp = boost::polygon;
using Segment = bp::segment_data<std::int32_t>;
using Diagram = bp::voronoi_diagram<double>;

struct XY {
    double x = 0.0;
    double y = 0.0;
};

XY to_xy(const bp::point_data<std::int32_t>& p) {
    return {static_cast<double>(p.x()), static_cast<double>(p.y())};
}

double cross(XY a, XY b, XY p) {
    return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}

double distance(XY a, XY b) {
    return std::hypot(b.x - a.x, b.y - a.y);
}

// The distance from p to a cell's site: its segment (p projects inside it: the segment's
// end points are sites of their own) or its point.
double site_distance(const Diagram::cell_type& cell, const std::vector<Segment>& segs, XY p) {
    const Segment& s = segs[cell.source_index()];
    const XY a = to_xy(bp::low(s));
    const XY b = to_xy(bp::high(s));
    if (cell.contains_segment()) return std::abs(cross(a, b, p)) / distance(a, b);
    return distance(cell.source_category() == bp::SOURCE_CATEGORY_SEGMENT_START_POINT ? a : b, p);
}

// Whether p lies inside the region (or on its boundary) as seen from a segment cell:
// interior is on the left of every boundary segment. The tolerance absorbs the rounding of
// Voronoi vertices that lie on the boundary (the ends of branches into corners).
bool left_of(const Diagram::cell_type& cell, const std::vector<Segment>& segs, XY p) {
    const Segment& s = segs[cell.source_index()];
    const XY a = to_xy(bp::low(s));
    const XY b = to_xy(bp::high(s));
    return cross(a, b, p) >= -1e-6 * distance(a, b) * (1.0 + distance(a, p));
}

// The medial graph: nodes with positions and radii, undirected edges.
struct Graph {
    std::vector<XY> at;
    std::vector<double> radius;
    std::vector<std::pair<std::size_t, std::size_t>> edges;
    std::vector<char> alive;  // per edge

    std::size_t add_node(XY p, double r) {
        at.push_back(p);
        radius.push_back(r);
        return at.size() - 1;
    }
};

// Incident edges per node, over the live edges.
std::vector<std::vector<std::size_t>> incidence(const Graph& g) {
    std::vector<std::vector<std::size_t>> inc(g.at.size());
    for (std::size_t e = 0; e < g.edges.size(); ++e) {
        if (!g.alive[e]) continue;
        inc[g.edges[e].first].push_back(e);
        inc[g.edges[e].second].push_back(e);
    }
    return inc;
}

std::size_t other_end(const Graph& g, std::size_t e, std::size_t n) {
    return g.edges[e].first == n ? g.edges[e].second : g.edges[e].first;
}

// A side branch is a spur (a branch the axis sends into a convex corner) when it ends where
// the region gets narrower than the minimum and is shorter than this many radii of the
// point it hangs from (a corner of 60 degrees or more: the branch to a corner of angle t is
// r / sin(t / 2) long).
constexpr double kSpurRadii = 2.0;

// Removes spurs, round after round (a junction left with two branches joins them into one
// line, and the branches of a junction are never all removed).
void prune_spurs(Graph& g, double min_radius) {
    for (int round = 0; round < 32; ++round) {
        const auto inc = incidence(g);
        // Per junction, its leaf branches: (length, edges).
        std::vector<std::vector<std::pair<double, std::vector<std::size_t>>>> spurs(g.at.size());
        for (std::size_t leaf = 0; leaf < g.at.size(); ++leaf) {
            if (inc[leaf].size() != 1 || g.radius[leaf] > min_radius + 1.0) continue;
            std::vector<std::size_t> path_edges;
            std::size_t n = leaf;
            std::size_t e = inc[leaf][0];
            double length = 0.0;
            while (true) {
                path_edges.push_back(e);
                const std::size_t m = other_end(g, e, n);
                length += distance(g.at[n], g.at[m]);
                n = m;
                if (inc[n].size() != 2) break;
                e = inc[n][0] == e ? inc[n][1] : inc[n][0];
            }
            if (inc[n].size() < 3 || length >= kSpurRadii * g.radius[n]) continue;
            spurs[n].emplace_back(length, std::move(path_edges));
        }
        bool changed = false;
        for (std::size_t n = 0; n < g.at.size(); ++n) {
            auto& list = spurs[n];
            if (list.empty()) continue;
            if (list.size() == inc[n].size()) {  // keep the longest branch
                const auto longest = std::max_element(
                    list.begin(), list.end(),
                    [](const auto& a, const auto& b) { return a.first < b.first; });
                list.erase(longest);
            }
            for (const auto& [length, edges] : list) {
                for (const std::size_t e : edges) g.alive[e] = 0;
                changed = true;
            }
        }
        if (!changed) return;
    }
}

// How far the region is shrunk before the diagram is built (um).
constexpr std::int64_t kSeparateUm = 2;

Point2 rounded(XY p) {
    return {std::llround(p.x), std::llround(p.y)};
}

}  // namespace

std::vector<MedialLine> medial_axis(const Paths2& region_in, std::int64_t min_radius_um) {
    // Boost's diagram needs segments that meet only at their ends. Booleans may leave a hole
    // touching its outer wire in the middle of an edge, or crossing it by a rounding: shrunk
    // by a hair, such contacts come apart.
    const Paths2 region = offset_of(region_in, -kSeparateUm);
    XY lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
    XY hi{-lo.x, -lo.y};
    std::vector<Segment> segs;
    for (const Path2& loop : region) {
        for (const Point2& p : loop) {
            lo = {std::min(lo.x, static_cast<double>(p.x)),
                  std::min(lo.y, static_cast<double>(p.y))};
            hi = {std::max(hi.x, static_cast<double>(p.x)),
                  std::max(hi.y, static_cast<double>(p.y))};
        }
    }
    const auto in_box = [&](XY p) {
        return p.x >= lo.x - 1.0 && p.x <= hi.x + 1.0 && p.y >= lo.y - 1.0 && p.y <= hi.y + 1.0;
    };
    for (const Path2& loop : region) {
        if (loop.size() < 3) continue;
        for (std::size_t i = 0; i < loop.size(); ++i) {
            const Point2 a = loop[i];
            const Point2 b = loop[(i + 1) % loop.size()];
            if (a == b) continue;
            segs.emplace_back(bp::point_data<std::int32_t>(static_cast<std::int32_t>(a.x),
                                                           static_cast<std::int32_t>(a.y)),
                              bp::point_data<std::int32_t>(static_cast<std::int32_t>(b.x),
                                                           static_cast<std::int32_t>(b.y)));
        }
    }
    if (segs.size() < 3) return {};
    Diagram vd;
    bp::construct_voronoi(segs.begin(), segs.end(), &vd);

    Graph g;
    constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
    std::vector<std::size_t> node_of(vd.vertices().size(), kNone);
    const double min_r = static_cast<double>(min_radius_um);
    const auto node = [&](const Diagram::vertex_type* v, double r) {
        std::size_t& id = node_of[static_cast<std::size_t>(v - vd.vertices().data())];
        if (id == kNone) id = g.add_node({v->x(), v->y()}, r);
        return id;
    };
    for (const Diagram::edge_type& e : vd.edges()) {
        if (&e > e.twin() || !e.is_finite() || !e.is_primary()) continue;
        const Diagram::cell_type& c1 = *e.cell();
        const Diagram::cell_type& c2 = *e.twin()->cell();
        const XY p0{e.vertex0()->x(), e.vertex0()->y()};
        const XY p1{e.vertex1()->x(), e.vertex1()->y()};
        // A vertex outside the region's box comes from a diagram spoiled by input it does not
        // accept (segments crossing after all): never a track there.
        if (!in_box(p0) || !in_box(p1)) continue;
        bool inside = true;
        bool decided = false;
        for (const Diagram::cell_type* c : {&c1, &c2}) {
            if (!c->contains_segment()) continue;
            decided = true;
            inside = inside && left_of(*c, segs, p0) && left_of(*c, segs, p1);
        }
        if (!decided) {  // between two reflex vertices: the midpoint decides
            const Point2 mid = rounded({0.5 * (p0.x + p1.x), 0.5 * (p0.y + p1.y)});
            inside = locate_point(region, mid) != Containment::kOutside;
        }
        if (!inside) continue;
        const double r0 = site_distance(c1, segs, p0);
        const double r1 = site_distance(c1, segs, p1);
        if (r0 < min_r && r1 < min_r) continue;
        std::size_t n0 = 0;
        std::size_t n1 = 0;
        if (r0 >= min_r && r1 >= min_r) {
            n0 = node(e.vertex0(), r0);
            n1 = node(e.vertex1(), r1);
        } else {
            // The radius runs (nearly) linearly along an edge: cut it where it is min_r.
            const double t = (min_r - r0) / (r1 - r0);
            const XY cut{p0.x + t * (p1.x - p0.x), p0.y + t * (p1.y - p0.y)};
            if (r0 >= min_r) {
                n0 = node(e.vertex0(), r0);
                n1 = g.add_node(cut, min_r);
            } else {
                n0 = g.add_node(cut, min_r);
                n1 = node(e.vertex1(), r1);
            }
        }
        if (n0 == n1) continue;
        g.edges.emplace_back(n0, n1);
        g.alive.push_back(1);
    }
    prune_spurs(g, min_r);

    // Chains between nodes that are not plain links, then the rings left.
    const auto inc = incidence(g);
    std::vector<char> used(g.edges.size(), 0);
    std::vector<MedialLine> out;
    const auto walk = [&](std::size_t start, std::size_t first_edge) {
        MedialLine line;
        line.points.push_back(rounded(g.at[start]));
        line.radius_um.push_back(g.radius[start]);
        std::size_t n = start;
        std::size_t e = first_edge;
        while (!used[e]) {
            used[e] = 1;
            n = other_end(g, e, n);
            line.points.push_back(rounded(g.at[n]));
            line.radius_um.push_back(g.radius[n]);
            if (inc[n].size() != 2) break;
            e = inc[n][0] == e ? inc[n][1] : inc[n][0];
        }
        line.closed = n == start && inc[n].size() == 2;
        return line;
    };
    for (std::size_t n = 0; n < g.at.size(); ++n) {
        if (inc[n].size() == 2) continue;
        for (const std::size_t e : inc[n]) {
            if (!used[e]) out.push_back(walk(n, e));
        }
    }
    for (std::size_t n = 0; n < g.at.size(); ++n) {
        for (const std::size_t e : inc[n]) {
            if (!used[e]) out.push_back(walk(n, e));
        }
    }
    // Lines of zero length (a chord between points that round alike) carry nothing.
    std::erase_if(out, [](const MedialLine& l) {
        return std::all_of(l.points.begin(), l.points.end(),
                           [&](const Point2& p) { return p == l.points.front(); });
    });
    std::sort(out.begin(), out.end(), [](const MedialLine& a, const MedialLine& b) {
        return *std::min_element(a.points.begin(), a.points.end()) <
               *std::min_element(b.points.begin(), b.points.end());
    });
    return out;
}

}  // namespace maxslice::geom2d
