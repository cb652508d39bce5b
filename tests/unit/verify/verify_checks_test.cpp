// Issue 23: the verifier's checks of a program's values and end (out of range, cut off,
// unterminated, laser or powder left on) and of the part it builds (nothing deposited,
// coverage and excess), each on programs written by hand in the test.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

#include "maxslice/verify/verify.hpp"
#include "support/fixtures.hpp"
#include "verify_programs.hpp"

namespace maxslice::verify {
namespace {

using core::Vec3d;
using testing::load;
using testing::ProgramText;
using testing::zigzag_block;

using testing::kHalf;
using testing::kLayers;
using testing::placed;

mesh::TriangleMesh block(const machine::Profiles& p) {
    return testing::placed_block(p);
}

Report verified(const std::string& text, const machine::Profiles& p,
                const mesh::TriangleMesh& model, const VerifySettings& s = {}) {
    auto r = verify_program(text, model, p, s);
    EXPECT_TRUE(r.has_value()) << r.error().describe();
    return r.value_or(Report{});
}

bool failed(const Report& r, std::string_view check) {
    const auto checks = failed_checks(r);
    return std::find(checks.begin(), checks.end(), check) != checks.end();
}

// The block built in `dialect`, laser and powder off at the end, and (unless gm) M2.
std::string clean_block(const machine::Profiles& p, ProgramDialect dialect) {
    ProgramText prog(p, dialect, false);
    const Vec3d c = mesh::bounding_box(block(p)).center();
    zigzag_block(prog, p, c.x, c.y, kHalf, kLayers);
    if (dialect != ProgramDialect::kGm) prog.raw("M2");
    return prog.text();
}

TEST(VerifyChecks, ACleanProgramIsSafeAndMatchesItsPart) {
    for (const auto& [file, dialect] :
         {std::pair{"reference_lmd.toml", ProgramDialect::kGm},
          std::pair{"linuxcnc_generic.toml", ProgramDialect::kLinuxCnc}}) {
        SCOPED_TRACE(file);
        const machine::Profiles p = load(file);
        const Report r = verified(clean_block(p, dialect), p, block(p));
        EXPECT_TRUE(r.passed()) << report_text(r);
        EXPECT_TRUE(r.matches_part()) << report_text(r);
        EXPECT_TRUE(r.accepted());
        EXPECT_TRUE(failed_checks(r).empty());
        const auto j = nlohmann::json::parse(report_json(r));
        EXPECT_TRUE(j.at("passed").get<bool>());
        EXPECT_TRUE(j.at("failed_checks").empty());
        EXPECT_NE(report_text(r).find("part match      yes"), std::string::npos);
    }
}

// A LinuxCNC program that ends with the laser on and no M2, and the same program cut in half
// (mid-line): unsafe, and the report says why.
TEST(VerifyChecks, LaserLeftOnUnterminatedAndCutProgramsFail) {
    const machine::Profiles p = load("linuxcnc_generic.toml");
    const Vec3d c = mesh::bounding_box(block(p)).center();
    ProgramText prog(p, ProgramDialect::kLinuxCnc, false);
    zigzag_block(prog, p, c.x, c.y, kHalf, kLayers);
    prog.laser(true);
    const int last = prog.move(c.x, c.y, kLayers * 0.5 + 0.5, p.process.deposition_feed_mm_min);
    const Report on = verified(prog.text(), p, block(p));
    EXPECT_FALSE(on.passed()) << report_text(on);
    EXPECT_EQ(on.left_on.count, 1U);
    ASSERT_TRUE(on.left_on.first);
    EXPECT_EQ(on.left_on.first->line, last);
    EXPECT_NE(on.left_on.first->detail.find("laser"), std::string::npos);
    EXPECT_EQ(on.unfinished.count, 1U);
    EXPECT_NE(on.unfinished.first->detail.find("M2"), std::string::npos);
    EXPECT_TRUE(failed(on, "left_on"));
    EXPECT_TRUE(failed(on, "unfinished"));
    EXPECT_FALSE(on.passed_apart_from_support());
    const auto j = nlohmann::json::parse(report_json(on));
    EXPECT_FALSE(j.at("passed").get<bool>());
    EXPECT_FALSE(j.at("safe").get<bool>());
    EXPECT_EQ(j.at("left_on").at("first").at("line").get<int>(), last);

    // Cut in the middle of a line, half-way through.
    const std::string whole = clean_block(p, ProgramDialect::kLinuxCnc);
    std::size_t half = whole.size() / 2;
    while (whole[half] == '\n' || whole[half - 1] == '\n') ++half;
    const Report cut = verified(whole.substr(0, half), p, block(p));
    EXPECT_FALSE(cut.passed()) << report_text(cut);
    EXPECT_EQ(cut.unfinished.count, 1U);
    EXPECT_NE(cut.unfinished.first->detail.find("cut off"), std::string::npos);
    EXPECT_TRUE(cut.coverage_low()) << report_text(cut);
    // The gm dialect has no end code: its cut program is known by its last line.
    const machine::Profiles gm = load("reference_lmd.toml");
    const std::string gm_whole = clean_block(gm, ProgramDialect::kGm);
    const Report gm_cut = verified(gm_whole.substr(0, gm_whole.size() / 2 + 3), gm, block(gm));
    EXPECT_EQ(gm_cut.unfinished.count, 1U) << report_text(gm_cut);
    EXPECT_FALSE(gm_cut.passed());
    EXPECT_TRUE(verified(gm_whole, gm, block(gm)).passed());
}

// An empty program and one of comments only deposit nothing; the RS-274 one has no M2 either.
TEST(VerifyChecks, EmptyAndCommentOnlyProgramsFail) {
    const machine::Profiles gm = load("reference_lmd.toml");
    const Report empty = verified("", gm, block(gm));
    EXPECT_TRUE(empty.deposits_nothing());
    EXPECT_FALSE(empty.matches_part());
    EXPECT_FALSE(empty.accepted());
    EXPECT_TRUE(failed(empty, "nothing_deposited"));
    EXPECT_NE(report_text(empty).find("deposits nothing"), std::string::npos);
    const machine::Profiles lc = load("linuxcnc_generic.toml");
    const Report comments = verified("(a comment)\n; another\n", lc, block(lc));
    EXPECT_FALSE(comments.passed());
    EXPECT_EQ(comments.unfinished.count, 1U);
    EXPECT_TRUE(comments.deposits_nothing());
    EXPECT_FALSE(comments.accepted());
}

// A model read in metres (1000 times too large) or a voxel coarser than the beads: the beads
// filled no voxel, 0 mm3 deposited, which was once reported PASSED; and a voxel a little
// coarser than a layer hid the layer under an overhanging bead (NIST CTC-05 on the large cell:
// 14 beads "on nothing" at 0.89 mm voxels, none at 0.30 mm). The verifier refuses a grid that
// cannot see the thinnest bead's layer (voxel above its height / 1.25), automatic or given.
TEST(VerifyChecks, AGridThatCannotSeeTheLayersGivesNoVerdict) {
    const machine::Profiles p = load("reference_lmd.toml");
    const std::string text = clean_block(p, ProgramDialect::kGm);
    const auto unseen = [](const core::Result<Report>& r, const std::string& where) {
        ASSERT_FALSE(r.has_value()) << report_text(*r);
        EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
        EXPECT_EQ(r.error().context, where);
        EXPECT_NE(r.error().message.find("cannot see this program's layers"), std::string::npos)
            << r.error().describe();
    };
    unseen(verify_program(text, placed(p, test::box({0, 0, 0}, {30000, 30000, 6000})), p, {}),
           "verify grid");
    const Report fine = verified(text, p, block(p));
    const double h = fine.bead_height_min_mm;
    ASSERT_GT(h, 0.0) << report_text(fine);
    EXPECT_LE(fine.voxel_mm, h / 1.25);
    VerifySettings coarse;
    for (const double v : {1e9, 1.3 * h / 1.25}) {
        coarse.voxel_mm = v;
        unseen(verify_program(text, block(p), p, coarse), "--voxel");
    }
    coarse.voxel_mm = 0.95 * h / 1.25;
    const Report just = verified(text, p, block(p), coarse);
    EXPECT_TRUE(just.passed()) << report_text(just);
    EXPECT_FALSE(just.deposits_nothing());
}

// -700 W laser power and 800 g/min powder on a machine whose maximum is 30, in gm's columns
// and in LinuxCNC's codes; a feed above the machine's maximum.
TEST(VerifyChecks, ValuesOutsideTheMachinesRangesFail) {
    const machine::Profiles gm = load("reference_lmd.toml");
    std::string text = clean_block(gm, ProgramDialect::kGm);
    const std::string on =
        fmt::format("{:.2f} {:.2f} ", gm.process.laser_power_w, gm.process.powder_feed_g_min);
    for (const std::string& bad : {std::string("-700.00 8.00 "), std::string("700.00 800.00 ")}) {
        SCOPED_TRACE(bad);
        std::string t = text;
        const std::size_t at = t.find(on);
        ASSERT_NE(at, std::string::npos);
        t.replace(at, on.size(), bad);
        const int line = static_cast<int>(std::count(t.begin(), t.begin() + at, '\n')) + 1;
        const Report r = verified(t, gm, block(gm));
        EXPECT_FALSE(r.passed()) << report_text(r);
        EXPECT_EQ(r.out_of_range.count, 1U);
        ASSERT_TRUE(r.out_of_range.first);
        EXPECT_EQ(r.out_of_range.first->line, line);
        EXPECT_TRUE(failed(r, "out_of_range"));
    }
    const machine::Profiles lc = load("linuxcnc_generic.toml");
    std::string ngc = clean_block(lc, ProgramDialect::kLinuxCnc);
    const std::string power = fmt::format("M68 E0 Q{:.2f}", lc.process.laser_power_w);
    for (std::size_t at = ngc.find(power); at != std::string::npos; at = ngc.find(power)) {
        ngc.replace(at, power.size(), "M68 E0 Q-700.00");
    }
    const Report negative = verified(ngc, lc, block(lc));
    EXPECT_EQ(negative.out_of_range.count, static_cast<std::size_t>(kLayers));
    EXPECT_NE(negative.out_of_range.first->detail.find("-700.00 W"), std::string::npos);
    EXPECT_FALSE(negative.passed());
    const std::string feed = fmt::format("F{:.1f}", lc.process.deposition_feed_mm_min);
    std::string fast = clean_block(lc, ProgramDialect::kLinuxCnc);
    fast.replace(fast.find(feed), feed.size(),
                 fmt::format("F{:.1f}", 2.0 * lc.machine.feed_max_mm_min));
    EXPECT_GE(verified(fast, lc, block(lc)).out_of_range.count, 1U);
}

// A program checked against the wrong part: safe, but it does not build that part.
TEST(VerifyChecks, AProgramOfAnotherPartDoesNotMatch) {
    const machine::Profiles p = load("reference_lmd.toml");
    const std::string text = clean_block(p, ProgramDialect::kGm);
    const Report other = verified(text, p, placed(p, test::box({0, 0, 0}, {40, 20, 8})));
    EXPECT_TRUE(other.passed()) << report_text(other);
    EXPECT_TRUE(other.coverage_judged());
    EXPECT_FALSE(other.matches_part()) << report_text(other);
    EXPECT_TRUE(failed(other, "coverage"));
    EXPECT_TRUE(failed(other, "excess"));
    EXPECT_NE(report_text(other).find("part match      no"), std::string::npos);
    const auto j = nlohmann::json::parse(report_json(other));
    EXPECT_FALSE(j.at("passed").get<bool>());
    EXPECT_TRUE(j.at("safe").get<bool>());
    EXPECT_FALSE(j.at("matches_part").get<bool>());
    // Stated thresholds: the same figures pass a looser bound.
    VerifySettings loose;
    loose.min_coverage = 0.0;
    loose.max_excess = 10.0;
    EXPECT_TRUE(
        verified(text, p, placed(p, test::box({0, 0, 0}, {40, 20, 8})), loose).matches_part());
    VerifySettings wrong;
    wrong.min_coverage = 1.5;
    EXPECT_FALSE(verify_program(text, block(p), p, wrong));
}

// A model whose inside the verifier cannot tell (open, or with a body inside out) is not
// judged on coverage and excess: the report says so and the program is not failed for them.
TEST(VerifyChecks, CoverageIsNotJudgedOnAModelWithABodyInsideOut) {
    const machine::Profiles p = load("reference_lmd.toml");
    const std::string text = clean_block(p, ProgramDialect::kGm);
    // The block and, beside it, a second box turned inside out.
    const mesh::TriangleMesh two =
        placed(p, test::merged(test::box({0, 0, 0}, {2 * kHalf, 2 * kHalf, kLayers * 0.5}),
                               test::inverted(test::box({40, 0, 0}, {50, 10, 6}))));
    const Report r = verified(text, p, two);
    EXPECT_GT(r.model_inverted_columns, 0U) << report_text(r);
    EXPECT_FALSE(r.coverage_judged());
    EXPECT_TRUE(r.matches_part()) << report_text(r);
    EXPECT_NE(report_text(r).find("inside out"), std::string::npos);
    EXPECT_NE(report_text(r).find("not judged"), std::string::npos);
    // A closed, well-oriented model has no such column.
    EXPECT_EQ(verified(text, p, block(p)).model_inverted_columns, 0U);
}

}  // namespace
}  // namespace maxslice::verify
