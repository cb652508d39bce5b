#include "maxslice/pipeline/plan_job.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <system_error>
#include <tuple>
#include <vector>

#include <tbb/parallel_for.h>

#include "maxslice/core/units.hpp"
#include "maxslice/pipeline/program_job.hpp"
#include "output.hpp"

namespace maxslice::pipeline {
namespace {

using nlohmann::ordered_json;

// Facets whose unit normals agree within this (1 - cos) are grouped as one flat face; and
// faces of less than this share of the surface are not offered as bases.
constexpr double kSameNormalCos = 1e-6;
constexpr double kMinFaceShare = 0.05;
constexpr int kMaxFaceCandidates = 4;
// Two candidate directions closer than this (1 - cos) are the same.
constexpr double kSameDirectionCos = 1e-9;

ordered_json frame_json(const slice::PlaneFrame& f) {
    return {{"origin", detail::vec_json(f.origin)},
            {"normal", detail::vec_json(f.normal)},
            {"u", detail::vec_json(f.u)},
            {"v", detail::vec_json(f.v)}};
}

ordered_json half_space_json(const plan::HalfSpace& h) {
    return {{"point", detail::vec_json(h.point)}, {"normal", detail::vec_json(h.normal)}};
}

const char* kind_name(plan::Decision::Kind k) {
    switch (k) {
        case plan::Decision::Kind::kSplit: return "split";
        case plan::Decision::Kind::kTiltWanted: return "tilt_wanted";
        case plan::Decision::Kind::kTilt: return "tilt";
        case plan::Decision::Kind::kTiltGaveUp: return "tilt_gave_up";
        case plan::Decision::Kind::kFloating: return "split_floating";
        case plan::Decision::Kind::kUnreachable: return "unreachable";
    }
    return "unknown";
}

// A colour per region (fixed palette, repeated).
std::array<int, 3> region_colour(int region) {
    static constexpr std::array<std::array<int, 3>, 10> kPalette{{{31, 119, 180},
                                                                  {255, 127, 14},
                                                                  {44, 160, 44},
                                                                  {214, 39, 40},
                                                                  {148, 103, 189},
                                                                  {140, 86, 75},
                                                                  {227, 119, 194},
                                                                  {127, 127, 127},
                                                                  {188, 189, 34},
                                                                  {23, 190, 207}}};
    return kPalette[static_cast<std::size_t>(region) % kPalette.size()];
}

template <class... A>
void put(fmt::memory_buffer& out, fmt::format_string<A...> format, A&&... args) {
    fmt::format_to(std::back_inserter(out), format, std::forward<A>(args)...);
}

std::string direction_label(const core::Vec3d& d) {
    return fmt::format("({:.4f}, {:.4f}, {:.4f})", d.x, d.y, d.z);
}

}  // namespace

plan::PlanSettings plan_settings(const machine::ProcessProfile& process) {
    plan::PlanSettings s;
    s.layer_mm = process.layer_height_mm;
    s.track_width_mm = process.track_width_mm;
    s.self_supporting_deg = process.self_supporting_angle_deg;
    s.footing_mm = process.footing_mm;
    s.leave_out_free_bodies = process.leave_out_free_bodies;
    s.h_min_mm = std::min(process.h_min_mm, s.layer_mm);
    s.h_max_mm = std::max(process.h_max_mm, s.layer_mm);
    return s;
}

plan::PlanSettings plan_settings(const machine::Profiles& profiles) {
    plan::PlanSettings s = plan_settings(profiles.process);
    s.head = nozzle_of(profiles.machine, nullptr);
    // A table that tilts presents a region's direction to the head within its tilt range.
    const machine::MachineProfile& m = profiles.machine;
    const char* tilt = m.kinematics == machine::Kinematics::kTableAc   ? "A"
                       : m.kinematics == machine::Kinematics::kTableBc ? "B"
                                                                       : nullptr;
    if (tilt != nullptr) {
        if (const machine::AxisLimits* a = m.find_axis(tilt)) {
            s.max_tilt_deg = std::min(180.0, std::max(std::abs(a->min), std::abs(a->max)));
        }
    }
    return s;
}

bool same_direction(const core::Vec3d& a, const core::Vec3d& b) {
    return core::dot(core::normalized(a), core::normalized(b)) > 1.0 - kSameDirectionCos;
}

std::tuple<bool, int, int> orientation_rank(const plan::Plan& plan) {
    return {!plan.unsupported_layers.empty(), plan.split_count(), plan.tilt_wanted_count()};
}

std::vector<OrientCandidate> orientation_candidates(const mesh::TriangleMesh& mesh) {
    std::vector<OrientCandidate> out;
    const auto add = [&](core::Vec3d d, std::string source) {
        d = core::normalized(d);
        for (const OrientCandidate& c : out) {
            if (same_direction(c.direction, d)) return;
        }
        out.push_back({d, std::move(source)});
    };
    add({0, 0, 1}, "+Z (as given)");
    add({0, 0, -1}, "-Z");
    add({1, 0, 0}, "+X");
    add({-1, 0, 0}, "-X");
    add({0, 1, 0}, "+Y");
    add({0, -1, 0}, "-Y");
    // Flat faces: facets grouped by (unit normal, plane offset).
    struct Face {
        core::Vec3d normal;
        double offset;
        double area;
    };
    std::vector<Face> faces;
    double total = 0.0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const core::Vec3d a = mesh::area_vector(mesh, t);
        const double area = 0.5 * core::norm(a);
        if (!(area > 0.0)) continue;
        total += area;
        const core::Vec3d n = core::normalized(a);
        const double offset = core::dot(n, mesh.corner(t, 0));
        bool merged = false;
        for (Face& f : faces) {
            if (core::dot(f.normal, n) > 1.0 - kSameNormalCos &&
                std::abs(f.offset - offset) < 1e-6 * (1.0 + std::abs(offset))) {
                f.area += area;
                merged = true;
                break;
            }
        }
        if (!merged) {
            if (faces.size() > 4096) continue;  // a freeform scan: no dominant flat faces
            faces.push_back({n, offset, area});
        }
    }
    std::stable_sort(faces.begin(), faces.end(),
                     [](const Face& a, const Face& b) { return a.area > b.area; });
    int taken = 0;
    for (const Face& f : faces) {
        if (taken == kMaxFaceCandidates || f.area < kMinFaceShare * total) break;
        // Standing on a face: its outward normal points down, the build goes along -n.
        add(-f.normal, fmt::format("largest flat face {} ({:.0f} mm2)", taken + 1, f.area));
        ++taken;
    }
    return out;
}

core::Result<std::vector<int>> trackless_layers(const plan::Plan& plan, std::span<const int> ids,
                                                const path::PathSettings& tracks) {
    std::vector<const geom2d::WireTree*> regions;
    regions.reserve(ids.size());
    for (const int id : ids) regions.push_back(&plan.layers[static_cast<std::size_t>(id)].wires);
    auto planned = path::plan_layers(regions, tracks, geom2d::Point2{});
    if (!planned) return std::unexpected(planned.error());
    std::vector<int> out;
    for (std::size_t i = 0; i < ids.size(); ++i) {
        if ((*planned)[i].strokes.empty()) out.push_back(ids[i]);
    }
    return out;
}

core::Result<std::vector<int>> laden_hanging(const plan::Plan& plan, std::span<const int> bare,
                                             const path::PathSettings& tracks,
                                             std::vector<char>& hangs) {
    const auto at = [&](int id) -> const plan::Layer& {
        return plan.layers[static_cast<std::size_t>(id)];
    };
    hangs.assign(plan.layers.size(), 0);
    for (const int id : bare) hangs[static_cast<std::size_t>(id)] = 1;
    std::vector<int> level(bare.begin(), bare.end());
    std::vector<int> laden;
    while (!level.empty()) {
        std::vector<int> next;
        for (const int id : level) {
            for (const int c : at(id).children) {
                if (hangs[static_cast<std::size_t>(c)] != 0) continue;
                const auto& ps = at(c).parents;
                if (std::all_of(ps.begin(), ps.end(),
                                [&](int q) { return hangs[static_cast<std::size_t>(q)] != 0; })) {
                    hangs[static_cast<std::size_t>(c)] = 1;
                    next.push_back(c);
                }
            }
        }
        std::sort(next.begin(), next.end());
        auto trackless = trackless_layers(plan, next, tracks);
        if (!trackless) return std::unexpected(trackless.error());
        for (const int id : next) {
            if (!std::binary_search(trackless->begin(), trackless->end(), id)) {
                laden.push_back(id);
            }
        }
        level = std::move(*trackless);  // a layer with a track carries what is above it
    }
    return laden;
}

namespace {

// What may hang from bare layers all the same, in all: this share of the plan's volume
// (decision 0044).
constexpr double kLeftOutShare = 1e-3;

// Moves the plan's layers on nothing that get no track to bare_unsupported_layers, unless a
// layer with a track hangs from them: one whose parents all hang from them (its tracks would
// all be cut to the beads below, a feature left out, decision 0013). Such a bare layer stays
// on nothing: the part (a body floating free, reached through a sliver) needs support; unless
// what hangs from it is a crumb (decision 0044: the bare layers in id order while all that
// hangs from them stays under kLeftOutShare of the plan), which is left out with it.
core::Result<void> set_aside_bare(plan::Plan& plan, const path::PathSettings& tracks) {
    if (plan.unsupported_layers.empty()) return {};
    auto bare = trackless_layers(plan, plan.unsupported_layers, tracks);
    if (!bare) return std::unexpected(bare.error());
    if (bare->empty()) return {};
    const auto at = [&](int id) -> const plan::Layer& {
        return plan.layers[static_cast<std::size_t>(id)];
    };
    std::vector<char> hangs;
    auto laden = laden_hanging(plan, *bare, tracks, hangs);
    if (!laden) return std::unexpected(laden.error());
    // The bare layers a laden layer hangs from stay on nothing.
    std::vector<char> keep(plan.layers.size(), 0);
    std::vector<int> up = std::move(*laden);
    while (!up.empty()) {
        const int id = up.back();
        up.pop_back();
        for (const int q : at(id).parents) {
            if (hangs[static_cast<std::size_t>(q)] != 0 && keep[static_cast<std::size_t>(q)] == 0) {
                keep[static_cast<std::size_t>(q)] = 1;
                up.push_back(q);
            }
        }
    }
    double left_out = 0.0;
    const double crumb = kLeftOutShare * plan.volume_mm3();
    for (const int id : *bare) {
        if (keep[static_cast<std::size_t>(id)] == 0) continue;
        const double load = plan::hanging_from(plan, id).volume_mm3;
        if (left_out + load < crumb) {
            left_out += load;
            keep[static_cast<std::size_t>(id)] = 0;
        }
    }
    std::erase_if(*bare, [&](int id) { return keep[static_cast<std::size_t>(id)] != 0; });
    std::erase_if(plan.unsupported_layers,
                  [&](int id) { return std::binary_search(bare->begin(), bare->end(), id); });
    plan.bare_unsupported_layers = std::move(*bare);
    return {};
}

}  // namespace

core::Result<PlannedPart> plan_mesh(const mesh::TriangleMesh& mesh, const PlanJobSettings& s,
                                    const core::Progress* progress) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto plan_along = [&](const core::Vec3d& direction) {
        if (!s.plate_center) return plan::plan_part(mesh, direction, s.plan, progress);
        return plan::plan_part(place_on_plate(mesh, direction, *s.plate_center), {0.0, 0.0, 1.0},
                               s.plan, progress);
    };
    PlannedPart out;
    if (s.orient == Orient::kGiven) {
        auto p = plan_along(s.direction);
        if (!p) return std::unexpected(p.error());
        if (s.tracks) {
            if (auto ok = set_aside_bare(*p, *s.tracks); !ok) return std::unexpected(ok.error());
        }
        out.plan = std::move(*p);
    } else {
        out.candidates = s.candidates.empty() ? orientation_candidates(mesh) : s.candidates;
        // Planned side by side (each plan is the same whatever runs beside it), then taken in
        // the candidates' order.
        std::vector<std::optional<core::Result<plan::Plan>>> plans(out.candidates.size());
        tbb::parallel_for(std::size_t{0}, out.candidates.size(), [&](std::size_t i) {
            plans[i] = plan_along(out.candidates[i].direction);
        });
        std::optional<core::Error> first_error;
        for (std::size_t i = 0; i < out.candidates.size(); ++i) {
            OrientCandidate& c = out.candidates[i];
            core::Result<plan::Plan>& p = *plans[i];
            if (!p) {
                if (p.error().code == core::ErrorCode::kCancelled)
                    return std::unexpected(p.error());
                c.error = p.error().describe();
                if (!first_error) first_error = p.error();
                continue;
            }
            if (s.tracks) {
                if (auto ok = set_aside_bare(*p, *s.tracks); !ok) {
                    return std::unexpected(ok.error());
                }
            }
            c.planned = true;
            c.splits = p->split_count();
            c.tilts_wanted = p->tilt_wanted_count();
            c.regions = static_cast<int>(p->regions.size());
            c.unsupported_layers = static_cast<int>(p->unsupported_layers.size());
            if (out.chosen < 0 || orientation_rank(*p) < orientation_rank(out.plan)) {
                out.chosen = static_cast<int>(i);
                out.plan = std::move(*p);
            }
        }
        if (out.chosen < 0) return std::unexpected(*first_error);
    }
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

plan::Nozzle nozzle_of(const machine::MachineProfile& machine, std::string* source) {
    plan::Nozzle n;
    if (machine.nozzle) {
        const machine::NozzleProfile& m = *machine.nozzle;
        n.half_angle_deg = m.half_angle_deg;
        n.cone_length_mm = m.cone_length_mm;
        n.standoff_mm = m.standoff_mm;
        n.body_radius_mm = m.body_radius_mm;
        n.body_length_mm = m.body_length_mm;
        n.clearance_mm = m.clearance_mm;
        if (source != nullptr) *source = fmt::format("machine profile '{}'", machine.name);
    } else if (source != nullptr) {
        *source = "default (the machine profile has no [machine.nozzle] table)";
    }
    return n;
}

core::Result<void> order_plan(PlannedPart& planned, const plan::Nozzle& nozzle,
                              std::string nozzle_source, const core::Progress* progress) {
    const auto t0 = std::chrono::steady_clock::now();
    plan::OrderSettings os;
    os.nozzle = nozzle;
    auto order = plan::order_layers(planned.plan, os, progress);
    if (!order) return std::unexpected(order.error());
    planned.order = std::move(*order);
    planned.nozzle = nozzle;
    planned.nozzle_source = std::move(nozzle_source);
    planned.order_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return {};
}

namespace {

// A margin as JSON: null when nothing is in reach (or the layer is not ordered).
ordered_json margin_json(double m) {
    return std::isfinite(m) ? ordered_json(m) : ordered_json();
}

ordered_json order_json(const PlannedPart& planned) {
    const plan::BuildOrder& o = *planned.order;
    const plan::Nozzle& n = planned.nozzle;
    ordered_json sections = ordered_json::array();
    for (const plan::Section& s : o.sections) {
        sections.push_back(
            {{"id", s.id}, {"side", s.side}, {"region", s.region}, {"layers", s.layers}});
    }
    ordered_json conflicts = ordered_json::array();
    for (const plan::Conflict& c : o.conflicts) {
        conflicts.push_back({{"layer", c.layer},
                             {"other", c.other},
                             {"apex", detail::vec_json(c.apex)},
                             {"hit", detail::vec_json(c.hit)},
                             {"margin_mm", c.margin_mm},
                             {"in_stream", c.in_stream},
                             {"reason", c.reason}});
    }
    return {{"complete", o.complete()},
            {"nozzle",
             {{"half_angle_deg", n.half_angle_deg},
              {"cone_length_mm", n.cone_length_mm},
              {"standoff_mm", n.standoff_mm},
              {"body_radius_mm", n.body_radius_mm},
              {"body_length_mm", n.body_length_mm},
              {"clearance_mm", n.clearance_mm},
              {"source", planned.nozzle_source}}},
            {"jumps", o.jumps},
            {"min_jumps", o.min_jumps},
            {"collision_edges", o.collision_edges},
            {"smallest_margin_mm", margin_json(o.smallest_margin_mm())},
            {"sections", std::move(sections)},
            {"conflicts", std::move(conflicts)}};
}

}  // namespace

std::string plan_json(const PlannedPart& planned, const PreparedPart& part) {
    const plan::Plan& p = planned.plan;
    ordered_json j;
    j["format"] = "maxslice-plan";
    j["version"] = 2;
    j["units"] = {{"length", "mm"},
                  {"angle", "deg"},
                  {"wire_points", "mm in the layer plane's (u, v) frame"}};
    j["part"] = {{"format", io::format_name(part.imported.format)},
                 {"triangles", part.report.triangles},
                 {"volume_mm3", part.report.volume_mm3}};
    const plan::PlanSettings& s = p.settings;
    j["settings"] = {{"layer_mm", s.layer_mm},
                     {"track_width_mm", s.track_width_mm},
                     {"self_supporting_deg", s.self_supporting_deg},
                     {"alpha_deg", s.alpha_deg},
                     {"beta_deg", s.beta_deg},
                     {"min_piece_area_mm2", s.min_piece_area_mm2},
                     {"max_regions", s.max_regions},
                     {"h_min_mm", s.h_min_mm},
                     {"h_max_mm", s.h_max_mm},
                     {"tilt_trigger_deg", s.tilt_trigger_deg},
                     {"max_tilt_tries", s.max_tilt_tries},
                     {"footing_mm", s.footing_mm},
                     {"footing_always", s.footing_always},
                     {"max_tilt_deg", s.max_tilt_deg}};
    ordered_json orient;
    orient["mode"] = planned.candidates.empty() ? "given" : "auto";
    orient["base_direction"] = detail::vec_json(p.base_direction);
    if (!planned.candidates.empty()) {
        ordered_json cands = ordered_json::array();
        for (const OrientCandidate& c : planned.candidates) {
            ordered_json cj{{"direction", detail::vec_json(c.direction)},
                            {"source", c.source},
                            {"planned", c.planned}};
            if (c.planned) {
                cj["splits"] = c.splits;
                cj["tilts_wanted"] = c.tilts_wanted;
                cj["regions"] = c.regions;
                cj["unsupported_layers"] = c.unsupported_layers;
            } else {
                cj["error"] = c.error;
            }
            cands.push_back(std::move(cj));
        }
        orient["candidates"] = std::move(cands);
        orient["chosen"] = planned.chosen;
        orient["rule"] =
            "no layer on nothing, then fewest splits, then fewest tilts wanted, then the first "
            "tried";
    }
    j["orientation"] = std::move(orient);
    j["summary"] = {{"regions", p.regions.size()},
                    {"layers", p.layers.size()},
                    {"splits", p.split_count()},
                    {"tilts_wanted", p.tilt_wanted_count()},
                    {"tilted_layers", p.tilted_layer_count()},
                    {"unsupported_layers", p.unsupported_layers.size()},
                    {"plan_volume_mm3", p.volume_mm3()}};
    ordered_json regions = ordered_json::array();
    for (const plan::Region& r : p.regions) {
        ordered_json cell = ordered_json::array();
        for (const plan::HalfSpace& h : r.cell) cell.push_back(half_space_json(h));
        regions.push_back({{"id", r.id},
                           {"parent", r.parent},
                           {"direction", detail::vec_json(r.direction)},
                           {"base", frame_json(r.base)},
                           {"cell", std::move(cell)},
                           {"layers", r.layers},
                           {"reason", plan::describe(p, r)}});
    }
    j["regions"] = std::move(regions);
    ordered_json layers = ordered_json::array();
    for (const plan::Layer& l : p.layers) {
        ordered_json wires = ordered_json::array();
        for (const geom2d::WireNode& n : l.wires.nodes) {
            ordered_json pts = ordered_json::array();
            for (const geom2d::Point2& q : n.wire) {
                pts.push_back({core::um_to_mm(q.x), core::um_to_mm(q.y)});
            }
            wires.push_back(
                {{"hole", n.is_hole}, {"parent", n.parent}, {"points", std::move(pts)}});
        }
        layers.push_back({{"id", l.id},
                          {"region", l.region},
                          {"index_in_region", l.index_in_region},
                          {"plane", frame_json(l.plane)},
                          {"bottom_mm", l.span.bottom},
                          {"top_mm", l.span.top},
                          {"cut_mm", l.span.cut},
                          {"thickness_min_mm", l.thickness_min_mm},
                          {"thickness_max_mm", l.thickness_max_mm},
                          {"thickness_mean_mm", l.thickness_mean_mm},
                          {"tilted", l.tilted},
                          {"top", frame_json(l.top)},
                          {"area_mm2", l.area_mm2},
                          {"on_plate", l.on_plate},
                          {"after_gap", l.after_gap},
                          {"parents", l.parents},
                          {"children", l.children},
                          {"wires", std::move(wires)}});
        if (planned.order) {
            const auto i = static_cast<std::size_t>(l.id);
            ordered_json& lj = layers.back();
            lj["side"] = planned.order->side_of[i];
            lj["section"] = planned.order->section_of[i];
            lj["margin_mm"] = margin_json(planned.order->margin_mm[i]);
        }
    }
    j["layers"] = std::move(layers);
    ordered_json decisions = ordered_json::array();
    for (const plan::Decision& d : p.decisions) {
        ordered_json dj{{"kind", kind_name(d.kind)},
                        {"region", d.region},
                        {"lower_layer", d.layer},
                        {"height_mm", d.height_mm},
                        {"piece",
                         {{"area_mm2", d.piece.area_mm2},
                          {"C", detail::vec_json(d.piece.C)},
                          {"P", detail::vec_json(d.piece.P)},
                          {"V", detail::vec_json(d.piece.V)},
                          {"ang_deg", d.piece.ang_deg},
                          {"touches_lower", d.piece.touches_lower}}},
                        {"reason", plan::describe(p, d)}};
        if (d.kind == plan::Decision::Kind::kSplit || d.kind == plan::Decision::Kind::kFloating) {
            dj["new_region"] = d.new_region;
            dj["continuation"] = d.continuation;
            dj["split_plane"] = half_space_json(d.split_plane);
            if (!d.far_regions.empty()) {
                ordered_json far = ordered_json::array();
                for (std::size_t k = 0; k < d.far_regions.size(); ++k) {
                    far.push_back({{"region", d.far_regions[k]},
                                   {"plane", half_space_json(d.far_planes[k])}});
                }
                dj["far_features"] = std::move(far);
            }
            if (d.head_checked) {
                dj["head"] = {
                    {"lean_deg", d.split_lean_deg},           {"turn_deg", d.split_turn_deg},
                    {"searched_deg", d.split_searched_deg},   {"margin_mm", d.head_margin_mm},
                    {"sideways_margin_mm", d.seed_margin_mm}, {"clears", d.head_clears}};
            }
        }
        if (d.kind == plan::Decision::Kind::kTilt) dj["lean_deg"] = d.lean_deg;
        decisions.push_back(std::move(dj));
    }
    j["decisions"] = std::move(decisions);
    j["unsupported_layers"] = p.unsupported_layers;
    j["bare_unsupported_layers"] = p.bare_unsupported_layers;
    ordered_json free = ordered_json::array();
    for (const plan::FreeBody& b : p.free_bodies) {
        free.push_back({{"volume_mm3", b.volume_mm3},
                        {"min", detail::vec_json(b.box.min)},
                        {"max", detail::vec_json(b.box.max)},
                        {"gap_mm", b.gap_mm}});
    }
    j["free_bodies"] = std::move(free);
    j["footing"] = {{"layers", p.footing.layers},
                    {"height_mm", p.footing.height_mm},
                    {"added_mm3", p.footing.added_mm3}};
    if (planned.order) {
        j["order"] = planned.order->order;
        j["build_order"] = order_json(planned);
    } else {
        j["order"] = plan::topological_order(p);
    }
    return j.dump(1) + "\n";
}

std::string plan_dot(const plan::Plan& p) {
    fmt::memory_buffer out;
    put(out, "digraph maxslice_plan {{\n  rankdir=BT;\n  node [shape=box, fontsize=9];\n");
    for (const plan::Region& r : p.regions) {
        const auto c = region_colour(r.id);
        put(out, "  subgraph cluster_region_{} {{\n    label=\"region {} along {}\";\n", r.id, r.id,
            direction_label(r.direction));
        for (const int id : r.layers) {
            const plan::Layer& l = p.layers[static_cast<std::size_t>(id)];
            put(out,
                "    L{} [label=\"L{} r{} #{}\\n{:.2f} mm, {:.1f} mm2\", style=filled, "
                "fillcolor=\"#{:02x}{:02x}{:02x}\"];\n",
                id, id, r.id, l.index_in_region, l.span.cut, l.area_mm2, c[0], c[1], c[2]);
        }
        put(out, "  }}\n");
    }
    for (const plan::Layer& l : p.layers) {
        for (const int child : l.children) put(out, "  L{} -> L{};\n", l.id, child);
    }
    put(out, "}}\n");
    return fmt::to_string(out);
}

namespace {

// The colour of every layer (by id) for a preview.
std::vector<std::array<int, 3>> layer_colours(const plan::Plan& p, PlanColour colour,
                                              const plan::BuildOrder* order) {
    constexpr std::array<int, 3> kUnordered{128, 128, 128};
    std::vector<std::array<int, 3>> out;
    out.reserve(p.layers.size());
    for (const plan::Layer& l : p.layers) out.push_back(region_colour(l.region));
    if (order == nullptr || colour == PlanColour::kRegion) return out;
    std::fill(out.begin(), out.end(), kUnordered);
    const std::size_t n = order->order.size();
    for (std::size_t k = 0; k < n; ++k) {
        const auto i = static_cast<std::size_t>(order->order[k]);
        if (colour == PlanColour::kSection) {
            out[i] = region_colour(order->section_of[i]);
        } else {
            const double t = n > 1 ? static_cast<double>(k) / static_cast<double>(n - 1) : 0.0;
            out[i] = {static_cast<int>(255 * t), 64, 255 - static_cast<int>(255 * t)};
        }
    }
    return out;
}

const char* colour_meaning(PlanColour colour) {
    switch (colour) {
        case PlanColour::kOrder: return "build order (blue first, red last, grey not ordered)";
        case PlanColour::kSection: return "section of the build order (grey not ordered)";
        case PlanColour::kRegion: break;
    }
    return "region";
}

}  // namespace

std::string plan_ply(const plan::Plan& p, PlanColour colour, const plan::BuildOrder* order) {
    fmt::memory_buffer verts, faces;
    std::size_t nv = 0, nf = 0;
    if (order == nullptr) colour = PlanColour::kRegion;
    const std::vector<std::array<int, 3>> colours = layer_colours(p, colour, order);
    const auto colour_of = [&](const plan::Layer& l) {
        return colours[static_cast<std::size_t>(l.id)];
    };
    const char* what = colour_meaning(colour);
    for (const plan::Layer& l : p.layers) {
        const auto c = colour_of(l);
        const double lo = l.span.bottom - l.span.cut, hi = l.span.top - l.span.cut;
        for (const geom2d::WireNode& n : l.wires.nodes) {
            const std::size_t k = n.wire.size();
            if (k < 3) continue;
            for (const geom2d::Point2& q : n.wire) {
                for (const double h : {lo, hi}) {
                    const core::Vec3d x = l.plane.to_3d(q, h);
                    fmt::format_to(std::back_inserter(verts), "{:.4f} {:.4f} {:.4f} {} {} {}\n",
                                   x.x, x.y, x.z, c[0], c[1], c[2]);
                }
            }
            for (std::size_t i = 0; i < k; ++i) {
                const std::size_t a = nv + 2 * i, b = nv + 2 * ((i + 1) % k);
                // Outward for outers (CCW seen from +normal), inward for holes: both face
                // away from the material.
                fmt::format_to(std::back_inserter(faces), "4 {} {} {} {}\n", a, b, b + 1, a + 1);
                ++nf;
            }
            nv += 2 * k;
        }
    }
    return fmt::format(
        "ply\nformat ascii 1.0\ncomment maxslice plan: layer walls coloured by {}\n"
        "element vertex {}\nproperty float x\nproperty float y\nproperty float z\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\n"
        "element face {}\nproperty list uchar int vertex_indices\nend_header\n{}{}",
        what, nv, nf, fmt::to_string(verts), fmt::to_string(faces));
}

core::Result<void> write_plan_svgs(const std::filesystem::path& dir, const plan::Plan& p) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec)
        return core::fail(core::ErrorCode::kIo, "cannot create folder: " + ec.message(),
                          dir.string());
    for (const plan::Region& r : p.regions) {
        // Every layer's wires in the region's base frame (layers are parallel to it).
        double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
        std::vector<std::vector<std::vector<std::pair<double, double>>>> drawn;
        for (const int id : r.layers) {
            const plan::Layer& l = p.layers[static_cast<std::size_t>(id)];
            auto& layer = drawn.emplace_back();
            for (const geom2d::WireNode& n : l.wires.nodes) {
                auto& loop = layer.emplace_back();
                for (const geom2d::Point2& q : n.wire) {
                    const geom2d::Point2 b = r.base.to_2d(l.plane.to_3d(q));
                    const double x = core::um_to_mm(b.x), y = -core::um_to_mm(b.y);
                    loop.emplace_back(x, y);
                    x0 = std::min(x0, x);
                    y0 = std::min(y0, y);
                    x1 = std::max(x1, x);
                    y1 = std::max(y1, y);
                }
            }
        }
        if (x0 > x1) x0 = y0 = 0.0, x1 = y1 = 1.0;
        const double margin = 2.0;
        fmt::memory_buffer out;
        fmt::format_to(std::back_inserter(out),
                       "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"{:.3f} {:.3f} {:.3f} "
                       "{:.3f}\" width=\"800\">\n<title>region {} along {}: {} layers</title>\n",
                       x0 - margin, y0 - margin, x1 - x0 + 2 * margin, y1 - y0 + 2 * margin, r.id,
                       direction_label(r.direction), r.layers.size());
        for (std::size_t i = 0; i < drawn.size(); ++i) {
            const double t = drawn.size() > 1
                                 ? static_cast<double>(i) / static_cast<double>(drawn.size() - 1)
                                 : 0.0;
            const int red = static_cast<int>(255 * t), blue = 255 - red;
            fmt::format_to(
                std::back_inserter(out),
                "<path fill=\"none\" stroke=\"#{:02x}40{:02x}\" stroke-width=\"0.1\" d=\"", red,
                blue);
            for (const auto& loop : drawn[i]) {
                for (std::size_t k = 0; k < loop.size(); ++k) {
                    fmt::format_to(std::back_inserter(out), "{}{:.3f} {:.3f} ", k == 0 ? "M" : "L",
                                   loop[k].first, loop[k].second);
                }
                fmt::format_to(std::back_inserter(out), "Z ");
            }
            fmt::format_to(std::back_inserter(out), "\"/>\n");
        }
        fmt::format_to(std::back_inserter(out), "</svg>\n");
        if (auto ok = detail::write_text(dir / fmt::format("region_{:03}.svg", r.id),
                                         fmt::to_string(out));
            !ok) {
            return ok;
        }
    }
    return {};
}

core::Result<void> write_order_svgs(const std::filesystem::path& dir, const plan::Plan& p,
                                    const plan::BuildOrder& order) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec)
        return core::fail(core::ErrorCode::kIo, "cannot create folder: " + ec.message(),
                          dir.string());
    struct View {
        const char* name;
        core::Vec3d right;
    };
    const View views[] = {{"xz", {1.0, 0.0, 0.0}}, {"yz", {0.0, 1.0, 0.0}}};
    for (const PlanColour colour : {PlanColour::kOrder, PlanColour::kSection}) {
        const std::vector<std::array<int, 3>> colours = layer_colours(p, colour, &order);
        for (const View& view : views) {
            // Side view: every wire projected on the plane spanned by `right` and +Z.
            double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
            fmt::memory_buffer paths;
            // Unordered layers first (under), then in build order.
            std::vector<int> ids;
            std::vector<char> placed(p.layers.size(), 0);
            for (const int id : order.order) placed[static_cast<std::size_t>(id)] = 1;
            for (const plan::Layer& l : p.layers) {
                if (placed[static_cast<std::size_t>(l.id)] == 0) ids.push_back(l.id);
            }
            ids.insert(ids.end(), order.order.begin(), order.order.end());
            for (const int id : ids) {
                const plan::Layer& l = p.layers[static_cast<std::size_t>(id)];
                const auto& c = colours[static_cast<std::size_t>(id)];
                put(paths,
                    "<path fill=\"none\" stroke=\"#{:02x}{:02x}{:02x}\" stroke-width=\"0.15\" d=\"",
                    c[0], c[1], c[2]);
                for (const geom2d::WireNode& n : l.wires.nodes) {
                    for (std::size_t k = 0; k < n.wire.size(); ++k) {
                        const core::Vec3d x = l.plane.to_3d(n.wire[k]);
                        const double u = core::dot(x, view.right), v = -x.z;
                        x0 = std::min(x0, u);
                        y0 = std::min(y0, v);
                        x1 = std::max(x1, u);
                        y1 = std::max(y1, v);
                        put(paths, "{}{:.3f} {:.3f} ", k == 0 ? "M" : "L", u, v);
                    }
                    put(paths, "Z ");
                }
                put(paths, "\"/>\n");
            }
            if (x0 > x1) x0 = y0 = 0.0, x1 = y1 = 1.0;
            const double margin = 2.0;
            const std::string what = colour == PlanColour::kOrder ? "order" : "sections";
            const std::string text = fmt::format(
                "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"{:.3f} {:.3f} {:.3f} {:.3f}\" "
                "width=\"800\">\n<title>side view ({}): layers coloured by {}</title>\n{}</svg>\n",
                x0 - margin, y0 - margin, x1 - x0 + 2 * margin, y1 - y0 + 2 * margin, view.name,
                colour_meaning(colour), fmt::to_string(paths));
            if (auto ok = detail::write_text(dir / fmt::format("{}_{}.svg", what, view.name), text);
                !ok) {
                return ok;
            }
        }
    }
    return {};
}

std::string volume_against_mesh(double volume_mm3, const mesh::ValidationReport& report) {
    if (!report.closed()) {
        return "(the mesh is not closed: its volume is not defined, nothing to compare)";
    }
    const double m = report.volume_mm3;
    return fmt::format("(mesh {:.6g} mm3, {:+.3f}%)", m,
                       m != 0.0 ? 100.0 * (volume_mm3 - m) / m : 0.0);
}

std::string footing_line(const plan::Footing& footing) {
    if (footing.layers == 0) return {};
    return fmt::format(
        "footing         {:.2f} mm: {} layers at the plate laid over the part's footprint, "
        "{:.4g} mm3 outside the part (under a rounded or chamfered bottom edge; machined off "
        "with the plate)\n",
        footing.height_mm, footing.layers, footing.added_mm3);
}

std::string plan_summary(const PlannedPart& planned, const mesh::ValidationReport& report) {
    const plan::Plan& p = planned.plan;
    fmt::memory_buffer out;
    if (!planned.candidates.empty()) {
        put(out, "orientation     auto: {} candidates\n", planned.candidates.size());
        for (std::size_t i = 0; i < planned.candidates.size(); ++i) {
            const OrientCandidate& c = planned.candidates[i];
            put(out, "  {} {:<32} {}\n", static_cast<int>(i) == planned.chosen ? "*" : " ",
                c.source,
                c.planned
                    ? fmt::format("{} splits, {} tilts wanted, {} regions{}", c.splits,
                                  c.tilts_wanted, c.regions,
                                  c.unsupported_layers > 0
                                      ? fmt::format(", {} layers on nothing", c.unsupported_layers)
                                      : "")
                    : "failed: " + c.error);
        }
    }
    put(out, "base direction  {}\n", direction_label(p.base_direction));
    put(out, "regions         {}\n", p.regions.size());
    for (const plan::Region& r : p.regions) {
        put(out, "  region {:<3} along {}  {} layers{}\n", r.id, direction_label(r.direction),
            r.layers.size(), r.parent >= 0 ? fmt::format(", from region {}", r.parent) : "");
    }
    put(out, "splits          {}\n", p.split_count());
    for (const plan::Decision& d : p.decisions) {
        if (d.kind == plan::Decision::Kind::kSplit || d.kind == plan::Decision::Kind::kFloating) {
            put(out, "  {}\n", plan::describe(p, d));
        }
    }
    put(out, "tilted layers   {}\n", p.tilted_layer_count());
    // The tilts and the give-ups, in the order taken; a run of give-ups with no tilt between
    // them is one line (the splits and other decisions between them are listed above).
    std::vector<const plan::Decision*> tilts;
    for (const plan::Decision& d : p.decisions) {
        if (d.kind == plan::Decision::Kind::kTilt || d.kind == plan::Decision::Kind::kTiltGaveUp) {
            tilts.push_back(&d);
        }
    }
    const auto gave_up = [&](std::size_t i) {
        return tilts[i]->kind == plan::Decision::Kind::kTiltGaveUp;
    };
    for (std::size_t i = 0; i < tilts.size(); ++i) {
        if (!gave_up(i)) {
            put(out, "  {}\n", plan::describe(p, *tilts[i]));
            continue;
        }
        std::size_t j = i;
        while (j + 1 < tilts.size() && gave_up(j + 1)) ++j;
        put(out, "  {}\n",
            plan::describe_tilt_gave_up(p, tilts[i]->layer, tilts[j]->layer, j - i + 1));
        i = j;
    }
    put(out, "tilts wanted    {} (overhangs with alpha < Ang <= beta left planar)\n",
        p.tilt_wanted_count());
    put(out, "layers          {}\n", p.layers.size());
    // A list of layers on nothing: its count and where the first is, then what it means.
    const auto on_nothing = [&](const char* label, const std::vector<int>& ids, const char* what,
                                const std::string& meaning) {
        if (ids.empty()) return;
        const plan::Layer& l = p.layers[static_cast<std::size_t>(ids.front())];
        const core::Vec3d at = plan::centroid_of(l);
        put(out, "{}{} layers {}, first: layer {} of region {} near ({:.3f}, {:.3f}, {:.3f}){}\n",
            label, ids.size(), what, l.id, l.region, at.x, at.y, at.z, meaning);
    };
    const std::string load =
        p.unsupported_layers.empty()
            ? std::string()
            : "; " + plan::describe_hanging(p, p.unsupported_layers.front(), "plan");
    on_nothing("unsupported     ", p.unsupported_layers,
               "rest on nothing (a body floating free of the rest, or material reached across a "
               "gap)",
               load + "; they need support or another base (--orient auto)");
    on_nothing("left bare       ", p.bare_unsupported_layers, "without parents where no track fits",
               ": nothing is laid there (narrower than the track), and tracks above them only "
               "over beads");
    if (!p.free_bodies.empty()) put(out, "left out        {}\n", plan::describe_free_bodies(p));
    const double v = p.volume_mm3();
    put(out, "plan volume     {:.6g} mm3 {}\n", v, volume_against_mesh(v, report));
    put(out, "{}", footing_line(p.footing));
    put(out, "planning time   {:.3f} s\n", planned.seconds);
    if (planned.order) {
        const plan::BuildOrder& o = *planned.order;
        const plan::Nozzle& n = planned.nozzle;
        put(out,
            "nozzle          cone {:.1f} deg half-angle, {:.1f} mm long, body {:.1f} x {:.1f} mm, "
            "clearance {:.2f} mm ({})\n",
            n.half_angle_deg, n.cone_length_mm, n.body_radius_mm, n.body_length_mm, n.clearance_mm,
            planned.nozzle_source);
        put(out, "build order     {} of {} layers{}\n", o.order.size(), p.layers.size(),
            o.complete() ? ", collision-free" : ": NO collision-free order (conflicts below)");
        put(out, "jumps           {} region changes (fewest possible {})\n", o.jumps, o.min_jumps);
        put(out, "sections        {}\n", o.sections.size());
        put(out, "nozzle orders   {} pairs the graph leaves free\n", o.collision_edges);
        const double m = o.smallest_margin_mm();
        put(out, "smallest margin {}\n",
            std::isfinite(m) ? fmt::format("{:.3f} mm", m)
                             : std::string("none in reach (every nozzle clears all material)"));
        for (const plan::Conflict& c : o.conflicts) put(out, "  conflict: {}\n", c.reason);
        put(out, "ordering time   {:.3f} s\n", planned.order_seconds);
    }
    return fmt::to_string(out);
}

}  // namespace maxslice::pipeline
