// Bit voxel grids for the verifier: a fine occupancy grid with a pyramid of coarser
// "any voxel set below" levels for sub-linear region queries. Private to verify.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "maxslice/core/vec3.hpp"

namespace maxslice::verify::detail {

/// floor / ceil of a grid coordinate as an int, saturated far outside any grid (a program may
/// send the tool anywhere). The conversion truncates toward zero and is corrected by one: the
/// same value as std::floor / std::ceil, without a call into libm (the verifier takes several
/// per voxel row).
[[nodiscard]] inline int floor_index(double f) {
    const double c = std::clamp(f, -4.0, 1.0e9);
    const int t = static_cast<int>(c);
    return static_cast<double>(t) > c ? t - 1 : t;
}
[[nodiscard]] inline int ceil_index(double f) {
    const double c = std::clamp(f, -4.0, 1.0e9);
    const int t = static_cast<int>(c);
    return static_cast<double>(t) < c ? t + 1 : t;
}

/// A grid of bits. A word holds 64 voxels of one (i, j) column along z; the words of one
/// z band (k / 64) form a plane with j fastest, so the columns a bead touches side by side lie
/// in neighbouring words (one cache line holds eight columns).
class BitGrid {
public:
    BitGrid() = default;
    BitGrid(int nx, int ny, int nz)
        : nx_(nx),
          ny_(ny),
          nz_(nz),
          plane_(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny)),
          bits_(plane_ * static_cast<std::size_t>((nz + 63) / 64), 0) {}

    [[nodiscard]] int nx() const { return nx_; }
    [[nodiscard]] int ny() const { return ny_; }
    [[nodiscard]] int nz() const { return nz_; }

    [[nodiscard]] bool get(int i, int j, int k) const {
        return (bits_[word(i, j, k)] >> (k & 63) & 1U) != 0;
    }
    /// Sets bits k0..k1 (inclusive) of column (i, j).
    void set_run(int i, int j, int k0, int k1) { set_block(i, j, j, k0, k1); }
    /// Sets bits k0..k1 (inclusive) of the columns (i, j0) to (i, j1); returns whether every
    /// one of them was set already.
    bool set_block(int i, int j0, int j1, int k0, int k1) { return set_rect(i, i, j0, j1, k0, k1); }
    /// Sets bits k0..k1 (inclusive) of the columns (i0..i1, j0..j1); returns whether every one
    /// of them was set already.
    bool set_rect(int i0, int i1, int j0, int j1, int k0, int k1) {
        const std::size_t n = static_cast<std::size_t>(j1 - j0) + 1;
        std::uint64_t missing = 0;
        int k = k0;
        for (;;) {
            const int lo = k & 63;
            const int hi = std::min(63, lo + (k1 - k));
            const std::uint64_t mask =
                (hi == 63 ? ~std::uint64_t{0} : ((std::uint64_t{1} << (hi + 1)) - 1)) &
                ~((std::uint64_t{1} << lo) - 1);
            std::uint64_t* row = &bits_[word(i0, j0, k)];
            for (int i = i0; i <= i1; ++i, row += ny_) {
                for (std::size_t j = 0; j < n; ++j) {
                    missing |= mask & ~row[j];
                    row[j] |= mask;
                }
            }
            k += hi - lo + 1;
            if (k > k1) return missing == 0;
        }
    }
    /// Every word; two grids of the same size match word for word.
    [[nodiscard]] const std::vector<std::uint64_t>& words() const { return bits_; }
    [[nodiscard]] std::size_t count() const {
        std::size_t n = 0;
        for (const std::uint64_t w : bits_) n += static_cast<std::size_t>(std::popcount(w));
        return n;
    }

private:
    [[nodiscard]] std::size_t word(int i, int j, int k) const {
        return static_cast<std::size_t>(k >> 6) * plane_ +
               static_cast<std::size_t>(i) * static_cast<std::size_t>(ny_) +
               static_cast<std::size_t>(j);
    }

    int nx_ = 0, ny_ = 0, nz_ = 0;
    std::size_t plane_ = 0;  // words in one z band
    std::vector<std::uint64_t> bits_;
};

/// The fine grid and its pyramid: level l holds one bit per 2^l voxels along each axis, set
/// when any voxel below it is set. Only grows (beads are added, never removed).
class OccupancyPyramid {
public:
    OccupancyPyramid() = default;
    OccupancyPyramid(int nx, int ny, int nz) {
        levels_.emplace_back(nx, ny, nz);
        while (std::max({nx, ny, nz}) > 1) {
            nx = (nx + 1) / 2;
            ny = (ny + 1) / 2;
            nz = (nz + 1) / 2;
            levels_.emplace_back(nx, ny, nz);
        }
    }
    [[nodiscard]] int level_count() const { return static_cast<int>(levels_.size()); }
    [[nodiscard]] const BitGrid& level(int l) const { return levels_[static_cast<std::size_t>(l)]; }
    [[nodiscard]] const BitGrid& fine() const { return levels_.front(); }
    /// The index box of every voxel set so far (lo > hi on an axis while nothing is set).
    [[nodiscard]] const std::array<int, 3>& set_lo() const { return set_lo_; }
    [[nodiscard]] const std::array<int, 3>& set_hi() const { return set_hi_; }

    /// Sets bits k0..k1 (inclusive) of the fine columns (i, j0) to (i, j1), and the pyramid.
    void set_block(int i, int j0, int j1, int k0, int k1) {
        extend_set_box({i, j0, k0}, {i, j1, k1});
        set_cells(i, i, j0, j1, k0, k1);
    }
    void set_run(int i, int j, int k0, int k1) { set_block(i, j, j, k0, k1); }

    /// Sets the fine columns (i0..i1, j0..j1), bits k0..k1, and the pyramid, but not the set
    /// box: for a caller that sets many blocks and then extends the box once by their bounds
    /// (it must, before the next query).
    void set_cells(int i0, int i1, int j0, int j1, int k0, int k1) {
        levels_.front().set_rect(i0, i1, j0, j1, k0, k1);
        // A coarse cell already set has every coarser cell above it set: stop at the first
        // level where the block was set already (neighbouring calls share their coarse cells).
        for (std::size_t l = 1; l < levels_.size(); ++l) {
            i0 >>= 1;
            i1 >>= 1;
            j0 >>= 1;
            j1 >>= 1;
            k0 >>= 1;
            k1 >>= 1;
            if (levels_[l].set_rect(i0, i1, j0, j1, k0, k1)) break;
        }
    }
    void extend_set_box(const std::array<int, 3>& lo, const std::array<int, 3>& hi) {
        for (std::size_t c = 0; c < 3; ++c) {
            set_lo_[c] = std::min(set_lo_[c], lo[c]);
            set_hi_[c] = std::max(set_hi_[c], hi[c]);
        }
    }

private:
    std::vector<BitGrid> levels_;
    std::array<int, 3> set_lo_{INT32_MAX, INT32_MAX, INT32_MAX};
    std::array<int, 3> set_hi_{-1, -1, -1};
};

}  // namespace maxslice::verify::detail
