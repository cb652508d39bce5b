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

TEST(SidewaysSupport, TheWallsOuterTrackCarriesTheLayerOnItsFace) {
    const SideLayer l;
    // The wall's contour track, half a track inside its face: its bead reaches the face.
    const geom2d::Paths2 out =
        sideways_support(l.bottom, 0.5, l.plane, horizontal_track(8.75, 5.0), 0.25);
    ASSERT_EQ(out.size(), 1u);
    ASSERT_EQ(out[0].size(), 2u);
    // Projected along +X onto the layer's plane: the whole track, 20 mm long.
    const double dx = static_cast<double>(out[0][1].x - out[0][0].x);
    const double dy = static_cast<double>(out[0][1].y - out[0][0].y);
    EXPECT_NEAR(std::hypot(dx, dy), 20.0 * core::kMicronsPerMm, 1.0);
}

TEST(SidewaysSupport, TracksDeepInsideTheWallOrBeyondTheLayerCarryNothing) {
    const SideLayer l;
    // A fill track 3 mm inside the face: its bead ends 1.75 mm short of it.
    EXPECT_TRUE(sideways_support(l.bottom, 0.5, l.plane, horizontal_track(7.0, 5.0), 0.25).empty());
    // A track in front of the face beyond the layer's top (x = 12): beside the layer, not under.
    EXPECT_TRUE(
        sideways_support(l.bottom, 0.5, l.plane, horizontal_track(12.0, 5.0), 0.25).empty());
    // Just inside the band: a bead whose side comes within the band below the face.
    EXPECT_FALSE(
        sideways_support(l.bottom, 0.5, l.plane, horizontal_track(8.6, 5.0), 0.25).empty());
}

TEST(SidewaysSupport, ATrackCrossingTheBandIsCutToIt) {
    const SideLayer l;
    // A track running across the wall along X, from deep inside to beyond the layer: only the
    // part whose bead reaches from 0.25 mm below the face to the layer's top is kept, that is
    // centres from x = 10 - 0.25 - 1.25 to 10 + 0.5 + 1.25, seen along +X as one point.
    SidewaysParent p = horizontal_track(0.0, 5.0);
    p.tips = {{{0.0, 5.0, 5.0}, {20.0, 5.0, 5.0}}};
    const geom2d::Paths2 out = sideways_support(l.bottom, 0.5, l.plane, p, 0.25);
    ASSERT_EQ(out.size(), 1u);
    ASSERT_EQ(out[0].size(), 2u);
    EXPECT_EQ(out[0][0], out[0][1]) << "projected along the layer's direction";
    // Tilted tracks are cut by the band: a track rising 1 mm per mm along X across the face.
    SidewaysParent rising = horizontal_track(0.0, 5.0);
    rising.tips = {{{5.0, 5.0, 0.0}, {15.0, 5.0, 10.0}}};
    const geom2d::Paths2 cut = sideways_support(l.bottom, 0.5, l.plane, rising, 0.25);
    ASSERT_EQ(cut.size(), 1u);
    const double length_um = std::hypot(static_cast<double>(cut[0][1].x - cut[0][0].x),
                                        static_cast<double>(cut[0][1].y - cut[0][0].y));
    // Centres from x = 8.5 to 11.75: 3.25 mm along Z on the layer's plane.
    EXPECT_NEAR(length_um, 3.25 * core::kMicronsPerMm, 2.0);
}

}  // namespace
}  // namespace maxslice::pipeline::detail
