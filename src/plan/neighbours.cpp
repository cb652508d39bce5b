// What the neighbour analysis of a layer pair asks of the walk (docs/method.md sections 3
// and 5): each new section U is compared with the layer L below it and with the layer a
// track's height below; a piece over beta, or one that touches nothing, splits the region
// (split.cpp); a piece over alpha is recorded as a wanted tilt; a floating piece that no
// sideways direction reaches is recorded and left in its layer.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>

#include "maxslice/core/units.hpp"
#include "planner_state.hpp"

namespace maxslice::plan::detail {
namespace {

using geom2d::Paths2;

// Rounding room (mm) when following grounded islands up through planar layers.
constexpr double kGroundSlackMm = 0.02;

}  // namespace

// Splits for U above `lower` (and above the look-back layer): nullopt when U may be
// added, else the walk's result after the split.
core::Result<std::optional<bool>> Planner::check_splits(int rid, int lower, const Paths2& u,
                                                        const slice::Slice& s) {
    std::vector<int> refs{lower};
    const Region& rr = plan_.regions[static_cast<std::size_t>(rid)];
    const auto k = static_cast<std::size_t>(look_back_);
    if (k > 1 && rr.layers.size() >= k) refs.push_back(rr.layers[rr.layers.size() - k]);
    // What of the region's last layer stands on the look-back layer (grounded_from): L as the
    // analysis sees it, an island of L that floats (a thin feature starting in the air)
    // carrying nothing, so that what stands on it is judged as floating too.
    const std::optional<Paths2> grounded =
        refs.size() > 1 ? grounded_from(rid, refs.back()) : std::nullopt;
    const bool l_grounded =
        grounded && rr.layers.back() == lower && geom2d::signed_area_mm2(*grounded) > 0.0;
    for (const int ref : refs) {
        const Layer& l = plan_.layers[static_cast<std::size_t>(ref)];
        auto a = analyse_neighbours(ref == lower && l_grounded ? *grounded : l.wires.paths(),
                                    l.plane, u, s.plane, analysis_);
        if (!a) {
            return std::unexpected(core::with_context(
                a.error(), fmt::format("region {}, height {:.3f} mm", rid, s.span.cut)));
        }
        for (const OverhangPiece& p : a->pieces) {
            // A piece that does not touch the look-back layer may stand on the layers in
            // between, grown out of it (a rail on the roof of an undercut built since):
            // then it is an overhang by its angle, not a floating piece.
            if (ref != lower && !p.touches_lower && p.ang_deg <= s_.beta_deg && grounded &&
                stands_on(*grounded, rid, ref, p)) {
                continue;
            }
            if (!p.touches_lower) {
                // A tip the region's cell cuts off the material it grows from (a wall or a
                // blade a split plane crosses at a slant): it rests on the part's material
                // just behind it, in another region's cell, which the hierarchy graph links it
                // to (decisions 0033, 0042). Not a floating piece to split for.
                auto across = rests_across_cell(ref, p);
                if (!across) return std::unexpected(across.error());
                if (*across) continue;
            }
            if (!p.touches_lower && !has_sideways(ref, p)) {
                // Nothing can reach it: it stays in its layer and rests on nothing there
                // (the plan says so; a refusal of this base, not of the whole plan).
                record_unreachable(rid, ref, s, p);
                continue;
            }
            if (p.ang_deg > s_.beta_deg || !p.touches_lower) {
                if (split_before(rid, ref, p)) {
                    // Split for once already, and the near side kept it: no plane of the
                    // tilt range takes it off, and another split would change nothing. It
                    // stays and rests on nothing (a refusal of this base, not a runaway).
                    record_unreachable(rid, ref, s, p);
                    continue;
                }
                if (retry_footing(rid, ref)) return std::optional<bool>(true);
                roll_back(rid, ref);
                auto again = split(rid, ref, s, p);
                if (!again) return std::unexpected(again.error());
                return std::optional<bool>(*again);
            }
        }
        for (const OverhangPiece& p : a->pieces) {
            if (p.ang_deg > s_.alpha_deg) {
                record_tilt(rid, ref, s, p);
                break;
            }
        }
    }
    return std::optional<bool>();
}

// Whether piece p, which touches nothing of layer `ref`, rests on the part's material in
// other cells at ref's plane (rests_on_section).
core::Result<bool> Planner::rests_across_cell(int ref, const OverhangPiece& p) {
    const Layer& l = plan_.layers[static_cast<std::size_t>(ref)];
    if (!sections_) sections_.emplace(mesh_);
    auto whole = sections_->section(l.plane, l.span.thickness());
    if (!whole) return std::unexpected(whole.error());
    return rests_on_section(p.region, *whole, l.plane.height(p.C), analysis_);
}

// The islands of region rid's last layer that stand on layer `ref` (a track's height below
// it) through the layers between, in the last layer's frame: from ref up, each layer's
// islands that meet the grounded part of the layer before (projected onto its plane and grown
// by the self-supporting allowance) are grounded. An island that floats in those layers (a
// thin feature starting in the air, narrower than a track at first) is not. nullopt when
// ref is not one of the region's layers.
std::optional<Paths2> Planner::grounded_from(int rid, int ref) const {
    const Region& rr = plan_.regions[static_cast<std::size_t>(rid)];
    const auto from = std::find(rr.layers.begin(), rr.layers.end(), ref);
    if (from == rr.layers.end()) return std::nullopt;
    const Layer* below = &plan_.layers[static_cast<std::size_t>(ref)];
    Paths2 grounded = below->wires.paths();
    for (auto it = from + 1; it != rr.layers.end(); ++it) {
        const Layer& l = plan_.layers[static_cast<std::size_t>(*it)];
        const Paths2 reach =
            geom2d::offset_of(project_paths(grounded, below->plane, l.plane), ground_growth_um(l));
        Paths2 next;
        for (Paths2& island : l.wires.islands()) {
            if (!geom2d::intersection_of(island, reach).empty()) {
                next.insert(next.end(), island.begin(), island.end());
            }
        }
        grounded = std::move(next);
        below = &l;
    }
    return grounded;
}

// How far a grounded island reaches into layer l above it (um): the self-supporting allowance
// over l's thickness, and rounding room.
std::int64_t Planner::ground_growth_um(const Layer& l) const {
    return core::mm_to_um(std::max(l.thickness_max_mm, s_.layer_mm) *
                              std::tan(s_.self_supporting_deg * std::numbers::pi / 180.0) +
                          kGroundSlackMm);
}

// Whether piece p (in the frame of layer `ref`, a track's height below the region's last
// layer) rests on material of the layers after ref that grew out of ref: `grounded`, what
// grounded_from(rid, ref) found of the last layer.
bool Planner::stands_on(const Paths2& grounded, int rid, int ref, const OverhangPiece& p) const {
    const Layer& last = plan_.layers[static_cast<std::size_t>(
        plan_.regions[static_cast<std::size_t>(rid)].layers.back())];
    const Layer& base = plan_.layers[static_cast<std::size_t>(ref)];
    const Paths2 on_ref = project_paths(grounded, last.plane, base.plane);
    return !geom2d::intersection_of(p.region, geom2d::offset_of(on_ref, ground_growth_um(last)))
                .empty();
}

// Whether region rid, not started yet, was split above layer `lower` for piece p already (the
// same centroid) and became that split's near side, which kept the piece.
bool Planner::split_before(int rid, int lower, const OverhangPiece& p) const {
    if (!plan_.regions[static_cast<std::size_t>(rid)].layers.empty()) return false;
    return std::any_of(plan_.decisions.begin(), plan_.decisions.end(), [&](const Decision& d) {
        return (d.kind == Decision::Kind::kSplit || d.kind == Decision::Kind::kFloating) &&
               d.region == rid && d.continuation == rid && d.layer == lower &&
               core::norm(d.piece.C - p.C) < 1e-9;
    });
}

void Planner::record_unreachable(int rid, int lower, const slice::Slice& s,
                                 const OverhangPiece& p) {
    for (const Decision& e : plan_.decisions) {  // seen from the look-back layer too
        if (e.kind == Decision::Kind::kUnreachable && e.region == rid &&
            e.height_mm == s.span.cut && core::norm(e.piece.C - p.C) < 1e-9) {
            return;
        }
    }
    record_piece(Decision::Kind::kUnreachable, rid, lower, s, p);
}

void Planner::record_tilt(int rid, int lower, const slice::Slice& s, const OverhangPiece& p) {
    record_piece(Decision::Kind::kTiltWanted, rid, lower, s, p);
}

// A decision about piece p of the slice s above layer `lower` of region rid.
void Planner::record_piece(Decision::Kind kind, int rid, int lower, const slice::Slice& s,
                           const OverhangPiece& p) {
    Decision d;
    d.kind = kind;
    d.region = rid;
    d.layer = lower;
    d.height_mm = s.span.cut;
    d.piece = p;
    plan_.decisions.push_back(std::move(d));
}

}  // namespace maxslice::plan::detail
