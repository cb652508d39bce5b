// The split plane and the sideways region (docs/method.md section 5): a piece over beta, or
// one that touches nothing, is built along the part of its V_i across the lower layer's
// normal, from a split plane through the centre of its contact line; what lies on the near
// side carries on along the old direction.

#include <fmt/format.h>

#include <numbers>
#include <string>
#include <utility>

#include "planner_state.hpp"

namespace maxslice::plan::detail {
namespace {

// A sideways direction N_s shorter than this (V_i almost along N_b) cannot be normalised.
constexpr double kMinSidewaysNorm = 1e-6;

}  // namespace

// The part of V_i across L's normal: the direction a region split for piece p above
// layer `lower` is built along (METHOD.md section 5), before it is normalised.
core::Vec3d Planner::sideways_of(int lower, const OverhangPiece& p) const {
    const core::Vec3d n = plan_.layers[static_cast<std::size_t>(lower)].top.normal;
    return p.V - n * core::dot(p.V, n);
}

// Whether piece p has a sideways direction to be built from (V_i not along L's normal).
bool Planner::has_sideways(int lower, const OverhangPiece& p) const {
    return core::norm(sideways_of(lower, p)) >= kMinSidewaysNorm;
}

// Direction d turned towards the base direction as far as the table's tilt range needs (in
// the plane of the two; d straight against the base direction turns towards the base plane's
// u axis).
core::Vec3d Planner::within_tilt(const core::Vec3d& d) const {
    const core::Vec3d up = plan_.regions.front().direction;
    const double limit = s_.max_tilt_deg * std::numbers::pi / 180.0;
    if (!(limit < std::numbers::pi) || angle_deg(d, up) * std::numbers::pi / 180.0 <= limit) {
        return d;
    }
    core::Vec3d across = d - up * core::dot(d, up);
    if (core::norm(across) < kMinSidewaysNorm) across = plan_.regions.front().base.u;
    return core::normalized(up * std::cos(limit) + core::normalized(across) * std::sin(limit));
}

// Splits region rid above its layer `lower` for piece p (METHOD.md section 5). Returns
// true when rid had no layer yet: its own cell was narrowed to the near side and it
// must be walked again; false when rid ends at `lower` and a continuation region
// carries on.
core::Result<bool> Planner::split(int rid, int lower, const slice::Slice& s,
                                  const OverhangPiece& p) {
    const Region parent = plan_.regions[static_cast<std::size_t>(rid)];
    const core::Vec3d n = plan_.layers[static_cast<std::size_t>(lower)].top.normal;
    const core::Vec3d sideways = sideways_of(lower, p);
    const std::string context = fmt::format("region {}, height {:.3f} mm", rid, s.span.cut);
    if (!has_sideways(lower, p)) {
        return invalid(unreachable_refusal(p), context);
    }
    if (static_cast<int>(plan_.regions.size()) + 2 > s_.max_regions) {
        return invalid(too_many_regions_refusal(s_.max_regions), context);
    }
    const Layer& l = plan_.layers[static_cast<std::size_t>(lower)];
    const HalfSpace above{l.top.origin, n};
    std::vector<HalfSpace> above_cell = parent.cell;
    above_cell.push_back(above);
    auto reach =
        direction_by_reach(lower, p, core::normalized(sideways), above_cell, parent.layers.empty());
    if (!reach) return std::unexpected(reach.error());
    const core::Vec3d ns = within_tilt(reach->direction);
    const HalfSpace beyond{p.contact_center, ns};
    const HalfSpace near{p.contact_center, -ns};

    Region child;
    child.id = static_cast<int>(plan_.regions.size());
    child.parent = rid;
    child.direction = ns;
    child.base = slice::PlaneFrame::from_normal(p.contact_center, ns);
    child.cell = parent.cell;
    child.cell.push_back(above);
    child.cell.push_back(beyond);
    // Features beyond the split plane that do not grow from the piece carry on along the old
    // direction, each in a region of its own (decision 0035).
    auto far = far_feature_bounds(child, lower, p);
    if (!far) return std::unexpected(far.error());
    if (static_cast<int>(plan_.regions.size() + far->size()) + 2 > s_.max_regions) {
        return invalid(too_many_regions_refusal(s_.max_regions), context);
    }
    std::vector<Region> far_regions;
    for (std::size_t k = 0; k < far->size(); ++k) {
        Region f;
        f.parent = rid;
        f.direction = n;
        f.base = l.top;
        f.cell = child.cell;  // parent's cell, above, beyond, the planes before this one
        f.cell.push_back({(*far)[k].point, (*far)[k].normal * -1.0});
        far_regions.push_back(std::move(f));
        child.cell.push_back((*far)[k]);
    }

    Decision d;
    d.kind = p.touches_lower ? Decision::Kind::kSplit : Decision::Kind::kFloating;
    d.region = rid;
    d.layer = lower;
    d.height_mm = s.span.cut;
    d.piece = p;
    d.new_region = child.id;
    d.split_plane = beyond;
    d.head_checked = s_.head.has_value();
    d.split_lean_deg = reach->lean_deg;
    d.split_turn_deg = reach->turn_deg;
    d.split_searched_deg = reach->searched_deg;
    d.head_margin_mm = reach->margin_mm;
    d.seed_margin_mm = reach->seed_margin_mm;
    d.head_clears = reach->clears;
    plan_.regions.push_back(child);
    jobs_.push_back({child.id, {}});
    for (Region& f : far_regions) {
        f.id = static_cast<int>(plan_.regions.size());
        d.far_regions.push_back(f.id);
        plan_.regions.push_back(std::move(f));
        jobs_.push_back({d.far_regions.back(), {lower}});
    }
    d.far_planes = *far;

    Region& r = plan_.regions[static_cast<std::size_t>(rid)];
    if (r.layers.empty()) {
        // The region had not started: it becomes the near side and is walked again.
        r.cell.push_back(near);
        d.continuation = rid;
        plan_.decisions.push_back(std::move(d));
        return true;
    }
    Region cont;
    cont.id = static_cast<int>(plan_.regions.size());
    cont.parent = rid;
    cont.direction = n;
    cont.base = l.top;
    cont.cell = parent.cell;
    cont.cell.push_back(above);
    cont.cell.push_back(near);
    d.continuation = cont.id;
    plan_.decisions.push_back(std::move(d));
    plan_.regions.push_back(cont);
    jobs_.push_back({cont.id, {lower}});
    return false;
}

}  // namespace maxslice::plan::detail
