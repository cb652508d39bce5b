// Every text the planner writes for people: what it decided and why, why a region exists,
// and why it refuses a part. Texts are built from the fields last, when they are printed:
// nothing in a plan holds prose that code would have to parse or rewrite (layer ids change
// when the layers are split into pieces).

#include <fmt/format.h>

#include <algorithm>
#include <string>

#include "maxslice/plan/order.hpp"
#include "maxslice/plan/planner.hpp"
#include "planner_state.hpp"

namespace maxslice::plan {
namespace {

// "turned 20 deg about the layer's normal, then " for a split direction turned first.
std::string turn_words(double turn_deg) {
    if (turn_deg == 0.0) return {};
    return fmt::format("turned {:.0f} deg about the lower layer's normal, then ", turn_deg);
}

// How the head's reach moved a split's direction off N_s: "turned 20 deg about the lower
// layer's normal, then leaned up 45 deg from the sideways direction" (`its`: "its sideways
// direction").
std::string moved_words(const Decision& d, bool its) {
    const char* sideways = its ? "its sideways direction" : "the sideways direction";
    if (d.split_searched_deg > 0.0) {
        return fmt::format(
            "found in a sample of the sphere within the table's tilt range, {:.0f} deg from {}",
            d.split_searched_deg, sideways);
    }
    return fmt::format("{}leaned up {:.0f} deg from {}", turn_words(d.split_turn_deg),
                       d.split_lean_deg, sideways);
}

}  // namespace

std::string describe(const Plan& plan, const Decision& d) {
    const PlanSettings& s = plan.settings;
    const OverhangPiece& p = d.piece;
    switch (d.kind) {
        case Decision::Kind::kSplit:
        case Decision::Kind::kFloating: {
            const core::Vec3d& at = d.split_plane.point;
            const core::Vec3d& ns = d.split_plane.normal;
            std::string reach;
            if (d.head_checked && !d.head_clears) {
                reach = fmt::format(
                    "; no lean up or turn of the sideways direction, nor any direction of a "
                    "sample of the sphere that carries the piece, keeps the head's {:.2f} mm "
                    "clearance from what is built before it and the plate (closest {:.2f} mm): "
                    "the build order and the verifier decide",
                    s.head->clearance_mm, d.head_margin_mm);
            } else if (d.moved_for_reach()) {
                reach = fmt::format(
                    " ({}, where the head would come within {:.2f} mm of what is built before it "
                    "or the plate; so moved, it keeps its {:.2f} mm clearance)",
                    moved_words(d, false), d.seed_margin_mm, s.head->clearance_mm);
            }
            if (s.max_tilt_deg < 180.0 && !plan.regions.empty() &&
                angle_deg(ns, plan.regions.front().direction) > s.max_tilt_deg - 1e-6) {
                reach += fmt::format(
                    "; turned up to the edge of the table's tilt range, {:.0f} deg from the base "
                    "direction",
                    s.max_tilt_deg);
            }
            return fmt::format(
                "above layer L{}: overhang piece of {:.1f} mm2 with Ang = {:.1f} deg {}: split "
                "plane through ({:.3f}, {:.3f}, {:.3f}) with normal ({:.4f}, {:.4f}, {:.4f}); "
                "region {} is built along it{}",
                d.layer, p.area_mm2, p.ang_deg,
                p.touches_lower ? fmt::format("> beta {:.0f}", s.beta_deg)
                                : std::string("(does not touch the layer below)"),
                at.x, at.y, at.z, ns.x, ns.y, ns.z, d.new_region, reach);
        }
        case Decision::Kind::kTiltWanted:
            return fmt::format(
                "layer above L{} at {:.3f} mm: overhang piece of {:.1f} mm2 with Ang = {:.1f} deg "
                "in (alpha {:.0f}, beta {:.0f}]: a tilted layer is wanted; layers tilt only where "
                "the chain of centroids leans, so this one may stay planar",
                d.layer, d.height_mm, p.area_mm2, p.ang_deg, s.alpha_deg, s.beta_deg);
        case Decision::Kind::kTilt:
            return fmt::format(
                "above layer L{}: the chain of centroids leans {:.1f} deg from the build "
                "direction (> {:.0f}): tilted 3D layers follow it from here",
                d.layer, d.lean_deg, s.tilt_trigger_deg);
        case Decision::Kind::kTiltGaveUp: return describe_tilt_gave_up(plan, d.layer, d.layer, 1);
        case Decision::Kind::kUnreachable:
            return fmt::format(
                "above layer L{} at {:.3f} mm: a piece of {:.1f} mm2 at ({:.3f}, {:.3f}, {:.3f}) "
                "floats straight above the layer below: no sideways build direction reaches it; "
                "left in its layer, where it rests on nothing",
                d.layer, d.height_mm, p.area_mm2, p.C.x, p.C.y, p.C.z);
    }
    return "unknown decision";
}

std::string describe_hanging(const Plan& plan, int id, std::string_view whole) {
    const HangingLoad h = hanging_from(plan, id);
    const double v = plan.volume_mm3();
    return fmt::format(
        "{} layers, {:.0f} mm3 ({:.1f}% of the {}), stand on it and on nothing the "
        "plate carries",
        h.layers, h.volume_mm3, v > 0.0 ? 100.0 * h.volume_mm3 / v : 0.0, whole);
}

std::string describe_free_bodies(const Plan& plan) {
    if (plan.free_bodies.empty()) return {};
    const FreeBody& b = plan.free_bodies.front();
    const core::Vec3d c = b.box.center();
    double v = 0.0;
    for (const FreeBody& f : plan.free_bodies) v += f.volume_mm3;
    return fmt::format(
        "{} {} of {:.0f} mm3 in all float free of the rest of the part and of the plate (the "
        "first: {:.0f} mm3 around ({:.1f}, {:.1f}, {:.1f}), at least {:.1f} mm from any other "
        "body): nothing can be deposited under {} from this base, so {} left out",
        plan.free_bodies.size(), plan.free_bodies.size() == 1 ? "body" : "bodies", v, b.volume_mm3,
        c.x, c.y, c.z, b.gap_mm, plan.free_bodies.size() == 1 ? "it" : "them",
        plan.free_bodies.size() == 1 ? "it is" : "they are");
}

std::string describe_tilt_gave_up(const Plan& plan, int first_layer, int last_layer,
                                  std::size_t count) {
    const PlanSettings& s = plan.settings;
    const std::string where =
        count == 1 ? fmt::format("above layer L{}", first_layer)
                   : fmt::format("above {} layers from L{} to L{}", count, first_layer, last_layer);
    return fmt::format(
        "{}: no tilt towards the centroid chain keeps the thickness in [{}, {}] mm after {} "
        "tries: {}",
        where, s.h_min_mm, s.h_max_mm, s.max_tilt_tries,
        count == 1 ? "a planar layer" : "planar layers");
}

std::string describe(const Plan& plan, const Region& r) {
    if (r.parent < 0) return "base region: the part stands on the plate along the base direction";
    for (const Decision& d : plan.decisions) {
        if (d.new_region == r.id) {
            return fmt::format("split from region {}: {}", d.region, describe(plan, d));
        }
        if (d.continuation == r.id && d.region != r.id) {
            return fmt::format(
                "carries on along region {}'s direction above layer L{}, on the near side of the "
                "split plane of region {}",
                d.region, d.layer, d.new_region);
        }
        if (std::find(d.far_regions.begin(), d.far_regions.end(), r.id) != d.far_regions.end()) {
            return fmt::format(
                "carries on along region {}'s direction above layer L{}, beyond the split plane "
                "of region {} but apart from what grows from its piece: a feature there that "
                "region {} would start in the air",
                d.region, d.layer, d.new_region, d.new_region);
        }
    }
    return fmt::format("split from region {}", r.parent);
}

const Decision* deciding_split(const Plan& plan, int region, int* from) {
    int at = region;
    for (std::size_t hops = 0; hops <= plan.regions.size(); ++hops) {
        const Decision* carried = nullptr;
        for (const Decision& d : plan.decisions) {
            if ((d.kind == Decision::Kind::kSplit || d.kind == Decision::Kind::kFloating) &&
                d.new_region == at) {
                if (from != nullptr) *from = at;
                return &d;
            }
            const bool far =
                std::find(d.far_regions.begin(), d.far_regions.end(), at) != d.far_regions.end();
            if ((d.continuation == at && d.region != at) || far) carried = &d;
        }
        if (carried == nullptr) break;
        at = carried->region;
    }
    return nullptr;
}

namespace detail {

std::string unreachable_refusal(const OverhangPiece& p) {
    return fmt::format(
        "an overhang piece of {:.1f} mm2 at ({:.3f}, {:.3f}, {:.3f}) floats straight above the "
        "layer below: no sideways build direction reaches it",
        p.area_mm2, p.C.x, p.C.y, p.C.z);
}

std::string too_many_regions_refusal(int max_regions) {
    return fmt::format(
        "the part needs more than {} regions (max_regions); is it a lattice or a scan with many "
        "small overhangs?",
        max_regions);
}

}  // namespace detail

std::string describe_refusal(const Plan& plan, const BuildOrder& order, const Nozzle& nozzle) {
    if (order.conflicts.empty()) return {};
    const Conflict& c = order.conflicts.front();
    const auto region_of = [&](int layer) {
        return plan.layers[static_cast<std::size_t>(layer)].region;
    };
    const int rid = region_of(c.layer);
    const Region& r = plan.regions[static_cast<std::size_t>(rid)];
    std::string out;
    // The split that made the region, or the region it carries on (a continuation keeps the
    // direction of the region it continues, and the reason for it).
    int from = rid;
    const Decision* made = deciding_split(plan, rid, &from);
    if (made != nullptr) {
        const OverhangPiece& p = made->piece;
        out = fmt::format(
            "In the way: region {}{}, the overhang of {:.1f} mm2 at ({:.2f}, {:.2f}, {:.2f}) "
            "built along ({:.3f}, {:.3f}, {:.3f})",
            rid, from != rid ? fmt::format(" (it carries on region {})", from) : std::string(),
            p.area_mm2, p.C.x, p.C.y, p.C.z, r.direction.x, r.direction.y, r.direction.z);
        if (made->moved_for_reach()) {
            out += ", " + moved_words(*made, true);
        }
        if (made->head_checked && !made->head_clears) {
            out += fmt::format(
                " (no lean up to the most that keeps its underside carried, nor any direction "
                "of a sample of the sphere that carries it, kept the head {:.2f} mm clear: "
                "closest {:.2f} mm)",
                nozzle.clearance_mm, made->head_margin_mm);
        }
        out += fmt::format(", reaches region {} only with the head in its way", region_of(c.other));
        // A piece that hangs below a region built sideways is split off along a direction
        // that points down: the head then comes at it from under the part, past the plate.
        const double down = angle_deg(r.direction, plan.regions.front().direction);
        if (down > 90.0) {
            out += fmt::format(
                "; that direction points {:.0f} deg from the plate's normal, down: the piece "
                "hangs below the sideways region it grows from, so the head would come at it "
                "from under the part (built another way up, it would grow from below)",
                down);
        }
    } else {
        out = fmt::format("In the way: region {} (along ({:.3f}, {:.3f}, {:.3f})) and region {}",
                          rid, r.direction.x, r.direction.y, r.direction.z, region_of(c.other));
    }
    const bool stream = std::any_of(order.conflicts.begin(), order.conflicts.end(),
                                    [](const Conflict& k) { return k.in_stream; });
    double closest = nozzle.clearance_mm;
    for (const Conflict& k : order.conflicts) closest = std::min(closest, k.margin_mm);
    const std::string gap =
        closest < 0.0 ? fmt::format("it would reach {:.2f} mm into what is built", -closest)
                      : fmt::format("the closest gap: {:.2f} mm of the {:.2f} mm clearance",
                                    closest, nozzle.clearance_mm);
    out += fmt::format(
        "; {} ({}); what may help: a slimmer head (machine.nozzle: a smaller body_radius_mm, "
        "half_angle_deg or cone_length_mm), another base (--orient auto), or a part given "
        "standing otherwise",
        stream ? "the powder stream itself meets what is built" : "the head comes too close", gap);
    return out;
}

}  // namespace maxslice::plan
