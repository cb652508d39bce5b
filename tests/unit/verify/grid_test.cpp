// The verifier's private voxel pyramid, convex fill and region query against brute force:
// every voxel the fill sets has its centre inside the solid and no other does, every coarse
// bit is the OR of the eight below it, and find_occupied finds a hit exactly when some set
// voxel passes the region test (its own early exits and its first look at the middle voxel
// change only how fast it answers).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <tuple>
#include <vector>

#include "region_query.hpp"
#include "stock_distance.hpp"
#include "voxel_grid.hpp"

namespace maxslice::verify::detail {
namespace {

using core::Vec3d;

constexpr int kN = 40;           // voxels along each axis (z spans a 64-bit word boundary)
constexpr double kVoxel = 0.25;  // mm
const Vec3d kOrigin{-0.013, 0.021, -0.007};

Vec3d centre(int i, int j, int k) {
    return kOrigin + Vec3d{(i + 0.5) * kVoxel, (j + 0.5) * kVoxel, (k + 0.5) * kVoxel};
}

Vec3d random_unit(std::mt19937& rng) {
    std::normal_distribution<double> g;
    for (;;) {
        const Vec3d v{g(rng), g(rng), g(rng)};
        if (core::norm(v) > 1e-3) return core::normalized(v);
    }
}

// A box with edges along t, s = d x t and d: the shape of a bead piece. Half of them have d
// straight up, as in a planar layer (the fill's row-at-once path); a third of those run along
// x or y (rows that set the same columns, which the fill sets as one rectangle).
struct Box {
    Slabs slabs;
    std::vector<std::pair<Vec3d, std::pair<double, double>>> planes;
};

Box random_box(std::mt19937& rng) {
    std::uniform_real_distribution<double> pos(1.0, kN * kVoxel - 1.0);
    std::uniform_real_distribution<double> len(0.2, 3.0);
    std::uniform_real_distribution<double> ang(0.0, 2.0 * std::numbers::pi);
    const bool upright = std::uniform_int_distribution<int>(0, 1)(rng) == 0;
    const Vec3d d = upright ? Vec3d{0, 0, 1} : random_unit(rng);
    Vec3d t;
    if (upright) {
        const int quarter = std::uniform_int_distribution<int>(0, 11)(rng);
        const double a = quarter < 4 ? 0.5 * std::numbers::pi * quarter : ang(rng);
        t = {std::cos(a), std::sin(a), 0.0};
    } else {
        const Vec3d other = std::abs(d.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
        t = core::normalized(core::cross(d, other));
    }
    const Vec3d s = core::cross(d, t);
    const Vec3d p{pos(rng), pos(rng), pos(rng)};
    const double lt = len(rng), ls = len(rng), ld = 0.5 * len(rng);
    Box b;
    for (const auto& [n, half] : {std::pair{t, lt}, std::pair{s, ls}, std::pair{d, ld}}) {
        const double c = core::dot(n, p);
        b.slabs.add(n, c - half, c + half);
        b.planes.push_back({n, {c - half, c + half}});
    }
    for (const double a : {-lt, lt}) {
        for (const double c : {-ls, ls}) {
            for (const double e : {-ld, ld}) b.slabs.add_corner(p + t * a + s * c + d * e);
        }
    }
    return b;
}

// 1 inside, 0 outside, -1 within rounding of a face (either answer is right).
int inside(const Box& b, const Vec3d& c) {
    bool edge = false;
    for (const auto& [n, range] : b.planes) {
        const double v = core::dot(n, c);
        if (v < range.first - 1e-9 || v > range.second + 1e-9) return 0;
        if (v < range.first + 1e-9 || v > range.second - 1e-9) edge = true;
    }
    return edge ? -1 : 1;
}

TEST(VoxelGrid, FillSetsTheVoxelsWhoseCentresLieInsideAndThePyramidIsTheirOr) {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 20; ++trial) {
        OccupancyPyramid grid(kN, kN, kN);
        std::vector<Box> boxes;
        const int count = std::uniform_int_distribution<int>(1, 6)(rng);
        for (int n = 0; n < count; ++n) {
            boxes.push_back(random_box(rng));
            fill(grid, kOrigin, kVoxel, boxes.back().slabs);
        }
        int set = 0;
        std::array<int, 3> lo{kN, kN, kN}, hi{-1, -1, -1};
        for (int i = 0; i < kN; ++i) {
            for (int j = 0; j < kN; ++j) {
                for (int k = 0; k < kN; ++k) {
                    bool any_in = false, any_edge = false;
                    for (const Box& b : boxes) {
                        const int v = inside(b, centre(i, j, k));
                        any_in = any_in || v == 1;
                        any_edge = any_edge || v == -1;
                    }
                    const bool got = grid.fine().get(i, j, k);
                    if (!any_edge) {
                        ASSERT_EQ(got, any_in) << trial << ": " << i << " " << j << " " << k;
                    }
                    if (got) {
                        ++set;
                        lo = {std::min(lo[0], i), std::min(lo[1], j), std::min(lo[2], k)};
                        hi = {std::max(hi[0], i), std::max(hi[1], j), std::max(hi[2], k)};
                    }
                }
            }
        }
        ASSERT_GT(set, 0);
        // The set box holds every set voxel (it may be larger: it follows the runs laid).
        for (std::size_t c = 0; c < 3; ++c) {
            EXPECT_LE(grid.set_lo()[c], lo[c]);
            EXPECT_GE(grid.set_hi()[c], hi[c]);
        }
        for (int l = 1; l < grid.level_count(); ++l) {
            const BitGrid& g = grid.level(l);
            const BitGrid& below = grid.level(l - 1);
            for (int i = 0; i < g.nx(); ++i) {
                for (int j = 0; j < g.ny(); ++j) {
                    for (int k = 0; k < g.nz(); ++k) {
                        bool any = false;
                        for (int c = 0; c < 8; ++c) {
                            const int ci = 2 * i + (c & 1), cj = 2 * j + (c >> 1 & 1),
                                      ck = 2 * k + (c >> 2);
                            if (ci < below.nx() && cj < below.ny() && ck < below.nz()) {
                                any = any || below.get(ci, cj, ck);
                            }
                        }
                        ASSERT_EQ(g.get(i, j, k), any) << "level " << l;
                    }
                }
            }
        }
    }
}

TEST(VoxelGrid, FindOccupiedAgreesWithAScanOfEverySetVoxel) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> pos(0.0, kN * kVoxel);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int hits = 0, misses = 0;
    for (int trial = 0; trial < 30; ++trial) {
        OccupancyPyramid grid(kN, kN, kN);
        const int count = std::uniform_int_distribution<int>(1, 5)(rng);
        for (int n = 0; n < count; ++n) fill(grid, kOrigin, kVoxel, random_box(rng).slabs);
        for (int q = 0; q < 60; ++q) {
            // A cone with a body (the nozzle) or a flat box under the apex (the support probe).
            Region region;
            if (q % 2 == 0) {
                const double apex = 0.25, len = 1.0 + 4.0 * unit(rng), tan = 0.2 + unit(rng);
                region.add({{{apex, -apex * tan},
                             {len, -len * tan},
                             {len, len * tan},
                             {apex, apex * tan}}});
                const double r = len * tan + 0.5, top = len + 2.0 * unit(rng);
                region.add({{{len, -r}, {top, -r}, {top, r}, {len, r}}});
            } else {
                const double top = -0.3 - unit(rng), bottom = top - 0.5, r = 0.3 + unit(rng);
                region.add({{{bottom, -r}, {top, -r}, {top, r}, {bottom, r}}});
            }
            const double margin = q % 3 == 0 ? 0.0 : 0.6 * unit(rng);
            const Vec3d apex{pos(rng), pos(rng), pos(rng)};
            const Vec3d axis = q % 4 == 1 ? Vec3d{0, 0, 1} : random_unit(rng);
            Vec3d hit;
            const bool found =
                find_occupied(grid, kOrigin, kVoxel, apex, axis, region, margin, &hit);
            const auto passes = [&](const Vec3d& c) {
                const Vec3d rel = c - apex;
                const double a = core::dot(rel, axis);
                const double r = core::norm(rel - axis * a);
                if (a < region.a_min) return false;
                if (region.distance_bound(a, r) > margin) return false;
                return margin == 0.0 || region.distance(a, r) <= margin;
            };
            bool expected = false;
            for (int i = 0; i < kN && !expected; ++i) {
                for (int j = 0; j < kN && !expected; ++j) {
                    for (int k = 0; k < kN && !expected; ++k) {
                        expected = grid.fine().get(i, j, k) && passes(centre(i, j, k));
                    }
                }
            }
            ASSERT_EQ(found, expected) << "trial " << trial << " query " << q;
            if (found) {
                ++hits;
                EXPECT_TRUE(passes(hit));
                const int i = static_cast<int>(std::floor((hit.x - kOrigin.x) / kVoxel));
                const int j = static_cast<int>(std::floor((hit.y - kOrigin.y) / kVoxel));
                const int k = static_cast<int>(std::floor((hit.z - kOrigin.z) / kVoxel));
                EXPECT_TRUE(grid.fine().get(i, j, k));
            } else {
                ++misses;
            }
        }
    }
    // Both answers occur often enough for the comparison to mean something.
    EXPECT_GT(hits, 100);
    EXPECT_GT(misses, 100);
}

TEST(VoxelGrid, NothingAtOrAboveTheFloorIsNoHitEvenWithMaterialJustBelow) {
    // A slab of material whose top lies just under the apex floor; the region's floor is at
    // a_min above the apex. Moving the apex down by a voxel puts material above the floor.
    OccupancyPyramid grid(kN, kN, kN);
    Slabs slab;
    slab.add({1, 0, 0}, 1.0, 9.0);
    slab.add({0, 1, 0}, 1.0, 9.0);
    slab.add({0, 0, 1}, 1.0, 3.0);
    for (const double x : {1.0, 9.0}) {
        for (const double y : {1.0, 9.0}) {
            for (const double z : {1.0, 3.0}) slab.add_corner({x, y, z});
        }
    }
    fill(grid, kOrigin, kVoxel, slab);
    Region cone;
    cone.add({{{0.25, -0.1}, {5.0, -2.0}, {5.0, 2.0}, {0.25, 0.1}}});
    const Vec3d up{0, 0, 1};
    Vec3d hit;
    EXPECT_FALSE(find_occupied(grid, kOrigin, kVoxel, {5.0, 5.0, 3.0}, up, cone, 1.0, &hit));
    EXPECT_TRUE(find_occupied(grid, kOrigin, kVoxel, {5.0, 5.0, 2.5}, up, cone, 1.0, &hit));
    // Pointing down into it, the floor test must not skip it either.
    EXPECT_TRUE(find_occupied(grid, kOrigin, kVoxel, {5.0, 5.0, 3.5}, {0, 0, -1}, cone, 0.0, &hit));
}

// smallest_stock as the job calls it, after checking that the planes' transforms and the
// search voxel by voxel give the same answer and voxel.
StockDistance stock_by_every_search(const BitGrid& beads, const BitGrid& finished, int limit) {
    const StockDistance got = smallest_stock(beads, finished, limit);
    for (const StockSearch how : {StockSearch::kPlanes, StockSearch::kEachVoxel}) {
        const StockDistance other = smallest_stock(beads, finished, limit, how);
        EXPECT_EQ(other.inside, got.inside);
        EXPECT_EQ(other.beyond, got.beyond);
        EXPECT_DOUBLE_EQ(other.distance, got.distance);
        EXPECT_EQ(std::tuple(other.i, other.j, other.k), std::tuple(got.i, got.j, got.k));
    }
    return got;
}

// The smallest stock against brute force over every pair of voxels: the squared distance it
// finds is the smallest (finished part inside the beads) or largest (sticking out) over the
// asked voxels of the squared distance to the nearest target voxel, exact below its limit
// and "beyond" above it; the voxel it names is a finished one with that distance.
TEST(VoxelGrid, SmallestStockAgreesWithBruteForce) {
    std::mt19937 rng(2026);
    constexpr int nx = 15, ny = 18, nz = 70;  // z spans a 64-bit word boundary
    std::uniform_int_distribution<int> ci(0, nx - 1), cj(0, ny - 1), ck(0, nz - 1);
    int inside_cases = 0, outside_cases = 0, beyond_cases = 0, far_cases = 0;
    for (int trial = 0; trial < 90; ++trial) {
        BitGrid beads(nx, ny, nz), blob(nx, ny, nz);
        const auto random_boxes = [&](BitGrid& g, int count, int grow) {
            for (int b = 0; b < count; ++b) {
                const int i = ci(rng), j = cj(rng), k = ck(rng);
                const int di = std::uniform_int_distribution<int>(0, grow)(rng);
                const int dj = std::uniform_int_distribution<int>(0, grow)(rng);
                const int dk = std::uniform_int_distribution<int>(0, 2 * grow)(rng);
                g.set_rect(std::max(0, i - di), std::min(nx - 1, i + di), std::max(0, j - dj),
                           std::min(ny - 1, j + dj), std::max(0, k - dk), std::min(nz - 1, k + dk));
            }
        };
        random_boxes(beads, 6, 6);
        random_boxes(blob, 3, 4);
        // Half the trials: the finished part is the blob's part inside the beads.
        const bool within = trial % 2 == 0;
        BitGrid finished(nx, ny, nz);
        for (int i = 0; i < nx; ++i) {
            for (int j = 0; j < ny; ++j) {
                for (int k = 0; k < nz; ++k) {
                    if (blob.get(i, j, k) && (!within || beads.get(i, j, k))) {
                        finished.set_run(i, j, k, k);
                    }
                }
            }
        }
        if (finished.count() == 0 || beads.count() == std::size_t{nx} * ny * nz) continue;
        // Reaches of 3 and 12 take the window's second pass, 40 (past the first reach of 8)
        // the lower envelope.
        const int limit = trial % 3 == 0 ? 3 : (trial % 3 == 1 ? 12 : 40);
        // Brute force.
        bool sticks_out = false;
        for (std::size_t w = 0; w < finished.words().size(); ++w) {
            if ((finished.words()[w] & ~beads.words()[w]) != 0) sticks_out = true;
        }
        const auto nearest_target = [&](int i, int j, int k) {
            long best = std::numeric_limits<long>::max();
            for (int a = 0; a < nx; ++a) {
                for (int b = 0; b < ny; ++b) {
                    for (int c = 0; c < nz; ++c) {
                        if (beads.get(a, b, c) == sticks_out) {
                            const long d2 = long{a - i} * (a - i) + long{b - j} * (b - j) +
                                            long{c - k} * (c - k);
                            best = std::min(best, d2);
                        }
                    }
                }
            }
            return best;
        };
        long want = sticks_out ? -1 : std::numeric_limits<long>::max();
        for (int i = 0; i < nx; ++i) {
            for (int j = 0; j < ny; ++j) {
                for (int k = 0; k < nz; ++k) {
                    if (!finished.get(i, j, k) || (sticks_out && beads.get(i, j, k))) continue;
                    const long d2 = nearest_target(i, j, k);
                    want = sticks_out ? std::max(want, d2) : std::min(want, d2);
                }
            }
        }
        const StockDistance got = stock_by_every_search(beads, finished, limit);
        SCOPED_TRACE(trial);
        ASSERT_FALSE(got.empty);
        EXPECT_EQ(got.inside, !sticks_out);
        const long lim2 = long{limit} * limit;
        EXPECT_EQ(got.beyond, want > lim2);
        if (limit > 16 && want > 16 * 16 && want <= lim2) ++far_cases;
        if (want <= lim2) {
            EXPECT_DOUBLE_EQ(got.distance, std::sqrt(static_cast<double>(want)));
            ASSERT_TRUE(finished.get(got.i, got.j, got.k));
            EXPECT_EQ(nearest_target(got.i, got.j, got.k), want);
        } else {
            EXPECT_DOUBLE_EQ(got.distance, limit);
            ++beyond_cases;
        }
        ++(sticks_out ? outside_cases : inside_cases);
    }
    // Both modes and the limit were exercised.
    EXPECT_GT(inside_cases, 5);
    EXPECT_GT(outside_cases, 5);
    EXPECT_GT(beyond_cases, 0);
    EXPECT_GT(far_cases, 0);
}

// On grids large enough that the search first guesses its reach on coarser grids (at least 64
// voxels along every axis), the answer is still the fine grid's exact one: against brute force
// over the few target voxels of sparse cases. Sticking out: small bead boxes, the finished
// part's voxels outside them asked. Inside: the beads fill a box but for a few holes, and the
// finished part's boundary voxels are asked; their nearest voxel outside the beads is a hole's
// or straight across the box's nearest face.
TEST(VoxelGrid, SmallestStockOnLargeGridsAgreesWithBruteForce) {
    std::mt19937 rng(1206);
    constexpr int nx = 80, ny = 72, nz = 90;
    constexpr int lo = 5, hi[3] = {nx - 6, ny - 6, nz - 6};  // the inside cases' bead box
    const auto uniform = [&](int a, int b) {
        return std::uniform_int_distribution<int>(a, b)(rng);
    };
    using Voxel = std::array<int, 3>;
    const auto d2_of = [](const Voxel& a, const Voxel& b) {
        return long{a[0] - b[0]} * (a[0] - b[0]) + long{a[1] - b[1]} * (a[1] - b[1]) +
               long{a[2] - b[2]} * (a[2] - b[2]);
    };
    int far_cases = 0, inside_cases = 0, outside_cases = 0;
    for (int trial = 0; trial < 16; ++trial) {
        SCOPED_TRACE(trial);
        const bool inside = trial % 2 == 0;
        BitGrid beads(nx, ny, nz), finished(nx, ny, nz);
        std::vector<Voxel> targets;  // bead voxels (sticking out) or holes (inside)
        const auto box = [&](BitGrid& g, int c0, int c1, int size, std::vector<Voxel>* list) {
            const int i = uniform(c0, c1 - size), j = uniform(c0, std::min(c1, ny - 1) - size);
            const int k = uniform(c0, c1 - size);
            g.set_rect(i, i + size, j, j + size, k, k + size);
            if (list == nullptr) return;
            for (int a = i; a <= i + size; ++a) {
                for (int b = j; b <= j + size; ++b) {
                    for (int c = k; c <= k + size; ++c) list->push_back({a, b, c});
                }
            }
        };
        if (inside) {
            beads.set_rect(lo, hi[0], lo, hi[1], lo, hi[2]);
            // The finished box, 16 to 24 voxels in from each face of the beads' (any face may
            // be the nearest), and three holes of 3^3 voxels in the beads, clear of it.
            int fl[3], fh[3];
            for (int a = 0; a < 3; ++a) {
                fl[a] = lo + uniform(16, 24);
                fh[a] = hi[a] - uniform(16, 24);
            }
            BitGrid holes(nx, ny, nz);
            for (int h = 0; h < 3; ++h) {
                int c[3];
                bool clear = false;
                if (h == 0) {
                    // Below or above the middle of the finished box: its nearest finished
                    // voxels are boundary voxels by their k neighbours alone.
                    c[0] = (fl[0] + fh[0]) / 2 - 1;
                    c[1] = (fl[1] + fh[1]) / 2 - 1;
                    c[2] = trial % 4 == 0 ? fl[2] - uniform(3, 6) - 2 : fh[2] + uniform(3, 6);
                    clear = true;
                }
                for (int attempt = 0; attempt < 50 && !clear; ++attempt) {
                    clear = false;
                    for (int a = 0; a < 3; ++a) {
                        c[a] = uniform(lo, hi[a] - 2);
                        clear = clear || c[a] + 2 < fl[a] - 1 || c[a] > fh[a] + 1;
                    }
                }
                if (!clear) continue;
                holes.set_rect(c[0], c[0] + 2, c[1], c[1] + 2, c[2], c[2] + 2);
                for (int a = c[0]; a <= c[0] + 2; ++a) {
                    for (int b = c[1]; b <= c[1] + 2; ++b) {
                        for (int d = c[2]; d <= c[2] + 2; ++d) targets.push_back({a, b, d});
                    }
                }
            }
            for (int i = fl[0]; i <= fh[0]; ++i) {
                for (int j = fl[1]; j <= fh[1]; ++j) finished.set_run(i, j, fl[2], fh[2]);
            }
            // The beads without the holes.
            BitGrid with_holes(nx, ny, nz);
            for (int i = 0; i < nx; ++i) {
                for (int j = 0; j < ny; ++j) {
                    for (int k = 0; k < nz; ++k) {
                        if (beads.get(i, j, k) && !holes.get(i, j, k)) {
                            with_holes.set_run(i, j, k, k);
                        }
                    }
                }
            }
            beads = with_holes;
        } else {
            for (int b = 0; b < 3; ++b) box(beads, 2, nx - 3, uniform(1, 4), &targets);
            for (int b = 0; b < 2; ++b) box(finished, 2, nx - 3, uniform(2, 7), nullptr);
        }
        const auto nearest = [&](const Voxel& v) {
            long best = std::numeric_limits<long>::max();
            for (const Voxel& t : targets) best = std::min(best, d2_of(v, t));
            if (inside) {
                for (int a = 0; a < 3; ++a) {
                    const long across = std::min(v[a] - (lo - 1), hi[a] + 1 - v[a]);
                    best = std::min(best, across * across);
                }
            }
            return best;
        };
        const auto fin = [&](int i, int j, int k) {
            return i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz &&
                   finished.get(i, j, k);
        };
        long want = inside ? std::numeric_limits<long>::max() : -1;
        for (int i = 0; i < nx; ++i) {
            for (int j = 0; j < ny; ++j) {
                for (int k = 0; k < nz; ++k) {
                    if (!finished.get(i, j, k)) continue;
                    const bool asked = inside ? !fin(i - 1, j, k) || !fin(i + 1, j, k) ||
                                                    !fin(i, j - 1, k) || !fin(i, j + 1, k) ||
                                                    !fin(i, j, k - 1) || !fin(i, j, k + 1)
                                              : !beads.get(i, j, k);
                    if (!asked) continue;
                    const long d2 = nearest({i, j, k});
                    want = inside ? std::min(want, d2) : std::max(want, d2);
                }
            }
        }
        if (want < 0) continue;  // the finished part lies inside the small beads
        const int limit = 150;   // beyond the grid's diagonal
        const StockDistance got = stock_by_every_search(beads, finished, limit);
        ASSERT_FALSE(got.empty);
        ASSERT_EQ(got.inside, inside);
        ASSERT_LE(want, long{limit} * limit);
        EXPECT_FALSE(got.beyond);
        EXPECT_DOUBLE_EQ(got.distance, std::sqrt(static_cast<double>(want)));
        ASSERT_TRUE(finished.get(got.i, got.j, got.k));
        EXPECT_EQ(nearest({got.i, got.j, got.k}), want);
        if (want > 16 * 16) ++far_cases;  // past the fine search's first reach of 8
        ++(inside ? inside_cases : outside_cases);
    }
    EXPECT_GT(inside_cases, 3);
    EXPECT_GT(outside_cases, 3);
    EXPECT_GT(far_cases, 3);
}

TEST(VoxelGrid, SmallestStockOfNoFinishedVoxelIsEmpty) {
    BitGrid beads(8, 8, 8), finished(8, 8, 8);
    beads.set_rect(0, 7, 0, 7, 0, 3);
    EXPECT_TRUE(smallest_stock(beads, finished, 4).empty);
}

}  // namespace
}  // namespace maxslice::verify::detail
