// The machining stock a deposit leaves around the finished part, on the verifier's voxels.
// Private to verify.
#pragma once

#include <cstddef>
#include <cstdint>

#include "voxel_grid.hpp"

namespace maxslice::verify::detail {

/// The smallest stock in voxel steps (docs/verifier.md, decision 0026). Distances are
/// Euclidean between voxel centres, searched up to `limit` voxels.
struct StockDistance {
    /// Every voxel of the finished part is a bead voxel. Then `distance` is the smallest
    /// distance from a finished voxel to a voxel outside the beads; otherwise the largest
    /// distance from a finished voxel outside the beads to a bead voxel.
    bool inside = true;
    double distance = 0.0;    ///< voxels; `limit` when nothing lies within `limit`
    bool beyond = false;      ///< nothing found within `limit` (distance is a bound)
    int i = 0, j = 0, k = 0;  ///< the finished voxel where it was found (the first in i, j, k)
    bool empty = true;        ///< the finished part has no voxel
};

/// The stock of `finished` inside `beads` (grids of one size). Work: the box of the voxels
/// asked about (the finished part's, or of its voxels outside the beads) grown by the reach,
/// once per reach tried (8 voxels, times 4 up to `limit` while nothing is found): a 2D squared
/// distance transform of each plane (two scans, then Felzenszwalb and Huttenlocher's lower
/// envelope of parabolas) and a scan of at most 2 reach + 1 planes at each voxel asked about;
/// memory: 2 reach + 17 planes of that box, 16 bits a voxel (the caller bounds limit so that it
/// fits, limit <= kMaxStockLimit). Planes are transformed in parallel and asked about in order,
/// exact in integers: the same grids give the same answer whatever the thread count.
inline constexpr int kMaxStockLimit = 180;
/// How the distances are searched: the planes' transforms, each voxel asked about on its own
/// (nearest offsets first: fewer voxels asked than the box holds), or the cheaper of the two
/// by their counts. All give the same answer.
enum class StockSearch { kCheaper, kPlanes, kEachVoxel };
[[nodiscard]] StockDistance smallest_stock(const BitGrid& beads, const BitGrid& finished, int limit,
                                           StockSearch how = StockSearch::kCheaper);

/// The largest limit <= want (and >= 1) whose planes of a box nx x ny voxels fit in
/// `budget_bytes` (at least 1 even when they do not).
[[nodiscard]] int stock_limit_within(int want, int nx, int ny, std::size_t budget_bytes);

}  // namespace maxslice::verify::detail
