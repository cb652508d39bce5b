#include "maxslice/plan/nozzle.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "head_profile.hpp"

// The head is a union of three convex pieces of its (t, r) half plane: the powder stream (the
// cone's triangle up to the nozzle tip), the nozzle (the cone's quadrilateral above it) and
// the body (a rectangle). The distance to a solid of revolution is the 2D distance of (t, r)
// to its outline, so every distance here is exact: the rim and the underside of a body wider
// than the cone count, which the cone-side formula of decision 0008 missed (decision 0023).

namespace maxslice::plan {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kDegToRad = std::numbers::pi / 180.0;
// Material this little above the apex's plane is the layer's own level (mm).
constexpr double kLevelTolerance = 1e-6;

double segment_distance(double t0, double r0, double t1, double r1, double t, double r) {
    const double et = t1 - t0, er = r1 - r0;
    const double len2 = et * et + er * er;
    const double s =
        len2 > 0.0 ? std::clamp(((t - t0) * et + (r - r0) * er) / len2, 0.0, 1.0) : 0.0;
    // Distances stay far from overflow: a plain square root is as good as hypot, and much
    // faster (the build order asks millions of times).
    const double dt = t - (t0 + s * et), dr = r - (r0 + s * er);
    return std::sqrt(dt * dt + dr * dr);
}

}  // namespace

namespace detail {

HeadProfile::HeadProfile(const Nozzle& nozzle) : nozzle_(nozzle) {
    const double a = nozzle.half_angle_deg * kDegToRad;
    cos_half_ = std::cos(a);
    sin_half_ = std::sin(a);
    const double tan_half = std::tan(a);
    const double s = nozzle.standoff_mm, h = nozzle.cone_length_mm;
    body_ = nozzle.body_radius_mm > 0.0 && nozzle.body_length_mm > 0.0;
    length_ = h + (body_ ? nozzle.body_length_mm : 0.0);
    stream_ = make({0.0, s, s, 0.0}, {0.0, 0.0, s * tan_half, 0.0}, s > 0.0);
    cone_ = make({s, h, h, s}, {0.0, 0.0, h * tan_half, s * tan_half}, h > s);
    whole_cone_ = make({0.0, h, h, 0.0}, {0.0, 0.0, h * tan_half, 0.0}, true);
    body_piece_ = make({h, length_, length_, h},
                       {0.0, 0.0, nozzle.body_radius_mm, nozzle.body_radius_mm}, body_);
}

HeadProfile::Piece HeadProfile::make(std::array<double, 4> t, std::array<double, 4> r,
                                     bool present) {
    Piece p{t, r, present, {}};
    for (std::size_t i = 0; i < 4; ++i) {
        const std::size_t j = (i + 1) % 4;
        p.len[i] = std::hypot(t[j] - t[i], r[j] - r[i]);
    }
    return p;
}

double HeadProfile::piece_distance(const Piece& p, double t, double r) {
    if (!p.present) return kInf;
    bool outside = false;
    double depth = -kInf;  // the largest signed distance to a boundary edge's line
    double best = kInf;
    for (std::size_t i = 0; i < 4; ++i) {
        const std::size_t j = (i + 1) % 4;
        const double et = p.t[j] - p.t[i], er = p.r[j] - p.r[i];
        const double len = p.len[i];
        if (len == 0.0) continue;
        // Outward normal of a counter-clockwise edge: (er, -et).
        const double line = ((t - p.t[i]) * er - (r - p.r[i]) * et) / len;
        if (line > 0.0) outside = true;
        if (i > 0) depth = std::max(depth, line);  // edge 0 lies on the axis
        best = std::min(best, segment_distance(p.t[i], p.r[i], p.t[j], p.r[j], t, r));
    }
    return outside ? best : depth;
}

double HeadProfile::distance(double t, double r) const {
    return std::min(piece_distance(whole_cone_, t, r), piece_distance(body_piece_, t, r));
}

double HeadProfile::hardware_distance(double t, double r) const {
    return std::min(piece_distance(cone_, t, r), piece_distance(body_piece_, t, r));
}

double HeadProfile::stream_distance(double t, double r) const {
    return piece_distance(stream_, t, r);
}

double HeadProfile::margin(double t, double r, double cover, bool* in_stream) const {
    const double hardware = hardware_distance(t, r) - cover;
    const double stream = stream_distance(t, r) + nozzle_.clearance_mm;
    if (in_stream != nullptr) *in_stream = stream < hardware;
    return std::min(hardware, stream);
}

double HeadProfile::bound(double t_lo, double t_hi, double r_lo) const {
    const double h = nozzle_.cone_length_mm;
    // The cone (stream and nozzle) lies under its side line and below t = H; the body inside
    // its rectangle's lines.
    const double cone = std::max(r_lo * cos_half_ - std::min(t_hi, h) * sin_half_, t_lo - h);
    if (!body_) return cone;
    const double body = std::max({r_lo - nozzle_.body_radius_mm, h - t_hi, t_lo - length_});
    return std::min(cone, body);
}

double HeadProfile::reach_within(double t, double m) const {
    const double h = nozzle_.cone_length_mm;
    double r = 0.0;
    if (t - h < m) r = (m + std::min(t, h) * sin_half_) / cos_half_;
    if (body_ && h - t < m && t - length_ < m) r = std::max(r, m + nozzle_.body_radius_mm);
    return std::max(r, 0.0);
}

}  // namespace detail

core::Result<void> validate(const Nozzle& n) {
    const auto bad = [](const std::string& m) {
        return core::fail(core::ErrorCode::kInvalidInput, m, "nozzle");
    };
    if (!(n.half_angle_deg > 0.0 && n.half_angle_deg <= 85.0)) {
        return bad(
            fmt::format("nozzle.half_angle_deg must be in (0, 85] (got {})", n.half_angle_deg));
    }
    if (!(n.cone_length_mm > 0.0 && n.cone_length_mm <= 1000.0)) {
        return bad(
            fmt::format("nozzle.cone_length_mm must be in (0, 1000] (got {})", n.cone_length_mm));
    }
    if (!(n.standoff_mm > 0.0 && n.standoff_mm <= n.cone_length_mm)) {
        return bad(fmt::format("nozzle.standoff_mm must be in (0, cone_length_mm = {}] (got {})",
                               n.cone_length_mm, n.standoff_mm));
    }
    if (!(n.body_radius_mm >= 0.0 && n.body_radius_mm <= 1000.0) ||
        !(n.body_length_mm >= 0.0 && n.body_length_mm <= 1000.0)) {
        return bad(
            fmt::format("nozzle.body_radius_mm and nozzle.body_length_mm must be in "
                        "[0, 1000] (got {} and {})",
                        n.body_radius_mm, n.body_length_mm));
    }
    if (!(n.clearance_mm >= 0.0 && n.clearance_mm <= 50.0)) {
        return bad(fmt::format("nozzle.clearance_mm must be in [0, 50] (got {})", n.clearance_mm));
    }
    return {};
}

double head_distance_mm(const Nozzle& nozzle, double t, double r) {
    return detail::HeadProfile(nozzle).distance(t, r);
}

double nozzle_margin_mm(const Nozzle& nozzle, double t, double r) {
    return detail::HeadProfile(nozzle).margin(t, r);
}

double head_distance_bound_mm(const Nozzle& nozzle, double t_lo, double t_hi, double r_lo) {
    return detail::HeadProfile(nozzle).bound(t_lo, t_hi, r_lo);
}

double nozzle_clearance(const Nozzle& nozzle, const core::Vec3d& apex, const core::Vec3d& axis,
                        const core::Vec3d& x) {
    const core::Vec3d rel = x - apex;
    const double t = core::dot(rel, axis);
    if (t <= kLevelTolerance) return kInf;
    return head_distance_mm(nozzle, t, core::norm(rel - axis * t));
}

}  // namespace maxslice::plan
