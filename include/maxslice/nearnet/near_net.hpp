// The near-net shape: what a DED job deposits so that machining gives the finished part
// (docs/decisions/0025-near-net-shape.md).
#pragma once

#include <cstddef>

#include "maxslice/core/progress.hpp"
#include "maxslice/core/result.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"

namespace maxslice::nearnet {

/// What machining takes off after the build. Both in mm; 0 turns each off.
struct NearNetSettings {
    /// Machining allowance per side: the deposit covers the finished surface by this much
    /// everywhere (up- and down-facing faces too), [0, kMaxStockMm].
    double stock_mm = 0.0;
    /// Holes, slots and inside corners narrower than this are filled and machined later
    /// (a morphological closing by a ball of half this diameter), [0, kMaxFillMm].
    double fill_below_mm = 0.0;

    static constexpr double kMaxStockMm = 20.0;
    static constexpr double kMaxFillMm = 100.0;

    /// Neither stock nor fill: the part is deposited as it is.
    [[nodiscard]] bool off() const { return stock_mm == 0.0 && fill_below_mm == 0.0; }
};

/// How the near-net shape was made, for the job's summary.
struct NearNetReport {
    double voxel_mm = 0.0;             ///< edge of the distance field's voxels (0 when off)
    std::size_t active_voxels = 0;     ///< voxels the distance field held at its largest
    double finished_volume_mm3 = 0.0;  ///< enclosed volume of the finished part
    double near_net_volume_mm3 = 0.0;  ///< enclosed volume of the near-net shape
    std::size_t open_edges = 0;        ///< the finished surface's edges used by one triangle
    std::size_t capped_holes = 0;      ///< holes capped for the fields' sign (mesh::cap_holes)
    [[nodiscard]] double added_fraction() const {
        return finished_volume_mm3 > 0.0 ? near_net_volume_mm3 / finished_volume_mm3 - 1.0 : 0.0;
    }
};

/// The near-net shape and how it was made.
struct NearNet {
    mesh::TriangleMesh mesh;
    NearNetReport report;
};

/// The shape to deposit for `finished` (part frame, mm; an open surface, such as a scan with
/// holes, has its holes capped first, mesh::cap_holes, so that the fields have an inside):
/// the finished part closed by a ball of diameter fill_below_mm (holes, slots and inside
/// corners narrower than that are filled), then grown by stock_mm. Computed on a narrow-band
/// signed distance field whose voxel is a fraction of the smaller non-zero of stock and fill
/// radius, coarsened for large parts down to a floor; the result is a closed, consistently
/// oriented mesh (outward normals), the same bytes whatever the number of threads. With
/// settings.off() the part comes back unchanged (bit for bit).
/// Errors: kInvalidInput for settings out of range, an empty part, non-finite coordinates,
/// a part whose surface would need more voxels than the bound at the coarsest voxel that
/// still resolves the stock (the message names the sizes and what would help), or a result
/// holding less than 99 % of the finished part's volume (the fields took some of its inside
/// for outside: the message says what would help);
/// kCancelled when `progress` is cancelled.
[[nodiscard]] core::Result<NearNet> near_net(const mesh::TriangleMesh& finished,
                                             const NearNetSettings& settings,
                                             const core::Progress* progress = nullptr);

/// Checks the settings' ranges; kInvalidInput names the field and the range.
[[nodiscard]] core::Result<void> validate(const NearNetSettings& settings);

}  // namespace maxslice::nearnet
