// The planner's driver (docs/method.md sections 3 to 6): the base region, then every region
// in the order it is made (walk.cpp, neighbours.cpp, split.cpp, footing.cpp), then one layer
// per piece and the hierarchy graph (hierarchy_graph.cpp). planner_state.hpp lists the steps.

#include "maxslice/plan/planner.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "free_bodies.hpp"
#include "maxslice/core/units.hpp"
#include "planner_state.hpp"

namespace maxslice::plan {
namespace detail {

int look_back_layers(const PlanSettings& s) {
    return std::max(1, static_cast<int>(std::ceil(s.track_width_mm / s.layer_mm - 1e-9)));
}

AnalysisSettings analysis_settings(const PlanSettings& s) {
    AnalysisSettings a;
    a.track_width_mm = s.track_width_mm;
    a.self_supporting_deg = s.self_supporting_deg;
    a.min_piece_area_mm2 =
        s.min_piece_area_mm2 > 0.0 ? s.min_piece_area_mm2 : s.track_width_mm * s.track_width_mm;
    // The look-back layer lies at most this far below U (every layer at its thickest).
    a.max_allowance_height_mm = (look_back_layers(s) + 1) * s.h_max_mm;
    return a;
}

std::unexpected<core::Error> invalid(const std::string& message, const std::string& context) {
    return core::fail(core::ErrorCode::kInvalidInput, message, context);
}

core::Result<Plan> Planner::run(const core::Vec3d& base_direction) {
    plan_.settings = s_;
    plan_.base_direction = core::normalized(base_direction);
    Region base;
    base.id = 0;
    base.direction = plan_.base_direction;
    base.base = slice::base_frame(mesh_, plan_.base_direction);
    plan_.regions.push_back(base);
    jobs_.push_back({0, {}});
    while (!jobs_.empty()) {
        const RegionJob job = jobs_.front();
        jobs_.pop_front();
        if (progress_ != nullptr && progress_->cancelled()) {
            return core::fail(core::ErrorCode::kCancelled, "cancelled", "planning");
        }
        if (auto ok = plan_region(job); !ok) return std::unexpected(ok.error());
        if (progress_ != nullptr) {
            progress_->report("planning", static_cast<double>(job.region + 1) /
                                              static_cast<double>(plan_.regions.size()));
        }
    }
    tally_footing();
    split_pieces(plan_);
    if (auto ok = build_graph(plan_); !ok) return std::unexpected(ok.error());
    return std::move(plan_);
}

core::Result<void> Planner::plan_region(RegionJob job) {
    const Region& r = plan_.regions[static_cast<std::size_t>(job.region)];
    const auto [lo, hi] = slice::extent_along(mesh_, r.base);
    (void)lo;
    if (!(hi > 0.0)) return {};
    SliceStack slices(mesh_, r.base,
                      slice::uniform_layers(0.0, hi, s_.layer_mm, s_.h_min_mm, s_.h_max_mm));
    std::optional<SliceStack> resumed;
    for (;;) {
        auto next = walk(job, slices, -1);
        for (;;) {
            if (!next) return std::unexpected(next.error());
            if (next->kind == Next::Kind::kMarch) {
                next = march(job.region, next->lower);
            } else if (next->kind == Next::Kind::kResume) {
                // A march met an empty section: the part's top, or a gap with more of the
                // part above (another body, a branch): the region goes on in planar layers
                // from L's top, as a walk does (empty sections skipped; what comes next is
                // analysed against L).
                const int lower = next->lower;
                const slice::PlaneFrame top = plan_.layers[static_cast<std::size_t>(lower)].top;
                const double above = slice::extent_along(mesh_, top).second;
                if (!(above > s_.layer_mm / 2)) return {};
                resumed.emplace(
                    mesh_, top,
                    slice::uniform_layers(0.0, above, s_.layer_mm, s_.h_min_mm, s_.h_max_mm));
                // Its first slice is the one the march found empty; the planar slicer may
                // still find some of the part there (an open mesh's loops are closed
                // differently in the two): no march from L again, or the two would hand L
                // back and forth for ever.
                next = walk({job.region, {lower}}, *resumed, lower);
            } else {
                break;
            }
        }
        if (next->kind == Next::Kind::kDone) return {};
        // kRewalk: split at the region's first layer; its cell changed (not its slices).
    }
}

}  // namespace detail

using detail::invalid;

core::Result<void> validate(const PlanSettings& s) {
    const std::string ctx = "plan settings";
    if (!(s.layer_mm > 0.0) || !std::isfinite(s.layer_mm)) {
        return invalid("layer height must be a positive number of mm", ctx);
    }
    if (!(s.track_width_mm > 0.0) || !std::isfinite(s.track_width_mm)) {
        return invalid("track width must be a positive number of mm", ctx);
    }
    if (!(s.self_supporting_deg >= 0.0 && s.self_supporting_deg < 90.0)) {
        return invalid(fmt::format("self-supporting angle must be in [0, 90) degrees (got {})",
                                   s.self_supporting_deg),
                       ctx);
    }
    if (!(s.alpha_deg >= 0.0 && s.alpha_deg <= s.beta_deg && s.beta_deg < 180.0)) {
        return invalid(fmt::format("alpha and beta must satisfy 0 <= alpha <= beta < 180 degrees "
                                   "(got alpha {}, beta {})",
                                   s.alpha_deg, s.beta_deg),
                       ctx);
    }
    if (!(s.min_piece_area_mm2 >= 0.0) || !std::isfinite(s.min_piece_area_mm2)) {
        return invalid("min_piece_area_mm2 must be 0 or more", ctx);
    }
    if (s.max_regions < 1) return invalid("max_regions must be at least 1", ctx);
    if (!(s.h_min_mm > 0.0 && s.h_min_mm <= s.layer_mm && s.layer_mm <= s.h_max_mm) ||
        !std::isfinite(s.h_max_mm)) {
        return invalid(fmt::format("layer heights must satisfy 0 < h_min <= layer <= h_max (got "
                                   "{}, {}, {})",
                                   s.h_min_mm, s.layer_mm, s.h_max_mm),
                       ctx);
    }
    if (!(s.tilt_trigger_deg >= 0.0 && s.tilt_trigger_deg < 90.0)) {
        return invalid("tilt_trigger_deg must be in [0, 90) degrees", ctx);
    }
    if (s.max_tilt_tries < 0) return invalid("max_tilt_tries must be 0 or more", ctx);
    if (!(s.footing_mm >= 0.0) || !std::isfinite(s.footing_mm)) {
        return invalid("footing_mm must be 0 or more", ctx);
    }
    return {};
}

int Plan::split_count() const {
    return static_cast<int>(
        std::count_if(decisions.begin(), decisions.end(), [](const Decision& d) {
            return d.kind == Decision::Kind::kSplit || d.kind == Decision::Kind::kFloating;
        }));
}

int Plan::tilt_wanted_count() const {
    return static_cast<int>(
        std::count_if(decisions.begin(), decisions.end(),
                      [](const Decision& d) { return d.kind == Decision::Kind::kTiltWanted; }));
}

int Plan::tilted_layer_count() const {
    return static_cast<int>(
        std::count_if(layers.begin(), layers.end(), [](const Layer& l) { return l.tilted; }));
}

double Plan::volume_mm3() const {
    double v = 0.0;
    for (const Layer& l : layers) v += l.area_mm2 * l.thickness_mean_mm;
    return v;
}

core::Result<Plan> plan_part(const mesh::TriangleMesh& mesh, const core::Vec3d& base_direction,
                             const PlanSettings& settings, const core::Progress* progress) {
    if (auto ok = validate(settings); !ok) return std::unexpected(ok.error());
    if (mesh.triangles.empty()) return invalid("the mesh has no triangles", "planning");
    // Along any direction the part is at most its box's diagonal tall.
    const core::Box3d box = mesh::bounding_box(mesh);
    if (auto ok = slice::check_layer_count(core::norm(box.max - box.min), settings.h_min_mm,
                                           "process.h_min_mm, --layer");
        !ok) {
        return std::unexpected(ok.error());
    }
    if (!core::is_finite(base_direction) || core::norm(base_direction) <= 0.0) {
        return invalid("the base direction must be a non-zero finite vector", "planning");
    }
    // Bodies that float free of the rest and of the plate are left out (decision 0036).
    detail::FreeBodies free = settings.leave_out_free_bodies
                                  ? detail::free_bodies(mesh, base_direction, settings)
                                  : detail::FreeBodies{};
    if (free.bodies.empty()) return detail::Planner(mesh, settings, progress).run(base_direction);
    auto p = detail::Planner(free.rest, settings, progress).run(base_direction);
    if (p) p->free_bodies = std::move(free.bodies);
    return p;
}

core::Vec3d centroid_of(const Layer& layer) {
    const geom2d::Paths2 paths = layer.wires.paths();
    if (geom2d::signed_area_mm2(paths) <= 0.0) return layer.plane.origin;
    const geom2d::Centroid2 c = geom2d::centroid_um(paths);
    return layer.plane.origin + layer.plane.u * (c.x / core::kMicronsPerMm) +
           layer.plane.v * (c.y / core::kMicronsPerMm);
}

}  // namespace maxslice::plan
