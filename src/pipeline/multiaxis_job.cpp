// The moves of a multi-axis plan in build order (METHOD.md sections 9 to 11).

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "maxslice/machine/program_builder.hpp"
#include "maxslice/machine/speed_law.hpp"
#include "maxslice/pipeline/program_job.hpp"
#include "sideways_support.hpp"

namespace maxslice::pipeline {
namespace {

using core::Vec3d;

/// A laid height this far from the planned one counts as clamped (mm).
constexpr double kClampToleranceMm = 1e-3;
/// Height above the part's top for a travel between sections (mm), at least.
constexpr double kSectionTravelMarginMm = 2.0;

// What a layer's tracks need: where its top is, which way it is built, and the plane its
// bottom lies on when it is a wedge.
struct LayerFrame {
    const plan::Layer* layer = nullptr;
    Vec3d direction;
    const slice::PlaneFrame* bottom = nullptr;  // wedge layers only

    // The tool tip for a point of the layer's wires: the point on the layer's top plane
    // along the build direction.
    [[nodiscard]] Vec3d tip(const geom2d::Point2& q) const {
        const Vec3d x = layer->plane.to_3d(q);
        return x - direction * layer->top.height(x);
    }
    // The local thickness under a tip: to the bottom plane along the build direction.
    [[nodiscard]] double thickness(const Vec3d& tip) const {
        if (bottom == nullptr) return layer->span.thickness();
        return bottom->height(tip) / core::dot(direction, bottom->normal);
    }
};

LayerFrame frame_of(const plan::Plan& plan, const plan::Layer& layer) {
    LayerFrame f;
    f.layer = &layer;
    f.direction = layer.top.normal;
    if (!layer.tilted) return f;
    // A wedge lies on the top of the layer below it in its region (the march's lower layer).
    for (const int p : layer.parents) {
        const plan::Layer& parent = plan.layers[static_cast<std::size_t>(p)];
        if (parent.region == layer.region && parent.index_in_region + 1 == layer.index_in_region) {
            f.bottom = &parent.top;
            break;
        }
    }
    return f;
}

// Parents built along a direction more than this far from the layer's (degrees) stand
// sideways under it: their beads carry it only where they reach its bottom plane.
constexpr double kSupportMaxTurnDeg = 10.0;
// Track centres may run this many half tracks beyond the parents' track centres: a bead
// is carried while it reaches the beads below (the planner ignores overhangs narrower than
// a track, METHOD.md section 3; the verifier asks for material within half a track and a
// voxel of a bead's centre), kept a little inside that.
constexpr double kSupportReachHalves = 1.9;
// A sideways bead carries the layer where it lies from kSideGapShare to kSideBandShare of
// the layer's thickness below the layer's bottom plane, and the layer's track centres within
// half a track of there: the verifier looks for earlier material from a quarter of a voxel to
// 2.25 voxels below a bead's bottom (0.04 to 0.34 mm at its 0.15 mm voxels) and within half a
// track and a voxel of its centre.
constexpr double kSideBandShare = 0.5;
constexpr double kSideGapShare = 0.15;

// A layer's track centres (its frame's tips) projected into another layer's plane frame (u, v),
// micrometres.
void project_tracks(const LayerFrame& frame, const path::LayerToolpath& tp, const plan::Layer& onto,
                    geom2d::Paths2& out) {
    for (const path::Stroke& s : tp.strokes) {
        geom2d::Path2& line = out.emplace_back();
        line.reserve(s.points.size());
        for (const geom2d::Point2& q : s.points) {
            const Vec3d d = frame.tip(q) - onto.plane.origin;
            line.push_back({core::mm_to_um(core::dot(d, onto.plane.u)),
                            core::mm_to_um(core::dot(d, onto.plane.v))});
        }
    }
}

// Where a layer's track centres are carried: its parents' tracks lifted onto their tops,
// projected along the layer's direction into its plane frame and swept by the reach (a parent
// built along another direction: where its beads lie just below the layer's bottom plane, grown
// by half a track); nullopt when the layer stands on the plate, or is a wedge on sideways
// parents.
std::optional<geom2d::Paths2> support_of(const plan::Plan& plan, const plan::Layer& layer,
                                         const std::vector<const path::LayerToolpath*>& done,
                                         std::int64_t reach_um, double half_track_mm) {
    if (layer.on_plate || layer.parents.empty()) return std::nullopt;
    const double cos_max = std::cos(kSupportMaxTurnDeg * std::numbers::pi / 180.0);
    geom2d::Paths2 lines;
    geom2d::Paths2 side_cuts;
    for (const int p : layer.parents) {
        const plan::Layer& parent = plan.layers[static_cast<std::size_t>(p)];
        const path::LayerToolpath* tp = done[static_cast<std::size_t>(p)];
        if (tp == nullptr) return std::nullopt;
        const LayerFrame frame = frame_of(plan, parent);
        if (core::dot(parent.top.normal, layer.top.normal) < cos_max) {
            if (layer.tilted) return std::nullopt;
            detail::SidewaysParent side;
            side.direction = frame.direction;
            side.thickness_mm = parent.span.thickness();
            side.half_track_mm = half_track_mm;
            for (const path::Stroke& s : tp->strokes) {
                std::vector<Vec3d>& tips = side.tips.emplace_back();
                tips.reserve(s.points.size());
                for (const geom2d::Point2& q : s.points) tips.push_back(frame.tip(q));
            }
            const slice::PlaneFrame bottom =
                layer.plane.shifted(layer.span.bottom - layer.span.cut);
            for (geom2d::Path2& q : detail::sideways_support(
                     bottom, layer.plane, side, kSideBandShare * layer.span.thickness(),
                     kSideGapShare * layer.span.thickness())) {
                side_cuts.push_back(std::move(q));
            }
            continue;
        }
        project_tracks(frame, *tp, layer, lines);
    }
    if (side_cuts.empty()) return geom2d::sweep_polylines(lines, reach_um);
    // The layer's track centres over the sideways beads' material below its bottom plane or
    // within half a track of it.
    geom2d::Paths2 support = geom2d::sweep_polylines(lines, reach_um);
    for (geom2d::Path2& q : side_cuts) q.push_back(q.front());  // closed outlines
    for (geom2d::Path2& q : geom2d::sweep_polylines(side_cuts, core::mm_to_um(half_track_mm))) {
        support.push_back(std::move(q));
    }
    for (geom2d::Path2& q : side_cuts) {
        q.pop_back();
        if (q.size() >= 3) support.push_back(std::move(q));
    }
    return geom2d::union_of(support);
}

// Lengths and coverage of a toolpath whose strokes changed, measured again.
void measure(path::LayerToolpath& tp, const geom2d::WireTree& wires, std::int64_t half_um) {
    using geom2d::length_um;
    geom2d::Paths2 tracks;
    double deposit = 0.0;
    double travel = 0.0;
    for (std::size_t i = 0; i < tp.strokes.size(); ++i) {
        const geom2d::Path2& pts = tp.strokes[i].points;
        tracks.push_back(pts);
        deposit += length_um(pts);
        if (i > 0) travel += length_um({tp.strokes[i - 1].points.back(), pts.front()});
    }
    tp.deposit_length_mm = deposit / core::kMicronsPerMm;
    tp.travel_length_mm = travel / core::kMicronsPerMm;
    tp.uncovered_mm2 = geom2d::uncovered_area_mm2(wires.paths(), tracks, half_um,
                                                  std::max<std::int64_t>(1, half_um / 8));
}

// A stroke whose clipped pieces are this much shorter than itself (um) is kept whole.
constexpr double kSameLengthUm = 1.0;

// Cuts a layer's strokes to where the beads below carry them; returns the length removed
// (mm). Pieces shorter than min_um are dropped. Lengths and coverage of the toolpath are
// measured again when anything was cut.
double trim_to_support(path::LayerToolpath& tp, const geom2d::Paths2& support,
                       const geom2d::WireTree& wires, std::int64_t half_um, std::int64_t min_um) {
    using geom2d::length_um;
    std::vector<path::Stroke> kept;
    double removed = 0.0;
    for (path::Stroke& s : tp.strokes) {
        geom2d::Paths2 pieces = geom2d::clip_polylines({s.points}, support);
        double inside = 0.0;
        for (const geom2d::Path2& piece : pieces) inside += length_um(piece);
        const double full = length_um(s.points);
        if (full - inside < kSameLengthUm) {  // all of it (the clip may add points)
            kept.push_back(std::move(s));
            continue;
        }
        inside = 0.0;
        for (geom2d::Path2& piece : pieces) {
            const double l = length_um(piece);
            if (piece.size() < 2 || l < static_cast<double>(min_um)) continue;
            inside += l;
            kept.push_back({path::StrokeKind::kFill, std::move(piece)});
        }
        removed += full - inside;
    }
    tp.strokes = std::move(kept);
    if (removed <= 0.0) return 0.0;
    measure(tp, wires, half_um);
    return removed / core::kMicronsPerMm;
}

// The narrow starts' beads may overhang their islands by at most this share of the volume of
// the layers built (decision 0049).
constexpr double kNarrowOverhangShare = 0.01;

// A feature that starts narrower than a track (the edge of a slanted rib, the tip of a wedge
// standing on a face, a thin fin under a wider one) gets no track in its first layers; every
// layer above it would then rest on nothing and be cut away below, the whole feature with it.
// So, from the last layer built down, an island of a layer standing on the plate or on parents
// (a layer on nothing is the plan's to judge) where no contour fits gets one track along its
// middle when tracks of a layer above, built along the same direction, come within the
// support's reach of it (decision 0049). Its beads overhang the narrow section: material the
// machining takes off, as the stock.
void lay_narrow_starts(const plan::Plan& plan, const std::vector<int>& order,
                       const path::PathSettings& settings,
                       std::vector<path::LayerToolpath>& toolpaths) {
    const double cos_max = std::cos(kSupportMaxTurnDeg * std::numbers::pi / 180.0);
    const std::int64_t half_um = core::mm_to_um(settings.track_width_mm / 2.0);
    const std::int64_t reach_um =
        core::mm_to_um(kSupportReachHalves * settings.track_width_mm / 2.0);
    std::vector<const path::LayerToolpath*> by_id(plan.layers.size(), nullptr);
    for (std::size_t i = 0; i < order.size(); ++i)
        by_id[static_cast<std::size_t>(order[i])] = &toolpaths[i];
    std::vector<std::pair<std::size_t, path::LayerToolpath>> before;  // of the layers given one
    double volume_mm3 = 0.0;                                          // of every layer built
    double overhang_mm3 = 0.0;  // of the tracks laid here, outside their islands
    for (std::size_t i = order.size(); i-- > 0;) {
        const plan::Layer& layer = plan.layers[static_cast<std::size_t>(order[i])];
        path::LayerToolpath& tp = toolpaths[i];
        volume_mm3 += layer.area_mm2 * layer.span.thickness();
        if (tp.uncovered_mm2 <= 0.0 || (!layer.on_plate && layer.parents.empty())) continue;
        geom2d::Paths2 above;
        for (const int c : layer.children) {
            const plan::Layer& child = plan.layers[static_cast<std::size_t>(c)];
            const path::LayerToolpath* ctp = by_id[static_cast<std::size_t>(c)];
            if (ctp == nullptr || core::dot(child.top.normal, layer.top.normal) < cos_max) continue;
            project_tracks(frame_of(plan, child), *ctp, layer, above);
        }
        if (above.empty()) continue;
        auto narrow = path::plan_narrow_layer(layer.wires, settings, geom2d::Point2{});
        if (!narrow || narrow->strokes.empty()) continue;
        const geom2d::Paths2 reach = geom2d::sweep_polylines(above, reach_um);
        std::erase_if(narrow->strokes, [&](const path::Stroke& s) {
            return geom2d::clip_polylines({s.points}, reach).empty();
        });
        if (narrow->strokes.empty()) continue;
        path::LayerToolpath had = tp;
        for (path::Stroke& s : narrow->strokes) tp.strokes.push_back(std::move(s));
        measure(tp, layer.wires, half_um);
        const double bead_mm2 =
            (tp.deposit_length_mm - had.deposit_length_mm) * settings.track_width_mm;
        const double island_mm2 = had.uncovered_mm2 - tp.uncovered_mm2;
        overhang_mm3 += std::max(0.0, bead_mm2 - island_mm2) * layer.span.thickness();
        before.emplace_back(i, std::move(had));
    }
    // Where those beads would overhang more than a small share of the whole part, the part is
    // not one with narrow starts but one narrower than the track all over (a part in other
    // units): nothing is laid there, as before.
    if (overhang_mm3 > kNarrowOverhangShare * volume_mm3) {
        for (auto& [i, had] : before) toolpaths[i] = std::move(had);
    }
}

double highest_along(const mesh::TriangleMesh& mesh, const Vec3d& d) {
    double h = -std::numeric_limits<double>::infinity();
    for (const auto& v : mesh.vertices) h = std::max(h, core::dot(v, d));
    return h;
}

class MoveBuilder {
public:
    MoveBuilder(const plan::Plan& plan, const mesh::TriangleMesh& placed,
                const machine::Profiles& profiles, MultiAxisProgram& out)
        : plan_(plan),
          placed_(placed),
          process_(profiles.process),
          law_(machine::SpeedLaw::of(profiles.process)),
          out_(out) {
        const auto& nozzle = profiles.machine.nozzle;
        margin_mm_ = std::max(kSectionTravelMarginMm, nozzle ? nozzle->clearance_mm : 0.0);
        out_.thickness.thickness_min_mm = std::numeric_limits<double>::infinity();
        out_.thickness.thickness_max_mm = 0.0;
    }

    void layer(const plan::Layer& layer, const path::LayerToolpath& tp, int section) {
        if (tp.strokes.empty()) return;
        const LayerFrame f = frame_of(plan_, layer);
        const Vec3d first = f.tip(tp.strokes.front().points.front());
        travel_to_layer(first, f.direction, layer, section);
        for (const path::Stroke& stroke : tp.strokes) {
            points_.clear();
            feeds_.clear();
            const double piece = f.bottom ? 0.5 * process_.track_width_mm : 0.0;
            Vec3d prev = f.tip(stroke.points.front());
            points_.push_back(prev);
            for (std::size_t i = 1; i < stroke.points.size(); ++i) {
                const Vec3d next = f.tip(stroke.points[i]);
                // Wedge tracks in pieces of at most half a track, each with its own feed.
                const double len = core::norm(next - prev);
                const int n =
                    piece > 0.0 ? std::max(1, static_cast<int>(std::ceil(len / piece))) : 1;
                for (int k = 1; k <= n; ++k) {
                    const Vec3d a = prev + (next - prev) * (static_cast<double>(k - 1) / n);
                    const Vec3d b =
                        k == n ? next : prev + (next - prev) * (static_cast<double>(k) / n);
                    feeds_.push_back(feed_for(f, layer, (a + b) * 0.5));
                    points_.push_back(b);
                }
                prev = next;
            }
            machine::append_wire(out_.program, points_, feeds_, process_, layer.id, layer.region,
                                 f.direction);
        }
        last_section_ = section;
        last_direction_ = f.direction;
    }

private:
    double feed_for(const LayerFrame& f, const plan::Layer& layer, const Vec3d& at) {
        const double planned = f.thickness(at);
        const double feed = law_.feed_mm_min(planned);
        const double error = std::abs(law_.height_mm(feed) - planned);
        ThicknessReport& t = out_.thickness;
        ++t.segments;
        t.thickness_min_mm = std::min(t.thickness_min_mm, planned);
        t.thickness_max_mm = std::max(t.thickness_max_mm, planned);
        if (error > kClampToleranceMm) ++t.clamped;
        if (error > t.worst_error_mm) {
            t.worst_error_mm = error;
            t.worst_layer = layer.id;
            t.worst_at = at;
        }
        return feed;
    }

    const machine::Move* last_position() const {
        const auto& moves = out_.program.moves;
        for (auto it = moves.rbegin(); it != moves.rend(); ++it) {
            if (it->kind == machine::MoveKind::kTravel || it->kind == machine::MoveKind::kDeposit)
                return &*it;
        }
        return nullptr;
    }

    void travel(const Vec3d& to, const Vec3d& d, const plan::Layer& layer) {
        machine::append_travel(out_.program, to, process_, layer.id, layer.region, d);
    }

    // From the last layer's end to this layer's first tip. Same section: rise along the
    // build direction to the new top, then across (the wire's own travel). Another section
    // of the same direction: up above the part's top, across, down. A new direction: the
    // writer's re-orientation (retract, turn, cross, approach) takes the head there.
    void travel_to_layer(const Vec3d& first, const Vec3d& d, const plan::Layer& layer,
                         int section) {
        const machine::Move* last = last_position();
        if (last == nullptr) return;
        const Vec3d from = last->position;
        if (core::dot(last_direction_, d) < 1.0 - 1e-12) return;
        if (section == last_section_) {
            const double rise = core::dot(first - from, d);
            if (rise > 0.0) travel(from + d * rise, d, layer);
            return;
        }
        ++out_.section_changes;
        if (core::norm(d - top_direction_) > 0.0) {  // once per direction, not per section
            top_direction_ = d;
            top_mm_ = highest_along(placed_, d);
        }
        const double top = top_mm_ + margin_mm_;
        const double up_from = top - core::dot(from, d);
        const double up_to = top - core::dot(first, d);
        if (up_from > 0.0) travel(from + d * up_from, d, layer);
        if (up_to > 0.0) travel(first + d * up_to, d, layer);
    }

    const plan::Plan& plan_;
    const mesh::TriangleMesh& placed_;
    const machine::ProcessProfile& process_;
    const machine::SpeedLaw law_;
    MultiAxisProgram& out_;
    double margin_mm_ = kSectionTravelMarginMm;
    int last_section_ = -1;
    Vec3d last_direction_{0.0, 0.0, 1.0};
    Vec3d top_direction_{};  // the direction top_mm_ was measured along (zero: none yet)
    double top_mm_ = 0.0;    // the part's highest point along it
    std::vector<Vec3d> points_;
    std::vector<double> feeds_;
};

}  // namespace

core::Result<MultiAxisProgram> plan_multiaxis_program(const plan::Plan& plan,
                                                      const plan::BuildOrder& order,
                                                      const mesh::TriangleMesh& placed,
                                                      const machine::Profiles& profiles,
                                                      const std::string& part_name,
                                                      const core::Progress* progress) {
    if (!order.complete()) {
        const plan::Conflict& c = order.conflicts.front();
        return core::fail(core::ErrorCode::kInvalidInput,
                          fmt::format("no collision-free build order: {} ({} conflicts)", c.reason,
                                      order.conflicts.size()),
                          "part " + part_name);
    }
    const path::PathSettings settings = path_settings(profiles.process);
    if (auto ok = path::validate(settings); !ok) return std::unexpected(ok.error());
    MultiAxisProgram out;
    out.order = order.order;
    out.program.part_name = part_name;
    std::vector<const geom2d::WireTree*> regions;
    regions.reserve(out.order.size());
    for (const int id : out.order)
        regions.push_back(&plan.layers[static_cast<std::size_t>(id)].wires);
    auto planned = path::plan_layers(regions, settings, geom2d::Point2{}, progress);
    if (!planned) return std::unexpected(planned.error());
    out.toolpaths = std::move(*planned);

    lay_narrow_starts(plan, out.order, settings, out.toolpaths);

    // Beads are laid only where the layer below carries them: a feature the tracks of one
    // layer leave bare (narrower than the track) may get a track a layer higher, where it is
    // a little wider; that track would rest on nothing.
    const std::int64_t half_um = core::mm_to_um(settings.track_width_mm / 2.0);
    const std::int64_t reach_um =
        core::mm_to_um(kSupportReachHalves * settings.track_width_mm / 2.0);
    std::vector<const path::LayerToolpath*> done(plan.layers.size(), nullptr);
    for (std::size_t i = 0; i < out.order.size(); ++i) {
        const plan::Layer& layer = plan.layers[static_cast<std::size_t>(out.order[i])];
        if (const auto support =
                support_of(plan, layer, done, reach_um, settings.track_width_mm / 2.0)) {
            const double cut = trim_to_support(out.toolpaths[i], *support, layer.wires, half_um,
                                               core::mm_to_um(settings.track_width_mm / 4.0));
            if (cut > 0.0) {
                out.trimmed_mm += cut;
                ++out.layers_trimmed;
            }
        }
        done[static_cast<std::size_t>(layer.id)] = &out.toolpaths[i];
    }

    MoveBuilder builder(plan, placed, profiles, out);
    for (std::size_t i = 0; i < out.order.size(); ++i) {
        const plan::Layer& layer = plan.layers[static_cast<std::size_t>(out.order[i])];
        const path::LayerToolpath& tp = out.toolpaths[i];
        out.region_area_mm2 += layer.area_mm2;
        out.uncovered_mm2 += tp.uncovered_mm2;
        if (tp.uncovered_mm2 > 0.01 * layer.area_mm2) ++out.layers_with_uncovered;
        builder.layer(layer, tp, order.section_of[static_cast<std::size_t>(layer.id)]);
    }
    if (out.thickness.segments == 0) out.thickness.thickness_min_mm = 0.0;
    auto summary = machine::summarize(out.program, profiles.process);
    if (!summary) return std::unexpected(summary.error());
    out.summary = *summary;
    return out;
}

}  // namespace maxslice::pipeline
