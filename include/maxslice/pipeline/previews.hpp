#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "maxslice/core/result.hpp"
#include "maxslice/path/toolpath.hpp"
#include "maxslice/pipeline/slice_job.hpp"

namespace maxslice::pipeline {

/// The part's facts and validation report as JSON text (for `maxslice info --json`).
[[nodiscard]] std::string info_json(const PreparedPart& part);
/// The same as a few human-readable lines.
[[nodiscard]] std::string info_text(const PreparedPart& part);

/// Writes the slice summary JSON: per layer the plane, span, thickness, area, counts of
/// outers and holes and the wire tree (parents, children, areas; no coordinates).
[[nodiscard]] core::Result<void> write_slices_json(const std::filesystem::path& file,
                                                   const SliceStack& stack,
                                                   const PreparedPart& part);

/// Writes one SVG per layer (layer_00001.svg ...) into dir: outers filled, holes cut out,
/// in the plane's own (u, v) frame, all layers at the same scale. With toolpaths (one per
/// slice), the deposited tracks are drawn as strokes of the track width (blue) and the idle
/// moves between them as thin dashed lines (red).
[[nodiscard]] core::Result<void> write_layer_svgs(
    const std::filesystem::path& dir, const SliceStack& stack,
    const std::vector<path::LayerToolpath>* toolpaths = nullptr, double track_width_mm = 0.0);
/// Writes all layers as a grid of small pictures in one SVG file.
[[nodiscard]] core::Result<void> write_contact_sheet(const std::filesystem::path& file,
                                                     const SliceStack& stack);

}  // namespace maxslice::pipeline
