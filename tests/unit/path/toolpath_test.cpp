#include "maxslice/path/toolpath.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <thread>

#include "regions.hpp"

namespace maxslice::path::test {
namespace {

PathSettings settings(double width = 2.5, double overlap = 0.3, int passes = 1) {
    PathSettings s;
    s.track_width_mm = width;
    s.overlap = overlap;
    s.contour_passes = passes;
    return s;
}

LayerToolpath plan(const geom2d::WireTree& tree, const PathSettings& s, Point2 start = {}) {
    auto r = plan_layer(tree, s, start);
    EXPECT_TRUE(r.has_value()) << (r ? "" : r.error().describe());
    return r ? *r : LayerToolpath{};
}

// Direction of a segment in degrees, in [0, 180).
double direction_deg(Point2 a, Point2 b) {
    double d = std::atan2(static_cast<double>(b.y - a.y), static_cast<double>(b.x - a.x)) * 180.0 /
               std::numbers::pi;
    if (d < 0) d += 180.0;
    if (d >= 180.0) d -= 180.0;
    return d;
}

double angle_between_deg(double a, double b) {
    const double d = std::fmod(std::abs(a - b), 180.0);
    return std::min(d, 180.0 - d);
}

// Fill segments longer than min_mm (the raster lines, not the links).
std::vector<std::pair<Point2, Point2>> long_fill_segments(const LayerToolpath& tp, double min_mm) {
    std::vector<std::pair<Point2, Point2>> out;
    for (const Stroke& s : tp.strokes) {
        if (s.kind != StrokeKind::kFill) continue;
        for (std::size_t i = 1; i < s.points.size(); ++i) {
            if (length_mm({s.points[i - 1], s.points[i]}) > min_mm) {
                out.emplace_back(s.points[i - 1], s.points[i]);
            }
        }
    }
    return out;
}

// The properties every toolpath must have, whatever the shape.
void expect_valid(const geom2d::WireTree& tree, const PathSettings& s, const LayerToolpath& tp,
                  Point2 start, double min_coverage) {
    const Paths2 loops = material(tree);
    const double area = area_mm2(loops);
    const std::int64_t half = um(s.track_width_mm / 2);
    ASSERT_FALSE(tp.strokes.empty());

    // Strokes are polylines; contours are closed.
    for (const Stroke& st : tp.strokes) {
        ASSERT_GE(st.points.size(), 2u);
        if (st.kind == StrokeKind::kContour) {
            EXPECT_EQ(st.points.front(), st.points.back());
        }
    }

    // Every point of every stroke lies inside the region, at least half a track from its
    // boundary (10 um for rounding), so no track sticks out.
    long outside = 0;
    for (const Stroke& st : tp.strokes) {
        for (const Point2& p : st.points) {
            if (geom2d::locate_point(loops, p) != geom2d::Containment::kInside ||
                distance_to_boundary_mm(loops, p) < s.track_width_mm / 2 - 0.010) {
                ++outside;
            }
        }
    }
    EXPECT_EQ(outside, 0) << "stroke points closer than half a track to the boundary";

    // No deposit outside the region (tracks swept as discs of the track width).
    const Paths2 deposit = geom2d::sweep_polylines(stroke_paths(tp), half);
    const double outside_mm2 =
        area_mm2(geom2d::difference_of(deposit, geom2d::offset_of(loops, 10)));
    EXPECT_LT(outside_mm2, 0.01) << "deposit outside the region";

    // No laser-on segment enters a hole.
    for (const Paths2& hole : holes_of(tree)) {
        double inside_mm = 0.0;
        for (const Path2& piece : geom2d::clip_polylines(stroke_paths(tp), hole)) {
            inside_mm += length_mm(piece);
        }
        EXPECT_EQ(inside_mm, 0.0) << "a deposit segment crosses a hole";
    }

    // Lengths add up.
    double deposit_mm = 0.0;
    double travel_mm = 0.0;
    Point2 at = start;
    for (const Stroke& st : tp.strokes) {
        deposit_mm += length_mm(st.points);
        travel_mm += length_mm({at, st.points.front()});
        at = st.points.back();
    }
    EXPECT_NEAR(tp.deposit_length_mm, deposit_mm, 1e-6 * deposit_mm);
    EXPECT_NEAR(tp.travel_length_mm, travel_mm, 1e-6 * travel_mm + 1e-9);

    // The reported uncovered area agrees with an independent grid sample.
    // About 250 x 250 samples, and at least 10 across a track.
    const double extent = std::sqrt(area);
    const GridCoverage grid(tree, tp, s.track_width_mm,
                            std::max(s.track_width_mm / 10.0, extent / 250.0));
    ASSERT_GT(grid.inside_samples(), 100);
    const double reported = 1.0 - tp.uncovered_mm2 / area;
    // Sampling error shrinks with the number of samples.
    EXPECT_NEAR(reported, grid.fraction(),
                0.01 + 1.0 / std::sqrt(static_cast<double>(grid.inside_samples())));
    EXPECT_GE(tp.uncovered_mm2, 0.0);
    EXPECT_GE(reported, min_coverage);
    EXPECT_GE(grid.fraction(), min_coverage);
    ::testing::Test::RecordProperty("coverage", std::to_string(reported));
}

struct Shape {
    std::string name;
    std::function<geom2d::WireTree()> build;
};

std::vector<Shape> shapes() {
    return {
        {"square_5_tracks", [] { return square_region(12.5); }},
        {"square_100", [] { return square_region(100.0); }},
        {"rectangle_60x20", [] { return region({rect(0, 0, 60, 20)}); }},
        {"rotated_rectangle_30", [] { return region({rotated_rect(40, 30, 60, 12, 30)}); }},
        {"rotated_rectangle_10to1", [] { return region({rotated_rect(0, 0, 100, 10, 30)}); }},
        {"plate_with_holes", [] { return plate_with_holes(); }},
        {"annulus", [] { return annulus(); }},
        {"l_shape", [] { return l_shape(); }},
        {"two_islands", [] { return two_islands(); }},
        {"island_in_hole", [] { return island_in_hole(); }},
        // A U whose slot (5 mm) is narrower than two fill pitches plus the contours: links
        // across the slot would deposit outside.
        {"u_shape",
         [] {
             return region({{pt(0, 0), pt(40, 0), pt(40, 40), pt(22.5, 40), pt(22.5, 8),
                             pt(17.5, 8), pt(17.5, 40), pt(0, 40)}});
         }},
        {"disc", [] { return region({ngon(0, 0, 25, 128)}); }},
    };
}

struct Case {
    double width;
    double overlap;
    int passes;
    double min_coverage;
};

class AllShapes : public ::testing::TestWithParam<Case> {};

TEST_P(AllShapes, TracksStayInsideCoverAndAvoidHoles) {
    const Case c = GetParam();
    const PathSettings s = settings(c.width, c.overlap, c.passes);
    for (const Shape& shape : shapes()) {
        SCOPED_TRACE(shape.name);
        const geom2d::WireTree tree = shape.build();
        const LayerToolpath tp = plan(tree, s, pt(-10, -10));
        expect_valid(tree, s, tp, pt(-10, -10), c.min_coverage);
    }
}

INSTANTIATE_TEST_SUITE_P(Settings, AllShapes,
                         // Without overlap round track ends leave more open (wedges where
                         // the boundary runs nearly along the lines).
                         ::testing::Values(Case{2.5, 0.3, 1, 0.98}, Case{2.5, 0.3, 2, 0.98},
                                           Case{1.0, 0.3, 2, 0.98}, Case{2.5, 0.5, 3, 0.98},
                                           Case{2.5, 0.0, 1, 0.93}),
                         [](const auto& info) {
                             return "w" + std::to_string(static_cast<int>(info.param.width * 10)) +
                                    "_ov" +
                                    std::to_string(static_cast<int>(info.param.overlap * 100)) +
                                    "_p" + std::to_string(info.param.passes);
                         });

TEST(Toolpath, FillOnlyStaysInsideAndAvoidsHoles) {
    // Without contours the line ends leave a sawtooth along slanted edges: coverage is not
    // asserted, only containment.
    const PathSettings s = settings(2.5, 0.3, 0);
    for (const Shape& shape : shapes()) {
        SCOPED_TRACE(shape.name);
        const geom2d::WireTree tree = shape.build();
        const LayerToolpath tp = plan(tree, s);
        expect_valid(tree, s, tp, {}, 0.0);
        for (const Stroke& st : tp.strokes) EXPECT_EQ(st.kind, StrokeKind::kFill);
    }
}

TEST(Toolpath, LinksNeverCutThroughHoles) {
    // Many small holes at pseudo-random places (fixed seed): line ends meet holes in every
    // way, and links that would cut through them must be refused (travel instead).
    std::uint64_t state = 12345;
    const auto next = [&](double lo, double hi) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return lo + (hi - lo) * static_cast<double>(state >> 11) / 9007199254740992.0;
    };
    Paths2 loops{{pt(0, 0), pt(80, 0), pt(80, 60), pt(0, 60)}};
    for (int i = 0; i < 40; ++i) {
        const double x = next(8, 72);
        const double y = next(8, 52);
        const double r = next(0.8, 2.5);
        bool clear = true;  // keep holes apart so the loops stay simple
        for (std::size_t j = 1; j < loops.size(); ++j) {
            const Point2 c = loops[j].front();
            if (std::hypot(static_cast<double>(c.x) / 1000 - x,
                           static_cast<double>(c.y) / 1000 - y) < 7.0) {
                clear = false;
            }
        }
        if (clear) loops.push_back(ngon(x, y, r, 24));
    }
    ASSERT_GE(loops.size(), 15u);
    const geom2d::WireTree plate = region(loops);
    for (const int passes : {0, 1}) {
        for (const double angle : {0.0, 90.0, 33.0}) {
            SCOPED_TRACE(std::to_string(passes) + " passes, raster at " + std::to_string(angle));
            PathSettings s = settings(2.5, 0.3, passes);
            s.raster_angle_deg = angle;
            expect_valid(plate, s, plan(plate, s), {}, 0.0);
        }
    }
}

TEST(Toolpath, RandomShapesKeepTheInvariants) {
    // Spiky stars with random holes and random settings (fixed seed): spikes thinner than a
    // track, holes cutting the outline, sharp corners. Coverage is not asserted here (spikes
    // cannot be covered), only that tracks stay inside, clear of holes, and add up.
    std::uint64_t state = 2024;
    const auto next = [&](double lo, double hi) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return lo + (hi - lo) * static_cast<double>(state >> 11) / 9007199254740992.0;
    };
    for (int i = 0; i < 60; ++i) {
        const int spikes = 3 + static_cast<int>(next(0, 40));
        const double r = next(5, 50);
        Path2 star;
        for (int k = 0; k < spikes; ++k) {
            const double a = 2 * std::numbers::pi * k / spikes;
            const double rk = r * next(0.3, 1.0);
            star.push_back(pt(rk * std::cos(a), rk * std::sin(a)));
        }
        Paths2 loops{star};
        const int holes = static_cast<int>(next(0, 5));
        // One draw per statement: the order of a call's arguments is unspecified (GCC takes
        // them last to first, clang first to last), and the shapes must not depend on it.
        for (int k = 0; k < holes; ++k) {
            const int sides = 5 + static_cast<int>(next(0, 30));
            const double radius = next(0.5, 0.2 * r);
            const double cy = next(-0.5, 0.5) * r;
            const double cx = next(-0.5, 0.5) * r;
            loops.push_back(ngon(cx, cy, radius, sides));
        }
        const geom2d::WireTree tree = region(loops);
        const int passes = static_cast<int>(next(0, 4));
        const double overlap = next(0, 0.6);
        PathSettings s = settings(next(0.5, 3.5), overlap, passes);
        if (next(0, 1) < 0.3) s.raster_angle_deg = next(0, 360);
        SCOPED_TRACE("case " + std::to_string(i));
        const Point2 start = pt(next(-50, 50), -80);
        const LayerToolpath tp = plan(tree, s, start);
        if (tp.strokes.empty()) continue;
        expect_valid(tree, s, tp, start, 0.0);
    }
}

TEST(Toolpath, ContourPassesFollowEveryWire) {
    const geom2d::WireTree plate = plate_with_holes();
    for (const int passes : {1, 2, 3}) {
        const LayerToolpath tp = plan(plate, settings(2.5, 0.3, passes));
        long contours = 0;
        for (const Stroke& s : tp.strokes) contours += s.kind == StrokeKind::kContour ? 1 : 0;
        EXPECT_EQ(contours, 6 * passes) << "outer + 5 holes per pass";
    }
    // Contour k runs half a track plus k pitches inside: its length on a square is known.
    const LayerToolpath sq = plan(square_region(40), settings(2.5, 0.3, 2));
    std::vector<double> lengths;
    for (const Stroke& s : sq.strokes) {
        if (s.kind == StrokeKind::kContour) lengths.push_back(length_mm(s.points));
    }
    std::sort(lengths.begin(), lengths.end());
    ASSERT_EQ(lengths.size(), 2u);
    EXPECT_NEAR(lengths[1], 4 * (40 - 2.5), 0.01);
    EXPECT_NEAR(lengths[0], 4 * (40 - 2.5 - 2 * 1.75), 0.01);
}

TEST(Toolpath, ContoursComeBeforeTheFillOfTheirIsland) {
    const geom2d::WireTree tree = two_islands();
    const Paths2 outers{tree.nodes[static_cast<std::size_t>(tree.roots[0])].wire,
                        tree.nodes[static_cast<std::size_t>(tree.roots[1])].wire};
    for (const Point2 start : {pt(-20, 0), pt(100, 0)}) {
        const LayerToolpath tp = plan(tree, settings(), start);
        std::vector<int> island_of;
        for (const Stroke& s : tp.strokes) {
            int island = -1;
            for (int i = 0; i < 2; ++i) {
                if (geom2d::locate_point({outers[static_cast<std::size_t>(i)]}, s.points.front()) ==
                    geom2d::Containment::kInside) {
                    island = i;
                }
            }
            ASSERT_GE(island, 0);
            island_of.push_back(island);
        }
        // Islands are not interleaved, and the nearer one comes first.
        const int first = island_of.front();
        const auto switch_at = std::find(island_of.begin(), island_of.end(), 1 - first);
        ASSERT_NE(switch_at, island_of.end());
        EXPECT_TRUE(std::all_of(switch_at, island_of.end(), [&](int i) { return i != first; }));
        const double d0 = std::abs(static_cast<double>(start.x - outers[0][0].x));
        const double d1 = std::abs(static_cast<double>(start.x - outers[1][0].x));
        EXPECT_EQ(first, d0 < d1 ? 0 : 1);
        // Inside an island, no contour after a fill stroke.
        for (std::size_t i = 1; i < tp.strokes.size(); ++i) {
            if (island_of[i] == island_of[i - 1] && tp.strokes[i].kind == StrokeKind::kContour) {
                EXPECT_EQ(tp.strokes[i - 1].kind, StrokeKind::kContour);
            }
        }
    }
}

TEST(Toolpath, ZigzagFollowsTheLongSideOfARotatedRectangle) {
    for (const double angle : {30.0, 0.0, 90.0, 151.0}) {
        SCOPED_TRACE(angle);
        // 20 mm wide: wider than a thin island, whose contour passes fill it (ThinIslands...).
        const geom2d::WireTree tree = region({rotated_rect(10, 20, 100, 20, angle)});
        const LayerToolpath tp = plan(tree, settings());
        EXPECT_LT(angle_between_deg(tp.raster_angle_deg, angle), 1.0);
        const auto segs = long_fill_segments(tp, 20.0);
        ASSERT_GE(segs.size(), 3u);
        for (const auto& [a, b] : segs) {
            EXPECT_LT(angle_between_deg(direction_deg(a, b), angle), 1.0);
        }
    }
}

TEST(Toolpath, RasterFollowsTheLongestBoxOfAnLAndAnArbitraryHull) {
    // A slanted parallelogram: its long side, not the bounding box of the axes, sets the fill.
    const geom2d::WireTree para = region({{pt(0, 0), pt(20, 0), pt(100, 40), pt(80, 40)}});
    const LayerToolpath tp = plan(para, settings());
    const double long_side = std::atan2(40.0, 80.0) * 180.0 / std::numbers::pi;
    EXPECT_LT(angle_between_deg(tp.raster_angle_deg, long_side), 1.0);
    // A square has no long side: ties go to the smaller angle (along u).
    EXPECT_EQ(plan(square_region(30), settings()).raster_angle_deg, 0.0);
}

TEST(Toolpath, RasterAngleSettingOverridesTheOrientation) {
    PathSettings s = settings();
    s.raster_angle_deg = 45.0;
    const LayerToolpath tp = plan(region({rect(0, 0, 100, 20)}), s);
    EXPECT_DOUBLE_EQ(tp.raster_angle_deg, 45.0);
    const auto segs = long_fill_segments(tp, 5.0);
    ASSERT_FALSE(segs.empty());
    for (const auto& [a, b] : segs) EXPECT_LT(angle_between_deg(direction_deg(a, b), 45.0), 1.0);
    s.raster_angle_deg = -135.0;  // the same direction
    EXPECT_DOUBLE_EQ(plan(region({rect(0, 0, 100, 20)}), s).raster_angle_deg, 45.0);
}

TEST(Toolpath, NeighbouringLinesAreLinkedIntoOneZigzag) {
    // A convex shape fills in one zigzag; a hole splits the fill into a few. (Short fill
    // strokes beside them are tracks along slivers the zigzag leaves at the contour.)
    const auto zigzags = [](const LayerToolpath& tp) {
        long n = 0;
        for (const Stroke& s : tp.strokes) {
            n += s.kind == StrokeKind::kFill && length_mm(s.points) > 20.0 ? 1 : 0;
        }
        return n;
    };
    for (const auto& tree : {region({rect(0, 0, 60, 20)}), region({ngon(0, 0, 25, 128)}),
                             region({rotated_rect(0, 0, 60, 30, 30)})}) {
        EXPECT_EQ(zigzags(plan(tree, settings())), 1);
    }
    const long ring = zigzags(plan(annulus(), settings()));
    EXPECT_GE(ring, 2);
    EXPECT_LE(ring, 4);
}

TEST(Toolpath, OrderingShortensIdleTravel) {
    const geom2d::WireTree plate = plate_with_holes();
    PathSettings s = settings(2.5, 0.3, 2);
    const LayerToolpath best = plan(plate, s, pt(-5, -5));
    s.order = StrokeOrder::kGenerated;
    const LayerToolpath plain = plan(plate, s, pt(-5, -5));
    RecordProperty("travel_short_mm", std::to_string(best.travel_length_mm));
    RecordProperty("travel_generated_mm", std::to_string(plain.travel_length_mm));
    EXPECT_LT(best.travel_length_mm, plain.travel_length_mm);
    // The same tracks, only in another order.
    EXPECT_EQ(best.strokes.size(), plain.strokes.size());
    EXPECT_NEAR(best.deposit_length_mm, plain.deposit_length_mm, 1e-3 * plain.deposit_length_mm);
    EXPECT_NEAR(best.uncovered_mm2, plain.uncovered_mm2, 0.05);
    std::printf("plate with holes: idle travel %.1f mm ordered, %.1f mm as generated\n",
                best.travel_length_mm, plain.travel_length_mm);
}

TEST(Toolpath, SameInputSameOutput) {
    const geom2d::WireTree plate = plate_with_holes();
    PathSettings s = settings(1.0, 0.3, 2);
    const LayerToolpath a = plan(plate, s, pt(3, 7));
    LayerToolpath b;
    std::thread([&] { b = plan(plate, s, pt(3, 7)); }).join();
    EXPECT_TRUE(a == b);
    s.raster_angle_deg = 17.0;
    EXPECT_TRUE(plan(island_in_hole(), s) == plan(island_in_hole(), s));
}

TEST(Toolpath, StackOfLayersChainsStartsAndMatchesLayerByLayer) {
    // plan_layers plans in parallel but must equal plan_layer called layer by layer, each
    // starting where the previous one ended, whatever the thread count.
    std::vector<geom2d::WireTree> trees;
    for (const Shape& shape : shapes()) trees.push_back(shape.build());
    std::vector<const geom2d::WireTree*> regions;
    for (const auto& t : trees) regions.push_back(&t);
    const PathSettings s = settings(1.5, 0.25, 2);
    auto all = plan_layers(regions, s, pt(-5, 3));
    ASSERT_TRUE(all.has_value());
    ASSERT_EQ(all->size(), trees.size());
    Point2 start = pt(-5, 3);
    for (std::size_t i = 0; i < trees.size(); ++i) {
        SCOPED_TRACE(i);
        const LayerToolpath one = plan(trees[i], s, start);
        EXPECT_TRUE((*all)[i] == one);
        if (!one.strokes.empty()) start = one.strokes.back().points.back();
    }
    PathSettings bad = s;
    bad.overlap = 1.0;
    EXPECT_FALSE(plan_layers(regions, bad, {}).has_value());
    core::Progress cancelled;
    cancelled.cancel();
    auto stopped = plan_layers(regions, s, {}, &cancelled);
    ASSERT_FALSE(stopped.has_value());
    EXPECT_EQ(stopped.error().code, core::ErrorCode::kCancelled);
}

TEST(Toolpath, NarrowPiecesThatVanishAreReportedUncovered) {
    // Two squares joined by a 1 mm strip: no 2.5 mm track fits in the strip.
    const geom2d::WireTree tree =
        region({{pt(0, 0), pt(20, 0), pt(20, 9.5), pt(40, 9.5), pt(40, 0), pt(60, 0), pt(60, 20),
                 pt(40, 20), pt(40, 10.5), pt(20, 10.5), pt(20, 20), pt(0, 20)}});
    const LayerToolpath tp = plan(tree, settings());
    EXPECT_GE(tp.uncovered_mm2, 0.9 * 20.0);
    EXPECT_LE(tp.uncovered_mm2, 20.0 + 0.04 * 800.0);
    expect_valid(tree, settings(), tp, {}, 0.0);
}

TEST(Toolpath, SliversBetweenTracksGetATrackAlongTheirMiddle) {
    // An annulus 5.9 mm wide: the contour tracks along both walls (2.5 mm each) leave a ring
    // 0.9 mm wide in the middle, too narrow for a fill line: one closed track along it.
    const geom2d::WireTree ring = annulus(30.0, 24.1);
    const LayerToolpath tp = plan(ring, settings());
    expect_valid(ring, settings(), tp, {}, 0.995);
    long closed_fill = 0;
    for (const Stroke& st : tp.strokes) {
        if (st.kind != StrokeKind::kFill || st.points.front() != st.points.back()) continue;
        ++closed_fill;
        for (const Point2& p : st.points) {
            const double r = std::hypot(static_cast<double>(p.x), static_cast<double>(p.y));
            EXPECT_NEAR(r, 27050.0, 60.0);  // the middle of the ring, 27.05 mm from the centre
        }
    }
    EXPECT_EQ(closed_fill, 1);
}

// A thin island (here rings 6 to 12 mm wide, the near-net wall of a tube) is filled with
// contour passes, the same number from each side, spread evenly so that neighbouring tracks
// lie at most a pitch apart plus half the overlap: no raster line runs along the ring where
// it bends to the raster (which left wedges bare between long lines and the contour), and
// the ring is covered. An odd number of tracks across puts the gap fill's one along the
// middle.
TEST(Toolpath, ThinIslandsAreFilledWithEvenlySpreadContourPasses) {
    const PathSettings s = settings();
    for (double width = 6.0; width <= 16.01; width += 0.5) {
        SCOPED_TRACE(width);
        const geom2d::WireTree ring = annulus(30.0, 30.0 - width);
        const LayerToolpath tp = plan(ring, s);
        expect_valid(ring, s, tp, {}, 0.995);
        std::vector<double> radii;  // of the closed strokes, from the centre
        for (const Stroke& st : tp.strokes) {
            EXPECT_TRUE(st.kind == StrokeKind::kContour || st.points.front() == st.points.back())
                << "an open stroke: a raster line or a scrap of one";
            double r = 0.0;
            for (const Point2& p : st.points) {
                r += std::hypot(static_cast<double>(p.x), static_cast<double>(p.y));
            }
            radii.push_back(r / static_cast<double>(st.points.size()) / 1000.0);
        }
        std::sort(radii.begin(), radii.end());
        ASSERT_GE(radii.size(), 2u);
        EXPECT_NEAR(radii.front(), 30.0 - width + s.track_width_mm / 2, 0.05);
        EXPECT_NEAR(radii.back(), 30.0 - s.track_width_mm / 2, 0.05);
        for (std::size_t k = 1; k < radii.size(); ++k) {
            EXPECT_LE(radii[k] - radii[k - 1],
                      s.pitch_mm() + (s.track_width_mm - s.pitch_mm()) / 2 + 0.05);
            EXPECT_GT(radii[k] - radii[k - 1], 0.5 * s.pitch_mm());
        }
    }
}

TEST(Toolpath, AShelfBesideATowerLeavesNoSliverBare) {
    // A wall 60 mm long with a tower 20 mm wide standing on its middle: the wall's top beside
    // the tower is a shelf inside the fill region. Lines spread over the whole height can
    // stand up to a pitch below the shelf, leaving a strip narrower than the gap fill takes
    // along 40 mm of it; the fill places its lines on each side of the shelf instead.
    const PathSettings s = settings();
    double worst = 0.0;
    std::string where;
    for (double wall = 10.0; wall <= 14.01; wall += 0.25) {
        for (double tower = 3.0; tower <= 8.01; tower += 0.5) {
            const geom2d::WireTree tree =
                region({{pt(0, 0), pt(60, 0), pt(60, wall), pt(40, wall), pt(40, wall + tower),
                         pt(20, wall + tower), pt(20, wall), pt(0, wall)}});
            const LayerToolpath tp = plan(tree, s);
            const double share = tp.uncovered_mm2 / area_mm2(material(tree));
            if (share > worst) {
                worst = share;
                where = "wall " + std::to_string(wall) + " mm, tower " + std::to_string(tower);
            }
            expect_valid(tree, s, tp, {}, 0.99);
        }
    }
    // Lines spread over the whole height left up to 2.7 % of these regions bare; what stays
    // bare now is the corners the tracks' round ends miss (about 0.3 %).
    EXPECT_LT(worst, 0.005) << where;
}

TEST(Toolpath, EmptyAndHoleOnlyRegionsGiveNoStrokes) {
    const auto empty = plan_layer({}, settings(), {});
    ASSERT_TRUE(empty.has_value());
    EXPECT_TRUE(empty->strokes.empty());
    EXPECT_EQ(empty->uncovered_mm2, 0.0);
    // A wire tree with only a hole (a tube cut at its end) has no material to deposit.
    geom2d::WireTree holes;
    Path2 hole = ngon(0, 0, 10, 32);
    std::reverse(hole.begin(), hole.end());
    holes.nodes.push_back({hole, -1, {}, true, 0});
    holes.roots.push_back(0);
    const auto r = plan_layer(holes, settings(), {});
    ASSERT_TRUE(r.has_value());
    EXPECT_TRUE(r->strokes.empty());
    // A region smaller than a track: nothing fits, all of it is uncovered.
    const auto tiny = plan_layer(square_region(1.0), settings(), {});
    ASSERT_TRUE(tiny.has_value());
    EXPECT_TRUE(tiny->strokes.empty());
    EXPECT_NEAR(tiny->uncovered_mm2, 1.0, 1e-9);
}

TEST(Toolpath, FarFromTheOriginTheSameTracks) {
    // Far away (400 m) the same shape gives the same tracks, shifted.
    const double off = 400'000.0;
    const geom2d::WireTree near = region({rect(0, 0, 80, 30), ngon(40, 15, 8, 64)});
    const geom2d::WireTree far =
        region({rect(off, off, off + 80, off + 30), ngon(off + 40, off + 15, 8, 64)});
    const LayerToolpath a = plan(near, settings(), pt(-5, -5));
    const LayerToolpath b = plan(far, settings(), pt(off - 5, off - 5));
    ASSERT_EQ(a.strokes.size(), b.strokes.size());
    EXPECT_NEAR(a.deposit_length_mm, b.deposit_length_mm, 1e-6 * a.deposit_length_mm);
    EXPECT_NEAR(a.uncovered_mm2, b.uncovered_mm2, 0.01);
    expect_valid(far, settings(), b, pt(off - 5, off - 5), 0.98);
}

TEST(Validate, AcceptsDefaults) {
    EXPECT_TRUE(validate(PathSettings{}).has_value());
    PathSettings s;
    s.overlap = 0.0;
    s.contour_passes = 0;
    EXPECT_TRUE(validate(s).has_value());
}

TEST(Validate, RejectsOutOfRangeSettingsNamingThem) {
    const auto expect_rejected = [](const PathSettings& s, const std::string& name) {
        const auto r = validate(s);
        ASSERT_FALSE(r.has_value()) << name;
        EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
        EXPECT_NE(r.error().describe().find(name), std::string::npos) << r.error().describe();
        // plan_layer refuses the same settings.
        const auto p = plan_layer(square_region(10), s, {});
        ASSERT_FALSE(p.has_value());
        EXPECT_NE(p.error().describe().find(name), std::string::npos);
    };
    for (const double w : {0.0, -1.0, std::nan("")}) {
        PathSettings s;
        s.track_width_mm = w;
        expect_rejected(s, "track_width_mm");
    }
    for (const double o : {1.0, 1.5, -0.1, std::nan("")}) {
        PathSettings s;
        s.overlap = o;
        expect_rejected(s, "overlap");
    }
    {
        PathSettings s;
        s.overlap = 0.9999;  // a pitch of 0.25 um
        expect_rejected(s, "overlap");
    }
    {
        PathSettings s;
        s.contour_passes = -1;
        expect_rejected(s, "contour_passes");
    }
    {
        PathSettings s;
        s.raster_angle_deg = INFINITY;
        expect_rejected(s, "raster_angle_deg");
    }
}

// The geometry helpers the checks above rely on must themselves be able to fail.
TEST(Helpers, GeometryChecksDetectWhatTheyLookFor) {
    const Paths2 sq{rect(0, 0, 10, 10)};
    EXPECT_EQ(geom2d::locate_point(sq, pt(5, 5)), geom2d::Containment::kInside);
    EXPECT_EQ(geom2d::locate_point(sq, pt(10, 5)), geom2d::Containment::kBoundary);
    EXPECT_EQ(geom2d::locate_point(sq, pt(11, 5)), geom2d::Containment::kOutside);
    const geom2d::WireTree ring = annulus(10, 5);
    EXPECT_EQ(geom2d::locate_point(ring.paths(), pt(0, 0)), geom2d::Containment::kOutside);
    EXPECT_EQ(geom2d::locate_point(ring.paths(), pt(7.5, 0)), geom2d::Containment::kInside);

    const Path2 hull = geom2d::convex_hull({rect(0, 0, 10, 10), {pt(5, 5), pt(20, 5)}});
    EXPECT_EQ(hull.size(), 5u);
    EXPECT_GT(geom2d::signed_area_um2(hull), 0.0);

    // A segment through a hole is found; one beside it is not.
    const Paths2 crossing = geom2d::clip_polylines({{pt(-20, 0), pt(20, 0)}}, {ngon(0, 0, 5, 64)});
    ASSERT_EQ(crossing.size(), 1u);
    EXPECT_NEAR(length_mm(crossing[0]), 10.0, 0.01);
    EXPECT_TRUE(geom2d::clip_polylines({{pt(-20, 6), pt(20, 6)}}, {ngon(0, 0, 5, 64)}).empty());

    // A track 2 mm wide and 10 mm long covers 20 mm^2 plus its round ends.
    const Paths2 track = geom2d::sweep_polylines({{pt(0, 0), pt(10, 0)}}, um(1.0));
    EXPECT_NEAR(area_mm2(track), 20.0 + std::numbers::pi, 0.05);

    // The grid coverage sees an uncovered square.
    LayerToolpath half;
    half.strokes.push_back({StrokeKind::kFill, {pt(0, 1), pt(10, 1)}});
    const GridCoverage grid(region({rect(0, 0, 10, 4)}), half, 2.0, 0.1);
    EXPECT_NEAR(grid.fraction(), 0.5, 0.02);
}

// plan_narrow_layer lays one track along the middle of an island too narrow for a contour,
// inside it and nearly its length, and nothing on an island a contour fits (plan_layer's).
TEST(Toolpath, ANarrowIslandGetsOneTrackAlongItsMiddleAndAWideOneNone) {
    const geom2d::WireTree tree = region({rect(0, 0, 40, 1.5), rect(0, 10, 20, 30)});
    auto narrow = plan_narrow_layer(tree, settings(), {});
    ASSERT_TRUE(narrow.has_value()) << narrow.error().describe();
    ASSERT_EQ(narrow->strokes.size(), 1u);
    const Stroke& s = narrow->strokes.front();
    double length = 0.0;
    for (std::size_t i = 0; i < s.points.size(); ++i) {
        EXPECT_NEAR(static_cast<double>(s.points[i].y), 750.0, 50.0);  // the strip's middle
        EXPECT_GT(s.points[i].x, 0);
        EXPECT_LT(s.points[i].x, 40000);
        if (i > 0) length += length_mm({s.points[i - 1], s.points[i]});
    }
    EXPECT_GT(length, 36.0);
    EXPECT_NEAR(narrow->deposit_length_mm, length, 1e-6);
    // The strip's beads cover it all but a sliver at its ends (the uncovered area counts the
    // narrow islands only: the square is plan_layer's).
    EXPECT_LT(narrow->uncovered_mm2, 0.05 * 60.0);
    // plan_layer lays nothing on the strip.
    const LayerToolpath full = plan(tree, settings());
    for (const Stroke& t : full.strokes) {
        for (const Point2& q : t.points) EXPECT_GT(q.y, 5000);
    }
    // A track narrower than the strip: plan_layer builds it, plan_narrow_layer nothing.
    auto fine = plan_narrow_layer(tree, settings(0.8), {});
    ASSERT_TRUE(fine.has_value());
    EXPECT_TRUE(fine->strokes.empty());
}

}  // namespace
}  // namespace maxslice::path::test
