#include "maxslice/plan/order.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <tuple>

#include <tbb/parallel_for.h>

#include "box_tree.hpp"
#include "head_profile.hpp"
#include "maxslice/core/units.hpp"
#include "maxslice/geom2d/polygon.hpp"
#include "maxslice/geom2d/wire_tree.hpp"
#include "region_distance.hpp"

// Collision control and build order (METHOD.md sections 7 and 8). The names follow the
// method: S1 is the layer in place, S2 the one being deposited; "hit(S2, S1)" means S2's
// nozzle, standing anywhere on S2's top, meets S1's material.

namespace maxslice::plan {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// How far (um) beyond the distance that can lower a pair's margin the footprint's distance is
// looked for: a sample's distance, 1-Lipschitz, then rules out the samples near it without a
// search (samples lie half a track apart; the 1002 tray's order with the 0.8 mm track took
// 470 million searches without it, 75 million with it).
constexpr double kLookOnUm = 5000.0;
constexpr double kDegToRad = std::numbers::pi / 180.0;
// Material this little above the apex's plane is the layer's own level (mm).
constexpr double kLevelTolerance = 1e-6;
// Plans with more layers are refused (the planner's own limit): the graph's ancestor rows
// cost n^2 / 64 word operations in all.
constexpr std::size_t kMaxLayers = 1'000'000;
// Words (8 bytes) the ancestor rows of one block of layers may take: 64 MB.
constexpr std::size_t kReachBudgetWords = std::size_t{8} << 20;
// Samples are checked in chunks of about this many sample spacings across.
constexpr double kChunkSamples = 6.0;
// Apexes stand this share of half a track inside the section (a margin for the offset's
// rounding against the toolpath's own).
constexpr double kApexInsetShare = 0.95;
// Clearances beyond this (mm, or twice the nozzle's clearance) are not measured: a pair that
// cannot come closer is skipped.
constexpr double kMarginCap = 10.0;
// Boxes are grown, and the bounds drawn from them lowered, by this much (mm): far more than
// the rounding of coordinates of parts of metres, so a bound never skips a sample whose
// clearance, computed on its own, is smaller.
constexpr double kBoxSlackMm = 1e-9;
// A footprint distance is looked for up to the radius that could lower a margin, grown by
// this share and this many micrometres: rounding never hides a closer point.
constexpr double kLimitPadShare = 1e-9;
constexpr double kLimitPadUm = 1e-3;
// A collision on a cycle of the order whose margin lies within the samples' cover of the
// clearance is measured again on the met layer sampled this many times finer across its
// section and on this many planes through its thickness (a smaller cover) ...
constexpr double kFinerSamples = 4.0;
constexpr int kFinerPlanes = 3;
// ... at most this many times in one order.
constexpr int kMaxRemeasured = 256;

struct Vec2 {
    double x = 0.0;
    double y = 0.0;
};

// A box aligned with a layer's own plane frame (u, v, normal): its centre (mm, part frame)
// and half its extent along each axis. A layer's samples lie on two faces parallel to its
// plane, so this box is as thin as the layer even where the layer stands sideways, where a
// box aligned with the part's axes would span the whole section in height.
struct FrameBox {
    core::Vec3d centre;
    double half[3] = {0.0, 0.0, 0.0};
};

// Samples [begin, end) of a layer that lie close together, with their box.
struct SampleChunk {
    std::size_t begin = 0;
    std::size_t end = 0;
    FrameBox box;
};

// A layer as the nozzle check sees it.
struct LayerShape {
    core::Vec3d d;          // build direction = nozzle axis (unit)
    slice::PlaneFrame top;  // apexes lie on this plane
    geom2d::Paths2 print;   // apexes' region on the top plane (um, top's u, v)
    detail::RegionDistance print_index;
    Vec2 print_lo{kInf, kInf};
    Vec2 print_hi{-kInf, -kInf};
    std::vector<core::Vec3d> samples;  // material points: bottom and top faces, by chunk
    std::vector<SampleChunk> chunks;
    core::Vec3d axes[3];               // the layer plane's u, v and normal
    FrameBox box;                      // box of the samples in that frame
    core::Vec3d lo{kInf, kInf, kInf};  // box of the samples (part frame)
    core::Vec3d hi{-kInf, -kInf, -kInf};
    core::Vec3d reach_lo;  // box of everything its nozzle can reach
    core::Vec3d reach_hi;
    // Every point of the layer's material lies within this of a sample (mm): the samples'
    // grid spacing across the section, half the thickness through it.
    double cover = 0.0;
};

void grow(core::Vec3d& lo, core::Vec3d& hi, const core::Vec3d& p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
}

bool boxes_meet(const core::Vec3d& alo, const core::Vec3d& ahi, const core::Vec3d& blo,
                const core::Vec3d& bhi) {
    return alo.x <= bhi.x && blo.x <= ahi.x && alo.y <= bhi.y && blo.y <= ahi.y && alo.z <= bhi.z &&
           blo.z <= ahi.z;
}

// Points of a region (contours in mm) at about `spacing` apart: along every contour and on a
// grid inside (scanlines).
std::vector<Vec2> sample_region(const std::vector<std::vector<Vec2>>& contours, double spacing) {
    std::vector<Vec2> out;
    Vec2 lo{kInf, kInf}, hi{-kInf, -kInf};
    for (const std::vector<Vec2>& c : contours) {
        for (std::size_t i = 0; i < c.size(); ++i) {
            const Vec2 a = c[i];
            const Vec2 b = c[(i + 1) % c.size()];
            lo = {std::min(lo.x, a.x), std::min(lo.y, a.y)};
            hi = {std::max(hi.x, a.x), std::max(hi.y, a.y)};
            const int steps = std::max(
                1, static_cast<int>(std::ceil(std::hypot(b.x - a.x, b.y - a.y) / spacing)));
            for (int k = 0; k < steps; ++k) {
                const double s = static_cast<double>(k) / steps;
                out.push_back({a.x + s * (b.x - a.x), a.y + s * (b.y - a.y)});
            }
        }
    }
    if (out.empty()) return out;
    std::vector<double> xs;
    for (double y = std::floor(lo.y / spacing) * spacing + spacing / 2; y < hi.y; y += spacing) {
        xs.clear();
        for (const std::vector<Vec2>& c : contours) {
            for (std::size_t i = 0; i < c.size(); ++i) {
                const Vec2 a = c[i];
                const Vec2 b = c[(i + 1) % c.size()];
                if ((a.y <= y) != (b.y <= y))
                    xs.push_back(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
            }
        }
        std::sort(xs.begin(), xs.end());
        for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
            for (double x = std::ceil(xs[k] / spacing) * spacing; x < xs[k + 1]; x += spacing)
                out.push_back({x, y});
        }
    }
    return out;
}

// Where the nozzle's apex can stand on a layer: the track centres lie at least half a track
// inside the section (path::plan_layer), so each island shrunk by that much; an island too
// thin for it (a single track along its middle) counts whole.
geom2d::Paths2 apex_region(const Layer& l, double track_width_mm) {
    geom2d::Paths2 out;
    const auto inset = core::mm_to_um(kApexInsetShare * track_width_mm / 2.0);
    for (const geom2d::Paths2& island : l.wires.islands()) {
        geom2d::Paths2 in = geom2d::offset_of(island, -inset);
        if (geom2d::signed_area_mm2(in) <= 0.0) in = island;
        out.insert(out.end(), in.begin(), in.end());
    }
    return out;
}

// The nozzle check's view of layer l: samples `spacing` apart across its section on `planes`
// planes through its thickness (its faces and evenly between them).
LayerShape shape_of(const Layer& l, const Nozzle& nozzle, double spacing, double track_width_mm,
                    int planes = 2) {
    LayerShape s;
    s.top = l.top;
    s.d = l.top.normal;
    // The section in its own plane (mm), for the samples.
    std::vector<std::vector<Vec2>> own;
    for (const geom2d::WireNode& n : l.wires.nodes) {
        std::vector<Vec2>& c = own.emplace_back();
        for (const geom2d::Point2& q : n.wire)
            c.push_back({core::um_to_mm(q.x), core::um_to_mm(q.y)});
    }
    // The apexes' region, on the top plane.
    for (const geom2d::Path2& path : apex_region(l, track_width_mm)) {
        geom2d::Path2& f = s.print.emplace_back();
        for (const geom2d::Point2& q : path) {
            const core::Vec3d x = l.plane.to_3d(q);
            const core::Vec3d on_top = x - s.d * s.top.height(x);
            const Vec2 p{core::dot(on_top - s.top.origin, s.top.u),
                         core::dot(on_top - s.top.origin, s.top.v)};
            f.push_back({core::mm_to_um(p.x), core::mm_to_um(p.y)});
            s.print_lo = {std::min(s.print_lo.x, p.x), std::min(s.print_lo.y, p.y)};
            s.print_hi = {std::max(s.print_hi.x, p.x), std::max(s.print_hi.y, p.y)};
        }
    }
    s.print_index = detail::RegionDistance(s.print);
    const double half = std::max(l.thickness_max_mm, l.span.thickness()) / 2.0;
    s.cover = std::hypot(spacing * std::numbers::sqrt2 / 2.0, half / (planes - 1));
    for (const Vec2& q : sample_region(own, spacing)) {
        const geom2d::Point2 p{core::mm_to_um(q.x), core::mm_to_um(q.y)};
        for (int k = 0; k < planes; ++k) {
            const double h = -half + 2.0 * half * k / (planes - 1);
            const core::Vec3d x = l.plane.to_3d(p, h);
            s.samples.push_back(x);
            grow(s.lo, s.hi, x);
        }
    }
    // Chunks: the samples sorted by cells of kChunkSamples x spacing.
    {
        const double cell = kChunkSamples * spacing;
        std::vector<std::pair<std::array<std::int64_t, 3>, core::Vec3d>> keyed;
        keyed.reserve(s.samples.size());
        for (const core::Vec3d& x : s.samples) {
            keyed.push_back({{static_cast<std::int64_t>(std::floor((x.x - s.lo.x) / cell)),
                              static_cast<std::int64_t>(std::floor((x.y - s.lo.y) / cell)),
                              static_cast<std::int64_t>(std::floor((x.z - s.lo.z) / cell))},
                             x});
        }
        std::stable_sort(keyed.begin(), keyed.end(),
                         [](const auto& p, const auto& q) { return p.first < q.first; });
        for (std::size_t k = 0; k < keyed.size(); ++k) {
            s.samples[k] = keyed[k].second;
            if (k == 0 || keyed[k].first != keyed[k - 1].first) s.chunks.push_back({k, k, {}});
            s.chunks.back().end = k + 1;
        }
    }
    // Boxes in the layer's own frame, of each chunk and of the whole layer.
    s.axes[0] = l.plane.u;
    s.axes[1] = l.plane.v;
    s.axes[2] = l.plane.normal;
    const auto frame_box = [&](std::size_t begin, std::size_t end) {
        double lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
        for (std::size_t k = begin; k < end; ++k) {
            const core::Vec3d rel = s.samples[k] - l.plane.origin;
            for (int j = 0; j < 3; ++j) {
                const double c = core::dot(rel, s.axes[j]);
                lo[j] = std::min(lo[j], c);
                hi[j] = std::max(hi[j], c);
            }
        }
        FrameBox b;
        b.centre = l.plane.origin;
        for (int j = 0; j < 3; ++j) {
            b.centre += s.axes[j] * (0.5 * (lo[j] + hi[j]));
            b.half[j] = 0.5 * (hi[j] - lo[j]) + kBoxSlackMm;
        }
        return b;
    };
    for (SampleChunk& c : s.chunks) c.box = frame_box(c.begin, c.end);
    s.box = frame_box(0, s.samples.size());
    // Reach: the footprint's box on the top plane swept along d by the nozzle's length and
    // the clearance, grown by its widest radius and the clearance.
    const double a = nozzle.half_angle_deg * kDegToRad;
    const double length = nozzle.cone_length_mm + nozzle.body_length_mm + nozzle.clearance_mm;
    const double radius =
        std::max(nozzle.cone_length_mm * std::tan(a), nozzle.body_radius_mm) + nozzle.clearance_mm;
    core::Vec3d rlo{kInf, kInf, kInf}, rhi{-kInf, -kInf, -kInf};
    for (const double u : {s.print_lo.x, s.print_hi.x}) {
        for (const double v : {s.print_lo.y, s.print_hi.y}) {
            const core::Vec3d p = s.top.origin + s.top.u * u + s.top.v * v;
            grow(rlo, rhi, p);
            grow(rlo, rhi, p + s.d * length);
        }
    }
    s.reach_lo = rlo - core::Vec3d{radius, radius, radius};
    s.reach_hi = rhi + core::Vec3d{radius, radius, radius};
    return s;
}

// What the nozzle of S2 (standing anywhere on S2's top) meets of S1's material.
struct Meeting {
    double margin = kInf;  // smallest margin (mm, see stream_margin); +inf beyond kMarginCap;
                           // below the nozzle's clearance: the first sample found there
    core::Vec3d apex;
    core::Vec3d hit;
    bool in_stream = false;  // the hit lies in the powder stream (below the nozzle tip)
    double cover = 0.0;      // S1's cover, taken off the hardware's gap
};

// How S1's frame axes project on S2's axes (d, top.u, top.v): p[k][j] = |S2 axis k . S1
// axis j|, the extent along S2's axis k of a unit step along S1's axis j.
struct Projection {
    double p[3][3];
};

Projection projection(const LayerShape& s2, const LayerShape& s1) {
    const core::Vec3d to[3] = {s2.d, s2.top.u, s2.top.v};
    Projection out{};
    for (int k = 0; k < 3; ++k) {
        for (int j = 0; j < 3; ++j) out.p[k][j] = std::abs(core::dot(to[k], s1.axes[j]));
    }
    return out;
}

// The smallest margin any point of the box can have from S2's head (a lower bound), or +inf
// when the whole box lies on or under S2's top plane.
double box_bound(const LayerShape& s2, const Projection& pr, const FrameBox& b,
                 const detail::HeadProfile& head) {
    const core::Vec3d rel = b.centre - s2.top.origin;
    const double t = core::dot(rel, s2.d), u = core::dot(rel, s2.top.u),
                 v = core::dot(rel, s2.top.v);
    double r[3];
    for (int k = 0; k < 3; ++k) {
        r[k] =
            pr.p[k][0] * b.half[0] + pr.p[k][1] * b.half[1] + pr.p[k][2] * b.half[2] + kBoxSlackMm;
    }
    const double t_lo = t - r[0], t_hi = t + r[0];
    // METHOD.md condition 2: all of it on or under S2's top plane.
    if (t_hi <= kLevelTolerance) return kInf;
    const double gu = std::max({s2.print_lo.x - (u + r[1]), 0.0, (u - r[1]) - s2.print_hi.x});
    const double gv = std::max({s2.print_lo.y - (v + r[2]), 0.0, (v - r[2]) - s2.print_hi.y});
    return head.bound(t_lo, t_hi, std::sqrt(gu * gu + gv * gv)) - kBoxSlackMm;
}

// The margin of S1's samples is nozzle_margin_mm less S1's cover (a bound for the material
// around each sample, the hardware's distance being 1-Lipschitz), so an ordered layer keeps
// clearance_mm from the hardware everywhere, not only at the samples (decision 0023).
// `deepest`: measured to the smallest margin even below the clearance (a conflict's own
// figure); otherwise the first sample below the clearance ends it (the pair is ordered, how
// deep does not matter).
Meeting meet(const LayerShape& s2, const LayerShape& s1, const Nozzle& nozzle,
             const detail::HeadProfile& head, bool deepest = false) {
    Meeting m;
    const double cap = std::max(kMarginCap, 2.0 * nozzle.clearance_mm);
    const double cover = s1.cover;
    m.cover = cover;
    // Nothing of S1 comes within the cap: skip the pair; then chunk by chunk.
    const Projection pr = projection(s2, s1);
    if (box_bound(s2, pr, s1.box, head) - cover >= cap) return m;
    m.margin = cap;  // below this the samples are measured
    // The last footprint distance measured (mm) and where: the distance is 1-Lipschitz, so it
    // bounds the next samples' from below (the head's margin grows with the distance).
    Vec2 last_q{0.0, 0.0};
    double last_r = -kInf;
    for (const SampleChunk& chunk : s1.chunks) {
        if (box_bound(s2, pr, chunk.box, head) - cover >= m.margin) continue;
        for (std::size_t k = chunk.begin; k < chunk.end; ++k) {
            const core::Vec3d& x = s1.samples[k];
            const core::Vec3d rel = x - s2.top.origin;
            const double t = core::dot(rel, s2.d);
            if (t <= kLevelTolerance) continue;
            const Vec2 q{core::dot(rel, s2.top.u), core::dot(rel, s2.top.v)};
            // A lower bound of the distance to the footprint: the distance to its box.
            const double bx = std::max({s2.print_lo.x - q.x, 0.0, q.x - s2.print_hi.x});
            const double by = std::max({s2.print_lo.y - q.y, 0.0, q.y - s2.print_hi.y});
            const double box = std::sqrt(bx * bx + by * by);
            const double near = last_r - std::sqrt((q.x - last_q.x) * (q.x - last_q.x) +
                                                   (q.y - last_q.y) * (q.y - last_q.y));
            if (head.bound(t, t, std::max(box, near)) - cover >= m.margin) continue;
            // The distance to the footprint (0 inside) and its closest point, when it can be
            // short enough to lower the margin: below r_max (mm), padded for rounding.
            const double r_max = head.reach_within(t, m.margin + cover);
            if (!(r_max > 0.0)) continue;
            // Looked for a little beyond that: the distance then bounds the next samples'.
            const double limit_um =
                r_max * core::kMicronsPerMm * (1.0 + kLimitPadShare) + kLimitPadUm + kLookOnUm;
            const std::optional<geom2d::ClosestPoint> found = s2.print_index.closest(
                {q.x * core::kMicronsPerMm, q.y * core::kMicronsPerMm}, limit_um);
            last_q = q;
            if (!found) {
                last_r = limit_um / core::kMicronsPerMm;  // at least this far
                continue;
            }
            const geom2d::ClosestPoint& cp = *found;
            const double r = cp.distance_um / core::kMicronsPerMm;
            last_r = r;
            bool in_stream = false;
            const double here = head.margin(t, r, cover, &in_stream);
            if (here < m.margin) {
                m.margin = here;
                m.in_stream = in_stream;
                m.hit = x;
                m.apex = s2.top.origin + s2.top.u * core::um_to_mm(cp.point.x) +
                         s2.top.v * core::um_to_mm(cp.point.y);
                // A collision: the pair is ordered, how deep does not matter.
                if (!deepest && m.margin < nozzle.clearance_mm) return m;
            }
        }
    }
    if (m.margin >= cap) m.margin = kInf;
    return m;
}

// Which of the layers [first, first + count) lie below each layer in the graph (the layer is
// deposited on them, directly or not), as a bit row per layer: n x count bits, so the order
// walks the layers in blocks and the memory stays within kReachBudgetWords whatever n is.
class Ancestors {
public:
    Ancestors(const Plan& plan, const std::vector<int>& topo, int first, int count)
        : first_(first),
          words_((static_cast<std::size_t>(count) + 63) / 64),
          bits_(plan.layers.size() * words_, 0) {
        for (const int id : topo) {
            std::uint64_t* row = bits_.data() + static_cast<std::size_t>(id) * words_;
            for (const int p : plan.layers[static_cast<std::size_t>(id)].parents) {
                const std::uint64_t* prow = bits_.data() + static_cast<std::size_t>(p) * words_;
                for (std::size_t w = 0; w < words_; ++w) row[w] |= prow[w];
                if (p >= first && p - first < count) {
                    row[static_cast<std::size_t>(p - first) / 64] |= std::uint64_t{1}
                                                                     << ((p - first) % 64);
                }
            }
        }
    }
    // Whether b lies above a in the graph; a in [first, first + count).
    [[nodiscard]] bool descends(int b, int a) const {
        const auto k = static_cast<std::size_t>(a - first_);
        return ((bits_[static_cast<std::size_t>(b) * words_ + k / 64] >> (k % 64)) & 1U) != 0;
    }

private:
    int first_;
    std::size_t words_;
    std::vector<std::uint64_t> bits_;
};

// Whether b lies above a in the graph (a search from a; for the few pairs a report names).
bool descends(const Plan& plan, int b, int a) {
    std::vector<char> seen(plan.layers.size(), 0);
    std::vector<int> stack{a};
    while (!stack.empty()) {
        const int id = stack.back();
        stack.pop_back();
        for (const int c : plan.layers[static_cast<std::size_t>(id)].children) {
            if (c == b) return true;
            if (seen[static_cast<std::size_t>(c)] == 0) {
                seen[static_cast<std::size_t>(c)] = 1;
                stack.push_back(c);
            }
        }
    }
    return false;
}

// A pair the nozzle orders: `first` must be deposited before `second`, whose material its
// nozzle would meet.
struct CollisionEdge {
    int first = -1;
    int second = -1;
    Meeting meeting;
};

// The side (branch) of every layer: a layer continues its parent's side when it is the
// parent's only child, the parent its only parent, and both lie in the same region.
std::vector<int> sides_of(const Plan& plan, const std::vector<int>& topo) {
    std::vector<int> side(plan.layers.size(), -1);
    int next = 0;
    for (const int id : topo) {
        const Layer& l = plan.layers[static_cast<std::size_t>(id)];
        if (l.parents.size() == 1) {
            const Layer& p = plan.layers[static_cast<std::size_t>(l.parents.front())];
            if (p.children.size() == 1 && p.region == l.region) {
                side[static_cast<std::size_t>(id)] = side[static_cast<std::size_t>(p.id)];
                continue;
            }
        }
        side[static_cast<std::size_t>(id)] = next++;
    }
    return side;
}

std::string describe(const Plan& plan, int id) {
    const Layer& l = plan.layers[static_cast<std::size_t>(id)];
    return fmt::format("layer {} (region {}, slice {})", id, l.region, l.index_in_region);
}

// Kahn's algorithm over the precedence `after`, preferring the current side, then region,
// then direction: out.order, and per layer the parents left unordered (indegree, all 0 when
// every layer is ordered).
void order_kahn(const Plan& plan, const std::vector<std::vector<int>>& after, BuildOrder& out,
                std::vector<int>& indegree) {
    const std::size_t n = plan.layers.size();
    std::fill(indegree.begin(), indegree.end(), 0);
    for (const std::vector<int>& a : after) {
        for (const int c : a) ++indegree[static_cast<std::size_t>(c)];
    }
    std::vector<int> ready;
    for (std::size_t i = 0; i < n; ++i) {
        if (indegree[i] == 0) ready.push_back(static_cast<int>(i));
    }
    int last = -1;
    const auto key = [&](int id) {
        const Layer& l = plan.layers[static_cast<std::size_t>(id)];
        int rank = 3;
        if (last >= 0) {
            const Layer& p = plan.layers[static_cast<std::size_t>(last)];
            if (out.side_of[static_cast<std::size_t>(id)] ==
                out.side_of[static_cast<std::size_t>(last)]) {
                rank = 0;
            } else if (l.region == p.region) {
                rank = 1;
            } else if (core::dot(l.top.normal, p.top.normal) > 1.0 - 1e-9) {
                rank = 2;
            }
        }
        return std::tuple(rank, l.region, l.index_in_region, id);
    };
    out.order.clear();
    out.order.reserve(n);
    while (!ready.empty()) {
        const auto best = std::min_element(ready.begin(), ready.end(),
                                           [&](int a, int b) { return key(a) < key(b); });
        const int id = *best;
        *best = ready.back();
        ready.pop_back();
        out.order.push_back(id);
        last = id;
        for (const int c : after[static_cast<std::size_t>(id)]) {
            if (--indegree[static_cast<std::size_t>(c)] == 0) ready.push_back(c);
        }
    }
}

// Stuck: a cycle among the layers left unordered. Walks back along "must follow" from one of
// them until a layer repeats; returns the collisions on that cycle.
std::vector<const CollisionEdge*> stuck_cycle(
    const Plan& plan, const std::vector<std::vector<CollisionEdge>>& collisions_into,
    const std::vector<int>& indegree) {
    const std::size_t n = plan.layers.size();
    std::vector<std::vector<std::pair<int, const CollisionEdge*>>> before(n);
    for (const Layer& l : plan.layers) {
        for (const int c : l.children)
            before[static_cast<std::size_t>(c)].push_back({l.id, nullptr});
    }
    for (std::size_t i = 0; i < n; ++i) {
        for (const CollisionEdge& e : collisions_into[i]) before[i].push_back({e.first, &e});
    }
    int start = -1;
    for (std::size_t i = 0; i < n && start < 0; ++i) {
        if (indegree[i] > 0) start = static_cast<int>(i);
    }
    std::vector<int> seen(n, -1);
    std::vector<std::pair<int, const CollisionEdge*>> walk;
    int at = start;
    while (seen[static_cast<std::size_t>(at)] < 0) {
        seen[static_cast<std::size_t>(at)] = static_cast<int>(walk.size());
        for (const auto& [p, e] : before[static_cast<std::size_t>(at)]) {
            if (indegree[static_cast<std::size_t>(p)] > 0) {
                walk.push_back({at, e});
                at = p;
                break;
            }
        }
    }
    std::vector<const CollisionEdge*> out;
    for (std::size_t k = static_cast<std::size_t>(seen[static_cast<std::size_t>(at)]);
         k < walk.size(); ++k) {
        if (walk[k].second != nullptr) out.push_back(walk[k].second);
    }
    return out;
}

// The conflicts of a cycle of collisions, for people.
void name_conflicts(const Plan& plan, const std::vector<const CollisionEdge*>& cycle,
                    const std::vector<LayerShape>& shapes, const Nozzle& nozzle,
                    const detail::HeadProfile& head, BuildOrder& out) {
    for (const CollisionEdge* e : cycle) {
        Conflict c;
        c.layer = e->first;
        c.other = e->second;
        // The pair's deepest meeting: the edge's is the first sample found below the
        // clearance, which says nothing of how far in the head would reach.
        const Meeting deep = meet(shapes[static_cast<std::size_t>(c.layer)],
                                  shapes[static_cast<std::size_t>(c.other)], nozzle, head, true);
        const Meeting& mt = deep.margin < e->meeting.margin ? deep : e->meeting;
        c.apex = mt.apex;
        c.hit = mt.hit;
        c.in_stream = mt.in_stream;
        c.cover_mm = mt.cover;
        c.margin_mm = mt.margin - (c.in_stream ? nozzle.clearance_mm : 0.0);
        c.reason = fmt::format(
            "the {} on {} at ({:.2f}, {:.2f}, {:.2f}) would meet {} at ({:.2f}, {:.2f}, "
            "{:.2f}) (clearance {:.2f} mm < {:.2f}), so {} must come first, yet {} must come "
            "before it ({})",
            c.in_stream ? "powder stream" : "nozzle", describe(plan, c.layer), c.apex.x, c.apex.y,
            c.apex.z, describe(plan, c.other), c.hit.x, c.hit.y, c.hit.z, c.margin_mm,
            c.in_stream ? 0.0 : nozzle.clearance_mm, describe(plan, c.layer),
            describe(plan, c.other),
            descends(plan, c.layer, c.other) ? "it is deposited on it"
                                             : "through the other conflicts listed");
        out.conflicts.push_back(std::move(c));
    }
}

}  // namespace

double BuildOrder::smallest_margin_mm() const {
    double m = kInf;
    for (const int id : order) m = std::min(m, margin_mm[static_cast<std::size_t>(id)]);
    return m;
}

core::Result<BuildOrder> order_layers(const Plan& plan, const OrderSettings& settings,
                                      const core::Progress* progress) {
    if (auto ok = validate(settings.nozzle); !ok) return std::unexpected(ok.error());
    const Nozzle& nozzle = settings.nozzle;
    const detail::HeadProfile head(nozzle);
    const double spacing = settings.sample_spacing_mm > 0.0 ? settings.sample_spacing_mm
                                                            : plan.settings.track_width_mm / 2.0;
    if (!(spacing > 0.0) || !std::isfinite(spacing)) {
        return core::fail(core::ErrorCode::kInvalidInput,
                          "the sample spacing must be a positive number of mm", "build order");
    }
    const std::size_t n = plan.layers.size();
    const std::vector<int> topo = topological_order(plan);
    if (topo.size() != n) {
        return core::fail(core::ErrorCode::kInternal,
                          "the hierarchy graph has a cycle (a bug in maxslice)", "build order");
    }
    if (n > kMaxLayers) {
        return core::fail(core::ErrorCode::kInvalidInput,
                          fmt::format("{} layers are more than the collision check handles ({}): "
                                      "use thicker layers or split the part",
                                      n, kMaxLayers),
                          "build order");
    }
    const auto cancelled = [&] { return progress != nullptr && progress->cancelled(); };

    // The layers left bare (on nothing, no track fits: nothing is laid there) hold no bead:
    // the nozzle never stands on them and they are in nobody's way.
    std::vector<char> bare(n, 0);
    for (const int id : plan.bare_unsupported_layers) {
        if (id >= 0 && static_cast<std::size_t>(id) < n) bare[static_cast<std::size_t>(id)] = 1;
    }
    std::vector<LayerShape> shapes(n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
        if (!cancelled() && bare[i] == 0) {
            shapes[i] = shape_of(plan.layers[i], nozzle, spacing, plan.settings.track_width_mm);
        }
    });
    if (cancelled()) return core::fail(core::ErrorCode::kCancelled, "cancelled", "build order");
    // The layers with samples, by their boxes: the candidates of each nozzle.
    const detail::BoxTree tree = [&] {
        std::vector<core::Vec3d> lo(n), hi(n);
        for (std::size_t i = 0; i < n; ++i) {
            lo[i] = shapes[i].samples.empty() ? core::Vec3d{kInf, kInf, kInf} : shapes[i].lo;
            hi[i] = shapes[i].samples.empty() ? core::Vec3d{-kInf, -kInf, -kInf} : shapes[i].hi;
        }
        return detail::BoxTree(lo, hi);
    }();

    // Every pair (S2, S1) where S1 may be in place when S2 is deposited (S1 is not above S2
    // in the graph) and S2's nozzle can reach S1's box: the exact check.
    std::vector<std::vector<std::pair<int, Meeting>>> meets(n);
    std::atomic<std::size_t> done{0};
    // In blocks of S2 whose ancestor rows fit the budget.
    const std::size_t block = std::clamp<std::size_t>(
        kReachBudgetWords / std::max<std::size_t>(n, 1) * 64, 64, std::max<std::size_t>(n, 64));
    for (std::size_t b0 = 0; b0 < n; b0 += block) {
        const std::size_t b1 = std::min(n, b0 + block);
        const Ancestors below(plan, topo, static_cast<int>(b0), static_cast<int>(b1 - b0));
        tbb::parallel_for(b0, b1, [&](std::size_t i) {
            if (cancelled()) return;
            const int s2 = static_cast<int>(i);
            const LayerShape& a = shapes[i];
            std::vector<int> candidates;
            if (bare[i] == 0) {
                tree.visit(
                    [&](const core::Vec3d& lo, const core::Vec3d& hi) {
                        return boxes_meet(a.reach_lo, a.reach_hi, lo, hi);
                    },
                    [&](std::uint32_t s1) {
                        if (static_cast<int>(s1) != s2 &&
                            boxes_meet(a.reach_lo, a.reach_hi, shapes[s1].lo, shapes[s1].hi)) {
                            candidates.push_back(static_cast<int>(s1));
                        }
                    });
            }
            std::sort(candidates.begin(), candidates.end());
            for (const int s1 : candidates) {
                if (below.descends(s1, s2)) continue;  // S1 comes after S2 in any order
                const Meeting m = meet(a, shapes[static_cast<std::size_t>(s1)], nozzle, head);
                if (m.margin < kInf) meets[i].emplace_back(s1, m);
            }
            if (progress != nullptr) {
                progress->report("build order",
                                 0.9 * static_cast<double>(++done) / static_cast<double>(n));
            }
        });
    }
    if (cancelled()) return core::fail(core::ErrorCode::kCancelled, "cancelled", "build order");

    // Precedence: the graph's edges and, for every S2 whose nozzle would meet S1 closer than
    // the clearance, S2 before S1.
    BuildOrder out;
    std::vector<std::vector<int>> after(n);  // after[a]: layers that must follow a
    std::vector<std::vector<CollisionEdge>> collisions_into(n);  // by `second`
    for (const Layer& l : plan.layers) {
        for (const int c : l.children) after[static_cast<std::size_t>(l.id)].push_back(c);
    }
    for (std::size_t i = 0; i < n; ++i) {
        for (const auto& [s1, m] : meets[i]) {
            if (m.margin >= nozzle.clearance_mm) continue;
            after[i].push_back(s1);
            collisions_into[static_cast<std::size_t>(s1)].push_back({static_cast<int>(i), s1, m});
            ++out.collision_edges;
        }
    }
    out.side_of = sides_of(plan, topo);
    std::vector<int> indegree(n, 0);
    // Ordered; when stuck, the collisions on a cycle whose margin the samples' cover leaves in
    // doubt are measured again finer, and those that then keep the clearance are dropped.
    int remeasured = 0;
    std::vector<std::pair<int, int>> measured_finer;  // (first, second), sorted
    for (;;) {
        order_kahn(plan, after, out, indegree);
        if (out.order.size() == n) break;
        std::vector<const CollisionEdge*> cycle = stuck_cycle(plan, collisions_into, indegree);
        bool dropped = false;
        for (const CollisionEdge* e : cycle) {
            const std::pair<int, int> pair{e->first, e->second};
            if (!settings.measure_doubtful_again || remeasured >= kMaxRemeasured ||
                e->meeting.margin + e->meeting.cover < nozzle.clearance_mm ||
                std::binary_search(measured_finer.begin(), measured_finer.end(), pair)) {
                continue;
            }
            measured_finer.insert(
                std::lower_bound(measured_finer.begin(), measured_finer.end(), pair), pair);
            ++remeasured;
            const LayerShape finer =
                shape_of(plan.layers[static_cast<std::size_t>(e->second)], nozzle,
                         spacing / kFinerSamples, plan.settings.track_width_mm, kFinerPlanes);
            const Meeting m = meet(shapes[static_cast<std::size_t>(e->first)], finer, nozzle, head);
            if (m.margin < nozzle.clearance_mm) continue;
            // Keeps the clearance: no longer an edge; its margin is the finer one.
            for (auto& [s1, kept] : meets[static_cast<std::size_t>(e->first)]) {
                if (s1 == e->second) kept = m;
            }
            std::vector<int>& a = after[static_cast<std::size_t>(e->first)];
            a.erase(std::find(a.begin(), a.end(), e->second));
            std::vector<CollisionEdge>& into = collisions_into[static_cast<std::size_t>(e->second)];
            into.erase(into.begin() + (e - into.data()));
            --out.collision_edges;
            dropped = true;
            break;  // the cycle's other edges point into the vector changed
        }
        if (!dropped) {
            name_conflicts(plan, cycle, shapes, nozzle, head, out);
            break;
        }
    }

    // Margins against what is in place, sections, jumps.
    std::vector<int> rank(n, -1);
    for (std::size_t k = 0; k < out.order.size(); ++k)
        rank[static_cast<std::size_t>(out.order[k])] = static_cast<int>(k);
    out.margin_mm.assign(n, std::numeric_limits<double>::quiet_NaN());
    for (const int id : out.order) {
        double m = kInf;
        for (const auto& [s1, meeting] : meets[static_cast<std::size_t>(id)]) {
            const int r1 = rank[static_cast<std::size_t>(s1)];
            if (r1 >= 0 && r1 < rank[static_cast<std::size_t>(id)]) m = std::min(m, meeting.margin);
        }
        out.margin_mm[static_cast<std::size_t>(id)] = m;
    }
    out.section_of.assign(n, -1);
    std::vector<char> used(plan.regions.size(), 0);
    for (std::size_t k = 0; k < out.order.size(); ++k) {
        const int id = out.order[k];
        const Layer& l = plan.layers[static_cast<std::size_t>(id)];
        used[static_cast<std::size_t>(l.region)] = 1;
        if (k > 0 && plan.layers[static_cast<std::size_t>(out.order[k - 1])].region != l.region)
            ++out.jumps;
        if (out.sections.empty() ||
            out.sections.back().side != out.side_of[static_cast<std::size_t>(id)]) {
            Section s;
            s.id = static_cast<int>(out.sections.size());
            s.side = out.side_of[static_cast<std::size_t>(id)];
            s.region = l.region;
            out.sections.push_back(std::move(s));
        }
        out.sections.back().layers.push_back(id);
        out.section_of[static_cast<std::size_t>(id)] = out.sections.back().id;
    }
    int regions_used = 0;
    for (const Region& r : plan.regions) regions_used += r.layers.empty() ? 0 : 1;
    out.min_jumps = std::max(0, regions_used - 1);
    if (progress != nullptr) progress->report("build order", 1.0);
    return out;
}

}  // namespace maxslice::plan
