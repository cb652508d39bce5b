#include "support/nozzle_check.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <numbers>
#include <utility>

#include "maxslice/path/toolpath.hpp"

namespace maxslice::test {
namespace {

using core::Vec3d;

// A sample at most this far above the apex's plane is material under the melt pool.
constexpr double kAboveApexMm = 1e-6;

double radians(double deg) {
    return deg * std::numbers::pi / 180.0;
}

Vec3d lift(const slice::PlaneFrame& f, double x_um, double y_um, double height_mm = 0.0) {
    return f.origin + f.u * (x_um * 1e-3) + f.v * (y_um * 1e-3) + f.normal * height_mm;
}

// Onto the layer's top plane along its normal.
Vec3d onto_top(const plan::Layer& l, const Vec3d& x) {
    return x - l.top.normal * core::dot(x - l.top.origin, l.top.normal);
}

// How far the nozzle reaches from its apex (mm).
double reach_mm(const plan::Nozzle& n) {
    const double a = radians(n.half_angle_deg);
    double r = n.cone_length_mm / std::cos(a);
    if (n.body_radius_mm > 0.0 && n.body_length_mm > 0.0) {
        r = std::max(r, std::hypot(n.cone_length_mm + n.body_length_mm, n.body_radius_mm));
    }
    return r;
}

double box_distance(const core::Box3d& b, const Vec3d& p) {
    const double dx = std::max({b.min.x - p.x, 0.0, p.x - b.max.x});
    const double dy = std::max({b.min.y - p.y, 0.0, p.y - b.max.y});
    const double dz = std::max({b.min.z - p.z, 0.0, p.z - b.max.z});
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

double box_box_distance(const core::Box3d& a, const core::Box3d& b) {
    const double dx = std::max({b.min.x - a.max.x, 0.0, a.min.x - b.max.x});
    const double dy = std::max({b.min.y - a.max.y, 0.0, a.min.y - b.max.y});
    const double dz = std::max({b.min.z - a.max.z, 0.0, a.min.z - b.max.z});
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

// The largest height of the box's corners along n.
double box_max_along(const core::Box3d& b, const Vec3d& n) {
    return (n.x > 0 ? b.max.x : b.min.x) * n.x + (n.y > 0 ? b.max.y : b.min.y) * n.y +
           (n.z > 0 ? b.max.z : b.min.z) * n.z;
}

// Points along a segment from a (excluded) to b (included), at most step apart (um).
template <class Emit>
void resample(double ax, double ay, double bx, double by, double step_um, Emit&& emit) {
    const double len = std::hypot(bx - ax, by - ay);
    const int n = std::max(1, static_cast<int>(std::ceil(len / step_um)));
    for (int k = 1; k <= n; ++k) {
        const double s = static_cast<double>(k) / n;
        emit(ax + (bx - ax) * s, ay + (by - ay) * s);
    }
}

struct Sampled {
    std::vector<Vec3d> points;
    core::Box3d box;
};

Sampled boxed(std::vector<Vec3d> points) {
    Sampled s{std::move(points), {}};
    for (const Vec3d& p : s.points) s.box.add(p);
    return s;
}

}  // namespace

std::string describe(const NozzleCollision& c) {
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "layer %d hits layer %d at (%.3f, %.3f, %.3f) from apex (%.3f, %.3f, %.3f), "
                  "clearance %.3f mm",
                  c.layer, c.other, c.point.x, c.point.y, c.point.z, c.apex.x, c.apex.y, c.apex.z,
                  c.clearance_mm);
    return buf;
}

namespace {

// Distance from (t, r) to the segment from (t0, r0) to (t1, r1).
double to_segment(double t, double r, double t0, double r0, double t1, double r1) {
    const double dt = t1 - t0, dr = r1 - r0;
    double s = ((t - t0) * dt + (r - r0) * dr) / (dt * dt + dr * dr);
    s = std::min(1.0, std::max(0.0, s));
    const double et = t - t0 - s * dt, er = r - r0 - s * dr;
    return std::sqrt(et * et + er * er);  // not std::hypot: ten times slower, no gain here
}

// The slice t in [lo, hi] of the cone r <= t tan(a): inside, minus the depth (to its side,
// or to the planes t = lo and t = hi); outside, the distance to its side and its two faces.
double to_cone_slice(double t, double r, double lo, double hi, double a) {
    if (!(hi > lo)) return std::numeric_limits<double>::infinity();
    const double ta = std::tan(a);
    if (t >= lo && t <= hi && r <= t * ta) {
        return -std::min({(t * ta - r) * std::cos(a), t - lo, hi - t});
    }
    return std::min({to_segment(t, r, lo, lo * ta, hi, hi * ta),
                     to_segment(t, r, hi, 0, hi, hi * ta),
                     lo > 0.0 ? to_segment(t, r, lo, 0, lo, lo * ta)
                              : std::numeric_limits<double>::infinity()});
}

double to_body(const plan::Nozzle& n, double t, double r) {
    if (!(n.body_radius_mm > 0.0 && n.body_length_mm > 0.0)) {
        return std::numeric_limits<double>::infinity();
    }
    const double lo = n.cone_length_mm, hi = lo + n.body_length_mm, rad = n.body_radius_mm;
    const double dt = std::max({lo - t, 0.0, t - hi}), dr = std::max(r - rad, 0.0);
    if (dt == 0.0 && dr == 0.0) return -std::min({t - lo, hi - t, rad - r});
    return std::sqrt(dt * dt + dr * dr);
}

// (t, r) of x for the head at apex along axis; false at or below the apex's plane.
bool head_coordinates(const Vec3d& apex, const Vec3d& axis, const Vec3d& x, double* t, double* r) {
    const Vec3d d = x - apex;
    *t = core::dot(d, axis);
    if (*t <= kAboveApexMm) return false;
    const Vec3d radial = d - axis * *t;
    *r = std::sqrt(core::dot(radial, radial));
    return true;
}

}  // namespace

double cone_clearance_mm(const plan::Nozzle& nozzle, const Vec3d& apex, const Vec3d& axis,
                         const Vec3d& x) {
    double t = 0.0, r = 0.0;
    if (!head_coordinates(apex, axis, x, &t, &r)) return std::numeric_limits<double>::infinity();
    const double a = radians(nozzle.half_angle_deg);
    return std::min(to_cone_slice(t, r, 0.0, nozzle.cone_length_mm, a), to_body(nozzle, t, r));
}

double hardware_clearance_mm(const plan::Nozzle& nozzle, const Vec3d& apex, const Vec3d& axis,
                             const Vec3d& x) {
    double t = 0.0, r = 0.0;
    if (!head_coordinates(apex, axis, x, &t, &r)) return std::numeric_limits<double>::infinity();
    const double a = radians(nozzle.half_angle_deg);
    return std::min(to_cone_slice(t, r, nozzle.standoff_mm, nozzle.cone_length_mm, a),
                    to_body(nozzle, t, r));
}

double stream_clearance_mm(const plan::Nozzle& nozzle, const Vec3d& apex, const Vec3d& axis,
                           const Vec3d& x) {
    double t = 0.0, r = 0.0;
    if (!head_coordinates(apex, axis, x, &t, &r)) return std::numeric_limits<double>::infinity();
    return to_cone_slice(t, r, 0.0, nozzle.standoff_mm, radians(nozzle.half_angle_deg));
}

bool inside_wires(const geom2d::WireTree& wires, double x_um, double y_um) {
    int winding = 0;
    for (const geom2d::WireNode& node : wires.nodes) {
        const geom2d::Path2& w = node.wire;
        for (std::size_t i = 0; i < w.size(); ++i) {
            const geom2d::Point2 a = w[i];
            const geom2d::Point2 b = w[(i + 1) % w.size()];
            const auto ay = static_cast<double>(a.y);
            const auto by = static_cast<double>(b.y);
            if ((ay <= y_um) == (by <= y_um)) continue;  // does not cross the ray's line
            const double xc =
                static_cast<double>(a.x) + (y_um - ay) * static_cast<double>(b.x - a.x) / (by - ay);
            if (xc > x_um) winding += by > ay ? 1 : -1;
        }
    }
    return winding > 0;
}

std::vector<Vec3d> nozzle_apexes(const plan::Layer& layer, double track_width_mm, double step_mm) {
    path::PathSettings ps;
    ps.track_width_mm = track_width_mm;
    const auto tp = path::plan_layer(layer.wires, ps, geom2d::Point2{});
    if (!tp) {
        ADD_FAILURE() << "plan_layer failed on layer " << layer.id << ": " << tp.error().describe();
        return {};
    }
    std::vector<Vec3d> out;
    const auto emit = [&](double x, double y) {
        out.push_back(onto_top(layer, lift(layer.plane, x, y)));
    };
    const double step_um = step_mm * 1000.0;
    for (const path::Stroke& s : tp->strokes) {
        if (s.points.empty()) continue;
        emit(static_cast<double>(s.points.front().x), static_cast<double>(s.points.front().y));
        for (std::size_t i = 1; i < s.points.size(); ++i) {
            resample(static_cast<double>(s.points[i - 1].x), static_cast<double>(s.points[i - 1].y),
                     static_cast<double>(s.points[i].x), static_cast<double>(s.points[i].y),
                     step_um, emit);
        }
    }
    return out;
}

std::vector<Vec3d> material_points(const plan::Layer& layer, double step_mm) {
    std::vector<Vec3d> out;
    const double half = 0.5 * layer.thickness_max_mm;
    const auto emit = [&](double x, double y) {
        out.push_back(lift(layer.plane, x, y, -half));
        out.push_back(onto_top(layer, lift(layer.plane, x, y)));
    };
    const double step_um = step_mm * 1000.0;
    double lo_x = INFINITY, lo_y = INFINITY, hi_x = -INFINITY, hi_y = -INFINITY;
    for (const geom2d::WireNode& node : layer.wires.nodes) {
        const geom2d::Path2& w = node.wire;
        for (std::size_t i = 0; i < w.size(); ++i) {
            const geom2d::Point2 a = w[i];
            const geom2d::Point2 b = w[(i + 1) % w.size()];
            lo_x = std::min(lo_x, static_cast<double>(a.x));
            lo_y = std::min(lo_y, static_cast<double>(a.y));
            hi_x = std::max(hi_x, static_cast<double>(a.x));
            hi_y = std::max(hi_y, static_cast<double>(a.y));
            // Ends at b: every vertex once, each edge resampled.
            resample(static_cast<double>(a.x), static_cast<double>(a.y), static_cast<double>(b.x),
                     static_cast<double>(b.y), step_um, emit);
        }
    }
    if (!(lo_x <= hi_x)) return out;
    for (double y = lo_y + 0.5 * step_um; y < hi_y; y += step_um) {
        for (double x = lo_x + 0.5 * step_um; x < hi_x; x += step_um) {
            if (inside_wires(layer.wires, x, y)) emit(x, y);
        }
    }
    return out;
}

std::vector<NozzleCollision> brute_force_collisions(const plan::Plan& plan,
                                                    std::span<const int> order,
                                                    const plan::Nozzle& nozzle,
                                                    double track_width_mm,
                                                    const NozzleCheckSettings& settings) {
    const auto n = plan.layers.size();
    std::vector<Sampled> apexes(n);
    std::vector<Sampled> material(n);
    for (const int id : order) {
        if (id < 0 || static_cast<std::size_t>(id) >= n) {
            ADD_FAILURE() << "order names layer " << id << " of " << n;
            return {};
        }
        const plan::Layer& l = plan.layers[static_cast<std::size_t>(id)];
        apexes[static_cast<std::size_t>(id)] =
            boxed(nozzle_apexes(l, track_width_mm, settings.sample_step_mm));
        material[static_cast<std::size_t>(id)] = boxed(material_points(l, settings.sample_step_mm));
    }
    const double reach = reach_mm(nozzle) + settings.clearance_mm;
    std::vector<NozzleCollision> out;
    for (std::size_t i = 0; i < order.size(); ++i) {
        const int lid = order[i];
        const Sampled& a = apexes[static_cast<std::size_t>(lid)];
        if (a.points.empty()) continue;
        const Vec3d axis = plan.layers[static_cast<std::size_t>(lid)].top.normal;
        double lowest = INFINITY;
        for (const Vec3d& p : a.points) lowest = std::min(lowest, core::dot(p, axis));
        for (std::size_t j = 0; j < i; ++j) {
            const int oid = order[j];
            const Sampled& m = material[static_cast<std::size_t>(oid)];
            if (m.points.empty()) continue;
            // Entirely under every apex's plane, or out of the nozzle's reach: nothing to hit.
            const double top = box_max_along(m.box, axis);
            if (top <= lowest + kAboveApexMm) continue;
            if (box_box_distance(a.box, m.box) > reach) continue;
            NozzleCollision worst;
            worst.clearance_mm = -settings.tolerance_mm;
            for (const Vec3d& apex : a.points) {
                if (top <= core::dot(apex, axis) + kAboveApexMm) continue;
                if (box_distance(m.box, apex) > reach) continue;
                for (const Vec3d& x : m.points) {
                    const double c = cone_clearance_mm(nozzle, apex, axis, x);
                    if (c < worst.clearance_mm) worst = {lid, oid, apex, x, c};
                    if (settings.clearance_mm > 0.0 && worst.layer < 0) {
                        const double h = hardware_clearance_mm(nozzle, apex, axis, x);
                        if (h < settings.clearance_mm - settings.tolerance_mm) {
                            worst = {lid, oid, apex, x, h};
                        }
                    }
                }
            }
            if (worst.layer >= 0) out.push_back(worst);
            if (settings.max_pairs > 0 && std::cmp_greater_equal(out.size(), settings.max_pairs)) {
                return out;
            }
        }
    }
    return out;
}

std::vector<NozzleCollision> brute_force_collisions(const plan::Plan& plan,
                                                    const plan::BuildOrder& order,
                                                    const plan::Nozzle& nozzle,
                                                    double track_width_mm,
                                                    const NozzleCheckSettings& settings) {
    return brute_force_collisions(plan, std::span<const int>(order.order), nozzle, track_width_mm,
                                  settings);
}

}  // namespace maxslice::test
