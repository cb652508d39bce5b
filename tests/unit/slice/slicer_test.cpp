#include "maxslice/slice/slicer.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <random>
#include <set>
#include <string>

#include "maxslice/core/tolerances.hpp"
#include "maxslice/core/units.hpp"
#include "maxslice/geom2d/wire_tree.hpp"
#include "support/fixtures.hpp"

namespace maxslice::slice {
namespace {

using core::Vec3d;
using geom2d::Path2;
using geom2d::Paths2;
using geom2d::Point2;
using geom2d::WireTree;
using test::Fixture;

// Areas must match within 0.5%. On top of that each boundary point may move by up to
// 0.71 um when it is rounded to the micrometre grid, which changes an area by at most
// (perimeter x 1 um): that allowance keeps small sections honest without hiding errors.
constexpr double kAreaRelative = 0.005;
constexpr double kGridMm = 0.001;

double perimeter_mm(const Paths2& paths) {
    double sum = 0.0;
    for (const Path2& p : paths) sum += geom2d::perimeter_mm(p);
    return sum;
}

double area_tolerance(double expected, double perimeter) {
    return kAreaRelative * std::abs(expected) + kGridMm * perimeter;
}

std::size_t distinct_points(const Path2& p) {
    return std::set<Point2>(p.begin(), p.end()).size();
}

// The loop's corners: its points without repeats and without points lying on the straight
// line between their neighbours.
std::set<Point2> corners_of(Path2 p) {
    p.erase(std::unique(p.begin(), p.end()), p.end());
    while (p.size() > 1 && p.front() == p.back()) p.pop_back();
    std::set<Point2> out;
    const std::size_t n = p.size();
    for (std::size_t i = 0; i < n; ++i) {
        const Point2 a = p[(i + n - 1) % n], b = p[i], c = p[(i + 1) % n];
        // Exact in double for test coordinates (well below 2^26 um).
        const double cross = static_cast<double>(b.x - a.x) * static_cast<double>(c.y - a.y) -
                             static_cast<double>(b.y - a.y) * static_cast<double>(c.x - a.x);
        if (cross != 0) out.insert(b);
    }
    return out;
}

// Parents before children, links both ways, depth and hole flags alternate, outers
// counter-clockwise and holes clockwise. Returns the deepest level.
int check_tree(const WireTree& t) {
    int max_depth = 0;
    std::vector<int> roots;
    for (std::size_t i = 0; i < t.nodes.size(); ++i) {
        const geom2d::WireNode& n = t.nodes[i];
        SCOPED_TRACE("wire " + std::to_string(i));
        EXPECT_GE(n.wire.size(), 3u);
        const double area = geom2d::signed_area_um2(n.wire);
        if (n.is_hole) {
            EXPECT_LT(area, 0.0) << "holes run clockwise";
        } else {
            EXPECT_GT(area, 0.0) << "outer wires run counter-clockwise";
        }
        if (n.parent < 0) {
            EXPECT_EQ(n.depth, 0);
            roots.push_back(static_cast<int>(i));
        } else {
            EXPECT_LT(n.parent, static_cast<int>(i));
            const geom2d::WireNode& p = t.nodes[static_cast<std::size_t>(n.parent)];
            EXPECT_EQ(n.depth, p.depth + 1);
            EXPECT_NE(n.is_hole, p.is_hole);
            EXPECT_EQ(std::count(p.children.begin(), p.children.end(), static_cast<int>(i)), 1);
        }
        for (const int c : n.children) {
            if (c < 0 || c >= static_cast<int>(t.nodes.size())) {
                ADD_FAILURE() << "child index " << c << " out of range";
                continue;
            }
            EXPECT_EQ(t.nodes[static_cast<std::size_t>(c)].parent, static_cast<int>(i));
        }
        max_depth = std::max(max_depth, n.depth);
    }
    EXPECT_EQ(roots, t.roots);
    return max_depth;
}

bool near_vertex_height(const Fixture& f, double z) {
    return std::any_of(f.vertex_heights.begin(), f.vertex_heights.end(),
                       [z](double h) { return std::abs(h - z) < 1e-6; });
}

std::vector<Slice> slice_along(const mesh::TriangleMesh& m, const Vec3d& dir, double layer_mm,
                               PlaneFrame* base_out = nullptr) {
    const PlaneFrame base = base_frame(m, dir);
    const auto [lo, hi] = extent_along(m, base);
    const auto layers = uniform_layers(lo, hi, layer_mm);
    auto slices = slice_mesh(m, base, layers);
    EXPECT_TRUE(slices.has_value()) << (slices ? "" : slices.error().describe());
    if (base_out != nullptr) *base_out = base;
    return slices ? *slices : std::vector<Slice>{};
}

double volume_of(const std::vector<Slice>& slices) {
    double v = 0.0;
    for (const Slice& s : slices) v += s.area_mm2() * s.thickness();
    return v;
}

// An oblique unit direction, at least ~12 degrees away from every axis plane.
Vec3d oblique_direction(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> c(-1.0, 1.0);
    while (true) {
        const Vec3d d = core::normalized({c(rng), c(rng), c(rng)});
        if (std::abs(d.x) > 0.2 && std::abs(d.y) > 0.2 && std::abs(d.z) > 0.2) return d;
    }
}

void expect_same_slices(const std::vector<Slice>& a, const std::vector<Slice>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        SCOPED_TRACE("slice " + std::to_string(i));
        EXPECT_EQ(a[i].index, b[i].index);
        EXPECT_EQ(a[i].span.bottom, b[i].span.bottom);
        EXPECT_EQ(a[i].span.top, b[i].span.top);
        EXPECT_EQ(a[i].span.cut, b[i].span.cut);
        EXPECT_EQ(a[i].plane.origin, b[i].plane.origin);
        EXPECT_EQ(a[i].plane.normal, b[i].plane.normal);
        EXPECT_EQ(a[i].gaps_closed, b[i].gaps_closed);
        EXPECT_EQ(a[i].wires.roots, b[i].wires.roots);
        ASSERT_EQ(a[i].wires.nodes.size(), b[i].wires.nodes.size());
        for (std::size_t k = 0; k < a[i].wires.nodes.size(); ++k) {
            const auto& x = a[i].wires.nodes[k];
            const auto& y = b[i].wires.nodes[k];
            EXPECT_EQ(x.wire, y.wire);
            EXPECT_EQ(x.parent, y.parent);
            EXPECT_EQ(x.children, y.children);
            EXPECT_EQ(x.is_hole, y.is_hole);
            EXPECT_EQ(x.depth, y.depth);
        }
    }
}

// ---- Properties over every fixture -------------------------------------------------------

class SliceFixture : public ::testing::TestWithParam<std::size_t> {
protected:
    Fixture fixture() const { return test::all_fixtures()[GetParam()]; }
};

TEST_P(SliceFixture, UniformSlicesMatchAnalyticAreasAndTopology) {
    const Fixture f = fixture();
    PlaneFrame base;
    const double extent = f.vertex_heights.back() - f.vertex_heights.front();
    const auto slices = slice_along(f.mesh, {0, 0, 1}, extent / 47.0, &base);
    ASSERT_EQ(slices.size(), 47u);
    int checked = 0;
    for (std::size_t i = 0; i < slices.size(); ++i) {
        const Slice& s = slices[i];
        const double z = base.origin.z + s.span.cut;
        SCOPED_TRACE(f.name + " slice " + std::to_string(i) + " z " + std::to_string(z));
        EXPECT_EQ(s.index, static_cast<int>(i));
        EXPECT_EQ(s.plane.normal, base.normal);
        EXPECT_NEAR(base.height(s.plane.origin), s.span.cut, 1e-9);
        EXPECT_EQ(s.gaps_closed, 0);
        const int depth = check_tree(s.wires);
        if (near_vertex_height(f, z)) continue;
        ++checked;
        const double expected = f.area_at(z);
        EXPECT_NEAR(s.area_mm2(), expected,
                    area_tolerance(expected, perimeter_mm(s.wires.paths())));
        const test::SectionShape shape = f.shape_at(z);
        EXPECT_EQ(static_cast<int>(s.wires.outer_count()), shape.outers);
        EXPECT_EQ(static_cast<int>(s.wires.hole_count()), shape.holes);
        EXPECT_EQ(depth, shape.max_depth);
    }
    EXPECT_GT(checked, 40);
}

TEST_P(SliceFixture, UniformLayersIntegrateToTheVolume) {
    const Fixture f = fixture();
    const double extent = f.vertex_heights.back() - f.vertex_heights.front();
    const auto slices = slice_along(f.mesh, {0, 0, 1}, extent / 400.0);
    EXPECT_NEAR(volume_of(slices), f.volume_mm3, kAreaRelative * f.volume_mm3);
}

TEST_P(SliceFixture, AdaptiveLayersIntegrateToTheVolume) {
    const Fixture f = fixture();
    const LayerSettings s{.layer_mm = 0.1,
                          .adaptive = true,
                          .cusp_mm = 0.02,
                          .min_layer_mm = 0.02,
                          .max_layer_mm = 0.5};
    ASSERT_TRUE(validate(s).has_value());
    const PlaneFrame base = base_frame(f.mesh, {0, 0, 1});
    const auto [lo, hi] = extent_along(f.mesh, base);
    const auto layers = adaptive_layers(f.mesh, base, lo, hi, s);
    ASSERT_FALSE(layers.empty());
    EXPECT_EQ(layers.front().bottom, lo);
    EXPECT_EQ(layers.back().top, hi);
    const auto slices = slice_mesh(f.mesh, base, layers);
    ASSERT_TRUE(slices.has_value());
    EXPECT_NEAR(volume_of(*slices), f.volume_mm3, kAreaRelative * f.volume_mm3);
}

TEST_P(SliceFixture, ObliqueDirectionIntegratesToTheVolume) {
    const Fixture f = fixture();
    const Vec3d d = oblique_direction(1000 + GetParam());
    const PlaneFrame base = base_frame(f.mesh, d);
    const auto [lo, hi] = extent_along(f.mesh, base);
    EXPECT_NEAR(lo, 0.0, 1e-9) << "the base frame starts at the lowest point";
    const auto slices = slice_along(f.mesh, d, (hi - lo) / 200.0);
    EXPECT_NEAR(volume_of(slices), f.volume_mm3, kAreaRelative * f.volume_mm3);
    for (const Slice& s : slices) check_tree(s.wires);
}

TEST_P(SliceFixture, CutsThroughVertexLevelsGiveExactlyTheSectionAbove) {
    // Planes through vertices, edges and horizontal faces: every loop is a real contour
    // (no empty or doubled loops, none missing) with the orientation of its role.
    const Fixture f = fixture();
    const PlaneFrame base = PlaneFrame::from_normal({0, 0, 0}, {0, 0, 1});
    const auto cuts = cut_mesh(f.mesh, base, f.vertex_heights);
    ASSERT_TRUE(cuts.has_value());
    ASSERT_EQ(cuts->size(), f.vertex_heights.size());
    for (std::size_t i = 0; i < cuts->size(); ++i) {
        const double z = f.vertex_heights[i];
        const PlaneCut& cut = (*cuts)[i];
        SCOPED_TRACE(f.name + " z " + std::to_string(z));
        EXPECT_EQ(cut.open_chains, 0);
        EXPECT_EQ(cut.gaps_closed, 0);
        const double expected = f.area_at(z);
        const test::SectionShape shape = f.shape_at(z);
        int ccw = 0, cw = 0;
        for (const Path2& loop : cut.loops) {
            EXPECT_GE(distinct_points(loop), 3u);
            const double a = core::um2_to_mm2(geom2d::signed_area_um2(loop));
            EXPECT_GT(std::abs(a), core::kSliceMinLoopAreaMm2);
            (a > 0 ? ccw : cw) += 1;
        }
        EXPECT_EQ(ccw, shape.outers);
        EXPECT_EQ(cw, shape.holes);
        EXPECT_NEAR(geom2d::signed_area_mm2(cut.loops), expected,
                    area_tolerance(expected, perimeter_mm(cut.loops)));
    }
}

TEST_P(SliceFixture, OppositeDirectionsGiveMirroredEqualRegions) {
    const Fixture f = fixture();
    for (const Vec3d& d : {Vec3d{0, 0, 1}, oblique_direction(2000 + GetParam())}) {
        const PlaneFrame up = base_frame(f.mesh, d);
        const PlaneFrame down = base_frame(f.mesh, -d);
        EXPECT_LE(core::norm(down.u - up.u), 1e-12);
        EXPECT_LE(core::norm(down.v + up.v), 1e-12);
        const auto [lo, hi] = extent_along(f.mesh, up);
        std::vector<double> vertex_levels;
        for (const Vec3d& p : f.mesh.vertices) vertex_levels.push_back(up.height(p));
        for (const double share : {0.137, 0.421, 0.733}) {
            const double h_up = lo + share * (hi - lo);
            if (std::any_of(vertex_levels.begin(), vertex_levels.end(),
                            [h_up](double h) { return std::abs(h - h_up) < 1e-6; })) {
                continue;  // at a vertex level "just above" differs between the two directions
            }
            const double h_down = down.height(up.origin + up.normal * h_up);
            const LayerSpan span_up{h_up - 0.01, h_up + 0.01, h_up};
            const LayerSpan span_down{h_down - 0.01, h_down + 0.01, h_down};
            const auto a = slice_mesh(f.mesh, up, std::span(&span_up, 1));
            const auto b = slice_mesh(f.mesh, down, std::span(&span_down, 1));
            ASSERT_TRUE(a && b);
            const Slice& sa = a->front();
            const Slice& sb = b->front();
            SCOPED_TRACE(f.name + " share " + std::to_string(share));
            const double perimeter = perimeter_mm(sa.wires.paths());
            EXPECT_GT(sa.area_mm2(), 0.0);
            EXPECT_NEAR(sa.area_mm2(), sb.area_mm2(), 2.0 * kGridMm * perimeter);
            EXPECT_EQ(sa.wires.outer_count(), sb.wires.outer_count());
            EXPECT_EQ(sa.wires.hole_count(), sb.wires.hole_count());
            // The second slice's wires, carried into the first frame, are the same region
            // traversed the other way round.
            Paths2 carried;
            for (const Path2& w : sb.wires.paths()) {
                Path2 p;
                for (const Point2& q : w) p.push_back(sa.plane.to_2d(sb.plane.to_3d(q)));
                std::reverse(p.begin(), p.end());
                carried.push_back(std::move(p));
            }
            const Paths2 mine = sa.wires.paths();
            const double xor_area =
                std::abs(geom2d::signed_area_mm2(geom2d::difference_of(mine, carried))) +
                std::abs(geom2d::signed_area_mm2(geom2d::difference_of(carried, mine)));
            EXPECT_LE(xor_area, 2.0 * kGridMm * perimeter);
        }
    }
}

TEST_P(SliceFixture, SameResultWithOneAndTwoThreads) {
    const Fixture f = fixture();
    const Vec3d d = oblique_direction(3000 + GetParam());
    auto run = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  static_cast<std::size_t>(threads));
        return slice_along(f.mesh, d, 0.02);
    };
    const auto one = run(1);
    const auto two = run(2);
    ASSERT_FALSE(one.empty());
    expect_same_slices(one, two);
}

// The wire trees take a fast path when a cut's loops already bound a region; they must be
// exactly the trees of the Clipper union of the raw loops, for closed and open meshes, at
// vertex levels and between them.
TEST_P(SliceFixture, WireTreesAreTheClipperUnionOfTheCut) {
    const Fixture f = fixture();
    mesh::TriangleMesh opened = f.mesh;
    opened.triangles.erase(opened.triangles.begin() +
                           static_cast<std::ptrdiff_t>(opened.triangles.size() / 2));
    std::size_t layers = 0, fast = 0;
    const mesh::TriangleMesh& open = opened;
    for (const mesh::TriangleMesh* m : {&f.mesh, &open}) {
        for (const Vec3d& d : {Vec3d{0, 0, 1}, oblique_direction(4000 + GetParam())}) {
            const PlaneFrame base = base_frame(*m, d);
            const auto [lo, hi] = extent_along(*m, base);
            std::vector<LayerSpan> spans = uniform_layers(lo, hi, (hi - lo) / 97.0);
            for (const double z : f.vertex_heights) spans.push_back({z - 0.01, z + 0.01, z});
            const auto slices = slice_mesh(*m, base, spans);
            std::vector<double> heights;
            for (const LayerSpan& s : spans) heights.push_back(s.cut);
            const auto cuts = cut_mesh(*m, base, heights);
            ASSERT_TRUE(slices && cuts);
            for (std::size_t i = 0; i < heights.size(); ++i) {
                SCOPED_TRACE(i);
                const Paths2& loops = (*cuts)[i].loops;
                const WireTree clipper =
                    geom2d::detail::clipper_wire_tree(loops, geom2d::FillRule::kPositive);
                const WireTree& mine = (*slices)[i].wires;
                EXPECT_EQ(mine.roots, clipper.roots);
                ASSERT_EQ(mine.nodes.size(), clipper.nodes.size());
                for (std::size_t k = 0; k < mine.nodes.size(); ++k) {
                    EXPECT_EQ(mine.nodes[k].wire, clipper.nodes[k].wire);
                    EXPECT_EQ(mine.nodes[k].parent, clipper.nodes[k].parent);
                    EXPECT_EQ(mine.nodes[k].children, clipper.nodes[k].children);
                    EXPECT_EQ(mine.nodes[k].is_hole, clipper.nodes[k].is_hole);
                    EXPECT_EQ(mine.nodes[k].depth, clipper.nodes[k].depth);
                }
                ++layers;
                fast += geom2d::detail::wire_tree_of_simple_loops(loops).has_value() ? 1 : 0;
            }
        }
    }
    EXPECT_GT(fast, layers / 2);  // the fast path is taken, so the comparison means something
}

INSTANTIATE_TEST_SUITE_P(All, SliceFixture,
                         ::testing::Range<std::size_t>(0, test::all_fixtures().size()),
                         [](const auto& info) { return test::all_fixtures()[info.param].name; });

// ---- Specific cases ----------------------------------------------------------------------

const PlaneFrame kXY = PlaneFrame::from_normal({0, 0, 0}, {0, 0, 1});

TEST(CutMesh, CubeAtItsFacesGivesTheSquareBelowTheTopNothing) {
    const double heights[] = {0.0, 1.0, 0.5};
    const auto cuts = cut_mesh(test::unit_cube(), kXY, heights);
    ASSERT_TRUE(cuts.has_value());
    ASSERT_EQ(cuts->size(), 3u);
    const std::set<Point2> corners{{0, 0}, {1000, 0}, {1000, 1000}, {0, 1000}};
    for (const std::size_t i : {std::size_t{0}, std::size_t{2}}) {
        SCOPED_TRACE(heights[i]);
        const PlaneCut& cut = (*cuts)[i];
        ASSERT_EQ(cut.loops.size(), 1u);
        const Path2& loop = cut.loops.front();
        if (i == 0) {
            // Just above the bottom face: exactly its four corners once repeats are dropped.
            EXPECT_EQ(std::set<Point2>(loop.begin(), loop.end()), corners);
        } else {
            // Mid-height: the side walls' diagonals add points along the sides.
            EXPECT_EQ(corners_of(loop), corners);
        }
        EXPECT_EQ(geom2d::signed_area_um2(loop), 1e6);
        EXPECT_EQ(cut.open_chains, 0);
        EXPECT_EQ(cut.gaps_closed, 0);
    }
    EXPECT_TRUE((*cuts)[1].loops.empty());
}

TEST(CutMesh, PlaneThroughAMidRingOfVertices) {
    const double heights[] = {0.5};
    const auto cuts = cut_mesh(test::unit_cube_with_mid_ring(), kXY, heights);
    ASSERT_TRUE(cuts.has_value());
    ASSERT_EQ(cuts->front().loops.size(), 1u);
    const Path2& loop = cuts->front().loops.front();
    EXPECT_EQ(std::set<Point2>(loop.begin(), loop.end()),
              (std::set<Point2>{{0, 0}, {1000, 0}, {1000, 1000}, {0, 1000}}));
    EXPECT_EQ(geom2d::signed_area_um2(loop), 1e6);
}

TEST(CutMesh, NestedBoxesAtTheirShellFaces) {
    // Raw loops, before any union: outer +400, cavity -196, island +64 (mm^2).
    const test::NestedSpec s{};
    const double a = s.wall, b = s.wall + s.gap;
    const std::vector<double> heights{0.0, a, b, s.size - b, s.size - a, s.size};
    const std::vector<std::vector<double>> expected{{400},       {-196, 400}, {-196, 64, 400},
                                                    {-196, 400}, {400},       {}};
    const auto cuts = cut_mesh(test::nested_boxes(s), kXY, heights);
    ASSERT_TRUE(cuts.has_value());
    for (std::size_t i = 0; i < heights.size(); ++i) {
        std::vector<double> areas;
        for (const Path2& loop : (*cuts)[i].loops) {
            areas.push_back(core::um2_to_mm2(geom2d::signed_area_um2(loop)));
        }
        std::sort(areas.begin(), areas.end());
        ASSERT_EQ(areas.size(), expected[i].size()) << "z " << heights[i];
        for (std::size_t k = 0; k < areas.size(); ++k) {
            EXPECT_NEAR(areas[k], expected[i][k], 1e-9) << "z " << heights[i];
        }
    }
}

TEST(CutMesh, ResultsFollowTheOrderOfTheHeights) {
    const test::TSpec t{};
    const std::vector<double> heights{12.0, 3.0, t.stem_height, 50.0, -1.0, 7.5};
    const auto cuts = cut_mesh(test::t_shape(t), kXY, heights);
    ASSERT_TRUE(cuts.has_value());
    ASSERT_EQ(cuts->size(), heights.size());
    for (std::size_t i = 0; i < heights.size(); ++i) {
        EXPECT_NEAR(geom2d::signed_area_mm2((*cuts)[i].loops), test::t_shape_area_at(t, heights[i]),
                    1e-6)
            << heights[i];
    }
}

TEST(CutMesh, RepeatedHeightsGiveRepeatedCuts) {
    const std::vector<double> heights{1.0, 0.25, 1.0, 0.25};
    const auto cuts = cut_mesh(test::tube(10.0, 3.0, 2.0, 32), kXY, heights);
    ASSERT_TRUE(cuts.has_value());
    ASSERT_EQ(cuts->size(), 4u);
    EXPECT_EQ((*cuts)[0].loops, (*cuts)[2].loops);
    EXPECT_EQ((*cuts)[1].loops, (*cuts)[3].loops);
    EXPECT_EQ((*cuts)[0].loops.size(), 2u);
}

TEST(CutMesh, EmptyInputs) {
    const auto none = cut_mesh(test::unit_cube(), kXY, std::span<const double>{});
    ASSERT_TRUE(none.has_value());
    EXPECT_TRUE(none->empty());
    const double heights[] = {0.5};
    const auto empty_mesh = cut_mesh(mesh::TriangleMesh{}, kXY, heights);
    ASSERT_TRUE(empty_mesh.has_value());
    ASSERT_EQ(empty_mesh->size(), 1u);
    EXPECT_TRUE(empty_mesh->front().loops.empty());
}

TEST(CutMesh, SmallGapInAnOpenMeshIsClosedAndCounted) {
    mesh::TriangleMesh m = test::unit_cube();
    m.triangles.erase(m.triangles.begin() + 4);  // one triangle of a side wall
    const double heights[] = {0.5};
    const auto cuts = cut_mesh(m, kXY, heights);
    ASSERT_TRUE(cuts.has_value());
    const PlaneCut& cut = cuts->front();
    ASSERT_EQ(cut.loops.size(), 1u);
    EXPECT_NEAR(core::um2_to_mm2(geom2d::signed_area_um2(cut.loops.front())), 1.0, 1e-6);
    EXPECT_EQ(cut.gaps_closed, 1);
}

TEST(CutMesh, WideGapLeavesAnOpenChainThatIsCountedNotFilled) {
    mesh::TriangleMesh m = test::box({0, 0, 0}, {10, 10, 10});
    m.triangles.erase(m.triangles.begin() + 4, m.triangles.begin() + 6);  // a whole side wall
    const double heights[] = {5.0};
    const auto cuts = cut_mesh(m, kXY, heights);
    ASSERT_TRUE(cuts.has_value());
    EXPECT_TRUE(cuts->front().loops.empty());
    EXPECT_EQ(cuts->front().open_chains, 1);
    EXPECT_EQ(cuts->front().gaps_closed, 0);
}

TEST(CutMesh, NonFiniteVertexIsAnError) {
    mesh::TriangleMesh m = test::unit_cube();
    m.vertices[3].y = std::nan("");
    const double heights[] = {0.5};
    const auto cuts = cut_mesh(m, kXY, heights);
    ASSERT_FALSE(cuts.has_value());
    EXPECT_EQ(cuts.error().code, core::ErrorCode::kInvalidInput);
}

TEST(CutMesh, SameLoopsWithOneAndTwoThreads) {
    const auto m = test::plate_with_holes();
    std::vector<double> heights;
    for (int i = 0; i < 500; ++i) heights.push_back(0.004 * i);
    const PlaneFrame base = PlaneFrame::from_normal({}, core::normalized({0.2, 0.1, 1.0}));
    auto run = [&](std::size_t threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        return cut_mesh(m, base, heights);
    };
    const auto one = run(1);
    const auto two = run(2);
    ASSERT_TRUE(one && two);
    ASSERT_EQ(one->size(), two->size());
    for (std::size_t i = 0; i < one->size(); ++i) EXPECT_EQ((*one)[i].loops, (*two)[i].loops) << i;
}

TEST(SliceMesh, NestedBoxesTreeHasAnIslandInAHole) {
    const LayerSpan span{9.5, 10.5, 10.0};
    const auto slices = slice_mesh(test::nested_boxes(), kXY, std::span(&span, 1));
    ASSERT_TRUE(slices.has_value());
    const WireTree& t = slices->front().wires;
    check_tree(t);
    ASSERT_EQ(t.nodes.size(), 3u);
    ASSERT_EQ(t.roots.size(), 1u);
    const auto& outer = t.nodes[static_cast<std::size_t>(t.roots[0])];
    EXPECT_FALSE(outer.is_hole);
    ASSERT_EQ(outer.children.size(), 1u);
    const auto& hole = t.nodes[static_cast<std::size_t>(outer.children[0])];
    EXPECT_TRUE(hole.is_hole);
    ASSERT_EQ(hole.children.size(), 1u);
    const auto& island = t.nodes[static_cast<std::size_t>(hole.children[0])];
    EXPECT_FALSE(island.is_hole);
    EXPECT_EQ(island.depth, 2);
    EXPECT_NEAR(core::um2_to_mm2(geom2d::signed_area_um2(island.wire)), 64.0, 1e-9);
}

TEST(SliceMesh, LayersKeepTheirGivenOrder) {
    const test::TSpec t{};
    const std::vector<LayerSpan> layers{{12.0, 12.5, 12.25}, {1.0, 1.5, 1.25}, {6.0, 6.5, 6.25}};
    const auto slices = slice_mesh(test::t_shape(t), kXY, layers);
    ASSERT_TRUE(slices.has_value());
    ASSERT_EQ(slices->size(), layers.size());
    for (std::size_t i = 0; i < layers.size(); ++i) {
        EXPECT_EQ((*slices)[i].index, static_cast<int>(i));
        EXPECT_EQ((*slices)[i].span.cut, layers[i].cut);
        EXPECT_NEAR((*slices)[i].area_mm2(), test::t_shape_area_at(t, layers[i].cut), 1e-6);
    }
}

TEST(SliceMesh, PartFarFromTheOrigin) {
    // 100 m away: 2D coordinates stay in range and areas exact to the micrometre grid.
    const auto m = test::translated(test::plate_with_holes(), {1e5, -1e5, 3e4});
    const test::PlateSpec spec{};
    const auto flat = slice_along(m, {0, 0, 1}, 0.25);
    ASSERT_EQ(flat.size(), 8u);
    for (const Slice& s : flat) {
        EXPECT_EQ(static_cast<int>(s.wires.hole_count()), spec.n_holes);
        EXPECT_NEAR(s.area_mm2(), test::plate_area_at(spec, 1.0),
                    area_tolerance(test::plate_area_at(spec, 1.0), perimeter_mm(s.wires.paths())));
    }
    const auto tilted = slice_along(m, core::normalized({0.0, 0.1, 1.0}), 0.01);
    EXPECT_NEAR(volume_of(tilted), test::plate_volume(spec),
                kAreaRelative * test::plate_volume(spec));
}

TEST(SliceMesh, PartBeyondTwoKilometresIsRefusedWithTheUnitsHint) {
    // The slicer keeps its crossing points in 32 bits of micrometres: about 2.1 km.
    for (const double x : {3e6, -2.2e6}) {
        const auto m = test::translated(test::unit_cube(), {x, 0, 0});
        const FrameExtent fe = base_frame_and_extent(m, {0, 0, 1});
        const auto layers = uniform_layers(fe.lo, fe.hi, 0.25);
        const auto slices = slice_mesh(m, fe, layers);
        ASSERT_FALSE(slices.has_value()) << x;
        EXPECT_EQ(slices.error().code, core::ErrorCode::kInvalidInput);
        EXPECT_NE(slices.error().message.find("2 km"), std::string::npos);
        EXPECT_NE(slices.error().message.find("--units"), std::string::npos);
    }
    // Just inside the limit it slices (Clipper then builds the trees: the fast path stops at
    // geom2d's 1 km).
    const auto near = test::translated(test::unit_cube(), {2.1e6, 0, 0});
    const auto slices = slice_along(near, {0, 0, 1}, 0.25);
    ASSERT_EQ(slices.size(), 4u);
    for (const Slice& s : slices) EXPECT_NEAR(s.area_mm2(), 1.0, 1e-6);
}

TEST(SliceMesh, OverlappingBodiesMerge) {
    // Two boxes overlapping in [1, 2] x [0, 1]: one outer of area 3 x 1 - 0 overlap counted
    // once.
    const auto m = test::merged(test::box({0, 0, 0}, {2, 1, 1}), test::box({1, 0, 0}, {3, 1, 1}));
    const LayerSpan span{0.4, 0.6, 0.5};
    const auto slices = slice_mesh(m, kXY, std::span(&span, 1));
    ASSERT_TRUE(slices.has_value());
    EXPECT_EQ(slices->front().wires.outer_count(), 1u);
    EXPECT_NEAR(slices->front().area_mm2(), 3.0, 1e-9);
}

TEST(SliceMesh, CancelledProgressStopsWithAnError) {
    core::Progress progress;
    progress.cancel();
    const auto layers = uniform_layers(0.0, 20.0, 0.5);
    const auto slices = slice_mesh(test::cylinder(10.0, 20.0), kXY, layers, &progress);
    ASSERT_FALSE(slices.has_value());
    EXPECT_EQ(slices.error().code, core::ErrorCode::kCancelled);
}

TEST(SliceMesh, ProgressReachesTheEnd) {
    std::atomic<int> calls{0};
    std::atomic<bool> in_range{true};
    std::atomic<long> best{0};
    const core::Progress progress([&](std::string_view, double fraction) {
        ++calls;
        if (!(fraction >= 0.0 && fraction <= 1.0)) in_range = false;
        long f = std::lround(fraction * 1e6);
        long cur = best.load();
        while (f > cur && !best.compare_exchange_weak(cur, f)) {
        }
    });
    const auto layers = uniform_layers(0.0, 20.0, 0.5);
    ASSERT_TRUE(slice_mesh(test::cylinder(10.0, 20.0), kXY, layers, &progress).has_value());
    EXPECT_GT(calls.load(), 0);
    EXPECT_TRUE(in_range.load());
    EXPECT_EQ(best.load(), 1'000'000);
}

TEST(BaseFrame, StartsAtTheLowestPointAlongTheDirection) {
    const auto m = test::translated(test::unit_cube(), {2, 3, 4});
    const PlaneFrame up = base_frame(m, {0, 0, 1});
    EXPECT_NEAR(up.origin.z, 4.0, 1e-12);
    const auto [lo, hi] = extent_along(m, up);
    EXPECT_NEAR(lo, 0.0, 1e-12);
    EXPECT_NEAR(hi, 1.0, 1e-12);
    const Vec3d diag = core::normalized({1, 1, 1});
    const PlaneFrame f = base_frame(m, diag);
    EXPECT_LE(core::norm(f.normal - diag), 1e-12);
    const auto [dlo, dhi] = extent_along(m, f);
    EXPECT_NEAR(dlo, 0.0, 1e-12);
    EXPECT_NEAR(dhi, std::sqrt(3.0), 1e-12);
    EXPECT_NEAR(f.height({2, 3, 4}), 0.0, 1e-12);
}

TEST(BaseFrameAndExtent, KeepsTheFrameHeightsAndSlicingWithThemChangesNothing) {
    const auto m = test::translated(test::plate_with_holes(), {12.5, -3.25, 7.0});
    for (const Vec3d& dir : {Vec3d{0, 0, 1}, core::normalized({1.0, 0.3, 0.8})}) {
        const FrameExtent fe = base_frame_and_extent(m, dir);
        const PlaneFrame base = base_frame(m, dir);
        EXPECT_EQ(fe.frame.origin, base.origin);
        EXPECT_EQ(fe.frame.normal, base.normal);
        EXPECT_EQ(std::make_pair(fe.lo, fe.hi), extent_along(m, base));
        ASSERT_EQ(fe.vertices, m.vertices.size());
        for (std::size_t i = 0; i < m.vertices.size(); ++i) {
            ASSERT_EQ(fe.heights[i], fe.frame.height(m.vertices[i])) << i;
        }
        const auto layers = uniform_layers(fe.lo, fe.hi, 0.3);
        const auto with = slice_mesh(m, fe, layers);
        const auto without = slice_mesh(m, fe.frame, layers);
        ASSERT_TRUE(with.has_value() && without.has_value());
        ASSERT_EQ(with->size(), without->size());
        for (std::size_t k = 0; k < with->size(); ++k) {
            EXPECT_EQ((*with)[k].wires.paths(), (*without)[k].wires.paths()) << k;
        }
    }
}

TEST(BaseFrameAndExtent, UnusedVerticesDoNotCountUnlessAllArePromisedUsed) {
    auto m = test::translated(test::unit_cube(), {2, 3, 4});
    const FrameExtent promised = base_frame_and_extent(m, {0, 0, 1}, VertexUse::kAllUsed);
    const FrameExtent checked = base_frame_and_extent(m, {0, 0, 1}, VertexUse::kCheck);
    EXPECT_EQ(promised.frame.origin, checked.frame.origin);
    EXPECT_EQ(std::make_pair(promised.lo, promised.hi), std::make_pair(checked.lo, checked.hi));
    // A vertex no triangle uses, far below and far above: not part of the solid.
    m.vertices.push_back({2, 3, -100});
    m.vertices.push_back({2, 3, 100});
    const FrameExtent fe = base_frame_and_extent(m, {0, 0, 1});
    EXPECT_NEAR(fe.frame.origin.z, 4.0, 1e-12);
    EXPECT_NEAR(fe.lo, 0.0, 1e-12);
    EXPECT_NEAR(fe.hi, 1.0, 1e-12);
    ASSERT_EQ(fe.vertices, m.vertices.size());
    EXPECT_NEAR(fe.heights[m.vertices.size() - 2], -104.0, 1e-12);
}

}  // namespace
}  // namespace maxslice::slice
