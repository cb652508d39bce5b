// The walk over a region's slices and the march of tilted 3D layers (docs/method.md
// sections 3 and 4): planar layers from the region's base plane up, each analysed against the
// layer below (neighbours.cpp); where the chain of section centroids leans, tilted layers
// follow it, one plane at a time.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "cell.hpp"
#include "footing.hpp"
#include "maxslice/core/units.hpp"
#include "planner_state.hpp"

namespace maxslice::plan::detail {
namespace {

using geom2d::Paths2;

// Tilts smaller than this (rad) are not made.
constexpr double kMinTiltRad = 0.5 * std::numbers::pi / 180.0;
// A plan with more layers is refused (a runaway march).
constexpr std::size_t kMaxLayers = 1'000'000;

// The centroid chain is followed only while sections keep their area within this share of
// the section a track's height below.
constexpr double kTiltAreaChange = 0.1;

bool steady_area(double area, double below) {
    return std::abs(area - below) <= kTiltAreaChange * below;
}

// The area centroid of a section lifted to 3D (mm).
core::Vec3d centroid3(const geom2d::Paths2& region, const slice::PlaneFrame& f) {
    const geom2d::Centroid2 c = geom2d::centroid_um(region);
    return f.origin + f.u * (c.x / core::kMicronsPerMm) + f.v * (c.y / core::kMicronsPerMm);
}

Next done_or_rewalk(bool rewalk) {
    return {rewalk ? Next::Kind::kRewalk : Next::Kind::kDone};
}

}  // namespace

core::Result<const slice::Slice*> SliceStack::at(std::size_t i) {
    while (i >= slices_.size()) {
        const std::size_t begin = slices_.size();
        const std::size_t end = std::min(spans_.size(), begin + batch_);
        batch_ = std::min(kMaxBatch, 2 * batch_);
        auto batch = slice::slice_mesh(mesh_, base_, std::span(spans_).subspan(begin, end - begin));
        if (!batch) return std::unexpected(batch.error());
        for (slice::Slice& sl : *batch) {
            sl.index = static_cast<int>(slices_.size());
            slices_.push_back(std::move(sl));
        }
    }
    return &slices_[i];
}

// Walks a region's slices (no tilt towards the centroid chain from layer
// `no_march_from`). Ends at the top, at a split, or where a march takes over.
core::Result<Next> Planner::walk(const RegionJob& job, SliceStack& slices, int no_march_from) {
    const int rid = job.region;
    int lower = job.seed.layer;  // L: a layer id, or -1
    bool gap = false;            // empty sections since L
    std::vector<Paths2> pads;    // the footing's layers, from slice pads_from up
    std::size_t pads_from = std::numeric_limits<std::size_t>::max();
    // A region leaned up for the head's reach keeps its direction: following its chain of
    // centroids (a beam's, running along the beam) would turn the head back down onto what
    // the lean cleared (decision 0029). Fixed when the region was made.
    const bool may_march = s_.tilt_trigger_deg > 0.0 && !leaned_by_reach(rid);
    for (std::size_t i = 0; i < slices.size(); ++i) {
        auto next = slices.at(i);
        if (!next) return std::unexpected(next.error());
        const slice::Slice& s = **next;
        Region& r = plan_.regions[static_cast<std::size_t>(rid)];
        Paths2 clipped = clip_to_cell(s.wires.paths(), r.cell, s.plane);
        double own_mm2 = -1.0;  // the section's own area where a footing pad replaces it
        // Heights above the region's base (slices of a resumed walk start elsewhere).
        const double off = r.base.height(s.plane.origin) - s.span.cut;
        if (geom2d::signed_area_mm2(clipped) <= 0.0) {
            // Empty sections after a layer, or at the base plane of a region split from
            // another: what comes next does not touch what lies below them.
            gap = gap || lower >= 0 || rid != 0;
            continue;
        }
        if (footing_ == FootingState::kOn && rid == 0 &&
            s.span.top + off <= s_.footing_mm + kFootingSlackMm) {
            if (pads_from > i) {
                auto made = footing_pads(
                    i, slices.size(), s_.footing_mm,
                    [&](std::size_t j) -> core::Result<Paths2> {
                        auto sj = slices.at(j);
                        if (!sj) return std::unexpected(sj.error());
                        return clip_to_cell((*sj)->wires.paths(), r.cell, (*sj)->plane);
                    },
                    [&](std::size_t j) {
                        const slice::Slice& sj = **slices.at(j);  // sliced above
                        return r.base.height(sj.plane.origin) - sj.span.cut + sj.span.top;
                    });
                if (!made) return std::unexpected(made.error());
                pads = std::move(*made);
                pads_from = i;
            }
            if (i - pads_from < pads.size()) {
                own_mm2 = geom2d::signed_area_mm2(clipped);
                clipped = pads[i - pads_from];
            }
        }
        if (lower >= 0) {
            // U against L, then against the layer a track's height below (look-back):
            // an overhang that grows by less than a track per layer (the underside of a
            // horizontal cylinder, a shallow shelf) is all slivers layer by layer, but a
            // piece wider than a track over that height. Splits happen at the lower of
            // the two; the layers in between go to the new regions.
            auto splits = check_splits(rid, lower, clipped, s);
            if (!splits) return std::unexpected(splits.error());
            if (*splits) return done_or_rewalk(**splits);
        }
        if (may_march && lower >= 0 && lower != no_march_from) {
            // The centroid chain over a track's height (METHOD.md section 4).
            const Region& rr = plan_.regions[static_cast<std::size_t>(rid)];
            const auto k = static_cast<std::size_t>(look_back_);
            const int ref = rr.layers.size() >= k ? rr.layers[rr.layers.size() - k] : lower;
            const Layer& lr = plan_.layers[static_cast<std::size_t>(ref)];
            const core::Vec3d d =
                centroid3(clipped, s.plane) - centroid3(lr.wires.paths(), lr.plane);
            if (angle_deg(d, lr.plane.normal) > s_.tilt_trigger_deg &&
                steady_area(geom2d::signed_area_mm2(clipped), lr.area_mm2)) {
                Decision dec;
                dec.kind = Decision::Kind::kTilt;
                dec.region = rid;
                dec.layer = lower;
                dec.height_mm = s.span.cut;
                dec.lean_deg = angle_deg(d, lr.plane.normal);
                plan_.decisions.push_back(std::move(dec));
                return Next{Next::Kind::kMarch, lower};
            }
        }
        Layer layer;
        layer.id = static_cast<int>(plan_.layers.size());
        layer.region = rid;
        layer.index_in_region = static_cast<int>(r.layers.size());
        layer.plane = s.plane;
        layer.span = {s.span.bottom + off, s.span.top + off, s.span.cut + off};
        layer.thickness_min_mm = layer.thickness_max_mm = layer.thickness_mean_mm =
            s.span.thickness();
        layer.top = s.plane.shifted(s.span.top - s.span.cut);
        layer.wires = geom2d::build_wire_tree(clipped, geom2d::FillRule::kPositive);
        layer.area_mm2 = layer.wires.area_mm2();
        layer.on_plate = rid == 0 && r.layers.empty();
        layer.after_gap = gap;
        gap = false;
        if (own_mm2 >= 0.0) {
            footing_added_.resize(plan_.layers.size() + 1, -1.0);
            footing_added_.back() = (layer.area_mm2 - own_mm2) * layer.thickness_mean_mm;
        }
        r.layers.push_back(layer.id);
        lower = layer.id;
        plan_.layers.push_back(std::move(layer));
    }
    return Next{};
}

// One section of the mesh by an arbitrary plane, clipped to region rid's cell. Marches
// cut one plane at a time: only the triangles near the plane are sliced (the index is
// built at the first march).
core::Result<Paths2> Planner::section(int rid, const slice::PlaneFrame& plane, double thickness) {
    if (!sections_) sections_.emplace(mesh_);
    auto cut = sections_->section(plane, thickness);
    if (!cut) return std::unexpected(cut.error());
    const Region& r = plan_.regions[static_cast<std::size_t>(rid)];
    return clip_to_cell(*cut, r.cell, plane);
}

// Tilted 3D layers (METHOD.md section 4): from layer `lower` up, each layer's top plane
// turns towards the chain of centroids by at most what keeps its local thickness in
// [h_min, h_max] over the layer below (the per-layer bound atan((h_max - h_min) / W));
// a tilt that breaks the range is halved, up to max_tilt_tries times, then dropped for
// that layer (recorded). Each plane is cut on its own. Ends at a split, or at an empty
// section (the top of the part, or a gap: planar layers resume there).
core::Result<Next> Planner::march(int rid, int lower) {
    const double h = s_.layer_mm;
    const auto k = static_cast<std::size_t>(look_back_);
    for (;;) {
        const Layer l = plan_.layers[static_cast<std::size_t>(lower)];
        const core::Vec3d nl = l.top.normal;
        const slice::PlaneFrame flat_mid = l.top.shifted(h / 2);
        auto u0 = section(rid, flat_mid, h);
        if (!u0) return std::unexpected(u0.error());
        if (geom2d::signed_area_mm2(*u0) <= 0.0) return Next{Next::Kind::kResume, lower};

        const Region& rr = plan_.regions[static_cast<std::size_t>(rid)];
        const int ref = rr.layers.size() >= k ? rr.layers[rr.layers.size() - k] : lower;
        const Layer& lr = plan_.layers[static_cast<std::size_t>(ref)];
        const core::Vec3d d = centroid3(*u0, flat_mid) - centroid3(lr.wires.paths(), lr.plane);
        const core::Vec3d cl = centroid3(l.wires.paths(), l.plane);
        const core::Vec3d c_top = cl - nl * l.top.height(cl);
        const core::Vec3d g = c_top + nl * h;

        // Points whose thickness matters: L's section on its top plane.
        std::vector<core::Vec3d> pts;
        for (const geom2d::Path2& path : l.wires.paths()) {
            for (const geom2d::Point2& q : path) {
                const core::Vec3d x = l.plane.to_3d(q);
                pts.push_back(x - nl * l.top.height(x));
            }
        }
        const auto thickness = [&](const core::Vec3d& x, const core::Vec3d& n) {
            return core::dot(g - x, n) / core::dot(nl, n);
        };
        core::Vec3d n_new = nl;
        const core::Vec3d t_raw = d - nl * core::dot(d, nl);
        const double want = std::atan2(core::norm(t_raw), core::dot(d, nl));
        double t_min = h, t_max = h;
        // Follow the chain while it leans more than half the trigger angle from this
        // layer's direction and the sections keep their size (a section that grows or
        // shrinks fast, at a branch or the part's top, moves its centroid sideways
        // without the part leaning).
        if (core::norm(t_raw) > 0.0 && want > kMinTiltRad &&
            want * 180.0 / std::numbers::pi > 0.5 * s_.tilt_trigger_deg &&
            steady_area(geom2d::signed_area_mm2(*u0), lr.area_mm2)) {
            const core::Vec3d t = core::normalized(t_raw);
            double lo = 1e300, hi = -1e300;
            for (const core::Vec3d& x : pts) {
                lo = std::min(lo, core::dot(x, t));
                hi = std::max(hi, core::dot(x, t));
            }
            const double width = std::max(hi - lo, 1e-3);
            double delta = std::min(want, std::atan((s_.h_max_mm - s_.h_min_mm) / width));
            bool ok = false;
            for (int tries = 0; tries <= s_.max_tilt_tries && !ok; ++tries) {
                n_new = core::normalized(nl * std::cos(delta) + t * std::sin(delta));
                t_min = 1e300;
                t_max = -1e300;
                for (const core::Vec3d& x : pts) {
                    const double tx = thickness(x, n_new);
                    t_min = std::min(t_min, tx);
                    t_max = std::max(t_max, tx);
                }
                // Within [h_min, h_max], and the head's axis within the table's tilt range.
                ok = t_min >= s_.h_min_mm - 1e-9 && t_max <= s_.h_max_mm + 1e-9 &&
                     angle_deg(n_new, plan_.regions.front().direction) <= s_.max_tilt_deg + 1e-9;
                if (!ok) delta *= 0.5;
            }
            if (!ok) {
                Decision dec;
                dec.kind = Decision::Kind::kTiltGaveUp;
                dec.region = rid;
                dec.layer = lower;
                plan_.decisions.push_back(std::move(dec));
                n_new = nl;
                t_min = t_max = h;
            }
        }
        const bool tilted = core::dot(n_new, nl) < 1.0 - 1e-12;
        slice::PlaneFrame top = l.top.shifted(h);
        slice::PlaneFrame mid = flat_mid;
        Paths2 u = *u0;
        if (tilted) {
            top = slice::PlaneFrame::from_normal(g, n_new);
            mid = slice::PlaneFrame::from_normal((c_top + g) * 0.5, core::normalized(nl + n_new));
            auto ut = section(rid, mid, h);
            if (!ut) return std::unexpected(ut.error());
            if (geom2d::signed_area_mm2(*ut) <= 0.0) return Next{Next::Kind::kResume, lower};
            u = std::move(*ut);
        }
        Region& r = plan_.regions[static_cast<std::size_t>(rid)];
        const double cut = r.base.height(mid.origin);
        const slice::Slice s{0, mid, {cut - h / 2, cut + h / 2, cut}, {}, 0, 0};
        auto splits = check_splits(rid, lower, u, s);
        if (!splits) return std::unexpected(splits.error());
        if (*splits) return done_or_rewalk(**splits);

        Layer layer;
        layer.id = static_cast<int>(plan_.layers.size());
        layer.region = rid;
        layer.index_in_region = static_cast<int>(r.layers.size());
        layer.plane = mid;
        layer.top = top;
        layer.tilted = tilted;
        layer.thickness_min_mm = t_min;
        layer.thickness_max_mm = t_max;
        const core::Vec3d cu = centroid3(u, mid);
        layer.thickness_mean_mm = tilted ? thickness(cu - nl * l.top.height(cu), n_new) : h;
        layer.span = {cut - layer.thickness_mean_mm / 2, cut + layer.thickness_mean_mm / 2, cut};
        layer.wires = geom2d::build_wire_tree(u, geom2d::FillRule::kPositive);
        layer.area_mm2 = layer.wires.area_mm2();
        r.layers.push_back(layer.id);
        lower = layer.id;
        plan_.layers.push_back(std::move(layer));
        if (plan_.layers.size() > kMaxLayers) {
            return invalid(fmt::format("more than {} layers", kMaxLayers),
                           fmt::format("region {}", rid));
        }
    }
}

// Removes region rid's layers above layer `keep` (the last ones made), and the tilt
// decisions taken for them.
void Planner::roll_back(int rid, int keep) {
    Region& r = plan_.regions[static_cast<std::size_t>(rid)];
    while (!r.layers.empty() && r.layers.back() > keep) {
        r.layers.pop_back();
        plan_.layers.pop_back();
    }
    if (footing_added_.size() > plan_.layers.size()) footing_added_.resize(plan_.layers.size());
    std::erase_if(plan_.decisions, [&](const Decision& d) {
        return (d.kind == Decision::Kind::kTiltWanted || d.kind == Decision::Kind::kUnreachable) &&
               d.region == rid && d.layer > keep;
    });
}

}  // namespace maxslice::plan::detail
