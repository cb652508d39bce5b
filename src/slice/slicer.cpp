// Mesh slicing: METHOD.md sections 1 and 2.
//
// The algorithm follows Minetto et al. (2017), "An optimal algorithm for 3D triangle mesh
// slicing": triangles are bucketed by the range of planes they cross (O(n log k) with a
// binary search per vertex, then a counting sort that writes each triangle's segments
// straight into its planes' buckets, while the triangle is in cache), each plane is cut
// independently (in parallel), and its segments are chained into loops through a hash table
// keyed on the mesh edge (the pair of vertex ids) each segment starts on: O(n log k + m) in
// all, with no rounding of coordinates involved in the topology.
//
// Degenerate positions are resolved by symbolic perturbation: a vertex counts as "above" a
// plane at height h only when its height is > h, so a plane through a vertex, an edge or a
// whole face behaves like a plane an infinitesimal step above it. Every triangle then
// crosses a plane in exactly zero or two of its edges, and two triangles sharing an edge
// agree on whether it is crossed, so loops close on any closed mesh.
#include "maxslice/slice/slicer.hpp"

#include <fmt/format.h>
#include <sys/resource.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <string>
#include <tuple>
#include <utility>

#include <unistd.h>

#include "maxslice/core/assert.hpp"
#include "maxslice/core/tolerances.hpp"
#include "maxslice/core/units.hpp"

namespace maxslice::slice {
namespace {

using geom2d::Path2;
using geom2d::Paths2;
using geom2d::Point2;

// A segment of the cut in one triangle: it enters the triangle across edge `from` and
// leaves it across edge `to` (both undirected edge keys), solid on its left. Plain integers
// (no default member initialisers), so an array of them is allocated without clearing. The
// crossing point is kept in 32 bits (24 bytes a segment, not 32: the segments are the largest
// array of the cut, written once and read once); prepare() refuses a part whose points do
// not fit, over 2 km from the frame's origin.
struct Segment {
    std::uint64_t from;
    std::uint64_t to;
    std::int32_t x, y;  // the crossing point on edge `from` (um)

    Point2 start() const { return {x, y}; }
};

// The largest coordinate a segment holds (um): 2^31 - 1, about 2.1 km.
constexpr std::int64_t kMaxSegmentUm = std::numeric_limits<std::int32_t>::max();

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
    const std::uint32_t lo = std::min(a, b), hi = std::max(a, b);
    return (static_cast<std::uint64_t>(lo) << 32) | hi;
}

// Per-mesh data shared by all planes: vertex heights along the normal (mm; computed here, or
// those base_frame_and_extent computed for the same frame), and for each
// plane (in sorted order) the segments of the triangles that cross it, in triangle order:
// plane k's are segs[bucket_begin[k], bucket_begin[k + 1]). In-plane coordinates are kept
// per vertex only when the planes cut more edges than the mesh has vertices (a coarse mesh
// or thin layers: each vertex is then used many times); otherwise they are computed for the
// vertices of each crossed edge (most vertices of a fine mesh lie on no crossed edge, and a
// table of them would be the largest array of the cut). Both give the same bits.
struct CutContext {
    const mesh::TriangleMesh* mesh = nullptr;
    PlaneFrame base;
    std::shared_ptr<const double[]> height;
    std::unique_ptr<double[]> uv;  // u, v of every vertex (mm), or null
    std::vector<double> sorted_heights;
    std::vector<std::size_t> bucket_begin;  // size planes + 1
    std::unique_ptr<Segment[]> segs;        // uninitialised until written: no zeroing pass
};

// Vertex i's in-plane coordinates (mm): from the table when there is one, else computed
// (the table holds the same computation's results).
std::pair<double, double> vertex_uv(const CutContext& ctx, std::uint32_t i) {
    if (ctx.uv) return {ctx.uv[2 * i], ctx.uv[2 * i + 1]};
    const core::Vec3d d = ctx.mesh->vertices[i] - ctx.base.origin;
    return {core::dot(d, ctx.base.u), core::dot(d, ctx.base.v)};
}

// The point where the plane at height h crosses edge (a, b), in millimetres. It is computed
// from the lower vertex id to the higher one so both triangles of the edge get equal bits.
// Inlined: it is the inner step of the segment fill.
[[gnu::always_inline]] inline std::pair<double, double> crossing_mm(const CutContext& ctx,
                                                                    std::uint32_t a,
                                                                    std::uint32_t b, double h) {
    if (a > b) std::swap(a, b);
    const double ha = ctx.height[a], hb = ctx.height[b];
    const auto [ua, va] = vertex_uv(ctx, a);
    const auto [ub, vb] = vertex_uv(ctx, b);
    const double t = (h - ha) / (hb - ha);
    const double u = ua + (ub - ua) * t;
    const double v = va + (vb - va) * t;
    return {u, v};
}

// The same point in micrometres.
Point2 crossing(const CutContext& ctx, std::uint32_t a, std::uint32_t b, double h) {
    const auto [u, v] = crossing_mm(ctx, a, b, h);
    return {core::mm_to_um(u), core::mm_to_um(v)};
}

// The segment of triangle tri in the plane at height h, which the triangle crosses
// (min height <= h < max height, three distinct vertices). `fits` is cleared when its point
// is too far out for a Segment (and left alone otherwise).
Segment segment_of(const CutContext& ctx, const std::array<std::uint32_t, 3>& tri, double h,
                   bool& fits) {
    // Walking the triangle's edges in winding order, the cut enters where an edge goes from
    // above the plane to below it and leaves where an edge goes back up; with the outward
    // normal from the winding, the solid is then on the left (seen from +normal). With the
    // vertex heights straddling h, exactly one edge goes down and one goes up.
    std::uint32_t fa = 0, fb = 0, ta = 0, tb = 0;
    for (int e = 0; e < 3; ++e) {
        const std::uint32_t a = tri[static_cast<std::size_t>(e)];
        const std::uint32_t b = tri[static_cast<std::size_t>((e + 1) % 3)];
        const bool above_a = ctx.height[a] > h, above_b = ctx.height[b] > h;
        if (above_a && !above_b) {
            fa = a, fb = b;
        } else if (!above_a && above_b) {
            ta = a, tb = b;
        }
    }
    const auto [u, v] = crossing_mm(ctx, fa, fb, h);
    // Within kMaxSegmentUm once rounded (false for NaN); not converted otherwise.
    constexpr double kMaxMm = static_cast<double>(kMaxSegmentUm - 1) / core::kMicronsPerMm;
    const bool in = std::fabs(u) <= kMaxMm && std::fabs(v) <= kMaxMm;
    fits &= in;
    return {edge_key(fa, fb), edge_key(ta, tb),
            in ? static_cast<std::int32_t>(core::mm_to_um(u)) : 0,
            in ? static_cast<std::int32_t>(core::mm_to_um(v)) : 0};
}

// Refuses, before the segments are made, a cut whose contours would not fit in memory: each
// crossing of a triangle and a plane holds its segment, then a loop point, a tree point and
// an edge-table slot until the plane's tree is built, about kBytesPerCrossing in all at the
// peak. The budget is half the machine's memory (or of the process's address-space limit).
constexpr double kBytesPerCrossing = 96.0;

core::Result<void> check_cut_memory(std::size_t crossings, std::size_t planes) {
    double budget = static_cast<double>(::sysconf(_SC_PHYS_PAGES)) *
                    static_cast<double>(::sysconf(_SC_PAGESIZE));
    struct rlimit lim {};
    if (::getrlimit(RLIMIT_AS, &lim) == 0 && lim.rlim_cur != RLIM_INFINITY) {
        budget = std::min(budget, static_cast<double>(lim.rlim_cur));
    }
    budget *= 0.5;
    const double need = kBytesPerCrossing * static_cast<double>(crossings);
    if (budget > 0.0 && need > budget) {
        return core::fail(
            core::ErrorCode::kInvalidInput,
            fmt::format("the {} layers cross the mesh's triangles {} times, about {:.1f} GB of "
                        "contours, more than the {:.1f} GB this job may use (half the memory): "
                        "use thicker layers (--layer) or a coarser mesh",
                        planes, crossings, need * 1e-9, budget * 1e-9),
            "slicing");
    }
    return {};
}

// vertex_heights: every vertex's base.height, or null to compute them here.
core::Result<CutContext> prepare(const mesh::TriangleMesh& mesh, const PlaneFrame& base,
                                 std::span<const double> heights,
                                 std::shared_ptr<const double[]> vertex_heights) {
    CutContext ctx;
    ctx.mesh = &mesh;
    ctx.base = base;
    for (const double h : heights) {
        if (!std::isfinite(h)) {
            return core::fail(core::ErrorCode::kInvalidInput, "a plane height is not finite",
                              "slicing");
        }
    }
    if (heights.size() > kMaxLayers) {
        return core::fail(core::ErrorCode::kInvalidInput,
                          fmt::format("{} planes are more than the {} a job may cut: use thicker "
                                      "layers",
                                      heights.size(), kMaxLayers),
                          "slicing");
    }
    ctx.sorted_heights.assign(heights.begin(), heights.end());
    std::sort(ctx.sorted_heights.begin(), ctx.sorted_heights.end());
    const auto& hs = ctx.sorted_heights;
    const std::size_t nt = mesh.triangles.size();
    const std::size_t np = hs.size();

    // lower_bound(x) over the planes: the first plane with h >= x. A table of lower bounds at
    // 4 bins per plane gives a start index close to the answer; short scans make it exact (the
    // same result as std::lower_bound). With evenly spaced planes a bin holds at most one
    // plane, so one step (without a branch: `padded` ends with +infinity) is all it takes.
    const double h0 = np > 0 ? hs.front() : 0.0;
    const std::size_t bins = 4 * np + 1;
    const double width = np >= 2 ? (hs.back() - h0) / static_cast<double>(bins - 1) : 0.0;
    const double per_width = width > 0.0 ? 1.0 / width : 0.0;
    std::vector<std::uint32_t> bin_start(bins, 0);
    if (width > 0.0) {
        for (std::size_t b = 0; b < bins; ++b) {
            const double x = h0 + width * static_cast<double>(b);
            bin_start[b] =
                static_cast<std::uint32_t>(std::lower_bound(hs.begin(), hs.end(), x) - hs.begin());
        }
    }
    std::vector<double> padded(hs);
    padded.push_back(std::numeric_limits<double>::infinity());
    const auto lower_bound = [&](double x) -> std::uint32_t {
        if (!(width > 0.0)) {
            return static_cast<std::uint32_t>(std::lower_bound(hs.begin(), hs.end(), x) -
                                              hs.begin());
        }
        // The bin, clamped to the table (NaN to bin 0, whose start is plane 0: the answer).
        double q = (x - h0) * per_width;
        q = q >= 0.0 ? q : 0.0;
        q = q < static_cast<double>(bins - 1) ? q : static_cast<double>(bins - 1);
        std::size_t k = bin_start[static_cast<std::size_t>(q)];
        k += padded[k] < x ? 1 : 0;
        while (padded[k] < x) ++k;
        while (k > 0 && hs[k - 1] >= x) --k;  // guards rounding in the bin computation
        return static_cast<std::uint32_t>(k);
    };

    // Every vertex's height and the first plane at or above it. lower_bound is monotone, so a
    // triangle's plane range [lower_bound(min), lower_bound(max)), the planes with
    // min <= h < max, is [the least of its vertices' bounds, the greatest): no search per
    // triangle. A non-finite coordinate gives a height that is not finite (NaN or infinite).
    const std::size_t nv = mesh.vertices.size();
    const auto vertex_plane = std::make_unique_for_overwrite<std::uint32_t[]>(nv);
    std::atomic<bool> finite{true};
    if (vertex_heights) {
        ctx.height = std::move(vertex_heights);
    } else {
        auto h = std::make_shared_for_overwrite<double[]>(nv);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 1 << 14), [&](const auto& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) h[i] = base.height(mesh.vertices[i]);
        });
        ctx.height = std::move(h);
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 1 << 14), [&](const auto& r) {
        bool ok = true;
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            vertex_plane[i] = lower_bound(ctx.height[i]);
            ok &= std::isfinite(ctx.height[i]);
        }
        if (!ok) finite.store(false);
    });
    if (!finite.load()) {
        return core::fail(core::ErrorCode::kInvalidInput,
                          "the mesh has NaN or infinite vertex coordinates", "slicing");
    }
    // Plane range [k0, k1) of triangle t; empty for a triangle with a repeated vertex (its
    // crossing edges are one edge: no segment). Computed in both passes below rather than
    // stored (two arrays the size of the mesh, written once and read once).
    const auto planes_of = [&](std::size_t t) -> std::pair<std::uint32_t, std::uint32_t> {
        const auto& tri = mesh.triangles[t];
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) return {0, 0};
        const std::uint32_t a = vertex_plane[tri[0]], b = vertex_plane[tri[1]],
                            c = vertex_plane[tri[2]];
        return {std::min({a, b, c}), std::max({a, b, c})};
    };
    // Counting sort of (plane, triangle) pairs, in parallel over fixed chunks of triangles:
    // each chunk counts its triangles per plane, and a chunk's segments of a plane go after
    // those of the chunks before it, so every plane lists its segments in triangle order
    // whatever the number of chunks or threads.
    const std::size_t chunk = std::max<std::size_t>(std::size_t{1} << 15, (nt + 63) / 64);
    const std::size_t chunks = (nt + chunk - 1) / chunk;
    // counts[c * (np + 1) + k]: chunk c's triangles that cross plane k (first as differences).
    std::vector<std::uint32_t> counts(chunks * (np + 1), 0);
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
        std::uint32_t* d = counts.data() + c * (np + 1);
        for (std::size_t t = c * chunk, end = std::min(nt, t + chunk); t < end; ++t) {
            const auto [k0, k1] = planes_of(t);
            ++d[k0];
            --d[k1];
        }
        std::uint32_t run = 0;
        for (std::size_t k = 0; k <= np; ++k) d[k] = run += d[k];
    });
    ctx.bucket_begin.assign(np + 1, 0);
    std::vector<std::size_t> offsets(chunks * (np + 1));
    std::size_t total = 0;
    for (std::size_t k = 0; k < np; ++k) {
        ctx.bucket_begin[k] = total;
        for (std::size_t c = 0; c < chunks; ++c) {
            offsets[c * (np + 1) + k] = total;
            total += counts[c * (np + 1) + k];
        }
    }
    ctx.bucket_begin[np] = total;
    if (auto ok = check_cut_memory(total, np); !ok) return std::unexpected(ok.error());
    if (total > nv) {
        auto uv = std::make_unique_for_overwrite<double[]>(2 * nv);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 1 << 14), [&](const auto& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                const auto [u, v] = vertex_uv(ctx, static_cast<std::uint32_t>(i));
                uv[2 * i] = u;
                uv[2 * i + 1] = v;
            }
        });
        ctx.uv = std::move(uv);
    }
    ctx.segs = std::make_unique_for_overwrite<Segment[]>(total);
    std::atomic<bool> fits{true};
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
        std::size_t* fill = offsets.data() + c * (np + 1);
        bool ok = true;
        for (std::size_t t = c * chunk, end = std::min(nt, t + chunk); t < end; ++t) {
            const auto [k0, k1] = planes_of(t);
            for (std::uint32_t k = k0; k < k1; ++k) {
                ctx.segs[fill[k]++] = segment_of(ctx, mesh.triangles[t], hs[k], ok);
            }
        }
        if (!ok) fits.store(false);
    });
    if (!fits.load()) {
        return core::fail(core::ErrorCode::kInvalidInput,
                          "the part reaches more than 2 km from the slicing frame's origin "
                          "(check the file's units: --units)",
                          "slicing");
    }
    return ctx;
}

// Open addressing table from an edge key to the segments that start on that edge (more than
// one only at non-manifold edges; they are linked through `next`). Each used slot keeps its
// key beside it, so a probe reads the table only.
class EdgeTable {
public:
    explicit EdgeTable(std::span<const Segment> segs) {
        std::size_t cap = 16;
        shift_ = 60;
        while (cap < 2 * segs.size()) cap <<= 1, --shift_;
        mask_ = cap - 1;
        slots_.assign(cap, kEmpty);
        keys_ = std::make_unique_for_overwrite<std::uint64_t[]>(cap);  // read where used only
        next_.assign(segs.size(), kEmpty);
        // Insert in reverse so each chain of equal keys lists segments in index order.
        for (std::size_t i = segs.size(); i-- > 0;) {
            const std::uint64_t key = segs[i].from;
            const std::size_t s = slot_of(key);
            next_[i] = slots_[s];
            slots_[s] = static_cast<std::uint32_t>(i);
            keys_[s] = key;
        }
    }
    // The first segment starting on edge key that is not used yet, or kEmpty.
    std::uint32_t find_unused(std::uint64_t key, const std::vector<char>& used) const {
        for (std::uint32_t i = slots_[slot_of(key)]; i != kEmpty; i = next_[i]) {
            if (!used[i]) return i;
        }
        return kEmpty;
    }
    // The one segment starting on edge key, kEmpty when none does, kMany when several do
    // (find_unused then picks).
    std::uint32_t find_only(std::uint64_t key) const {
        const std::uint32_t i = slots_[slot_of(key)];
        return i == kEmpty || next_[i] == kEmpty ? i : kMany;
    }
    static constexpr std::uint32_t kEmpty = std::numeric_limits<std::uint32_t>::max();
    static constexpr std::uint32_t kMany = kEmpty - 1;

private:
    // Fibonacci hashing: the top bits of the product, which depend on every bit of the key.
    std::size_t hash(std::uint64_t key) const {
        return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ULL) >> shift_);
    }
    // The slot holding key, or the empty slot where it would go (linear probing).
    std::size_t slot_of(std::uint64_t key) const {
        std::size_t s = hash(key);
        while (slots_[s] != kEmpty && keys_[s] != key) s = (s + 1) & mask_;
        return s;
    }
    std::size_t mask_ = 0;
    int shift_ = 60;
    std::vector<std::uint32_t> slots_;
    std::unique_ptr<std::uint64_t[]> keys_;
    std::vector<std::uint32_t> next_;
};

void drop_repeated_points(Path2& path) {
    path.erase(std::unique(path.begin(), path.end()), path.end());
    while (path.size() > 1 && path.front() == path.back()) path.pop_back();
}

double distance_um(const Point2& a, const Point2& b) {
    return std::hypot(static_cast<double>(a.x - b.x), static_cast<double>(a.y - b.y));
}

// Rejoins the pieces of one open run that were started in the middle: a piece that ends
// exactly where another starts continues into it. Runs that form a cycle become loops.
std::vector<Path2> join_exact(std::vector<Path2>& open, PlaneCut& cut) {
    std::vector<std::pair<Point2, std::size_t>> starts;
    starts.reserve(open.size());
    for (std::size_t i = 0; i < open.size(); ++i) starts.emplace_back(open[i].front(), i);
    std::sort(starts.begin(), starts.end());
    const std::size_t none = open.size();
    std::vector<std::size_t> next(open.size(), none);
    std::vector<char> has_prev(open.size(), 0);
    for (std::size_t i = 0; i < open.size(); ++i) {
        auto it = std::lower_bound(starts.begin(), starts.end(),
                                   std::make_pair(open[i].back(), std::size_t{0}));
        for (; it != starts.end() && it->first == open[i].back(); ++it) {
            if (it->second != i && !has_prev[it->second]) {
                next[i] = it->second;
                has_prev[it->second] = 1;
                break;
            }
        }
    }
    std::vector<Path2> runs;
    std::vector<char> done(open.size(), 0);
    auto walk = [&](std::size_t head) {
        Path2 run;
        std::size_t i = head;
        while (i != none && !done[i]) {
            done[i] = 1;
            run.insert(run.end(), open[i].begin(), open[i].end());
            i = next[i];
        }
        return std::make_pair(std::move(run), i == head);
    };
    for (std::size_t i = 0; i < open.size(); ++i) {
        if (!has_prev[i] && !done[i]) runs.push_back(walk(i).first);
    }
    for (std::size_t i = 0; i < open.size(); ++i) {
        if (done[i]) continue;
        auto [run, cycle] = walk(i);  // every piece has a predecessor: a closed cycle
        drop_repeated_points(run);
        if (cycle && run.size() >= 3) cut.loops.push_back(std::move(run));
    }
    return runs;
}

// Closes open chains (from open meshes: holes in scans, cracks) end to start when the gap is
// below the closing tolerance, nearest first; chains that cannot be closed are dropped and
// counted.
void close_open_chains(std::vector<Path2>& open, double max_gap_mm, PlaneCut& cut) {
    const double tol = max_gap_mm * core::kMicronsPerMm;
    std::vector<char> taken(open.size(), 0);
    for (std::size_t i = 0; i < open.size(); ++i) {
        if (taken[i]) continue;
        taken[i] = 1;
        Path2 chain = std::move(open[i]);
        int joins = 0;
        while (true) {
            const Point2 end = chain.back();
            double best = distance_um(end, chain.front());
            std::size_t best_j = open.size();
            for (std::size_t j = 0; j < open.size(); ++j) {
                if (taken[j]) continue;
                const double d = distance_um(end, open[j].front());
                if (d < best) best = d, best_j = j;
            }
            if (best > tol) break;
            ++joins;
            if (best_j == open.size()) {  // nearest is our own start: close
                drop_repeated_points(chain);
                if (chain.size() >= 3) {
                    cut.loops.push_back(std::move(chain));
                    cut.gaps_closed += joins;
                }
                chain.clear();
                break;
            }
            taken[best_j] = 1;
            chain.insert(chain.end(), open[best_j].begin(), open[best_j].end());
        }
        if (!chain.empty()) ++cut.open_chains;
    }
}

PlaneCut cut_plane(const CutContext& ctx, std::size_t k, double max_gap_mm) {
    const double h = ctx.sorted_heights[k];
    const std::span<const Segment> segs(ctx.segs.get() + ctx.bucket_begin[k],
                                        ctx.bucket_begin[k + 1] - ctx.bucket_begin[k]);

    PlaneCut cut;
    const EdgeTable table(segs);
    // Each segment's successor, looked up for all segments first: the lookups do not depend
    // on each other, so they overlap in the processor, where the walk below would wait for
    // each in turn.
    std::vector<std::uint32_t> succ(segs.size());
    for (std::size_t i = 0; i < segs.size(); ++i) succ[i] = table.find_only(segs[i].to);
    std::vector<char> used(segs.size(), 0);
    std::vector<Path2> open;
    Path2 chain;  // the chain being walked: one buffer, each loop then copied at its size
    chain.reserve(segs.size() + 1);
    for (std::size_t s0 = 0; s0 < segs.size(); ++s0) {
        if (used[s0]) continue;
        chain.clear();
        std::uint32_t cur = static_cast<std::uint32_t>(s0);
        bool closed = false;
        while (true) {
            used[cur] = 1;
            chain.push_back(segs[cur].start());
            // The chain closes when its next edge is the one it started on: when s0 is the
            // next edge's only segment (no other segment can start on it otherwise).
            std::uint32_t nxt = succ[cur];
            if (nxt == s0 || (nxt == EdgeTable::kMany && segs[cur].to == segs[s0].from)) {
                closed = true;
                break;
            }
            const std::uint64_t next_edge = segs[cur].to;
            if (nxt == EdgeTable::kMany) {
                nxt = table.find_unused(next_edge, used);
            } else if (nxt != EdgeTable::kEmpty && used[nxt]) {
                nxt = EdgeTable::kEmpty;
            }
            if (nxt == EdgeTable::kEmpty) {
                // The cut leaves the surface through an open edge: end the chain there.
                chain.push_back(crossing(ctx, static_cast<std::uint32_t>(next_edge >> 32),
                                         static_cast<std::uint32_t>(next_edge), h));
                break;
            }
            cur = nxt;
        }
        if (closed) {
            drop_repeated_points(chain);
            if (chain.size() >= 3) cut.loops.emplace_back(chain.begin(), chain.end());
        } else {
            open.emplace_back(chain.begin(), chain.end());
        }
    }
    if (!open.empty()) {
        std::vector<Path2> runs = join_exact(open, cut);
        close_open_chains(runs, max_gap_mm, cut);
    }
    return cut;
}

core::Result<std::vector<std::size_t>> plane_order(std::span<const double> heights) {
    std::vector<std::size_t> idx(heights.size());
    std::iota(idx.begin(), idx.end(), std::size_t{0});
    std::stable_sort(idx.begin(), idx.end(),
                     [&](std::size_t a, std::size_t b) { return heights[a] < heights[b]; });
    return idx;
}

}  // namespace

namespace {

// Cuts every plane in parallel; emit(k_sorted, input_index, cut) stores the result. Each
// plane writes only its own slot, so the result does not depend on the thread count.
template <class Emit>
core::Result<void> cut_all(const mesh::TriangleMesh& mesh, const PlaneFrame& base,
                           std::shared_ptr<const double[]> vertex_heights,
                           std::span<const double> heights, const core::Progress* progress,
                           double max_gap_mm, Emit&& emit) {
    auto ctx = prepare(mesh, base, heights, std::move(vertex_heights));
    if (!ctx) return std::unexpected(ctx.error());
    auto order = plane_order(heights);
    std::atomic<std::size_t> done{0};
    tbb::parallel_for(std::size_t{0}, heights.size(), [&](std::size_t k) {
        if (progress != nullptr && progress->cancelled()) return;
        emit((*order)[k], cut_plane(*ctx, k, max_gap_mm));
        if (progress != nullptr) {
            progress->report("slicing",
                             static_cast<double>(++done) / static_cast<double>(heights.size()));
        }
    });
    if (progress != nullptr && progress->cancelled()) {
        return core::fail(core::ErrorCode::kCancelled, "cancelled", "slicing");
    }
    return {};
}

}  // namespace

core::Result<std::vector<PlaneCut>> cut_mesh(const mesh::TriangleMesh& mesh, const PlaneFrame& base,
                                             std::span<const double> heights,
                                             const core::Progress* progress, double max_gap_mm) {
    std::vector<PlaneCut> out(heights.size());
    auto ok = cut_all(mesh, base, nullptr, heights, progress, max_gap_mm,
                      [&](std::size_t i, PlaneCut cut) { out[i] = std::move(cut); });
    if (!ok) return std::unexpected(ok.error());
    return out;
}

namespace {

core::Result<std::vector<Slice>> slice_with(const mesh::TriangleMesh& mesh, const PlaneFrame& base,
                                            std::shared_ptr<const double[]> vertex_heights,
                                            std::span<const LayerSpan> layers,
                                            const core::Progress* progress, double max_gap_mm) {
    std::vector<double> heights(layers.size());
    for (std::size_t i = 0; i < layers.size(); ++i) heights[i] = layers[i].cut;
    std::vector<Slice> out(layers.size());
    auto ok = cut_all(mesh, base, std::move(vertex_heights), heights, progress, max_gap_mm,
                      [&](std::size_t i, PlaneCut cut) {
                          Slice& s = out[i];
                          s.index = static_cast<int>(i);
                          s.span = layers[i];
                          s.plane = base.shifted(layers[i].cut);
                          s.gaps_closed = cut.gaps_closed;
                          s.open_chains = cut.open_chains;
                          s.wires = geom2d::build_wire_tree(std::move(cut.loops),
                                                            geom2d::FillRule::kPositive);
                      });
    if (!ok) return std::unexpected(ok.error());
    return out;
}

}  // namespace

core::Result<std::vector<Slice>> slice_mesh(const mesh::TriangleMesh& mesh, const PlaneFrame& base,
                                            std::span<const LayerSpan> layers,
                                            const core::Progress* progress, double max_gap_mm) {
    return slice_with(mesh, base, nullptr, layers, progress, max_gap_mm);
}

core::Result<std::vector<Slice>> slice_mesh(const mesh::TriangleMesh& mesh, const FrameExtent& base,
                                            std::span<const LayerSpan> layers,
                                            const core::Progress* progress, double max_gap_mm) {
    MAXSLICE_ASSERT(base.heights != nullptr && base.vertices == mesh.vertices.size());
    return slice_with(mesh, base.frame, base.heights, layers, progress, max_gap_mm);
}

namespace {

// Which vertices the triangles use: a mesh may carry vertices no triangle uses (repair drops
// faces), and they must not count in its extent. Marked in parallel over blocks of triangles
// (every store writes 1, relaxed: no order is needed, only the final values).
std::vector<std::uint8_t> used_vertices(const mesh::TriangleMesh& mesh) {
    std::vector<std::uint8_t> used(mesh.vertices.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.triangles.size(), 1 << 15),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t t = r.begin(); t != r.end(); ++t) {
                              for (const std::uint32_t i : mesh.triangles[t]) {
                                  std::atomic_ref<std::uint8_t>(used[i]).store(
                                      1, std::memory_order_relaxed);
                              }
                          }
                      });
    return used;
}

// The range of frame heights from used_vertex_range, or [0, 0] when no vertex is used.
std::pair<double, double> extent_from(std::pair<double, double> range) {
    if (!(range.first <= range.second)) return {0.0, 0.0};
    return range;
}

// The smallest and largest of f(i) over the used vertices i (every vertex when `used` is
// empty), in parallel: min and max are exact, so the result does not depend on the split. NaN
// values are skipped (std::min/max keep the running value), as in a serial loop. f is called
// once for every vertex, used or not (it may store its values).
template <class F>
std::pair<double, double> used_vertex_range(const mesh::TriangleMesh& mesh,
                                            const std::vector<std::uint8_t>& used, F f) {
    using Range = std::pair<double, double>;
    const Range empty{std::numeric_limits<double>::infinity(),
                      -std::numeric_limits<double>::infinity()};
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, mesh.vertices.size(), 1 << 15), empty,
        [&](const tbb::blocked_range<std::size_t>& r, Range acc) {
            const bool all = used.empty();
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                const double h = f(i);
                if (!all && used[i] == 0) continue;
                acc.first = std::min(acc.first, h);
                acc.second = std::max(acc.second, h);
            }
            return acc;
        },
        [](const Range& a, const Range& b) {
            return Range{std::min(a.first, b.first), std::max(a.second, b.second)};
        });
}

PlaneFrame frame_of(const mesh::TriangleMesh& mesh, const std::vector<std::uint8_t>& used,
                    const core::Vec3d& direction) {
    const core::Vec3d d = core::normalized(direction);
    double lo = used_vertex_range(mesh, used, [&](std::size_t i) {
                    return core::dot(mesh.vertices[i], d);
                }).first;
    if (!std::isfinite(lo)) lo = 0.0;
    return PlaneFrame::from_normal(d * lo, d);
}

}  // namespace

PlaneFrame base_frame(const mesh::TriangleMesh& mesh, const core::Vec3d& direction) {
    return frame_of(mesh, used_vertices(mesh), direction);
}

std::pair<double, double> extent_along(const mesh::TriangleMesh& mesh, const PlaneFrame& frame) {
    return extent_from(used_vertex_range(
        mesh, used_vertices(mesh), [&](std::size_t i) { return frame.height(mesh.vertices[i]); }));
}

FrameExtent base_frame_and_extent(const mesh::TriangleMesh& mesh, const core::Vec3d& direction,
                                  VertexUse use) {
    // Empty: every vertex is used (a promise the assertion checks in checked builds).
    const std::vector<std::uint8_t> used =
        use == VertexUse::kAllUsed ? std::vector<std::uint8_t>{} : used_vertices(mesh);
    MAXSLICE_ASSERT(
        use == VertexUse::kCheck ||
        std::ranges::all_of(used_vertices(mesh), [](std::uint8_t u) { return u != 0; }));
    FrameExtent out;
    out.frame = frame_of(mesh, used, direction);
    // Every vertex's height, kept for slice_mesh, in the same look at the vertices.
    const std::size_t nv = mesh.vertices.size();
    auto heights = std::make_shared_for_overwrite<double[]>(nv);
    std::tie(out.lo, out.hi) = extent_from(used_vertex_range(mesh, used, [&](std::size_t i) {
        return heights[i] = out.frame.height(mesh.vertices[i]);
    }));
    out.heights = std::move(heights);
    out.vertices = nv;
    return out;
}

}  // namespace maxslice::slice
