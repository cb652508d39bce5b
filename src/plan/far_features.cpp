// Far features of a split (docs/method.md section 5, decision 0035): the half-space beyond a
// split plane takes in everything of the part on that side, also features far from the
// overhang piece that do not grow from it (a post further along a shelf, the next body of a
// multi-body part). Built along the new region's direction they start as tips in the air. The
// new region keeps what grows from its piece: the material of its cell connected to the piece
// through its own slices. A feature apart from it that stands on the layer below the split
// carries on along the old direction, as it would have without the split, in a region of its
// own past a plane between it and the new region's material. Cells stay convex.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <numeric>
#include <vector>

#include "cell.hpp"
#include "maxslice/core/union_find.hpp"
#include "maxslice/core/units.hpp"
#include "maxslice/geom2d/wire_tree.hpp"
#include "planner_state.hpp"

namespace maxslice::plan::detail {
namespace {

// Normals tried for a separating plane: this many around the new region's direction (planes
// along it, cutting its layers square) ...
constexpr int kAround = 72;
// ... and this many spread over the sphere (a Fibonacci lattice).
constexpr int kSphere = 256;
// The climb from the best candidate normal: steps from this angle (rad) ...
constexpr double kRefineStartRad = 4.0 * std::numbers::pi / 180.0;
// ... halved down to this one, trying this many directions around the normal at each ...
constexpr double kRefineEndRad = 0.05 * std::numbers::pi / 180.0;
constexpr int kRefineAround = 8;
// ... and going on at a step while the gap grows by more than this (mm), at most this often.
constexpr double kRefineGainMm = 1e-6;
constexpr int kRefineRounds = 32;
// No island's root.
constexpr std::size_t kNoRoot = static_cast<std::size_t>(-1);
// A feature whose lowest point lies within a layer of L's top, and this much (mm), stands
// on L.
constexpr double kOnLayerSlackMm = 0.01;

struct Island {
    std::size_t slice = 0;
    geom2d::Paths2 paths;
    geom2d::Point2 lo;
    geom2d::Point2 hi;
};

bool boxes_overlap(const Island& a, const Island& b) {
    return a.lo.x <= b.hi.x && b.lo.x <= a.hi.x && a.lo.y <= b.hi.y && b.lo.y <= a.hi.y;
}

// The best plane between two point sets: the normal w (of the candidates) with the widest
// gap min(w . b) - max(w . a), and the middle of the gap along w.
struct Separation {
    core::Vec3d w;
    double gap = -1e300;
    double mid = 0.0;
};

void try_normal(const std::vector<core::Vec3d>& a, const std::vector<core::Vec3d>& b,
                const core::Vec3d& w, Separation& best) {
    double amax = -1e300;
    for (const core::Vec3d& x : a) amax = std::max(amax, core::dot(w, x));
    double bmin = 1e300;
    for (const core::Vec3d& x : b) {
        bmin = std::min(bmin, core::dot(w, x));
        if (bmin - amax <= best.gap) return;  // no better than the best so far
    }
    best = {w, bmin - amax, 0.5 * (amax + bmin)};
}

Separation separate(const std::vector<core::Vec3d>& a, const std::vector<core::Vec3d>& b,
                    const std::vector<core::Vec3d>& normals) {
    Separation best;
    for (const core::Vec3d& w : normals) try_normal(a, b, w, best);
    // Then climbs from the best candidate, turning it by smaller and smaller steps, so that
    // the gap found hardly depends on where the candidates happen to lie (a part turned about
    // its base direction gets the same plane).
    for (double step = kRefineStartRad; step >= kRefineEndRad; step *= 0.5) {
        bool better = true;
        for (int round = 0; better && round < kRefineRounds; ++round) {
            better = false;
            const core::Vec3d w = best.w;
            const core::Vec3d e1 =
                core::normalized(std::abs(w.x) < 0.9 ? core::cross(w, core::Vec3d{1, 0, 0})
                                                     : core::cross(w, core::Vec3d{0, 1, 0}));
            const core::Vec3d e2 = core::cross(w, e1);
            for (int k = 0; k < kRefineAround; ++k) {
                const double turn = 2.0 * std::numbers::pi * k / kRefineAround;
                const double gap = best.gap;
                const core::Vec3d aside = e1 * std::cos(turn) + e2 * std::sin(turn);
                try_normal(a, b, core::normalized(w * std::cos(step) + aside * std::sin(step)),
                           best);
                better = better || best.gap > gap + kRefineGainMm;
            }
        }
    }
    return best;
}

}  // namespace

core::Result<std::vector<HalfSpace>> Planner::far_feature_bounds(const Region& child, int lower,
                                                                 const OverhangPiece& p) {
    const double hi = slice::extent_along(mesh_, child.base).second;
    if (!(hi > 0.0)) return std::vector<HalfSpace>{};
    SliceStack slices(mesh_, child.base,
                      slice::uniform_layers(0.0, hi, s_.layer_mm, s_.h_min_mm, s_.h_max_mm));
    // The islands of the new region's slices, within its cell.
    std::vector<Island> islands;
    std::vector<std::size_t> first_of(slices.size() + 1, 0);  // islands of slice i: [first, next)
    for (std::size_t i = 0; i < slices.size(); ++i) {
        first_of[i] = islands.size();
        auto s = slices.at(i);
        if (!s) return std::unexpected(s.error());
        const geom2d::Paths2 clipped = clip_to_cell((*s)->wires.paths(), child.cell, (*s)->plane);
        if (geom2d::signed_area_mm2(clipped) <= 0.0) continue;
        for (geom2d::Paths2& isl :
             geom2d::build_wire_tree(clipped, geom2d::FillRule::kPositive).islands()) {
            Island is;
            is.slice = i;
            is.lo = {isl.front().front().x, isl.front().front().y};
            is.hi = is.lo;
            for (const geom2d::Point2& q : isl.front()) {
                is.lo = {std::min(is.lo.x, q.x), std::min(is.lo.y, q.y)};
                is.hi = {std::max(is.hi.x, q.x), std::max(is.hi.y, q.y)};
            }
            is.paths = std::move(isl);
            islands.push_back(std::move(is));
        }
    }
    first_of[slices.size()] = islands.size();
    if (islands.size() < 2) return std::vector<HalfSpace>{};

    // Connected through the slices: an island on one it overlaps in the slice below.
    core::UnionFind uf(islands.size());
    const auto root = [&](std::size_t i) -> std::size_t {
        return uf.find(static_cast<std::uint32_t>(i));
    };
    for (std::size_t i = 1; i < slices.size(); ++i) {
        for (std::size_t a = first_of[i]; a < first_of[i + 1]; ++a) {
            for (std::size_t b = first_of[i - 1]; b < first_of[i]; ++b) {
                if (root(a) == root(b) || !boxes_overlap(islands[a], islands[b])) continue;
                if (geom2d::signed_area_mm2(
                        geom2d::intersection_of(islands[a].paths, islands[b].paths)) > 0.0) {
                    uf.unite(static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b));
                }
            }
        }
    }

    // What grows from the piece: the islands within a track of the piece's points (its
    // outline and centroid on U, its contact centre) in the slices those points fall in.
    const Layer& l = plan_.layers[static_cast<std::size_t>(lower)];
    std::vector<core::Vec3d> seeds{p.C, p.contact_center};
    for (const geom2d::Path2& path : p.region) {
        for (const geom2d::Point2& q : path) seeds.push_back(l.plane.to_3d(q));
    }
    const double reach_um = s_.track_width_mm * core::kMicronsPerMm;
    std::vector<char> own_root(islands.size(), 0);
    bool any_own = false;
    for (const core::Vec3d& x : seeds) {
        const double t = child.base.height(x);
        for (std::size_t i = 0; i < slices.size(); ++i) {
            const slice::Slice& s = **slices.at(i);  // sliced above
            if (t < s.span.bottom - s_.layer_mm || t > s.span.top + s_.layer_mm) continue;
            const geom2d::Point2 q = s.plane.to_2d(x);
            for (std::size_t k = first_of[i]; k < first_of[i + 1]; ++k) {
                const geom2d::ClosestPoint c = geom2d::closest_region_point(
                    islands[k].paths, {static_cast<double>(q.x), static_cast<double>(q.y)});
                if (c.distance_um <= reach_um) {
                    own_root[root(k)] = 1;
                    any_own = true;
                }
            }
        }
    }
    if (!any_own) return std::vector<HalfSpace>{};

    // The features apart from the piece, in the order their first islands come, and the
    // islands of each (group 0: the new region's own).
    std::vector<std::size_t> roots{kNoRoot};
    std::vector<std::vector<std::size_t>> members(1);
    for (std::size_t k = 0; k < islands.size(); ++k) {
        const std::size_t r = root(k);
        std::size_t g = 0;
        if (own_root[r] == 0) {
            g = static_cast<std::size_t>(std::find(roots.begin(), roots.end(), r) - roots.begin());
            if (g == roots.size()) {
                roots.push_back(r);
                members.emplace_back();
            }
        }
        members[g].push_back(k);
    }
    // Points standing for a group's material: per slice, the corners of the hull of its
    // islands there, on both faces of the slice.
    const auto points_of = [&](const std::vector<std::size_t>& group) {
        std::vector<core::Vec3d> out;
        for (std::size_t a = 0; a < group.size();) {
            const std::size_t slice = islands[group[a]].slice;
            geom2d::Paths2 paths;
            for (; a < group.size() && islands[group[a]].slice == slice; ++a) {
                const geom2d::Paths2& p = islands[group[a]].paths;
                paths.insert(paths.end(), p.begin(), p.end());
            }
            const slice::Slice& s = **slices.at(slice);  // sliced above
            const double half = 0.5 * s.span.thickness();
            for (const geom2d::Point2& q : geom2d::convex_hull(paths)) {
                out.push_back(s.plane.to_3d(q, -half));
                out.push_back(s.plane.to_3d(q, half));
            }
        }
        return out;
    };
    std::vector<core::Vec3d> own = points_of(members[0]);
    struct Feature {
        std::vector<core::Vec3d> points;
    };
    std::vector<Feature> features;
    for (std::size_t g = 1; g < members.size(); ++g) features.push_back({points_of(members[g])});
    // A feature that stands on L along the old direction carries on along it, as it would
    // have without the split: its points within a layer of L's top all lie over L's section
    // (within a track). One that does not hangs from something above L, or sticks out past L
    // as the piece does (a second arm beside the first): it stays with the new region.
    const geom2d::Paths2 l_paths = l.wires.paths();
    const auto stands_on_l = [&](const std::vector<core::Vec3d>& points) {
        bool any = false;
        for (const core::Vec3d& x : points) {
            if (l.top.height(x) > s_.layer_mm + kOnLayerSlackMm) continue;
            any = true;
            const geom2d::Point2 q = l.plane.to_2d(x);
            const geom2d::ClosestPoint c = geom2d::closest_region_point(
                l_paths, {static_cast<double>(q.x), static_cast<double>(q.y)});
            if (c.distance_um > reach_um) return false;
        }
        return any;
    };
    std::vector<std::vector<core::Vec3d>> far;
    for (Feature& f : features) {
        if (stands_on_l(f.points)) {
            far.push_back(std::move(f.points));
        } else {
            own.insert(own.end(), f.points.begin(), f.points.end());
        }
    }
    if (far.empty()) return std::vector<HalfSpace>{};

    std::vector<core::Vec3d> normals;
    const core::Vec3d ns = child.direction;
    for (int k = 0; k < kAround; ++k) {
        const double a = 2.0 * std::numbers::pi * k / kAround;
        normals.push_back(child.base.u * std::cos(a) + child.base.v * std::sin(a));
    }
    const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
    for (int k = 0; k < kSphere; ++k) {
        const double z = 1.0 - (2.0 * k + 1.0) / kSphere;
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        normals.push_back(child.base.u * (r * std::cos(golden * k)) +
                          child.base.v * (r * std::sin(golden * k)) + ns * z);
    }
    // A plane with less room than half a track on each side could cut what it separates
    // between the points that stand for it.
    const double min_gap = s_.track_width_mm;
    const auto bound = [](const Separation& s) {
        return HalfSpace{s.w * s.mid, s.w * -1.0};  // the own side: w . x <= mid
    };
    std::vector<core::Vec3d> all_far;
    for (const std::vector<core::Vec3d>& f : far) all_far.insert(all_far.end(), f.begin(), f.end());
    const Separation one = separate(own, all_far, normals);
    if (one.gap >= min_gap) return std::vector<HalfSpace>{bound(one)};
    // One plane per feature, the largest first; a feature wholly past an earlier plane
    // goes with that plane's region.
    std::vector<std::size_t> by_size(far.size());
    std::iota(by_size.begin(), by_size.end(), 0);
    std::stable_sort(by_size.begin(), by_size.end(),
                     [&](std::size_t a, std::size_t b) { return far[a].size() > far[b].size(); });
    std::vector<HalfSpace> out;
    for (const std::size_t k : by_size) {
        const std::vector<core::Vec3d>& f = far[k];
        const bool past = std::any_of(out.begin(), out.end(), [&](const HalfSpace& h) {
            return std::none_of(f.begin(), f.end(),
                                [&](const core::Vec3d& x) { return h.contains(x); });
        });
        if (past) continue;
        const Separation s = separate(own, f, normals);
        if (s.gap >= min_gap) out.push_back(bound(s));
    }
    return out;
}

}  // namespace maxslice::plan::detail
