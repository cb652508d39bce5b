#include "maxslice/plan/analysis.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "maxslice/core/units.hpp"
#include "maxslice/geom2d/wire_tree.hpp"

namespace maxslice::plan {
namespace {

using geom2d::Path2;
using geom2d::Paths2;
using geom2d::Point2;

// The contact line between a piece and L is found within this distance (um) beyond the
// self-supporting allowance: the piece's boundary and L's lie that far apart at most after
// the integer offsets' rounding.
constexpr std::int64_t kContactSlackUm = 20;
// Boundaries are simplified to this share of a track before the analysis (0.01: 25 um at a
// 2.5 mm track; the pieces it decides about are a track wide).
constexpr double kSimplifyShare = 0.01;
// Half the side of the squares that cut a piece into quadrants (um): far beyond any part.
constexpr std::int64_t kQuadrantUm = geom2d::kMaxCoordinateUm / 4;

std::unexpected<core::Error> invalid(const std::string& what) {
    return core::fail(core::ErrorCode::kInvalidInput, what, "neighbour analysis");
}

core::Vec3d to_3d(const slice::PlaneFrame& f, geom2d::Centroid2 c) {
    return f.origin + f.u * (c.x / core::kMicronsPerMm) + f.v * (c.y / core::kMicronsPerMm);
}

// A region without its parts narrower than twice `half` (um): a morphological opening.
Paths2 opened_by(const Paths2& region, std::int64_t half) {
    return geom2d::intersection_of(geom2d::offset_of(geom2d::offset_of(region, -half), half),
                                   region);
}

// The pieces of a region: each outer wire with its holes.
std::vector<Paths2> pieces_of(const Paths2& region) {
    return geom2d::build_wire_tree(region, geom2d::FillRule::kPositive).islands();
}

// The four quadrants of a piece about point c, along the frame's axes.
std::vector<Paths2> quadrants(const Paths2& piece, geom2d::Centroid2 c) {
    const Point2 o{std::llround(c.x), std::llround(c.y)};
    std::vector<Paths2> out;
    for (const auto& [sx, sy] : {std::pair{1, 1}, {-1, 1}, {-1, -1}, {1, -1}}) {
        const std::int64_t x1 = o.x + sx * kQuadrantUm, y1 = o.y + sy * kQuadrantUm;
        Path2 square{{std::min(o.x, x1), std::min(o.y, y1)},
                     {std::max(o.x, x1), std::min(o.y, y1)},
                     {std::max(o.x, x1), std::max(o.y, y1)},
                     {std::min(o.x, x1), std::max(o.y, y1)}};
        for (Paths2& q : pieces_of(geom2d::intersection_of(piece, {square}))) {
            out.push_back(std::move(q));
        }
    }
    return out;
}

// The self-supporting allowance over a height h_mm (um): h tan(phi_self), h at most the
// settings' cap.
std::int64_t allowance_um(double h_mm, const AnalysisSettings& s) {
    double h = std::max(0.0, h_mm);
    if (s.max_allowance_height_mm > 0.0) h = std::min(h, s.max_allowance_height_mm);
    return core::mm_to_um(h * std::tan(s.self_supporting_deg * std::numbers::pi / 180));
}

}  // namespace

Paths2 project_paths(const Paths2& region, const slice::PlaneFrame& from,
                     const slice::PlaneFrame& to) {
    Paths2 out;
    out.reserve(region.size());
    for (const Path2& path : region) {
        Path2& q = out.emplace_back();
        q.reserve(path.size());
        for (const Point2& p : path) q.push_back(to.to_2d(from.to_3d(p)));
    }
    return out;
}

bool rests_on_section(const Paths2& piece, const Paths2& below, double h_mm,
                      const AnalysisSettings& s) {
    if (geom2d::signed_area_mm2(below) <= 0.0) return false;
    const auto allowance = allowance_um(h_mm, s);
    const Paths2 carried = allowance > 0 ? geom2d::offset_of(below, allowance) : below;
    return geom2d::signed_area_mm2(geom2d::difference_of(piece, carried)) < s.min_piece_area_mm2;
}

double angle_deg(const core::Vec3d& a, const core::Vec3d& b) {
    const double na = core::norm(a), nb = core::norm(b);
    if (na <= 0.0 || nb <= 0.0) return 0.0;
    const double c = std::clamp(core::dot(a, b) / (na * nb), -1.0, 1.0);
    return std::acos(c) * 180.0 / std::numbers::pi;
}

core::Result<NeighbourAnalysis> analyse_neighbours(const Paths2& lower_in,
                                                   const slice::PlaneFrame& lower_plane,
                                                   const Paths2& upper,
                                                   const slice::PlaneFrame& upper_plane,
                                                   const AnalysisSettings& s) {
    if (!(s.track_width_mm > 0.0) || !std::isfinite(s.track_width_mm)) {
        return invalid("track_width_mm must be a positive number of mm");
    }
    if (!(s.self_supporting_deg >= 0.0) || !(s.self_supporting_deg < 90.0)) {
        return invalid("the self-supporting angle must be at least 0 and below 90 degrees");
    }
    if (!(s.min_piece_area_mm2 >= 0.0) || !std::isfinite(s.min_piece_area_mm2)) {
        return invalid("min_piece_area_mm2 must be a non-negative number");
    }
    if (!(s.max_allowance_height_mm >= 0.0) || !std::isfinite(s.max_allowance_height_mm)) {
        return invalid("max_allowance_height_mm must be a non-negative number");
    }
    NeighbourAnalysis out;
    // Vertices that move a boundary by less than this are dropped first: finely tessellated
    // round sections would otherwise make every offset resolve thousands of tiny edges.
    const auto tolerance =
        std::max<std::int64_t>(1, core::mm_to_um(kSimplifyShare * s.track_width_mm));
    const Paths2 lower_s = geom2d::simplify(lower_in, tolerance);
    const Paths2& lower = lower_s;
    const Paths2 u = geom2d::simplify(project_paths(upper, upper_plane, lower_plane), tolerance);
    if (geom2d::signed_area_mm2(u) <= 0.0) return out;  // nothing above: carried

    // h: the distance between the planes along N_b, at U's centroid.
    const geom2d::Centroid2 uc = geom2d::centroid_um(upper);
    const double h = lower_plane.height(to_3d(upper_plane, uc));
    const auto allowance = allowance_um(h, s);
    const Paths2 grown = allowance > 0 ? geom2d::offset_of(lower, allowance) : lower;
    const Paths2 raw = geom2d::difference_of(u, grown);
    if (raw.empty()) return out;

    // Slivers narrower than a track: a morphological opening by half a track. Not so an island
    // of U that meets nothing of L: narrow or not, it starts in the air.
    const auto half = core::mm_to_um(s.track_width_mm / 2);
    const bool lower_empty = geom2d::signed_area_mm2(lower) <= 0.0;
    Paths2 floating;
    if (!lower_empty) {
        for (const Paths2& island : pieces_of(u)) {
            if (geom2d::intersection_of(island, grown).empty()) {
                floating.insert(floating.end(), island.begin(), island.end());
            }
        }
    }
    Paths2 opened = opened_by(raw, half);
    if (!floating.empty()) {
        opened.insert(opened.end(), floating.begin(), floating.end());
        opened = geom2d::union_of(opened);
    }

    std::vector<Paths2> pieces;
    for (Paths2& piece : pieces_of(opened)) {
        if (geom2d::signed_area_mm2(piece) < s.min_piece_area_mm2) continue;
        const geom2d::Centroid2 c = geom2d::centroid_um(piece);
        const Point2 ci{std::llround(c.x), std::llround(c.y)};
        if (!lower_empty && geom2d::locate_point(grown, ci) != geom2d::Containment::kOutside) {
            for (Paths2& q : quadrants(piece, c)) {
                if (geom2d::signed_area_mm2(q) >= s.min_piece_area_mm2) pieces.push_back(q);
            }
        } else {
            pieces.push_back(std::move(piece));
        }
    }
    if (pieces.empty()) return out;

    // L where a track fits: L opened by half a track.
    const Paths2 lower_tracked = lower_empty ? Paths2{} : opened_by(lower, half);
    bool any_touching = false;
    for (Paths2& piece : pieces) {
        OverhangPiece p;
        p.area_mm2 = geom2d::signed_area_mm2(piece);
        const geom2d::Centroid2 c = geom2d::centroid_um(piece);
        const core::Vec3d c_low = to_3d(lower_plane, c);
        // C_i on U's plane: along N_b from L's plane.
        const double denom = core::dot(lower_plane.normal, upper_plane.normal);
        const double t = std::abs(denom) > 1e-12
                             ? core::dot(upper_plane.origin - c_low, upper_plane.normal) / denom
                             : h;
        p.C = c_low + lower_plane.normal * t;
        if (lower_empty) {
            p.P = c_low;
            p.touches_lower = false;
        } else {
            const geom2d::ClosestPoint cp = geom2d::closest_boundary_point(lower, c);
            p.P = lower_plane.to_3d(cp.point);
            const Paths2 contact = geom2d::intersection_of(
                geom2d::offset_of(piece, allowance + kContactSlackUm), lower);
            p.touches_lower = !contact.empty();
            if (p.touches_lower) {
                std::int64_t x0 = INT64_MAX, y0 = INT64_MAX, x1 = INT64_MIN, y1 = INT64_MIN;
                for (const Path2& q : contact) {
                    for (const Point2& pt : q) {
                        x0 = std::min(x0, pt.x);
                        y0 = std::min(y0, pt.y);
                        x1 = std::max(x1, pt.x);
                        y1 = std::max(y1, pt.y);
                    }
                }
                p.contact_center = to_3d(lower_plane, {0.5 * static_cast<double>(x0 + x1),
                                                       0.5 * static_cast<double>(y0 + y1)});
            }
        }
        if (!p.touches_lower && !lower_empty && !lower_tracked.empty()) {
            // A piece that touches nothing hangs from L where a track is laid, not from a
            // sliver of L narrower than one (left bare: it carries nothing).
            p.P = lower_plane.to_3d(geom2d::closest_boundary_point(lower_tracked, c).point);
        }
        if (!p.touches_lower) p.contact_center = p.P;
        any_touching = any_touching || p.touches_lower;
        p.V = p.C - p.P;
        p.ang_deg = angle_deg(p.V, lower_plane.normal);
        p.region = std::move(piece);
        out.pieces.push_back(std::move(p));
    }
    std::stable_sort(out.pieces.begin(), out.pieces.end(),
                     [](const OverhangPiece& a, const OverhangPiece& b) {
                         if (a.ang_deg != b.ang_deg) return a.ang_deg > b.ang_deg;
                         return a.area_mm2 > b.area_mm2;
                     });
    // dA = U: nothing of U rests on L.
    const bool u_on_l = !geom2d::intersection_of(u, grown).empty();
    out.support = u_on_l || any_touching ? Support::kOverhang : Support::kUnrelated;
    return out;
}

}  // namespace maxslice::plan
