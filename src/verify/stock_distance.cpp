#include "stock_distance.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace maxslice::verify::detail {
namespace {

// Squared distance transform of one line (Felzenszwalb and Huttenlocher, "Distance transforms
// of sampled functions", 2012): d[q] = min over p of f[p] + (q - p)^2, by the lower envelope
// of the parabolas rooted at each p. Exact in 64-bit integers but for the breakpoints, which
// are compared as doubles (values below 2^31: exact too).
class LineTransform {
public:
    void run(const std::vector<std::int64_t>& f, std::vector<std::int64_t>& d) {
        const std::size_t n = f.size();
        v_.assign(n, 0);
        z_.assign(n + 1, 0.0);
        d.assign(n, 0);
        std::size_t k = 0;
        v_[0] = 0;
        z_[0] = -std::numeric_limits<double>::infinity();
        z_[1] = std::numeric_limits<double>::infinity();
        for (std::size_t q = 1; q < n; ++q) {
            double s = 0.0;
            for (;;) {
                const std::size_t p = v_[k];
                const auto qi = static_cast<std::int64_t>(q), pi = static_cast<std::int64_t>(p);
                s = static_cast<double>((f[q] + qi * qi) - (f[p] + pi * pi)) /
                    static_cast<double>(2 * (qi - pi));
                if (s > z_[k] || k == 0) break;
                --k;
            }
            ++k;
            v_[k] = q;
            z_[k] = s;
            z_[k + 1] = std::numeric_limits<double>::infinity();
        }
        k = 0;
        for (std::size_t q = 0; q < n; ++q) {
            while (z_[k + 1] < static_cast<double>(q)) ++k;
            const auto dq = static_cast<std::int64_t>(q) - static_cast<std::int64_t>(v_[k]);
            d[q] = dq * dq + f[v_[k]];
        }
    }

private:
    std::vector<std::size_t> v_;
    std::vector<double> z_;
};

/// Planes transformed at once (in parallel) beyond the 2 reach + 1 a voxel asked about needs.
constexpr int kPlaneBatch = 16;
/// Up to this reach the second pass takes the minimum over the window directly (vectorized,
/// 2 reach row passes); beyond, the lower envelope (a few operations a voxel, not vectorized).
constexpr int kWindowReach = 16;

/// Each voxel asked about is searched on its own, nearest offsets first, not by the planes'
/// transforms, when the voxels asked about times the offsets nearer than the stock expected
/// (the coarse search's, else the reach) are fewer than this share of the box's voxels times
/// the transforms' passes (2 reach + 3): a random bit read costs several of their vectorized
/// steps. So a stock sticking out in a few places of a large part is found voxel by voxel.
constexpr double kDirectShare = 0.25;

struct IndexBox {
    int lo[3] = {std::numeric_limits<int>::max(), std::numeric_limits<int>::max(),
                 std::numeric_limits<int>::max()};
    int hi[3] = {-1, -1, -1};
};

}  // namespace

int stock_limit_within(int want, int nx, int ny, std::size_t budget_bytes) {
    const std::size_t plane = static_cast<std::size_t>(std::max(nx, 1)) *
                              static_cast<std::size_t>(std::max(ny, 1)) * sizeof(std::uint16_t);
    const std::size_t planes = budget_bytes / plane;
    const std::size_t fixed = 1 + kPlaneBatch;
    const int fit =
        planes >= fixed + 2
            ? static_cast<int>(std::min<std::size_t>((planes - fixed) / 2, kMaxStockLimit))
            : 1;
    return std::clamp(std::min(want, fit), 1, kMaxStockLimit);
}

namespace {

// Each voxel of the coarse grid stands for kCoarse^3 fine ones and is set when any of them is.
constexpr int kCoarse = 4;

BitGrid coarsened(const BitGrid& fine) {
    BitGrid out((fine.nx() + kCoarse - 1) / kCoarse, (fine.ny() + kCoarse - 1) / kCoarse,
                (fine.nz() + kCoarse - 1) / kCoarse);
    const std::vector<std::uint64_t>& w = fine.words();
    const std::size_t plane =
        static_cast<std::size_t>(fine.nx()) * static_cast<std::size_t>(fine.ny());
    for (std::size_t at = 0; at < w.size(); ++at) {
        std::uint64_t bits = w[at];
        if (bits == 0) continue;
        const int band = static_cast<int>(at / plane);
        const std::size_t rem = at % plane;
        const int i = static_cast<int>(rem / static_cast<std::size_t>(fine.ny())) / kCoarse;
        const int j = static_cast<int>(rem % static_cast<std::size_t>(fine.ny())) / kCoarse;
        while (bits != 0) {
            const int k = (band * 64 + std::countr_zero(bits)) / kCoarse;
            out.set_run(i, j, k, k);
            // The rest of this coarse voxel's bits in the word are one set.
            const int next = (k + 1) * kCoarse - band * 64;
            bits = next >= 64 ? 0 : bits & ~((std::uint64_t{1} << next) - 1);
        }
    }
    return out;
}

// Stocks are mostly a few voxels: the search starts this near and reaches farther only while it
// finds nothing, four times as far each time (the work grows with the reach and the box).
constexpr int kFirstReach = 8;

StockDistance stock_from(const BitGrid& beads, const BitGrid& finished, int limit,
                         const StockDistance* coarse, StockSearch how);

}  // namespace

StockDistance smallest_stock(const BitGrid& beads, const BitGrid& finished, int limit,
                             StockSearch how) {
    limit = std::clamp(limit, 1, kMaxStockLimit);
    // On fine grids the stock is often tens of voxels (a 1 mm machining stock at 0.075 mm):
    // the same search on grids kCoarse times coarser (set where any voxel is) first says about
    // how far to reach, and the fine search starts there. Where that guess falls short, the
    // fine search reaches farther as before: the answer is the fine grid's either way.
    if (std::min({finished.nx(), finished.ny(), finished.nz()}) >= kCoarse * 2 * kFirstReach) {
        const StockDistance c = stock_from(coarsened(beads), coarsened(finished),
                                           std::max(1, limit / kCoarse + 1), nullptr, how);
        return stock_from(beads, finished, limit, &c, how);
    }
    return stock_from(beads, finished, limit, nullptr, how);
}

namespace {

// smallest_stock, its first reach guessed from `coarse` (the answer on coarser grids) when that
// found a stock of the same kind (inside or sticking out).
StockDistance stock_from(const BitGrid& beads, const BitGrid& finished, int limit,
                         const StockDistance* coarse, StockSearch how) {
    StockDistance out;
    limit = std::clamp(limit, 1, kMaxStockLimit);
    const int nx = finished.nx(), ny = finished.ny(), nz = finished.nz();
    const std::vector<std::uint64_t>& fw = finished.words();
    const std::vector<std::uint64_t>& bw = beads.words();
    const std::size_t plane = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
    // The boxes of the finished voxels and of those outside the beads.
    IndexBox all, outside;
    const auto extend = [&](IndexBox& box, std::size_t w, std::uint64_t bits) {
        const int band = static_cast<int>(w / plane);
        const std::size_t rem = w % plane;
        const int c[3] = {static_cast<int>(rem / static_cast<std::size_t>(ny)),
                          static_cast<int>(rem % static_cast<std::size_t>(ny)),
                          band * 64 + std::countr_zero(bits)};
        const int top = band * 64 + 63 - std::countl_zero(bits);
        for (int a = 0; a < 3; ++a) {
            box.lo[a] = std::min(box.lo[a], c[a]);
            box.hi[a] = std::max(box.hi[a], a == 2 ? top : c[a]);
        }
    };
    for (std::size_t w = 0; w < fw.size(); ++w) {
        if (fw[w] == 0) continue;
        extend(all, w, fw[w]);
        if ((fw[w] & ~bw[w]) != 0) extend(outside, w, fw[w] & ~bw[w]);
    }
    if (all.hi[0] < 0) return out;
    out.empty = false;
    out.inside = outside.hi[0] < 0;
    const IndexBox& box = out.inside ? all : outside;  // the voxels asked about lie in it
    // Inside: the distance to the nearest voxel outside the beads, asked at the finished
    // part's boundary voxels (the nearest pair has its finished end there: a voxel with all six
    // neighbours finished has one a step closer). Sticking out: the distance to the nearest
    // bead voxel, asked at every finished voxel outside the beads. Found 64 voxels of a column
    // at a time, in the grids' own words (a neighbour outside the grid is not finished).
    const std::vector<std::uint64_t> asked_words = [&] {
        std::vector<std::uint64_t> a(fw.size(), 0);
        const std::size_t bands = fw.size() / plane;
        for (std::size_t w = 0; w < fw.size(); ++w) {
            const std::uint64_t f = fw[w];
            if (f == 0) continue;
            if (!out.inside) {
                a[w] = f & ~bw[w];
                continue;
            }
            const std::size_t band = w / plane;
            const std::size_t rem = w % plane;
            const std::size_t i = rem / static_cast<std::size_t>(ny);
            const std::size_t j = rem % static_cast<std::size_t>(ny);
            const auto uy = static_cast<std::size_t>(ny);
            std::uint64_t all = f;  // the bits whose six neighbours are all finished
            all &= i > 0 ? fw[w - uy] : 0;
            all &= i + 1 < static_cast<std::size_t>(nx) ? fw[w + uy] : 0;
            all &= j > 0 ? fw[w - 1] : 0;
            all &= j + 1 < uy ? fw[w + 1] : 0;
            all &= (f << 1) | (band > 0 ? fw[w - plane] >> 63 : 0);
            all &= (f >> 1) | (band + 1 < bands ? fw[w + plane] << 63 : 0);
            a[w] = f & ~all;
        }
        return a;
    }();
    const auto asked = [&](int i, int j, int k) {
        const std::size_t w = static_cast<std::size_t>(k >> 6) * plane +
                              static_cast<std::size_t>(i) * static_cast<std::size_t>(ny) +
                              static_cast<std::size_t>(j);
        return (asked_words[w] >> (k & 63) & 1U) != 0;
    };
    // The stock expected (voxels): the coarse search's when it found one of the same kind, else
    // the reach of each search.
    double expected = std::numeric_limits<double>::infinity();
    std::size_t asked_count = 0;
    for (const std::uint64_t w : asked_words)
        asked_count += static_cast<std::size_t>(std::popcount(w));
    // search(reach) by each voxel asked about on its own: the offsets within the reach,
    // nearest first, until a target (or, once one voxel is known, until no offset left can
    // change the answer). The same answer and voxel as the planes' transforms: the voxels are
    // taken in the same order (k, then i, then j), a better one replacing the best only when
    // strictly better.
    const auto search_each = [&](int reach) {
        const std::int64_t cap = static_cast<std::int64_t>(reach + 1) * (reach + 1);
        struct Offset {
            std::int64_t d2;
            int di, dj, dk;
        };
        std::vector<Offset> offsets;
        for (int di = -reach; di <= reach; ++di) {
            for (int dj = -reach; dj <= reach; ++dj) {
                for (int dk = -reach; dk <= reach; ++dk) {
                    const std::int64_t d2 =
                        std::int64_t{di} * di + std::int64_t{dj} * dj + std::int64_t{dk} * dk;
                    if (d2 < cap) offsets.push_back({d2, di, dj, dk});
                }
            }
        }
        std::stable_sort(offsets.begin(), offsets.end(),
                         [](const Offset& a, const Offset& b) { return a.d2 < b.d2; });
        const std::uint64_t flip = out.inside ? ~std::uint64_t{0} : 0;  // target: bit ^ flip
        const auto target = [&](int i, int j, int k) {
            if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return false;
            const std::size_t w = static_cast<std::size_t>(k >> 6) * plane +
                                  static_cast<std::size_t>(i) * static_cast<std::size_t>(ny) +
                                  static_cast<std::size_t>(j);
            return ((bw[w] ^ flip) >> (k & 63) & 1U) != 0;
        };
        std::int64_t best = out.inside ? std::numeric_limits<std::int64_t>::max() : -1;
        for (int q = box.lo[2]; q <= box.hi[2]; ++q) {
            for (int i = box.lo[0]; i <= box.hi[0]; ++i) {
                for (int j = box.lo[1]; j <= box.hi[1]; ++j) {
                    if (!asked(i, j, q)) continue;
                    std::int64_t d2 = cap;
                    for (const Offset& o : offsets) {
                        // Inside, the smallest is wanted: no farther offset does better.
                        if (out.inside && o.d2 >= best) break;
                        if (target(i + o.di, j + o.dj, q + o.dk)) {
                            d2 = o.d2;
                            break;
                        }
                    }
                    if (out.inside ? d2 < best : d2 > best) {
                        best = d2;
                        out.i = i;
                        out.j = j;
                        out.k = q;
                    }
                }
            }
        }
        return best;
    };
    std::vector<std::uint16_t> planes;
    // The best squared distance within `reach` voxels, or one above reach^2 when there is none
    // (or, sticking out, when some voxel asked about has none).
    const auto search = [&](int reach) {
        int lo[3], hi[3];
        const int n[3] = {nx, ny, nz};
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::max(0, box.lo[a] - reach);
            hi[a] = std::min(n[a] - 1, box.hi[a] + reach);
        }
        const int bx = hi[0] - lo[0] + 1, by = hi[1] - lo[1] + 1, bz = hi[2] - lo[2] + 1;
        const int ring = std::min(2 * reach + 1 + kPlaneBatch, bz);
        const std::int64_t cap = static_cast<std::int64_t>(reach + 1) * (reach + 1);
        const double e = std::min<double>(expected, reach) + 1.0;
        const double walk = 4.2 * e * e * e;  // offsets within the stock expected
        const bool each =
            how == StockSearch::kCheaper
                ? static_cast<double>(asked_count) * walk <
                      kDirectShare * static_cast<double>(bx) * by * bz * (2.0 * reach + 3.0)
                : how == StockSearch::kEachVoxel;
        if (each) return search_each(reach);
        const std::size_t bplane = static_cast<std::size_t>(bx) * static_cast<std::size_t>(by);
        planes.assign(static_cast<std::size_t>(ring) * bplane, 0);
        // The squared in-plane distance to the nearest target of plane k, capped at
        // (reach+1)^2: along j by two scans, then across i by the lower envelope (a line all
        // at 0 or all at the cap stays so). A capped value stands for one at least as large,
        // so any result below the cap is exact.
        const auto slot = [&](int k) {
            return planes.data() + static_cast<std::size_t>((k - lo[2]) % ring) * bplane;
        };
        const std::uint64_t flip = out.inside ? ~std::uint64_t{0} : 0;  // target: bit ^ flip
        const auto transform_plane = [&](int k) {
            std::uint16_t* g = slot(k);
            const std::uint64_t* band = bw.data() + static_cast<std::size_t>(k >> 6) * plane;
            const int bit = k & 63;
            for (int i = lo[0]; i <= hi[0]; ++i) {
                const std::uint64_t* row =
                    band + static_cast<std::size_t>(i) * static_cast<std::size_t>(ny);
                std::uint16_t* out_row = g + static_cast<std::size_t>(i - lo[0]) * by;
                int last = -(reach + 2);
                for (int j = lo[1]; j <= hi[1]; ++j) {
                    if (((row[j] ^ flip) >> bit & 1U) != 0) last = j;
                    out_row[j - lo[1]] = static_cast<std::uint16_t>(std::min(j - last, reach + 1));
                }
                last = std::numeric_limits<int>::max() / 2;
                for (int j = hi[1]; j >= lo[1]; --j) {
                    if (((row[j] ^ flip) >> bit & 1U) != 0) last = j;
                    const std::int64_t s =
                        std::min<std::int64_t>({out_row[j - lo[1]], last - j, reach + 1});
                    out_row[j - lo[1]] = static_cast<std::uint16_t>(s * s);
                }
            }
            if (reach <= kWindowReach) {
                // Across i within the reach only: a nearer target than reach + 1 lies within
                // it, and each offset is one pass over whole rows of 16-bit values (the sums
                // stay below 2 (reach + 1)^2 < 2^16).
                const std::vector<std::uint16_t> pass1(g, g + bplane);
                for (int off = 1; off <= reach; ++off) {
                    const auto o2 = static_cast<std::uint16_t>(off * off);
                    for (int i = 0; i < bx; ++i) {
                        std::uint16_t* row = g + static_cast<std::size_t>(i) * by;
                        for (const int from : {i - off, i + off}) {
                            if (from < 0 || from >= bx) continue;
                            const std::uint16_t* src =
                                pass1.data() + static_cast<std::size_t>(from) * by;
                            for (int j = 0; j < by; ++j) {
                                row[j] = std::min(row[j], static_cast<std::uint16_t>(src[j] + o2));
                            }
                        }
                    }
                }
                const auto c16 = static_cast<std::uint16_t>(cap);
                for (std::size_t v = 0; v < bplane; ++v) g[v] = std::min(g[v], c16);
                return;
            }
            std::vector<std::int64_t> f(static_cast<std::size_t>(bx)), d;
            LineTransform line;
            for (int j = 0; j < by; ++j) {
                const std::int64_t first = g[j];
                bool flat = first == 0 || first == cap;
                for (int i = 0; i < bx; ++i) {
                    const std::int64_t v = g[static_cast<std::size_t>(i) * by + j];
                    f[static_cast<std::size_t>(i)] = v;
                    flat = flat && v == first;
                }
                if (flat) continue;
                line.run(f, d);
                for (int i = 0; i < bx; ++i) {
                    g[static_cast<std::size_t>(i) * by + j] =
                        static_cast<std::uint16_t>(std::min(d[static_cast<std::size_t>(i)], cap));
                }
            }
        };
        std::int64_t best = out.inside ? std::numeric_limits<std::int64_t>::max() : -1;
        // The planes q - reach .. q + reach (null outside the box), for the scan along k.
        std::vector<const std::uint16_t*> near(static_cast<std::size_t>(2 * reach + 1));
        const auto ask_plane = [&](int q) {
            for (int dz = -reach; dz <= reach; ++dz) {
                const int k = q + dz;
                near[static_cast<std::size_t>(dz + reach)] =
                    k >= lo[2] && k <= hi[2] ? slot(k) : nullptr;
            }
            const std::uint16_t* const* mid = near.data() + reach;
            for (int i = box.lo[0]; i <= box.hi[0]; ++i) {
                for (int j = box.lo[1]; j <= box.hi[1]; ++j) {
                    if (!asked(i, j, q)) continue;
                    const std::size_t v =
                        static_cast<std::size_t>(i - lo[0]) * static_cast<std::size_t>(by) +
                        static_cast<std::size_t>(j - lo[1]);
                    std::int64_t d2 = mid[0][v];
                    for (int dz = 1; static_cast<std::int64_t>(dz) * dz < d2; ++dz) {
                        const std::int64_t dz2 = static_cast<std::int64_t>(dz) * dz;
                        if (mid[-dz] != nullptr) d2 = std::min<std::int64_t>(d2, mid[-dz][v] + dz2);
                        if (mid[dz] != nullptr) d2 = std::min<std::int64_t>(d2, mid[dz][v] + dz2);
                    }
                    d2 = std::min(d2, cap);
                    if (out.inside ? d2 < best : d2 > best) {
                        best = d2;
                        out.i = i;
                        out.j = j;
                        out.k = q;
                    }
                }
            }
        };
        // Planes are transformed a batch at a time, in parallel (each into its own slot of the
        // ring), and asked about in order: the same answer whatever the thread count. The
        // ring keeps the planes from q - reach to q + reach + kPlaneBatch.
        int computed = lo[2] - 1;
        for (int q = box.lo[2]; q <= box.hi[2]; ++q) {
            if (std::min(hi[2], q + reach) > computed) {
                const int end = std::min(hi[2], q + reach + kPlaneBatch);
                tbb::parallel_for(computed + 1, end + 1, [&](int k) { transform_plane(k); });
                computed = end;
            }
            ask_plane(q);
        }
        return best;
    };
    int reach = std::min(limit, kFirstReach);  // the last search decides
    if (coarse != nullptr && !coarse->empty && !coarse->beyond && coarse->inside == out.inside) {
        const int guess = static_cast<int>(std::ceil(coarse->distance)) * kCoarse + 2 * kCoarse;
        reach = std::clamp(guess, reach, limit);
        expected = coarse->distance * kCoarse;
    }
    std::int64_t best = search(reach);
    while (best > static_cast<std::int64_t>(reach) * reach && reach < limit) {
        reach = std::min(limit, 4 * reach);
        best = search(reach);
    }
    const std::int64_t lim2 = static_cast<std::int64_t>(limit) * limit;
    out.beyond = best > lim2;
    out.distance = out.beyond ? static_cast<double>(limit) : std::sqrt(static_cast<double>(best));
    return out;
}

}  // namespace

}  // namespace maxslice::verify::detail
