// The planner's neighbour analysis and look-back over a planar stack, without regions: what
// a 3-axis program of it would deposit on nothing (docs/method.md section 3), with the
// footing where it saves an overhang at the plate (decision 0017).

#include <algorithm>
#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>

#include "footing.hpp"
#include "maxslice/plan/planner.hpp"
#include "planner_state.hpp"

namespace maxslice::plan {

using detail::analysis_settings;
using detail::footing_pads;
using detail::footing_zone_mm;
using detail::look_back_layers;
using geom2d::Paths2;

core::Result<PlanarCheck> check_planar(std::span<const slice::Slice> slices,
                                       const PlanSettings& s) {
    if (auto ok = validate(s); !ok) return std::unexpected(ok.error());
    const AnalysisSettings a = analysis_settings(s);
    const auto k = static_cast<std::size_t>(look_back_layers(s));
    // Per layer: 0 carried, 1 tilt wanted, 2 overhang; and its first overhang piece. Each
    // layer is compared, as the planner's walk does, with the layer right below and with the
    // one a track's height below (or the first layer): overhangs that grow in slivers show
    // only over that height, but the allowance grows with it (h tan(phi_self) on each side,
    // 0.9 mm at 2.5 mm), so the flat ceiling of a 3 mm channel, a 2.6 mm piece over the
    // layer right below, is a 1.2 mm sliver over the look-back layer. Layers go in chunks, in
    // parallel inside a chunk, and the check stops after the chunk with the first overhang:
    // a refused part costs only up to there, and the result does not depend on the thread
    // count.
    std::vector<int> kind(slices.size(), 0);
    std::vector<OverhangPiece> first(slices.size());
    std::vector<std::optional<core::Error>> errors(slices.size());
    constexpr std::size_t kChunk = 64;
    PlanarCheck out;
    for (std::size_t c0 = 1; c0 < slices.size(); c0 += kChunk) {
        const std::size_t c1 = std::min(slices.size(), c0 + kChunk);
        tbb::parallel_for(c0, c1, [&](std::size_t i) {
            const std::size_t back = i >= k ? i - k : 0;
            const std::size_t refs[] = {i - 1, back};
            for (std::size_t n = 0; n < (back == i - 1 ? 1U : 2U) && kind[i] < 2; ++n) {
                const slice::Slice& l = slices[refs[n]];
                auto r = analyse_neighbours(l.wires.paths(), l.plane, slices[i].wires.paths(),
                                            slices[i].plane, a);
                if (!r) {
                    errors[i] = r.error();
                    return;
                }
                for (const OverhangPiece& p : r->pieces) {
                    if (p.ang_deg > s.beta_deg || !p.touches_lower) {
                        if (kind[i] < 2) first[i] = p;
                        kind[i] = 2;
                    } else if (p.ang_deg > s.alpha_deg && kind[i] == 0) {
                        kind[i] = 1;
                    }
                }
            }
        });
        for (std::size_t i = c0; i < c1; ++i) {
            if (errors[i]) return std::unexpected(*errors[i]);
            if (kind[i] == 1) ++out.tilts_wanted;
            if (kind[i] == 2) {
                ++out.overhangs;
                if (out.examples.size() < 3) {
                    out.examples.push_back(first[i]);
                    out.heights_mm.push_back(slices[i].span.cut);
                }
            }
        }
        if (out.overhangs > 0) {
            out.checked_up_to = c1;
            return out;
        }
    }
    out.checked_up_to = slices.size();
    return out;
}

core::Result<PlanarCheck> check_planar_on_footing(std::vector<slice::Slice>& slices,
                                                  const PlanSettings& s) {
    auto bare = check_planar(slices, s);
    // Whether a check's first overhang starts within a track's height above the footing.
    const auto at_plate = [&](const PlanarCheck& c) {
        if (c.overhangs == 0) return false;
        const auto at = std::find_if(slices.begin(), slices.end(), [&](const slice::Slice& sl) {
            return sl.span.cut == c.heights_mm.front();
        });
        return at != slices.end() && at->span.bottom <= footing_zone_mm(s);
    };
    if (!bare || !(s.footing_mm > 0.0) || !at_plate(*bare)) return bare;
    auto pads = footing_pads(
        0, slices.size(), s.footing_mm,
        [&](std::size_t j) -> core::Result<Paths2> { return slices[j].wires.paths(); },
        [&](std::size_t j) { return slices[j].span.top; });
    if (!pads) return std::unexpected(pads.error());
    std::vector<geom2d::WireTree> kept;
    Footing footing;
    for (std::size_t k = 0; k < pads->size(); ++k) {
        kept.push_back(std::move(slices[k].wires));
        slices[k].wires = geom2d::build_wire_tree((*pads)[k], geom2d::FillRule::kPositive);
        ++footing.layers;
        footing.height_mm = slices[k].span.top;
        footing.added_mm3 +=
            (slices[k].wires.area_mm2() - kept.back().area_mm2()) * slices[k].span.thickness();
    }
    auto on = check_planar(slices, s);
    if (!on) return on;
    if (!at_plate(*on)) {
        on->footing = footing;
        return on;
    }
    for (std::size_t k = 0; k < kept.size(); ++k) slices[k].wires = std::move(kept[k]);
    return bare;
}

}  // namespace maxslice::plan
