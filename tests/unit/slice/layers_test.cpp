#include "maxslice/slice/layers.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "maxslice/slice/slicer.hpp"
#include "support/fixtures.hpp"

namespace maxslice::slice {
namespace {

using core::Vec3d;

// Spans cover [from, to] with no gap and no overlap, and each cut lies in its span.
void expect_covers(const std::vector<LayerSpan>& layers, double from, double to) {
    ASSERT_FALSE(layers.empty());
    EXPECT_EQ(layers.front().bottom, from);
    EXPECT_EQ(layers.back().top, to);
    for (std::size_t i = 0; i < layers.size(); ++i) {
        SCOPED_TRACE("layer " + std::to_string(i));
        EXPECT_GT(layers[i].thickness(), 0.0);
        EXPECT_GE(layers[i].cut, layers[i].bottom);
        EXPECT_LE(layers[i].cut, layers[i].top);
        if (i + 1 < layers.size()) {
            EXPECT_EQ(layers[i].top, layers[i + 1].bottom);
        }
    }
}

TEST(LayerSettings, DefaultsAreValid) {
    EXPECT_TRUE(validate(LayerSettings{}).has_value());
}

TEST(LayerSettings, RejectsBadRanges) {
    auto rejected = [](LayerSettings s) {
        const auto r = validate(s);
        return !r.has_value() && r.error().code == core::ErrorCode::kInvalidInput &&
               !r.error().message.empty();
    };
    EXPECT_TRUE(rejected({.layer_mm = 0.0}));
    EXPECT_TRUE(rejected({.layer_mm = -0.5}));
    EXPECT_TRUE(rejected({.layer_mm = std::nan("")}));
    EXPECT_TRUE(rejected({.layer_mm = INFINITY}));
    EXPECT_TRUE(rejected({.layer_mm = 0.3, .adaptive = true, .cusp_mm = 0.0}));
    EXPECT_TRUE(rejected({.layer_mm = 0.3, .adaptive = true, .min_layer_mm = 0.0}));
    EXPECT_TRUE(
        rejected({.layer_mm = 0.3, .adaptive = true, .min_layer_mm = 0.6, .max_layer_mm = 0.4}));
    EXPECT_FALSE(
        rejected({.layer_mm = 0.3, .adaptive = true, .min_layer_mm = 0.1, .max_layer_mm = 0.4}));
}

TEST(UniformLayers, ExactMultipleGivesEqualLayers) {
    const auto layers = uniform_layers(0.0, 10.0, 0.5);
    ASSERT_EQ(layers.size(), 20u);
    expect_covers(layers, 0.0, 10.0);
    for (const auto& l : layers) {
        EXPECT_NEAR(l.thickness(), 0.5, 1e-12);
        EXPECT_NEAR(l.cut, 0.5 * (l.bottom + l.top), 1e-12);
    }
}

TEST(UniformLayers, RemainderBecomesAThinnerLastLayer) {
    const auto layers = uniform_layers(0.0, 10.2, 0.5);
    ASSERT_EQ(layers.size(), 21u);
    expect_covers(layers, 0.0, 10.2);
    EXPECT_NEAR(layers.back().thickness(), 0.2, 1e-9);
}

TEST(UniformLayers, TinyRemainderIsMergedIntoTheLastLayer) {
    const auto layers = uniform_layers(0.0, 10.003, 0.5);
    ASSERT_EQ(layers.size(), 20u);
    expect_covers(layers, 0.0, 10.003);
    EXPECT_NEAR(layers.back().thickness(), 0.503, 1e-9);
}

TEST(UniformLayers, InexactDecimalsStillCoverExactly) {
    // 3.3 - 2.5 is 0.7999999999999998 in binary: still 8 layers, none a sliver.
    const auto layers = uniform_layers(2.5, 3.3, 0.1);
    ASSERT_EQ(layers.size(), 8u);
    expect_covers(layers, 2.5, 3.3);
    for (const auto& l : layers) EXPECT_NEAR(l.thickness(), 0.1, 1e-9);
}

TEST(UniformLayers, RandomRangesAreCoveredWithoutSlivers) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> pos(-50.0, 50.0), len(0.05, 80.0), h(0.05, 2.0);
    for (int i = 0; i < 500; ++i) {
        const double from = pos(rng), to = from + len(rng), layer = h(rng);
        const auto layers = uniform_layers(from, to, layer);
        SCOPED_TRACE(std::to_string(from) + " " + std::to_string(to) + " " + std::to_string(layer));
        expect_covers(layers, from, to);
        for (std::size_t k = 0; k + 1 < layers.size(); ++k) {
            EXPECT_NEAR(layers[k].thickness(), layer, 1e-9 * (1.0 + std::abs(to)));
        }
        if (layers.size() > 1) {
            EXPECT_GE(layers.back().thickness(), 0.01 * layer * (1.0 - 1e-6));
        }
        EXPECT_LE(layers.back().thickness(), 1.01 * layer * (1.0 + 1e-9));
    }
}

// ---- Adaptive layers ----------------------------------------------------------------------

const LayerSettings kAdaptive{
    .layer_mm = 0.2, .adaptive = true, .cusp_mm = 0.1, .min_layer_mm = 0.05, .max_layer_mm = 0.5};

// The steepest |n . d| over facets that reach into the open span (bottom, top), heights
// measured in the base frame.
double steepest_cos_in(const mesh::TriangleMesh& m, const PlaneFrame& base, const LayerSpan& span) {
    double worst = 0.0;
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const Vec3d a = m.corner(t, 0), b = m.corner(t, 1), c = m.corner(t, 2);
        const double lo = std::min({base.height(a), base.height(b), base.height(c)});
        const double hi = std::max({base.height(a), base.height(b), base.height(c)});
        if (hi <= span.bottom + 1e-9 || lo >= span.top - 1e-9) continue;
        const Vec3d n = core::normalized(core::cross(b - a, c - a));
        worst = std::max(worst, std::abs(core::dot(n, base.normal)));
    }
    return worst;
}

struct AdaptiveCase {
    mesh::TriangleMesh mesh;
    PlaneFrame base;
    double lo = 0.0, hi = 0.0;
    std::vector<LayerSpan> layers;
};

AdaptiveCase adaptive_case(mesh::TriangleMesh m, const Vec3d& dir, const LayerSettings& s) {
    AdaptiveCase c;
    c.base = base_frame(m, dir);
    std::tie(c.lo, c.hi) = extent_along(m, c.base);
    c.layers = adaptive_layers(m, c.base, c.lo, c.hi, s);
    c.mesh = std::move(m);
    return c;
}

void expect_adaptive_properties(const AdaptiveCase& c, const LayerSettings& s) {
    expect_covers(c.layers, c.lo, c.hi);
    int cusp_violations = 0;
    for (std::size_t i = 0; i < c.layers.size(); ++i) {
        const LayerSpan& l = c.layers[i];
        SCOPED_TRACE("layer " + std::to_string(i) + " [" + std::to_string(l.bottom) + ", " +
                     std::to_string(l.top) + "]");
        EXPECT_GE(l.thickness(), s.min_layer_mm - 1e-9);
        EXPECT_LE(l.thickness(), s.max_layer_mm + 1e-9);
        // The cusp bound holds unless the layer is already at its minimum thickness, or it
        // is the last one and too short to split into two layers of at least the minimum.
        const double cusp = l.thickness() * steepest_cos_in(c.mesh, c.base, l);
        const bool forced = l.thickness() <= s.min_layer_mm + 1e-9 ||
                            (i + 1 == c.layers.size() && l.thickness() < 2.0 * s.min_layer_mm);
        if (!forced && cusp > s.cusp_mm * (1.0 + 1e-6)) {
            ++cusp_violations;
            ADD_FAILURE() << "cusp " << cusp << " > " << s.cusp_mm;
        }
    }
    EXPECT_EQ(cusp_violations, 0);
}

TEST(AdaptiveLayers, CylinderOnItsSideBoundsTheCusp) {
    const auto c = adaptive_case(test::cylinder_on_side(10.0, 30.0, 64), {0, 0, 1}, kAdaptive);
    EXPECT_NEAR(c.lo, 0.0, 1e-12);
    EXPECT_NEAR(c.hi, 20.0, 1e-12);
    expect_adaptive_properties(c, kAdaptive);
}

TEST(AdaptiveLayers, CylinderOnItsSideIsThinnerWhereTheSurfaceIsFlat) {
    const auto c = adaptive_case(test::cylinder_on_side(10.0, 30.0, 64), {0, 0, 1}, kAdaptive);
    ASSERT_GE(c.layers.size(), 3u);
    // The lowest facets are within pi/64 of horizontal: h <= cusp / cos(pi / 64).
    EXPECT_LE(c.layers.front().thickness(),
              kAdaptive.cusp_mm / std::cos(std::numbers::pi / 64) + 1e-9);
    // Within 1 mm of the bottom and top the facets are within 26 degrees of horizontal.
    for (const LayerSpan& l : c.layers) {
        if (l.top <= 1.0 || l.bottom >= 19.0) {
            EXPECT_LE(l.thickness(), kAdaptive.cusp_mm / std::cos(26.0 * std::numbers::pi / 180))
                << l.bottom;
        }
    }
    // At mid-height the facets are within pi/64 of vertical: the maximum layer fits.
    for (const LayerSpan& l : c.layers) {
        if (l.bottom <= 10.0 && 10.0 < l.top) {
            EXPECT_NEAR(l.thickness(), kAdaptive.max_layer_mm, 1e-9);
        }
    }
    // Fewer layers than at the minimum thickness, more than at the maximum.
    EXPECT_LT(c.layers.size(), static_cast<std::size_t>(20.0 / kAdaptive.min_layer_mm));
    EXPECT_GT(c.layers.size(), static_cast<std::size_t>(20.0 / kAdaptive.max_layer_mm));
}

TEST(AdaptiveLayers, DoNotDependOnWhereThePartIs) {
    // Heights given to adaptive_layers come from extent_along(base_frame(...)), as
    // slice_mesh expects them: moving the part must not change the layers.
    const auto here = adaptive_case(test::cylinder_on_side(10.0, 30.0, 64), {0, 0, 1}, kAdaptive);
    const auto there =
        adaptive_case(test::translated(test::cylinder_on_side(10.0, 30.0, 64), {3.0, -2.0, 7.0}),
                      {0, 0, 1}, kAdaptive);
    ASSERT_EQ(here.layers.size(), there.layers.size());
    for (std::size_t i = 0; i < here.layers.size(); ++i) {
        EXPECT_NEAR(here.layers[i].bottom, there.layers[i].bottom, 1e-9) << i;
        EXPECT_NEAR(here.layers[i].top, there.layers[i].top, 1e-9) << i;
    }
    expect_adaptive_properties(there, kAdaptive);
}

TEST(AdaptiveLayers, ObliqueDirectionBoundsTheCusp) {
    const Vec3d d = core::normalized({0.3, -0.5, 1.0});
    const auto c = adaptive_case(test::cylinder_on_side(10.0, 30.0, 64), d, kAdaptive);
    expect_adaptive_properties(c, kAdaptive);
}

TEST(AdaptiveLayers, VerticalWallsGetTheMaximumLayer) {
    const auto c = adaptive_case(test::cylinder(10.0, 20.0, 64), {0, 0, 1}, kAdaptive);
    expect_adaptive_properties(c, kAdaptive);
    for (const LayerSpan& l : c.layers) EXPECT_NEAR(l.thickness(), kAdaptive.max_layer_mm, 1e-9);
}

TEST(AdaptiveLayers, LayersCrossingFlatFacesStayUnderTheCusp) {
    // A horizontal face has |n . d| = 1: a layer across it may be at most cusp thick (or
    // it ends on the face).
    expect_adaptive_properties(adaptive_case(test::nested_boxes(), {0, 0, 1}, kAdaptive),
                               kAdaptive);
    expect_adaptive_properties(adaptive_case(test::t_shape(), {0, 0, 1}, kAdaptive), kAdaptive);
}

TEST(AdaptiveLayers, FlatFaceJustAboveALayerBoundary) {
    // Settings where a flat face (the cavity floor at z = 3, the bar's underside at z = 10)
    // comes less than min_layer above a layer boundary.
    const LayerSettings nested{.layer_mm = 0.2,
                               .adaptive = true,
                               .cusp_mm = 0.133,
                               .min_layer_mm = 0.137,
                               .max_layer_mm = 0.728};
    ASSERT_TRUE(validate(nested).has_value());
    expect_adaptive_properties(adaptive_case(test::nested_boxes(), {0, 0, 1}, nested), nested);
    const LayerSettings tee{.layer_mm = 0.2,
                            .adaptive = true,
                            .cusp_mm = 0.155,
                            .min_layer_mm = 0.161,
                            .max_layer_mm = 0.449};
    ASSERT_TRUE(validate(tee).has_value());
    expect_adaptive_properties(adaptive_case(test::t_shape(), {0, 0, 1}, tee), tee);
}

TEST(UniformLayers, ALastLayerThinnerThanHMinIsFoldedIntoTheOneBelow) {
    // 15.01 mm in 0.5 mm layers: 30 layers and a 0.01 mm remainder (above the 1% merge).
    const auto plain = uniform_layers(0.0, 15.01, 0.5);
    ASSERT_EQ(plain.size(), 31u);
    EXPECT_NEAR(plain.back().thickness(), 0.01, 1e-9);
    const auto merged = uniform_layers(0.0, 15.01, 0.5, 0.3, 0.7);
    ASSERT_EQ(merged.size(), 30u);
    EXPECT_NEAR(merged.back().thickness(), 0.51, 1e-9);
    EXPECT_DOUBLE_EQ(merged.back().top, 15.01);
    // A remainder that would make the merged layer too thick: the last two share the height.
    const auto even = uniform_layers(0.0, 15.25, 0.5, 0.3, 0.7);
    ASSERT_EQ(even.size(), 31u);
    EXPECT_NEAR(even[29].thickness(), 0.375, 1e-9);
    EXPECT_NEAR(even[30].thickness(), 0.375, 1e-9);
    EXPECT_DOUBLE_EQ(even[30].top, 15.25);
    for (std::size_t i = 0; i + 1 < even.size(); ++i) {
        EXPECT_DOUBLE_EQ(even[i].top, even[i + 1].bottom);
        EXPECT_GE(even[i].thickness(), 0.3 - 1e-9);
        EXPECT_LE(even[i].thickness(), 0.7 + 1e-9);
    }
    // A remainder of at least h_min, or a range thinner than h_min, is left as it is.
    const auto kept = uniform_layers(0.0, 15.3, 0.5, 0.3, 0.7);
    const auto reference = uniform_layers(0.0, 15.3, 0.5);
    ASSERT_EQ(kept.size(), reference.size());
    for (std::size_t i = 0; i < kept.size(); ++i) {
        EXPECT_DOUBLE_EQ(kept[i].bottom, reference[i].bottom);
        EXPECT_DOUBLE_EQ(kept[i].top, reference[i].top);
    }
    EXPECT_EQ(uniform_layers(0.0, 0.2, 0.5, 0.3, 0.7).size(), 1u);
}

}  // namespace
}  // namespace maxslice::slice
