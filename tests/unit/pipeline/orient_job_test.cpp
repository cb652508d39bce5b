// The program job's orientation search (docs/decisions/0015-orientation-fallback.md): the
// plan check that the job fills with its program and verifier, and the refusal of a part
// standing on a strip where no track fits.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "maxslice/machine/profile.hpp"
#include "maxslice/pipeline/orient_job.hpp"
#include "maxslice/pipeline/program_job.hpp"
#include "support/fixtures.hpp"
#include "support/planner_fixtures.hpp"

namespace maxslice::pipeline {
namespace {

machine::Profiles reference_profiles() {
    const std::array<std::filesystem::path, 1> files{std::filesystem::path(MAXSLICE_SOURCE_DIR) /
                                                     "examples/profiles/reference_5axis_ac.toml"};
    auto profiles = machine::load_profiles(files);
    EXPECT_TRUE(profiles.has_value()) << (profiles ? "" : profiles.error().describe());
    return profiles ? *profiles : machine::Profiles{};
}

// The top of the placed part along +Z (mm).
double top_z(const mesh::TriangleMesh& m) {
    double z = -1e300;
    for (const core::Vec3d& v : m.vertices) z = std::max(z, v.z);
    return z;
}

// A check that refuses plans whose placed part is as tall as `refused_height_mm` (within
// 1e-6 mm), and counts the calls.
struct RefuseByHeight {
    double refused_height_mm = 0.0;
    std::vector<double> heights;
    core::Result<std::string> operator()(const mesh::TriangleMesh& placed, const PlannedPart& p) {
        EXPECT_TRUE(p.order.has_value()) << "only ordered plans are checked";
        const double h = top_z(placed);
        heights.push_back(h);
        return std::abs(h - refused_height_mm) < 1e-6 ? std::string("refused by the test")
                                                      : std::string();
    }
};

// The L-bracket builds as given (along +Z). A check that refuses it sends the search on: the
// part is kept along another candidate, the given try carries the check's words, and the
// check was asked about the given plan first, then about the one kept.
TEST(OrientJob, APlanTheCheckRefusesIsNotKept) {
    const machine::Profiles profiles = reference_profiles();
    const mesh::TriangleMesh part = test::l_bracket().mesh;
    auto given = orient_multiaxis(part, {0, 0, 1}, OrientPolicy::kGiven, profiles);
    ASSERT_TRUE(given.has_value()) << given.error().describe();
    ASSERT_EQ(given->tries.size(), 1u);
    ASSERT_TRUE(given->tries[0].refusal.empty()) << given->tries[0].refusal;
    const double given_height = top_z(given->placed);

    RefuseByHeight check{given_height, {}};
    core::Vec3d last_direction;  // the one the check was last asked about
    auto o = orient_multiaxis(
        part, {0, 0, 1}, OrientPolicy::kFallback, profiles, nullptr,
        [&](const core::Vec3d& d, const mesh::TriangleMesh& m, const PlannedPart& p) {
            last_direction = d;
            return check(m, p);
        });
    ASSERT_TRUE(o.has_value()) << o.error().describe();
    ASSERT_GE(o->tries.size(), 2u);
    EXPECT_EQ(o->tries[0].source, "as given");
    EXPECT_EQ(o->tries[0].refusal, "refused by the test");
    ASSERT_GT(o->chosen, 0);
    EXPECT_TRUE(o->tries[static_cast<std::size_t>(o->chosen)].refusal.empty());
    EXPECT_GT(std::abs(top_z(o->placed) - given_height), 1e-6);
    EXPECT_LT(core::norm(last_direction - o->tries[static_cast<std::size_t>(o->chosen)].direction),
              1e-12)
        << "the check is told the direction of the plan it judges";
    ASSERT_GE(check.heights.size(), 2u);
    EXPECT_NEAR(check.heights.front(), given_height, 1e-6);
    EXPECT_NEAR(check.heights.back(), top_z(o->placed), 1e-6);
    // Nothing is checked after the plan kept.
    for (std::size_t i = 1; i + 1 < check.heights.size(); ++i) {
        EXPECT_NEAR(check.heights[i], given_height, 1e-6) << "a refused plan in between";
    }

    // --orient given: the answer is recorded, the given plan kept.
    RefuseByHeight again{given_height, {}};
    auto g = orient_multiaxis(part, {0, 0, 1}, OrientPolicy::kGiven, profiles, nullptr,
                              [&](const core::Vec3d&, const mesh::TriangleMesh& m,
                                  const PlannedPart& p) { return again(m, p); });
    ASSERT_TRUE(g.has_value());
    ASSERT_EQ(g->tries.size(), 1u);
    EXPECT_EQ(g->tries[0].refusal, "refused by the test");
    EXPECT_NEAR(top_z(g->placed), given_height, 1e-6);
    EXPECT_EQ(again.heights.size(), 1u);
}

// A block with a cube floating beside it, off the plate along every axis, the free body kept
// (process.leave_out_free_bodies = false): every base leaves layers on nothing. Such plans are
// refused as planned; none is ordered (the order of a plan that cannot be built is never used,
// and ordering is the slow part). With the default the cube is left out (decision 0036).
TEST(OrientJob, PlansWithLayersOnNothingAreRefusedWithoutAnOrder) {
    machine::Profiles profiles = reference_profiles();
    auto left_out = orient_multiaxis(
        test::merged(test::box({0, 0, 0}, {20, 20, 10}), test::box({30, 5, 5}, {40, 15, 15})),
        {0, 0, 1}, OrientPolicy::kGiven, profiles);
    ASSERT_TRUE(left_out.has_value()) << left_out.error().describe();
    EXPECT_EQ(left_out->planned.plan.free_bodies.size(), 1u);
    EXPECT_TRUE(left_out->planned.plan.unsupported_layers.empty());
    profiles.process.leave_out_free_bodies = false;
    const mesh::TriangleMesh part =
        test::merged(test::box({0, 0, 0}, {20, 20, 10}), test::box({30, 5, 5}, {40, 15, 15}));
    for (const OrientPolicy policy : {OrientPolicy::kFallback, OrientPolicy::kAuto}) {
        int checks = 0;
        auto o = orient_multiaxis(part, {0, 0, 1}, policy, profiles, nullptr,
                                  [&](const core::Vec3d&, const mesh::TriangleMesh&,
                                      const PlannedPart&) -> core::Result<std::string> {
                                      ++checks;
                                      return std::string();
                                  });
        ASSERT_TRUE(o.has_value()) << o.error().describe();
        EXPECT_FALSE(o->planned.plan.unsupported_layers.empty());
        EXPECT_FALSE(o->planned.order.has_value());
        EXPECT_EQ(checks, 0);
        ASSERT_GE(o->tries.size(), 6u);
        for (const OrientTry& t : o->tries) {
            EXPECT_NE(t.refusal.find("layers rest on nothing"), std::string::npos)
                << t.source << ": " << t.refusal;
        }
    }
}

// An error of the check (not a refusal of the base: a bug, a cancellation, a file) ends the
// search with that error.
TEST(OrientJob, AnErrorOfTheCheckEndsTheSearch) {
    const machine::Profiles profiles = reference_profiles();
    auto o = orient_multiaxis(
        test::l_bracket().mesh, {0, 0, 1}, OrientPolicy::kFallback, profiles, nullptr,
        [](const core::Vec3d&, const mesh::TriangleMesh&,
           const PlannedPart&) -> core::Result<std::string> {
            return core::fail(core::ErrorCode::kInternal, "test error", "check");
        });
    ASSERT_FALSE(o.has_value());
    EXPECT_EQ(o.error().message, "test error");
}

// A program the machine cannot run along a base (the check's kInvalidInput: a pose beyond the
// axis limits, a retract above the Z travel) refuses that base, and the search goes on; with
// --orient given it is the answer.
TEST(OrientJob, AProgramTheMachineCannotRunRefusesThatBaseOnly) {
    const machine::Profiles profiles = reference_profiles();
    const mesh::TriangleMesh part = test::l_bracket().mesh;
    auto given = orient_multiaxis(part, {0, 0, 1}, OrientPolicy::kGiven, profiles);
    ASSERT_TRUE(given.has_value()) << given.error().describe();
    const double given_height = top_z(given->placed);
    const auto check = [&](const core::Vec3d&, const mesh::TriangleMesh& m,
                           const PlannedPart&) -> core::Result<std::string> {
        if (std::abs(top_z(m) - given_height) < 1e-6) {
            return core::fail(core::ErrorCode::kInvalidInput,
                              "move 7 (layer 0, region 0): no pose reaches it: the A axis ends",
                              "machine");
        }
        return std::string();
    };
    auto o = orient_multiaxis(part, {0, 0, 1}, OrientPolicy::kFallback, profiles, nullptr, check);
    ASSERT_TRUE(o.has_value()) << o.error().describe();
    EXPECT_EQ(o->tries[0].refusal, "no program: move 7 (layer 0, region 0): no pose reaches it");
    ASSERT_GT(o->chosen, 0);
    EXPECT_TRUE(o->tries[static_cast<std::size_t>(o->chosen)].refusal.empty());
    EXPECT_GT(std::abs(top_z(o->placed) - given_height), 1e-6);

    auto g = orient_multiaxis(part, {0, 0, 1}, OrientPolicy::kGiven, profiles, nullptr, check);
    ASSERT_FALSE(g.has_value());
    EXPECT_EQ(g.error().code, core::ErrorCode::kInvalidInput);
}

// With an estimate the search keeps, among the bases that build, the one with the shortest
// verified build time (decision 0015). Test figures: a base's estimate is 1000 s plus 10 s a
// millimetre of the part's height on the plate, its verified time 1 s more; the check refuses
// the lowest base, and calls a base "short of the figures" where the test says so.
TEST(OrientJob, TheSearchKeepsTheShortestVerifiedBuildTime) {
    const machine::Profiles profiles = reference_profiles();
    const mesh::TriangleMesh part = test::l_bracket().mesh;
    const auto seconds = [](const mesh::TriangleMesh& m) { return 1000.0 + 10.0 * top_z(m); };
    for (const bool lowest_kept_short : {false, true}) {
        SCOPED_TRACE(lowest_kept_short ? "the fastest is short of the figures" : "plain");
        std::vector<double> estimated, checked;  // heights, in call order
        double refused_height = 1e300;           // the lowest, known after the estimates
        core::Vec3d last_direction;
        const auto estimate = [&](const core::Vec3d&, const mesh::TriangleMesh& m,
                                  const PlannedPart& p) -> core::Result<ProgramVerdict> {
            EXPECT_TRUE(p.order.has_value()) << "only ordered plans are estimated";
            estimated.push_back(top_z(m));
            refused_height = std::min(refused_height, top_z(m));
            return ProgramVerdict{{}, seconds(m)};
        };
        const auto check = [&](const core::Vec3d& d, const mesh::TriangleMesh& m,
                               const PlannedPart&) -> core::Result<ProgramVerdict> {
            checked.push_back(top_z(m));
            last_direction = d;
            if (std::abs(top_z(m) - refused_height) < 1e-6) return ProgramVerdict{"refused"};
            // Among the others, the lowest is short of the figures in the second round.
            double next_lowest = 1e300;
            for (double h : estimated) {
                if (h > refused_height + 1e-6) next_lowest = std::min(next_lowest, h);
            }
            const bool short_of = lowest_kept_short && std::abs(top_z(m) - next_lowest) < 1e-6;
            return ProgramVerdict{{}, seconds(m) + 1.0, short_of};
        };
        auto o = orient_multiaxis(part, {0, 0, 1}, OrientPolicy::kAuto, profiles, nullptr, check,
                                  {}, estimate);
        ASSERT_TRUE(o.has_value()) << o.error().describe();
        ASSERT_GE(estimated.size(), 3u) << "the bracket builds on several bases";
        const OrientTry& kept = o->tries[static_cast<std::size_t>(o->chosen)];
        EXPECT_TRUE(kept.refusal.empty()) << kept.refusal;
        const double kept_height = top_z(o->placed);
        EXPECT_LT(core::norm(last_direction - kept.direction), 1e-12)
            << "the last check is of the base kept";
        // The kept base is the lowest of those the check passed and that meet the figures.
        std::vector<double> sorted = estimated;
        std::sort(sorted.begin(), sorted.end());
        std::vector<double> passing;
        for (double h : sorted) {
            if (h > refused_height + 1e-6) passing.push_back(h);
        }
        ASSERT_GE(passing.size(), 2u);
        const double expected = lowest_kept_short
                                    ? *std::find_if(passing.begin(), passing.end(),
                                                    [&](double h) { return h > passing[0] + 1e-6; })
                                    : passing[0];
        EXPECT_NEAR(kept_height, expected, 1e-6);
        // Nothing taller than the kept base's verified time allows is checked.
        for (double h : checked)
            EXPECT_LT((1000.0 + 10.0 * h), (1000.0 + 10.0 * kept_height) + 1.0 + 1e-9);
        int longer = 0;
        for (const OrientTry& t : o->tries) {
            if (t.refusal.find("no shorter than") != std::string::npos) ++longer;
        }
        EXPECT_GE(longer, 1) << "the bases that build but take longer say so";
    }
}

// A wedge standing on a strip 0.5 mm wide, wider above: its plate layer has no track and
// layers with tracks stand on it. As given it is refused for that; the search stands it on
// a face. A block on its 12 mm wide foot has no such layer.
TEST(OrientJob, APartOnAStripNarrowerThanATrackIsStoodOnAFace) {
    const machine::Profiles profiles = reference_profiles();
    test::RampSpec spec;
    spec.base_length = 0.5;
    spec.lean_deg = 30.0;
    const mesh::TriangleMesh wedge = test::ramp_45(spec).mesh;
    auto given = orient_multiaxis(wedge, {0, 0, 1}, OrientPolicy::kGiven, profiles);
    ASSERT_TRUE(given.has_value()) << given.error().describe();
    EXPECT_FALSE(given->bare_plate_layers.empty());
    EXPECT_EQ(given->tries[0].refusal, "stands on 1 piece(s) where no track fits");

    auto o = orient_multiaxis(wedge, {0, 0, 1}, OrientPolicy::kFallback, profiles);
    ASSERT_TRUE(o.has_value()) << o.error().describe();
    EXPECT_GT(o->chosen, 0);
    EXPECT_TRUE(o->bare_plate_layers.empty());

    auto block =
        orient_multiaxis(test::vertical_prism().mesh, {0, 0, 1}, OrientPolicy::kGiven, profiles);
    ASSERT_TRUE(block.has_value());
    EXPECT_TRUE(block->bare_plate_layers.empty());
    EXPECT_TRUE(block->tries[0].refusal.empty());
}

// A block with a fin beside its foot: the fin stands on the plate as a strip 0.7 mm wide at
// the first layer (no track fits), leaning into the block, which it joins 1.2 mm up. What has
// tracks above the strip rests on the block's layers too: nothing hangs from the strip alone,
// so the part is not refused for it (its tracks are cut to the beads below, and the verifier
// judges the program). Without the block the fin stands on the strip alone and is refused.
TEST(OrientJob, AStripAtThePlateThatJoinsTheFootDoesNotRefuseThePart) {
    const machine::Profiles profiles = reference_profiles();
    const std::vector<test::CapPoint> outline{{0, 0},    {20, 0},    {20, 1.2}, {21.5, 0},
                                              {21.9, 0}, {21.9, 10}, {0, 10}};
    const mesh::TriangleMesh part = test::extrude_xz(test::polygon_cap(outline), 0.0, 20.0);
    auto o = orient_multiaxis(part, {0, 0, 1}, OrientPolicy::kGiven, profiles);
    ASSERT_TRUE(o.has_value()) << o.error().describe();
    const plan::Plan& plan = o->planned.plan;
    std::vector<int> plate;
    for (const plan::Layer& l : plan.layers) {
        if (l.on_plate) plate.push_back(l.id);
    }
    auto bare = trackless_layers(plan, plate, path_settings(profiles.process));
    ASSERT_TRUE(bare.has_value());
    EXPECT_EQ(plate.size(), 2u) << "the foot and the strip";
    EXPECT_EQ(bare->size(), 1u) << "the strip gets no track";
    EXPECT_TRUE(o->bare_plate_layers.empty());
    EXPECT_TRUE(o->tries[0].refusal.empty()) << o->tries[0].refusal;

    const std::vector<test::CapPoint> fin{{21.5, 0}, {21.9, 0}, {21.9, 10}, {18.0, 10}};
    auto alone = orient_multiaxis(test::extrude_xz(test::polygon_cap(fin), 0.0, 20.0), {0, 0, 1},
                                  OrientPolicy::kGiven, profiles);
    ASSERT_TRUE(alone.has_value()) << alone.error().describe();
    EXPECT_FALSE(alone->bare_plate_layers.empty());
    EXPECT_EQ(alone->tries[0].refusal, "stands on 1 piece(s) where no track fits");
}

// The 3-axis search: the block builds as given; a check refusing the given stack sends the
// search to the candidates (kept: one the check passes, after the given), and --orient given
// records the answer and keeps the given stack.
TEST(OrientJob, AStackTheCheckRefusesIsNotKept) {
    const machine::Profiles profiles = reference_profiles();
    const mesh::TriangleMesh part = test::vertical_prism().mesh;
    SliceSettings settings;
    settings.layers.layer_mm = profiles.process.layer_height_mm;
    auto given = orient_planar(part, {0, 0, 1}, OrientPolicy::kGiven, settings, profiles);
    ASSERT_TRUE(given.has_value()) << given.error().describe();
    ASSERT_TRUE(given->tries[0].refusal.empty());
    const double given_height = top_z(given->placed);
    int calls = 0;
    const StackCheck check = [&](const core::Vec3d&, const mesh::TriangleMesh& placed,
                                 const SliceStack&) -> core::Result<std::string> {
        ++calls;
        return std::abs(top_z(placed) - given_height) < 1e-6 ? std::string("refused by the test")
                                                             : std::string();
    };
    auto o = orient_planar(part, {0, 0, 1}, OrientPolicy::kFallback, settings, profiles, nullptr,
                           nullptr, check);
    ASSERT_TRUE(o.has_value()) << o.error().describe();
    EXPECT_EQ(o->tries[0].refusal, "refused by the test");
    ASSERT_GT(o->chosen, 0);
    EXPECT_TRUE(o->tries[static_cast<std::size_t>(o->chosen)].refusal.empty());
    EXPECT_GT(std::abs(top_z(o->placed) - given_height), 1e-6);
    EXPECT_GE(calls, 2);

    calls = 0;
    auto g = orient_planar(part, {0, 0, 1}, OrientPolicy::kGiven, settings, profiles, nullptr,
                           nullptr, check);
    ASSERT_TRUE(g.has_value());
    EXPECT_EQ(g->tries[0].refusal, "refused by the test");
    EXPECT_NEAR(top_z(g->placed), given_height, 1e-6);
    EXPECT_EQ(calls, 1);
}

// The quick fit check of a job that deposits a near-net shape is of the part grown by the
// stock: a 1 mm square column, standing as given, reaches farthest from the table's axes at its
// top, which the stock raises by s (the column stands on s of stock) and moves s farther up:
// the tallest column that fits is 2 s shorter than without stock. Laid down (the candidates),
// a column too tall to stand fits; a slab wider than the travel fits no way, and the refusal
// names the stock and the orientations tried.
TEST(OrientJob, TheFitCheckIsOfThePartGrownByTheStock) {
    machine::Profiles profiles = reference_profiles();
    // About the machine's travel: without the plate, whose own check (the footprint on it)
    // would refuse the long column laid down first.
    profiles.machine.substrate.reset();
    const double stock = profiles.process.machining_stock_mm;
    ASSERT_GT(stock, 0.0);
    const auto column = [](double h) { return test::box({0, 0, 0}, {1, 1, h}); };
    const auto fits = [&](double h, double grown, OrientPolicy policy) {
        return check_fits_machine(column(h), {0, 0, 1}, policy, profiles, grown).has_value();
    };
    // The tallest column that fits standing, to 1e-4 mm.
    const auto tallest = [&](double grown) {
        double lo = 10.0, hi = 1e4;
        EXPECT_TRUE(fits(lo, grown, OrientPolicy::kGiven));
        EXPECT_FALSE(fits(hi, grown, OrientPolicy::kGiven));
        while (hi - lo > 1e-4) {
            const double mid = 0.5 * (lo + hi);
            (fits(mid, grown, OrientPolicy::kGiven) ? lo : hi) = mid;
        }
        return lo;
    };
    const double bare = tallest(0.0);
    const double grown = tallest(stock);
    EXPECT_NEAR(bare - grown, 2.0 * stock, 0.01) << bare << " " << grown;

    const auto too_tall =
        check_fits_machine(column(grown + 1.0), {0, 0, 1}, OrientPolicy::kGiven, profiles, stock);
    ASSERT_FALSE(too_tall.has_value());
    EXPECT_NE(too_tall.error().message.find("does not fit the machine"), std::string::npos);
    EXPECT_NE(too_tall.error().message.find("machining stock"), std::string::npos);
    EXPECT_EQ(too_tall.error().message.find("other orientations"), std::string::npos);
    EXPECT_TRUE(fits(grown + 1.0, stock, OrientPolicy::kFallback));
    EXPECT_TRUE(fits(grown + 1.0, stock, OrientPolicy::kAuto));

    const auto slab = check_fits_machine(test::box({0, 0, 0}, {2000, 2000, 10}), {0, 0, 1},
                                         OrientPolicy::kFallback, profiles, stock);
    ASSERT_FALSE(slab.has_value());
    EXPECT_NE(slab.error().message.find("other orientations tried"), std::string::npos);

    // A 3-axis machine: nothing is checked here (its program's limit check names the move).
    machine::Profiles xyz = profiles;
    xyz.machine.kinematics = machine::Kinematics::kXyz;
    EXPECT_TRUE(check_fits_machine(test::box({0, 0, 0}, {2000, 2000, 10}), {0, 0, 1},
                                   OrientPolicy::kGiven, xyz, stock)
                    .has_value());
}

}  // namespace
}  // namespace maxslice::pipeline
