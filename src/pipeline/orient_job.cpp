#include "maxslice/pipeline/orient_job.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include <tbb/parallel_for.h>

#include "maxslice/machine/kinematics.hpp"
#include "maxslice/pipeline/program_job.hpp"

namespace maxslice::pipeline {
namespace {

using core::Vec3d;

// Whether the policy tries the part as given (first).
bool tries_given(OrientPolicy policy) {
    return policy == OrientPolicy::kGiven || policy == OrientPolicy::kFallback;
}

// Why a multi-axis plan cannot be built, or "" when it can.
std::string multiaxis_refusal(const PlannedPart& p, const std::vector<int>& bare_plate) {
    if (!p.plan.unsupported_layers.empty()) {
        return fmt::format("{} layers rest on nothing", p.plan.unsupported_layers.size());
    }
    if (!bare_plate.empty()) {
        return fmt::format("stands on {} piece(s) where no track fits", bare_plate.size());
    }
    if (p.order && !p.order->complete()) {
        return fmt::format("no collision-free build order ({} conflicts)",
                           p.order->conflicts.size());
    }
    return {};
}

// The layers on the plate whose toolpaths have no track (every feature narrower than the
// track) when something with a track stands on them alone, directly or over more such layers:
// a part standing on a knife edge or a tip. The toolpath stage would leave them bare and cut
// every track above them (decision 0013), layer after layer. A layer that also rests on a
// layer with a track (a sliver at the plate beside the part's foot, which the next layers
// join) does not hang from them: its tracks are cut to the beads below it, and the verifier
// judges what is left. Parts where no track fits anywhere above them (too fine for the track,
// or in other units) give none: the toolpath stage names that case.
core::Result<std::vector<int>> bare_plate_layers(const plan::Plan& plan,
                                                 const machine::Profiles& profiles) {
    const path::PathSettings settings = path_settings(profiles.process);
    std::vector<int> plate;
    for (const plan::Layer& l : plan.layers) {
        if (l.on_plate) plate.push_back(l.id);
    }
    auto bare_plate = trackless_layers(plan, plate, settings);
    if (!bare_plate) return std::unexpected(bare_plate.error());
    std::vector<char> hangs;
    auto laden = laden_hanging(plan, *bare_plate, settings, hangs);
    if (!laden) return std::unexpected(laden.error());
    if (!laden->empty()) return bare_plate;  // a track stands on them
    return std::vector<int>{};
}

struct Placed {
    Vec3d direction;  // the part file's direction built upwards
    mesh::TriangleMesh placed;
    PlannedPart planned;
    std::vector<int> bare_plate;
};

// The part's lowest layer must stand on the substrate plate (decision 0028): beads beyond
// its top face rest on nothing. `plate` holds the lowest layer's vertices; grown by grown_mm
// on every side as deposited.
core::Result<void> check_on_plate(const machine::MachineProfile& machine,
                                  const std::vector<Vec3d>& plate, double grown_mm) {
    if (!machine.substrate || plate.empty()) return {};
    const Vec3d c = machine::plate_center(machine);
    const double hx = machine.substrate->size_x_mm / 2, hy = machine.substrate->size_y_mm / 2;
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (const Vec3d& v : plate) {
        x0 = std::min(x0, v.x - grown_mm);
        x1 = std::max(x1, v.x + grown_mm);
        y0 = std::min(y0, v.y - grown_mm);
        y1 = std::max(y1, v.y + grown_mm);
    }
    if (x0 >= c.x - hx && x1 <= c.x + hx && y0 >= c.y - hy && y1 <= c.y + hy) return {};
    return core::fail(
        core::ErrorCode::kInvalidInput,
        fmt::format("the part's footprint on the plate, {:.1f} x {:.1f} mm, reaches {:.1f} mm "
                    "along X and {:.1f} mm along Y from the plate's centre (the part's place), "
                    "beyond the substrate plate ({:.1f} x {:.1f} mm, [machine.substrate]): beads "
                    "there would rest on nothing; enter the size of the plate the part is welded "
                    "onto",
                    x1 - x0, y1 - y0, std::max(c.x - x0, x1 - c.x), std::max(c.y - y0, y1 - c.y),
                    2 * hx, 2 * hy),
        "machine.substrate");
}

// Whether the table can bring `placed` (a part on the plate) under the nozzle at all
// (MachineKinematics::check_reach, with a track's width of slack), as deposited grown by
// `grown_mm` on every side: a part larger than the machine is refused before it is planned.
// The grown part's points are checked exactly where it matters most: every point of a part
// grown by s lies within s of the part, and the farthest from the table's axes is a vertex
// moved s farther out, so the check of the vertices is made with s less slack (the grown part
// stands s higher: its box is the part's grown by s). Its lowest layer is checked on the
// part's own lowest layer moved down by s (a part of the grown one's lowest layer: a bound
// that never refuses what the grown part's own check would pass). The lowest layer must
// also stand on the plate (check_on_plate).
core::Result<void> check_reach_of(const machine::MachineKinematics& kinematics,
                                  const machine::MachineProfile& machine,
                                  const mesh::TriangleMesh& placed,
                                  const machine::ProcessProfile& process, double grown_mm) {
    double bottom = INFINITY;
    for (const Vec3d& v : placed.vertices) bottom = std::min(bottom, v.z);
    std::vector<Vec3d> plate;
    for (const Vec3d& v : placed.vertices) {
        if (v.z <= bottom + process.layer_height_mm) plate.push_back(v);
    }
    if (grown_mm <= 0.0) {
        if (auto ok = kinematics.check_reach(placed.vertices, plate, process.track_width_mm); !ok) {
            return ok;
        }
        return check_on_plate(machine, plate, grown_mm);
    }
    std::vector<Vec3d> raised = placed.vertices;
    for (Vec3d& v : raised) v.z += grown_mm;
    if (auto ok = kinematics.check_reach(raised, {}, process.track_width_mm - grown_mm); !ok) {
        return ok;
    }
    if (auto ok = kinematics.check_reach({}, plate, process.track_width_mm); !ok) return ok;
    return check_on_plate(machine, plate, grown_mm);
}

core::Result<Placed> plan_along(const mesh::TriangleMesh& part, const Vec3d& direction,
                                const machine::Profiles& profiles, const core::Progress* progress) {
    Placed out;
    out.direction = direction;
    out.placed = place_on_plate(part, direction, machine::plate_center(profiles.machine));
    // A part the table cannot bring under the nozzle is refused before it is planned.
    auto kinematics = machine::MachineKinematics::create(profiles.machine);
    if (!kinematics) return std::unexpected(kinematics.error());
    if (auto ok = check_reach_of(*kinematics, profiles.machine, out.placed, profiles.process, 0.0);
        !ok) {
        return std::unexpected(ok.error());
    }
    PlanJobSettings ps;
    ps.plan = plan_settings(profiles);
    ps.tracks = path_settings(profiles.process);
    auto planned = plan_mesh(out.placed, ps, progress);
    if (!planned) return std::unexpected(planned.error());
    out.planned = std::move(*planned);
    auto bare = bare_plate_layers(out.planned.plan, profiles);
    if (!bare) return std::unexpected(bare.error());
    out.bare_plate = std::move(*bare);
    // A part whose first layers no track fits (a near-net shape's rounded bottom edge, a part
    // standing on an edge) and that got no footing, since no split at the plate asked for it:
    // planned again with the footing laid from the plate, kept when tracks then stand on it
    // (decision 0017).
    if (!out.bare_plate.empty() && ps.plan.footing_mm > 0.0 &&
        out.planned.plan.footing.layers == 0) {
        ps.plan.footing_always = true;
        auto again = plan_mesh(out.placed, ps, progress);
        if (!again) {
            // A refusal of the plan with the footing: the first plan and its refusal stand.
            if (again.error().code != core::ErrorCode::kInvalidInput) {
                return std::unexpected(again.error());  // cancelled, or a bug
            }
            return out;
        }
        auto still = bare_plate_layers(again->plan, profiles);
        if (!still) return std::unexpected(still.error());
        if (still->empty()) {
            out.planned = std::move(*again);
            out.bare_plate.clear();
        }
    }
    return out;
}

core::Result<void> order(Placed& p, const machine::Profiles& profiles,
                         const core::Progress* progress) {
    std::string source;
    const plan::Nozzle nozzle = nozzle_of(profiles.machine, &source);
    return order_plan(p.planned, nozzle, std::move(source), progress);
}

// An error's message up to its first ": " (the rest is detail for the direction kept).
std::string first_clause(const core::Error& e) {
    const std::size_t colon = e.message.find(": ");
    return colon == std::string::npos ? e.message : e.message.substr(0, colon);
}

std::string planar_refusal(const plan::PlanarCheck& check) {
    if (check.overhangs == 0) return {};
    return fmt::format("overhangs a planar build cannot hold from {:.3f} mm up",
                       check.heights_mm.empty() ? 0.0 : check.heights_mm.front());
}

}  // namespace

std::string other_tries(const std::vector<OrientTry>& tries, int chosen) {
    std::string out;
    for (std::size_t i = 0; i < tries.size(); ++i) {
        if (static_cast<int>(i) == chosen || tries[i].source == "as given") continue;
        out += fmt::format("{}{} ({})", out.empty() ? "" : ", ", tries[i].source,
                           tries[i].refusal.empty() ? "builds" : tries[i].refusal);
    }
    return out.empty() ? out : "; other orientations tried: " + out;
}

core::Result<void> check_fits_machine(const mesh::TriangleMesh& part, const Vec3d& given,
                                      OrientPolicy policy, const machine::Profiles& profiles,
                                      double grown_mm) {
    if (!machine::is_table_tilt(profiles.machine.kinematics)) return {};
    auto kinematics = machine::MachineKinematics::create(profiles.machine);
    if (!kinematics) return std::unexpected(kinematics.error());
    // The most slack any of the job's processes gets (each attempt checks again with its own).
    machine::ProcessProfile widest = profiles.process;
    for (const machine::ProcessProfile& p : profiles.process.finer) {
        widest.track_width_mm = std::max(widest.track_width_mm, p.track_width_mm);
    }
    std::vector<std::pair<Vec3d, std::string>> directions;
    if (tries_given(policy)) directions.emplace_back(given, "as given");
    if (policy != OrientPolicy::kGiven) {
        for (const OrientCandidate& c : orientation_candidates(part)) {
            if (policy == OrientPolicy::kAuto || !same_direction(c.direction, given)) {
                directions.emplace_back(c.direction, c.source);
            }
        }
    }
    std::vector<OrientTry> tries;
    std::optional<core::Error> first;
    for (const auto& [direction, source] : directions) {
        const mesh::TriangleMesh placed =
            place_on_plate(part, direction, machine::plate_center(profiles.machine));
        auto ok = check_reach_of(*kinematics, profiles.machine, placed, widest, grown_mm);
        if (ok) return {};
        if (ok.error().code != core::ErrorCode::kInvalidInput) return ok;
        tries.push_back(
            {core::normalized(direction), source, "no plan: " + first_clause(ok.error())});
        if (!first) first = ok.error();
    }
    if (!first) return {};
    if (grown_mm > 0.0) {
        first->message += fmt::format(
            " (the part as deposited: grown by its {:.2f} mm machining stock, checked before its "
            "near-net shape is made)",
            grown_mm);
    }
    first->message += other_tries(tries, 0);
    return std::unexpected(*first);
}

namespace {

// A candidate base that can be built, with the build time its program was estimated at.
struct Buildable {
    std::size_t item = 0;      // the caller's index of the candidate
    std::size_t tried = 0;     // index into the tries
    double estimate_s = 0.0;   // the program's build time before it is written and verified
    double verified_s = -1.0;  // the check's build time (-1: not checked, or refused)
    bool short_of_figures = false;
};

// Of `buildable`, the one with the shortest verified build time among those that meet the
// figures (else among those that verify): checked from the shortest estimate up (ties: their
// order), until one meets the figures and the next estimate is no shorter than its verified
// time. The tries of the others say why they were not kept. The last check made is of the one
// returned (the caller's program is its). nullptr: the check refused every one.
core::Result<const Buildable*> keep_shortest(
    std::vector<Buildable>& buildable, std::vector<OrientTry>& tries,
    const std::function<core::Result<ProgramVerdict>(std::size_t item)>& check) {
    std::stable_sort(
        buildable.begin(), buildable.end(),
        [](const Buildable& a, const Buildable& b) { return a.estimate_s < b.estimate_s; });
    // Meets the figures first, then the shorter verified build time.
    const auto better = [](const Buildable& a, const Buildable& b) {
        if (a.short_of_figures != b.short_of_figures) return !a.short_of_figures;
        return a.verified_s < b.verified_s;
    };
    const Buildable* fastest = nullptr;
    const Buildable* last = nullptr;  // the last one checked
    for (Buildable& b : buildable) {
        if (fastest != nullptr && !fastest->short_of_figures &&
            !(b.estimate_s < fastest->verified_s)) {
            break;
        }
        auto c = check(b.item);
        if (!c) return std::unexpected(c.error());
        last = &b;
        if (!c->refusal.empty()) {
            tries[b.tried].refusal = std::move(c->refusal);
            continue;
        }
        b.verified_s = std::isfinite(c->build_time_s) ? c->build_time_s : b.estimate_s;
        b.short_of_figures = c->short_of_figures;
        if (fastest == nullptr || better(b, *fastest)) fastest = &b;
    }
    if (fastest == nullptr) return nullptr;
    for (const Buildable& b : buildable) {
        if (&b == fastest || !tries[b.tried].refusal.empty()) continue;
        tries[b.tried].refusal =
            b.verified_s >= 0.0
                ? fmt::format(
                      "builds in {:.1f} min, {}", b.verified_s / 60.0,
                      b.short_of_figures ? "short of the figures" : "no shorter than the base kept")
                : fmt::format(
                      "its program takes {:.1f} min before verification, no shorter "
                      "than the {:.1f} min of the base kept",
                      b.estimate_s / 60.0, fastest->verified_s / 60.0);
    }
    if (last != fastest) {
        auto c = check(fastest->item);
        if (!c) return std::unexpected(c.error());
        if (!c->refusal.empty()) {
            return core::fail(core::ErrorCode::kInternal,
                              "the base kept was refused when checked again: " + c->refusal,
                              "orientation search");
        }
    }
    return fastest;
}

}  // namespace

core::Result<OrientedPlan> orient_multiaxis(const mesh::TriangleMesh& part, const Vec3d& given,
                                            OrientPolicy policy, const machine::Profiles& profiles,
                                            const core::Progress* progress,
                                            const ProgramCheck& check,
                                            const std::vector<OrientCandidate>& candidates_of,
                                            const ProgramCheck& estimate) {
    // What `ask` (check or estimate) says of `p`, buildable as planned. A program this machine
    // cannot run along that base (a pose beyond the axis limits, a retract above the Z travel)
    // is a refused try like a plan that cannot be built, and the search goes on; with kGiven it
    // is the answer.
    const auto answer = [&](const ProgramCheck& ask,
                            const Placed& p) -> core::Result<ProgramVerdict> {
        if (!ask) return ProgramVerdict{};
        auto c = ask(p.direction, p.placed, p.planned);
        if (!c && c.error().code == core::ErrorCode::kInvalidInput &&
            policy != OrientPolicy::kGiven) {
            // "move N (layer, region): why: detail" names the move and why.
            const std::string& m = c.error().message;
            const std::size_t colon = m.find(": ");
            return ProgramVerdict{"no program: " + m.substr(0, colon == std::string::npos
                                                                   ? colon
                                                                   : m.find(": ", colon + 2))};
        }
        return c;
    };
    const auto checked = [&](const Placed& p) { return answer(check, p); };
    OrientedPlan out;
    std::optional<Placed> as_given;
    std::optional<core::Error> given_error;  // the given direction could not be planned
    if (tries_given(policy)) {
        auto g = plan_along(part, given, profiles, progress);
        // Ordered only when nothing refuses the plan already: the order of a plan with layers
        // on nothing is never used, and it is the slow part (seconds to minutes on fine tracks).
        if (g && multiaxis_refusal(g->planned, g->bare_plate).empty()) {
            if (auto ok = order(*g, profiles, progress); !ok) return std::unexpected(ok.error());
        }
        // A plan the planner refuses along this direction (a piece nothing can reach) may
        // exist along another: with kFallback the search goes on, and the error stands if
        // nothing builds.
        if (!g &&
            (policy == OrientPolicy::kGiven || g.error().code != core::ErrorCode::kInvalidInput)) {
            return std::unexpected(g.error());
        }
        std::string refusal = g ? multiaxis_refusal(g->planned, g->bare_plate)
                                : "no plan: " + first_clause(g.error());
        if (g && refusal.empty()) {
            auto c = checked(*g);
            if (!c) return std::unexpected(c.error());
            refusal = std::move(c->refusal);
        }
        out.tries.push_back({core::normalized(given), "as given", refusal});
        if (g && (refusal.empty() || policy == OrientPolicy::kGiven)) {
            out.placed = std::move(g->placed);
            out.planned = std::move(g->planned);
            out.bare_plate_layers = std::move(g->bare_plate);
            return out;
        }
        if (g) {
            as_given = std::move(*g);
        } else {
            given_error = g.error();
        }
    }
    // Every other candidate planned, then ranked: no layer on nothing first, then the fewest
    // splits, then the fewest tilts wanted, then the order of orientation_candidates.
    struct Ranked {
        OrientCandidate candidate;
        Placed placed;
    };
    std::vector<OrientCandidate> candidates;
    for (const OrientCandidate& c :
         candidates_of.empty() ? orientation_candidates(part) : candidates_of) {
        if (policy == OrientPolicy::kAuto || !same_direction(c.direction, given)) {
            candidates.push_back(c);
        }
    }
    // Planned side by side (each plan is the same whatever runs beside it), then taken in the
    // candidates' order.
    std::vector<std::optional<core::Result<Placed>>> plans(candidates.size());
    tbb::parallel_for(std::size_t{0}, candidates.size(), [&](std::size_t i) {
        plans[i] = plan_along(part, candidates[i].direction, profiles, progress);
    });
    std::vector<Ranked> ranked;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
        const OrientCandidate& c = candidates[i];
        core::Result<Placed>& p = *plans[i];
        if (!p && p.error().code == core::ErrorCode::kCancelled) return std::unexpected(p.error());
        if (!p) {
            out.tries.push_back({c.direction, c.source, "no plan: " + first_clause(p.error())});
            continue;
        }
        ranked.push_back({c, std::move(*p)});
    }
    std::stable_sort(ranked.begin(), ranked.end(), [](const Ranked& a, const Ranked& b) {
        return orientation_rank(a.placed.planned.plan) < orientation_rank(b.placed.planned.plan);
    });
    std::vector<Buildable> buildable;  // with an estimate: the bases that can be built
    const auto keep = [&](Ranked& r, std::size_t tried) {
        out.placed = std::move(r.placed.placed);
        out.planned = std::move(r.placed.planned);
        out.bare_plate_layers = std::move(r.placed.bare_plate);
        out.chosen = static_cast<int>(tried);
        return std::move(out);
    };
    for (std::size_t i = 0; i < ranked.size(); ++i) {
        Ranked& r = ranked[i];
        std::string refusal = multiaxis_refusal(r.placed.planned, r.placed.bare_plate);
        if (refusal.empty()) {
            if (auto ok = order(r.placed, profiles, progress); !ok) {
                refusal = "no build order: " + first_clause(ok.error());
            } else {
                refusal = multiaxis_refusal(r.placed.planned, r.placed.bare_plate);
            }
        }
        double estimate_s = 0.0;
        if (refusal.empty()) {
            auto c = answer(check && estimate ? estimate : check, r.placed);
            if (!c) return std::unexpected(c.error());
            refusal = std::move(c->refusal);
            estimate_s = c->build_time_s;
        }
        out.tries.push_back({r.candidate.direction, r.candidate.source, refusal});
        if (!refusal.empty()) continue;
        if (!(check && estimate)) return keep(r, out.tries.size() - 1);  // the first that builds
        buildable.push_back({i, out.tries.size() - 1, estimate_s});
    }
    auto kept = keep_shortest(buildable, out.tries,
                              [&](std::size_t i) { return checked(ranked[i].placed); });
    if (!kept) return std::unexpected(kept.error());
    if (*kept) return keep(ranked[(*kept)->item], (*kept)->tried);
    // Nothing builds: the given direction's plan (kAuto: the best ranked) carries the refusal.
    if (as_given) {
        out.placed = std::move(as_given->placed);
        out.planned = std::move(as_given->planned);
        out.bare_plate_layers = std::move(as_given->bare_plate);
        out.chosen = 0;
        return out;
    }
    if (given_error) {
        given_error->message += other_tries(out.tries, 0);
        return std::unexpected(*given_error);
    }
    if (ranked.empty()) {
        return core::fail(
            core::ErrorCode::kInvalidInput,
            "no base orientation of the part can be planned: " +
                (out.tries.empty() ? std::string("no candidates") : out.tries.front().refusal));
    }
    Ranked& best = ranked.front();
    if (!best.placed.planned.order &&
        multiaxis_refusal(best.placed.planned, best.placed.bare_plate).empty()) {
        if (auto ok = order(best.placed, profiles, progress); !ok) {
            return std::unexpected(ok.error());
        }
    }
    for (std::size_t t = 0; t < out.tries.size(); ++t) {
        if (same_direction(out.tries[t].direction, best.candidate.direction)) {
            out.chosen = static_cast<int>(t);
        }
    }
    out.placed = std::move(best.placed.placed);
    out.planned = std::move(best.placed.planned);
    out.bare_plate_layers = std::move(best.placed.bare_plate);
    return out;
}

core::Result<OrientedStack> orient_planar(const mesh::TriangleMesh& part, const Vec3d& given,
                                          OrientPolicy policy, const SliceSettings& settings,
                                          const machine::Profiles& profiles,
                                          const core::Progress* progress, StageTimes* times,
                                          const StackCheck& check,
                                          const std::vector<OrientCandidate>& candidates_of,
                                          const StackCheck& estimate) {
    const plan::PlanSettings ps = plan_settings(profiles.process);
    SliceSettings along_z = settings;
    along_z.direction = {0.0, 0.0, 1.0};
    const auto slice_along = [&](const Vec3d& d, StageTimes* t) -> core::Result<OrientedStack> {
        OrientedStack s;
        s.direction = d;
        s.placed = place_on_plate(part, d, machine::plate_center(profiles.machine));
        // The part's mesh moved onto the plate: welded or repaired, every vertex is used.
        auto stack = slice_part(s.placed, along_z, progress, t, slice::VertexUse::kAllUsed);
        if (!stack) return std::unexpected(stack.error());
        s.stack = std::move(*stack);
        auto check = plan::check_planar_on_footing(s.stack.slices, ps);
        if (!check) return std::unexpected(check.error());
        s.check = std::move(*check);
        return s;
    };
    std::optional<OrientedStack> as_given;
    std::vector<OrientTry> tries;
    if (tries_given(policy)) {
        auto g = slice_along(given, times);
        if (!g) return std::unexpected(g.error());
        std::string refusal = planar_refusal(g->check);
        if (refusal.empty() && check) {
            auto c = check(g->direction, g->placed, g->stack);
            if (!c) return std::unexpected(c.error());
            refusal = std::move(c->refusal);
        }
        tries.push_back({core::normalized(given), "as given", refusal});
        if (refusal.empty() || policy == OrientPolicy::kGiven) {
            g->tries = std::move(tries);
            return std::move(*g);
        }
        as_given = std::move(*g);
    }
    // Of the candidates without overhangs: the fewest tilts wanted, then the first tried (the
    // ranking of plan --orient auto, all of them needing no split), the first `check` keeps.
    std::vector<OrientedStack> passing;
    std::optional<OrientedStack> first;  // kAuto when none passes: the first that slices
    for (const OrientCandidate& c :
         candidates_of.empty() ? orientation_candidates(part) : candidates_of) {
        if (as_given && same_direction(c.direction, given)) continue;
        auto s = slice_along(c.direction, nullptr);
        if (!s && s.error().code == core::ErrorCode::kCancelled) return std::unexpected(s.error());
        if (!s) {
            tries.push_back(
                {c.direction, c.source, "cannot be sliced: " + first_clause(s.error())});
            continue;
        }
        std::string refusal = planar_refusal(s->check);
        tries.push_back({c.direction, c.source, refusal});
        s->chosen = static_cast<int>(tries.size()) - 1;
        if (!refusal.empty()) {
            if (!first) first = std::move(*s);
            continue;
        }
        passing.push_back(std::move(*s));
    }
    std::stable_sort(passing.begin(), passing.end(),
                     [](const OrientedStack& a, const OrientedStack& b) {
                         return a.check.tilts_wanted < b.check.tilts_wanted;
                     });
    std::optional<OrientedStack> best;
    if (check && estimate) {
        // The shortest verified build time among those without overhangs.
        std::vector<Buildable> buildable;
        for (std::size_t i = 0; i < passing.size(); ++i) {
            const OrientedStack& s = passing[i];
            auto e = estimate(s.direction, s.placed, s.stack);
            if (!e) return std::unexpected(e.error());
            const auto tried = static_cast<std::size_t>(s.chosen);
            if (!e->refusal.empty()) {
                tries[tried].refusal = std::move(e->refusal);
                continue;
            }
            buildable.push_back({i, tried, e->build_time_s});
        }
        auto kept = keep_shortest(buildable, tries, [&](std::size_t i) {
            const OrientedStack& s = passing[i];
            return check(s.direction, s.placed, s.stack);
        });
        if (!kept) return std::unexpected(kept.error());
        if (*kept) best = std::move(passing[(*kept)->item]);
    } else {
        for (OrientedStack& s : passing) {
            if (check) {
                auto c = check(s.direction, s.placed, s.stack);
                if (!c) return std::unexpected(c.error());
                if (!c->refusal.empty()) {
                    tries[static_cast<std::size_t>(s.chosen)].refusal = std::move(c->refusal);
                    continue;
                }
            }
            best = std::move(s);
            break;
        }
    }
    OrientedStack out;
    if (best) {
        out = std::move(*best);
    } else if (as_given) {
        out = std::move(*as_given);
        out.chosen = 0;
    } else if (first) {
        out = std::move(*first);
    } else if (!passing.empty()) {
        out = std::move(passing.front());
    } else {
        return core::fail(
            core::ErrorCode::kInvalidInput,
            "no base orientation of the part can be sliced: " +
                (tries.empty() ? std::string("no candidates") : tries.front().refusal));
    }
    out.tries = std::move(tries);
    return out;
}

}  // namespace maxslice::pipeline
