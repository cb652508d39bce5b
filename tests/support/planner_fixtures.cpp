#include "support/planner_fixtures.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <utility>

#include "support/fixture_checks.hpp"

namespace maxslice::test {
namespace {

using core::Vec3d;
using mesh::TriangleMesh;

using detail::cross2;
using detail::require;

double radians(double deg) {
    return deg * std::numbers::pi / 180.0;
}

// The 45 degree ramp is the common case: keep its slope exact.
double tan_deg(double deg) {
    return deg == 45.0 ? 1.0 : std::tan(radians(deg));
}

double polygon_area(std::span<const CapPoint> p) {
    double twice = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const CapPoint a = p[i];
        const CapPoint b = p[(i + 1) % p.size()];
        twice += a.x * b.y - a.y * b.x;
    }
    return 0.5 * twice;
}

// A regular n-gon (n a multiple of 4) at angles 2 pi i / n, counter-clockwise. Unlike
// regular_polygon(), the points on the axes are exact and the polygon is exactly symmetric about
// both axes through its centre (one table of first-quadrant values, turned by quarter turns), so
// mirror-image points that a fixture puts on one line (a cradle's chord) are exactly level.
std::vector<CapPoint> ring_points(CapPoint center, double radius, int n) {
    require(n >= 4 && n % 4 == 0, "ring needs a multiple of 4 segments");
    const int q = n / 4;
    std::vector<CapPoint> first(static_cast<std::size_t>(q));  // (cos, sin) in [0, 90) degrees
    for (int j = 0; j < q; ++j) {
        CapPoint cs;
        if (j == 0) {
            cs = {1.0, 0.0};
        } else if (2 * j == q) {
            cs = {std::sqrt(0.5), std::sqrt(0.5)};
        } else if (2 * j < q) {
            const double a = 2.0 * std::numbers::pi * j / n;
            cs = {std::cos(a), std::sin(a)};
        } else {
            const double a = 2.0 * std::numbers::pi * (q - j) / n;
            cs = {std::sin(a), std::cos(a)};
        }
        first[static_cast<std::size_t>(j)] = cs;
    }
    std::vector<CapPoint> out;
    out.reserve(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        CapPoint cs = first[static_cast<std::size_t>(i % q)];
        for (int k = 0; k < i / q; ++k) cs = {-cs.y, cs.x};
        out.push_back({center.x + radius * cs.x, center.y + radius * cs.y});
    }
    return out;
}

// ---- Ear clipping ------------------------------------------------------------------------

bool within_box(CapPoint a, CapPoint b, CapPoint p) {
    return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
           p.y <= std::max(a.y, b.y);
}

// Closed segments ab and cd share a point (crossing, touching or overlapping).
bool segments_meet(CapPoint a, CapPoint b, CapPoint c, CapPoint d) {
    const double d1 = cross2(c, d, a);
    const double d2 = cross2(c, d, b);
    const double d3 = cross2(a, b, c);
    const double d4 = cross2(a, b, d);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) {
        return true;
    }
    return (d1 == 0 && within_box(c, d, a)) || (d2 == 0 && within_box(c, d, b)) ||
           (d3 == 0 && within_box(a, b, c)) || (d4 == 0 && within_box(a, b, d));
}

// Whether q lies strictly inside the corner prev -> p -> next of a loop whose region is on its
// left (counter-clockwise outer, clockwise hole).
bool in_corner(CapPoint prev, CapPoint p, CapPoint next, CapPoint q) {
    const CapPoint u{next.x - p.x, next.y - p.y};
    const CapPoint w{prev.x - p.x, prev.y - p.y};
    const CapPoint d{q.x - p.x, q.y - p.y};
    auto cr = [](CapPoint a, CapPoint b) { return a.x * b.y - a.y * b.x; };
    if (cross2(prev, p, next) > 0.0) return cr(u, d) > 0.0 && cr(d, w) > 0.0;
    // Reflex or straight corner: inside unless in the (closed) outer wedge from w to u.
    return !(cr(w, d) >= 0.0 && cr(d, u) >= 0.0);
}

bool loop_blocks(std::span<const CapPoint> loop, CapPoint m, CapPoint p) {
    for (std::size_t j = 0; j < loop.size(); ++j) {
        const CapPoint e0 = loop[j];
        const CapPoint e1 = loop[(j + 1) % loop.size()];
        if (e0 == p || e1 == p || e0 == m || e1 == m) continue;
        if (segments_meet(m, p, e0, e1)) return true;
    }
    return false;
}

// Joins each hole (clockwise) to the outer loop by a bridge from its rightmost point to the
// nearest loop vertex that sees it (the classic reduction of a polygon with holes to one weakly
// simple loop). Holes are taken by decreasing rightmost x, so a bridge never has to cross a hole
// that is still to come.
std::vector<CapPoint> bridged(std::vector<CapPoint> loop,
                              std::vector<std::vector<CapPoint>> holes) {
    auto max_x = [](const std::vector<CapPoint>& h) {
        return std::ranges::max(h, {}, &CapPoint::x).x;
    };
    std::ranges::stable_sort(holes,
                             [&](const auto& a, const auto& b) { return max_x(a) > max_x(b); });
    for (std::size_t h = 0; h < holes.size(); ++h) {
        const std::vector<CapPoint>& hole = holes[h];
        const std::size_t hn = hole.size();
        const std::size_t mi = static_cast<std::size_t>(
            std::ranges::max_element(hole, {}, &CapPoint::x) - hole.begin());
        const CapPoint m = hole[mi];
        const CapPoint m_prev = hole[(mi + hn - 1) % hn];
        const CapPoint m_next = hole[(mi + 1) % hn];
        std::vector<std::size_t> order(loop.size());
        std::iota(order.begin(), order.end(), std::size_t{0});
        auto dist2 = [&](std::size_t k) {
            return (loop[k].x - m.x) * (loop[k].x - m.x) + (loop[k].y - m.y) * (loop[k].y - m.y);
        };
        std::ranges::stable_sort(order,
                                 [&](std::size_t a, std::size_t b) { return dist2(a) < dist2(b); });
        std::size_t found = loop.size();
        for (const std::size_t k : order) {
            const std::size_t n = loop.size();
            const CapPoint p = loop[k];
            if (!in_corner(loop[(k + n - 1) % n], p, loop[(k + 1) % n], m)) continue;
            if (!in_corner(m_prev, m, m_next, p)) continue;
            bool blocked = loop_blocks(loop, m, p) || loop_blocks(hole, m, p);
            for (std::size_t g = h + 1; g < holes.size() && !blocked; ++g) {
                blocked = loop_blocks(holes[g], m, p);
            }
            if (!blocked) {
                found = k;
                break;
            }
        }
        require(found < loop.size(), "polygon_cap: a hole cannot be joined to the outer loop");
        std::vector<CapPoint> next;
        next.reserve(loop.size() + hn + 2);
        next.insert(next.end(), loop.begin(),
                    loop.begin() + static_cast<std::ptrdiff_t>(found) + 1);
        for (std::size_t i = 0; i <= hn; ++i) next.push_back(hole[(mi + i) % hn]);
        next.insert(next.end(), loop.begin() + static_cast<std::ptrdiff_t>(found), loop.end());
        loop = std::move(next);
    }
    return loop;
}

// Ear clipping of a weakly simple counter-clockwise loop. Each step cuts the best-shaped ear
// (largest area over squared edge lengths): O(n^3), fine for fixture-sized loops. Points at the
// same place as an ear's corner (the two ends of a bridge) do not block that ear.
Cap ear_clipped(const std::vector<CapPoint>& pts) {
    const std::size_t n = pts.size();
    std::vector<std::size_t> prev(n), next(n);
    for (std::size_t i = 0; i < n; ++i) {
        prev[i] = (i + n - 1) % n;
        next[i] = (i + 1) % n;
    }
    CapBuilder b;
    std::size_t alive = n;
    std::size_t start = 0;
    while (alive > 3) {
        std::size_t best = n;
        double best_quality = 0.0;
        std::size_t i = start;
        for (std::size_t step = 0; step < alive; ++step, i = next[i]) {
            const CapPoint a = pts[prev[i]], p = pts[i], c = pts[next[i]];
            const double twice_area = cross2(a, p, c);
            if (twice_area <= 0.0) continue;
            bool empty = true;
            for (std::size_t j = next[next[i]]; j != prev[i] && empty; j = next[j]) {
                const CapPoint q = pts[j];
                if (q == a || q == p || q == c) continue;
                if (cross2(a, p, q) >= 0.0 && cross2(p, c, q) >= 0.0 && cross2(c, a, q) >= 0.0) {
                    empty = false;
                }
            }
            if (!empty) continue;
            auto sq = [](CapPoint u, CapPoint v) {
                return (u.x - v.x) * (u.x - v.x) + (u.y - v.y) * (u.y - v.y);
            };
            const double quality = twice_area / (sq(a, p) + sq(p, c) + sq(c, a));
            if (quality > best_quality) {
                best_quality = quality;
                best = i;
            }
        }
        require(best < n, "polygon_cap: no ear found (the polygon is not simple)");
        b.triangle(pts[prev[best]], pts[best], pts[next[best]]);
        next[prev[best]] = next[best];
        prev[next[best]] = prev[best];
        start = next[best];
        --alive;
    }
    b.triangle(pts[prev[start]], pts[start], pts[next[start]]);
    return b.cap();
}

// ---- Meshes ------------------------------------------------------------------------------

// The fixture's exact mapping of an extrusion's (u, v, w) to part coordinates.
template <typename Map>
TriangleMesh remapped(TriangleMesh m, Map map) {
    for (Vec3d& p : m.vertices) p = map(p);
    return m;
}

PlannerFixture make(std::string name, std::string description, TriangleMesh m, double volume,
                    core::Box3d box, std::function<double(double)> area_at) {
    PlannerFixture f;
    f.name = std::move(name);
    f.description = std::move(description);
    f.mesh = std::move(m);
    f.volume_mm3 = volume;
    f.box = box;
    f.area_at = std::move(area_at);
    return f;
}

core::Box3d box_of(const Vec3d& min, const Vec3d& max) {
    core::Box3d b;
    b.add(min);
    b.add(max);
    return b;
}

// A section area that is constant for z in [z0, z1) and zero elsewhere.
std::function<double(double)> between(double z0, double z1, double area) {
    return [=](double z) { return (z >= z0 && z < z1) ? area : 0.0; };
}

}  // namespace

// ---- Construction helpers ----------------------------------------------------------------

Cap polygon_cap(std::span<const CapPoint> outer, std::span<const std::vector<CapPoint>> holes) {
    require(outer.size() >= 3 && polygon_area(outer) > 0.0,
            "polygon_cap: the outer loop must be counter-clockwise");
    std::vector<std::vector<CapPoint>> cw;
    for (const auto& h : holes) {
        require(h.size() >= 3 && polygon_area(h) > 0.0,
                "polygon_cap: holes must be given counter-clockwise");
        cw.emplace_back(h.rbegin(), h.rend());
    }
    return ear_clipped(bridged({outer.begin(), outer.end()}, std::move(cw)));
}

TriangleMesh fused(std::span<const TriangleMesh> bodies) {
    TriangleMesh all;
    std::map<std::array<double, 3>, std::uint32_t> welded;
    for (const TriangleMesh& body : bodies) {
        std::vector<std::uint32_t> index(body.vertices.size());
        for (std::size_t i = 0; i < body.vertices.size(); ++i) {
            const Vec3d& p = body.vertices[i];
            // + 0.0 turns -0.0 into 0.0, so a point is one key whatever its zero's sign.
            const std::array<double, 3> key{p.x + 0.0, p.y + 0.0, p.z + 0.0};
            const auto [it, inserted] =
                welded.try_emplace(key, static_cast<std::uint32_t>(all.vertices.size()));
            if (inserted) all.vertices.push_back({key[0], key[1], key[2]});
            index[i] = it->second;
        }
        for (const auto& t : body.triangles) {
            all.triangles.push_back({index[t[0]], index[t[1]], index[t[2]]});
        }
    }
    // Coincident triangles of opposite orientation are the faces along which bodies touch.
    std::map<std::array<std::uint32_t, 3>, std::array<std::vector<std::size_t>, 2>> by_corners;
    for (std::size_t i = 0; i < all.triangles.size(); ++i) {
        auto t = all.triangles[i];
        std::ranges::rotate(t, std::ranges::min_element(t));
        const int parity = t[1] < t[2] ? 0 : 1;
        std::array<std::uint32_t, 3> key = t;
        std::ranges::sort(key);
        by_corners[key][static_cast<std::size_t>(parity)].push_back(i);
    }
    std::vector<bool> keep(all.triangles.size(), true);
    for (const auto& [key, sides] : by_corners) {
        const std::size_t pairs = std::min(sides[0].size(), sides[1].size());
        for (std::size_t k = 0; k < pairs; ++k) {
            keep[sides[0][k]] = false;
            keep[sides[1][k]] = false;
        }
    }
    TriangleMesh out;
    std::vector<std::int64_t> renumber(all.vertices.size(), -1);
    for (std::size_t i = 0; i < all.triangles.size(); ++i) {
        if (!keep[i]) continue;
        mesh::Triangle t{};
        for (std::size_t k = 0; k < 3; ++k) {
            auto& slot = renumber[all.triangles[i][k]];
            if (slot < 0) {
                slot = static_cast<std::int64_t>(out.vertices.size());
                out.vertices.push_back(all.vertices[all.triangles[i][k]]);
            }
            t[k] = static_cast<std::uint32_t>(slot);
        }
        out.triangles.push_back(t);
    }
    return out;
}

TriangleMesh extrude_xz(const Cap& profile, double y0, double y1) {
    // Extruded along w over [-y1, -y0], then turned +90 degrees about X: (u, v, w) ->
    // (u, -w, v), a rotation, so the orientation is kept and the coordinates stay exact.
    return remapped(extrude(profile, -y1, -y0), [](const Vec3d& p) {
        return Vec3d{p.x, -p.z, p.y};
    });
}

TriangleMesh extrude_yz(const Cap& profile, double x0, double x1) {
    // (u, v, w) -> (w, u, v): a cyclic permutation of the axes, a rotation.
    return remapped(extrude(profile, x0, x1), [](const Vec3d& p) { return Vec3d{p.z, p.x, p.y}; });
}

TriangleMesh chamfered_block(double run, double rise) {
    require(0.0 <= run && run < 20.0 && 0.0 <= rise && rise < 10.0,
            "chamfered_block: need run in [0, 20) and rise in [0, 10)");
    const std::vector<CapPoint> profile{{run, 0}, {20, 0}, {20, 10}, {0, 10}, {0, rise}};
    return extrude_xz(polygon_cap(profile), 0.0, 20.0);
}

// ---- 1. Vertical walls -------------------------------------------------------------------

PlannerFixture vertical_prism(const PrismSpec& spec) {
    const double l = spec.leg_length;
    const double w = spec.leg_width;
    const double h = spec.height;
    require(0.0 < w && w < l && h > 0.0, "vertical_prism: need 0 < leg_width < leg_length");
    // The corner square shares its corners with both legs: no T-junctions.
    CapBuilder b;
    b.add(rectangle_cap(0.0, 0.0, w, w));
    b.add(rectangle_cap(w, 0.0, l, w));
    b.add(rectangle_cap(0.0, w, w, l));
    const double area = w * (2.0 * l - w);
    return make("vertical_prism", "L-profile prism: every layer fully carried, build along Z",
                extrude(b.cap(), 0.0, h), area * h, box_of({0, 0, 0}, {l, l, h}),
                between(0.0, h, area));
}

PlannerFixture cylinder_with_holes(const HoledCylinderSpec& spec) {
    const double r_out = spec.radius;
    const double rc = spec.hole_circle_radius;
    const double r = spec.hole_radius;
    const int k = spec.holes;
    require(k >= 1 && r > 0.0 && spec.height > 0.0, "cylinder_with_holes: bad spec");
    require(rc + r < r_out * std::cos(std::numbers::pi / spec.segments),
            "cylinder_with_holes: holes must lie inside the outer polygon");
    require(k == 1 || rc * std::sin(std::numbers::pi / k) > r,
            "cylinder_with_holes: holes must not overlap");
    std::vector<std::vector<CapPoint>> holes;
    for (int i = 0; i < k; ++i) {
        const double a = 2.0 * std::numbers::pi * i / k;
        const CapPoint c =
            i == 0 ? CapPoint{rc, 0.0} : CapPoint{rc * std::cos(a), rc * std::sin(a)};
        holes.push_back(ring_points(c, r, spec.hole_segments));
    }
    const Cap cap = polygon_cap(ring_points({0, 0}, r_out, spec.segments), holes);
    const double area = regular_polygon_area(r_out, spec.segments) -
                        k * regular_polygon_area(r, spec.hole_segments);
    return make("cylinder_with_holes",
                "cylinder with vertical through-holes: holes are deposited, every layer carried",
                extrude(cap, 0.0, spec.height), area * spec.height,
                box_of({-r_out, -r_out, 0.0}, {r_out, r_out, spec.height}),
                between(0.0, spec.height, area));
}

// ---- 2. Slopes ---------------------------------------------------------------------------

PlannerFixture ramp_45(const RampSpec& spec) {
    const double b = spec.base_length;
    const double h = spec.height;
    const double d = spec.depth;
    require(b > 0.0 && h > 0.0 && d > 0.0, "ramp_45: sizes must be positive");
    require(spec.lean_deg >= 0.0 && spec.lean_deg <= 60.0, "ramp_45: lean must be in [0, 60]");
    const double slope = tan_deg(spec.lean_deg);
    const double top = b + h * slope;
    CapBuilder cap;
    cap.quad({0.0, 0.0}, {b, 0.0}, {top, h}, {0.0, h});
    return make("ramp_45",
                "wedge whose sloped face overhangs 45 degrees: slight change, tilted layers",
                extrude_xz(cap.cap(), 0.0, d), d * h * (b + 0.5 * h * slope),
                box_of({0, 0, 0}, {top, d, h}),
                [=](double z) { return (z >= 0.0 && z < h) ? (b + z * slope) * d : 0.0; });
}

PlannerFixture cone(const ConeSpec& spec) {
    const double r0 = spec.base_radius;
    const double r1 = spec.top_radius;
    const double h = spec.height;
    const int n = spec.segments;
    require(r0 > 0.0 && r1 >= 0.0 && r1 < r0 && h > 0.0, "cone: need 0 <= top < base radius");
    const std::vector<CapPoint> unit = ring_points({0, 0}, 1.0, n);
    TriangleMesh m;
    const auto un = static_cast<std::uint32_t>(n);
    m.vertices.push_back({0.0, 0.0, 0.0});
    for (const CapPoint& p : unit) m.vertices.push_back({r0 * p.x, r0 * p.y, 0.0});
    const std::uint32_t top_center = 1 + un;
    m.vertices.push_back({0.0, 0.0, h});
    if (r1 > 0.0) {
        for (const CapPoint& p : unit) m.vertices.push_back({r1 * p.x, r1 * p.y, h});
    }
    for (std::uint32_t i = 0; i < un; ++i) {
        const std::uint32_t j = (i + 1) % un;
        const std::uint32_t b0 = 1 + i, b1 = 1 + j;
        m.triangles.push_back({0, b1, b0});
        if (r1 > 0.0) {
            const std::uint32_t t0 = top_center + 1 + i, t1 = top_center + 1 + j;
            m.triangles.push_back({b0, b1, t1});
            m.triangles.push_back({b0, t1, t0});
            m.triangles.push_back({top_center, t0, t1});
        } else {
            m.triangles.push_back({b0, b1, top_center});
        }
    }
    const double unit_area = regular_polygon_area(1.0, n);
    return make("cone", "upright cone: slopes lean inwards, no overhang, build along Z",
                std::move(m), unit_area * h * (r0 * r0 + r0 * r1 + r1 * r1) / 3.0,
                box_of({-r0, -r0, 0.0}, {r0, r0, h}), [=](double z) {
                    if (z < 0.0 || z >= h) return 0.0;
                    const double r = r0 + (r1 - r0) * z / h;
                    return unit_area * r * r;
                });
}

// ---- 3. A boss sticking out sideways -----------------------------------------------------

PlannerFixture bearing_seat(const BearingSeatSpec& spec) {
    const double l = spec.block_length;
    const double w = spec.block_width;
    const double h = spec.block_height;
    const double r = spec.boss_radius;
    require(l > 0.0 && spec.boss_length > 0.0, "bearing_seat: sizes must be positive");
    require(0.0 < r && r < 0.5 * w && r < 0.5 * h, "bearing_seat: the boss must fit the face");
    // The block's face x = l in the (y, z) plane: the rectangle around the boss's disc plus the
    // disc itself, triangulated exactly as the boss's end so the two fuse into one body.
    const CapPoint center{0.5 * w, 0.5 * h};
    const std::vector<CapPoint> rim = ring_points(center, r, spec.segments);
    const Cap disc = fan_cap(center, rim);
    const std::vector<CapPoint> face_outline{{0, 0}, {w, 0}, {w, h}, {0, h}};
    const std::vector<std::vector<CapPoint>> face_holes{rim};
    CapBuilder face;
    face.add(polygon_cap(face_outline, face_holes));
    face.add(disc);
    const TriangleMesh pieces[] = {extrude_yz(face.cap(), 0.0, l),
                                   extrude_yz(disc, l, l + spec.boss_length)};
    const double boss_area = regular_polygon_area(r, spec.segments);
    const double boss_length = spec.boss_length;
    return make("bearing_seat",
                "block with a horizontal boss at mid-height: Z, then 90 degrees for the boss, "
                "then Z",
                fused(pieces), l * w * h + boss_area * boss_length,
                box_of({0, 0, 0}, {l + boss_length, w, h}), [=](double z) {
                    return ((z >= 0.0 && z < h) ? l * w : 0.0) + boss_length * cap_chord(disc, z);
                });
}

// ---- 4. Horizontal members on a column ---------------------------------------------------

double cylinder_on_column_axis_height(const ColumnCylinderSpec& spec) {
    const int n = spec.segments;
    const int steps = static_cast<int>(std::lround(spec.cradle_deg * n / 360.0));
    require(n % 4 == 0 && steps > 0 && steps < n / 4 &&
                std::abs(steps * 360.0 / n - spec.cradle_deg) < 1e-9,
            "cylinder_on_column: cradle_deg must be a multiple of 360 / segments in (0, 90)");
    // The cradle's ends are the ring points 3n/4 -+ steps; their height below the axis is
    // radius * |y| of the unit ring's point there.
    const std::vector<CapPoint> unit = ring_points({0, 0}, 1.0, n);
    const double below = -unit[static_cast<std::size_t>(3 * n / 4 + steps)].y;
    return spec.column_height + spec.cylinder_radius * below;
}

PlannerFixture cylinder_on_column(const ColumnCylinderSpec& spec) {
    const double a = 0.5 * spec.column_width;
    const double b = 0.5 * spec.column_depth;
    const double r = spec.cylinder_radius;
    const double left = spec.overhang_left;
    const double right = spec.overhang_right;
    const int n = spec.segments;
    const double zc = cylinder_on_column_axis_height(spec);
    const int steps = static_cast<int>(std::lround(spec.cradle_deg * n / 360.0));
    require(a > 0.0 && r > 0.0 && left >= 0.0 && right >= 0.0 && zc - r > 0.0,
            "cylinder_on_column: bad sizes");
    // In the (y, z) plane: the cylinder's disc and, below its cradle, the column's section.
    const CapPoint center{0.0, zc};
    const std::vector<CapPoint> rim = ring_points(center, r, n);
    const auto i_right = static_cast<std::size_t>(3 * n / 4 + steps);
    const auto i_left = static_cast<std::size_t>(3 * n / 4 - steps);
    const double top = rim[i_right].y;  // the column's top: the cradle's chord
    require(rim[i_right].x < b, "cylinder_on_column: the column must be wider than the cradle");
    std::vector<CapPoint> column{{-b, 0.0}, {b, 0.0}, {b, top}};
    for (std::size_t i = i_right; i >= i_left; --i) column.push_back(rim[i]);
    column.push_back({-b, top});
    const Cap disc = fan_cap(center, rim);
    CapBuilder middle;
    middle.add(polygon_cap(column));
    middle.add(disc);
    std::vector<TriangleMesh> pieces{extrude_yz(middle.cap(), -a, a)};
    if (left > 0.0) pieces.push_back(extrude_yz(disc, -a - left, -a));
    if (right > 0.0) pieces.push_back(extrude_yz(disc, a, a + right));
    // The disc's part below the chord, which the column's section leaves out.
    std::vector<CapPoint> segment(rim.begin() + static_cast<std::ptrdiff_t>(i_left),
                                  rim.begin() + static_cast<std::ptrdiff_t>(i_right) + 1);
    const double disc_area = regular_polygon_area(r, n);
    const double column_area = 2.0 * b * top - polygon_area(segment);
    const double length = 2.0 * a + left + right;
    return make("cylinder_on_column",
                "column with a horizontal cylinder across its top, overhanging both ends: Z, then "
                "sideways for the overhangs",
                fused(pieces), 2.0 * a * column_area + length * disc_area,
                box_of({-a - left, -std::max(b, r), 0.0}, {a + right, std::max(b, r), zc + r}),
                [=](double z) {
                    const double chord = cap_chord(disc, z);
                    if (z >= 0.0 && z < top) return 4.0 * a * b + (left + right) * chord;
                    return length * chord;
                });
}

PlannerFixture t_shape_arms(const TArmsSpec& spec) {
    const TSpec t{.stem_width = spec.column_width,
                  .stem_height = spec.column_height,
                  .bar_width = spec.column_width + 2.0 * spec.arm_length,
                  .bar_height = spec.arm_thickness,
                  .depth = spec.depth};
    require(spec.arm_length > 0.0, "t_shape_arms: arms must stick out");
    return make("t_shape_arms",
                "column with two horizontal arms at its top: Z, then sideways for each arm",
                t_shape(t), t_shape_volume(t),
                box_of({0, 0, 0}, {t.bar_width, t.depth, t.stem_height + t.bar_height}),
                [t](double z) { return t_shape_area_at(t, z); });
}

PlannerFixture l_bracket(const LBracketSpec& spec) {
    const double w = spec.column_width;
    const double h = spec.column_height;
    const double l = spec.arm_length;
    const double t = spec.arm_thickness;
    const double d = spec.depth;
    require(w > 0.0 && h > 0.0 && l > 0.0 && t > 0.0 && d > 0.0, "l_bracket: bad sizes");
    CapBuilder b;
    b.add(rectangle_cap(0.0, 0.0, w, h));
    b.add(rectangle_cap(0.0, h, w, h + t));
    b.add(rectangle_cap(w, h, w + l, h + t));
    return make("l_bracket",
                "column with one horizontal arm at its top (a gamma): Z, then sideways for the arm",
                extrude_xz(b.cap(), 0.0, d), d * (w * h + (w + l) * t),
                box_of({0, 0, 0}, {w + l, d, h + t}), [=](double z) {
                    if (z >= 0.0 && z < h) return w * d;
                    return (z >= h && z < h + t) ? (w + l) * d : 0.0;
                });
}

// ---- 5. A freeform column ----------------------------------------------------------------

namespace {

std::array<Vec3d, 4> control_points(const LeaningColumnSpec& spec) {
    const double h = spec.height;
    const double slope = tan_deg(spec.lean_deg);
    const Vec3d p3{spec.top_offset, 0.0, h};
    return {Vec3d{0.0, 0.0, 0.0}, Vec3d{0.0, 0.0, h / 3.0},
            Vec3d{spec.top_offset - h / 3.0 * slope, 0.0, 2.0 * h / 3.0}, p3};
}

// Length of the spine: Simpson's rule on |B'(t)|, far finer than the rings.
double spine_length(const LeaningColumnSpec& spec) {
    const std::array<Vec3d, 4> p = control_points(spec);
    auto speed = [&](double t) {
        const double s = 1.0 - t;
        return core::norm((p[1] - p[0]) * (3.0 * s * s) + (p[2] - p[1]) * (6.0 * s * t) +
                          (p[3] - p[2]) * (3.0 * t * t));
    };
    const int n = 4096;
    double sum = speed(0.0) + speed(1.0);
    for (int i = 1; i < n; ++i) sum += (i % 2 == 1 ? 4.0 : 2.0) * speed(static_cast<double>(i) / n);
    return sum / (3.0 * n);
}

}  // namespace

Vec3d leaning_column_spine(const LeaningColumnSpec& spec, double t) {
    const std::array<Vec3d, 4> p = control_points(spec);
    const double s = 1.0 - t;
    return p[0] * (s * s * s) + p[1] * (3.0 * s * s * t) + p[2] * (3.0 * s * t * t) +
           p[3] * (t * t * t);
}

Vec3d leaning_column_axis(const LeaningColumnSpec& spec, double t) {
    const std::array<Vec3d, 4> p = control_points(spec);
    const double s = 1.0 - t;
    return core::normalized((p[1] - p[0]) * (s * s) + (p[2] - p[1]) * (2.0 * s * t) +
                            (p[3] - p[2]) * (t * t));
}

std::vector<Vec3d> leaning_column_spine_polyline(const LeaningColumnSpec& spec, int samples) {
    require(samples >= 1, "leaning_column_spine_polyline: need at least one step");
    std::vector<Vec3d> out;
    for (int i = 0; i <= samples; ++i) {
        out.push_back(leaning_column_spine(spec, static_cast<double>(i) / samples));
    }
    return out;
}

PlannerFixture leaning_column(const LeaningColumnSpec& spec) {
    const double r = spec.radius;
    const int n = spec.segments;
    const int rings = spec.rings;
    const double lean_offset = spec.height / 3.0 * tan_deg(spec.lean_deg);
    require(r > 0.0 && spec.height > 0.0 && rings >= 2, "leaning_column: bad sizes");
    require(spec.lean_deg >= 0.0 && spec.lean_deg <= 60.0, "leaning_column: lean in [0, 60]");
    require(spec.top_offset >= lean_offset && spec.top_offset <= 2.0 * lean_offset,
            "leaning_column: top_offset out of range (the lean would not grow monotonically)");
    const std::vector<CapPoint> unit = ring_points({0, 0}, 1.0, n);
    TriangleMesh m;
    const auto un = static_cast<std::uint32_t>(n);
    m.vertices.push_back({0.0, 0.0, 0.0});
    for (int i = 0; i <= rings; ++i) {
        const double t = static_cast<double>(i) / rings;
        const Vec3d c = leaning_column_spine(spec, t);
        const Vec3d axis = leaning_column_axis(spec, t);
        // e1 x e2 = axis: a ring counter-clockwise about the spine, like an extruded cap.
        const Vec3d e1{axis.z, 0.0, -axis.x};
        const Vec3d e2{0.0, 1.0, 0.0};
        for (const CapPoint& p : unit) {
            Vec3d v = c + e1 * (r * p.x) + e2 * (r * p.y);
            if (i == 0) v.z = 0.0;  // the vertical start tangent puts it there; make it exact
            m.vertices.push_back(v);
        }
    }
    const auto top_center = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.push_back(leaning_column_spine(spec, 1.0));
    auto at = [un](int ring, std::uint32_t j) {
        return 1 + static_cast<std::uint32_t>(ring) * un + j % un;
    };
    for (std::uint32_t j = 0; j < un; ++j) {
        m.triangles.push_back({0, at(0, j + 1), at(0, j)});
        for (int i = 0; i < rings; ++i) {
            m.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
            m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
        }
        m.triangles.push_back({top_center, at(rings, j), at(rings, j + 1)});
    }
    const double lean = radians(spec.lean_deg);
    PlannerFixture f =
        make("leaning_column",
             "n-gon swept along a spline leaning up to lean_deg: gradual tilt, tilted 3D layers",
             std::move(m), regular_polygon_area(r, n) * spine_length(spec),
             box_of({-r, -r, 0.0},
                    {spec.top_offset + r * std::cos(lean), r, spec.height + r * std::sin(lean)}),
             {});
    // The rings replace the smooth spine by chords (about 0.8 degrees of turn apart): the mesh
    // holds 2e-5 less than the smooth sweep with the default spec.
    f.volume_accuracy = 1e-4;
    return f;
}

// ---- 6. Several bases, frames, narrow gaps -----------------------------------------------

double arch_soffit_height(const ArchSpec& spec) {
    const double half = 0.5 * spec.span;
    return spec.height * (half - spec.foot_width) / (half - 0.5 * spec.crown_width);
}

PlannerFixture arch(const ArchSpec& spec) {
    const double s = spec.span;
    const double h = spec.height;
    const double f = spec.foot_width;
    const double c = 0.5 * spec.crown_width;
    const double d = spec.depth;
    require(0.0 < c && 2.0 * c < f && f < 0.5 * s && h > 0.0 && d > 0.0,
            "arch: need 0 < crown_width < foot_width < span / 2");
    const double hi = arch_soffit_height(spec);
    const double lean = 0.5 * s - c;  // outer faces run x = lean * z / h from the outer corners
    const std::vector<CapPoint> outline{{0.0, 0.0}, {f, 0.0},      {0.5 * s, hi}, {s - f, 0.0},
                                        {s, 0.0},   {s - lean, h}, {lean, h}};
    return make("arch",
                "two legs leaning towards each other on separate feet, joined at the top: grow "
                "each side in turn (distance-angle method), close the crown last",
                extrude_xz(polygon_cap(outline), 0.0, d),
                d * (2.0 * f * hi + s * (h - hi) - lean * (h * h - hi * hi) / h),
                box_of({0, 0, 0}, {s, d, h}), [=](double z) {
                    if (z < 0.0 || z >= h) return 0.0;
                    return z < hi ? 2.0 * f * d : (s - 2.0 * lean * z / h) * d;
                });
}

PlannerFixture portal_frame(const PortalSpec& spec) {
    const double s = spec.span;
    const double w = spec.column_width;
    const double h = spec.column_height;
    const double t = spec.beam_thickness;
    const double d = spec.depth;
    require(w > 0.0 && 2.0 * w < s && h > 0.0 && t > 0.0 && d > 0.0, "portal_frame: bad sizes");
    CapBuilder b;
    b.add(rectangle_cap(0.0, 0.0, w, h));
    b.add(rectangle_cap(s - w, 0.0, s, h));
    b.add(rectangle_cap(0.0, h, w, h + t));
    b.add(rectangle_cap(w, h, s - w, h + t));
    b.add(rectangle_cap(s - w, h, s, h + t));
    return make("portal_frame",
                "two columns and a beam on top: the beam's middle bridges the opening",
                extrude_xz(b.cap(), 0.0, d), d * (2.0 * w * h + s * t),
                box_of({0, 0, 0}, {s, d, h + t}), [=](double z) {
                    if (z >= 0.0 && z < h) return 2.0 * w * d;
                    return (z >= h && z < h + t) ? s * d : 0.0;
                });
}

PlannerFixture tall_portal() {
    PlannerFixture f = portal_frame({60.0, 10.0, 40.0, 8.0, 10.0});
    f.name = "tall_portal";
    return f;
}

PlannerFixture slot(const SlotSpec& spec) {
    const double w = spec.wall_thickness;
    const double g = spec.slot_width;
    const double hb = spec.base_height;
    const double h = spec.height;
    const double d = spec.depth;
    require(w > 0.0 && g > 0.0 && 0.0 < hb && hb < h && d > 0.0, "slot: bad sizes");
    const double x = 2.0 * w + g;
    CapBuilder b;
    b.add(rectangle_cap(0.0, 0.0, w, hb));
    b.add(rectangle_cap(w, 0.0, w + g, hb));
    b.add(rectangle_cap(w + g, 0.0, x, hb));
    b.add(rectangle_cap(0.0, hb, w, h));
    b.add(rectangle_cap(w + g, hb, x, h));
    return make("slot",
                "two walls with a deep narrow slot between them on a common base: the nozzle's "
                "tightest spot",
                extrude_xz(b.cap(), 0.0, d), d * (x * hb + 2.0 * w * (h - hb)),
                box_of({0, 0, 0}, {x, d, h}), [=](double z) {
                    if (z >= 0.0 && z < hb) return x * d;
                    return (z >= hb && z < h) ? 2.0 * w * d : 0.0;
                });
}

// ---- 7. Parts as given, with the plate in the machine ------------------------------------

PlannerFixture cross_hole_block(const CrossHoleBlockSpec& spec) {
    const double s = spec.size;
    const double r = 0.5 * spec.hole_diameter;
    require(0.0 < r && 2.0 * r < s, "cross_hole_block: the hole must fit inside the block");
    // In the (x, z) plane: the square with the hole, extruded along Y.
    const CapPoint center{0.5 * s, 0.5 * s};
    const std::vector<CapPoint> rim = ring_points(center, r, spec.segments);
    const std::vector<CapPoint> outline{{0, 0}, {s, 0}, {s, s}, {0, s}};
    const std::vector<std::vector<CapPoint>> holes{rim};
    const Cap hole = fan_cap(center, rim);
    return make("cross_hole_block",
                "40 mm block with a horizontal 20 mm through-hole: the hole's roof bridges the two "
                "sides",
                extrude_xz(polygon_cap(outline, holes), 0.0, s),
                s * (s * s - regular_polygon_area(r, spec.segments)), box_of({0, 0, 0}, {s, s, s}),
                [=](double z) { return (z >= 0.0 && z < s) ? s * (s - cap_chord(hole, z)) : 0.0; });
}

PlannerFixture tab_with_hole(const TabWithHoleSpec& spec) {
    const double l = spec.plate_length;
    const double w = spec.plate_width;
    const double t = spec.plate_thickness;
    const double tw = spec.tab_width;
    const double tt = spec.tab_thickness;
    const double th = spec.tab_height;
    const double r = 0.5 * spec.hole_diameter;
    const double zh = t + spec.hole_height;
    require(l > 0.0 && w > 0.0 && t > 0.0 && 0.0 < tw && tw < l && 0.0 < tt && tt < w && th > 0.0,
            "tab_with_hole: bad sizes");
    require(0.0 < r && 2.0 * r < tw && zh - r > t && zh + r < t + th,
            "tab_with_hole: the hole must fit inside the tab");
    // In the (x, z) plane: the plate's section in three rectangles (the tab's foot is the middle
    // one's top, so the tab joins without T-junctions) and the tab with its hole; extruded along
    // Y in three slabs, the middle one with the tab.
    const double x0 = 0.5 * (l - tw);
    const double x1 = x0 + tw;
    const double y0 = 0.5 * (w - tt);
    const double y1 = y0 + tt;
    CapBuilder plate;
    plate.add(rectangle_cap(0.0, 0.0, x0, t));
    plate.add(rectangle_cap(x0, 0.0, x1, t));
    plate.add(rectangle_cap(x1, 0.0, l, t));
    const CapPoint center{0.5 * l, zh};
    const std::vector<CapPoint> rim = ring_points(center, r, spec.segments);
    const std::vector<CapPoint> tab_outline{{x0, t}, {x1, t}, {x1, t + th}, {x0, t + th}};
    const std::vector<std::vector<CapPoint>> holes{rim};
    CapBuilder middle;
    middle.add(plate.cap());
    middle.add(polygon_cap(tab_outline, holes));
    const TriangleMesh pieces[] = {extrude_xz(plate.cap(), 0.0, y0),
                                   extrude_xz(middle.cap(), y0, y1),
                                   extrude_xz(plate.cap(), y1, w)};
    const Cap hole = fan_cap(center, rim);
    return make("tab_with_hole",
                "plate with an upright tab holding a horizontal 10 mm hole: Z, the hole's roof "
                "bridges the tab's two sides",
                fused(pieces), l * w * t + tt * (tw * th - regular_polygon_area(r, spec.segments)),
                box_of({0, 0, 0}, {l, w, t + th}), [=](double z) {
                    if (z >= 0.0 && z < t) return l * w;
                    return (z >= t && z < t + th) ? tt * (tw - cap_chord(hole, z)) : 0.0;
                });
}

double helical_ring_ground_angle(const HelicalRingSpec& spec) {
    return std::numbers::pi * spec.section / spec.pitch;
}

PlannerFixture helical_ring(const HelicalRingSpec& spec) {
    const double a = spec.radius - 0.5 * spec.section;
    const double b = spec.radius + 0.5 * spec.section;
    const double half = 0.5 * spec.section;
    const int n = spec.segments_per_turn;
    const int steps = n * spec.turns;
    require(a > 0.0 && spec.section > 0.0 && spec.pitch > spec.section && spec.turns >= 1 && n >= 8,
            "helical_ring: bad sizes");
    const double ground_steps = n * spec.section / (2.0 * spec.pitch);
    require(ground_steps == std::floor(ground_steps),
            "helical_ring: the ground end must end on a step");
    // Ring k: the section's corners (a, bottom), (b, bottom), (b, top), (a, top) in the
    // half-plane at theta_k; heights from k alone (pitch * k / n), so the ground end's bottom is
    // exactly 0 and the top exactly turns * pitch + half.
    TriangleMesh m;
    for (int k = 0; k <= steps; ++k) {
        const double theta = 2.0 * std::numbers::pi * k / n;
        const double c = std::cos(theta);
        const double s = std::sin(theta);
        const double zc = spec.pitch * k / n;
        const double bottom = std::max(0.0, zc - half);
        const double top = zc + half;
        m.vertices.push_back({a * c, a * s, bottom});
        m.vertices.push_back({b * c, b * s, bottom});
        m.vertices.push_back({b * c, b * s, top});
        m.vertices.push_back({a * c, a * s, top});
    }
    auto at = [](int k, int corner) { return static_cast<std::uint32_t>(4 * k + corner % 4); };
    // The corners run counter-clockwise in the (radius, z) plane, whose normal at theta is
    // -d/dtheta: so the start cap faces backwards as listed and each side quad runs k -> k + 1
    // before the next corner.
    m.triangles.push_back({at(0, 0), at(0, 1), at(0, 2)});
    m.triangles.push_back({at(0, 0), at(0, 2), at(0, 3)});
    for (int k = 0; k < steps; ++k) {
        for (int i = 0; i < 4; ++i) {
            m.triangles.push_back({at(k, i), at(k + 1, i), at(k + 1, i + 1)});
            m.triangles.push_back({at(k, i), at(k + 1, i + 1), at(k, i + 1)});
        }
    }
    m.triangles.push_back({at(steps, 0), at(steps, 2), at(steps, 1)});
    m.triangles.push_back({at(steps, 0), at(steps, 3), at(steps, 2)});
    // A screw motion keeps volume as the radius weights it: the smooth sweep holds
    // (b^2 - a^2) / 2 times the integral of the section's height over theta; the ground end
    // loses the triangle below the plate, half * ground angle.
    const double ground = helical_ring_ground_angle(spec);
    const double sweep = 0.5 * (b * b - a * a) *
                         (spec.section * 2.0 * std::numbers::pi * spec.turns - 0.5 * half * ground);
    PlannerFixture f = make(
        "helical_ring",
        "square section wound two turns along a helix, standing on its ground end: the growth "
        "turns, follow it with tilted layers as far as the tilt range allows, then a new base",
        std::move(m), sweep, box_of({-b, -b, 0.0}, {b, b, spec.turns * spec.pitch + half}), {});
    // The faceting, to leading order in the step d: the side walls are chords, which hold
    // sin(d) / d of the arcs' volume; the top and bottom faces (helicoids, flat on the ground
    // end) are each step a twisted quad cut along one diagonal, which adds or removes about half
    // the tetrahedron between its two diagonals, (b - a)^2 rise sin(d) / 6 for the rise
    // pitch / n of a step. 2.4e-3 with the default spec; measured 2e-4 (the two partly cancel).
    const double d = 2.0 * std::numbers::pi / n;
    const double sliver = (b - a) * (b - a) * (spec.pitch / n) * std::sin(d) / 6.0;
    const double twisted = 2.0 * steps - ground_steps;
    f.volume_accuracy = (1.0 - std::sin(d) / d) + 0.5 * sliver * twisted / sweep;
    return f;
}

PlannerFixture wall_boss(const WallBossSpec& spec) {
    const double l = spec.wall_length;
    const double t = spec.wall_thickness;
    const double h = spec.wall_height;
    const double r = 0.5 * spec.boss_diameter;
    const double bl = spec.boss_length;
    require(l > 0.0 && t > 0.0 && h > 0.0 && bl > 0.0, "wall_boss: sizes must be positive");
    require(0.0 < r && 2.0 * r < l && 2.0 * r < h, "wall_boss: the boss must fit the face");
    // The wall's face y = t in the (x, z) plane: the rectangle around the boss's disc plus the
    // disc, triangulated exactly as the boss's end so the two fuse into one body.
    const CapPoint center{0.5 * l, 0.5 * h};
    const std::vector<CapPoint> rim = ring_points(center, r, spec.segments);
    const Cap disc = fan_cap(center, rim);
    const std::vector<CapPoint> outline{{0, 0}, {l, 0}, {l, h}, {0, h}};
    const std::vector<std::vector<CapPoint>> holes{rim};
    CapBuilder face;
    face.add(polygon_cap(outline, holes));
    face.add(disc);
    const TriangleMesh pieces[] = {extrude_xz(face.cap(), 0.0, t), extrude_xz(disc, t, t + bl)};
    return make("wall_boss",
                "vertical wall with a horizontal boss at mid-height: Z for the wall, sideways for "
                "the boss",
                fused(pieces), l * t * h + regular_polygon_area(r, spec.segments) * bl,
                box_of({0, 0, 0}, {l, t + bl, h}), [=](double z) {
                    return ((z >= 0.0 && z < h) ? l * t : 0.0) + bl * cap_chord(disc, z);
                });
}

PlannerFixture arm_and_post(const ArmAndPostSpec& spec) {
    const double bl = spec.base_length, bh = spec.base_height, d = spec.depth;
    const double w = spec.column_width, ch = spec.column_height, al = spec.arm_length;
    const double at = spec.arm_thickness, px = spec.post_x, ph = spec.post_height;
    require(bl > 0.0 && bh > 0.0 && d > 0.0 && w > 0.0 && ch > 0.0 && al > 0.0 && at > 0.0,
            "arm_and_post: sizes must be positive");
    require(w + al < px && px + w <= bl && ph > ch + at,
            "arm_and_post: the post must stand "
            "on the base beyond the arm's end and above its top");
    // Rectangles that share whole edges, so the pieces fuse without T-junctions.
    CapBuilder b;
    b.add(rectangle_cap(0.0, 0.0, w, bh));
    b.add(rectangle_cap(w, 0.0, px, bh));
    b.add(rectangle_cap(px, 0.0, px + w, bh));
    if (px + w < bl) b.add(rectangle_cap(px + w, 0.0, bl, bh));
    b.add(rectangle_cap(0.0, bh, w, bh + ch));
    b.add(rectangle_cap(0.0, bh + ch, w, bh + ch + at));
    b.add(rectangle_cap(w, bh + ch, w + al, bh + ch + at));
    b.add(rectangle_cap(px, bh, px + w, bh + ph));
    return make("arm_and_post",
                "a column with an arm at its top and a taller post further along, on one base: "
                "the arm is built sideways, the post carries on upright",
                extrude_xz(b.cap(), 0.0, d), d * (bl * bh + w * ch + (w + al) * at + w * ph),
                box_of({0, 0, 0}, {bl, d, bh + ph}), [=](double z) {
                    if (z >= 0.0 && z < bh) return bl * d;
                    double a = (z >= bh && z < bh + ph) ? w * d : 0.0;  // the post
                    if (z >= bh && z < bh + ch) a += w * d;
                    if (z >= bh + ch && z < bh + ch + at) a += (w + al) * d;
                    return a;
                });
}

PlannerFixture hook(const HookSpec& spec) {
    const double bl = spec.base_length, bh = spec.base_height, d = spec.depth;
    const double w = spec.column_width, ch = spec.column_height, al = spec.arm_length;
    const double at = spec.arm_thickness, fw = spec.finger_width, fl = spec.finger_length;
    require(bl > 0.0 && bh > 0.0 && d > 0.0 && w > 0.0 && ch > 0.0 && al > 0.0 && at > 0.0 &&
                fw > 0.0 && fl > 0.0,
            "hook: sizes must be positive");
    require(w <= bl && fw < al && fl < ch && w + al - fw > bl,
            "hook: the finger must hang from the arm's end, beyond the base and above it");
    const double top = bh + ch;  // the arm's underside
    // Rectangles that share whole edges, so the pieces fuse without T-junctions.
    CapBuilder b;
    b.add(rectangle_cap(0.0, 0.0, w, bh));
    if (w < bl) b.add(rectangle_cap(w, 0.0, bl, bh));
    b.add(rectangle_cap(0.0, bh, w, top));
    b.add(rectangle_cap(0.0, top, w, top + at));
    b.add(rectangle_cap(w, top, w + al - fw, top + at));
    b.add(rectangle_cap(w + al - fw, top, w + al, top + at));
    b.add(rectangle_cap(w + al - fw, top - fl, w + al, top));
    return make("hook",
                "a column with an arm at its top and a finger hanging from the arm's end: the "
                "arm is built sideways, the finger grows from it towards the plate",
                extrude_xz(b.cap(), 0.0, d), d * (bl * bh + w * ch + (w + al) * at + fw * fl),
                box_of({0, 0, 0}, {w + al, d, top + at}), [=](double z) {
                    if (z >= 0.0 && z < bh) return bl * d;
                    double a = (z >= bh && z < top) ? w * d : 0.0;
                    if (z >= top - fl && z < top) a += fw * d;
                    if (z >= top && z < top + at) a += (w + al) * d;
                    return a;
                });
}

std::vector<PlannerFixture> all_planner_fixtures() {
    std::vector<PlannerFixture> out;
    out.push_back(vertical_prism());
    out.push_back(cylinder_with_holes());
    out.push_back(ramp_45());
    out.push_back(cone());
    out.push_back(bearing_seat());
    out.push_back(cylinder_on_column());
    out.push_back(t_shape_arms());
    out.push_back(l_bracket());
    out.push_back(leaning_column());
    out.push_back(arch());
    out.push_back(portal_frame());
    out.push_back(slot());
    out.push_back(tall_portal());
    out.push_back(cross_hole_block());
    out.push_back(tab_with_hole());
    out.push_back(helical_ring());
    out.push_back(wall_boss());
    out.push_back(arm_and_post());
    return out;
}

}  // namespace maxslice::test
