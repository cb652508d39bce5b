#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "maxslice/machine/profile.hpp"

namespace maxslice::machine {
namespace {

namespace fs = std::filesystem;

const fs::path kProfilesDir = fs::path(MAXSLICE_SOURCE_DIR) / "examples" / "profiles";

constexpr std::string_view kMachine = R"(
[machine]
name = "test"
kinematics = "xyz"
dialect = "gm"
feed_min_mm_min = 1.0
feed_max_mm_min = 5000.0
laser_power_min_w = 0.0
laser_power_max_w = 1000.0
powder_feed_max_g_min = 20.0

[machine.axes]
X = { min = -100.0, max = 100.0 }
Y = { min = -100.0, max = 100.0 }
Z = { min = 0.0, max = 200.0 }

[machine.codes]
laser_on = "M8"
laser_off = "M9"
powder_on = ""
powder_off = ""
)";

constexpr std::string_view kProcess = R"(
[process]
track_width_mm = 2.5
layer_height_mm = 0.5
h_min_mm = 0.3
h_max_mm = 0.7
overlap = 0.3
contour_passes = 1
laser_power_w = 700.0
laser_power_off_w = 0.0
powder_feed_g_min = 8.0
deposition_feed_mm_min = 381.0
travel_feed_mm_min = 2540.0
dwell_after_laser_on_ms = 500.0
self_supporting_angle_deg = 20.0
)";

// Values away from NozzleProfile's defaults, so a key read into the wrong member shows.
constexpr std::string_view kNozzle = R"(
[machine.nozzle]
half_angle_deg = 25.0
cone_length_mm = 45.0
standoff_mm = 9.0
body_radius_mm = 30.0
body_length_mm = 120.0
clearance_mm = 1.5
)";

// Values away from TableProfile's defaults, so a key read into the wrong member shows.
constexpr std::string_view kTable = R"(
[machine.table]
pivot = [1.5, -2.5, -75.0]
c_offset = [0.25, -0.5]
a_direction = -1
c_direction = 1
retract_mm = 15.0
)";

std::string fmt_line(std::string_view key, std::string_view value) {
    return std::string(key) + " = \"" + std::string(value) + "\"";
}

std::string fmt_axis(std::string_view name, double lo, double hi) {
    return std::string(name) + " = { min = " + std::to_string(lo) +
           ", max = " + std::to_string(hi) + " }";
}

std::string base() {
    return std::string(kMachine) + std::string(kProcess);
}

std::string base_with_nozzle() {
    return std::string(kMachine) + std::string(kNozzle) + std::string(kProcess);
}

// The base text with one line replaced (the whole line starting with `key =`).
std::string with(std::string text, const std::string& key, const std::string& line) {
    const std::size_t at = text.find("\n" + key + " = ");
    EXPECT_NE(at, std::string::npos) << key;
    const std::size_t end = text.find('\n', at + 1);
    return text.replace(at + 1, end - at - 1, line);
}

std::string without(const std::string& text, const std::string& key) {
    std::string out = with(text, key, "");
    return out;
}

// Parses the text and expects an kInvalidInput error whose message holds every fragment.
void expect_refused(const std::string& text, const std::vector<std::string>& fragments) {
    const auto r = parse_profile(text, "test.toml");
    ASSERT_FALSE(r.has_value()) << "accepted, expected an error with " << fragments.front();
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    EXPECT_EQ(r.error().context, "profile test.toml");
    for (const auto& f : fragments) {
        EXPECT_NE(r.error().message.find(f), std::string::npos)
            << "`" << f << "` not in: " << r.error().describe();
    }
}

TEST(Profile, ReferenceExampleHasTheReferenceProcess) {
    const fs::path file = kProfilesDir / "reference_lmd.toml";
    const auto r = load_profiles(std::span(&file, 1));
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    const ProcessProfile& p = r->process;
    EXPECT_DOUBLE_EQ(p.laser_power_w, 700.0);
    EXPECT_DOUBLE_EQ(p.laser_power_off_w, 0.0);
    EXPECT_DOUBLE_EQ(p.powder_feed_g_min, 8.0);
    EXPECT_DOUBLE_EQ(p.deposition_feed_mm_min, 381.0);
    EXPECT_DOUBLE_EQ(p.travel_feed_mm_min, 2540.0);
    EXPECT_DOUBLE_EQ(p.track_width_mm, 2.5);
    EXPECT_DOUBLE_EQ(p.layer_height_mm, 0.5);
    EXPECT_LE(p.h_min_mm, p.layer_height_mm);
    EXPECT_GE(p.h_max_mm, p.layer_height_mm);
    EXPECT_FALSE(p.powder_catch_efficiency.has_value());
    const MachineProfile& m = r->machine;
    EXPECT_EQ(m.dialect, Dialect::kGm);
    EXPECT_EQ(m.kinematics, Kinematics::kXyz);
    ASSERT_EQ(m.axes.size(), 3u);
    for (const char* axis : {"X", "Y", "Z"}) {
        const AxisLimits* a = m.find_axis(axis);
        ASSERT_NE(a, nullptr) << axis;
        EXPECT_GE(a->max - a->min, 500.0) << axis;
    }
    EXPECT_EQ(m.find_axis("A"), nullptr);
    EXPECT_EQ(m.codes.laser_on.blocks, std::vector<std::string>{"M8"});
    EXPECT_EQ(m.codes.laser_off.blocks, std::vector<std::string>{"M9"});
    EXPECT_TRUE(m.codes.powder_on.blocks.empty());
}

TEST(Profile, LinuxCncExampleUsesDigitalOutputs) {
    const auto r = read_profile(kProfilesDir / "linuxcnc_generic.toml");
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    ASSERT_TRUE(r->machine && r->process);
    EXPECT_EQ(r->machine->dialect, Dialect::kLinuxCnc);
    const auto& c = r->machine->codes;
    const auto has = [](const CodeTemplate& t, const std::string& block) {
        return std::find(t.blocks.begin(), t.blocks.end(), block) != t.blocks.end();
    };
    EXPECT_TRUE(has(c.laser_on, "M64 P0"));
    EXPECT_TRUE(has(c.laser_off, "M65 P0"));
    EXPECT_TRUE(has(c.powder_on, "M64 P1"));
    EXPECT_TRUE(has(c.powder_off, "M65 P1"));
    EXPECT_TRUE(check_compatible(*r->machine, *r->process).has_value());
}

TEST(Profile, BaseTextIsValid) {
    const auto r = parse_profile(base(), "test.toml");
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    EXPECT_TRUE(r->machine.has_value());
    EXPECT_TRUE(r->process.has_value());
}

TEST(Profile, IntegersAreAcceptedForNumbers) {
    const auto r = parse_profile(with(base(), "track_width_mm", "track_width_mm = 3"), "t");
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    EXPECT_DOUBLE_EQ(r->process->track_width_mm, 3.0);
}

TEST(Profile, CatchEfficiencyIsOptional) {
    const auto r = parse_profile(base() + "powder_catch_efficiency = 0.6\n", "test.toml");
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    ASSERT_TRUE(r->process->powder_catch_efficiency.has_value());
    EXPECT_DOUBLE_EQ(*r->process->powder_catch_efficiency, 0.6);
    expect_refused(base() + "powder_catch_efficiency = 1.5\n",
                   {"process.powder_catch_efficiency = 1.5", "(0, 1]"});
}

TEST(Profile, FootingIsOptional) {
    const auto dflt = parse_profile(base(), "test.toml");
    ASSERT_TRUE(dflt.has_value()) << dflt.error().describe();
    EXPECT_DOUBLE_EQ(dflt->process->footing_mm, 1.0);
    const auto off = parse_profile(base() + "footing_mm = 0\n", "test.toml");
    ASSERT_TRUE(off.has_value()) << off.error().describe();
    EXPECT_DOUBLE_EQ(off->process->footing_mm, 0.0);
    const auto r = parse_profile(base() + "footing_mm = 2.5\n", "test.toml");
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    EXPECT_DOUBLE_EQ(r->process->footing_mm, 2.5);
    expect_refused(base() + "footing_mm = -0.5\n", {"process.footing_mm = -0.5", "[0, 50] mm"});
    expect_refused(base() + "footing_mm = 80\n", {"process.footing_mm = 80", "[0, 50] mm"});
}

// The near-net shape's keys (decision 0025): optional, 0 = off, ranges checked; the finer
// processes inherit them and cannot set their own.
TEST(Profile, NearNetKeysAreOptionalCheckedAndInherited) {
    const auto dflt = parse_profile(base(), "test.toml");
    ASSERT_TRUE(dflt.has_value()) << dflt.error().describe();
    EXPECT_EQ(dflt->process->machining_stock_mm, 0.0);
    EXPECT_EQ(dflt->process->fill_below_mm, 0.0);
    std::string finer(kProcess);
    finer = with(finer, "track_width_mm", "track_width_mm = 1.0");
    finer = with(finer, "layer_height_mm", "layer_height_mm = 0.25");
    finer = with(finer, "h_min_mm", "h_min_mm = 0.1");
    finer.replace(finer.find("[process]"), 9, "[[process.finer]]");
    const std::string on = base() + "machining_stock_mm = 1.5\nfill_below_mm = 8\n";
    const auto r = parse_profile(on + finer, "test.toml");
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    EXPECT_DOUBLE_EQ(r->process->machining_stock_mm, 1.5);
    EXPECT_DOUBLE_EQ(r->process->fill_below_mm, 8.0);
    ASSERT_EQ(r->process->finer.size(), 1u);
    const auto fine = with_finer_process({*r->machine, *r->process}, 1);
    ASSERT_TRUE(fine.has_value()) << fine.error().describe();
    EXPECT_DOUBLE_EQ(fine->process.machining_stock_mm, 1.5);
    EXPECT_DOUBLE_EQ(fine->process.fill_below_mm, 8.0);
    expect_refused(base() + "machining_stock_mm = -1\n",
                   {"process.machining_stock_mm = -1", "[0, 20] mm"});
    expect_refused(base() + "machining_stock_mm = 25\n", {"process.machining_stock_mm = 25"});
    expect_refused(base() + "fill_below_mm = 200\n", {"process.fill_below_mm = 200", "[0, 100]"});
    const auto own = parse_profile(on + finer + "machining_stock_mm = 0.5\n", "test.toml");
    ASSERT_FALSE(own.has_value());
    EXPECT_NE(own.error().describe().find("belongs to [process] only"), std::string::npos)
        << own.error().describe();
}

TEST(Profile, SpeedLawIsReadAndChecked) {
    const auto r = parse_profile(
        base() + "speed_height = [[250, 0.72], [381.0, 0.5], [650.0, 0.3]]\n", "test.toml");
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    ASSERT_EQ(r->process->speed_height.size(), 3u);
    EXPECT_DOUBLE_EQ(r->process->speed_height[0].feed_mm_min, 250.0);
    EXPECT_DOUBLE_EQ(r->process->speed_height[2].height_mm, 0.3);
    expect_refused(base() + "speed_height = [[381.0, 0.5]]\n", {"process.speed_height", "2 to 64"});
    expect_refused(base() + "speed_height = [[250, 0.72], [381.0]]\n",
                   {"process.speed_height[1]", "pair of numbers"});
    expect_refused(base() + "speed_height = [[250, 0.72], [200.0, 0.5]]\n",
                   {"process.speed_height[1]", "feeds must increase"});
    expect_refused(base() + "speed_height = [[250, 0.9], [381.0, 0.6]]\n",
                   {"process.speed_height", "must agree"});
}

TEST(Profile, MissingKeyIsNamed) {
    expect_refused(without(base(), "track_width_mm"),
                   {"missing key", "process.track_width_mm", "(0, 50] mm"});
    expect_refused(without(base(), "dialect"), {"missing key", "machine.dialect"});
    expect_refused(without(base(), "laser_on"), {"missing key", "machine.codes.laser_on"});
    expect_refused(without(base(), "Z"), {"missing key", "machine.axes.Z"});
}

TEST(Profile, NegativeWidthIsRefused) {
    expect_refused(with(base(), "track_width_mm", "track_width_mm = -2.5"),
                   {"process.track_width_mm = -2.5", "out of range", "(0, 50] mm"});
}

TEST(Profile, OverlapOfOneIsRefused) {
    expect_refused(with(base(), "overlap", "overlap = 1.0"), {"process.overlap = 1", "[0, 1)"});
    expect_refused(with(base(), "overlap", "overlap = -0.1"), {"process.overlap = -0.1"});
}

TEST(Profile, UnknownDialectIsRefused) {
    expect_refused(
        with(base(), "dialect", "dialect = \"heidenhain\""),
        {"machine.dialect = \"heidenhain\"", "\"gm\"", "\"linuxcnc\"", "\"fanuc\"", "\"siemens\""});
}

TEST(Profile, EveryDialectParsesBackFromItsName) {
    for (const Dialect d : {Dialect::kGm, Dialect::kLinuxCnc, Dialect::kFanuc, Dialect::kSiemens}) {
        EXPECT_EQ(parse_dialect(dialect_name(d)), d);
    }
    EXPECT_FALSE(parse_dialect("Fanuc").has_value());
    EXPECT_FALSE(parse_dialect("").has_value());
    EXPECT_FALSE(parse_dialect("gm ").has_value());
}

TEST(Profile, DialectsWithoutAPowerColumnNeedLaserCodes) {
    for (const char* dialect : {"fanuc", "siemens"}) {
        std::string text = with(base(), "dialect", std::string("dialect = \"") + dialect + "\"");
        text = with(text, "laser_on", "laser_on = \"\"");
        expect_refused(text, {"machine.codes.laser_on", dialect});
    }
}

TEST(Profile, LayerAboveTrackWidthIsRefused) {
    std::string text = with(base(), "h_max_mm", "h_max_mm = 4.0");
    text = with(text, "layer_height_mm", "layer_height_mm = 3.0");
    expect_refused(text, {"process.layer_height_mm = 3", "process.track_width_mm = 2.5"});
}

TEST(Profile, UnknownKeyIsNamedWithASuggestion) {
    expect_refused(with(base(), "track_width_mm", "trak_width_mm = 2.5"),
                   {"unknown key `process.trak_width_mm`", "did you mean `track_width_mm`"});
    expect_refused(base() + "colour = \"red\"\n", {"unknown key `process.colour`"});
    expect_refused(with(base(), "name", "nmae = \"x\""), {"machine.nmae", "did you mean `name`"});
    expect_refused(base() + "[proces]\n", {"unknown key `proces`", "did you mean `process`"});
    expect_refused(with(base(), "X", "X = { min = -100.0, maximum = 100.0 }"),
                   {"machine.axes.X.maximum", "did you mean `max`"});
    expect_refused(with(base(), "laser_on", "laser_onn = \"M8\""),
                   {"machine.codes.laser_onn", "did you mean `laser_on`"});
}

TEST(Profile, HMinAboveHMaxIsRefused) {
    expect_refused(with(base(), "h_min_mm", "h_min_mm = 0.8"),
                   {"process.h_min_mm = 0.8", "process.h_max_mm = 0.7"});
}

TEST(Profile, LayerOutsideHRangeIsRefused) {
    expect_refused(with(base(), "layer_height_mm", "layer_height_mm = 0.2"),
                   {"process.layer_height_mm = 0.2", "process.h_min_mm"});
}

TEST(Profile, OtherRangesAndTypes) {
    expect_refused(with(base(), "deposition_feed_mm_min", "deposition_feed_mm_min = 0"),
                   {"process.deposition_feed_mm_min = 0", "mm/min"});
    expect_refused(with(base(), "travel_feed_mm_min", "travel_feed_mm_min = \"fast\""),
                   {"process.travel_feed_mm_min", "must be a number", "\"fast\""});
    expect_refused(with(base(), "laser_power_w", "laser_power_w = nan"),
                   {"process.laser_power_w = nan", "not a finite number"});
    expect_refused(with(base(), "contour_passes", "contour_passes = 1.5"),
                   {"process.contour_passes", "must be an integer"});
    expect_refused(with(base(), "contour_passes", "contour_passes = -1"),
                   {"process.contour_passes = -1"});
    expect_refused(with(base(), "self_supporting_angle_deg", "self_supporting_angle_deg = 90"),
                   {"process.self_supporting_angle_deg = 90", "[0, 90) deg"});
    expect_refused(with(base(), "laser_power_off_w", "laser_power_off_w = 800"),
                   {"process.laser_power_off_w = 800", "process.laser_power_w = 700"});
    expect_refused(with(base(), "feed_min_mm_min", "feed_min_mm_min = 6000"),
                   {"machine.feed_min_mm_min = 6000", "machine.feed_max_mm_min = 5000"});
    expect_refused(with(base(), "name", "name = \"\""), {"machine.name"});
}

TEST(Profile, UnknownKinematicsIsRefused) {
    expect_refused(with(base(), "kinematics", "kinematics = \"table_ac\""),
                   {"machine.kinematics = \"table_ac\"", "unknown", "\"xyzac-trt\""});
    expect_refused(with(base(), "kinematics", "kinematics = \"xyzac_trt\""),
                   {"machine.kinematics = \"xyzac_trt\"", "did you mean `xyzac-trt`"});
}

TEST(Profile, XyzTakesNoRotaryAxesAndNoTable) {
    expect_refused(base() + "\n[machine.axes.A]\nmin = -30\nmax = 120\n",
                   {"machine.axes.A", "rotary", "\"xyzac-trt\""});
    expect_refused(base() + std::string(kTable), {"machine.table", "only for", "\"xyz\""});
}

// A tilting-rotary table machine: the base machine with kinematics, rotary axes and a table.
std::string table_base(std::string_view kinematics = "xyzac-trt", std::string_view tilt = "A",
                       std::string_view table = kTable) {
    std::string text = with(base(), "kinematics", fmt_line("kinematics", kinematics));
    text = with(text, "Z",
                fmt_axis("Z", 0.0, 200.0) + "\n" + fmt_axis(tilt, -120.0, 120.0) + "\n" +
                    fmt_axis("C", -3600.0, 3600.0));
    const std::size_t process = text.find("[process]");
    return text.insert(process, std::string(table) + "\n");
}

TEST(Profile, TableTiltMachineIsRead) {
    const auto r = parse_profile(table_base(), "test.toml");
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    const MachineProfile& m = *r->machine;
    EXPECT_EQ(m.kinematics, Kinematics::kTableAc);
    EXPECT_EQ(kinematics_name(m.kinematics), "xyzac-trt");
    EXPECT_TRUE(is_table_tilt(m.kinematics));
    ASSERT_EQ(m.axes.size(), 5u);
    const std::vector<std::string> names{"X", "Y", "Z", "A", "C"};
    for (std::size_t i = 0; i < names.size(); ++i) EXPECT_EQ(m.axes[i].name, names[i]);
    EXPECT_DOUBLE_EQ(m.axes[3].min, -120.0);
    EXPECT_DOUBLE_EQ(m.axes[4].max, 3600.0);
    ASSERT_TRUE(m.table.has_value());
    EXPECT_DOUBLE_EQ(m.table->pivot_mm.x, 1.5);
    EXPECT_DOUBLE_EQ(m.table->pivot_mm.y, -2.5);
    EXPECT_DOUBLE_EQ(m.table->pivot_mm.z, -75.0);
    EXPECT_DOUBLE_EQ(m.table->c_offset_x_mm, 0.25);
    EXPECT_DOUBLE_EQ(m.table->c_offset_y_mm, -0.5);
    EXPECT_EQ(m.table->tilt_direction, -1);
    EXPECT_EQ(m.table->c_direction, 1);
    EXPECT_DOUBLE_EQ(m.table->retract_mm, 15.0);

    std::string bc_table(kTable);
    bc_table.replace(bc_table.find("a_direction"), 1, "b");
    const auto bc = parse_profile(table_base("xyzbc-trt", "B", bc_table), "test.toml");
    ASSERT_TRUE(bc.has_value()) << bc.error().describe();
    EXPECT_EQ(bc->machine->kinematics, Kinematics::kTableBc);
    EXPECT_EQ(bc->machine->axes[3].name, "B");
    EXPECT_EQ(bc->machine->table->tilt_direction, -1);
    // The B/C table names its tilt sign b_direction.
    expect_refused(table_base("xyzbc-trt", "B"),
                   {"unknown key `machine.table.a_direction`", "did you mean `b_direction`"});
}

TEST(Profile, TableTiltNeedsItsAxesAndTable) {
    const std::string text = table_base();
    expect_refused(
        text.substr(0, text.find("[machine.table]")) + text.substr(text.find("[process]")),
        {"missing key `machine.table`", "xyzac-trt"});
    expect_refused(with(text, "C", ""), {"missing key", "machine.axes.C"});
    expect_refused(with(text, "A", ""), {"missing key", "machine.axes.A"});
    expect_refused(with(text, "A", fmt_axis("B", -120.0, 120.0)), {"machine.axes.B", "xyzbc-trt"});
    expect_refused(with(text, "A", "A = { min = -400.0, max = 120.0 }"),
                   {"machine.axes.A.min = -400", "deg"});
    expect_refused(with(text, "C", "C = { min = 10.0, max = -10.0 }"),
                   {"machine.axes.C.min = 10", "machine.axes.C.max = -10"});
}

TEST(Profile, TableKeysAreCheckedAndNamed) {
    const std::string text = table_base();
    for (const std::string key :
         {"pivot", "c_offset", "a_direction", "c_direction", "retract_mm"}) {
        expect_refused(without(text, key), {"missing key", "machine.table." + key});
    }
    expect_refused(with(text, "pivot", "pivot = [1.0, 2.0]"),
                   {"machine.table.pivot", "array of 3 numbers", "2 elements"});
    expect_refused(with(text, "pivot", "pivot = [1.0, \"2\", 3.0]"),
                   {"machine.table.pivot[1]", "must be a number"});
    expect_refused(with(text, "pivot", "pivot = [1.0, 2.0, 1e6]"),
                   {"machine.table.pivot[2]", "out of range"});
    expect_refused(with(text, "c_offset", "c_offset = 3.0"),
                   {"machine.table.c_offset", "array of 2 numbers"});
    expect_refused(with(text, "c_offset", "c_offset = [nan, 0.0]"),
                   {"machine.table.c_offset[0] = nan", "not a finite number"});
    expect_refused(with(text, "a_direction", "a_direction = 0"),
                   {"machine.table.a_direction = 0", "1 or -1"});
    expect_refused(with(text, "c_direction", "c_direction = 1.0"),
                   {"machine.table.c_direction", "must be an integer"});
    expect_refused(with(text, "retract_mm", "retract_mm = 0"),
                   {"machine.table.retract_mm = 0", "(0, 1000] mm"});
    expect_refused(with(text, "retract_mm", "retract_mm = -5"), {"machine.table.retract_mm = -5"});
    expect_refused(with(text, "retract_mm", "retrat_mm = 5"),
                   {"unknown key `machine.table.retrat_mm`", "did you mean `retract_mm`"});
    expect_refused(with(text, "pivot", "pivot = [0, 0, 0]\nspeed = 3"),
                   {"unknown key `machine.table.speed`"});
}

TEST(Profile, ValidateChecksTheTableInCode) {
    const auto r = parse_profile(table_base(), "test.toml");
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    MachineProfile m = *r->machine;
    m.table->c_direction = 2;
    auto ok = validate(m);
    ASSERT_FALSE(ok.has_value());
    EXPECT_NE(ok.error().message.find("machine.table.c_direction = 2"), std::string::npos);
    m = *r->machine;
    m.table.reset();
    ok = validate(m);
    ASSERT_FALSE(ok.has_value());
    EXPECT_NE(ok.error().message.find("machine.table"), std::string::npos);
    m = *r->machine;
    m.axes.pop_back();
    ok = validate(m);
    ASSERT_FALSE(ok.has_value());
    EXPECT_NE(ok.error().message.find("X, Y, Z, A, C"), std::string::npos);
}

TEST(Profile, FiveAxisReferenceExampleLoads) {
    const fs::path file = kProfilesDir / "reference_5axis_ac.toml";
    const auto r = load_profiles(std::span(&file, 1));
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    EXPECT_EQ(r->machine.kinematics, Kinematics::kTableAc);
    ASSERT_TRUE(r->machine.table.has_value());
    EXPECT_GT(r->machine.table->retract_mm, 0.0);
    EXPECT_DOUBLE_EQ(r->process.laser_power_w, 700.0);
    EXPECT_DOUBLE_EQ(r->process.powder_feed_g_min, 8.0);
    const AxisLimits* a = r->machine.find_axis("A");
    ASSERT_NE(a, nullptr);
    EXPECT_DOUBLE_EQ(a->min, -120.0);
    EXPECT_DOUBLE_EQ(a->max, 120.0);
}

TEST(Profile, AxisLimitsAreChecked) {
    expect_refused(with(base(), "Y", "Y = { min = 50.0, max = -50.0 }"),
                   {"machine.axes.Y.min = 50", "machine.axes.Y.max = -50"});
    expect_refused(with(base(), "Y", "Y = { min = -50.0 }"), {"missing key", "machine.axes.Y.max"});
    expect_refused(with(base(), "Y", "Y = 3"), {"machine.axes.Y", "must be a table"});
}

TEST(Profile, TemplatesAreChecked) {
    expect_refused(with(base(), "laser_on", "laser_on = \"M3 S{pwr}\""),
                   {"machine.codes.laser_on[0]", "unknown placeholder {pwr}"});
    expect_refused(with(base(), "laser_on", "laser_on = \"M3 S{power\""),
                   {"machine.codes.laser_on[0]", "without"});
    expect_refused(with(base(), "laser_on", "laser_on = [\"M8\", 3]"),
                   {"machine.codes.laser_on[1]", "must be a string"});
    expect_refused(with(base(), "laser_on", "laser_on = \"M8\\nM3\""),
                   {"machine.codes.laser_on[0]", "line break"});
    expect_refused(with(base(), "laser_on", "laser_on = [\"M8\", \"\"]"),
                   {"machine.codes.laser_on[1]", "empty block"});
    const auto ok = parse_profile(
        with(base(), "laser_on", "laser_on = [\"M3 S{power}\", \"M201 (LASER ON {power_pct})\"]"),
        "t");
    ASSERT_TRUE(ok.has_value()) << ok.error().describe();
    EXPECT_EQ(ok->machine->codes.laser_on.blocks.size(), 2u);
}

// Issue 23: a template that moves the machine was written verbatim and its move never
// replayed (program_end = "G0 X0 Y0 Z0" drove the nozzle through the part, "verified").
// Every key refuses motion, naming the key and the word; switches, dwells, macro calls and
// controller variables stay accepted.
TEST(Profile, TemplatesThatMoveTheMachineAreRefused) {
    const auto codes_with = [&](const std::string& key, const std::string& value) {
        std::string text = base();
        const std::string line = key + " = \"" + value + "\"";
        if (text.find("\n" + key + " = ") != std::string::npos) return with(text, key, line);
        const std::size_t at = text.find("[machine.codes]\n") + 16;
        return text.insert(at, line + "\n");
    };
    const std::vector<std::pair<std::string, std::string>> moving = {
        {"program_end", "G0 X0 Y0 Z0"},  {"laser_on", "M8 G1 X0 Y0 Z0"},
        {"laser_off", "M9 Z50"},         {"program_start", "G28"},
        {"powder_on", "g01x1"},          {"powder_off", "M72 (off) G2 X1 Y1 I1"},
        {"program_end", "G91 Z{power}"}, {"laser_on", "G65 P9011 A{power} G1"},
        {"program_start", "TRANS X10"},  {"laser_off", "M9 (G0 X0 is a comment, C5 is not) C5"},
    };
    for (const auto& [key, block] : moving) {
        SCOPED_TRACE(key + " = " + block);
        const auto r = parse_profile(codes_with(key, block), "test.toml");
        ASSERT_FALSE(r.has_value()) << "accepted";
        EXPECT_NE(r.error().message.find("machine.codes." + key + "["), std::string::npos)
            << r.error().message;
        EXPECT_NE(r.error().message.find("moves the machine"), std::string::npos)
            << r.error().message;
        EXPECT_TRUE(motion_word(block).has_value());
    }
    EXPECT_EQ(motion_word("G0 X0 Y0 Z0").value_or(""), "G0");
    EXPECT_EQ(motion_word("M9 Z50").value_or(""), "Z word");
    for (const std::string block :
         {"M8", "M68 E0 Q{power}", "M64 P0", "G4 P0.5", "G65 P9011 A{power}", "$A_OUTA[1]={power}",
          "M201 (LASER ON {power_pct}, X Y Z)", "o<laser_on> call [{power}]", "TRAORI", "G90 G94",
          "M3 S{power}", "#<_x> = 3", "M9 ; G0 X0",
          // A G number past int's range is no known motion (and reads without overflow).
          "M64 G22222222222222222222222222222222222222222222222222222222222222222 P1"}) {
        SCOPED_TRACE(block);
        EXPECT_FALSE(motion_word(block).has_value()) << *motion_word(block);
        EXPECT_TRUE(parse_profile(codes_with("program_start", block), "test.toml").has_value());
    }
    // The bundled profiles hold no motion in their templates.
    for (const auto& entry : fs::directory_iterator(kProfilesDir)) {
        SCOPED_TRACE(entry.path().string());
        EXPECT_TRUE(read_profile(entry.path()).has_value());
    }
}

TEST(Profile, LinuxCncNeedsLaserCodes) {
    std::string text = with(base(), "dialect", "dialect = \"linuxcnc\"");
    text = with(text, "laser_on", "laser_on = \"\"");
    expect_refused(text, {"machine.codes.laser_on", "linuxcnc"});
}

TEST(Profile, SyntaxErrorsNameTheLine) {
    expect_refused(base() + "oops = = 3\n", {"line "});
    expect_refused("", {"neither"});
    expect_refused("machine = 3\n", {"`machine` must be a table"});
}

TEST(Profile, ExpandBlock) {
    EXPECT_EQ(expand_block("M3 S{power}", 700.0, 8.0, 1000.0), "M3 S700.00");
    EXPECT_EQ(expand_block("M201 (LASER ON {power_pct})", 700.0, 8.0, 1000.0),
              "M201 (LASER ON 70.00)");
    EXPECT_EQ(expand_block("M68 E1 Q{powder}", 700.0, 8.0, 1000.0), "M68 E1 Q8.00");
    EXPECT_EQ(expand_block("M64 P0", 700.0, 8.0, 1000.0), "M64 P0");
}

TEST(Profile, NozzleTableIsRead) {
    const auto r = parse_profile(base_with_nozzle(), "test.toml");
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    ASSERT_TRUE(r->machine->nozzle.has_value());
    const NozzleProfile& n = *r->machine->nozzle;
    EXPECT_DOUBLE_EQ(n.half_angle_deg, 25.0);
    EXPECT_DOUBLE_EQ(n.cone_length_mm, 45.0);
    EXPECT_DOUBLE_EQ(n.standoff_mm, 9.0);
    EXPECT_DOUBLE_EQ(n.body_radius_mm, 30.0);
    EXPECT_DOUBLE_EQ(n.body_length_mm, 120.0);
    EXPECT_DOUBLE_EQ(n.clearance_mm, 1.5);
}

TEST(Profile, AbsentNozzleTableIsUnset) {
    const auto r = parse_profile(base(), "test.toml");
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    EXPECT_FALSE(r->machine->nozzle.has_value());
}

TEST(Profile, NozzleAcceptsIntegersNoBodyAndASlimBody) {
    std::string text = with(base_with_nozzle(), "half_angle_deg", "half_angle_deg = 30");
    text = with(text, "body_radius_mm", "body_radius_mm = 0");
    text = with(text, "body_length_mm", "body_length_mm = 0.0");
    text = with(text, "clearance_mm", "clearance_mm = 0");
    const auto none = parse_profile(text, "t");
    ASSERT_TRUE(none.has_value()) << none.error().describe();
    EXPECT_DOUBLE_EQ(none->machine->nozzle->half_angle_deg, 30.0);
    EXPECT_DOUBLE_EQ(none->machine->nozzle->body_radius_mm, 0.0);
    // A body narrower than the cone's top (45 mm x tan 25 deg = 21 mm) is allowed.
    const auto slim =
        parse_profile(with(base_with_nozzle(), "body_radius_mm", "body_radius_mm = 5"), "t");
    ASSERT_TRUE(slim.has_value()) << slim.error().describe();
    EXPECT_DOUBLE_EQ(slim->machine->nozzle->body_radius_mm, 5.0);
}

TEST(Profile, NozzleRangeViolationsNameTheKey) {
    struct Case {
        std::string key;
        std::string value;
        std::string range;
    };
    const std::vector<Case> cases{
        {"half_angle_deg", "0", "(0, 85] deg"},      {"half_angle_deg", "90", "(0, 85] deg"},
        {"half_angle_deg", "-30", "(0, 85] deg"},    {"cone_length_mm", "0", "(0, 1000] mm"},
        {"cone_length_mm", "45000", "(0, 1000] mm"}, {"standoff_mm", "0", "(0, 1000] mm"},
        {"standoff_mm", "-9", "(0, 1000] mm"},       {"body_radius_mm", "-30", "[0, 1000] mm"},
        {"body_radius_mm", "30000", "[0, 1000] mm"}, {"body_length_mm", "-120", "[0, 1000] mm"},
        {"body_length_mm", "1200", "[0, 1000] mm"},  {"clearance_mm", "-1", "[0, 50] mm"},
        {"clearance_mm", "60", "[0, 50] mm"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.key + " = " + c.value);
        expect_refused(with(base_with_nozzle(), c.key, c.key + " = " + c.value),
                       {"machine.nozzle." + c.key + " = " + c.value, "out of range", c.range});
    }
    expect_refused(with(base_with_nozzle(), "half_angle_deg", "half_angle_deg = nan"),
                   {"machine.nozzle.half_angle_deg = nan", "not a finite number"});
}

TEST(Profile, NozzleCrossChecksNameBothKeys) {
    expect_refused(with(base_with_nozzle(), "standoff_mm", "standoff_mm = 50"),
                   {"machine.nozzle.standoff_mm = 50", "machine.nozzle.cone_length_mm = 45"});
    expect_refused(with(base_with_nozzle(), "body_length_mm", "body_length_mm = 0"),
                   {"machine.nozzle.body_radius_mm = 30", "machine.nozzle.body_length_mm = 0"});
    expect_refused(with(base_with_nozzle(), "body_radius_mm", "body_radius_mm = 0"),
                   {"machine.nozzle.body_radius_mm = 0", "machine.nozzle.body_length_mm = 120"});
    // The tip may sit at the cone's end.
    const auto at_end =
        parse_profile(with(base_with_nozzle(), "standoff_mm", "standoff_mm = 45"), "t");
    EXPECT_TRUE(at_end.has_value()) << at_end.error().describe();
}

TEST(Profile, ValidateChecksTheNozzle) {
    const auto r = parse_profile(base_with_nozzle(), "t");
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    MachineProfile m = *r->machine;
    ASSERT_TRUE(validate(m).has_value());
    m.nozzle->standoff_mm = 60.0;
    const auto standoff = validate(m);
    ASSERT_FALSE(standoff.has_value());
    EXPECT_NE(standoff.error().message.find("machine.nozzle.standoff_mm = 60"), std::string::npos)
        << standoff.error().describe();
    m.nozzle = NozzleProfile{};
    m.nozzle->clearance_mm = -0.5;
    const auto clearance = validate(m);
    ASSERT_FALSE(clearance.has_value());
    EXPECT_NE(clearance.error().message.find("machine.nozzle.clearance_mm = -0.5"),
              std::string::npos)
        << clearance.error().describe();
    m.nozzle.reset();
    EXPECT_TRUE(validate(m).has_value());
    // The defaults the planner falls back on are themselves a valid nozzle.
    m.nozzle = NozzleProfile{};
    EXPECT_TRUE(validate(m).has_value());
}

TEST(Profile, NozzleMissingUnknownAndMistypedKeys) {
    expect_refused(without(base_with_nozzle(), "standoff_mm"),
                   {"missing key", "machine.nozzle.standoff_mm", "(0, 1000] mm"});
    expect_refused(without(base_with_nozzle(), "clearance_mm"),
                   {"missing key", "machine.nozzle.clearance_mm", "[0, 50] mm"});
    expect_refused(with(base_with_nozzle(), "standoff_mm", "standof_mm = 9.0"),
                   {"unknown key `machine.nozzle.standof_mm`", "did you mean `standoff_mm`"});
    expect_refused(
        with(base_with_nozzle(), "clearance_mm", "clearance_mm = 1.5\ncolour = 3"),
        {"unknown key `machine.nozzle.colour`", "allowed in [machine.nozzle]", "half_angle_deg"});
    expect_refused(with(base_with_nozzle(), "half_angle_deg", "half_angle_deg = \"30\""),
                   {"machine.nozzle.half_angle_deg", "must be a number", "\"30\""});
    expect_refused(with(base(), "name", "name = \"test\"\nnozzle = 3"),
                   {"`machine.nozzle` must be a table", "an integer"});
    expect_refused(with(base(), "name", "name = \"test\"\nnozle = 3"),
                   {"unknown key `machine.nozle`", "did you mean `nozzle`"});
}

// [machine.substrate]: optional; when there, every size is required and positive.
TEST(Profile, SubstrateTableIsReadAndChecked) {
    const std::string plate =
        "\n[machine.substrate]\nsize_x_mm = 150\nsize_y_mm = 120.5\nthickness_mm = 12\n";
    const std::string text = std::string(kMachine) + plate + std::string(kProcess);
    const auto r = parse_profile(text, "test.toml");
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    ASSERT_TRUE(r->machine->substrate.has_value());
    EXPECT_DOUBLE_EQ(r->machine->substrate->size_x_mm, 150.0);
    EXPECT_DOUBLE_EQ(r->machine->substrate->size_y_mm, 120.5);
    EXPECT_DOUBLE_EQ(r->machine->substrate->thickness_mm, 12.0);
    const auto none = parse_profile(base(), "test.toml");
    ASSERT_TRUE(none.has_value()) << none.error().describe();
    EXPECT_FALSE(none->machine->substrate.has_value());

    expect_refused(with(text, "size_y_mm", "size_y_mm = -5"),
                   {"machine.substrate.size_y_mm = -5", "out of range", "(0, 10000] mm"});
    expect_refused(with(text, "thickness_mm", "thickness_mm = 0"),
                   {"machine.substrate.thickness_mm = 0", "out of range"});
    expect_refused(without(text, "size_x_mm"), {"missing key", "machine.substrate.size_x_mm"});
    expect_refused(with(text, "thickness_mm", "thickness_mm = 12\nsize_z_mm = 3"),
                   {"unknown key `machine.substrate.size_z_mm`"});
    expect_refused(with(base(), "name", "name = \"test\"\nsubstrate = 3"),
                   {"`machine.substrate` must be a table"});
    // validate() checks a substrate set in code.
    MachineProfile m = *r->machine;
    m.substrate->size_x_mm = 0.0;
    const auto bad = validate(m);
    ASSERT_FALSE(bad.has_value());
    EXPECT_NE(bad.error().message.find("machine.substrate.size_x_mm"), std::string::npos);
}

TEST(Profile, ShippedProfilesCarryANozzle) {
    for (const char* name : {"reference_lmd.toml", "linuxcnc_generic.toml"}) {
        SCOPED_TRACE(name);
        const auto r = read_profile(kProfilesDir / name);
        ASSERT_TRUE(r.has_value()) << r.error().describe();
        ASSERT_TRUE(r->machine.has_value());
        ASSERT_TRUE(r->machine->nozzle.has_value());
        const NozzleProfile& n = *r->machine->nozzle;
        EXPECT_LE(n.standoff_mm, n.cone_length_mm);
        EXPECT_GT(n.body_radius_mm, 0.0);
        EXPECT_GT(n.body_length_mm, 0.0);
    }
    // The reference LENS-type coaxial head (nominal values).
    const auto ref = read_profile(kProfilesDir / "reference_lmd.toml");
    ASSERT_TRUE(ref.has_value()) << ref.error().describe();
    const NozzleProfile& n = ref->machine->nozzle.value();
    EXPECT_DOUBLE_EQ(n.half_angle_deg, 30.0);
    EXPECT_DOUBLE_EQ(n.cone_length_mm, 45.0);
    EXPECT_DOUBLE_EQ(n.standoff_mm, 9.0);
    EXPECT_DOUBLE_EQ(n.body_radius_mm, 30.0);
    EXPECT_DOUBLE_EQ(n.body_length_mm, 120.0);
    EXPECT_DOUBLE_EQ(n.clearance_mm, 1.0);
}

class ProfileFiles : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::path(::testing::TempDir()) /
               ("maxslice_profile_" +
                std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path write(const std::string& name, std::string_view text) {
        const fs::path p = dir_ / name;
        std::ofstream(p) << text;
        return p;
    }
    fs::path dir_;
};

TEST_F(ProfileFiles, MachineAndProcessInSeparateFiles) {
    const std::vector<fs::path> files{write("m.toml", kMachine), write("p.toml", kProcess)};
    const auto r = load_profiles(files);
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    EXPECT_EQ(r->machine.name, "test");
    EXPECT_DOUBLE_EQ(r->process.laser_power_w, 700.0);
    const std::vector<fs::path> reversed{files[1], files[0]};
    EXPECT_TRUE(load_profiles(reversed).has_value());
}

TEST_F(ProfileFiles, EachTableExactlyOnce) {
    const std::vector<fs::path> only_machine{write("m.toml", kMachine)};
    const auto missing = load_profiles(only_machine);
    ASSERT_FALSE(missing.has_value());
    EXPECT_NE(missing.error().message.find("no [process]"), std::string::npos);

    const std::vector<fs::path> twice{write("both.toml", base()), write("p.toml", kProcess)};
    const auto dup = load_profiles(twice);
    ASSERT_FALSE(dup.has_value());
    EXPECT_NE(dup.error().message.find("[process] is given in both"), std::string::npos);
}

TEST_F(ProfileFiles, IncompatiblePairIsRefused) {
    const std::string text = with(base(), "feed_max_mm_min", "feed_max_mm_min = 2000.0");
    const std::vector<fs::path> files{write("slow.toml", text)};
    const auto r = load_profiles(files);
    ASSERT_FALSE(r.has_value());
    EXPECT_NE(r.error().message.find("process.travel_feed_mm_min = 2540"), std::string::npos)
        << r.error().describe();
    EXPECT_NE(r.error().message.find("machine.feed_max_mm_min"), std::string::npos);
}

TEST_F(ProfileFiles, MissingFileIsAnIoError) {
    const auto r = read_profile(dir_ / "nope.toml");
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().code, core::ErrorCode::kIo);
}

TEST_F(ProfileFiles, ErrorsNameTheFile) {
    const fs::path file = write("bad.toml", with(base(), "overlap", "overlap = 1.0"));
    const auto r = read_profile(file);
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().context, "profile " + file.string());
}

// [[process.finer]]: whole processes with narrower tracks, read and checked like [process]
// (decision 0019).
TEST(Profile, FinerProcessesAreReadAndChecked) {
    // The base process with another track and layer, as a finer one.
    const auto finer = [](std::string_view track, std::string_view layer) {
        std::string p(kProcess);
        p = with(p, "track_width_mm", "track_width_mm = " + std::string(track));
        p = with(p, "layer_height_mm", "layer_height_mm = " + std::string(layer));
        p = with(p, "h_min_mm", "h_min_mm = 0.1");
        p.replace(p.find("[process]"), 9, "[[process.finer]]");
        return p;
    };
    const auto r = parse_profile(base() + finer("1.0", "0.25") + finer("0.6", "0.2"), "t.toml");
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    const ProcessProfile& p = *r->process;
    EXPECT_DOUBLE_EQ(p.track_width_mm, 2.5);
    ASSERT_EQ(p.finer.size(), 2u);
    EXPECT_DOUBLE_EQ(p.finer[0].track_width_mm, 1.0);
    EXPECT_DOUBLE_EQ(p.finer[0].layer_height_mm, 0.25);
    EXPECT_DOUBLE_EQ(p.finer[1].track_width_mm, 0.6);
    EXPECT_DOUBLE_EQ(p.finer[1].laser_power_w, 700.0);
    EXPECT_TRUE(p.finer[0].finer.empty());

    // Picking one: its process, no finer ones left; 0 the main one; others refused.
    const Profiles both{*r->machine, p};
    const auto second = with_finer_process(both, 2);
    ASSERT_TRUE(second.has_value()) << second.error().describe();
    EXPECT_DOUBLE_EQ(second->process.track_width_mm, 0.6);
    EXPECT_TRUE(second->process.finer.empty());
    const auto main = with_finer_process(both, 0);
    ASSERT_TRUE(main.has_value());
    EXPECT_DOUBLE_EQ(main->process.track_width_mm, 2.5);
    EXPECT_TRUE(main->process.finer.empty());
    for (const int n : {3, -1}) {
        const auto none = with_finer_process(both, n);
        ASSERT_FALSE(none.has_value()) << n;
        EXPECT_NE(none.error().message.find("has 2"), std::string::npos) << none.error().message;
    }

    // Refused, naming the table: not narrower, a bad key inside, finer inside finer, not
    // tables, and (with the machine) a power the machine does not have.
    const auto refused = [](const std::string& text, const std::vector<std::string>& parts) {
        const auto bad = parse_profile(text, "t.toml");
        ASSERT_FALSE(bad.has_value()) << parts.front();
        EXPECT_EQ(bad.error().code, core::ErrorCode::kInvalidInput);
        for (const std::string& f : parts) {
            EXPECT_NE(bad.error().describe().find(f), std::string::npos)
                << "`" << f << "` not in: " << bad.error().describe();
        }
    };
    refused(base() + finer("2.5", "0.5"), {"number 1", "track_width_mm = 2.5", "narrower"});
    refused(base() + finer("1.0", "0.25") + finer("1.2", "0.25"),
            {"number 2", "track_width_mm = 1.2", "narrower than the 1 mm"});
    refused(base() + finer("1.0", "0.25") + "tracks = 3\n", {"number 1", "unknown key", "tracks"});
    refused(base() + finer("1.0", "0.25") + "[[process.finer.finer]]\n", {"number 1", "finer"});
    refused(base() + "finer = 3\n", {"process.finer", "[[process.finer]]"});
    refused(base() + with(finer("1.0", "0.25"), "laser_power_w", "laser_power_w = -5.0"),
            {"number 1", "laser_power_w = -5"});
    std::string hot = finer("1.0", "0.25");
    hot = with(hot, "laser_power_w", "laser_power_w = 900.0");
    const auto parsed = parse_profile(base() + hot, "t.toml");
    ASSERT_TRUE(parsed.has_value()) << parsed.error().describe();
    MachineProfile weak = *parsed->machine;
    weak.laser_power_max_w = 800.0;
    const auto ok = check_compatible(weak, *parsed->process);
    ASSERT_FALSE(ok.has_value());
    EXPECT_NE(ok.error().describe().find("[[process.finer]] number 1"), std::string::npos)
        << ok.error().describe();
    EXPECT_NE(ok.error().describe().find("laser_power_w = 900"), std::string::npos)
        << ok.error().describe();
}

// The reference A/C cell's finer process is the fine-spot profile's process, value for value,
// so that the fallback and the separate profile cannot drift apart.
TEST(Profile, TheReferenceCellsFinerProcessIsTheFineProfiles) {
    const fs::path reference = kProfilesDir / "reference_5axis_ac.toml";
    const fs::path fine = kProfilesDir / "fine_5axis_ac.toml";
    const auto r = load_profiles(std::span(&reference, 1));
    const auto f = load_profiles(std::span(&fine, 1));
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    ASSERT_TRUE(f.has_value()) << f.error().describe();
    ASSERT_EQ(r->process.finer.size(), 1u);
    const ProcessProfile& a = r->process.finer[0];
    const ProcessProfile& b = f->process;
    EXPECT_LT(a.track_width_mm, r->process.track_width_mm);
    EXPECT_EQ(a.track_width_mm, b.track_width_mm);
    EXPECT_EQ(a.layer_height_mm, b.layer_height_mm);
    EXPECT_EQ(a.h_min_mm, b.h_min_mm);
    EXPECT_EQ(a.h_max_mm, b.h_max_mm);
    EXPECT_EQ(a.overlap, b.overlap);
    EXPECT_EQ(a.contour_passes, b.contour_passes);
    EXPECT_EQ(a.laser_power_w, b.laser_power_w);
    EXPECT_EQ(a.laser_power_off_w, b.laser_power_off_w);
    EXPECT_EQ(a.powder_feed_g_min, b.powder_feed_g_min);
    EXPECT_EQ(a.deposition_feed_mm_min, b.deposition_feed_mm_min);
    EXPECT_EQ(a.travel_feed_mm_min, b.travel_feed_mm_min);
    EXPECT_EQ(a.dwell_after_laser_on_ms, b.dwell_after_laser_on_ms);
    EXPECT_EQ(a.self_supporting_angle_deg, b.self_supporting_angle_deg);
    EXPECT_EQ(a.footing_mm, b.footing_mm);
    EXPECT_EQ(a.powder_catch_efficiency, b.powder_catch_efficiency);
    EXPECT_EQ(a.speed_height.size(), b.speed_height.size());
    EXPECT_TRUE(b.finer.empty());
}

}  // namespace
}  // namespace maxslice::machine
