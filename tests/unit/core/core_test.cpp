#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "maxslice/core/progress.hpp"
#include "maxslice/core/result.hpp"
#include "maxslice/core/revolution.hpp"
#include "maxslice/core/units.hpp"
#include "maxslice/core/vec3.hpp"

namespace maxslice::core {
namespace {

constexpr LengthUnit kAllUnits[] = {LengthUnit::kMillimetre, LengthUnit::kInch,
                                    LengthUnit::kMetre,      LengthUnit::kCentimetre,
                                    LengthUnit::kMicron,     LengthUnit::kFoot};

TEST(Units, ParseKnownNamesInAnyCase) {
    EXPECT_EQ(parse_unit("mm"), LengthUnit::kMillimetre);
    EXPECT_EQ(parse_unit("MM"), LengthUnit::kMillimetre);
    EXPECT_EQ(parse_unit("Millimetre"), LengthUnit::kMillimetre);
    EXPECT_EQ(parse_unit("in"), LengthUnit::kInch);
    EXPECT_EQ(parse_unit("Inch"), LengthUnit::kInch);
    EXPECT_EQ(parse_unit("inches"), LengthUnit::kInch);
    EXPECT_EQ(parse_unit("m"), LengthUnit::kMetre);
    EXPECT_EQ(parse_unit("meter"), LengthUnit::kMetre);
    EXPECT_EQ(parse_unit("cm"), LengthUnit::kCentimetre);
    EXPECT_EQ(parse_unit("um"), LengthUnit::kMicron);
    EXPECT_EQ(parse_unit("micron"), LengthUnit::kMicron);
    EXPECT_EQ(parse_unit("ft"), LengthUnit::kFoot);
    EXPECT_EQ(parse_unit("FEET"), LengthUnit::kFoot);
}

TEST(Units, RejectUnknownNames) {
    EXPECT_EQ(parse_unit(""), std::nullopt);
    EXPECT_EQ(parse_unit("furlong"), std::nullopt);
    EXPECT_EQ(parse_unit(" mm"), std::nullopt);
    EXPECT_EQ(parse_unit("mm "), std::nullopt);
    EXPECT_EQ(parse_unit("mmm"), std::nullopt);
    EXPECT_EQ(parse_unit("µm"), std::nullopt);
}

TEST(Units, EveryNameParsesBackToItsUnit) {
    for (const LengthUnit u : kAllUnits) {
        EXPECT_EQ(parse_unit(unit_name(u)), u) << unit_name(u);
    }
}

TEST(Units, ScaleFactors) {
    EXPECT_EQ(mm_per_unit(LengthUnit::kMillimetre), 1.0);
    EXPECT_EQ(mm_per_unit(LengthUnit::kInch), 25.4);
    EXPECT_EQ(mm_per_unit(LengthUnit::kMetre), 1000.0);
    EXPECT_EQ(mm_per_unit(LengthUnit::kCentimetre), 10.0);
    EXPECT_EQ(mm_per_unit(LengthUnit::kMicron), 0.001);
    EXPECT_DOUBLE_EQ(mm_per_unit(LengthUnit::kFoot), 12.0 * 25.4);
}

TEST(Units, MillimetresRoundToTheNearestMicrometre) {
    EXPECT_EQ(mm_to_um(0.0), 0);
    EXPECT_EQ(mm_to_um(1.0), 1000);
    EXPECT_EQ(mm_to_um(0.0004), 0);
    EXPECT_EQ(mm_to_um(0.0006), 1);
    EXPECT_EQ(mm_to_um(-0.0006), -1);
    EXPECT_EQ(mm_to_um(1.2346), 1235);
    EXPECT_EQ(mm_to_um(-1.2344), -1234);
    EXPECT_EQ(mm_to_um(0.0015), 2);  // halves round away from zero
    EXPECT_EQ(mm_to_um(-0.0025), -3);
    EXPECT_EQ(mm_to_um(1e6), 1'000'000'000);
    EXPECT_EQ(mm_to_um(-1e6), -1'000'000'000);
}

TEST(Units, IntegerMicrometresSurviveARoundTrip) {
    for (std::int64_t um = -2'000'000; um <= 2'000'000; um += 997) {
        EXPECT_EQ(mm_to_um(um_to_mm(um)), um);
    }
    for (const std::int64_t um : {std::int64_t{999'999'999}, std::int64_t{-1'000'000'000}}) {
        EXPECT_EQ(mm_to_um(um_to_mm(um)), um);
    }
    EXPECT_EQ(um_to_mm(1500), 1.5);
    EXPECT_EQ(um2_to_mm2(2.5e6), 2.5);
}

TEST(Result, FailCarriesCodeMessageAndContext) {
    const Result<int> r = fail(ErrorCode::kIo, "cannot open", "file part.stl");
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().code, ErrorCode::kIo);
    EXPECT_EQ(r.error().message, "cannot open");
    EXPECT_EQ(r.error().context, "file part.stl");
    EXPECT_EQ(r.error().describe(), "file part.stl: cannot open");
}

TEST(Result, DescribeWithoutContextIsTheMessage) {
    const Result<void> r = fail(ErrorCode::kInvalidInput, "bad number");
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().context, "");
    EXPECT_EQ(r.error().describe(), "bad number");
}

TEST(Result, ValuesPassThrough) {
    const Result<std::string> r = std::string("ok");
    ASSERT_TRUE(r.has_value());
    EXPECT_EQ(*r, "ok");
    const Result<void> v{};
    EXPECT_TRUE(v.has_value());
}

TEST(Result, WithContextAddsTheOuterPlaceFirst) {
    const Error inner{ErrorCode::kInvalidInput, "bad number", "line 12"};
    const Error outer = with_context(inner, "file foo.stl");
    EXPECT_EQ(outer.code, ErrorCode::kInvalidInput);
    EXPECT_EQ(outer.message, "bad number");
    EXPECT_EQ(outer.context, "file foo.stl, line 12");
    EXPECT_EQ(outer.describe(), "file foo.stl, line 12: bad number");
    const Error bare = with_context(Error{ErrorCode::kInternal, "oops", ""}, "layer 3");
    EXPECT_EQ(bare.context, "layer 3");
    EXPECT_EQ(with_context(with_context(bare, "region 2"), "job").context,
              "job, region 2, layer 3");
}

TEST(Progress, DefaultDoesNothingAndCanBeCancelled) {
    Progress p;
    p.report("slicing", 0.5);  // no callback: nothing happens
    EXPECT_FALSE(p.cancelled());
    p.cancel();
    EXPECT_TRUE(p.cancelled());
}

TEST(Progress, CallbackReceivesStageAndFraction) {
    std::string stage;
    double fraction = -1.0;
    const Progress p([&](std::string_view s, double f) {
        stage = s;
        fraction = f;
    });
    p.report("planning", 0.25);
    EXPECT_EQ(stage, "planning");
    EXPECT_EQ(fraction, 0.25);
}

TEST(Vec3, Arithmetic) {
    const Vec3d a{1, 2, 3}, b{4, 5, 6};
    EXPECT_EQ(a + b, (Vec3d{5, 7, 9}));
    EXPECT_EQ(b - a, (Vec3d{3, 3, 3}));
    EXPECT_EQ(-a, (Vec3d{-1, -2, -3}));
    EXPECT_EQ(a * 2.0, (Vec3d{2, 4, 6}));
    EXPECT_EQ(b / 2.0, (Vec3d{2, 2.5, 3}));
    EXPECT_EQ(dot(a, b), 32.0);
    EXPECT_EQ(cross(Vec3d{1, 0, 0}, Vec3d{0, 1, 0}), (Vec3d{0, 0, 1}));
    EXPECT_EQ(dot(cross(a, b), a), 0.0);
    EXPECT_EQ(a[0], 1.0);
    EXPECT_EQ(a[2], 3.0);
    EXPECT_DOUBLE_EQ(norm(Vec3d{3, 4, 12}), 13.0);
    EXPECT_DOUBLE_EQ(norm(normalized(b)), 1.0);
    EXPECT_EQ(normalized(Vec3d{}), (Vec3d{}));
    EXPECT_FALSE(is_finite(Vec3d{0, NAN, 0}));
    EXPECT_FALSE(is_finite(Vec3d{0, 0, INFINITY}));
    EXPECT_TRUE(is_finite(a));
}

TEST(Box3d, StartsEmptyAndGrows) {
    Box3d box;
    EXPECT_TRUE(box.empty());
    EXPECT_EQ(box.size(), (Vec3d{}));
    box.add(Vec3d{1, 2, 3});
    EXPECT_FALSE(box.empty());
    EXPECT_EQ(box.size(), (Vec3d{}));
    box.add(Vec3d{-1, 5, 4});
    EXPECT_EQ(box.min, (Vec3d{-1, 2, 3}));
    EXPECT_EQ(box.max, (Vec3d{1, 5, 4}));
    EXPECT_EQ(box.center(), (Vec3d{0, 3.5, 3.5}));
    Box3d other;
    box.add(other);  // adding an empty box changes nothing
    EXPECT_EQ(box.min, (Vec3d{-1, 2, 3}));
    other.add(Vec3d{10, 10, 10});
    box.add(other);
    EXPECT_EQ(box.max, (Vec3d{10, 10, 10}));
}

}  // namespace
}  // namespace maxslice::core

// The lowest point of a head outline, against the rims of its circles sampled point by point:
// a point at angle phi on the circle of radius r, t along the axis, stands t cos + r sin cos(phi)
// high along a direction at angle acos(cos) to the axis.
TEST(Revolution, LowestPointMatchesTheSampledRims) {
    const std::vector<std::pair<double, double>> head = {
        {0.0, 0.0}, {9.0, 5.2}, {45.0, 26.0}, {45.0, 30.0}, {165.0, 30.0}};
    for (const double c : {1.0, 0.8, 0.5, 0.0, -0.3, -1.0}) {
        SCOPED_TRACE(c);
        const double s = std::sqrt(1.0 - c * c);
        double sampled = 1e300;
        for (const auto& [t, r] : head) {
            for (int k = 0; k < 3600; ++k) {
                const double phi = 2.0 * std::numbers::pi * k / 3600.0;
                sampled = std::min(sampled, t * c + r * s * std::cos(phi));
            }
        }
        const double lowest = maxslice::core::lowest_on_revolution(head, c);
        EXPECT_NEAR(lowest, sampled, 1e-9);
        EXPECT_LE(lowest, 0.0);  // the apex itself is on the outline
    }
    EXPECT_TRUE(std::isinf(maxslice::core::lowest_on_revolution({}, 0.5)));
}
