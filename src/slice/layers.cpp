#include "maxslice/slice/layers.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace maxslice::slice {
namespace {

// A remainder thinner than this share of a layer is merged into the layer below.
constexpr double kMergeRemainderShare = 0.01;
// Facets whose normal is this close to the direction count as flat (horizontal).
constexpr double kFlatFacetCos = 1.0 - 1e-9;

LayerSpan make_span(double bottom, double top) {
    return {bottom, top, 0.5 * (bottom + top)};
}

}  // namespace

core::Result<void> check_layer_count(double height_mm, double thinnest_mm, std::string_view flag) {
    const double count = height_mm / thinnest_mm;
    if (!(thinnest_mm > 0.0) || !(count <= static_cast<double>(kMaxLayers))) {
        return core::fail(
            core::ErrorCode::kInvalidInput,
            fmt::format("{:.4g} mm layers over the part's {:.4g} mm would make {:.3g} layers, more "
                        "than the {} a job may cut: make them at least {:.3g} mm ({})",
                        thinnest_mm, height_mm, count, kMaxLayers,
                        height_mm / static_cast<double>(kMaxLayers), flag),
            std::string(flag));
    }
    return {};
}

core::Result<void> validate(const LayerSettings& s) {
    auto bad = [](std::string key, std::string why) {
        return core::fail(core::ErrorCode::kInvalidInput, key + " " + why, "layer settings");
    };
    if (!(s.layer_mm > 0.0) || !std::isfinite(s.layer_mm)) {
        return bad("layer height", "must be a positive number of mm");
    }
    if (s.adaptive) {
        if (!(s.cusp_mm > 0.0)) return bad("cusp", "must be a positive number of mm");
        if (!(s.min_layer_mm > 0.0)) return bad("minimum layer", "must be positive");
        if (!(s.max_layer_mm >= s.min_layer_mm)) {
            return bad("maximum layer", "must not be below the minimum layer height");
        }
    }
    return {};
}

std::vector<LayerSpan> uniform_layers(double from, double to, double layer_mm) {
    std::vector<LayerSpan> out;
    if (!(to > from) || !(layer_mm > 0.0)) return out;
    const double total = to - from;
    const auto n =
        static_cast<std::size_t>(std::max(1.0, std::ceil(total / layer_mm - kMergeRemainderShare)));
    out.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double bottom = from + static_cast<double>(i) * layer_mm;
        const double top = i + 1 == n ? to : from + static_cast<double>(i + 1) * layer_mm;
        out.push_back(make_span(bottom, top));
    }
    return out;
}

std::vector<LayerSpan> uniform_layers(double from, double to, double layer_mm, double h_min_mm,
                                      double h_max_mm) {
    std::vector<LayerSpan> out = uniform_layers(from, to, layer_mm);
    if (out.size() < 2 || !(out.back().thickness() < h_min_mm)) return out;
    const double bottom = out[out.size() - 2].bottom;
    const double top = out.back().top;
    out.pop_back();
    if (top - bottom <= h_max_mm) {
        out.back() = make_span(bottom, top);
    } else {
        const double mid = 0.5 * (bottom + top);
        out.back() = make_span(bottom, mid);
        out.push_back(make_span(mid, top));
    }
    return out;
}

std::vector<LayerSpan> adaptive_layers(const mesh::TriangleMesh& mesh, const PlaneFrame& base,
                                       double from, double to, const LayerSettings& s) {
    // Cusp height of a facet with unit normal n cut by layers of thickness h along d is
    // c = h |n . d| (METHOD.md section 2), so a facet allows h <= cusp / |n . d|. Facets are
    // swept by their lowest height; the active set holds those that reach the current layer.
    struct Facet {
        double lo, hi, cos;
    };
    std::vector<Facet> facets;
    std::vector<double> flats;  // heights of flat facets: good places for a layer boundary
    facets.reserve(mesh.triangles.size());
    const core::Vec3d d = base.normal;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const core::Vec3d a = mesh.corner(t, 0), b = mesh.corner(t, 1), c = mesh.corner(t, 2);
        const core::Vec3d n = core::normalized(core::cross(b - a, c - a));
        const double ha = base.height(a), hb = base.height(b), hc = base.height(c);
        const double cos = std::abs(core::dot(n, d));
        if (cos >= kFlatFacetCos) {
            flats.push_back(ha);
            continue;
        }
        facets.push_back({std::min({ha, hb, hc}), std::max({ha, hb, hc}), cos});
    }
    std::sort(facets.begin(), facets.end(), [](const Facet& x, const Facet& y) {
        return x.lo < y.lo || (x.lo == y.lo && x.hi < y.hi);
    });
    std::sort(flats.begin(), flats.end());

    std::vector<LayerSpan> out;
    std::vector<Facet> active;
    std::size_t next = 0;
    double z = from;
    const double hmin = s.min_layer_mm, hmax = s.max_layer_mm;
    while (to - z > kMergeRemainderShare * hmin) {
        while (next < facets.size() && facets[next].lo < z + hmax) active.push_back(facets[next++]);
        std::erase_if(active, [z](const Facet& f) { return f.hi <= z; });
        double h = hmax;
        for (const Facet& f : active) {
            if (f.lo < z + h && f.cos > 0.0) h = std::min(h, s.cusp_mm / f.cos);
        }
        h = std::clamp(h, hmin, hmax);
        // A flat face inside the layer is a step the layer would blur by up to its whole
        // thickness: end the layer on it when that leaves at least h_min, else keep the
        // layer as thin as a facet with |n . d| = 1 allows.
        auto flat = std::upper_bound(flats.begin(), flats.end(), z);
        if (flat != flats.end() && *flat < z + h) {
            h = *flat - z >= hmin ? *flat - z : std::min(h, std::max(hmin, s.cusp_mm));
        }
        // Do not leave a remainder thinner than h_min at the top: finish here when what is
        // left fits, else stop h_min short of the top (thinner than the cusp bound allows,
        // so still within it) and let the last layer be h_min.
        const double left = to - z;
        if (left <= h) {
            h = left;
        } else if (left - h < hmin) {
            if (left >= 2.0 * hmin) {
                h = left - hmin;
            } else {
                h = left <= hmax ? left : 0.5 * left;  // forced: [from, to] leaves no choice
            }
        }
        out.push_back(make_span(z, z + h));
        z += h;
    }
    if (!out.empty()) out.back() = make_span(out.back().bottom, to);
    return out;
}

}  // namespace maxslice::slice
