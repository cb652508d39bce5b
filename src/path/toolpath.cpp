#include "maxslice/path/toolpath.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include <tbb/parallel_for.h>

#include "gap_fill.hpp"
#include "maxslice/core/units.hpp"
#include "raster.hpp"
#include "route.hpp"

namespace maxslice::path {
namespace {

using geom2d::Path2;
using geom2d::Paths2;
using geom2d::Point2;

// The smallest pitch accepted (mm): below it the number of fill lines explodes.
constexpr double kMinPitchMm = 0.01;
// The widest track accepted (mm); keeps every offset far inside the integer range.
constexpr double kMaxTrackWidthMm = 1000.0;
// Links between fill lines longer than this many pitches are not deposited: a long link runs
// along the boundary over tracks already laid (an L's inner step, a shallow edge), and
// travelling with the laser off instead avoids the extra material. Along a boundary at angle
// a to the raster a link is about pitch / sin(a) long, so edges steeper than ~14 degrees
// are linked.
constexpr double kMaxLinkPitches = 4.0;
// Gaps between contours where no fill line fits get a track along their middle when that
// track overlaps each neighbour by at most the nominal overlap or this share of a track,
// whichever is larger (0.4: gaps from 20% of a track wide at the default overlap); narrower
// gaps are left and reported as uncovered (a track there would pile up material).
constexpr double kMaxGapFillOverlap = 0.4;
// ... and never gaps narrower than this share of a track (numerical slivers).
constexpr double kMinGapFillShare = 0.05;
// The outermost fill lines may lie up to this share of the overlap further in than one pitch
// from the innermost contour: they still overlap its track by a quarter of the overlap, and a
// thin fill region gets one line instead of two close ones.
constexpr double kMarginShare = 0.75;
// An island whose fill region (inside its contour passes) is nowhere wider than twice this
// many pitches is thin: contour passes may fill it (plan_island).
constexpr double kThinPitches = 3.0;
// A thin island's depth (its inscribed circle's radius) is found to this many micrometres.
constexpr std::int64_t kThinDepthToleranceUm = 5;
// Parts of the fill region thinner than twice this many pitches go to the gap fill.
constexpr double kOpeningPitches = 0.5;
// Sections of finely tessellated parts carry many vertices closer together than a track
// could ever follow; each offset of such a wire makes Clipper resolve a swarm of tiny
// self-intersections. Vertices that move the boundary by less than this share of a track
// are dropped before planning (0.005: 5 um at a 1 mm track, far below a bead's roughness).
constexpr double kSimplifyShare = 0.005;

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

std::unexpected<core::Error> invalid(std::string message) {
    return core::fail(core::ErrorCode::kInvalidInput, std::move(message), "path settings");
}

double distance_um(Point2 a, Point2 b) {
    return geom2d::length_um(Path2{a, b});
}

// The distances of a plan in whole micrometres.
struct Widths {
    explicit Widths(const PathSettings& s)
        : half(core::mm_to_um(s.track_width_mm) / 2),
          pitch(core::mm_to_um(s.pitch_mm())),
          passes(s.contour_passes),
          max_margin(core::mm_to_um(kMarginShare * s.overlap * s.track_width_mm)),
          opening(core::mm_to_um(kOpeningPitches * s.pitch_mm())),
          max_link(core::mm_to_um(kMaxLinkPitches * s.pitch_mm())),
          thin(core::mm_to_um(kThinPitches * s.pitch_mm())),
          min_sliver(core::mm_to_um(kMinGapFillShare * s.track_width_mm)),
          min_gap(core::mm_to_um(
              std::max(kMinGapFillShare, 1.0 - 2.0 * std::max(s.overlap, kMaxGapFillOverlap)) *
              s.track_width_mm)) {}

    std::int64_t half;        // half a track
    std::int64_t pitch;       // between neighbouring track centres
    int passes;               // contour passes
    std::int64_t max_margin;  // of the outermost fill lines, see raster.hpp
    std::int64_t opening;     // fill region parts thinner than twice this go to the gap fill
    std::int64_t max_link;    // longest link between fill lines
    std::int64_t thin;        // an island whose fill region is nowhere wider than 2 x this
    std::int64_t min_sliver;  // narrowest gap ever filled
    std::int64_t min_gap;     // narrowest gap filled
};

// An island's strokes in the layer frame, and the area they leave bare.
struct PlannedIsland {
    detail::RouteIsland route;
    double uncovered_mm2 = 0.0;
};

// Whether an island is thin: its fill region (inside its contour passes) nowhere wider than
// twice w.thin. Such an island may be filled with contour passes all the way in.
bool is_thin(const Paths2& island, const Widths& w) {
    return w.passes > 0 &&
           geom2d::offset_of(island, -(w.half + w.passes * w.pitch + w.thin)).empty();
}

// Contours, fill and gap fill of one island (an outer wire and its holes, `local`: in the
// raster frame, fill lines along +x), returned in the layer frame. With `concentric` (a
// thin island), contour passes fill it all the way in instead of a raster: a raster across a
// ring or a bent wall turns along it where it bends to the raster, and leaves wedges between
// its long lines and the contour. The n tracks across are spread evenly over the island's
// widest part: n / 2 passes from each side and, for odd n, the gap fill's track along the
// middle. Of the numbers n whose spacing leaves at least half the nominal overlap (and, for
// odd n, a middle strip the gap fill takes), the one spaced nearest the pitch: the innermost
// tracks then overlap across the middle as neighbouring tracks do.
PlannedIsland plan_island(const Paths2& local, const detail::RasterFrame& frame, const Widths& w,
                          bool concentric) {
    // Track centres may run anywhere half a track inside the region: pass 0, and where
    // straight links between fill lines may go.
    const Paths2 centres = geom2d::offset_of(local, -w.half);
    std::vector<std::int64_t> depths;  // of each pass's centre line below the boundary
    bool middle_track = false;
    if (concentric) {
        std::int64_t inside = 0, outside = w.half + w.passes * w.pitch + w.thin;
        while (outside - inside > kThinDepthToleranceUm) {
            const std::int64_t mid = inside + (outside - inside) / 2;
            (geom2d::offset_of(local, -mid).empty() ? outside : inside) = mid;
        }
        const std::int64_t across = 2 * std::max<std::int64_t>(0, inside - w.half);
        const std::int64_t widest = w.pitch + (2 * w.half - w.pitch) / 2;
        std::int64_t n = 2;
        std::int64_t best = -1;
        for (std::int64_t k = 2; across / (k - 1) >= w.pitch / 2 || k == 2; ++k) {
            const std::int64_t spacing = across / (k - 1);
            const bool fits =
                spacing <= widest && (k % 2 == 0 || 2 * spacing >= 2 * w.half + w.min_gap);
            if (fits && (best < 0 || std::abs(spacing - w.pitch) < best)) {
                best = std::abs(spacing - w.pitch);
                n = k;
            }
        }
        const std::int64_t spacing = across / (n - 1);
        for (std::int64_t k = 0; k < n / 2; ++k) depths.push_back(w.half + k * spacing);
        middle_track = n % 2 == 1;
    } else {
        for (int k = 0; k < w.passes; ++k) depths.push_back(w.half + k * w.pitch);
    }
    std::vector<Paths2> passes;
    for (const std::int64_t depth : depths) {
        Paths2 wires = depth == w.half ? centres : geom2d::offset_of(local, -depth);
        if (wires.empty()) break;  // narrower than this pass
        passes.push_back(std::move(wires));
    }
    detail::RouteGroup contours;
    for (const Paths2& wires : passes) {
        for (const Path2& wire : wires) {
            contours.push_back({StrokeKind::kContour, true, frame.from_raster(wire)});
        }
    }

    // The fill's line ends and outermost lines lie one pitch inside the innermost contour,
    // overlapping its track by the overlap as neighbouring fill tracks do. Parts of the fill
    // region thinner than twice the opening are removed (a morphological opening): rastering
    // them gives scraps of lines across a thin ring, or no line along a thin strip; the gap
    // fill lays tracks along them instead.
    const std::int64_t inset = w.passes > 0 ? w.half + w.passes * w.pitch : w.half;
    const Paths2 eroded = geom2d::offset_of(local, -(inset + w.opening));
    detail::RouteGroup fill;
    Paths2 raster_lines;
    if (!concentric && !eroded.empty()) {
        // Growing back with mitred joins can poke past sharp corners of the inset region:
        // clip to where track centres may run.
        const Paths2 fill_region =
            geom2d::intersection_of(geom2d::offset_of(eroded, w.opening), centres);
        raster_lines =
            detail::zigzag_fill({&fill_region, &centres, w.pitch, w.max_margin, w.max_link});
        for (const Path2& line : raster_lines) {
            fill.push_back({StrokeKind::kFill, false, frame.from_raster(line)});
        }
    }

    // Gaps: inside each contour pass's track, what neither the next pass (its track and all
    // inside it) nor, after the last pass, the fill tracks laid reach (swept by squares of half
    // a track, geom2d::sweep_polylines_square: about a bead's cover, far cheaper to unite than
    // discs; what they differ by is narrower than any gap a track fills). The fill's own tracks,
    // not its region grown by a pitch: where a boundary wavers (a near-net shape's voxel steps),
    // the outermost line may run along the fill region's edge and be clipped to scraps, leaving a
    // strip up to a pitch wide between the fill and the contour. A pass missing in a narrow arm
    // leaves the arm's middle to the gap fill.
    Paths2 gaps;
    for (std::size_t k = 0; k < passes.size(); ++k) {
        const Paths2 inner = geom2d::offset_of(local, -(depths[k] + w.half));
        if (inner.empty()) break;
        Paths2 reached;
        if (k + 1 < passes.size()) {
            reached = geom2d::offset_of(passes[k + 1], w.half);
        } else if (k + 1 == static_cast<std::size_t>(w.passes) && !raster_lines.empty()) {
            reached = geom2d::sweep_polylines_square(raster_lines, w.half);
        }
        Paths2 left = reached.empty() ? inner : geom2d::difference_of(inner, reached);
        gaps.insert(gaps.end(), std::make_move_iterator(left.begin()),
                    std::make_move_iterator(left.end()));
    }
    // Coverage, in the raster frame where fill tracks run along the rows of the integration
    // (each meets only the rows of its own width).
    Paths2 tracks;
    for (const Paths2& wires : passes) {
        for (const Path2& wire : wires) {
            tracks.push_back(wire);
            tracks.back().push_back(wire.front());
        }
    }
    tracks.insert(tracks.end(), raster_lines.begin(), raster_lines.end());
    for (detail::RouteStroke& gap :
         detail::gap_fill(gaps, 2 * w.half, middle_track ? w.min_sliver : w.min_gap)) {
        tracks.push_back(gap.points);
        if (gap.closed) tracks.back().push_back(gap.points.front());
        gap.points = frame.from_raster(gap.points);
        fill.push_back(std::move(gap));
    }
    const double uncovered =
        geom2d::uncovered_area_mm2(local, tracks, w.half, std::max<std::int64_t>(1, w.half / 8));
    return {{std::move(contours), std::move(fill)}, uncovered};
}

// A thin island planned both ways, contour passes and raster: the one that leaves less of
// it bare (contour passes on a tie). Passes spread over the widest part fit an island of
// even width (a tube's wall, a ring); a wall with a tower on it is filled better by the
// raster, whose lines keep a pitch wherever it is wide.
PlannedIsland plan_island(const Paths2& island, const detail::RasterFrame& frame, const Widths& w) {
    const Paths2 local = frame.to_raster(island);
    PlannedIsland raster = plan_island(local, frame, w, false);
    if (!is_thin(local, w)) return raster;
    PlannedIsland passes = plan_island(local, frame, w, true);
    return passes.uncovered_mm2 <= raster.uncovered_mm2 ? std::move(passes) : std::move(raster);
}

}  // namespace

core::Result<void> validate(const PathSettings& s) {
    if (!std::isfinite(s.track_width_mm) || s.track_width_mm <= 0.0) {
        return invalid("track_width_mm must be greater than 0 mm (got " + number(s.track_width_mm) +
                       ")");
    }
    if (s.track_width_mm > kMaxTrackWidthMm) {
        return invalid("track_width_mm must be at most " + number(kMaxTrackWidthMm) + " mm (got " +
                       number(s.track_width_mm) + ")");
    }
    if (!std::isfinite(s.overlap) || s.overlap < 0.0 || s.overlap >= 1.0) {
        return invalid("overlap must be at least 0 and below 1 (got " + number(s.overlap) + ")");
    }
    if (s.pitch_mm() < kMinPitchMm) {
        return invalid("overlap " + number(s.overlap) + " with track_width_mm " +
                       number(s.track_width_mm) + " gives a pitch of " + number(s.pitch_mm()) +
                       " mm, below the smallest " + number(kMinPitchMm) + " mm");
    }
    if (s.contour_passes < 0) {
        return invalid("contour_passes must be 0 or more (got " + std::to_string(s.contour_passes) +
                       ")");
    }
    if (s.raster_angle_deg && !std::isfinite(*s.raster_angle_deg)) {
        return invalid("raster_angle_deg must be a finite number of degrees");
    }
    return {};
}

namespace {

// A layer's tracks before ordering, with what does not depend on the order.
struct PreparedLayer {
    std::vector<detail::RouteIsland> route;
    double raster_angle_deg = 0.0;
    double uncovered_mm2 = 0.0;
};

// Everything of plan_layer but the ordering: the costly part, independent between layers.
// Settings are validated by the caller.
PreparedLayer prepare_layer(const geom2d::WireTree& region, const PathSettings& settings) {
    const Widths widths(settings);
    PreparedLayer out;
    std::vector<Paths2> islands = region.islands();
    const auto tolerance = core::mm_to_um(kSimplifyShare * settings.track_width_mm);
    for (Paths2& island : islands) island = geom2d::simplify(island, tolerance);
    std::erase_if(islands, [](const Paths2& island) {
        return island.empty() || geom2d::signed_area_um2(island.front()) <= 0.0;
    });

    // Each island is rastered along its own long side: one orientation for unrelated
    // islands fits none of them (the tracks of a rectangle next to a disc would run slanted
    // and leave wedges along its long edges). The angle reported is the largest island's.
    std::optional<double> fixed_deg;
    if (settings.raster_angle_deg) {
        fixed_deg = std::fmod(*settings.raster_angle_deg, 180.0);
        if (*fixed_deg < 0.0) *fixed_deg += 180.0;
        out.raster_angle_deg = *fixed_deg;
    }
    double largest_area = -1.0;
    out.route.reserve(islands.size());
    for (const Paths2& island : islands) {
        const double angle_rad = fixed_deg ? *fixed_deg * std::numbers::pi / 180.0
                                           : geom2d::long_side_angle({island.front()});
        const double area = geom2d::signed_area_mm2(island);
        if (!fixed_deg && area > largest_area) {
            largest_area = area;
            out.raster_angle_deg = angle_rad * 180.0 / std::numbers::pi;
        }
        PlannedIsland planned = plan_island(island, detail::RasterFrame(angle_rad), widths);
        out.route.push_back(std::move(planned.route));
        out.uncovered_mm2 += planned.uncovered_mm2;
    }
    return out;
}

// One track along the middle of each island too narrow for a contour (plan_narrow_layer).
PreparedLayer prepare_narrow_layer(const geom2d::WireTree& region, const PathSettings& settings) {
    const Widths widths(settings);
    PreparedLayer out;
    const auto tolerance = core::mm_to_um(kSimplifyShare * settings.track_width_mm);
    for (const Paths2& raw : region.islands()) {
        const Paths2 island = geom2d::simplify(raw, tolerance);
        if (island.empty() || geom2d::signed_area_um2(island.front()) <= 0.0) continue;
        if (!geom2d::offset_of(island, -widths.half).empty()) continue;  // a contour fits
        Paths2 tracks;
        detail::RouteGroup fill;
        for (detail::RouteStroke& s :
             detail::gap_fill(island, 2 * widths.half, widths.min_sliver)) {
            tracks.push_back(s.points);
            if (s.closed) tracks.back().push_back(s.points.front());
            fill.push_back(std::move(s));
        }
        out.uncovered_mm2 += geom2d::uncovered_area_mm2(island, tracks, widths.half,
                                                        std::max<std::int64_t>(1, widths.half / 8));
        if (fill.empty()) continue;
        out.route.emplace_back().push_back(std::move(fill));
    }
    return out;
}

// Puts a prepared layer's strokes in deposition order from `start` and measures them.
LayerToolpath order_layer(PreparedLayer&& prepared, StrokeOrder order, Point2 start) {
    LayerToolpath out;
    out.raster_angle_deg = prepared.raster_angle_deg;
    out.uncovered_mm2 = prepared.uncovered_mm2;
    out.strokes = order == StrokeOrder::kShortTravel
                      ? detail::route_short(std::move(prepared.route), start)
                      : detail::route_generated(std::move(prepared.route));
    Point2 at = start;
    double deposit = 0.0;
    double travel = 0.0;
    for (const Stroke& s : out.strokes) {
        travel += distance_um(at, s.points.front());
        deposit += geom2d::length_um(s.points);
        at = s.points.back();
    }
    out.deposit_length_mm = deposit / core::kMicronsPerMm;
    out.travel_length_mm = travel / core::kMicronsPerMm;
    return out;
}

}  // namespace

core::Result<LayerToolpath> plan_layer(const geom2d::WireTree& region, const PathSettings& settings,
                                       geom2d::Point2 start) {
    if (auto ok = validate(settings); !ok) return std::unexpected(ok.error());
    return order_layer(prepare_layer(region, settings), settings.order, start);
}

core::Result<LayerToolpath> plan_narrow_layer(const geom2d::WireTree& region,
                                              const PathSettings& settings, geom2d::Point2 start) {
    if (auto ok = validate(settings); !ok) return std::unexpected(ok.error());
    return order_layer(prepare_narrow_layer(region, settings), settings.order, start);
}

core::Result<std::vector<LayerToolpath>> plan_layers(
    std::span<const geom2d::WireTree* const> regions, const PathSettings& settings,
    geom2d::Point2 start, const core::Progress* progress) {
    if (auto ok = validate(settings); !ok) return std::unexpected(ok.error());
    // Tracks of every layer in parallel (each writes its own slot: the result does not depend
    // on the thread count), then the ordering layer by layer: each starts where the previous
    // one ended.
    std::vector<PreparedLayer> prepared(regions.size());
    std::atomic<std::size_t> done{0};
    tbb::parallel_for(std::size_t{0}, regions.size(), [&](std::size_t i) {
        if (progress != nullptr && progress->cancelled()) return;
        prepared[i] = prepare_layer(*regions[i], settings);
        if (progress != nullptr) {
            progress->report("toolpaths",
                             static_cast<double>(++done) / static_cast<double>(regions.size()));
        }
    });
    if (progress != nullptr && progress->cancelled()) {
        return core::fail(core::ErrorCode::kCancelled, "cancelled", "toolpaths");
    }
    std::vector<LayerToolpath> out;
    out.reserve(regions.size());
    for (PreparedLayer& layer : prepared) {
        out.push_back(order_layer(std::move(layer), settings.order, start));
        if (!out.back().strokes.empty()) start = out.back().strokes.back().points.back();
    }
    return out;
}

}  // namespace maxslice::path
