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
/// send the tool anywhere).
[[nodiscard]] inline int floor_index(double f) {
    return static_cast<int>(std::floor(std::clamp(f, -4.0, 1.0e9)));
}
[[nodiscard]] inline int ceil_index(double f) {
    return static_cast<int>(std::ceil(std::clamp(f, -4.0, 1.0e9)));
}

/// A grid of bits, z fastest: each (i, j) column is a run of 64-bit words.
class BitGrid {
public:
    BitGrid() = default;
    BitGrid(int nx, int ny, int nz)
        : nx_(nx),
          ny_(ny),
          nz_(nz),
          words_per_column_((nz + 63) / 64),
          bits_(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny) *
                    static_cast<std::size_t>(words_per_column_),
                0) {}

    [[nodiscard]] int nx() const { return nx_; }
    [[nodiscard]] int ny() const { return ny_; }
    [[nodiscard]] int nz() const { return nz_; }

    [[nodiscard]] bool get(int i, int j, int k) const {
        return (bits_[word(i, j, k)] >> (k & 63) & 1U) != 0;
    }
    /// Sets bits k0..k1 (inclusive) of column (i, j).
    void set_run(int i, int j, int k0, int k1) {
        std::uint64_t* col = &bits_[word(i, j, 0)];
        if ((k0 >> 6) == (k1 >> 6)) {  // one word: the usual bead column
            const int lo = k0 & 63, n = k1 - k0 + 1;
            const std::uint64_t ones = n == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << n) - 1;
            col[k0 >> 6] |= ones << lo;
            return;
        }
        int k = k0;
        while (k <= k1) {
            const int w = k >> 6;
            const int lo = k & 63;
            const int hi = std::min(63, lo + (k1 - k));
            const std::uint64_t mask =
                (hi == 63 ? ~std::uint64_t{0} : ((std::uint64_t{1} << (hi + 1)) - 1)) &
                ~((std::uint64_t{1} << lo) - 1);
            col[w] |= mask;
            k += hi - lo + 1;
        }
    }
    [[nodiscard]] const std::vector<std::uint64_t>& words() const { return bits_; }
    [[nodiscard]] std::size_t count() const {
        std::size_t n = 0;
        for (const std::uint64_t w : bits_) n += static_cast<std::size_t>(std::popcount(w));
        return n;
    }

private:
    [[nodiscard]] std::size_t word(int i, int j, int k) const {
        return (static_cast<std::size_t>(i) * static_cast<std::size_t>(ny_) +
                static_cast<std::size_t>(j)) *
                   static_cast<std::size_t>(words_per_column_) +
               static_cast<std::size_t>(k >> 6);
    }

    int nx_ = 0, ny_ = 0, nz_ = 0, words_per_column_ = 0;
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

    void set_run(int i, int j, int k0, int k1) {
        levels_.front().set_run(i, j, k0, k1);
        // Neighbouring columns share their coarse cells: stop at the first level whose run was
        // the previous call's (every coarser level was set then too).
        for (std::size_t l = 1; l < levels_.size(); ++l) {
            i >>= 1;
            j >>= 1;
            k0 >>= 1;
            k1 >>= 1;
            std::array<int, 4>& last = last_[l];
            if (last[0] == i && last[1] == j && last[2] == k0 && last[3] == k1) break;
            last = {i, j, k0, k1};
            levels_[l].set_run(i, j, k0, k1);
        }
    }

private:
    std::vector<BitGrid> levels_;
    std::vector<std::array<int, 4>> last_ = std::vector<std::array<int, 4>>(64, {-1, -1, -1, -1});
};

}  // namespace maxslice::verify::detail
