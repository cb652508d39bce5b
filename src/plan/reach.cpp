#include "reach.hpp"

#include "cell.hpp"
#include "planner_state.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <span>
#include <utility>

#include "maxslice/core/revolution.hpp"
#include "maxslice/core/units.hpp"
#include "maxslice/geom2d/wire_tree.hpp"

namespace maxslice::plan::detail {
namespace {

using core::Vec3d;

// Material this little above the apex's plane is the layer's own level (mm), as in nozzle.cpp.
constexpr double kLevelTolerance = 1e-6;
// Material this little above the plane `built_below` still counts as built (mm).
constexpr double kBuiltSlackMm = 1e-6;

// The smallest margin of the head at `apex` over the cloud's points on or below `below`
// (every point when below is null), down from best.
double cloud_margin(const HeadProfile& head, const PointCloud& cloud,
                    const slice::PlaneFrame* below, const Vec3d& apex, const Vec3d& axis,
                    double best) {
    const auto& pts = cloud.points();
    cloud.tree().visit(
        [&](const Vec3d& lo, const Vec3d& hi) {
            const Vec3d centre = (lo + hi) * 0.5;
            const Vec3d half = (hi - lo) * 0.5;
            const auto spread = [&](const Vec3d& dir) {
                return half.x * std::abs(dir.x) + half.y * std::abs(dir.y) +
                       half.z * std::abs(dir.z);
            };
            if (below != nullptr && below->height(centre) - spread(below->normal) > kBuiltSlackMm) {
                return false;
            }
            const Vec3d d = centre - apex;
            const double t_c = core::dot(d, axis), t_half = spread(axis);
            if (t_c + t_half <= kLevelTolerance) return false;
            const double r_c = core::norm(d - axis * t_c);
            const double r_lo = std::max(0.0, r_c - core::norm(half));
            return head.bound(std::max(0.0, t_c - t_half), t_c + t_half, r_lo) < best;
        },
        [&](std::uint32_t i) {
            const Vec3d& x = pts[i];
            if (below != nullptr && below->height(x) > kBuiltSlackMm) return;
            const Vec3d d = x - apex;
            const double t = core::dot(d, axis);
            if (t <= kLevelTolerance) return;
            const double r = core::norm(d - axis * t);
            best = std::min(best, head.margin(t, r));
        });
    return best;
}

// The head's lowest point above the plate with its apex at `apex`: the hardware's and the
// stream's, each as the lowest corner of its outline in the (t, r) half plane (a solid of
// revolution is lowest on the rim of one of its circles).
double plate_margin(const Nozzle& n, const slice::PlaneFrame& plate, const Vec3d& apex,
                    const Vec3d& axis) {
    const double c = core::dot(axis, plate.normal);
    const double base = plate.height(apex);
    const double tan_half = std::tan(n.half_angle_deg * std::numbers::pi / 180.0);
    const double so = n.standoff_mm, h = n.cone_length_mm;
    // Called for every apex sampled: fixed outlines, nothing allocated.
    const std::pair<double, double> stream[] = {{0.0, 0.0}, {so, so * tan_half}};
    const std::pair<double, double> hardware[] = {{so, so * tan_half},
                                                  {h, h * tan_half},
                                                  {h, n.body_radius_mm},
                                                  {h + n.body_length_mm, n.body_radius_mm}};
    const bool body = n.body_radius_mm > 0.0 && n.body_length_mm > 0.0;
    return base + std::min(core::lowest_on_revolution(std::span(hardware).first(body ? 4 : 2), c),
                           core::lowest_on_revolution(stream, c) + n.clearance_mm);
}

}  // namespace

PointCloud::PointCloud(std::vector<core::Vec3d> points) : points_(std::move(points)) {
    tree_ = BoxTree(points_, points_);
}

std::vector<Vec3d> boundary_points(const geom2d::Paths2& paths, const slice::PlaneFrame& frame,
                                   double spacing_mm, double lift_mm) {
    std::vector<Vec3d> out;
    for (const geom2d::Path2& path : paths) {
        for (std::size_t i = 0; i < path.size(); ++i) {
            const Vec3d a = frame.to_3d(path[i], lift_mm);
            const Vec3d b = frame.to_3d(path[(i + 1) % path.size()], lift_mm);
            const int n = std::max(1, static_cast<int>(std::ceil(core::norm(b - a) / spacing_mm)));
            for (int k = 0; k < n; ++k) out.push_back(a + (b - a) * (static_cast<double>(k) / n));
        }
    }
    return out;
}

std::vector<Vec3d> interior_points(const geom2d::Paths2& paths, const slice::PlaneFrame& frame,
                                   double spacing_mm, double lift_mm) {
    std::vector<Vec3d> out;
    if (paths.empty()) return out;
    std::int64_t x0 = INT64_MAX, y0 = INT64_MAX, x1 = INT64_MIN, y1 = INT64_MIN;
    for (const geom2d::Path2& path : paths) {
        for (const geom2d::Point2& p : path) {
            x0 = std::min(x0, p.x);
            y0 = std::min(y0, p.y);
            x1 = std::max(x1, p.x);
            y1 = std::max(y1, p.y);
        }
    }
    const auto step = std::max<std::int64_t>(1, core::mm_to_um(spacing_mm));
    for (std::int64_t y = y0 + step / 2; y <= y1; y += step) {
        for (std::int64_t x = x0 + step / 2; x <= x1; x += step) {
            if (geom2d::locate_point(paths, {x, y}) != geom2d::Containment::kOutside) {
                out.push_back(frame.to_3d({x, y}, lift_mm));
            }
        }
    }
    return out;
}

double reach_margin(const Nozzle& nozzle, const ReachScene& scene, std::span<const Vec3d> apexes,
                    const Vec3d& axis, double enough) {
    const HeadProfile head(nozzle);
    double best = enough;
    for (const Vec3d& apex : apexes) {
        best = std::min(best, plate_margin(nozzle, scene.plate, apex, axis));
        if (scene.surface != nullptr) {
            best = cloud_margin(head, *scene.surface, &scene.built_below, apex, axis, best);
        }
        if (scene.extra != nullptr) {
            best = cloud_margin(head, *scene.extra, nullptr, apex, axis, best);
        }
    }
    return best;
}

Vec3d leaned(const Vec3d& ns, const Vec3d& n, double lean_deg) {
    const double a = lean_deg * std::numbers::pi / 180.0;
    return core::normalized(ns * std::cos(a) + n * std::sin(a));
}

core::Result<ReachChoice> choose_by_reach(
    const Nozzle& nozzle, const ReachScene& scene, std::span<const ReachCandidate> candidates,
    double slack_mm,
    const std::function<core::Result<std::vector<Vec3d>>(const Vec3d&)>& apexes_along) {
    if (candidates.empty()) {
        return core::fail(core::ErrorCode::kInvalidInput, "no direction to try", "head reach");
    }
    const double wanted = nozzle.clearance_mm + slack_mm;
    // Margins are looked for only this far above what is wanted: enough to tell.
    const double enough = wanted + 1.0;
    ReachChoice out;
    out.direction = candidates.front().direction;
    std::vector<double> margins;
    margins.reserve(candidates.size());
    for (const ReachCandidate& c : candidates) {
        // Turned directions only where no direction not turned keeps the clearance.
        if (c.turn_deg != 0.0 && std::any_of(margins.begin(), margins.end(),
                                             [&](double m) { return m >= nozzle.clearance_mm; })) {
            break;
        }
        auto apexes = apexes_along(c.direction);
        if (!apexes) return std::unexpected(apexes.error());
        const double m = reach_margin(nozzle, scene, *apexes, c.direction, enough);
        if (margins.empty()) {
            out.seed_margin_mm = m;
            out.margin_mm = m;
        }
        margins.push_back(m);
        if (m >= wanted) break;
    }
    // Among those within the samples' slack of the largest margin, if that keeps the
    // clearance: the least turned, then the most leaned (the most room from the head for
    // the least change of the seed's direction). Margins closer than the slack are one to the
    // samples: taking the largest of them would let a sample's error pick the direction (a
    // part turned about Z would then split differently).
    const double largest = *std::max_element(margins.begin(), margins.end());
    if (largest < nozzle.clearance_mm) return out;
    const double good = std::max(nozzle.clearance_mm, std::min(wanted, largest - slack_mm));
    std::size_t pick = margins.size();
    for (std::size_t k = 0; k < margins.size(); ++k) {
        if (margins[k] < good) continue;
        const ReachCandidate& c = candidates[k];
        if (pick == margins.size() ||
            std::make_pair(std::abs(c.turn_deg), -c.lean_deg) <
                std::make_pair(std::abs(candidates[pick].turn_deg), -candidates[pick].lean_deg)) {
            pick = k;
        }
    }
    out.direction = candidates[pick].direction;
    out.lean_deg = candidates[pick].lean_deg;
    out.turn_deg = candidates[pick].turn_deg;
    out.margin_mm = margins[pick];
    out.clears = true;
    return out;
}

// Two directions closer than this (deg) are one candidate.
constexpr double kSameTowardsDeg = 1.0;

namespace {

// Whether a split plane through p's contact with the layer below, along d, takes p off the
// near side: p's centroid lies in front of it. A region that has not started becomes the near
// side and is walked again: it would keep the piece whole and split for it again and again
// (NIST CTC-04 as given: a lean of a direction turned to the edge of the tilt range put the
// piece behind its plane). A region that has started ends below the piece whatever the plane.
bool separates(const OverhangPiece& p, const Vec3d& d, bool separate) {
    return !separate || core::dot(p.C - p.contact_center, d) > 0.0;
}

}  // namespace

// The sideways region's apexes are sampled on this many planes at most along a direction.
constexpr int kReachPlanes = 48;

// The sphere's sample (direction_by_sphere): neighbours this far apart (deg) ...
constexpr double kSphereStepDeg = 15.0;
// ... and where none of those keeps the clearance, this far apart (deg): a piece's way out can
// be narrower than the coarse step (NIST FTC-06 as given: 6 degrees wide).
constexpr double kSphereFineStepDeg = 5.0;
// A direction of the sample is taken at once when the head keeps this much more than the
// clearance (and the samples' slack) along it; else the one with the largest margin. The
// sample is coarse and the reach check samples the material: the room keeps the build order,
// which measures finer, from finding the head just within the clearance (box_sides.STEP as
// given: without it, a direction 0.1 mm inside).
constexpr double kSphereRoomMm = 2.0;
// Sections grow by at most beta's overhang from one sampled plane to the next, beta capped
// here (deg) so that the growth stays finite.
constexpr double kSphereMaxBetaDeg = 85.0;
// A direction this close to `up` (norm of its part across) has no azimuth of its own.
constexpr double kMinAcross = 1e-9;

// Sample spacing of the head's reach checks: half a track. The margins they give are within a
// quarter track of the surface's, so a direction must keep that much more than the clearance
// (the build order and the verifier check the program itself).
double Planner::reach_spacing() const {
    return std::max(0.5, s_.track_width_mm / 2);
}

// The layers a layer stands on, region by region down to the plate: (region, its last layer
// in the chain) for the layer's own region, then for the region that one grew from, and so on.
// Every layer of the chain is laid before a region split off above `lower`.
std::vector<std::pair<int, int>> Planner::lineage(int lower) const {
    std::vector<std::pair<int, int>> out;
    int layer = lower;
    while (layer >= 0 && out.size() <= plan_.regions.size()) {
        const int r = plan_.layers[static_cast<std::size_t>(layer)].region;
        out.emplace_back(r, layer);
        const auto grew =
            std::find_if(plan_.decisions.begin(), plan_.decisions.end(), [&](const Decision& d) {
                return d.new_region == r || d.continuation == r ||
                       std::find(d.far_regions.begin(), d.far_regions.end(), r) !=
                           d.far_regions.end();
            });
        if (grew == plan_.decisions.end() || grew->layer == layer) break;
        layer = grew->layer;
    }
    return out;
}

// What the head must clear while a region split above layer `lower` is built (s_.head set):
// the part's surface half a layer under L's top (the layer's own top is `top`, and a body
// that only touches that plane from above, the underside of the overhang itself, is not built
// yet), L's top face, the surface of the regions L stands on (after sideways splits, much of
// that lies in front of L's plane: decision 0037), and the plate.
ReachScene Planner::reach_scene(int lower, PointCloud& top) {
    const Layer& l = plan_.layers[static_cast<std::size_t>(lower)];
    const double spacing = reach_spacing();
    if (!surface_) surface_.emplace(mesh::surface_samples(mesh_, spacing));
    const slice::PlaneFrame built_below = l.top.shifted(-s_.layer_mm / 2);
    std::vector<Vec3d> extra =
        interior_points(l.wires.paths(), l.plane, spacing, l.span.top - l.span.cut);
    // L's own region below L's top is built_below already: the regions under it add to it.
    auto chain = lineage(lower);
    chain.erase(chain.begin());
    for (const Vec3d& q : chain.empty() ? std::span<const Vec3d>{} : surface_->points()) {
        if (built_below.height(q) <= kBuiltSlackMm) continue;  // in the scene already
        const bool laid = std::any_of(chain.begin(), chain.end(), [&](const auto& rl) {
            const Region& r = plan_.regions[static_cast<std::size_t>(rl.first)];
            const Layer& last = plan_.layers[static_cast<std::size_t>(rl.second)];
            return last.top.height(q) <= -s_.layer_mm / 2 &&
                   std::all_of(r.cell.begin(), r.cell.end(),
                               [&](const HalfSpace& h) { return h.contains(q); });
        });
        if (laid) extra.push_back(q);
    }
    top = PointCloud(std::move(extra));
    return ReachScene{&*surface_, built_below, &top, plan_.regions.front().base};
}

bool Planner::leaned_by_reach(int rid) const {
    return std::any_of(plan_.decisions.begin(), plan_.decisions.end(), [&](const Decision& d) {
        if (d.new_region == rid) return d.moved_for_reach();
        // A leaned region split again goes on along its direction in its continuation, which
        // must not march either: its tilted layers would turn the head back onto what the
        // lean cleared.
        const bool carries_on =
            (d.continuation == rid && d.region != rid) ||
            std::find(d.far_regions.begin(), d.far_regions.end(), rid) != d.far_regions.end();
        return carries_on && leaned_by_reach(d.region);
    });
}

Planner::ReachPlanes Planner::reach_planes(const OverhangPiece& p,
                                           const std::vector<HalfSpace>& cell,
                                           const Vec3d& d) const {
    ReachPlanes out;
    out.cell = cell;
    out.cell.push_back({p.contact_center, d});
    out.base = slice::PlaneFrame::from_normal(p.contact_center, d);
    const double hi = slice::extent_along(mesh_, out.base).second;
    if (!(hi > 0.0)) return out;
    const int planes = std::clamp(static_cast<int>(std::ceil(hi / s_.layer_mm)), 1, kReachPlanes);
    // The region's first layer, then evenly up to its top.
    const double first = std::min(s_.layer_mm / 2, hi / 2);
    for (int k = 0; k < planes; ++k) {
        out.heights.push_back(planes == 1 ? first : first + (hi - first) * k / (planes - 1));
    }
    return out;
}

core::Result<ReachChoice> Planner::direction_by_reach(int lower, const OverhangPiece& p,
                                                      const Vec3d& ns,
                                                      const std::vector<HalfSpace>& cell,
                                                      bool separate) {
    const Layer& l = plan_.layers[static_cast<std::size_t>(lower)];
    if (!s_.head) return ReachChoice{ns, 0.0, 0.0, 0.0, true};
    const double spacing = reach_spacing();
    const double slack = spacing / 2;
    if (!sections_) sections_.emplace(mesh_);
    PointCloud top;
    const ReachScene scene = reach_scene(lower, top);
    // Leans up to the one whose underside the neighbour analysis still calls carried (a
    // face across the old direction overhangs by tan(lean) per layer height: Ang is about
    // atan(tan(lean) / 2) over the look-back), and no further than 60 degrees.
    const double max_lean =
        std::min(60.0, std::atan(2.0 * std::tan(s_.alpha_deg * std::numbers::pi / 180.0)) * 180.0 /
                           std::numbers::pi);
    // N_s, then N_s leaned towards L's normal (away from what L stands on); after a chain of
    // sideways splits L's normal may lie across the plate, so then also towards the base
    // direction (away from the plate). Each within the table's tilt range, each once.
    const Vec3d up = plan_.regions.front().direction;
    const Vec3d seed = within_tilt(ns);
    std::vector<ReachCandidate> candidates{{seed, 0.0, 0.0}};
    const auto add = [&](const Vec3d& d, double lean, double turn) {
        const bool seen = std::any_of(candidates.begin(), candidates.end(), [&](const auto& c) {
            return angle_deg(c.direction, d) < kSameTowardsDeg;
        });
        if (!seen && separates(p, d, separate)) candidates.push_back({d, lean, turn});
    };
    const auto leans_of = [&](const Vec3d& from, double turn) {
        for (const Vec3d& towards : {l.top.normal, up}) {
            for (const double a : {15.0, 30.0, 40.0, 45.0, 50.0, 60.0}) {
                if (a > max_lean + 1e-9) break;
                add(within_tilt(leaned(from, towards, a)), a, turn);
            }
        }
    };
    leans_of(seed, 0.0);
    const auto apexes_along = [&](const Vec3d& d) -> core::Result<std::vector<Vec3d>> {
        const ReachPlanes rp = reach_planes(p, cell, d);
        const std::vector<HalfSpace>& c = rp.cell;
        std::vector<Vec3d> apexes;
        for (const double at : rp.heights) {
            const slice::PlaneFrame plane = rp.base.shifted(at);
            auto cut = sections_->section(plane, s_.layer_mm);
            if (!cut) return std::unexpected(cut.error());
            const geom2d::Paths2 clipped = clip_to_cell(*cut, c, plane);
            // The melt pool lies on the top of the layer being laid.
            const std::vector<Vec3d> pts =
                boundary_points(clipped, plane, spacing, s_.layer_mm / 2);
            apexes.insert(apexes.end(), pts.begin(), pts.end());
        }
        return apexes;
    };
    // Then N_s turned about L's normal towards either side, and those leaned up again (the
    // piece grows aslant: its sides overhang by the turn); tried only when no lean of N_s
    // itself keeps the clearance.
    for (const double az : {20.0, -20.0, 40.0, -40.0}) {
        const double a = az * std::numbers::pi / 180.0;
        const Vec3d n = l.top.normal;
        const Vec3d turned =
            within_tilt(core::normalized(ns * std::cos(a) + core::cross(n, ns) * std::sin(a)));
        add(turned, 0.0, az);
        leans_of(turned, az);
    }
    auto choice = choose_by_reach(*s_.head, scene, candidates, slack, apexes_along);
    if (!choice || choice->clears) return choice;
    auto searched = direction_by_sphere(p, ns, cell, scene, slack, separate);
    if (!searched) return std::unexpected(searched.error());
    if (!searched->has_value() || !(*searched)->clears) return choice;
    (*searched)->seed_margin_mm = choice->seed_margin_mm;
    return **searched;
}

// Directions on a sphere about `up`, each at most `step_deg` from a neighbour and no more than
// max_tilt_deg from `up`: rings of polar angle every step_deg, each ring's azimuths counted
// from `ns`'s, so a part turned about `up` gets the same directions turned with it.
std::vector<Vec3d> sphere_sample(const Vec3d& up, const Vec3d& ns, double max_tilt_deg,
                                 double step_deg) {
    const double deg = std::numbers::pi / 180.0;
    Vec3d e1 = ns - up * core::dot(ns, up);
    if (core::norm(e1) < kMinAcross) {
        e1 = std::abs(up.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
        e1 = e1 - up * core::dot(e1, up);
    }
    e1 = core::normalized(e1);
    const Vec3d e2 = core::cross(up, e1);
    std::vector<Vec3d> out{up};
    const int rings = static_cast<int>(std::floor(std::min(max_tilt_deg, 180.0) / step_deg + 1e-9));
    for (int k = 1; k <= rings; ++k) {
        const double theta = k * step_deg * deg;
        const int around =
            std::max(1, static_cast<int>(std::ceil(360.0 * std::sin(theta) / step_deg)));
        for (int j = 0; j < around; ++j) {
            const double phi = 2.0 * std::numbers::pi * j / around;
            out.push_back(
                core::normalized(up * std::cos(theta) +
                                 (e1 * std::cos(phi) + e2 * std::sin(phi)) * std::sin(theta)));
        }
    }
    return out;
}

// No lean or turn of N_s keeps the clearance: a sample of the sphere within the table's tilt
// range, nearest to N_s first. A direction is kept only where the material beyond the split
// plane rests on what lies before it (each sampled section within the one before grown as far
// as beta allows, the first on the material just before the split plane) and the head clears
// what is built and the plate: the first such, else the one with the largest margin.
core::Result<std::optional<ReachChoice>> Planner::direction_by_sphere(
    const OverhangPiece& p, const Vec3d& ns, const std::vector<HalfSpace>& cell,
    const ReachScene& scene, double slack, bool separate) {
    const Vec3d up = plan_.regions.front().direction;
    const double spacing = reach_spacing();
    const double tan_beta =
        std::tan(std::min(s_.beta_deg, kSphereMaxBetaDeg) * std::numbers::pi / 180.0);
    const auto half_track = core::mm_to_um(s_.track_width_mm / 2);
    std::vector<Vec3d> tried;
    // The sample at `step` deg, nearest N_s first, but for directions tried before.
    const auto sample = [&](double step) {
        std::vector<std::pair<double, Vec3d>> dirs;
        for (const Vec3d& d : sphere_sample(up, ns, s_.max_tilt_deg, step)) {
            // N_s itself was tried first among the leans.
            const double off = angle_deg(d, ns);
            if (off < kSameTowardsDeg || !separates(p, d, separate) ||
                std::any_of(tried.begin(), tried.end(),
                            [&](const Vec3d& t) { return angle_deg(t, d) < kSameTowardsDeg; })) {
                continue;
            }
            dirs.emplace_back(off, d);
        }
        std::stable_sort(dirs.begin(), dirs.end(),
                         [](const auto& a, const auto& b) { return a.first < b.first; });
        return dirs;
    };
    // What lies before the split plane: the parent's cell (cell's last half-space is 'above
    // L'), which L's region and the region carrying on from L fill before this one.
    const std::vector<HalfSpace> before_split(cell.begin(), cell.end() - 1);
    const double wanted = s_.head->clearance_mm + slack + kSphereRoomMm;
    std::optional<ReachChoice> best;
    for (const double step : {kSphereStepDeg, kSphereFineStepDeg}) {
        if (best) break;
        const auto dirs = sample(step);
        for (const auto& [off, d] : dirs) {
            tried.push_back(d);
            const ReachPlanes rp = reach_planes(p, cell, d);
            if (rp.heights.empty()) continue;
            const slice::PlaneFrame behind = rp.base.shifted(-s_.layer_mm / 2);
            auto before = sections_->section(behind, s_.layer_mm);
            if (!before) return std::unexpected(before.error());
            geom2d::Paths2 prev = clip_to_cell(*before, before_split, behind);
            double prev_at = -s_.layer_mm / 2;
            // Plane by plane: a direction is dropped at the first section that overhangs the one
            // before, or whose head comes closer than the clearance (most directions fail so).
            bool kept = true;
            bool any_apex = false;
            double m = wanted + 1.0;
            for (std::size_t k = 0; k < rp.heights.size() && kept; ++k) {
                const double at = rp.heights[k];
                const slice::PlaneFrame plane = rp.base.shifted(at);
                auto cut = sections_->section(plane, s_.layer_mm);
                if (!cut) return std::unexpected(cut.error());
                geom2d::Paths2 clipped = clip_to_cell(*cut, rp.cell, plane);
                // What overhangs the section before by more than beta allows, without slivers
                // narrower than a track (as the neighbour analysis sees pieces).
                const geom2d::Paths2 bare = geom2d::difference_of(
                    clipped, geom2d::offset_of(prev, core::mm_to_um((at - prev_at) * tan_beta)));
                const geom2d::Paths2 opened = geom2d::intersection_of(
                    geom2d::offset_of(geom2d::offset_of(bare, -half_track), half_track), bare);
                kept = geom2d::signed_area_mm2(opened) < analysis_.min_piece_area_mm2;
                if (kept) {
                    const std::vector<Vec3d> pts =
                        boundary_points(clipped, plane, spacing, s_.layer_mm / 2);
                    any_apex = any_apex || !pts.empty();
                    m = reach_margin(*s_.head, scene, pts, d, m);
                    kept = m >= s_.head->clearance_mm;
                }
                prev = std::move(clipped);
                prev_at = at;
            }
            if (!kept || !any_apex) continue;
            if (!best || m > best->margin_mm) {
                best = ReachChoice{d, 0.0, 0.0, m, 0.0, m >= s_.head->clearance_mm};
                best->searched_deg = off;
            }
            if (m >= wanted) return best;
        }
    }
    return best;
}

}  // namespace maxslice::plan::detail
