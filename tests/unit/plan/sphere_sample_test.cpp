// The sample of the sphere the planner searches when no lean or turn of a sideways direction
// keeps the head clear (decision 0046): within the table's tilt range, no direction of that
// range farther than a step from a sample, and the same sample, turned, for a part turned
// about the base direction.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "maxslice/plan/analysis.hpp"
#include "reach.hpp"

namespace maxslice::plan::detail {
namespace {

using core::Vec3d;

// Directions spread evenly over the whole sphere (a Fibonacci lattice), to probe the sample.
std::vector<Vec3d> probe_directions(int n) {
    std::vector<Vec3d> out;
    const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
    for (int k = 0; k < n; ++k) {
        const double z = 1.0 - (2.0 * k + 1.0) / n;
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        out.push_back({r * std::cos(golden * k), r * std::sin(golden * k), z});
    }
    return out;
}

Vec3d turned_about_z(const Vec3d& d, double deg) {
    const double a = deg * std::numbers::pi / 180.0;
    return {d.x * std::cos(a) - d.y * std::sin(a), d.x * std::sin(a) + d.y * std::cos(a), d.z};
}

TEST(SphereSample, StaysWithinTheTiltRangeAndLeavesNoDirectionOfItFartherThanAStep) {
    const Vec3d up{0, 0, 1};
    const Vec3d ns = core::normalized(Vec3d{0.8, -0.3, -0.4});
    for (const double tilt : {30.0, 90.0, 120.0, 180.0}) {
        for (const double step : {10.0, 15.0}) {
            const std::vector<Vec3d> sample = sphere_sample(up, ns, tilt, step);
            ASSERT_FALSE(sample.empty());
            for (const Vec3d& d : sample) {
                EXPECT_NEAR(core::norm(d), 1.0, 1e-12);
                EXPECT_LE(angle_deg(d, up), tilt + 1e-9) << "tilt " << tilt << ", step " << step;
            }
            // Every direction within the range lies within a step of a sample.
            double worst = 0.0;
            for (const Vec3d& q : probe_directions(4000)) {
                if (angle_deg(q, up) > tilt) continue;
                double nearest = 180.0;
                for (const Vec3d& d : sample) nearest = std::min(nearest, angle_deg(q, d));
                worst = std::max(worst, nearest);
            }
            EXPECT_LE(worst, step) << "tilt " << tilt << ", step " << step;
        }
    }
}

TEST(SphereSample, APartTurnedAboutTheBaseDirectionGetsTheSameDirectionsTurned) {
    const Vec3d up{0, 0, 1};
    const Vec3d ns = core::normalized(Vec3d{-0.2, 0.9, 0.1});
    const std::vector<Vec3d> sample = sphere_sample(up, ns, 120.0, 15.0);
    for (const double turn : {37.0, 113.0, 247.0}) {
        const std::vector<Vec3d> turned = sphere_sample(up, turned_about_z(ns, turn), 120.0, 15.0);
        ASSERT_EQ(turned.size(), sample.size()) << turn;
        for (std::size_t k = 0; k < sample.size(); ++k) {
            const Vec3d want = turned_about_z(sample[k], turn);
            EXPECT_LT(core::norm(turned[k] - want), 1e-9) << "turn " << turn << ", direction " << k;
        }
    }
}

TEST(SphereSample, ASeedAlongTheBaseDirectionStillGetsAFullSample) {
    const Vec3d up = core::normalized(Vec3d{0.3, -0.2, 0.9});
    const std::vector<Vec3d> sample = sphere_sample(up, up, 120.0, 15.0);
    const std::vector<Vec3d> other = sphere_sample(up, Vec3d{1, 0, 0}, 120.0, 15.0);
    EXPECT_EQ(sample.size(), other.size());
    for (const Vec3d& d : sample) EXPECT_LE(angle_deg(d, up), 120.0 + 1e-9);
}

}  // namespace
}  // namespace maxslice::plan::detail
