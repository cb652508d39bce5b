#include <gtest/gtest.h>

#include <random>

#include "machine_fixtures.hpp"
#include "maxslice/machine/speed_law.hpp"

namespace maxslice::machine {
namespace {

using testing::reference_process;

ProcessProfile measured_process() {
    ProcessProfile p = reference_process();
    p.speed_height = {{250.0, 0.72}, {300.0, 0.62}, {381.0, 0.5}, {500.0, 0.4}, {650.0, 0.3}};
    return p;
}

TEST(SpeedLaw, ConstantMassLawPassesThroughTheNominalPoint) {
    const ProcessProfile p = reference_process();
    const SpeedLaw law = SpeedLaw::of(p);
    EXPECT_FALSE(law.measured());
    EXPECT_NEAR(law.height_mm(p.deposition_feed_mm_min), p.layer_height_mm, 1e-12);
    EXPECT_NEAR(law.feed_mm_min(p.layer_height_mm), p.deposition_feed_mm_min, 1e-9);
    // The window is the feeds that lay [h_min, h_max]: height x feed stays constant.
    EXPECT_NEAR(law.height_min_mm(), p.h_min_mm, 1e-12);
    EXPECT_NEAR(law.height_max_mm(), p.h_max_mm, 1e-12);
    EXPECT_NEAR(law.height_mm(1.2 * p.deposition_feed_mm_min) * 1.2, p.layer_height_mm, 1e-12);
}

TEST(SpeedLaw, MeasuredLawInterpolatesItsPairs) {
    const ProcessProfile p = measured_process();
    ASSERT_TRUE(validate(p).has_value()) << validate(p).error().describe();
    const SpeedLaw law = SpeedLaw::of(p);
    EXPECT_TRUE(law.measured());
    for (const SpeedPoint& q : p.speed_height) {
        EXPECT_NEAR(law.height_mm(q.feed_mm_min), q.height_mm, 1e-12);
        EXPECT_NEAR(law.feed_mm_min(q.height_mm), q.feed_mm_min, 1e-9);
    }
    // Half-way between two pairs, linearly.
    EXPECT_NEAR(law.height_mm(275.0), 0.67, 1e-12);
    EXPECT_NEAR(law.feed_mm_min(0.45), 440.5, 1e-9);
    EXPECT_DOUBLE_EQ(law.feed_min_mm_min(), 250.0);
    EXPECT_DOUBLE_EQ(law.feed_max_mm_min(), 650.0);
}

TEST(SpeedLaw, InverseRoundTripsAndIsMonotone) {
    for (const ProcessProfile& p : {reference_process(), measured_process()}) {
        const SpeedLaw law = SpeedLaw::of(p);
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> h(law.height_min_mm(), law.height_max_mm());
        for (int i = 0; i < 1000; ++i) {
            const double a = h(rng), b = h(rng);
            EXPECT_NEAR(law.height_mm(law.feed_mm_min(a)), a, 1e-9);
            // A lower track needs a higher feed.
            if (a < b) {
                EXPECT_GT(law.feed_mm_min(a), law.feed_mm_min(b));
            }
        }
    }
}

TEST(SpeedLaw, FeedsAreClampedToTheWindow) {
    for (const ProcessProfile& p : {reference_process(), measured_process()}) {
        const SpeedLaw law = SpeedLaw::of(p);
        EXPECT_DOUBLE_EQ(law.feed_mm_min(law.height_max_mm() * 3.0), law.feed_min_mm_min());
        EXPECT_DOUBLE_EQ(law.feed_mm_min(law.height_min_mm() * 0.1), law.feed_max_mm_min());
        EXPECT_DOUBLE_EQ(law.height_mm(law.feed_max_mm_min() * 10.0), law.height_min_mm());
        EXPECT_DOUBLE_EQ(law.height_mm(0.5 * law.feed_min_mm_min()), law.height_max_mm());
    }
}

TEST(SpeedLaw, ValidationRefusesABadLaw) {
    const auto refused = [](std::vector<SpeedPoint> pts, std::string_view needle) {
        ProcessProfile p = reference_process();
        p.speed_height = std::move(pts);
        const auto ok = validate(p);
        ASSERT_FALSE(ok.has_value());
        EXPECT_NE(ok.error().describe().find(needle), std::string::npos) << ok.error().describe();
    };
    refused({{381.0, 0.5}}, "pairs");
    refused({{300.0, 0.6}, {381.0, 0.5}, {370.0, 0.45}}, "feeds must increase");
    refused({{300.0, 0.5}, {381.0, 0.5}}, "heights decrease");
    refused({{300.0, 0.6}, {381.0, -0.5}}, "height");
    refused({{300.0, 0.7}, {600.0, 0.6}}, "must agree");  // lays 0.66 mm at 381 mm/min
}

TEST(SpeedLaw, TheMachineMustAcceptEveryFeedOfTheLaw) {
    ProcessProfile p = measured_process();
    MachineProfile m = testing::gm_machine();
    EXPECT_TRUE(check_compatible(m, p).has_value());
    m.feed_max_mm_min = 600.0;  // below the law's 650 mm/min
    p.travel_feed_mm_min = 600.0;
    const auto ok = check_compatible(m, p);
    ASSERT_FALSE(ok.has_value());
    EXPECT_NE(ok.error().message.find("process.speed_height[4] feed 650"), std::string::npos)
        << ok.error().describe();
}

}  // namespace
}  // namespace maxslice::machine
