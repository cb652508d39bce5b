#pragma once

namespace maxslice::core {

// Each tolerance is named for its purpose; there is no shared epsilon.

/// A triangle whose area is below this (mm^2) counts as degenerate.
inline constexpr double kDegenerateTriangleAreaMm2 = 1e-12;
/// Default vertex weld distance for --repair, relative to the part's bounding-box diagonal.
inline constexpr double kRepairWeldRelative = 1e-6;
/// Parts smaller than this (largest extent, mm) are suspiciously small for millimetres.
inline constexpr double kImplausiblySmallPartMm = 1.0;
/// Parts larger than this (largest extent, mm) are suspiciously large for millimetres.
inline constexpr double kImplausiblyLargePartMm = 10000.0;
/// Open slice chains whose ends lie closer than this (mm) are closed by the slicer.
inline constexpr double kSliceGapCloseMm = 2.0;
/// Loops with a smaller area than this (mm^2) are dropped from a slice as noise.
inline constexpr double kSliceMinLoopAreaMm2 = 1e-4;

}  // namespace maxslice::core
