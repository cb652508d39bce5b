#include "stock_distance.hpp"

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
    const int fit =
        planes >= 3 ? static_cast<int>(std::min<std::size_t>((planes - 1) / 2, kMaxStockLimit)) : 1;
    return std::clamp(std::min(want, fit), 1, kMaxStockLimit);
}

StockDistance smallest_stock(const BitGrid& beads, const BitGrid& finished, int limit) {
    StockDistance out;
    limit = std::clamp(limit, 1, kMaxStockLimit);
    const int nx = finished.nx(), ny = finished.ny(), nz = finished.nz();
    const std::vector<std::uint64_t>& fw = finished.words();
    const std::vector<std::uint64_t>& bw = beads.words();
    const std::size_t plane = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
    IndexBox box;
    bool sticks_out = false;
    for (std::size_t w = 0; w < fw.size(); ++w) {
        if (fw[w] == 0) continue;
        if ((fw[w] & ~bw[w]) != 0) sticks_out = true;
        const int band = static_cast<int>(w / plane);
        const std::size_t rem = w % plane;
        const int c[3] = {static_cast<int>(rem / static_cast<std::size_t>(ny)),
                          static_cast<int>(rem % static_cast<std::size_t>(ny)),
                          band * 64 + std::countr_zero(fw[w])};
        const int top = band * 64 + 63 - std::countl_zero(fw[w]);
        for (int a = 0; a < 3; ++a) {
            box.lo[a] = std::min(box.lo[a], c[a]);
            box.hi[a] = std::max(box.hi[a], a == 2 ? top : c[a]);
        }
    }
    if (box.hi[0] < 0) return out;
    out.empty = false;
    out.inside = !sticks_out;
    // Inside: the distance to the nearest voxel outside the beads, asked at the finished
    // part's boundary voxels (the nearest pair has its finished end there: a voxel with all six
    // neighbours finished has one a step closer). Sticking out: the distance to the nearest
    // bead voxel, asked at every finished voxel outside the beads.
    const auto target = [&](int i, int j, int k) { return beads.get(i, j, k) != out.inside; };
    const auto finished_at = [&](int i, int j, int k) {
        return i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz && finished.get(i, j, k);
    };
    const auto asked = [&](int i, int j, int k) {
        if (!finished.get(i, j, k)) return false;
        if (!out.inside) return !beads.get(i, j, k);
        return !finished_at(i - 1, j, k) || !finished_at(i + 1, j, k) ||
               !finished_at(i, j - 1, k) || !finished_at(i, j + 1, k) ||
               !finished_at(i, j, k - 1) || !finished_at(i, j, k + 1);
    };
    int lo[3], hi[3];
    const int n[3] = {nx, ny, nz};
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::max(0, box.lo[a] - limit);
        hi[a] = std::min(n[a] - 1, box.hi[a] + limit);
    }
    const int bx = hi[0] - lo[0] + 1, by = hi[1] - lo[1] + 1, bz = hi[2] - lo[2] + 1;
    const int ring = std::min(2 * limit + 1, bz);
    const std::int64_t cap = static_cast<std::int64_t>(limit + 1) * (limit + 1);
    const std::size_t bplane = static_cast<std::size_t>(bx) * static_cast<std::size_t>(by);
    std::vector<std::uint16_t> planes(static_cast<std::size_t>(ring) * bplane);
    const auto at = [&](int i, int j, int k) -> std::uint16_t& {
        return planes[static_cast<std::size_t>((k - lo[2]) % ring) * bplane +
                      static_cast<std::size_t>(i - lo[0]) * static_cast<std::size_t>(by) +
                      static_cast<std::size_t>(j - lo[1])];
    };
    std::vector<std::int64_t> f, d;
    LineTransform line;
    // The squared in-plane distance to the nearest target of plane k, capped at (limit+1)^2:
    // along j by two scans, then across i by the lower envelope. A capped value stands for
    // one at least as large, so any result below the cap is exact.
    const auto transform_plane = [&](int k) {
        for (int i = lo[0]; i <= hi[0]; ++i) {
            int last = -(limit + 2);
            for (int j = lo[1]; j <= hi[1]; ++j) {
                if (target(i, j, k)) last = j;
                at(i, j, k) =
                    static_cast<std::uint16_t>(std::min<std::int64_t>(j - last, limit + 1));
            }
            last = std::numeric_limits<int>::max() / 2;
            for (int j = hi[1]; j >= lo[1]; --j) {
                if (target(i, j, k)) last = j;
                const std::int64_t s = std::min<std::int64_t>({at(i, j, k), last - j, limit + 1});
                at(i, j, k) = static_cast<std::uint16_t>(s * s);
            }
        }
        f.resize(static_cast<std::size_t>(bx));
        for (int j = lo[1]; j <= hi[1]; ++j) {
            for (int i = lo[0]; i <= hi[0]; ++i)
                f[static_cast<std::size_t>(i - lo[0])] = at(i, j, k);
            line.run(f, d);
            for (int i = lo[0]; i <= hi[0]; ++i) {
                at(i, j, k) = static_cast<std::uint16_t>(
                    std::min(d[static_cast<std::size_t>(i - lo[0])], cap));
            }
        }
    };
    std::int64_t best = out.inside ? std::numeric_limits<std::int64_t>::max() : -1;
    const auto ask_plane = [&](int q) {
        const int k0 = std::max(lo[2], q - limit), k1 = std::min(hi[2], q + limit);
        for (int i = box.lo[0]; i <= box.hi[0]; ++i) {
            for (int j = box.lo[1]; j <= box.hi[1]; ++j) {
                if (!asked(i, j, q)) continue;
                std::int64_t d2 = at(i, j, q);
                for (int dz = 1; static_cast<std::int64_t>(dz) * dz < d2; ++dz) {
                    const std::int64_t dz2 = static_cast<std::int64_t>(dz) * dz;
                    if (q - dz >= k0) d2 = std::min<std::int64_t>(d2, at(i, j, q - dz) + dz2);
                    if (q + dz <= k1) d2 = std::min<std::int64_t>(d2, at(i, j, q + dz) + dz2);
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
    for (int k = lo[2]; k <= hi[2] + limit; ++k) {
        if (k <= hi[2]) transform_plane(k);
        const int q = k - limit;
        if (q >= box.lo[2] && q <= box.hi[2]) ask_plane(q);
    }
    const std::int64_t lim2 = static_cast<std::int64_t>(limit) * limit;
    out.beyond = best > lim2;
    out.distance = out.beyond ? static_cast<double>(limit) : std::sqrt(static_cast<double>(best));
    return out;
}

}  // namespace maxslice::verify::detail
