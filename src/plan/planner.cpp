#include "maxslice/plan/planner.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <deque>
#include <limits>
#include <numbers>
#include <optional>
#include <queue>
#include <string>

#include <tbb/parallel_for.h>

#include "cell.hpp"
#include "maxslice/core/units.hpp"
#include "maxslice/slice/slicer.hpp"
#include "section_index.hpp"

namespace maxslice::plan {
namespace {

using geom2d::Paths2;

// Tilts smaller than this (rad) are not made.
constexpr double kMinTiltRad = 0.5 * std::numbers::pi / 180.0;
// A plan with more layers is refused (a runaway march).
constexpr std::size_t kMaxLayers = 1'000'000;

// The centroid chain is followed only while sections keep their area within this share of
// the section a track's height below.
constexpr double kTiltAreaChange = 0.1;
/// Rounding room (mm) when following grounded islands up through planar layers.
constexpr double kGroundSlackMm = 0.02;
/// Rounding room (mm) when comparing a layer's top with the footing's height.
constexpr double kFootingSlackMm = 1e-6;

// The look-back distance in layers: as many as make a track's height (at least one).
int look_back_layers(const PlanSettings& s) {
    return std::max(1, static_cast<int>(std::ceil(s.track_width_mm / s.layer_mm - 1e-9)));
}

// Splits and overhangs on a layer that ends (or the one above starts) at most this high above
// the plate are where the footing is tried (decision 0017): the footing and a look-back above.
double footing_zone_mm(const PlanSettings& s) {
    return s.footing_mm + look_back_layers(s) * s.layer_mm + kFootingSlackMm;
}

// The neighbour analysis the planner's walk and the planar check both run.
AnalysisSettings analysis_settings(const PlanSettings& s) {
    AnalysisSettings a;
    a.track_width_mm = s.track_width_mm;
    a.self_supporting_deg = s.self_supporting_deg;
    a.min_piece_area_mm2 =
        s.min_piece_area_mm2 > 0.0 ? s.min_piece_area_mm2 : s.track_width_mm * s.track_width_mm;
    return a;
}

bool steady_area(double area, double below) {
    return std::abs(area - below) <= kTiltAreaChange * below;
}

// The area centroid of a section lifted to 3D (mm).
core::Vec3d centroid3(const geom2d::Paths2& region, const slice::PlaneFrame& f) {
    const geom2d::Centroid2 c = geom2d::centroid_um(region);
    return f.origin + f.u * (c.x / core::kMicronsPerMm) + f.v * (c.y / core::kMicronsPerMm);
}

// An axis-aligned box in the part frame (mm).
struct Box3 {
    double lo[3] = {1e300, 1e300, 1e300};
    double hi[3] = {-1e300, -1e300, -1e300};
};

Box3 box_of(const Layer& l) {
    Box3 b;
    for (const geom2d::WireNode& n : l.wires.nodes) {
        for (const geom2d::Point2& p : n.wire) {
            const core::Vec3d x = l.plane.to_3d(p);
            const double c[3] = {x.x, x.y, x.z};
            for (int k = 0; k < 3; ++k) {
                b.lo[k] = std::min(b.lo[k], c[k]);
                b.hi[k] = std::max(b.hi[k], c[k]);
            }
        }
    }
    return b;
}

// An axis-aligned box in a plane frame (um).
struct Box2 {
    geom2d::Point2 lo{std::numeric_limits<std::int64_t>::max(),
                      std::numeric_limits<std::int64_t>::max()};
    geom2d::Point2 hi{std::numeric_limits<std::int64_t>::min(),
                      std::numeric_limits<std::int64_t>::min()};
};

Box2 box2_of(const geom2d::Paths2& paths) {
    Box2 b;
    for (const geom2d::Path2& path : paths) {
        for (const geom2d::Point2& p : path) {
            b.lo = {std::min(b.lo.x, p.x), std::min(b.lo.y, p.y)};
            b.hi = {std::max(b.hi.x, p.x), std::max(b.hi.y, p.y)};
        }
    }
    return b;
}

// Rewrites the layer names "L<id>" in a reason with new ids.
template <class Renumber>
std::string renumber_layer_names(const std::string& text, const Renumber& renumber) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size();) {
        const bool word_start = i == 0 || !std::isalnum(static_cast<unsigned char>(text[i - 1]));
        std::size_t j = i + 1;
        while (j < text.size() && std::isdigit(static_cast<unsigned char>(text[j])) != 0) ++j;
        if (text[i] == 'L' && word_start && j > i + 1 &&
            (j == text.size() || !std::isalnum(static_cast<unsigned char>(text[j])))) {
            out += 'L';
            out += std::to_string(renumber(std::stoi(text.substr(i + 1, j - i - 1))));
            i = j;
        } else {
            out += text[i++];
        }
    }
    return out;
}

// A sideways direction N_s shorter than this (V_i almost along N_b) cannot be normalised.
constexpr double kMinSidewaysNorm = 1e-6;
// A first layer rests on a layer of another region when their footprints on its base plane
// overlap by at least this share of a track width squared.
constexpr double kContactAreaShare = 0.05;
// A layer whose wires lie this far (mm) outside the strip behind a base plane has nothing in
// it: far beyond the rounding of the strip's trace to micrometres.
constexpr double kStripSlackMm = 0.01;
// Slack (um) of the box test before an overlap is measured: beyond the rounding of offsets.
constexpr std::int64_t kNearSlackUm = 10;

std::unexpected<core::Error> invalid(const std::string& message, const std::string& context) {
    return core::fail(core::ErrorCode::kInvalidInput, message, context);
}

// The lower layer a region's first layer is analysed against (a continuation region's
// first layer stands on its parent's last layer).
struct Seed {
    int layer = -1;
};

struct RegionJob {
    int region = 0;
    Seed seed;
};

// What a walk or a march of a region asks for next. plan_region runs them in a loop (they
// used to call each other: a bunny scan nested thousands of calls deep and overflowed the
// stack).
struct Next {
    enum class Kind {
        kDone,    // walked to the top, or split after some layers
        kRewalk,  // split at the region's first layer: its cell changed, walk it again
        kMarch,   // tilted layers from layer `lower` up
        kResume,  // planar layers again from layer `lower`'s top
    };
    Kind kind = Kind::kDone;
    int lower = -1;
};

Next done_or_rewalk(bool rewalk) {
    return {rewalk ? Next::Kind::kRewalk : Next::Kind::kDone};
}

// The footing (decision 0017) from section `first` of a stack of n parallel sections (in-plane
// axes shared), whose layers' tops lie at top(j) above the plate: for each section from first
// whose top lies within footing_mm, the union of it and every later section up to and with
// the first whose top lies above that height, or up to an empty section (a gap). Each such
// layer then carries the next, and the first layer above the footing stands on it whole.
template <class Section, class Top>
core::Result<std::vector<Paths2>> footing_pads(std::size_t first, std::size_t n, double footing_mm,
                                               Section&& section, Top&& top) {
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

// A region's uniform slices, cut in batches as the walk asks for them: a walk that stops
// at a split (most do, in parts that split) does not pay for the slices above it. Each
// plane's section depends only on its own height (slice::slice_mesh cuts planes
// independently), so batches give the slices one call for all of them would.
class SliceStack {
public:
    SliceStack(const mesh::TriangleMesh& mesh, const slice::PlaneFrame& base,
               std::vector<slice::LayerSpan> spans)
        : mesh_(mesh), base_(base), spans_(std::move(spans)) {}

    [[nodiscard]] std::size_t size() const { return spans_.size(); }

    // Slice i (index within the whole stack); valid as long as the stack.
    core::Result<const slice::Slice*> at(std::size_t i) {
        while (i >= slices_.size()) {
            const std::size_t begin = slices_.size();
            const std::size_t end = std::min(spans_.size(), begin + batch_);
            batch_ = std::min(kMaxBatch, 2 * batch_);
            auto batch =
                slice::slice_mesh(mesh_, base_, std::span(spans_).subspan(begin, end - begin));
            if (!batch) return std::unexpected(batch.error());
            for (slice::Slice& sl : *batch) {
                sl.index = static_cast<int>(slices_.size());
                slices_.push_back(std::move(sl));
            }
        }
        return &slices_[i];
    }

private:
    // The first batch is small (many walks stop within it); batches double up to this.
    static constexpr std::size_t kMaxBatch = 128;
    const mesh::TriangleMesh& mesh_;
    slice::PlaneFrame base_;
    std::vector<slice::LayerSpan> spans_;
    std::deque<slice::Slice> slices_;  // a deque: later batches move no earlier slice
    std::size_t batch_ = 8;
};

class Planner {
public:
    Planner(const mesh::TriangleMesh& mesh, const PlanSettings& settings,
            const core::Progress* progress)
        : mesh_(mesh),
          s_(settings),
          progress_(progress),
          analysis_(analysis_settings(settings)),
          look_back_(look_back_layers(settings)) {}

    core::Result<Plan> run(const core::Vec3d& base_direction) {
        plan_.settings = s_;
        plan_.base_direction = core::normalized(base_direction);
        Region base;
        base.id = 0;
        base.direction = plan_.base_direction;
        base.base = slice::base_frame(mesh_, plan_.base_direction);
        base.reason = "base region: the part stands on the plate along the base direction";
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
        for (std::size_t id = 0; id < footing_added_.size() && id < plan_.layers.size(); ++id) {
            if (footing_added_[id] < 0.0) continue;
            ++plan_.footing.layers;
            plan_.footing.height_mm = std::max(plan_.footing.height_mm, plan_.layers[id].span.top);
            plan_.footing.added_mm3 += footing_added_[id];
        }
        split_pieces();
        if (auto ok = build_graph(); !ok) return std::unexpected(ok.error());
        return std::move(plan_);
    }

private:
    // Slices one region and walks up its layers; stops at the first split (the rest goes to
    // the new regions).
    core::Result<void> plan_region(RegionJob job) {
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
                    // A march met an empty section: the part's top, or a gap with more of
                    // the part above (another body, a branch): the region goes on in planar
                    // layers from L's top, as a walk does (empty sections skipped; what
                    // comes next is analysed against L).
                    const int lower = next->lower;
                    const slice::PlaneFrame top = plan_.layers[static_cast<std::size_t>(lower)].top;
                    const double above = slice::extent_along(mesh_, top).second;
                    if (!(above > s_.layer_mm / 2)) return {};
                    resumed.emplace(
                        mesh_, top,
                        slice::uniform_layers(0.0, above, s_.layer_mm, s_.h_min_mm, s_.h_max_mm));
                    // Its first slice is the one the march found empty; the planar slicer
                    // may still find some of the part there (an open mesh's loops are
                    // closed differently in the two): no march from L again, or the two
                    // would hand L back and forth for ever.
                    next = walk({job.region, {lower}}, *resumed, lower);
                } else {
                    break;
                }
            }
            if (next->kind == Next::Kind::kDone) return {};
            // kRewalk: split at the region's first layer; its cell changed (not its slices).
        }
    }

    // Walks a region's slices (no tilt towards the centroid chain from layer
    // `no_march_from`). Ends at the top, at a split, or where a march takes over.
    core::Result<Next> walk(const RegionJob& job, SliceStack& slices, int no_march_from) {
        const int rid = job.region;
        int lower = job.seed.layer;  // L: a layer id, or -1
        bool gap = false;            // empty sections since L
        std::vector<Paths2> pads;    // the footing's layers, from slice pads_from up
        std::size_t pads_from = std::numeric_limits<std::size_t>::max();
        for (std::size_t i = 0; i < slices.size(); ++i) {
            auto next = slices.at(i);
            if (!next) return std::unexpected(next.error());
            const slice::Slice& s = **next;
            Region& r = plan_.regions[static_cast<std::size_t>(rid)];
            Paths2 clipped = detail::clip_to_cell(s.wires.paths(), r.cell, s.plane);
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
                            return detail::clip_to_cell((*sj)->wires.paths(), r.cell, (*sj)->plane);
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
            if (lower >= 0 && lower != no_march_from && s_.tilt_trigger_deg > 0.0) {
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
                    dec.reason = fmt::format(
                        "above layer L{}: the chain of centroids leans {:.1f} deg from the build "
                        "direction (> {:.0f}): tilted 3D layers follow it from here",
                        lower, angle_deg(d, lr.plane.normal), s_.tilt_trigger_deg);
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
    core::Result<Paths2> section(int rid, const slice::PlaneFrame& plane, double thickness) {
        if (!sections_) sections_.emplace(mesh_);
        auto cut = sections_->section(plane, thickness);
        if (!cut) return std::unexpected(cut.error());
        const Region& r = plan_.regions[static_cast<std::size_t>(rid)];
        return detail::clip_to_cell(*cut, r.cell, plane);
    }

    // Splits for U above `lower` (and above the look-back layer): nullopt when U may be
    // added, else the walk's result after the split.
    core::Result<std::optional<bool>> check_splits(int rid, int lower, const Paths2& u,
                                                   const slice::Slice& s) {
        std::vector<int> refs{lower};
        const Region& rr = plan_.regions[static_cast<std::size_t>(rid)];
        const auto k = static_cast<std::size_t>(look_back_);
        if (k > 1 && rr.layers.size() >= k) refs.push_back(rr.layers[rr.layers.size() - k]);
        for (const int ref : refs) {
            const Layer& l = plan_.layers[static_cast<std::size_t>(ref)];
            auto a = analyse_neighbours(l.wires.paths(), l.plane, u, s.plane, analysis_);
            if (!a) {
                return std::unexpected(core::with_context(
                    a.error(), fmt::format("region {}, height {:.3f} mm", rid, s.span.cut)));
            }
            for (const OverhangPiece& p : a->pieces) {
                // A piece that does not touch the look-back layer may stand on the layers in
                // between, grown out of it (a rail on the roof of an undercut built since):
                // then it is an overhang by its angle, not a floating piece.
                if (ref != lower && !p.touches_lower && p.ang_deg <= s_.beta_deg &&
                    grounded_between(rid, ref, p)) {
                    continue;
                }
                if (!p.touches_lower && !has_sideways(ref, p)) {
                    // Nothing can reach it: it stays in its layer and rests on nothing there
                    // (the plan says so; a refusal of this base, not of the whole plan).
                    record_unreachable(rid, ref, s, p);
                    continue;
                }
                if (p.ang_deg > s_.beta_deg || !p.touches_lower) {
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

    // Whether piece p (in the frame of layer `ref`, a track's height below the region's last
    // layer) rests on material of the layers after ref that grew out of ref: from ref up,
    // each layer's islands that meet the grounded part of the layer before (grown by the
    // self-supporting allowance) are grounded. A piece over an island that floats in those
    // layers (a thin feature starting in the air, narrower than a track at first) is not.
    // Planar layers of one direction only (their frames share the in-plane axes); false
    // otherwise.
    bool grounded_between(int rid, int ref, const OverhangPiece& p) const {
        const Region& rr = plan_.regions[static_cast<std::size_t>(rid)];
        const Layer& base = plan_.layers[static_cast<std::size_t>(ref)];
        const auto from = std::find(rr.layers.begin(), rr.layers.end(), ref);
        if (from == rr.layers.end()) return false;
        const auto grow = core::mm_to_um(
            s_.layer_mm * std::tan(s_.self_supporting_deg * std::numbers::pi / 180.0) +
            kGroundSlackMm);
        Paths2 grounded = base.wires.paths();
        for (auto it = from + 1; it != rr.layers.end(); ++it) {
            const Layer& l = plan_.layers[static_cast<std::size_t>(*it)];
            if (l.tilted || base.tilted || !(l.plane.normal == base.plane.normal) ||
                !(l.plane.u == base.plane.u) || !(l.plane.v == base.plane.v)) {
                return false;
            }
            const Paths2 reach = geom2d::offset_of(grounded, grow);
            Paths2 next;
            for (Paths2& island : l.wires.islands()) {
                if (!geom2d::intersection_of(island, reach).empty()) {
                    next.insert(next.end(), island.begin(), island.end());
                }
            }
            grounded = std::move(next);
        }
        return !geom2d::intersection_of(p.region, geom2d::offset_of(grounded, grow)).empty();
    }

    // Tilted 3D layers (METHOD.md section 4): from layer `lower` up, each layer's top plane
    // turns towards the chain of centroids by at most what keeps its local thickness in
    // [h_min, h_max] over the layer below (the per-layer bound atan((h_max - h_min) / W));
    // a tilt that breaks the range is halved, up to max_tilt_tries times, then dropped for
    // that layer (recorded). Each plane is cut on its own. Ends at a split, or at an empty
    // section (the top of the part, or a gap: planar layers resume there).
    core::Result<Next> march(int rid, int lower) {
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
                    ok = t_min >= s_.h_min_mm - 1e-9 && t_max <= s_.h_max_mm + 1e-9;
                    if (!ok) delta *= 0.5;
                }
                if (!ok) {
                    Decision dec;
                    dec.kind = Decision::Kind::kTiltGaveUp;
                    dec.region = rid;
                    dec.layer = lower;
                    dec.reason = fmt::format(
                        "above layer L{}: no tilt towards the centroid chain keeps the thickness "
                        "in [{}, {}] mm after {} tries: a planar layer",
                        lower, s_.h_min_mm, s_.h_max_mm, s_.max_tilt_tries);
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
                mid =
                    slice::PlaneFrame::from_normal((c_top + g) * 0.5, core::normalized(nl + n_new));
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
            layer.span = {cut - layer.thickness_mean_mm / 2, cut + layer.thickness_mean_mm / 2,
                          cut};
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

    // The footing is laid only where it saves a split at the plate. A split in the base region
    // at a layer that ends within a track's height above the footing's height: without the
    // footing (the first walk), the base region is walked again from the plate with it; with
    // it, the overhang goes on above it (a chamfer, a sphere) and the footing would only move
    // the split up and add material: walked again without it, for good. Every layer and
    // decision of the walk is dropped first. True when a walk again is due.
    bool retry_footing(int rid, int ref) {
        if (rid != 0 || footing_ == FootingState::kDropped) return false;
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

    // Removes region rid's layers above layer `keep` (the last ones made), and the tilt
    // decisions taken for them.
    void roll_back(int rid, int keep) {
        Region& r = plan_.regions[static_cast<std::size_t>(rid)];
        while (!r.layers.empty() && r.layers.back() > keep) {
            r.layers.pop_back();
            plan_.layers.pop_back();
        }
        if (footing_added_.size() > plan_.layers.size()) footing_added_.resize(plan_.layers.size());
        std::erase_if(plan_.decisions, [&](const Decision& d) {
            return (d.kind == Decision::Kind::kTiltWanted ||
                    d.kind == Decision::Kind::kUnreachable) &&
                   d.region == rid && d.layer > keep;
        });
    }

    // The part of V_i across L's normal: the direction a region split for piece p above
    // layer `lower` is built along (METHOD.md section 5), before it is normalised.
    core::Vec3d sideways_of(int lower, const OverhangPiece& p) const {
        const core::Vec3d n = plan_.layers[static_cast<std::size_t>(lower)].top.normal;
        return p.V - n * core::dot(p.V, n);
    }

    // Whether piece p has a sideways direction to be built from (V_i not along L's normal).
    bool has_sideways(int lower, const OverhangPiece& p) const {
        return core::norm(sideways_of(lower, p)) >= kMinSidewaysNorm;
    }

    void record_unreachable(int rid, int lower, const slice::Slice& s, const OverhangPiece& p) {
        for (const Decision& e : plan_.decisions) {  // seen from the look-back layer too
            if (e.kind == Decision::Kind::kUnreachable && e.region == rid &&
                e.height_mm == s.span.cut && core::norm(e.piece.C - p.C) < 1e-9) {
                return;
            }
        }
        record_piece(Decision::Kind::kUnreachable, rid, lower, s, p,
                     fmt::format("above layer L{} at {:.3f} mm: a piece of {:.1f} mm2 at ({:.3f}, "
                                 "{:.3f}, {:.3f}) floats straight above the layer below: no "
                                 "sideways build direction reaches it; left in its layer, where "
                                 "it rests on nothing",
                                 lower, s.span.cut, p.area_mm2, p.C.x, p.C.y, p.C.z));
    }

    void record_tilt(int rid, int lower, const slice::Slice& s, const OverhangPiece& p) {
        record_piece(
            Decision::Kind::kTiltWanted, rid, lower, s, p,
            fmt::format("layer above L{} at {:.3f} mm: overhang piece of {:.1f} mm2 with Ang = "
                        "{:.1f} deg in (alpha {:.0f}, beta {:.0f}]: a tilted layer is wanted; "
                        "layers tilt only where the chain of centroids leans, so this one "
                        "may stay planar",
                        lower, s.span.cut, p.area_mm2, p.ang_deg, s_.alpha_deg, s_.beta_deg));
    }

    // A decision about piece p of the slice s above layer `lower` of region rid.
    void record_piece(Decision::Kind kind, int rid, int lower, const slice::Slice& s,
                      const OverhangPiece& p, std::string reason) {
        Decision d;
        d.kind = kind;
        d.region = rid;
        d.layer = lower;
        d.height_mm = s.span.cut;
        d.piece = p;
        d.reason = std::move(reason);
        plan_.decisions.push_back(std::move(d));
    }

    // Splits region rid above its layer `lower` for piece p (METHOD.md section 5). Returns
    // true when rid had no layer yet: its own cell was narrowed to the near side and it
    // must be walked again; false when rid ends at `lower` and a continuation region
    // carries on.
    core::Result<bool> split(int rid, int lower, const slice::Slice& s, const OverhangPiece& p) {
        const Region parent = plan_.regions[static_cast<std::size_t>(rid)];
        const core::Vec3d n = plan_.layers[static_cast<std::size_t>(lower)].top.normal;
        const core::Vec3d sideways = sideways_of(lower, p);
        const std::string context = fmt::format("region {}, height {:.3f} mm", rid, s.span.cut);
        if (!has_sideways(lower, p)) {
            return invalid(fmt::format("an overhang piece of {:.1f} mm2 at ({:.3f}, {:.3f}, "
                                       "{:.3f}) floats straight above the layer below: no "
                                       "sideways build direction reaches it",
                                       p.area_mm2, p.C.x, p.C.y, p.C.z),
                           context);
        }
        if (static_cast<int>(plan_.regions.size()) + 2 > s_.max_regions) {
            return invalid(fmt::format("the part needs more than {} regions (max_regions); is it "
                                       "a lattice or a scan with many small overhangs?",
                                       s_.max_regions),
                           context);
        }
        const core::Vec3d ns = core::normalized(sideways);
        const Layer& l = plan_.layers[static_cast<std::size_t>(lower)];
        const HalfSpace above{l.top.origin, n};
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

        Decision d;
        d.kind = p.touches_lower ? Decision::Kind::kSplit : Decision::Kind::kFloating;
        d.region = rid;
        d.layer = lower;
        d.height_mm = s.span.cut;
        d.piece = p;
        d.new_region = child.id;
        d.split_plane = beyond;
        d.reason = fmt::format(
            "above layer L{}: overhang piece of {:.1f} mm2 with Ang = {:.1f} deg {}: split plane "
            "through ({:.3f}, {:.3f}, {:.3f}) with normal ({:.4f}, {:.4f}, {:.4f}); region {} is "
            "built along it",
            lower, p.area_mm2, p.ang_deg,
            p.touches_lower ? fmt::format("> beta {:.0f}", s_.beta_deg)
                            : std::string("(does not touch the layer below)"),
            p.contact_center.x, p.contact_center.y, p.contact_center.z, ns.x, ns.y, ns.z, child.id);
        child.reason = fmt::format("split from region {}: {}", rid, d.reason);
        plan_.regions.push_back(child);
        jobs_.push_back({child.id, {}});

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
        cont.reason = fmt::format(
            "carries on along region {}'s direction above layer L{}, on "
            "the near side of the split plane of region {}",
            rid, lower, child.id);
        d.continuation = cont.id;
        plan_.decisions.push_back(std::move(d));
        plan_.regions.push_back(cont);
        jobs_.push_back({cont.id, {lower}});
        return false;
    }

    // One layer per piece (METHOD.md section 6): a slice whose section falls apart into
    // separate islands (two legs, two branches) gives one layer per island, so that branches
    // can merge and fork in the graph and the build order can grow them in turn. Pieces of a
    // slice share its index_in_region; ids stay contiguous per region, and the layer ids the
    // decisions name (fields and reasons) are renumbered to the slice's first piece.
    void split_pieces() {
        std::vector<Layer> out;
        out.reserve(plan_.layers.size());
        std::vector<int> first_piece(plan_.layers.size(), -1);
        for (Region& r : plan_.regions) {
            std::vector<int> ids;
            ids.reserve(r.layers.size());
            for (const int old : r.layers) {
                Layer& l = plan_.layers[static_cast<std::size_t>(old)];
                std::vector<Paths2> parts = l.wires.islands();
                first_piece[static_cast<std::size_t>(old)] = static_cast<int>(out.size());
                if (parts.size() <= 1) {
                    l.id = static_cast<int>(out.size());
                    ids.push_back(l.id);
                    out.push_back(std::move(l));
                    continue;
                }
                l.wires = {};
                for (Paths2& part : parts) {
                    Layer piece = l;
                    piece.id = static_cast<int>(out.size());
                    piece.wires = geom2d::build_wire_tree(part, geom2d::FillRule::kPositive);
                    piece.area_mm2 = piece.wires.area_mm2();
                    ids.push_back(piece.id);
                    out.push_back(std::move(piece));
                }
            }
            r.layers = std::move(ids);
        }
        const auto renumber = [&](int old) {
            return old >= 0 && static_cast<std::size_t>(old) < first_piece.size()
                       ? first_piece[static_cast<std::size_t>(old)]
                       : old;
        };
        for (Decision& d : plan_.decisions) {
            d.layer = renumber(d.layer);
            d.reason = renumber_layer_names(d.reason, renumber);
        }
        for (Region& r : plan_.regions) r.reason = renumber_layer_names(r.reason, renumber);
        plan_.layers = std::move(out);
    }

    // The pieces of region rid's slice that layer id belongs to.
    std::vector<int> step_of(int id) const {
        const Layer& l = plan_.layers[static_cast<std::size_t>(id)];
        std::vector<int> out;
        for (const int q : plan_.regions[static_cast<std::size_t>(l.region)].layers) {
            if (plan_.layers[static_cast<std::size_t>(q)].index_in_region == l.index_in_region)
                out.push_back(q);
        }
        return out;
    }

    // The hierarchy graph (METHOD.md section 6).
    core::Result<void> build_graph() {
        std::vector<Layer>& layers = plan_.layers;
        boxes_.resize(layers.size());
        tbb::parallel_for(std::size_t{0}, layers.size(),
                          [&](std::size_t i) { boxes_[i] = box_of(layers[i]); });
        const double min_area = kContactAreaShare * s_.track_width_mm * s_.track_width_mm;
        const auto link = [&](int from, int to) {
            layers[static_cast<std::size_t>(from)].children.push_back(to);
            layers[static_cast<std::size_t>(to)].parents.push_back(from);
        };
        // Within each region (and from a continuation's seed): each piece on the pieces of
        // the slice below whose projection it overlaps. Pure geometry, so the pairs are
        // tested in parallel; the edges are made region by region below, in the order the
        // sideways links' cycle check relies on.
        std::vector<LinkTask> tasks;
        for (const Region& r : plan_.regions) {
            if (r.layers.empty()) continue;
            std::vector<int> below;
            for (const Decision& d : plan_.decisions) {
                if (d.continuation == r.id && d.continuation != d.region) below = step_of(d.layer);
            }
            for (std::size_t i = 0; i < r.layers.size();) {
                std::size_t j = i;
                const int step = layers[static_cast<std::size_t>(r.layers[i])].index_in_region;
                while (j < r.layers.size() &&
                       layers[static_cast<std::size_t>(r.layers[j])].index_in_region == step) {
                    ++j;
                }
                const std::vector<int> here(r.layers.begin() + static_cast<std::ptrdiff_t>(i),
                                            r.layers.begin() + static_cast<std::ptrdiff_t>(j));
                for (const int b : below) tasks.push_back({r.id, b, here, {}});
                below = here;
                i = j;
            }
        }
        tbb::parallel_for(std::size_t{0}, tasks.size(), [&](std::size_t k) { rests_on(tasks[k]); });
        std::size_t next_task = 0;
        for (const Region& r : plan_.regions) {
            for (; next_task < tasks.size() && tasks[next_task].region == r.id; ++next_task) {
                const LinkTask& t = tasks[next_task];
                for (std::size_t k = 0; k < t.uppers.size(); ++k) {
                    if (t.rests[k] != 0) link(t.lower, t.uppers[k]);
                }
            }
            if (r.layers.empty()) continue;
            // A sideways region's first layer: on the layers of other regions across its base.
            if (r.parent < 0 ||
                r.direction == plan_.regions[static_cast<std::size_t>(r.parent)].direction) {
                continue;
            }
            std::vector<int> others;
            for (const Region& other : plan_.regions) {
                if (other.id == r.id || descends_from(other.id, r.id)) continue;
                others.insert(others.end(), other.layers.begin(), other.layers.end());
            }
            // Every piece of the first slice (the slice may cut the part in several).
            const int first_step =
                layers[static_cast<std::size_t>(r.layers.front())].index_in_region;
            for (const int id : r.layers) {
                const Layer& first = layers[static_cast<std::size_t>(id)];
                if (first.index_in_region != first_step) break;
                // Empty sections between the base plane and the first layer: nothing across
                // the base plane touches it (a body beside the part, reached across the air).
                if (first.after_gap) continue;
                const Box2 first_box = box2_of(first.wires.paths());
                std::vector<char> touches(others.size(), 0);
                tbb::parallel_for(std::size_t{0}, others.size(), [&](std::size_t k) {
                    const Layer& q = layers[static_cast<std::size_t>(others[k])];
                    touches[k] = contact_mm2(q, first, first_box, r) >= min_area ? 1 : 0;
                });
                for (std::size_t k = 0; k < others.size(); ++k) {
                    // Two first layers may touch each other across both base planes (sideways
                    // regions meeting at a corner): the edge that would close a cycle is left
                    // out, so the earlier-made one goes first and the graph stays acyclic.
                    if (touches[k] != 0 && !reaches(first.id, others[k])) {
                        link(others[k], first.id);
                    }
                }
            }
        }
        for (Layer& l : layers) {
            std::sort(l.parents.begin(), l.parents.end());
            std::sort(l.children.begin(), l.children.end());
            if (l.parents.empty() && !l.on_plate) plan_.unsupported_layers.push_back(l.id);
        }
        if (topological_order(plan_).size() != layers.size()) {
            return core::fail(core::ErrorCode::kInternal,
                              "the hierarchy graph has a cycle (a bug in maxslice)", "planning");
        }
        return {};
    }

    // Whether `to` can be reached from `from` along the edges made so far: a search over
    // from's descendants only (the marks of earlier searches are told apart by a stamp).
    bool reaches(int from, int to) {
        seen_.resize(plan_.layers.size(), 0);
        ++stamp_;
        std::vector<int> stack{from};
        while (!stack.empty()) {
            const int id = stack.back();
            stack.pop_back();
            if (id == to) return true;
            if (seen_[static_cast<std::size_t>(id)] == stamp_) continue;
            seen_[static_cast<std::size_t>(id)] = stamp_;
            for (const int c : plan_.layers[static_cast<std::size_t>(id)].children)
                stack.push_back(c);
        }
        return false;
    }

    bool descends_from(int region, int ancestor) const {
        for (int r = region; r >= 0; r = plan_.regions[static_cast<std::size_t>(r)].parent) {
            if (r == ancestor) return true;
        }
        return false;
    }

    // The uppers of one slice that rest on one lower layer (overlap_mm2 > 0).
    struct LinkTask {
        int region = 0;
        int lower = -1;
        std::vector<int> uppers;
        std::vector<char> rests;  // per upper
    };

    void rests_on(LinkTask& t) const {
        const Layer& lower = plan_.layers[static_cast<std::size_t>(t.lower)];
        t.rests.assign(t.uppers.size(), 0);
        const Box2 lower_box = box2_of(lower.wires.paths());
        Paths2 grown;  // lower grown by `grown_by`, made when first needed
        std::int64_t grown_by = -1;
        for (std::size_t k = 0; k < t.uppers.size(); ++k) {
            const Layer& upper = plan_.layers[static_cast<std::size_t>(t.uppers[k])];
            if (upper.after_gap || !may_overlap(lower, upper)) continue;
            const Paths2 u = projected(upper, lower);
            const std::int64_t grow = growth_um(lower, upper);
            // The grown region lies within twice the growth of lower (mitred corners): a
            // piece whose box stays clear of that has no overlap.
            if (!boxes_near(box2_of(u), lower_box, 2 * grow + kNearSlackUm)) {
                continue;
            }
            if (grow != grown_by) {
                grown = geom2d::offset_of(lower.wires.paths(), grow);
                grown_by = grow;
            }
            t.rests[k] = geom2d::signed_area_mm2(geom2d::intersection_of(u, grown)) > 0.0 ? 1 : 0;
        }
    }

    // Whether upper's footprint can reach lower's grown region (boxes of their wires in
    // 3D, grown by the growth overlap_mm2 allows and the distance between the layers).
    bool may_overlap(const Layer& lower, const Layer& upper) const {
        const Box3& a = boxes_[static_cast<std::size_t>(lower.id)];
        const Box3& b = boxes_[static_cast<std::size_t>(upper.id)];
        const double gap = 2.0 * s_.track_width_mm + 2.0 * s_.h_max_mm +
                           core::norm(upper.plane.origin - lower.plane.origin) *
                               std::tan(s_.self_supporting_deg * std::numbers::pi / 180.0);
        for (int k = 0; k < 3; ++k) {
            if (a.lo[k] > b.hi[k] + gap || b.lo[k] > a.hi[k] + gap) return false;
        }
        return true;
    }

    // Area (mm2) where upper, projected onto lower's plane, overlaps lower grown by the
    // self-supporting allowance and a track: what the analysis calls carried (slivers
    // narrower than a track included) rests on lower.
    // Upper's section projected onto lower's plane (um, lower's frame).
    static Paths2 projected(const Layer& upper, const Layer& lower) {
        Paths2 u;
        for (const geom2d::Path2& path : upper.wires.paths()) {
            geom2d::Path2& q = u.emplace_back();
            for (const geom2d::Point2& p : path)
                q.push_back(lower.plane.to_2d(upper.plane.to_3d(p)));
        }
        return u;
    }

    // How far lower is grown before the overlap is measured: the self-supporting allowance
    // over the height between them, and a track, so that what the analysis calls carried
    // (slivers narrower than a track included) rests on lower.
    std::int64_t growth_um(const Layer& lower, const Layer& upper) const {
        const double h = std::max(0.0, lower.plane.height(upper.plane.origin));
        return core::mm_to_um(h * std::tan(s_.self_supporting_deg * std::numbers::pi / 180.0) +
                              s_.track_width_mm);
    }

    static bool boxes_near(const Box2& a, const Box2& b, std::int64_t gap) {
        return a.lo.x <= b.hi.x + gap && b.lo.x <= a.hi.x + gap && a.lo.y <= b.hi.y + gap &&
               b.lo.y <= a.hi.y + gap;
    }

    // Area (mm2) where layer q's material just behind the base plane of region r meets the
    // footprint of r's first layer.
    double contact_mm2(const Layer& q, const Layer& first, const Box2& first_box,
                       const Region& r) const {
        const core::Vec3d ns = r.direction;
        const core::Vec3d s = r.base.origin;
        const double depth = std::max(s_.layer_mm, q.span.thickness());
        // Most layers lie wholly in front of the base plane or far behind it: their box
        // tells, without clipping.
        const Box3& box = boxes_[static_cast<std::size_t>(q.id)];
        double centre = 0.0, radius = 0.0;
        for (int k = 0; k < 3; ++k) {
            centre += 0.5 * (box.lo[k] + box.hi[k] - 2.0 * s[k]) * ns[k];
            radius += 0.5 * (box.hi[k] - box.lo[k]) * std::abs(ns[k]);
        }
        if (centre - radius > kStripSlackMm || centre + radius < -depth - kStripSlackMm) return 0.0;
        // Nor can q's slab meet the first layer where its box, grown by the slab's half
        // thickness and seen on the first layer's plane, misses the first layer's box.
        const double ext =
            std::max(std::abs(q.span.bottom - q.span.cut), std::abs(q.span.top - q.span.cut));
        double u_lo = INFINITY, u_hi = -INFINITY, v_lo = INFINITY, v_hi = -INFINITY;
        for (int corner = 0; corner < 8; ++corner) {
            const core::Vec3d x{(corner & 1) != 0 ? box.hi[0] + ext : box.lo[0] - ext,
                                (corner & 2) != 0 ? box.hi[1] + ext : box.lo[1] - ext,
                                (corner & 4) != 0 ? box.hi[2] + ext : box.lo[2] - ext};
            const double u = core::dot(x - first.plane.origin, first.plane.u);
            const double v = core::dot(x - first.plane.origin, first.plane.v);
            u_lo = std::min(u_lo, u);
            u_hi = std::max(u_hi, u);
            v_lo = std::min(v_lo, v);
            v_hi = std::max(v_hi, v);
        }
        const double slack_um = core::kMicronsPerMm * kStripSlackMm;
        if (u_hi * core::kMicronsPerMm < static_cast<double>(first_box.lo.x) - slack_um ||
            u_lo * core::kMicronsPerMm > static_cast<double>(first_box.hi.x) + slack_um ||
            v_hi * core::kMicronsPerMm < static_cast<double>(first_box.lo.y) - slack_um ||
            v_lo * core::kMicronsPerMm > static_cast<double>(first_box.hi.y) + slack_um) {
            return 0.0;
        }
        const HalfSpace strip[] = {{s, -ns}, {s - ns * depth, ns}};
        const Paths2 near = detail::clip_to_cell(q.wires.paths(), strip, q.plane);
        if (near.empty()) return 0.0;
        // q's slab: its section between its bottom and top, seen on r's base plane.
        geom2d::Paths2 hulls;
        for (const geom2d::Path2& path : near) {
            if (geom2d::signed_area_um2(path) <= 0.0) continue;
            geom2d::Path2 pts;
            for (const geom2d::Point2& p : path) {
                for (const double h : {q.span.bottom - q.span.cut, q.span.top - q.span.cut}) {
                    pts.push_back(first.plane.to_2d(q.plane.to_3d(p, h)));
                }
            }
            geom2d::Path2 hull = geom2d::convex_hull({pts});
            if (hull.size() >= 3) hulls.push_back(std::move(hull));
        }
        if (hulls.empty()) return 0.0;
        return geom2d::signed_area_mm2(
            geom2d::intersection_of(geom2d::union_of(hulls), first.wires.paths()));
    }

    const mesh::TriangleMesh& mesh_;
    PlanSettings s_;
    const core::Progress* progress_;
    AnalysisSettings analysis_;
    int look_back_ = 1;  // layers in a track's height: the look-back distance
    enum class FootingState { kUntried, kOn, kDropped };
    FootingState footing_ = s_.footing_mm > 0.0 ? FootingState::kUntried : FootingState::kDropped;
    // Per layer id: the area x thickness its footing pad adds, or -1 (not a footing layer).
    std::vector<double> footing_added_;
    Plan plan_;
    std::deque<RegionJob> jobs_;
    std::optional<detail::SectionIndex> sections_;
    std::vector<Box3> boxes_;  // per layer id, while the graph is built
    std::vector<int> seen_;    // marks of reaches(), per layer id
    int stamp_ = 0;
};

}  // namespace

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
    return Planner(mesh, settings, progress).run(base_direction);
}

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

std::vector<int> topological_order(const Plan& plan) {
    std::vector<int> indegree(plan.layers.size(), 0);
    for (const Layer& l : plan.layers)
        indegree[static_cast<std::size_t>(l.id)] = static_cast<int>(l.parents.size());
    std::priority_queue<int, std::vector<int>, std::greater<>> ready;
    for (const Layer& l : plan.layers) {
        if (indegree[static_cast<std::size_t>(l.id)] == 0) ready.push(l.id);
    }
    std::vector<int> order;
    order.reserve(plan.layers.size());
    while (!ready.empty()) {
        const int id = ready.top();
        ready.pop();
        order.push_back(id);
        for (const int c : plan.layers[static_cast<std::size_t>(id)].children) {
            if (--indegree[static_cast<std::size_t>(c)] == 0) ready.push(c);
        }
    }
    return order;
}

}  // namespace maxslice::plan
