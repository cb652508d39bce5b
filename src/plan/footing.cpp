// The footing at the plate (decision 0017): a rounded or chamfered bottom edge, or a part
// touching the plate along a line or at a point, stands on a straight pad machined off with
// the plate. The planner lays it only where it saves a split at the plate.

#include "footing.hpp"

#include <algorithm>
#include <utility>

#include "planner_state.hpp"

namespace maxslice::plan::detail {

using geom2d::Paths2;

double footing_zone_mm(const PlanSettings& s) {
    return s.footing_mm + look_back_layers(s) * s.layer_mm + kFootingSlackMm;
}

core::Result<std::vector<Paths2>> footing_pads(
    std::size_t first, std::size_t n, double footing_mm,
    const std::function<core::Result<Paths2>(std::size_t)>& section,
    const std::function<double(std::size_t)>& top) {
    std::vector<Paths2> sections;
    std::size_t band = 0;
    for (std::size_t j = first; j < n; ++j) {
        auto c = section(j);
        if (!c) return std::unexpected(c.error());
        if (geom2d::signed_area_mm2(*c) <= 0.0) break;
        sections.push_back(std::move(*c));
        if (top(j) > footing_mm + kFootingSlackMm) break;
        ++band;
    }
    std::vector<Paths2> pads(band);
    Paths2 pad;
    for (std::size_t k = sections.size(); k-- > 0;) {
        pad.insert(pad.end(), sections[k].begin(), sections[k].end());
        pad = geom2d::union_of(pad);
        if (k < band) pads[k] = pad;
    }
    return pads;
}

// A split in the base region at a layer that ends within a track's height above the
// footing's height: without the footing (the first walk), the base region is walked again
// from the plate with it; with it, the overhang goes on above it (a chamfer, a sphere) and
// the footing would only move the split up and add material: walked again without it, for
// good. Every layer and decision of the walk is dropped first. True when a walk again is due.
bool Planner::retry_footing(int rid, int ref) {
    if (rid != 0 || footing_ == FootingState::kDropped || s_.footing_always) return false;
    const Layer& l = plan_.layers[static_cast<std::size_t>(ref)];
    if (l.span.top > footing_zone_mm(s_)) return false;
    footing_ = footing_ == FootingState::kUntried ? FootingState::kOn : FootingState::kDropped;
    roll_back(rid, -1);
    std::erase_if(plan_.decisions, [&](const Decision& d) {
        return d.region == rid && d.kind != Decision::Kind::kSplit &&
               d.kind != Decision::Kind::kFloating;
    });
    return true;
}

// The footing's figures from the layers that got a pad.
void Planner::tally_footing() {
    for (std::size_t id = 0; id < footing_added_.size() && id < plan_.layers.size(); ++id) {
        if (footing_added_[id] < 0.0) continue;
        ++plan_.footing.layers;
        plan_.footing.height_mm = std::max(plan_.footing.height_mm, plan_.layers[id].span.top);
        plan_.footing.added_mm3 += footing_added_[id];
    }
}

}  // namespace maxslice::plan::detail
