// Which beads of a parent built along another direction carry a layer: a wall of horizontal
// layers (built along +Z) with a region built along +X standing on its face x = 10.

#include "sideways_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "maxslice/core/units.hpp"

namespace maxslice::pipeline::detail {
namespace {

// A track along Y at x, its tips on the top z of a horizontal layer 0.5 mm thick.
SidewaysParent horizontal_track(double x, double z) {
    SidewaysParent p;
    p.tips = {{{x, 0.0, z}, {x, 20.0, z}}};
    p.direction = {0.0, 0.0, 1.0};
    p.thickness_mm = 0.5;
    p.half_track_mm = 1.25;
    return p;
}

// The layer built along +X whose bottom plane is x = 10, 0.5 mm thick.
struct SideLayer {
    slice::PlaneFrame bottom = slice::PlaneFrame::from_normal({10.0, 0.0, 0.0}, {1.0, 0.0, 0.0});
    slice::PlaneFrame plane = bottom.shifted(0.25);
};

// Material counts from 0.25 mm to 0.05 mm below the layer's bottom plane.
constexpr double kDepth = 0.25;
constexpr double kGap = 0.05;

// The cut seen along +X: its extent in mm along the plane's two axes, and its area in mm2.
struct Seen {
    double extent_u = 0.0, extent_v = 0.0, area = 0.0;
};
Seen seen(const geom2d::Paths2& cuts) {
    EXPECT_EQ(cuts.size(), 1u);
    Seen s;
    if (cuts.empty()) return s;
    std::int64_t u0 = cuts[0][0].x, u1 = u0, v0 = cuts[0][0].y, v1 = v0;
    for (const geom2d::Point2& q : cuts[0]) {
        u0 = std::min(u0, q.x);
        u1 = std::max(u1, q.x);
        v0 = std::min(v0, q.y);
        v1 = std::max(v1, q.y);
    }
    s.extent_u = static_cast<double>(u1 - u0) / core::kMicronsPerMm;
    s.extent_v = static_cast<double>(v1 - v0) / core::kMicronsPerMm;
    s.area = std::abs(geom2d::signed_area_mm2(cuts));
    return s;
}

// The plane's axes are Y and Z in some order and sense: the larger and smaller extents.
void expect_extents(const Seen& s, double large, double small) {
    EXPECT_NEAR(std::max(s.extent_u, s.extent_v), large, 1e-3);
    EXPECT_NEAR(std::min(s.extent_u, s.extent_v), small, 1e-3);
    EXPECT_NEAR(s.area, large * small, 1e-3 * large);
}

TEST(SidewaysSupport, TheWallsOuterTrackCarriesTheLayerOnItsFace) {
    const SideLayer l;
    // The wall's contour track, half a track inside its face: its bead (x 7.5 to 10) fills
    // the slab; seen along +X, the whole track, 20 mm long and its bead's 0.5 mm deep.
    const Seen s =
        seen(sideways_support(l.bottom, l.plane, horizontal_track(8.75, 5.0), kDepth, kGap));
    expect_extents(s, 20.0, 0.5);
}

TEST(SidewaysSupport, TracksDeepInsideTheWallOrBeyondTheLayerCarryNothing) {
    const SideLayer l;
    // A fill track 3 mm inside the face: its bead ends 1.75 mm short of it.
    EXPECT_TRUE(
        sideways_support(l.bottom, l.plane, horizontal_track(7.0, 5.0), kDepth, kGap).empty());
    // A track in front of the face beyond the layer (x = 12): beside the layer, not under.
    EXPECT_TRUE(
        sideways_support(l.bottom, l.plane, horizontal_track(12.0, 5.0), kDepth, kGap).empty());
    // A bead whose side ends in the gap just below the face does not count ...
    EXPECT_TRUE(
        sideways_support(l.bottom, l.plane, horizontal_track(11.22, 5.0), kDepth, kGap).empty());
    // ... one whose side ends in the slab does.
    EXPECT_FALSE(
        sideways_support(l.bottom, l.plane, horizontal_track(8.6, 5.0), kDepth, kGap).empty());
}

TEST(SidewaysSupport, ATrackCrossingTheSlabIsCutToIt) {
    const SideLayer l;
    // A track running across the wall along X: where its bead crosses the slab, seen along +X,
    // its width (2.5 mm) by its depth (0.5 mm).
    SidewaysParent p = horizontal_track(0.0, 5.0);
    p.tips = {{{0.0, 5.0, 5.0}, {20.0, 5.0, 5.0}}};
    expect_extents(seen(sideways_support(l.bottom, l.plane, p, kDepth, kGap)), 2.5, 0.5);
    // A track rising 1 mm per mm along X: its tips at z = x - 5 and the bead 0.5 mm below
    // them; over the slab (x 9.75 to 9.95) it spans z from 9.75 - 5.5 to 9.95 - 5.
    SidewaysParent rising = horizontal_track(0.0, 5.0);
    rising.tips = {{{5.0, 5.0, 0.0}, {15.0, 5.0, 10.0}}};
    expect_extents(seen(sideways_support(l.bottom, l.plane, rising, kDepth, kGap)), 2.5, 0.7);
}

TEST(SidewaysSupport, ABeadLeaningIntoTheFaceCountsOnlyWhereItsBodyIsInTheSlab) {
    const SideLayer l;
    // A layer built along a direction 45 degrees between +Z and +X: its track along Y with tips
    // at x = 9.5, z = 5. The bead's box runs from the tips 0.5 mm down along (-1, 0, -1)/sqrt 2
    // and 1.25 mm to either side along (-1, 0, 1)/sqrt 2; what of it lies within the slab is a
    // narrow strip well off the centre line, not the centre line swept by half a track.
    SidewaysParent p = horizontal_track(9.5, 5.0);
    p.direction = core::normalized(core::Vec3d{1.0, 0.0, 1.0});
    const geom2d::Paths2 cuts = sideways_support(l.bottom, l.plane, p, kDepth, kGap);
    const Seen s = seen(cuts);
    EXPECT_NEAR(std::max(s.extent_u, s.extent_v), 20.0, 1e-3);
    // The box's cross-section is a 2.5 x 0.5 rectangle turned 45 degrees; the slab (x from
    // 9.75 to 9.95) cuts from it a piece spanning z from 5 - (0.45 sqrt 2 + 1) / sqrt 2 to
    // 5 - 0.25: 0.907 mm, where the centre line swept by half a track would span 2.5 mm about
    // z = 5, reaching 1.25 mm above the material.
    EXPECT_NEAR(std::min(s.extent_u, s.extent_v), 0.45 + 1.0 / std::sqrt(2.0) - 0.25, 1e-3);
}

}  // namespace
}  // namespace maxslice::pipeline::detail
