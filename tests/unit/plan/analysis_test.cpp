#include "maxslice/plan/analysis.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "maxslice/geom2d/wire_tree.hpp"

namespace maxslice::plan {
namespace {

using geom2d::Path2;
using geom2d::Paths2;

Path2 rect(double x0, double y0, double x1, double y1) {
    auto um = [](double mm) { return std::llround(mm * 1000.0); };
    return {{um(x0), um(y0)}, {um(x1), um(y0)}, {um(x1), um(y1)}, {um(x0), um(y1)}};
}

const slice::PlaneFrame kLower = slice::PlaneFrame::from_normal({0, 0, 10}, {0, 0, 1});
const slice::PlaneFrame kUpper = kLower.shifted(0.5);

NeighbourAnalysis analyse(const Paths2& lower, const Paths2& upper) {
    auto a = analyse_neighbours(lower, kLower, upper, kUpper, AnalysisSettings{});
    EXPECT_TRUE(a.has_value()) << (a ? "" : a.error().describe());
    return a ? *a : NeighbourAnalysis{};
}

TEST(Neighbours, SameSectionIsCarried) {
    const auto a = analyse({rect(0, 0, 20, 20)}, {rect(0, 0, 20, 20)});
    EXPECT_EQ(a.support, Support::kCarried);
    EXPECT_TRUE(a.pieces.empty());
    // A shift within h tan(phi_self) = 0.18 mm, and smaller sections, are carried too.
    EXPECT_TRUE(analyse({rect(0, 0, 20, 20)}, {rect(0.15, 0, 20.15, 20)}).pieces.empty());
    EXPECT_TRUE(analyse({rect(0, 0, 20, 20)}, {rect(5, 5, 15, 15)}).pieces.empty());
}

TEST(Neighbours, SliversNarrowerThanATrackAreIgnored) {
    // A 45 degree wall moves out by h = 0.5 mm per layer; a 2 mm ledge is still narrower
    // than the 2.5 mm track.
    EXPECT_TRUE(analyse({rect(0, 0, 20, 20)}, {rect(0, 0, 20.5, 20)}).pieces.empty());
    EXPECT_TRUE(analyse({rect(0, 0, 20, 20)}, {rect(0, 0, 22, 20)}).pieces.empty());
}

TEST(Neighbours, AShelfIsOneOverhangPieceWithItsQuantities) {
    // L: 20 x 20; U: L plus a 10 mm shelf along +x, 8 mm wide.
    const Paths2 upper = geom2d::union_of({rect(0, 0, 20, 20), rect(20, 6, 30, 14)});
    const auto a = analyse({rect(0, 0, 20, 20)}, upper);
    EXPECT_EQ(a.support, Support::kOverhang);
    ASSERT_EQ(a.pieces.size(), 1u);
    const OverhangPiece& p = a.pieces.front();
    // dA: the shelf minus the 0.18 mm allowance.
    const double allowance = 0.5 * std::tan(20.0 * std::numbers::pi / 180.0);
    EXPECT_NEAR(p.area_mm2, (10.0 - allowance) * 8.0, 0.05);
    EXPECT_NEAR(p.C.x, 20.0 + allowance + (10.0 - allowance) / 2, 0.01);
    EXPECT_NEAR(p.C.y, 10.0, 0.01);
    EXPECT_NEAR(p.C.z, 10.5, 1e-9);  // on U's plane
    EXPECT_NEAR(p.P.x, 20.0, 0.01);  // on L's edge
    EXPECT_NEAR(p.P.z, 10.0, 1e-9);
    EXPECT_NEAR(p.ang_deg, std::atan2(p.C.x - 20.0, 0.5) * 180.0 / std::numbers::pi, 0.1);
    EXPECT_GT(p.ang_deg, 80.0);
    EXPECT_TRUE(p.touches_lower);
    // The contact line is the shelf's root: x = 20, y in [6, 14].
    EXPECT_NEAR(p.contact_center.x, 20.0, 0.05);
    EXPECT_NEAR(p.contact_center.y, 10.0, 0.05);
}

TEST(Neighbours, ASeparateIslandIsUnrelated) {
    const auto a = analyse({rect(0, 0, 20, 20)}, {rect(40, 0, 50, 10)});
    EXPECT_EQ(a.support, Support::kUnrelated);
    ASSERT_EQ(a.pieces.size(), 1u);
    EXPECT_FALSE(a.pieces.front().touches_lower);
    EXPECT_GT(a.pieces.front().ang_deg, 80.0);
}

// An island of U that meets nothing of L starts in the air however narrow it is: a 2 mm
// wide, 10 mm long rib (narrower than the 2.5 mm track, whose opening would take a ledge that
// wide away) is a floating piece.
TEST(Neighbours, AFloatingIslandNarrowerThanATrackIsAPiece) {
    const Paths2 upper = geom2d::union_of({rect(0, 0, 20, 20), rect(30, 5, 32, 15)});
    const auto a = analyse({rect(0, 0, 20, 20)}, upper);
    ASSERT_EQ(a.pieces.size(), 1u);
    const OverhangPiece& p = a.pieces.front();
    EXPECT_FALSE(p.touches_lower);
    EXPECT_NEAR(p.area_mm2, 20.0, 1e-6);
    EXPECT_NEAR(p.C.x, 31.0, 1e-3);
    // The same rib joined to L's edge by U's own material is a ledge the opening takes.
    const Paths2 joined = geom2d::union_of({rect(0, 0, 20, 20), rect(20, 5, 22, 15)});
    EXPECT_TRUE(analyse({rect(0, 0, 20, 20)}, joined).pieces.empty());
}

// A floating piece hangs from L where a track fits, not from a sliver of L narrower than one
// (which gets no bead and carries nothing): P lies on the 20 mm square's edge, not on the
// 1 mm sliver standing between the square and the piece.
TEST(Neighbours, AFloatingPieceHangsFromLWhereATrackFits) {
    const Paths2 lower = geom2d::union_of({rect(0, 0, 20, 20), rect(30, 0, 31, 20)});
    const Paths2 upper = geom2d::union_of({rect(0, 0, 20, 20), rect(35, 5, 45, 15)});
    const auto a = analyse(lower, upper);
    ASSERT_EQ(a.pieces.size(), 1u);
    const OverhangPiece& p = a.pieces.front();
    EXPECT_FALSE(p.touches_lower);
    EXPECT_NEAR(p.P.x, 20.0, 0.05);
    EXPECT_NEAR(p.P.y, 10.0, 0.05);
    EXPECT_NEAR(p.contact_center.x, 20.0, 0.05);
    // Without the square, the sliver is all of L: the piece hangs from it.
    const auto b = analyse({rect(30, 0, 31, 20)}, {rect(35, 5, 45, 15)});
    ASSERT_EQ(b.pieces.size(), 1u);
    EXPECT_NEAR(b.pieces.front().P.x, 31.0, 0.05);
}

TEST(Neighbours, ARingAllRoundIsCutIntoFourWays) {
    // A mushroom: a 10 x 10 stem under a 40 x 40 cap: the overhang's centroid lies inside
    // the stem, so it is cut into quadrants, each pointing out its own way.
    const auto a = analyse({rect(15, 15, 25, 25)}, {rect(0, 0, 40, 40)});
    EXPECT_EQ(a.support, Support::kOverhang);
    ASSERT_EQ(a.pieces.size(), 4u);
    for (const OverhangPiece& p : a.pieces) {
        EXPECT_GT(p.ang_deg, 80.0);
        // V points out from the stem.
        EXPECT_GT((p.C.x - 20.0) * p.V.x + (p.C.y - 20.0) * p.V.y, 0.0);
    }
}

// Sections with empty ones between them (a gap of 100 mm along the normal): nothing bridges
// the gap, so an island 20 mm beside L starts in the air. Grown by 100 mm tan(phi_self) = 36 mm
// L would take it in; the allowance's height is capped at what the walk's look-back spans.
TEST(Neighbours, AnIslandAcrossAGapIsFloating) {
    const slice::PlaneFrame far_above = kLower.shifted(100.0);
    const Paths2 lower{rect(0, 0, 20, 20)};
    const Paths2 upper{rect(40, 5, 50, 15)};
    AnalysisSettings s;
    auto uncapped = analyse_neighbours(lower, kLower, upper, far_above, s);
    ASSERT_TRUE(uncapped.has_value());
    EXPECT_TRUE(uncapped->pieces.empty());
    s.max_allowance_height_mm = 4.2;
    auto capped = analyse_neighbours(lower, kLower, upper, far_above, s);
    ASSERT_TRUE(capped.has_value());
    ASSERT_EQ(capped->pieces.size(), 1u);
    EXPECT_FALSE(capped->pieces.front().touches_lower);
    EXPECT_NEAR(capped->pieces.front().area_mm2, 100.0, 1e-6);
    // Layers within the cap keep their allowance: a 0.15 mm shift is carried.
    auto near = analyse_neighbours(lower, kLower, {rect(0.15, 0, 20.15, 20)}, kUpper, s);
    ASSERT_TRUE(near.has_value());
    EXPECT_TRUE(near->pieces.empty());
}

// A piece that touches nothing of L may still rest on the part's material beside L's cell
// (the whole section at L's plane): then no more of it than the area tolerance hangs.
TEST(Neighbours, APieceRestsOnTheWholeSectionWhenLittleOfItHangs) {
    const AnalysisSettings s;                 // 20 deg, 1 mm2 tolerance
    const Paths2 piece{rect(30, 0, 34, 10)};  // 40 mm2
    // The whole section holds L (0..20) and the wall the cell cut off (29..40): all carried.
    const Paths2 whole = geom2d::union_of({rect(0, 0, 20, 20), rect(29, 0, 40, 20)});
    EXPECT_TRUE(rests_on_section(piece, whole, 0.5, s));
    // Under L alone it hangs whole.
    EXPECT_FALSE(rests_on_section(piece, {rect(0, 0, 20, 20)}, 0.5, s));
    // Half of it over the wall: 20 mm2 hang, more than the tolerance.
    EXPECT_FALSE(rests_on_section(piece, {rect(32, 0, 40, 20)}, 0.5, s));
    // Within the allowance: the wall ends 0.1 mm short of the piece's edge (0.18 mm carried).
    EXPECT_TRUE(rests_on_section(piece, {rect(30.1, 0, 40, 20)}, 0.5, s));
    EXPECT_FALSE(rests_on_section(piece, {}, 0.5, s));
}

TEST(Neighbours, BadSettingsAreRefused) {
    AnalysisSettings s;
    s.track_width_mm = 0;
    EXPECT_FALSE(analyse_neighbours({}, kLower, {}, kUpper, s).has_value());
    s = {};
    s.self_supporting_deg = 95;
    EXPECT_FALSE(analyse_neighbours({}, kLower, {}, kUpper, s).has_value());
    s = {};
    s.max_allowance_height_mm = -1;
    EXPECT_FALSE(analyse_neighbours({}, kLower, {}, kUpper, s).has_value());
    EXPECT_NEAR(angle_deg({1, 0, 0}, {0, 0, 1}), 90.0, 1e-12);
    EXPECT_EQ(angle_deg({0, 0, 0}, {0, 0, 1}), 0.0);
}

}  // namespace
}  // namespace maxslice::plan
