// The finished part's figures (decision 0026): the share of the finished part inside the
// beads and the smallest machining stock, measured beside coverage and excess of the model
// the program deposits (a near-net shape). Programs written by hand: the zigzag block of
// verify_programs.hpp, 30 x 30 x 6 mm, checked against finished blocks inside it and
// reaching out of it.
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <numbers>
#include <string>
#include <vector>

#include "maxslice/verify/verify.hpp"
#include "support/fixtures.hpp"
#include "verify_programs.hpp"

namespace maxslice::verify {
namespace {

using core::Vec3d;
using testing::kHalf;
using testing::kLayers;
using testing::load;
using testing::ProgramText;
using testing::zigzag_block;

constexpr double kVoxelMm = 0.25;
constexpr double kLayerMm = 0.5;
constexpr double kTopMm = kLayers * kLayerMm;  // the block's beads reach from 0 to here

// The deposited model in its file frame: the 30 x 30 x 6 mm block the program builds.
mesh::TriangleMesh block_file() {
    return test::box({0, 0, 0}, {2 * kHalf, 2 * kHalf, kTopMm});
}

// A finished block inside the deposited one by `side` on its four sides, `bottom` above its
// bottom and `top` below its top (negative: reaching out), placed as the block is.
mesh::TriangleMesh finished_block(const machine::Profiles& p, double side, double bottom,
                                  double top) {
    auto r = place_like(
        test::box({side, side, bottom}, {2 * kHalf - side, 2 * kHalf - side, kTopMm - top}),
        block_file(), {0, 0, 1}, p.machine);
    EXPECT_TRUE(r.has_value());
    return r.value_or(mesh::TriangleMesh{});
}

struct Job {
    machine::Profiles p;
    std::string text;
    mesh::TriangleMesh model;
};

Job block_job() {
    Job j{load("reference_lmd.toml"), {}, {}};
    j.model = testing::placed(j.p, block_file());
    ProgramText prog(j.p, ProgramDialect::kGm, false);
    const Vec3d c = mesh::bounding_box(j.model).center();
    zigzag_block(prog, j.p, c.x, c.y, kHalf, kLayers);
    j.text = prog.text();
    return j;
}

Report verified(const Job& j, const mesh::TriangleMesh* finished) {
    VerifySettings s;
    s.voxel_mm = kVoxelMm;
    auto r = verify_program(j.text, j.model, j.p, s, finished);
    EXPECT_TRUE(r.has_value()) << r.error().describe();
    return r.value_or(Report{});
}

TEST(FinishedPart, PlaceLikeMovesThePartWithItsNearNetShape) {
    const machine::Profiles p = load("reference_5axis_ac.toml");
    const mesh::TriangleMesh inner = test::box({2, 3, 1}, {20, 25, 8});
    const mesh::TriangleMesh outer = test::box({0, 0, 0}, {24, 30, 10});
    for (const Vec3d d : {Vec3d{0, 0, 1}, Vec3d{1, 0, 0}, Vec3d{0.3, -0.5, 0.8}}) {
        auto a = place_model(outer, d, p.machine);
        auto b = place_like(inner, outer, d, p.machine);
        ASSERT_TRUE(a && b);
        EXPECT_EQ(b->triangles, inner.triangles);
        EXPECT_NEAR(mesh::signed_volume(*b), mesh::signed_volume(inner), 1e-9);
        // The same rigid motion: every distance between a vertex of one and of the other is
        // kept (the inner box stays 1 mm above the outer's bottom, 2 mm below its top ...).
        for (std::size_t u = 0; u < inner.vertices.size(); ++u) {
            for (std::size_t k = 0; k < outer.vertices.size(); ++k) {
                EXPECT_NEAR(core::norm(b->vertices[u] - a->vertices[k]),
                            core::norm(inner.vertices[u] - outer.vertices[k]), 1e-9);
            }
        }
    }
    EXPECT_FALSE(place_like(mesh::TriangleMesh{}, outer, {0, 0, 1}, p.machine));
}

// A finished block wholly inside the deposited one: all of it inside beads, and the smallest
// stock the thinnest of the sides, bottom and top within a voxel, found on that face.
TEST(FinishedPart, AFinishedBlockInsideTheBeadsHasTheStockBetween) {
    const Job j = block_job();
    const Report without = verified(j, nullptr);
    struct Case {
        double side, bottom, top;
    };
    for (const Case c :
         {Case{3.0, 2.0, 1.0}, Case{1.4, 2.5, 2.5}, Case{2.0, 0.6, 2.0}, Case{1.6, 1.9, 1.3}}) {
        SCOPED_TRACE(fmt::format("side {}, bottom {}, top {}", c.side, c.bottom, c.top));
        const mesh::TriangleMesh fin = finished_block(j.p, c.side, c.bottom, c.top);
        const Report r = verified(j, &fin);
        EXPECT_TRUE(r.finished_given);
        EXPECT_TRUE(r.finished_judged());
        EXPECT_DOUBLE_EQ(r.finished_inside, 1.0) << report_text(r);
        const double want = std::min({c.side, c.bottom, c.top});
        EXPECT_NEAR(r.smallest_stock_mm, want, r.voxel_mm + 1e-9) << report_text(r);
        EXPECT_GE(r.stock_limit_mm, 4.0);
        // Found within a voxel of a face of the finished block whose stock is within the
        // resolution (two voxels) of the thinnest.
        const core::Box3d box = mesh::bounding_box(fin);
        const Vec3d& at = r.smallest_stock_at_mm;
        const std::pair<double, double> faces[] = {
            {c.top, box.max.z - at.z},
            {c.bottom, at.z - box.min.z},
            {c.side,
             std::min({at.x - box.min.x, box.max.x - at.x, at.y - box.min.y, box.max.y - at.y})}};
        EXPECT_TRUE(std::ranges::any_of(faces, [&](const auto& f) {
            return f.first <= want + 2.0 * r.voxel_mm && f.second < r.voxel_mm;
        })) << report_text(r);
        EXPECT_GT(r.finished_volume_mm3, 0.0);
        EXPECT_NEAR(
            r.finished_volume_mm3,
            (2 * kHalf - 2 * c.side) * (2 * kHalf - 2 * c.side) * (kTopMm - c.top - c.bottom),
            0.05 * r.finished_volume_mm3);
        // Coverage and excess stay the model's: the same figures as without the finished part.
        EXPECT_EQ(r.coverage, without.coverage);
        EXPECT_EQ(r.excess, without.excess);
        EXPECT_EQ(r.model_volume_mm3, without.model_volume_mm3);
        EXPECT_TRUE(r.accepted()) << report_text(r);
        // The text report carries the summary's line.
        EXPECT_NE(report_text(r).find("finished part   " + finished_text(r)), std::string::npos);
    }
}

// A finished part reaching out of the beads: less than all of it inside, the stock below 0
// (minus how far it reaches out, within a voxel), and under 97 % inside the program does not
// build it. The finished block inside by 2 mm on its sides (the deposit's rounded vertical
// edges stay away), with a bump on its top reaching `out` above the beads over a square of
// `bump` mm, or its whole top reaching `out` above them (bump 0).
TEST(FinishedPart, AFinishedPartReachingOutOfTheBeadsHasNoStock) {
    const Job j = block_job();
    struct Case {
        double out, bump;
        bool builds;  // at least 97 % inside
    };
    for (const Case c : {Case{1.5, 0.0, false}, Case{0.8, 2.0, true}, Case{2.5, 8.0, false}}) {
        SCOPED_TRACE(fmt::format("out {}, bump {}", c.out, c.bump));
        constexpr double kSide = 2.0, kBottom = 1.0, kTop = 1.0;
        mesh::TriangleMesh file =
            c.bump > 0.0 ? test::box({kSide, kSide, kBottom},
                                     {2 * kHalf - kSide, 2 * kHalf - kSide, kTopMm - kTop})
                         : test::box({kSide, kSide, kBottom},
                                     {2 * kHalf - kSide, 2 * kHalf - kSide, kTopMm + c.out});
        double in_mm3 = (2 * kHalf - 2 * kSide) * (2 * kHalf - 2 * kSide) *
                        (c.bump > 0.0 ? kTopMm - kTop - kBottom : kTopMm - kBottom);
        double out_mm3 =
            c.bump > 0.0 ? 0.0 : (2 * kHalf - 2 * kSide) * (2 * kHalf - 2 * kSide) * c.out;
        if (c.bump > 0.0) {
            // A second body standing on the block's top face, apart from the first.
            mesh::append(file, test::box({10, 10, kTopMm - kTop + 0.5},
                                         {10 + c.bump, 10 + c.bump, kTopMm + c.out}));
            in_mm3 += c.bump * c.bump * (kTop - 0.5);
            out_mm3 = c.bump * c.bump * c.out;
        }
        auto fin = place_like(std::move(file), block_file(), {0, 0, 1}, j.p.machine);
        ASSERT_TRUE(fin.has_value());
        const Report r = verified(j, &*fin);
        EXPECT_LT(r.finished_inside, 1.0) << report_text(r);
        EXPECT_LT(r.smallest_stock_mm, 0.0) << report_text(r);
        EXPECT_NEAR(r.smallest_stock_mm, -c.out, r.voxel_mm + 1e-9) << report_text(r);
        // Where: a finished voxel above the beads.
        EXPECT_GT(r.smallest_stock_at_mm.z, kTopMm) << report_text(r);
        EXPECT_NEAR(r.finished_inside, in_mm3 / (in_mm3 + out_mm3), 0.01) << report_text(r);
        EXPECT_EQ(r.finished_low(), !c.builds) << report_text(r);
        EXPECT_EQ(r.matches_part(), c.builds) << report_text(r);
        const std::vector<std::string_view> failed = failed_checks(r);
        EXPECT_EQ(std::ranges::find(failed, "finished_inside") != failed.end(), !c.builds);
        EXPECT_TRUE(r.passed()) << report_text(r);  // safe: only the part is missed
    }
}

// Without a finished part, the model is the finished part: its share inside is the coverage.
TEST(FinishedPart, WithoutAFinishedPartTheModelIsTheFinishedPart) {
    const Job j = block_job();
    const Report r = verified(j, nullptr);
    EXPECT_FALSE(r.finished_given);
    EXPECT_EQ(r.finished_inside, r.coverage);
    EXPECT_EQ(r.finished_volume_mm3, r.model_volume_mm3);
    EXPECT_EQ(r.finished_low(), r.coverage_low());
    if (r.finished_inside < 1.0) {
        EXPECT_LE(r.smallest_stock_mm, 0.0);
    }
    // The model reaches out of the beads only at the deposit's rounded vertical edges (a wire's
    // round end, half a track in radius, in a square corner): (sqrt 2 - 1) w / 2.
    const double corner = (std::numbers::sqrt2 - 1.0) * 0.5 * j.p.process.track_width_mm;
    EXPECT_NEAR(r.smallest_stock_mm, -corner, r.voxel_mm + 1e-9) << report_text(r);
    EXPECT_NE(report_text(r).find("finished part   " + finished_text(r)), std::string::npos);
    // The model missing half its layers: under 97 % of it inside, and the failed check is
    // the coverage (no separate finished part to name).
    ProgramText half(j.p, ProgramDialect::kGm, false);
    const Vec3d c = mesh::bounding_box(j.model).center();
    zigzag_block(half, j.p, c.x, c.y, kHalf, kLayers / 2);
    const Report h = verified(Job{j.p, half.text(), j.model}, nullptr);
    EXPECT_NEAR(h.finished_inside, 0.5, 0.03);
    EXPECT_TRUE(h.finished_low());
    EXPECT_NEAR(h.smallest_stock_mm, -0.5 * kTopMm, h.voxel_mm + 1e-9) << report_text(h);
    const std::vector<std::string_view> failed = failed_checks(h);
    EXPECT_EQ(std::count(failed.begin(), failed.end(), "coverage"), 1);
    EXPECT_EQ(std::count(failed.begin(), failed.end(), "finished_inside"), 0);
}

TEST(FinishedPart, JsonCarriesTheFiguresAndTheBytesDoNotDependOnTheThreads) {
    const Job j = block_job();
    const mesh::TriangleMesh fin = finished_block(j.p, 1.5, 1.0, -0.5);
    const std::string many = report_json(verified(j, &fin));
    std::string one;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = report_json(verified(j, &fin));
    }
    EXPECT_EQ(many, one);
    const auto json = nlohmann::json::parse(many);
    const Report r = verified(j, &fin);
    EXPECT_EQ(json["finished_given"], true);
    EXPECT_NEAR(json["finished_inside"].get<double>(), r.finished_inside, 1e-6);
    EXPECT_NEAR(json["smallest_stock_mm"].get<double>(), r.smallest_stock_mm, 1e-4);
    EXPECT_LT(json["smallest_stock_mm"].get<double>(), 0.0);
    EXPECT_NEAR(json["finished_inside_target"].get<double>(), kFinishedInsideTarget, 1e-9);
    EXPECT_EQ(json["smallest_stock_at_mm"].size(), 3U);
}

}  // namespace
}  // namespace maxslice::verify
