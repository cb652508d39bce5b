#include "region_query.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace maxslice::verify::detail {
namespace {

using core::Vec3d;

/// Rounding room for the floor test of find_occupied (mm): its bound and the per-voxel test
/// compute a voxel centre's a in different orders.
constexpr double kFloorSlack = 1e-9;

double segment_distance(const AxialPoint& p, const AxialPoint& q, double a, double r) {
    const double ea = q.a - p.a, er = q.r - p.r;
    const double len2 = ea * ea + er * er;
    double t = len2 > 0.0 ? ((a - p.a) * ea + (r - p.r) * er) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    const double da = a - (p.a + t * ea), dr = r - (p.r + t * er);
    return std::sqrt(da * da + dr * dr);
}

double polygon_distance(const std::array<AxialPoint, 4>& poly, double a, double r) {
    double inside = -std::numeric_limits<double>::infinity();
    bool outside = false;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < 4; ++i) {
        const AxialPoint& p = poly[i];
        const AxialPoint& q = poly[(i + 1) % 4];
        const double ea = q.a - p.a, er = q.r - p.r;
        const double len = std::sqrt(ea * ea + er * er);
        if (len == 0.0) continue;
        // Outward normal of a counter-clockwise edge: (er, -ea).
        const double line = ((a - p.a) * er - (r - p.r) * ea) / len;
        if (line > 0.0) outside = true;
        inside = std::max(inside, line);
        best = std::min(best, segment_distance(p, q, a, r));
    }
    return outside ? best : inside;
}

struct Query {
    const OccupancyPyramid& grid;
    Vec3d origin;
    double voxel;
    Vec3d apex;
    Vec3d axis;
    double axial_half_extent;  // |axis.x| + |axis.y| + |axis.z|, times half a cell
    const Region& region;
    double margin;
    Vec3d* hit;

    bool cell(int level, int i, int j, int k) const {
        const BitGrid& g = grid.level(level);
        if (i >= g.nx() || j >= g.ny() || k >= g.nz()) return false;
        if (!g.get(i, j, k)) return false;
        const double size = voxel * static_cast<double>(1 << level);
        const Vec3d c = origin + Vec3d{(i + 0.5) * size, (j + 0.5) * size, (k + 0.5) * size};
        const Vec3d rel = c - apex;
        const double a = core::dot(rel, axis);
        if (level == 0) {
            if (a < region.a_min) return false;
            const double r = core::norm(rel - axis * a);
            if (!region.bound_within(a, r, margin) ||
                (margin > 0.0 && region.distance(a, r) > margin)) {
                return false;
            }
            if (hit != nullptr) *hit = c;
            return true;
        }
        const double ext = 0.5 * size * axial_half_extent;
        if (a + ext < region.a_min || a - ext > region.a_max + margin) return false;
        const double r = core::norm(rel - axis * a);
        const double rho = 0.5 * size * std::numbers::sqrt3;
        if (!region.bound_within(a, r, margin + rho)) return false;
        for (int di = 0; di < 2; ++di) {
            for (int dj = 0; dj < 2; ++dj) {
                for (int dk = 0; dk < 2; ++dk) {
                    if (cell(level - 1, 2 * i + di, 2 * j + dj, 2 * k + dk)) return true;
                }
            }
        }
        return false;
    }
};

}  // namespace

void Region::add(const std::array<AxialPoint, 4>& p) {
    if (polygons.empty()) {
        a_min = std::numeric_limits<double>::infinity();
        a_max = -std::numeric_limits<double>::infinity();
        r_max = 0.0;
    }
    polygons.push_back(p);
    std::array<Edge, 4> e{};
    for (std::size_t i = 0; i < 4; ++i) {
        const AxialPoint& u = p[i];
        const AxialPoint& w = p[(i + 1) % 4];
        const double ea = w.a - u.a, er = w.r - u.r;
        const double len = std::sqrt(ea * ea + er * er);
        if (len == 0.0) {
            e[i] = {0.0, 0.0, 0.0};  // never the largest for a point outside
            continue;
        }
        e[i] = {er / len, -ea / len, (u.a * er - u.r * ea) / len};
    }
    edges.push_back(e);
    for (const AxialPoint& q : p) {
        a_min = std::min(a_min, q.a);
        a_max = std::max(a_max, q.a);
        r_max = std::max(r_max, std::abs(q.r));
    }
}

double Region::distance_bound(double a, double r) const {
    double d = std::numeric_limits<double>::infinity();
    for (const auto& poly : edges) {
        double m = -std::numeric_limits<double>::infinity();
        for (const Edge& e : poly) m = std::max(m, a * e.na + r * e.nr - e.offset);
        d = std::min(d, m);
    }
    return d;
}

bool Region::bound_within(double a, double r, double limit) const {
    for (const auto& poly : edges) {
        bool within = true;
        for (const Edge& e : poly) {
            if (a * e.na + r * e.nr - e.offset > limit) {
                within = false;
                break;
            }
        }
        if (within) return true;
    }
    return false;
}

double Region::distance(double a, double r) const {
    double d = std::numeric_limits<double>::infinity();
    for (const auto& p : polygons) d = std::min(d, polygon_distance(p, a, r));
    return d;
}

bool find_occupied(const OccupancyPyramid& grid, const Vec3d& origin, double voxel,
                   const Vec3d& apex, const Vec3d& axis, const Region& region, double margin,
                   Vec3d* hit) {
    if (region.polygons.empty()) return false;
    // Nothing set at or above the region's floor (a planar layer's head above everything built
    // so far, a travel move above the part): no voxel of the set box reaches a_min.
    const std::array<int, 3>& set_lo = grid.set_lo();
    const std::array<int, 3>& set_hi = grid.set_hi();
    if (set_lo[0] > set_hi[0]) return false;
    double top = 0.0;  // the largest a of a voxel centre in the set box
    for (int c = 0; c < 3; ++c) {
        const auto u = static_cast<std::size_t>(c);
        const double lo_c = origin[c] + (set_lo[u] + 0.5) * voxel - apex[c];
        const double hi_c = origin[c] + (set_hi[u] + 0.5) * voxel - apex[c];
        top += std::max(axis[c] * lo_c, axis[c] * hi_c);
    }
    if (top < region.a_min - kFloorSlack) return false;
    const Query q{grid,   origin, voxel,
                  apex,   axis,   std::abs(axis.x) + std::abs(axis.y) + std::abs(axis.z),
                  region, margin, hit};
    // The voxel at the middle of the region's axis first: the material under a bead usually
    // lies right there, and a hit there ends the search in one look. A hit there lies inside
    // the index box computed below (the region's box cut to the set voxels), so looking before
    // computing that box changes only the time.
    const BitGrid& fine = grid.fine();
    const std::array<int, 3> n{fine.nx(), fine.ny(), fine.nz()};
    const Vec3d mid = apex + axis * (0.5 * (region.a_min + region.a_max));
    std::array<int, 3> probe{};
    bool probe_inside = true;
    for (std::size_t c = 0; c < 3; ++c) {
        const int ci = static_cast<int>(c);
        probe[c] = floor_index((mid[ci] - origin[ci]) / voxel);
        probe_inside = probe_inside && probe[c] >= set_lo[c] && probe[c] <= set_hi[c];
    }
    if (probe_inside && q.cell(0, probe[0], probe[1], probe[2])) return true;
    // The region's bounding box: the axis segment widened by r_max across it.
    std::array<double, 3> lo{}, hi{};
    const double reach = region.r_max + margin;
    for (int c = 0; c < 3; ++c) {
        const double ac = axis[c];
        const double p0 = apex[c] + ac * region.a_min, p1 = apex[c] + ac * region.a_max;
        const double across = reach * std::sqrt(std::max(0.0, 1.0 - ac * ac));
        lo[static_cast<std::size_t>(c)] = std::min(p0, p1) - across - margin;
        hi[static_cast<std::size_t>(c)] = std::max(p0, p1) + across + margin;
    }
    std::array<int, 3> i0{}, i1{};
    int span = 1;
    for (std::size_t c = 0; c < 3; ++c) {
        const double o = origin[static_cast<int>(c)];
        i0[c] = std::max(set_lo[c], floor_index((lo[c] - o) / voxel));
        i1[c] = std::min({n[c] - 1, set_hi[c], floor_index((hi[c] - o) / voxel)});
        if (i0[c] > i1[c]) return false;
        span = std::max(span, i1[c] - i0[c] + 1);
    }
    // Start at the level where the box spans about two cells along its longest side.
    int level = 0;
    while (level + 1 < grid.level_count() && (span >> level) > 2) ++level;
    for (int i = i0[0] >> level; i <= i1[0] >> level; ++i) {
        for (int j = i0[1] >> level; j <= i1[1] >> level; ++j) {
            for (int k = i0[2] >> level; k <= i1[2] >> level; ++k) {
                if (q.cell(level, i, j, k)) return true;
            }
        }
    }
    return false;
}

void fill(OccupancyPyramid& grid, const Vec3d& origin, double voxel, const Slabs& solid) {
    core::Box3d box;
    for (const Vec3d& c : solid.corners()) box.add(c);
    if (box.empty()) return;
    const BitGrid& fine = grid.fine();
    const double inv_voxel = 1.0 / voxel;
    const auto index = [&](double x, double o, int n, bool upper) {
        // Voxel centres o + (i + 0.5) v inside [x_lo, x_hi].
        const double f = (x - o) * inv_voxel - 0.5;
        const int i = upper ? floor_index(f) : ceil_index(f);
        return std::clamp(i, -1, n);
    };
    const int i0 = std::max(0, index(box.min.x, origin.x, fine.nx(), false));
    const int i1 = std::min(fine.nx() - 1, index(box.max.x, origin.x, fine.nx(), true));
    const int j0 = std::max(0, index(box.min.y, origin.y, fine.ny(), false));
    const int j1 = std::min(fine.ny() - 1, index(box.max.y, origin.y, fine.ny(), true));
    // Slabs parallel to z bound each row's y range (with 1 / n.y once per slab, not per row);
    // only the others are evaluated per column.
    struct Vertical {
        const Slabs::Slab* slab;
        double inv_ny;  // 0 for a slab across x only
    };
    std::array<Vertical, Slabs::kMax> vertical_slabs{};
    std::size_t vertical_count = 0;
    struct Tilted {
        double nx_over_nz, ny_over_nz, lo_over_nz, hi_over_nz;
    };
    std::array<Tilted, Slabs::kMax> tilted_slabs{};
    std::size_t tilted_count = 0;
    for (const auto& sl : solid.slabs()) {
        if (std::abs(sl.n.z) < 1e-12) {
            vertical_slabs[vertical_count++] = {&sl, std::abs(sl.n.y) < 1e-12 ? 0.0 : 1.0 / sl.n.y};
        } else {
            const double inv = 1.0 / sl.n.z;
            double lo = sl.lo * inv, hi = sl.hi * inv;
            if (lo > hi) std::swap(lo, hi);
            tilted_slabs[tilted_count++] = {sl.n.x * inv, sl.n.y * inv, lo, hi};
        }
    }
    const std::span<const Vertical> vertical(vertical_slabs.data(), vertical_count);
    const std::span<const Tilted> tilted(tilted_slabs.data(), tilted_count);
    // No slab's bound on z changes along y (a bead laid straight down): rows are blocks.
    const bool level_rows = std::all_of(tilted.begin(), tilted.end(),
                                        [](const Tilted& t) { return t.ny_over_nz == 0.0; });
    // Neighbouring rows that set the same columns and bits (a bead along x) are set as one
    // rectangle, the pyramid above it once; the set box grows once, at the end.
    std::array<int, 3> set_lo{INT32_MAX, INT32_MAX, INT32_MAX};
    std::array<int, 3> set_hi{-1, -1, -1};
    struct Rect {
        int i0 = 0, i1 = -2, j0 = 0, j1 = 0, k0 = 0, k1 = 0;
    } rect;
    const auto set = [&](const Rect& r) {
        grid.set_cells(r.i0, r.i1, r.j0, r.j1, r.k0, r.k1);
        set_lo = {std::min(set_lo[0], r.i0), std::min(set_lo[1], r.j0), std::min(set_lo[2], r.k0)};
        set_hi = {std::max(set_hi[0], r.i1), std::max(set_hi[1], r.j1), std::max(set_hi[2], r.k1)};
    };
    const auto flush = [&] {
        if (rect.i1 < rect.i0) return;
        set(rect);
        rect.i1 = rect.i0 - 1;
    };
    const auto set_row = [&](int i, int ja, int jb, int k0, int k1) {
        if (i == rect.i1 + 1 && ja == rect.j0 && jb == rect.j1 && k0 == rect.k0 && k1 == rect.k1) {
            rect.i1 = i;
            return;
        }
        flush();
        rect = {i, i, ja, jb, k0, k1};
    };
    // A column of its own (the z interval changes along the row): set at once.
    const auto set_column = [&](int i, int j, int k0, int k1) { set({i, i, j, j, k0, k1}); };
    for (int i = i0; i <= i1; ++i) {
        const double x = origin.x + (i + 0.5) * voxel;
        double y_lo = box.min.y, y_hi = box.max.y;
        bool empty = false;
        for (const auto& [sl, inv] : vertical) {
            const double base = sl->n.x * x;
            if (inv == 0.0) {
                if (base < sl->lo || base > sl->hi) empty = true;
                continue;
            }
            double a = (sl->lo - base) * inv, b = (sl->hi - base) * inv;
            if (a > b) std::swap(a, b);
            y_lo = std::max(y_lo, a);
            y_hi = std::min(y_hi, b);
        }
        if (empty || y_lo > y_hi) continue;
        const int ja = std::max(j0, index(y_lo, origin.y, fine.ny(), false));
        const int jb = std::min(j1, index(y_hi, origin.y, fine.ny(), true));
        if (ja <= jb && level_rows) {
            // Every column of the row gets the same z interval: one block.
            double t0 = box.min.z, t1 = box.max.z;
            for (const Tilted& sl : tilted) {
                const double base = sl.nx_over_nz * x;
                t0 = std::max(t0, sl.lo_over_nz - base);
                t1 = std::min(t1, sl.hi_over_nz - base);
            }
            if (t0 > t1) continue;
            const int k0 = std::max(0, index(t0, origin.z, fine.nz(), false));
            const int k1 = std::min(fine.nz() - 1, index(t1, origin.z, fine.nz(), true));
            if (k0 <= k1) set_row(i, ja, jb, k0, k1);
            continue;
        }
        for (int j = ja; j <= jb; ++j) {
            const double y = origin.y + (j + 0.5) * voxel;
            // The column x, y, z = t: each remaining slab bounds t to an interval.
            double t0 = box.min.z, t1 = box.max.z;
            for (const Tilted& sl : tilted) {
                const double base = sl.nx_over_nz * x + sl.ny_over_nz * y;
                t0 = std::max(t0, sl.lo_over_nz - base);
                t1 = std::min(t1, sl.hi_over_nz - base);
            }
            if (t0 > t1) continue;
            const int k0 = std::max(0, index(t0, origin.z, fine.nz(), false));
            const int k1 = std::min(fine.nz() - 1, index(t1, origin.z, fine.nz(), true));
            if (k0 <= k1) set_column(i, j, k0, k1);
        }
    }
    flush();
    if (set_lo[0] <= set_hi[0]) grid.extend_set_box(set_lo, set_hi);
}

}  // namespace maxslice::verify::detail
