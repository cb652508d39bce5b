#include "maxslice/geom2d/wire_tree.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "maxslice/geom2d/polygon.hpp"

namespace maxslice::geom2d {
namespace {

// Square [x0, x1] x [y0, y1] given in mm, counter-clockwise unless cw.
Path2 square(double x0, double y0, double x1, double y1, bool cw = false) {
    auto um = [](double mm) { return static_cast<std::int64_t>(std::llround(mm * 1000.0)); };
    Path2 p{{um(x0), um(y0)}, {um(x1), um(y0)}, {um(x1), um(y1)}, {um(x0), um(y1)}};
    if (cw) std::reverse(p.begin(), p.end());
    return p;
}

// Regular n-gon of circumradius r (mm) centred on (cx, cy), counter-clockwise.
Path2 ngon(double cx, double cy, double r, int n) {
    Path2 p;
    for (int i = 0; i < n; ++i) {
        const double a = 2.0 * std::numbers::pi * i / n;
        p.push_back({std::llround((cx + r * std::cos(a)) * 1000.0),
                     std::llround((cy + r * std::sin(a)) * 1000.0)});
    }
    return p;
}

double perimeter_sum(const Paths2& paths) {
    double sum = 0.0;
    for (const auto& p : paths) sum += perimeter_mm(p);
    return sum;
}

Path2 reversed(Path2 p) {
    std::reverse(p.begin(), p.end());
    return p;
}

void expect_same_tree(const WireTree& a, const WireTree& b) {
    EXPECT_EQ(a.roots, b.roots);
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    for (std::size_t i = 0; i < a.nodes.size(); ++i) {
        SCOPED_TRACE(i);
        EXPECT_EQ(a.nodes[i].wire, b.nodes[i].wire);
        EXPECT_EQ(a.nodes[i].parent, b.nodes[i].parent);
        EXPECT_EQ(a.nodes[i].children, b.nodes[i].children);
        EXPECT_EQ(a.nodes[i].is_hole, b.nodes[i].is_hole);
        EXPECT_EQ(a.nodes[i].depth, b.nodes[i].depth);
    }
}

// ---- Polygons ----------------------------------------------------------------------------

TEST(Polygon, SignedAreaIsPositiveCounterClockwise) {
    EXPECT_DOUBLE_EQ(signed_area_um2(square(0, 0, 10, 10)), 1e8);
    EXPECT_DOUBLE_EQ(signed_area_um2(square(0, 0, 10, 10, true)), -1e8);
    EXPECT_DOUBLE_EQ(signed_area_um2(Path2{{0, 0}, {4, 0}, {0, 3}}), 6.0);
    EXPECT_DOUBLE_EQ(signed_area_um2(Path2{{0, 0}, {0, 3}, {4, 0}}), -6.0);
}

TEST(Polygon, SignedAreaDoesNotDependOnTheStartPoint) {
    Path2 p = ngon(3, -2, 7, 13);
    const double a = signed_area_um2(p);
    for (std::size_t k = 0; k < p.size(); ++k) {
        std::rotate(p.begin(), p.begin() + 1, p.end());
        EXPECT_DOUBLE_EQ(signed_area_um2(p), a);
    }
}

TEST(Polygon, DegenerateLoopsHaveNoArea) {
    EXPECT_EQ(signed_area_um2(Path2{}), 0.0);
    EXPECT_EQ(signed_area_um2(Path2{{1, 1}, {5, 5}}), 0.0);
    EXPECT_EQ(signed_area_um2(Path2{{0, 0}, {1, 1}, {2, 2}}), 0.0);
}

TEST(Polygon, AreaAtTheEdgeOfTheCoordinateRange) {
    const std::int64_t m = kMaxCoordinateUm;
    const Path2 p{{-m, -m}, {m, -m}, {m, m}, {-m, m}};
    EXPECT_DOUBLE_EQ(signed_area_um2(p), 4.0 * static_cast<double>(m) * static_cast<double>(m));
    EXPECT_DOUBLE_EQ(perimeter_mm(p), 8.0 * static_cast<double>(m) / 1000.0);
}

TEST(Polygon, AreaSumAndPerimeterInMillimetres) {
    const Paths2 ring{square(0, 0, 10, 10), square(2, 2, 8, 8, true)};
    EXPECT_DOUBLE_EQ(signed_area_mm2(ring), 100.0 - 36.0);
    EXPECT_DOUBLE_EQ(perimeter_mm(square(0, 0, 10, 5)), 30.0);
    EXPECT_DOUBLE_EQ(perimeter_mm(Path2{{0, 0}, {3000, 4000}, {0, 4000}}), 5.0 + 3.0 + 4.0);
}

// ---- Wire trees --------------------------------------------------------------------------

Paths2 nested_loops() {
    return {square(0, 0, 100, 100), square(10, 10, 90, 90, true), square(20, 20, 80, 80),
            square(30, 30, 70, 70, true)};
}

TEST(WireTree, NestedSquaresFormAChain) {
    for (const FillRule rule : {FillRule::kPositive, FillRule::kNonZero, FillRule::kEvenOdd}) {
        SCOPED_TRACE(static_cast<int>(rule));
        const WireTree t = build_wire_tree(nested_loops(), rule);
        ASSERT_EQ(t.nodes.size(), 4u);
        ASSERT_EQ(t.roots, (std::vector<int>{0}));
        int id = 0;
        for (int depth = 0; depth < 4; ++depth) {
            const WireNode& n = t.nodes[static_cast<std::size_t>(id)];
            EXPECT_EQ(n.depth, depth);
            EXPECT_EQ(n.is_hole, depth % 2 == 1);
            EXPECT_EQ(n.parent, depth == 0 ? -1 : id - 1);
            EXPECT_EQ(signed_area_um2(n.wire) < 0.0, n.is_hole);
            if (depth < 3) {
                ASSERT_EQ(n.children.size(), 1u);
                id = n.children[0];
                EXPECT_GT(id, n.parent);
            } else {
                EXPECT_TRUE(n.children.empty());
            }
        }
        EXPECT_EQ(t.outer_count(), 2u);
        EXPECT_EQ(t.hole_count(), 2u);
        EXPECT_DOUBLE_EQ(t.area_mm2(), 10000.0 - 6400.0 + 3600.0 - 1600.0);
    }
}

TEST(WireTree, EvenOddIgnoresOrientation) {
    Paths2 all_ccw = nested_loops();
    for (auto& p : all_ccw) {
        if (signed_area_um2(p) < 0) p = reversed(p);
    }
    const WireTree t = build_wire_tree(all_ccw, FillRule::kEvenOdd);
    EXPECT_EQ(t.outer_count(), 2u);
    EXPECT_EQ(t.hole_count(), 2u);
    EXPECT_DOUBLE_EQ(t.area_mm2(), 5600.0);
}

TEST(WireTree, SeveralTopLevelOuters) {
    const Paths2 loops{square(50, 0, 60, 10), square(0, 0, 10, 10), square(20, 0, 40, 20),
                       square(25, 5, 35, 15, true)};
    const WireTree t = build_wire_tree(loops, FillRule::kPositive);
    ASSERT_EQ(t.roots.size(), 3u);
    EXPECT_EQ(t.outer_count(), 3u);
    EXPECT_EQ(t.hole_count(), 1u);
    EXPECT_DOUBLE_EQ(t.area_mm2(), 100.0 + 100.0 + 400.0 - 100.0);
    int with_hole = 0;
    for (const int r : t.roots) {
        const WireNode& n = t.nodes[static_cast<std::size_t>(r)];
        EXPECT_EQ(n.parent, -1);
        EXPECT_FALSE(n.is_hole);
        if (!n.children.empty()) {
            ++with_hole;
            EXPECT_DOUBLE_EQ(signed_area_um2(n.wire), 4e8);
        }
    }
    EXPECT_EQ(with_hole, 1);
    // Parents come before their children.
    for (std::size_t i = 0; i < t.nodes.size(); ++i) {
        EXPECT_LT(t.nodes[i].parent, static_cast<int>(i));
    }
}

TEST(WireTree, HoleLikeLoopsAloneAreEmptyUnderThePositiveRule) {
    const Paths2 loops{square(0, 0, 10, 10, true), square(20, 0, 30, 10, true)};
    const WireTree positive = build_wire_tree(loops, FillRule::kPositive);
    EXPECT_TRUE(positive.empty());
    EXPECT_EQ(positive.area_mm2(), 0.0);
    EXPECT_TRUE(positive.roots.empty());
    // Under the non-zero rule the same loops are filled regions with outers made CCW.
    const WireTree nonzero = build_wire_tree(loops, FillRule::kNonZero);
    EXPECT_EQ(nonzero.outer_count(), 2u);
    EXPECT_DOUBLE_EQ(nonzero.area_mm2(), 200.0);
}

TEST(WireTree, EmptyAndDegenerateInput) {
    EXPECT_TRUE(build_wire_tree({}, FillRule::kPositive).empty());
    const Paths2 junk{{}, {{0, 0}}, {{0, 0}, {10, 10}}, {{0, 0}, {5, 5}, {10, 10}}};
    EXPECT_TRUE(build_wire_tree(junk, FillRule::kPositive).empty());
    Paths2 with_junk = nested_loops();
    with_junk.insert(with_junk.begin() + 1, junk.begin(), junk.end());
    expect_same_tree(build_wire_tree(with_junk, FillRule::kPositive),
                     build_wire_tree(nested_loops(), FillRule::kPositive));
}

TEST(WireTree, OverlappingLoopsMergeUnderThePositiveRule) {
    // Two CCW squares overlapping in a 5 x 5 corner: one outer, the overlap counted once.
    const WireTree both =
        build_wire_tree({square(0, 0, 10, 10), square(5, 5, 15, 15)}, FillRule::kPositive);
    EXPECT_EQ(both.nodes.size(), 1u);
    EXPECT_DOUBLE_EQ(both.area_mm2(), 175.0);
    // A CW loop over part of a CCW one cancels it there (winding 0) and adds nothing
    // outside it (winding -1).
    const Paths2 mixed{square(0, 0, 10, 10), square(5, 5, 15, 15, true)};
    EXPECT_DOUBLE_EQ(build_wire_tree(mixed, FillRule::kPositive).area_mm2(), 75.0);
    // Non-zero fills both parts with winding +-1 and leaves the overlap empty.
    EXPECT_DOUBLE_EQ(build_wire_tree(mixed, FillRule::kNonZero).area_mm2(), 150.0);
    // A CW loop inside a CCW one is a hole.
    const WireTree ring =
        build_wire_tree({square(0, 0, 10, 10), square(2, 2, 8, 8, true)}, FillRule::kPositive);
    EXPECT_EQ(ring.outer_count(), 1u);
    EXPECT_EQ(ring.hole_count(), 1u);
    EXPECT_DOUBLE_EQ(ring.area_mm2(), 64.0);
}

TEST(WireTree, SameTreeForAnyInputOrderAndStartPoint) {
    Paths2 loops = nested_loops();
    loops.push_back(square(200, 0, 210, 10));
    loops.push_back(ngon(150, 50, 20, 24));
    loops.push_back(reversed(ngon(150, 50, 10, 24)));
    loops.push_back(square(-50, -50, -40, -40));
    const WireTree reference = build_wire_tree(loops, FillRule::kPositive);
    ASSERT_EQ(reference.nodes.size(), 8u);
    std::mt19937_64 rng(42);
    for (int trial = 0; trial < 20; ++trial) {
        Paths2 shuffled = loops;
        std::shuffle(shuffled.begin(), shuffled.end(), rng);
        for (Path2& p : shuffled) {
            std::uniform_int_distribution<std::size_t> k(0, p.size() - 1);
            std::rotate(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(k(rng)), p.end());
        }
        SCOPED_TRACE(trial);
        expect_same_tree(build_wire_tree(shuffled, FillRule::kPositive), reference);
    }
}

TEST(WireTree, PathsFollowNodeOrder) {
    const WireTree t = build_wire_tree(nested_loops(), FillRule::kPositive);
    const Paths2 paths = t.paths();
    ASSERT_EQ(paths.size(), t.nodes.size());
    for (std::size_t i = 0; i < paths.size(); ++i) EXPECT_EQ(paths[i], t.nodes[i].wire);
    EXPECT_DOUBLE_EQ(signed_area_mm2(paths), t.area_mm2());
}

// ---- The fast path for loops that already bound a region --------------------------------

// Loops in micrometres, counter-clockwise unless reversed.
Path2 um_path(std::initializer_list<Point2> pts) {
    return Path2(pts);
}

// The fast path, when it answers, must give Clipper's tree; build_wire_tree must give it
// always, from a copy of the loops or from the loops themselves. The fast path that takes the
// loops' points answers when the other does, and leaves the loops as they were when it does
// not. Returns whether the fast path answered.
bool fast_path_agrees(const Paths2& loops) {
    const WireTree clipper = detail::clipper_wire_tree(loops, FillRule::kPositive);
    expect_same_tree(build_wire_tree(loops, FillRule::kPositive), clipper);
    expect_same_tree(build_wire_tree(Paths2(loops), FillRule::kPositive), clipper);
    const auto fast = detail::wire_tree_of_simple_loops(loops);
    if (fast) expect_same_tree(*fast, clipper);
    Paths2 taken = loops;
    const auto took = detail::take_wire_tree_of_simple_loops(taken);
    EXPECT_EQ(took.has_value(), fast.has_value());
    if (took) expect_same_tree(*took, clipper);
    if (!took) {
        EXPECT_EQ(taken, loops);
    }
    return fast.has_value();
}

// Rings of regular polygons, alternately oriented, nested `levels` deep, with a few rings of
// islands side by side: what a cut through a closed mesh gives.
Paths2 nested_rings(std::mt19937_64& rng, int levels) {
    std::uniform_real_distribution<double> jitter(-0.3, 0.3);
    std::uniform_int_distribution<int> sides(12, 40);  // inner rings stay inside outer ones
    Paths2 loops;
    for (int col = 0; col < 3; ++col) {
        const double cx = 100.0 * col + jitter(rng), cy = 20.0 * jitter(rng);
        for (int level = 0; level < levels; ++level) {
            const double r = 45.0 - 8.0 * level + jitter(rng);
            Path2 p = ngon(cx, cy, r, sides(rng));
            std::rotate(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(p.size() / 2), p.end());
            loops.push_back(level % 2 == 0 ? p : reversed(p));
        }
        if (levels % 2 == 0) {  // the innermost loop is a hole: two islands in it
            loops.push_back(ngon(cx - 2.0, cy, 1.5, 12));
            loops.push_back(ngon(cx + 2.0, cy, 1.5, 12));
        }
    }
    std::shuffle(loops.begin(), loops.end(), rng);
    return loops;
}

TEST(WireTreeFastPath, AgreesWithClipperOnNestedRegions) {
    std::mt19937_64 rng(7);
    for (int trial = 0; trial < 60; ++trial) {
        SCOPED_TRACE(trial);
        const Paths2 loops = nested_rings(rng, 1 + trial % 5);
        EXPECT_TRUE(fast_path_agrees(loops));
    }
    EXPECT_TRUE(fast_path_agrees({}));
}

TEST(WireTreeFastPath, DropsRepeatedAndCollinearPointsAsClipperDoes) {
    const Path2 p = um_path({{0, 0},
                             {5000, 0},
                             {5000, 0},
                             {10000, 0},
                             {10000, 4000},
                             {10000, 10000},
                             {3000, 7000},
                             {0, 10000},
                             {0, 10000},
                             {0, 0}});
    EXPECT_TRUE(fast_path_agrees({p}));
    EXPECT_EQ(build_wire_tree({p}, FillRule::kPositive).nodes.at(0).wire.size(), 5u);
}

TEST(WireTreeFastPath, RefusesWhatOnlyClipperCanResolve) {
    const Paths2 cases[] = {
        {square(0, 0, 10, 10), square(10, 10, 20, 20)},      // touching at a corner
        {square(0, 0, 10, 10), square(5, 0, 15, 10)},        // overlapping bodies
        {square(0, 0, 10, 10), square(2, 2, 8, 8)},          // same orientation nested
        {square(0, 0, 10, 10, true)},                        // a hole with no outer
        {square(0, 0, 10, 10), square(10, 2, 12, 8, true)},  // hole touching its outer
        {um_path({{0, 0}, {10, 10}, {10, 0}, {0, 10}})},     // a bow tie
        // A vertex of one loop 1 um from an edge of another: Clipper's rounding may merge.
        {square(0, 0, 10, 10), um_path({{10001, 5000}, {20000, 0}, {20000, 10000}})},
        // A spike: the loop runs out and back along one line.
        {um_path({{0, 0}, {10, 0}, {20, 0}, {10, 0}, {10, 10}})},
        // A notch narrower than a unit one unit below its tip, as in a real cut: Clipper's
        // rounded sweep cuts it off.
        {um_path({{3, 3}, {0, 0}, {0, -1}, {-1, 1}, {-13, 13}, {0, -100}})},
    };
    for (std::size_t i = 0; i < std::size(cases); ++i) {
        SCOPED_TRACE(i);
        EXPECT_FALSE(fast_path_agrees(cases[i]));
    }
}

TEST(WireTreeFastPath, AgreesWithClipperOnFoundCases) {
    // Loops random fuzzing once caught the fast path on: collinear horizontal edges of the
    // two sides of one loop overlapping at a single height.
    const Paths2 cases[] = {
        {um_path({{6, 2}, {7, 1}, {5, 1}, {0, 0}, {6, 1}, {8, 1}})},
        {um_path({{33, 27}, {31, 31}, {31, 27}, {26, 27}, {27, 23}, {30, 27}})},
        {um_path({{8, 7}, {0, 8}, {5, 7}, {1, 7}, {0, 4}, {3, 7}})},
        {um_path({{3, 5}, {0, 5}, {0, 3}, {2, 5}, {6, 5}, {5, 7}})},
    };
    for (std::size_t i = 0; i < std::size(cases); ++i) {
        SCOPED_TRACE(i);
        fast_path_agrees(cases[i]);
    }
}

TEST(WireTreeFastPath, AgreesWithClipperOnRandomSmallLoops) {
    // Random loops on a tiny grid: crossings, touching, collinear runs, spikes, slivers and
    // near misses are common. Every answer of the fast path must be Clipper's.
    std::mt19937_64 rng(11);
    int answered = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        std::uniform_int_distribution<int> count(1, 3), points(3, 7);
        std::uniform_int_distribution<std::int64_t> coord(0, trial % 2 == 0 ? 12 : 400);
        Paths2 loops;
        const int n = count(rng);
        for (int l = 0; l < n; ++l) {
            Path2 p;
            const int k = points(rng);
            for (int i = 0; i < k; ++i) p.push_back({coord(rng), coord(rng)});
            loops.push_back(std::move(p));
        }
        SCOPED_TRACE(trial);
        answered += fast_path_agrees(loops) ? 1 : 0;
    }
    EXPECT_GT(answered, 100);  // the property is not vacuous
}

TEST(WireTreeFastPath, AgreesWithClipperOnFineNoisyCircles) {
    // Circles of a few hundred um with points rounded to the um grid and jittered by a unit
    // or two, nested and side by side, as the cuts of a fine lattice give them.
    std::mt19937_64 rng(5);
    std::uniform_int_distribution<int> jit(-2, 2);
    int answered = 0;
    for (int trial = 0; trial < 400; ++trial) {
        Paths2 loops;
        for (int c = 0; c < 4; ++c) {
            for (int level = 0; level < 2; ++level) {
                const double r = 0.15 - 0.06 * level;
                Path2 p = ngon(0.35 * c, 0.0, r, 40 + trial % 50);
                for (Point2& q : p) q = {q.x + jit(rng), q.y + jit(rng)};
                loops.push_back(level == 0 ? p : reversed(p));
            }
        }
        SCOPED_TRACE(trial);
        answered += fast_path_agrees(loops) ? 1 : 0;
    }
    EXPECT_GT(answered, 10);
}

TEST(WireTreeFastPath, AgreesWithClipperOnNestedNoisyStars) {
    // Star-shaped loops with random radii (many y-monotone chains each, as a scanned part's
    // cut), nested up to three deep and side by side, jittered by up to three units; every
    // fifth set has its heights rounded to 16 units, so many edges are horizontal.
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int answered = 0;
    const int trials = 600;
    for (int trial = 0; trial < trials; ++trial) {
        const int j = trial % 4;
        std::uniform_int_distribution<int> jit(-j, j);
        Paths2 loops;
        for (int col = 0; col <= trial % 4; ++col) {
            for (int level = 0; level <= trial % 3; ++level) {
                const int k = 8 + static_cast<int>(unit(rng) * 60);
                Path2 p;
                for (int i = 0; i < k; ++i) {
                    const double a = 2.0 * std::numbers::pi * i / k;
                    const double r = (200.0 - 60.0 * level) * (0.75 + 0.25 * unit(rng));
                    p.push_back({std::llround(450.0 * col + r * std::cos(a)) + jit(rng),
                                 std::llround(r * std::sin(a)) + jit(rng)});
                }
                if (trial % 5 == 0) {
                    for (Point2& q : p) q.y = q.y / 16 * 16;
                }
                loops.push_back(level % 2 == 0 ? p : reversed(p));
            }
        }
        std::shuffle(loops.begin(), loops.end(), rng);
        SCOPED_TRACE(trial);
        answered += fast_path_agrees(loops) ? 1 : 0;
    }
    EXPECT_GT(answered, trials / 2);  // most sets are clear: the fast path must answer them
}

// ---- Booleans and offsets ----------------------------------------------------------------

TEST(Booleans, OverlappingSquares) {
    const Paths2 a{square(0, 0, 10, 10)};
    const Paths2 b{square(5, 5, 15, 15)};
    EXPECT_DOUBLE_EQ(signed_area_mm2(union_of({a[0], b[0]})), 175.0);
    EXPECT_DOUBLE_EQ(signed_area_mm2(intersection_of(a, b)), 25.0);
    EXPECT_DOUBLE_EQ(signed_area_mm2(difference_of(a, b)), 75.0);
    EXPECT_DOUBLE_EQ(signed_area_mm2(difference_of(b, a)), 75.0);
    EXPECT_TRUE(intersection_of(a, {square(20, 20, 30, 30)}).empty());
}

TEST(Booleans, DifferenceMakesAHoleOrientedClockwise) {
    const Paths2 d = difference_of({square(0, 0, 10, 10)}, {square(3, 3, 7, 7)});
    ASSERT_EQ(d.size(), 2u);
    const int negatives = static_cast<int>(
        std::count_if(d.begin(), d.end(), [](const Path2& p) { return signed_area_um2(p) < 0.0; }));
    EXPECT_EQ(negatives, 1);
    EXPECT_DOUBLE_EQ(signed_area_mm2(d), 84.0);
}

TEST(Booleans, UnionWithFillRules) {
    const Paths2 mixed{square(0, 0, 10, 10), square(5, 5, 15, 15, true)};
    EXPECT_DOUBLE_EQ(signed_area_mm2(union_of(mixed, FillRule::kNonZero)), 150.0);
    EXPECT_DOUBLE_EQ(signed_area_mm2(union_of(mixed, FillRule::kPositive)), 75.0);
    EXPECT_DOUBLE_EQ(signed_area_mm2(union_of(mixed, FillRule::kEvenOdd)), 150.0);
}

TEST(Booleans, PolygonIntersectionMatchesAnalyticArea) {
    // A 64-gon of radius 10 cut by the half plane x >= 0 (a large square): half its area.
    const Path2 circle = ngon(0, 0, 10, 64);
    const double area = signed_area_mm2({circle});
    EXPECT_NEAR(area, 0.5 * 64 * 100 * std::sin(2 * std::numbers::pi / 64),
                perimeter_mm(circle) * 0.001);
    EXPECT_NEAR(signed_area_mm2(intersection_of({circle}, {square(0, -20, 20, 20)})), area / 2,
                1e-6 * area);
}

TEST(Offset, SquareGrowsAndShrinksWithMitredCorners) {
    const Paths2 sq{square(0, 0, 10, 10)};
    EXPECT_NEAR(signed_area_mm2(offset_of(sq, 1000)), 144.0, 1e-9);
    EXPECT_NEAR(signed_area_mm2(offset_of(sq, -1000)), 64.0, 1e-9);
    EXPECT_TRUE(offset_of(sq, -5001).empty());
    EXPECT_TRUE(offset_of({square(0, 0, 20, 2)}, -1500).empty());
}

TEST(Offset, RingGrowsOutwardAndItsHoleShrinks) {
    const Paths2 ring{square(0, 0, 20, 20), square(5, 5, 15, 15, true)};
    const Paths2 grown = offset_of(ring, 1000);
    EXPECT_NEAR(signed_area_mm2(grown), 22.0 * 22.0 - 8.0 * 8.0, 1e-9);
    EXPECT_EQ(grown.size(), 2u);
}

TEST(Offset, RegularPolygonGrowsToALargerRegularPolygon) {
    // Offsetting a regular n-gon by d with mitres moves each side out by d: the apothem
    // becomes a + d and the area n (a + d)^2 tan(pi / n).
    const int n = 64;
    const Path2 poly = ngon(0, 0, 10, n);
    const double a = 10.0 * std::cos(std::numbers::pi / n);
    for (const double d : {1.0, -2.0}) {
        const Paths2 out = offset_of({poly}, std::llround(d * 1000));
        const double expected = n * (a + d) * (a + d) * std::tan(std::numbers::pi / n);
        EXPECT_NEAR(signed_area_mm2(out), expected, perimeter_sum(out) * 0.001) << d;
    }
}

TEST(Offset, ShrinkingPastTheCentreLeavesNothingWhateverTheShortcut) {
    // A small fine polygon shrunk by more than its inradius: the result is empty, both just
    // past its half width (the bounding-box shortcut) and just short of it (Clipper itself,
    // which must leave the thin middle).
    const Path2 fine = ngon(0, 0, 0.5, 400);
    EXPECT_TRUE(offset_of({fine}, -501).empty());
    EXPECT_TRUE(offset_of({fine}, -5000).empty());
    const Paths2 left = offset_of({fine}, -450);
    ASSERT_FALSE(left.empty());
    EXPECT_GT(signed_area_mm2(left), 0.0);
    // A big outer keeps the region alive even when its small neighbour vanishes.
    const Paths2 two{fine, square(5, 0, 10, 5)};
    EXPECT_NEAR(signed_area_mm2(offset_of(two, -1000)), 9.0, 1e-9);
}

TEST(Coverage, UncoveredAreaMatchesTheBooleanDifference) {
    // Against Clipper's exact answer (region minus the union of the swept strokes), on a
    // ring and a plate with random strokes: the row integration agrees within 0.5% of the
    // region's area at rows of 1/8 of the radius.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> coord(-5.0, 45.0);
    const Paths2 ring{ngon(20, 20, 20, 90), reversed(ngon(20, 20, 8, 40))};
    const Paths2 plate{square(0, 0, 40, 40), square(10, 10, 15, 30, true)};
    for (const Paths2* region : {&ring, &plate}) {
        for (int trial = 0; trial < 5; ++trial) {
            Paths2 strokes;
            for (int i = 0; i < 12; ++i) {
                Path2 line;
                for (int k = 0; k < 3; ++k) {
                    line.push_back(
                        {std::llround(coord(rng) * 1000), std::llround(coord(rng) * 1000)});
                }
                strokes.push_back(line);
            }
            strokes.push_back({{20000, 2000}});  // a single point: a disc
            const std::int64_t r = 1500;
            const double exact =
                signed_area_mm2(difference_of(*region, sweep_polylines(strokes, r)));
            const double rows = uncovered_area_mm2(*region, strokes, r, r / 8);
            EXPECT_NEAR(rows, exact, 0.005 * signed_area_mm2(*region)) << trial;
            EXPECT_GT(exact, 0.0);
        }
    }
    // No strokes: the region's own area; strokes everywhere: nothing.
    EXPECT_NEAR(uncovered_area_mm2(ring, {}, 500, 50), signed_area_mm2(ring),
                0.002 * signed_area_mm2(ring));
    EXPECT_NEAR(uncovered_area_mm2(plate, {{{20000, -100000}, {20000, 100000}}}, 100000, 1000), 0.0,
                1e-9);
    EXPECT_EQ(uncovered_area_mm2({}, {}, 500, 50), 0.0);
}

// A straight stroke's square sweep is its rectangle with half a width added at both ends; on
// random polylines the square sweep holds all but a sliver of the round one (under 1 % of it:
// Clipper squares the outer corners of sharp turns off) and lies within the round sweep grown
// by the corners' reach (half a width times sqrt 2).
TEST(Coverage, SquareSweepHoldsTheRoundSweep) {
    const std::int64_t h = 1000;
    const Paths2 line{{{0, 0}, {10000, 0}}};
    EXPECT_NEAR(signed_area_mm2(sweep_polylines_square(line, h)), 12.0 * 2.0, 1e-6);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> coord(0.0, 30.0);
    for (int trial = 0; trial < 5; ++trial) {
        Paths2 strokes;
        for (int i = 0; i < 6; ++i) {
            Path2 poly;
            for (int k = 0; k < 4; ++k) {
                poly.push_back({std::llround(coord(rng) * 1000), std::llround(coord(rng) * 1000)});
            }
            strokes.push_back(poly);
        }
        const Paths2 round = sweep_polylines(strokes, h);
        const Paths2 square = sweep_polylines_square(strokes, h);
        EXPECT_LT(signed_area_mm2(difference_of(round, square)), 0.01 * signed_area_mm2(round))
            << trial;
        EXPECT_GT(signed_area_mm2(difference_of(square, round)), 0.0) << trial;
        const Paths2 reach = sweep_polylines(strokes, h * 3 / 2);
        EXPECT_LT(signed_area_mm2(difference_of(square, reach)), 1e-3) << trial;
    }
    EXPECT_TRUE(sweep_polylines_square(line, 0).empty());
}

// closest_region_point agrees with locate_point and closest_boundary_point: 0 and the point
// itself inside (the hole excluded), the boundary's closest point outside and in the hole.
TEST(ClosestRegionPoint, AgreesWithLocateAndClosestBoundary) {
    const Paths2 ring{square(0, 0, 10, 10), square(3, 3, 7, 7, true)};
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> coord(-5000.0, 15000.0);
    int inside = 0, outside = 0;
    for (int k = 0; k < 2000; ++k) {
        const Centroid2 p{coord(rng), coord(rng)};
        const Point2 pi{std::llround(p.x), std::llround(p.y)};
        const Containment where = locate_point(ring, pi);
        if (where == Containment::kBoundary) continue;
        const ClosestPoint c = closest_region_point(ring, p);
        if (where == Containment::kInside) {
            ++inside;
            EXPECT_EQ(c.distance_um, 0.0);
            EXPECT_EQ(c.point, pi);
        } else {
            ++outside;
            const ClosestPoint b = closest_boundary_point(ring, p);
            EXPECT_GT(c.distance_um, 0.0);
            EXPECT_DOUBLE_EQ(c.distance_um, b.distance_um);
            EXPECT_EQ(c.point, b.point);
        }
    }
    EXPECT_GT(inside, 100);
    EXPECT_GT(outside, 100);
    // In the hole: the distance to the hole's wall.
    EXPECT_NEAR(closest_region_point(ring, {5000.0, 4000.0}).distance_um, 1000.0, 1e-9);
}

TEST(Simplify, DropsVerticesThatBarelyMoveTheBoundary) {
    // A square whose sides carry many nearly collinear vertices (a 1 um zigzag).
    Path2 noisy;
    for (int i = 0; i < 1000; ++i) noisy.push_back({i * 10, (i % 2) * 1});
    for (int i = 0; i < 1000; ++i) noisy.push_back({10000, i * 10});
    for (int i = 0; i < 1000; ++i) noisy.push_back({10000 - i * 10, 10000});
    for (int i = 0; i < 1000; ++i) noisy.push_back({0, 10000 - i * 10});
    const Paths2 simple = simplify({noisy}, 5);
    ASSERT_EQ(simple.size(), 1u);
    EXPECT_LT(simple.front().size(), 20u);
    EXPECT_NEAR(signed_area_mm2(simple), signed_area_mm2({noisy}), perimeter_mm(noisy) * 0.005);
    // Tolerance 0 keeps every vertex; loops that collapse are dropped.
    EXPECT_EQ(simplify({noisy}, 0).front().size(), noisy.size());
    EXPECT_TRUE(simplify({Path2{{0, 0}, {3, 0}, {0, 3}}}, 5).empty());
    // Holes keep their orientation.
    const Paths2 ring = simplify({square(0, 0, 20, 20), square(5, 5, 15, 15, true)}, 5);
    ASSERT_EQ(ring.size(), 2u);
    EXPECT_NEAR(signed_area_mm2(ring), 300.0, 1e-9);
}

}  // namespace
}  // namespace maxslice::geom2d
