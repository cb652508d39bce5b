#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

#include "maxslice/core/result.hpp"
#include "maxslice/core/vec3.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"
#include "maxslice/slice/plane_frame.hpp"

namespace maxslice::slice {

/// One layer's extent along the slicing direction, as heights (mm) above a base plane.
/// The layer is cut at `cut` (its mid-height unless stated otherwise).
struct LayerSpan {
    double bottom = 0.0;
    double top = 0.0;
    double cut = 0.0;
    [[nodiscard]] double thickness() const { return top - bottom; }
};

/// Settings for choosing layer heights along one direction.
struct LayerSettings {
    double layer_mm = 0.5;      ///< uniform thickness
    bool adaptive = false;      ///< vary thickness to bound the cusp height
    double cusp_mm = 0.1;       ///< largest staircase (cusp) height allowed when adaptive
    double min_layer_mm = 0.2;  ///< h_min when adaptive
    double max_layer_mm = 0.5;  ///< h_max when adaptive
};

/// The most layers one job may cut. Every stage after the cut (trees, tracks, program,
/// verifier) grows with the layer count: a bound set before any work starts keeps a mistyped
/// layer height (1e-6 mm) from running for minutes and exhausting the memory. 100000 layers
/// is 10 m of 0.1 mm layers, far beyond any DED cell.
inline constexpr std::size_t kMaxLayers = 100000;

/// Refuses, before any layer is made, a job whose layers no thinner than `thinnest_mm` over
/// `height_mm` would number more than kMaxLayers; the message gives the count, the height and
/// the thinnest layer that keeps within the bound, and names `flag`, the option that sets
/// the layer height ("--layer", "--min-layer").
[[nodiscard]] core::Result<void> check_layer_count(double height_mm, double thinnest_mm,
                                                   std::string_view flag);

/// Checks ranges (positive, h_min <= layer <= h_max when adaptive ...).
[[nodiscard]] core::Result<void> validate(const LayerSettings& settings);

/// Equidistant layers covering heights [from, to]; the last layer is trimmed to end at `to`
/// (a remainder thinner than 1% of the layer is merged into the previous layer).
[[nodiscard]] std::vector<LayerSpan> uniform_layers(double from, double to, double layer_mm);

/// Equidistant layers as uniform_layers, but a last layer thinner than h_min (a process
/// cannot lay it: the speed law's thinnest track is h_min) is folded into the one below: the
/// two become one layer when that is at most h_max thick, else two of equal thickness. Only
/// the last two layers change; a range thinner than h_min stays one layer.
[[nodiscard]] std::vector<LayerSpan> uniform_layers(double from, double to, double layer_mm,
                                                    double h_min_mm, double h_max_mm);

/// Adaptive layers along base.normal over heights [from, to] measured from the base plane
/// (as extent_along gives them): each layer is as thick as the cusp bound allows for the
/// facets it crosses (c = h |n . d|), clamped to [min_layer_mm, max_layer_mm], and ends on a
/// flat face when one lies inside it. Only the last layer may be thinner than min_layer_mm,
/// when [from, to] itself is.
[[nodiscard]] std::vector<LayerSpan> adaptive_layers(const mesh::TriangleMesh& mesh,
                                                     const PlaneFrame& base, double from, double to,
                                                     const LayerSettings& settings);

}  // namespace maxslice::slice
