// Five-axis jobs as a process engineer runs them: `maxslice slice PART --profile TABLE.toml -o P`
// on the planner's fixtures (exported as STL) and on the shared models, with the verifier's
// figures the command prints; `maxslice verify` on the written program agrees; programs that
// collide, nozzles that cannot build a part and --no-verify are handled as documented
// (docs/verifier.md, docs/program-dialects.md).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "maxslice/io/read_mesh.hpp"
#include "maxslice/verify/verify.hpp"
#include "support/fixtures.hpp"
#include "support/planner_fixtures.hpp"

namespace fs = std::filesystem;
using maxslice::test::CliRun;
using maxslice::test::kSource;
using maxslice::test::kTestData;
using maxslice::test::PlannerFixture;
using maxslice::test::run_cli;
using maxslice::test::slurp;

namespace {

const fs::path kProfiles = kSource / "examples/profiles";
const fs::path kReference5 = kProfiles / "reference_5axis_ac.toml";
// `maxslice verify`'s exit code for an unsafe or wrong program (docs/verifier.md).
constexpr int kExitUnsafe = 3;

fs::path temp_dir(const std::string& name) {
    return maxslice::test::fresh_temp_dir("five_axis_test", name);
}

// Writes a fixture as binary STL into dir (NAME.stl).
fs::path export_fixture(const PlannerFixture& f, const fs::path& dir) {
    const fs::path file = dir / (f.name + ".stl");
    auto ok = maxslice::io::write_stl_binary(file, f.mesh);
    EXPECT_TRUE(ok.has_value()) << (ok ? "" : ok.error().describe());
    return file;
}

// The verifier's figures as `maxslice slice -o` prints them:
//   verified        N collisions, N unsupported beads, N limit violations (...)
//   coverage        X% of the part, excess Y%
struct Figures {
    bool verified = false;  // the "verified N collisions ..." line is there
    bool coverage_line = false;
    long collisions = -1;
    long unsupported = -1;
    long limit_violations = -1;
    double coverage_pct = NAN;
    double excess_pct = NAN;
    // finished part   X% inside beads, smallest stock S mm
    bool finished_line = false;
    double finished_pct = NAN;
    double stock_mm = NAN;
    bool finished_estimated = false;  // "(estimates: the mesh is not closed)" follows
};

Figures read_figures(const std::string& out);

// The verifier's figures are printed and say 0 collisions, 0 unsupported beads, 0 limit
// violations.
void expect_clean(const Figures& f, const std::string& out) {
    ASSERT_TRUE(f.verified) << out;
    ASSERT_TRUE(f.coverage_line) << out;
    ASSERT_TRUE(f.finished_line) << out;
    // No program is written with under 97 % of the finished part inside beads (decision 0026).
    EXPECT_GE(f.finished_pct, 97.0) << out;
    EXPECT_EQ(f.collisions, 0) << out;
    EXPECT_EQ(f.unsupported, 0) << out;
    EXPECT_EQ(f.limit_violations, 0) << out;
}

Figures read_figures(const std::string& out) {
    static const std::regex verified(
        R"((?:^|\n)verified +(\d+) collisions, (\d+) unsupported beads, (\d+) limit violations)");
    static const std::regex coverage(
        R"((?:^|\n)coverage +([0-9.]+)% of the part, excess ([0-9.]+)%)");
    Figures f;
    std::smatch m;
    if (std::regex_search(out, m, verified)) {
        f.verified = true;
        f.collisions = std::stol(m[1].str());
        f.unsupported = std::stol(m[2].str());
        f.limit_violations = std::stol(m[3].str());
    }
    if (std::regex_search(out, m, coverage)) {
        f.coverage_line = true;
        f.coverage_pct = std::stod(m[1].str());
        f.excess_pct = std::stod(m[2].str());
    }
    static const std::regex finished(
        R"((?:^|\n)finished part   ([0-9.]+)% inside beads, smallest stock (-?[0-9.]+) mm)");
    if (std::regex_search(out, m, finished)) {
        f.finished_line = true;
        f.finished_pct = std::stod(m[1].str());
        f.stock_mm = std::stod(m[2].str());
        f.finished_estimated = m.suffix().str().starts_with(" (estimates");
    }
    return f;
}

// A job refused for leaving the part short (decision 0026): the error names the share of the
// part inside beads, under 97 %, and the smallest stock.
void expect_short_of_part(const std::string& err) {
    static const std::regex short_of(
        R"(maxslice: error: verifying the program: the program holds ([0-9.]+)% of the (finished )?part inside its beads \(smallest stock -?[0-9.]+ mm\), under the 97% a written program must)");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(err, m, short_of)) << err;
    EXPECT_LT(std::stod(m[1].str()), 97.0) << err;
}

// `maxslice verify PROGRAM --model PART --profile PROFILE --json R` and its JSON report.
struct VerifyRun {
    CliRun run;
    nlohmann::json report;
};

VerifyRun run_verify(const fs::path& program, const fs::path& part, const fs::path& profile,
                     const fs::path& json, const std::vector<std::string>& extra = {}) {
    VerifyRun v;
    fs::remove(json);
    std::vector<std::string> args = {"verify",    program.string(), "--model", part.string(),
                                     "--profile", profile.string(), "--json",  json.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    v.run = run_cli(args);
    if (fs::exists(json)) {
        v.report = nlohmann::json::parse(slurp(json), nullptr, false);
        EXPECT_FALSE(v.report.is_discarded()) << "the report is not JSON: " << json;
    } else {
        ADD_FAILURE() << "no JSON report written\n" << v.run.err;
    }
    return v;
}

// The options of the job's "verify with" line (printed when the job built the part on another
// base or with a finer process): its --direction and --finer, as a user replays the program.
// The gm dialect names no base in the program, so its replay needs them; none when the job
// built the part as given with its main process (no such line).
std::vector<std::string> replay_options(const std::string& out) {
    static const std::regex line(
        R"((?:^|\n)verify with +maxslice verify \S+ --model \S+((?: --(?:direction|finer) \S+)*) \(and the same --profile\))");
    std::smatch m;
    if (!std::regex_search(out, m, line)) return {};
    std::vector<std::string> options;
    std::istringstream words(m[1].str());
    for (std::string w; words >> w;) options.push_back(w);
    return options;
}

// A copy of `profile` in `dir` with its machining stock and fill at 0: the job deposits the
// part as it is, no near-net shape (decision 0025). For tests about the track against the
// part's own features, which the reference profiles' near-net shape fills.
// A copy of the profile in dir (named after it and `suffix`) with the first value of each key
// set to 0.
fs::path zeroed_copy(const fs::path& profile, const fs::path& dir,
                     std::initializer_list<std::string> keys, const std::string& suffix) {
    std::string text = slurp(profile);
    for (const std::string& name : keys) {
        const std::string key = name + " = ";
        const std::size_t at = text.find(key);
        EXPECT_NE(at, std::string::npos) << key << " in " << profile;
        if (at == std::string::npos) continue;
        text.replace(at, text.find(' ', at + key.size()) - at, key + "0.0");
    }
    const fs::path copy = dir / (profile.stem().string() + suffix + ".toml");
    std::ofstream(copy) << text;
    return copy;
}

// A copy of the profile named `name` in dir, with the first `from` in its text made `to`.
fs::path replaced_copy(const fs::path& profile, const fs::path& dir, const std::string& name,
                       const std::string& from, const std::string& to) {
    std::string text = slurp(profile);
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from << " in " << profile;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    const fs::path copy = dir / name;
    std::ofstream(copy) << text;
    return copy;
}

fs::path net_shape_copy(const fs::path& profile, const fs::path& dir) {
    return zeroed_copy(profile, dir, {"machining_stock_mm", "fill_below_mm"}, "_net_shape");
}

// A clean 5-axis job: slice exits 0 and writes the program; the printed figures say no
// collision, no unsupported bead, no axis-limit violation, coverage >= 97%, excess < 5%; a
// separate `maxslice verify` of the written file passes and its JSON says the same.
void expect_clean_job(const fs::path& part, const fs::path& profile, const fs::path& dir,
                      const std::string& dialect, const std::vector<std::string>& extra = {}) {
    SCOPED_TRACE(part.filename().string() + " with " + profile.filename().string());
    const fs::path program = dir / (part.stem().string() + "." + dialect);
    fs::remove(program);
    std::vector<std::string> args{"slice",          part.string(), "--profile",
                                  profile.string(), "-o",          program.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    const CliRun r = run_cli(args);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    ASSERT_TRUE(fs::exists(program));
    EXPECT_GT(fs::file_size(program), 10000u);
    EXPECT_EQ(r.err.find("maxslice: error"), std::string::npos) << r.err;
    const Figures f = read_figures(r.out);
    expect_clean(f, r.out);
    EXPECT_GE(f.coverage_pct, 97.0) << r.out;
    EXPECT_LT(f.excess_pct, 5.0) << r.out;

    // Replayed as the job says (the plate, decision 0028, and the near-net shape, 0025, can
    // make it build the part on another base).
    const VerifyRun v =
        run_verify(program, part, profile, dir / "report.json", replay_options(r.out));
    EXPECT_EQ(v.run.exit_code, 0) << v.run.out << v.run.err;
    EXPECT_NE(v.run.out.find("PASSED"), std::string::npos) << v.run.out;
    ASSERT_TRUE(v.report.is_object());
    EXPECT_EQ(v.report.value("passed", false), true);
    EXPECT_EQ(v.report.value("dialect", ""), dialect);
    EXPECT_EQ(v.report["contact"].value("count", -1), 0);
    EXPECT_EQ(v.report["clearance"].value("count", -1), 0);
    EXPECT_EQ(v.report["unsupported"].value("count", -1), 0);
    EXPECT_EQ(v.report["limit_violations"].value("count", -1), 0);
    // The same program, model and profile: the same coverage and excess as slice printed
    // (which rounds to 0.01%).
    EXPECT_NEAR(100.0 * v.report.value("coverage", -1.0), f.coverage_pct, 0.005 + 1e-9);
    EXPECT_NEAR(100.0 * v.report.value("excess", -1.0), f.excess_pct, 0.005 + 1e-9);
    EXPECT_GT(v.report.value("deposit_moves", 0), 100);
}

std::vector<PlannerFixture> job_fixtures() {
    return {maxslice::test::bearing_seat(), maxslice::test::arch(), maxslice::test::t_shape_arms(),
            maxslice::test::leaning_column(), maxslice::test::l_bracket()};
}

// One positioning line of a gm program: power and powder columns, then `G1 X Y Z A C F`.
struct GmMove {
    std::size_t index = 0;  // 0-based line index
    double power = 0.0;
    double x = 0.0, y = 0.0, z = 0.0, a = 0.0, c = 0.0, f = 0.0;
};

std::vector<std::string> split_lines(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) lines.push_back(line);
    return lines;
}

std::string join_lines(const std::vector<std::string>& lines) {
    std::string text;
    for (const std::string& l : lines) text += l + "\n";
    return text;
}

// The gm lines that carry all five axis words (every positioning block after the start).
std::vector<GmMove> gm_moves(const std::vector<std::string>& lines) {
    static const std::regex move(
        R"(^([0-9.]+) [0-9.]+ G1 X(-?[0-9.]+) Y(-?[0-9.]+) Z(-?[0-9.]+) A(-?[0-9.]+) )"
        R"(C(-?[0-9.]+) F([0-9.]+)$)");
    std::vector<GmMove> out;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        std::smatch m;
        if (!std::regex_match(lines[i], m, move)) continue;
        out.push_back({i, std::stod(m[1].str()), std::stod(m[2].str()), std::stod(m[3].str()),
                       std::stod(m[4].str()), std::stod(m[5].str()), std::stod(m[6].str()),
                       std::stod(m[7].str())});
    }
    return out;
}

std::string gm_line(double power, double powder, double x, double y, double z, double a, double c,
                    double f) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%.2f %.2f G1 X%.3f Y%.3f Z%.3f A%.3f C%.3f F%.1f", power,
                  powder, x, y, z, a, c, f);
    return buf;
}

// The verifier's text line "contact         N (first: line L: ...)".
std::string collisions_line(const std::string& out) {
    const auto at = out.find("\ncontact");
    if (at == std::string::npos) return {};
    return out.substr(at + 1, out.find('\n', at + 1) - at - 1);
}

// `maxslice slice PART --orient given` with the reference profile, written to `program`: the
// job exits 0, its figures are clean (expect_clean), and a separate `maxslice verify` of the
// program (with the finer process when the job took it) passes. Returns the job's figures.
Figures clean_job_as_given(const fs::path& part, const fs::path& program) {
    const CliRun r = run_cli({"slice", part.string(), "--profile", kReference5.string(), "-o",
                              program.string(), "--orient", "given"});
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    const Figures fig = read_figures(r.out);
    if (r.exit_code != 0) return fig;
    expect_clean(fig, r.out);
    std::vector<std::string> verify = {"verify",      program.string(), "--model",
                                       part.string(), "--profile",      kReference5.string()};
    if (r.out.find("process         finer 1") != std::string::npos) {
        verify.insert(verify.end(), {"--finer", "1"});
    }
    const CliRun v = run_cli(verify);
    EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
    return fig;
}

}  // namespace

// The 5-axis example parts with the reference profile (gm, A/C table): programs the verifier
// passes with at least 97% of the part covered.
TEST(FiveAxis, FixturesBuildCleanWithTheReferenceProfile) {
    const fs::path dir = temp_dir("reference");
    for (const PlannerFixture& f : job_fixtures()) {
        expect_clean_job(export_fixture(f, dir), kReference5, dir, "gm");
    }
}

// Issue 24's parts as given (--orient given, the reference A/C profile with its plate): the
// portals and the arch, whose top bridges two bases, the block with a horizontal through-hole,
// the plate with a holed tab, the two-turn helical ring, the wall with a boss (its boss built
// sideways onto the wall's face; the 2.5 mm track leaves the finished part short there, and
// the job takes the finer one) and the demo's bearing seat. Each program verifies clean, a separate
// `maxslice verify` passes it, at least 99.5% of the finished part lies inside its beads and the
// excess over the near-net shape stays under 5%.
TEST(FiveAxis, PartsAsGivenBuildWithTheFinishedPartInsideTheBeads) {
    const fs::path dir = temp_dir("as_given");
    for (const PlannerFixture& f : {maxslice::test::portal_frame(), maxslice::test::tall_portal(),
                                    maxslice::test::arch(), maxslice::test::cross_hole_block(),
                                    maxslice::test::tab_with_hole(), maxslice::test::helical_ring(),
                                    maxslice::test::wall_boss(), maxslice::test::bearing_seat()}) {
        SCOPED_TRACE(f.name);
        const Figures fig = clean_job_as_given(export_fixture(f, dir), dir / (f.name + ".gm"));
        EXPECT_GE(fig.finished_pct, 99.5);
        EXPECT_LT(fig.excess_pct, 5.0);
    }
}

// Issue 24's two-turn helical ring turned about Z by 37 and 90 degrees is built as given too
// (verified clean, a separate `maxslice verify` passing it). Its near-net shape fills the turns
// into one band, which the first split plane (at the ground end) cuts again half a turn on, at
// a slant: the tail of the first turn beyond that cut starts in the air in the base region's
// cell, as a sliver narrower than a track. It is built from the column over the ground end,
// not hung from that sliver (decision 0040). (Slow: left out of the sanitizer run.)
TEST(FiveAxisSlow, TheHelicalRingTurnedAboutZIsBuiltAsGiven) {
    const fs::path dir = temp_dir("helical");
    for (const double turn : {37.0, 90.0}) {
        SCOPED_TRACE(turn);
        PlannerFixture f = maxslice::test::helical_ring();
        f.name += "_" + std::to_string(static_cast<int>(turn));
        f.mesh = maxslice::test::rotated(f.mesh, {0.0, 0.0, 1.0}, turn);
        clean_job_as_given(export_fixture(f, dir), dir / (f.name + ".gm"));
    }
}

// Turning a part about Z changes neither the head's reach nor the plate under it, and the
// near-net shape's voxels lie in the part's own frame (decision 0041): every fixture's whole
// job as given, with the main process, gives the same number of regions and the same verdict
// turned by an arbitrary angle as it does as drawn. (Slow: left out of the sanitizer run.)
// The cylinder with holes is the hardest: its plan's hull is a 64-gon, whose long side ties
// between its edges, so its grids turn by a multiple of 5.6 degrees against its holes; its
// filled holes reach the plate because the closing's fills are carried down to it (decision
// 0025), so no fill starts above the plate at a height the voxels decide.
TEST(FiveAxisSlow, EveryFixtureTurnedAboutZKeepsItsRegionsAndItsVerdict) {
    const fs::path dir = temp_dir("turned");
    struct Outcome {
        int exit_code = -1;
        long regions = -1;
    };
    const auto job = [&](const PlannerFixture& f) {
        const fs::path part = export_fixture(f, dir);
        const CliRun r =
            run_cli({"slice", part.string(), "--profile", kReference5.string(), "-o",
                     (dir / (f.name + ".gm")).string(), "--orient", "given", "--finer", "off"});
        Outcome o{r.exit_code, -1};
        std::smatch m;
        if (std::regex_search(r.out, m, std::regex(R"(\nregions +(\d+) )"))) {
            o.regions = std::stol(m[1]);
        }
        return o;
    };
    int built = 0;
    for (const PlannerFixture& f : maxslice::test::all_planner_fixtures()) {
        SCOPED_TRACE(f.name);
        const Outcome given = job(f);
        // (Past a half turn too: the plan's long side is a line, without a direction.)
        for (const double deg : {113.0, 247.0}) {
            PlannerFixture turned = f;
            turned.name += "_turned";
            const maxslice::core::Box3d box = maxslice::mesh::bounding_box(f.mesh);
            turned.mesh = maxslice::test::rotated(
                f.mesh, {0.0, 0.0, 1.0}, deg,
                {0.5 * (box.min.x + box.max.x), 0.5 * (box.min.y + box.max.y), 0.0});
            const Outcome other = job(turned);
            EXPECT_EQ(given.exit_code, other.exit_code) << deg;
            EXPECT_EQ(given.regions, other.regions) << deg;
        }
        if (given.exit_code == 0) {
            EXPECT_GT(given.regions, 0);  // the summary's line was read
            ++built;
        }
    }
    EXPECT_GT(built, 0);
}

// One fixture through each of the other bundled table profiles (their dialects and, for
// Siemens, the B/C table).
TEST(FiveAxis, FixturesBuildCleanWithTheOtherTableProfiles) {
    const fs::path dir = temp_dir("dialects");
    struct Case {
        PlannerFixture fixture;
        std::string profile, dialect;
    };
    const std::vector<Case> cases = {
        {maxslice::test::bearing_seat(), "linuxcnc_5axis_ac.toml", "linuxcnc"},
        {maxslice::test::leaning_column(), "fanuc_5axis_ac.toml", "fanuc"},
        {maxslice::test::t_shape_arms(), "siemens_5axis_bc.toml", "siemens"},
    };
    for (const Case& c : cases) {
        expect_clean_job(export_fixture(c.fixture, dir), kProfiles / c.profile, dir, c.dialect);
    }
}

// The portal of issue 23 with the LinuxCNC 5-axis cell, whose profile asks for 2 mm of
// clearance: built upside down, the head body's rim passed 1.35 mm from the finished column's
// top when the tip went down for the other column's first layer, and the program verified
// because only contact was checked. The order now keeps the clearance from the body too, and
// `maxslice verify` checks the profile's clearance by default, contact and clearance apart.
TEST(FiveAxis, TheProfilesClearanceIsKeptByTheHeadBody) {
    const fs::path dir = temp_dir("clearance");
    const fs::path part = export_fixture(maxslice::test::tall_portal(), dir);
    const fs::path profile = kProfiles / "linuxcnc_5axis_ac.toml";
    const fs::path program = dir / "p.ngc";
    const CliRun r =
        run_cli({"slice", part.string(), "--profile", profile.string(), "-o", program.string()});
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    expect_clean(read_figures(r.out), r.out);
    const VerifyRun v = run_verify(program, part, profile, dir / "report.json");
    EXPECT_EQ(v.run.exit_code, 0) << v.run.out << v.run.err;
    ASSERT_TRUE(v.report.is_object());
    EXPECT_DOUBLE_EQ(v.report.value("clearance_mm", -1.0), 2.0);
    EXPECT_EQ(v.report["contact"].value("count", -1), 0);
    EXPECT_EQ(v.report["clearance"].value("count", -1), 0) << v.run.out;
    EXPECT_NE(v.run.out.find("\nclearance 2.00  none"), std::string::npos) << v.run.out;

    // The same program against a head asking for 6 mm: it touches nothing, but the body
    // passes closer than that; the verifier says so apart from contact, and fails it.
    const fs::path wide = replaced_copy(profile, dir, "wide_clearance.toml", "clearance_mm = 2.0",
                                        "clearance_mm = 6.0");
    const VerifyRun w = run_verify(program, part, wide, dir / "wide.json");
    EXPECT_NE(w.run.exit_code, 0) << w.run.out;
    ASSERT_TRUE(w.report.is_object());
    EXPECT_EQ(w.report.value("passed", true), false);
    EXPECT_EQ(w.report["contact"].value("count", -1), 0);
    EXPECT_GT(w.report["clearance"].value("count", 0), 0);
    EXPECT_NE(w.run.out.find("\nclearance 6.00  "), std::string::npos) << w.run.out;
    EXPECT_NE(w.run.out.find("comes within 6.00 mm of material"), std::string::npos) << w.run.out;
    // --clearance 0 checks contact only.
    const CliRun c = run_cli({"verify", program.string(), "--model", part.string(), "--profile",
                              wide.string(), "--clearance", "0"});
    EXPECT_EQ(c.exit_code, 0) << c.out << c.err;
}

// The parts of the shared set whose features are narrower than the reference cell's 2.5 mm
// track: at the reference profile they stay under 97 % (decision 0012); with the fine-spot
// profile (0.8 mm) they meet the issue's figures.
TEST(FiveAxis, PartsTooFineForTheReferenceTrackBuildCleanWithTheFineTrack) {
    const fs::path fine = kProfiles / "fine_5axis_ac.toml";
    const fs::path dir = temp_dir("fine_track");
    for (const char* part :
         {"stl-models/gearwheel.bin.stl", "openscad/adns2610_dev_circuit_inv.stl",
          "prusaslicer/M3x10_screw.stl", "netgen/part1.stl"}) {
        expect_clean_job(kTestData / "meshes" / part, fine, dir, "gm");
    }
    // At the reference track alone (--finer off) the beads hold under 97 % of the part as it
    // is: no program is written (decision 0026), and the job says the figure, why it is low and
    // what builds the part. The part as it is: the reference cell without its machining stock
    // and fill (whose near-net shape fills the gaps between the teeth, below).
    const fs::path gear = kTestData / "meshes/stl-models/gearwheel.bin.stl";
    const fs::path net = net_shape_copy(kReference5, dir);
    const CliRun r = run_cli({"slice", gear.string(), "--profile", net.string(), "-o",
                              (dir / "g.gm").string(), "--finer", "off"});
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_FALSE(fs::exists(dir / "g.gm"));
    expect_short_of_part(r.err);
    EXPECT_NE(r.err.find("narrower than the 2.50 mm track"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("fine_5axis_ac.toml"), std::string::npos) << r.err;
    // The shipped reference profile deposits the gear's near-net shape (1 mm stock, gaps under
    // 10 mm filled, decision 0025): its 2.5 mm track builds that, the finished gear inside.
    const CliRun grown = run_cli({"slice", gear.string(), "--profile", kReference5.string(), "-o",
                                  (dir / "g.gm").string(), "--finer", "off"});
    ASSERT_EQ(grown.exit_code, 0) << grown.out << grown.err;
    EXPECT_NE(grown.out.find("near-net shape  1.00 mm machining stock"), std::string::npos)
        << grown.out;
    expect_clean(read_figures(grown.out), grown.out);
    // With the fine track already, the hint is the units: the angle block is in inches
    // (MANIFEST.md); read as mm it is 1.35 mm across and mostly narrower than 0.8 mm. The part
    // as it is: the fine profile's near-net shape (0.5 mm stock) makes it a block the fine
    // track's contour passes fill, and that program holds all of it.
    const fs::path block = kTestData / "meshes/trimesh/angle_block.STL";
    const CliRun small =
        run_cli({"slice", block.string(), "--repair", "--profile",
                 net_shape_copy(fine, dir).string(), "-o", (dir / "b.gm").string()});
    EXPECT_EQ(small.exit_code, 2) << small.out << small.err;
    EXPECT_FALSE(fs::exists(dir / "b.gm"));
    expect_short_of_part(small.err);
    EXPECT_NE(small.err.find("narrower than the 0.80 mm track"), std::string::npos) << small.err;
    EXPECT_NE(small.err.find("--units"), std::string::npos) << small.err;
    EXPECT_EQ(small.err.find("fine_5axis_ac.toml"), std::string::npos) << small.err;
}

// The reference cell's profile holds the fine-spot head as a finer process (decision 0019):
// a part its 2.5 mm track leaves under 97 % is built with the 0.8 mm track instead, the
// summary says so, and `maxslice verify --finer 1` passes the program with the same figures
// (without it, the verifier lays 2.5 mm beads: other figures). A part the 2.5 mm track
// builds keeps it; a part neither builds is refused with what the finer track gave.
TEST(FiveAxis, TheReferenceCellFallsBackToItsFinerTrackWhereItsTrackMissesTheFigures) {
    const fs::path dir = temp_dir("finer_fallback");
    // The reference cell without its machining stock and fill: its near-net shape fills the
    // gear's tooth gaps, which the 2.5 mm track then builds (PartsTooFine... checks that);
    // here the track meets the part's own features.
    const fs::path net = net_shape_copy(kReference5, dir);
    const fs::path gear = kTestData / "meshes/stl-models/gearwheel.bin.stl";
    const fs::path program = dir / "g.gm";
    const CliRun r = run_cli(
        {"slice", gear.string(), "--profile", net.string(), "-o", program.string(), "--timings"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // Its timings add both attempts' (the main track's, the finer one's) and say so.
    std::smatch attempts;
    ASSERT_TRUE(std::regex_search(r.err, attempts, std::regex(R"(timing attempts ([0-9]+))")))
        << r.err;
    EXPECT_GE(std::stoi(attempts[1].str()), 2) << r.err;
    const Figures f = read_figures(r.out);
    expect_clean(f, r.out);
    EXPECT_GE(f.coverage_pct, 97.0) << r.out;
    EXPECT_LT(f.excess_pct, 5.0) << r.out;
    std::smatch main_track;
    ASSERT_TRUE(std::regex_search(
        r.out, main_track,
        std::regex(R"(process         finer 1: 0\.80 mm track, 0\.20 mm layers \(the 2\.50 mm )"
                   R"(track: ([0-9.]+)% coverage)")))
        << r.out;
    EXPECT_LT(std::stod(main_track[1].str()), 97.0) << r.out;
    EXPECT_NE(r.out.find("--finer 1"), std::string::npos) << r.out;
    EXPECT_NE(r.err.find("the 2.50 mm track misses 97% coverage"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("warning: the beads cover"), std::string::npos) << r.err;
    const std::string text = slurp(program);
    EXPECT_NE(text.find("300.00 3.00 M8"), std::string::npos) << "the fine head's power/powder";
    EXPECT_EQ(text.find("700.00 8.00"), std::string::npos) << "no bead of the 2.5 mm head";

    const auto verify = [&](std::vector<std::string> extra, const fs::path& prog) {
        std::vector<std::string> args = {"verify",      prog.string(), "--model",
                                         gear.string(), "--profile",   net.string()};
        args.insert(args.end(), extra.begin(), extra.end());
        return run_cli(args);
    };
    const std::string coverage = fmt::format("coverage        {:.2f}%", f.coverage_pct);
    const CliRun v = verify({"--finer", "1"}, program);
    EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
    EXPECT_NE(v.out.find(coverage), std::string::npos) << v.out;
    // Without --finer the replay takes the process whose laser power the program has.
    const CliRun found = verify({}, program);
    EXPECT_EQ(found.exit_code, 0) << found.out << found.err;
    EXPECT_NE(found.out.find("process         finer 1: 0.80 mm track, by the program's laser "
                             "power (300 W)"),
              std::string::npos)
        << found.out;
    EXPECT_NE(found.out.find(coverage), std::string::npos) << found.out;
    EXPECT_EQ(found.err.find("warning"), std::string::npos) << found.err;
    // A power of no process of the profile: replayed with the main track, and said so.
    const fs::path odd = dir / "odd.gm";
    {
        std::string edited = text;
        for (std::size_t at = 0; (at = edited.find("300.00 3.00", at)) != std::string::npos;) {
            edited.replace(at, 3, "450");
        }
        std::ofstream(odd) << edited;
    }
    const CliRun unknown = verify({}, odd);
    EXPECT_NE(unknown.err.find("warning: the program deposits with 450.0 W, the power of none of "
                               "the profile's processes: its beads are replayed with the main "
                               "process's 2.50 mm track"),
              std::string::npos)
        << unknown.err;
    EXPECT_EQ(unknown.out.find(coverage), std::string::npos) << unknown.out;
    const CliRun none = verify({"--finer", "2"}, program);
    EXPECT_EQ(none.exit_code, 2);
    EXPECT_NE(none.err.find("no finer process 2"), std::string::npos) << none.err;

    // --finer 1 picks it at once: the same program.
    const fs::path direct = dir / "g1.gm";
    const CliRun d = run_cli(
        {"slice", gear.string(), "--profile", net.string(), "-o", direct.string(), "--finer", "1"});
    ASSERT_EQ(d.exit_code, 0) << d.err;
    EXPECT_EQ(slurp(direct), text);
    const CliRun bad = run_cli({"slice", gear.string(), "--profile", net.string(), "-o",
                                direct.string(), "--finer", "fine"});
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.err.find("--finer"), std::string::npos) << bad.err;
    const CliRun layered = run_cli({"slice", gear.string(), "--profile", net.string(), "-o",
                                    direct.string(), "--finer", "1", "--layer", "0.5"});
    EXPECT_EQ(layered.exit_code, 2);
    EXPECT_NE(layered.err.find("--layer sets the main process"), std::string::npos) << layered.err;

    // A part the 2.5 mm track builds to the figures keeps it.
    const fs::path seat = export_fixture(maxslice::test::bearing_seat(), dir);
    const CliRun kept =
        run_cli({"slice", seat.string(), "--profile", net.string(), "-o", (dir / "s.gm").string()});
    ASSERT_EQ(kept.exit_code, 0) << kept.err;
    EXPECT_EQ(kept.out.find("process         finer"), std::string::npos) << kept.out;
    EXPECT_EQ(kept.err.find("note:"), std::string::npos) << kept.err;
    EXPECT_EQ(slurp(dir / "s.gm").find("300.00 3.00"), std::string::npos);
    // Its replay with the finer track is warned of: the program has the main process's power.
    // Replayed on the base the job built it on (with the plate, decision 0028, not the file's).
    const std::vector<std::string> base = replay_options(kept.out);
    std::vector<std::string> forced_args = {"verify",    (dir / "s.gm").string(),
                                            "--model",   seat.string(),
                                            "--profile", net.string(),
                                            "--finer",   "1"};
    forced_args.insert(forced_args.end(), base.begin(), base.end());
    const CliRun forced = run_cli(forced_args);
    EXPECT_NE(forced.err.find("warning: the program deposits with the laser power of the "
                              "profile's main process, not of finer process 1 (--finer)"),
              std::string::npos)
        << forced.err;
    std::vector<std::string> plain_args = {
        "verify", (dir / "s.gm").string(), "--model", seat.string(), "--profile", net.string()};
    plain_args.insert(plain_args.end(), base.begin(), base.end());
    const CliRun plain = run_cli(plain_args);
    EXPECT_EQ(plain.exit_code, 0) << plain.err;
    EXPECT_EQ(plain.out.find("process         finer"), std::string::npos) << plain.out;
    EXPECT_EQ(plain.err.find("warning"), std::string::npos) << plain.err;

    // Neither track builds the angle block read as mm (it is in inches): refused as with the
    // 2.5 mm track, with what the 0.8 mm one gave.
    const fs::path block = kTestData / "meshes/trimesh/angle_block.STL";
    const fs::path none_written = dir / "b.gm";
    const CliRun refused = run_cli({"slice", block.string(), "--repair", "--profile", net.string(),
                                    "-o", none_written.string()});
    EXPECT_EQ(refused.exit_code, 2) << refused.out;
    EXPECT_FALSE(fs::exists(none_written));
    EXPECT_NE(refused.err.find("error: " + block.string() + ": no track fits"), std::string::npos)
        << refused.err;
    EXPECT_TRUE(std::regex_search(
        refused.err, std::regex(R"(the 0\.80 mm track \(finer process 1\): [0-9.]+% coverage)")))
        << refused.err;
}

// A near-net job is judged by the finished part its beads hold (decision 0030): NIST FTC-11's
// near-net shape fills bores and slots the 2.5 mm track leaves partly bare (under 99.5 % of the
// near-net shape), but the beads hold over 99.5 % of the finished part, so the main process is
// kept, not the finer one (which takes five times as long to build).
TEST(FiveAxis, ANearNetJobKeepsItsTrackWhenTheBeadsHoldTheFinishedPart) {
    const fs::path dir = temp_dir("finer_by_finished");
    const fs::path part = kTestData / "step/nist/nist_ftc_11_asme1_rb.stp";
    const fs::path program = dir / "f.gm";
    const CliRun r = run_cli(
        {"slice", part.string(), "--profile", kReference5.string(), "-o", program.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Figures f = read_figures(r.out);
    expect_clean(f, r.out);
    EXPECT_LT(f.coverage_pct, 100.0 * maxslice::verify::kFinishedInsideTarget)
        << "the near-net shape is not all beads: " << r.out;
    EXPECT_GE(f.finished_pct, 100.0 * maxslice::verify::kFinishedInsideTarget) << r.out;
    EXPECT_EQ(r.out.find("process         finer"), std::string::npos) << r.out;
    EXPECT_EQ(r.err.find("finer process"), std::string::npos) << r.err;
    const std::string text = slurp(program);
    EXPECT_NE(text.find("700.00 8.00 M8"), std::string::npos) << "the 2.5 mm head's power";
    EXPECT_EQ(text.find("300.00 3.00"), std::string::npos) << "no bead of the fine head";
}

// The same fallback on a 3-axis machine (the planar job): the 3-axis reference cell with the
// fine head as its finer process.
TEST(FiveAxis, APlanarJobFallsBackToTheFinerTrackToo) {
    const fs::path dir = temp_dir("finer_planar");
    const std::string five = slurp(kReference5);
    const fs::path profile = dir / "lmd_finer.toml";
    // The 3-axis cell without its machining stock and fill: the near-net shape of part1 (its
    // narrow features filled, decision 0025) is built by the 2.5 mm track; here the track
    // meets the part's own features.
    std::ofstream(profile) << slurp(net_shape_copy(kProfiles / "reference_lmd.toml", dir)) << "\n"
                           << five.substr(five.find("[[process.finer]]"));
    const fs::path part1 = kTestData / "meshes/netgen/part1.stl";
    const fs::path program = dir / "p.gm";
    const CliRun off = run_cli({"slice", part1.string(), "--profile", profile.string(), "-o",
                                program.string(), "--finer", "off"});
    // The main track alone leaves the part under 97 %: nothing written (decision 0026).
    EXPECT_EQ(off.exit_code, 2) << off.out << off.err;
    EXPECT_FALSE(fs::exists(program));
    expect_short_of_part(off.err);
    const CliRun r =
        run_cli({"slice", part1.string(), "--profile", profile.string(), "-o", program.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Figures f = read_figures(r.out);
    expect_clean(f, r.out);
    EXPECT_GE(f.coverage_pct, 97.0) << r.out;
    EXPECT_LT(f.excess_pct, 5.0) << r.out;
    EXPECT_NE(r.out.find("process         finer 1: 0.80 mm track"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("layers          "), std::string::npos) << r.out;
}

// The fine profile is the reference cell with another head: its machine tables are the
// reference's, byte for byte, so the two cannot drift apart.
TEST(FiveAxis, TheFineProfileRunsOnTheReferenceMachine) {
    const auto machine_part = [](const fs::path& file) {
        const std::string text = slurp(file);
        const std::size_t from = text.find("[machine]\n");
        const std::size_t to = text.find("[process]\n");
        EXPECT_NE(from, std::string::npos) << file;
        EXPECT_NE(to, std::string::npos) << file;
        EXPECT_LT(from, to) << file;
        return text.substr(from, to - from);
    };
    const std::string reference = machine_part(kReference5);
    EXPECT_GT(reference.size(), 500u);
    EXPECT_EQ(machine_part(kProfiles / "fine_5axis_ac.toml"), reference);
}

// The large cell (decision 0034) differs from the reference only in its table: the same head,
// codes and processes, a larger plate and travel.
TEST(FiveAxis, TheLargeCellHasTheReferenceHeadAndProcesses) {
    const auto from = [](const std::string& text, const std::string& table) {
        const std::size_t at = text.find(table);
        EXPECT_NE(at, std::string::npos) << table;
        return at == std::string::npos ? std::string() : text.substr(at);
    };
    const auto between = [&](const std::string& text, const std::string& a, const std::string& b) {
        const std::string tail = from(text, a);
        return tail.substr(0, tail.find(b));
    };
    const std::string reference = slurp(kReference5);
    const std::string large = slurp(kProfiles / "large_5axis_ac.toml");
    EXPECT_EQ(from(large, "[process]\n"), from(reference, "[process]\n"));
    EXPECT_EQ(between(large, "[machine.codes]\n", "[machine.substrate]\n"),
              between(reference, "[machine.codes]\n", "[machine.substrate]\n"));
    EXPECT_GT(between(reference, "[machine.codes]\n", "[machine.substrate]\n").size(), 300u);
    EXPECT_NE(between(large, "[machine.substrate]\n", "[process]\n"),
              between(reference, "[machine.substrate]\n", "[process]\n"));
    // What it is for: a bar longer than the reference plate, laid flat as given, is refused
    // there for the plate, before planning, and builds clean on the large cell.
    const fs::path dir = temp_dir("large_cell");
    const fs::path bar = dir / "bar_420mm.stl";
    ASSERT_TRUE(maxslice::io::write_stl_binary(bar, maxslice::test::box({0, 0, 0}, {420, 40, 6}))
                    .has_value());
    const CliRun refused = run_cli({"slice", bar.string(), "--profile", kReference5.string(),
                                    "--orient", "given", "-o", (dir / "bar.gm").string()});
    EXPECT_EQ(refused.exit_code, 2) << refused.err;
    EXPECT_NE(refused.err.find("the part's footprint on the plate"), std::string::npos)
        << refused.err;
    EXPECT_FALSE(fs::exists(dir / "bar.gm"));
    expect_clean_job(bar, kProfiles / "large_5axis_ac.toml", dir, "gm", {"--orient", "given"});
}

// A profile (the reference one by default) with a nozzle of 75 degree half angle, written into
// dir. (With 60 degrees the portal's beam is built as given since decision 0046: a direction
// from the sample of the sphere clears it.)
fs::path wide_nozzle_profile(const fs::path& dir, const fs::path& from_profile = kReference5) {
    return replaced_copy(from_profile, dir, "wide.toml", "half_angle_deg = 30.0",
                         "half_angle_deg = 75.0");
}

// A part whose footprint reaches beyond the substrate plate on every base is refused before it
// is planned, naming the plate (beads there would rest on nothing), with no program written.
// (On a 20 mm plate the bearing seat stands on its boss's end and builds.)
TEST(FiveAxis, APartLargerThanThePlateIsRefusedNamingThePlate) {
    const fs::path dir = temp_dir("small_plate");
    std::string text = slurp(kReference5);
    for (const std::string key : {"size_x_mm = 300.0", "size_y_mm = 300.0"}) {
        const auto pos = text.find(key);
        ASSERT_NE(pos, std::string::npos) << key;
        text.replace(pos, key.size(), key.substr(0, 12) + "10.0");
    }
    const fs::path profile = dir / "small_plate.toml";
    std::ofstream(profile) << text;
    const fs::path part = export_fixture(maxslice::test::bearing_seat(), dir);
    const fs::path program = dir / "p.gm";
    const CliRun r =
        run_cli({"slice", part.string(), "--profile", profile.string(), "-o", program.string()});
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("beyond the substrate plate (10.0 x 10.0 mm"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(program));
}

// A body floating beside the part (a 10 mm cube 10 mm above the plate and 10 mm beside a
// block standing on it) cannot be built. By default it is left out with a warning that says
// where it is (decision 0036); without it the program holds under 97 % of the finished part,
// so nothing is written, and the refusal names the body left out. With the free body kept
// (process.leave_out_free_bodies = false) the refusal says how big the section that rests on
// nothing is and where, within the floating cube's underside, how much of the part stands on
// it (the cube: its near-net shape, at most 12 mm a side), and what may help.
TEST(FiveAxis, ABodyFloatingFreeIsRefusedNamingWhereItStarts) {
    const fs::path dir = temp_dir("floating");
    maxslice::mesh::TriangleMesh part = maxslice::test::box({-20, -10, 0}, {20, 10, 10});
    const maxslice::mesh::TriangleMesh cube = maxslice::test::box({30, -5, 20}, {40, 5, 30});
    const auto base = static_cast<std::uint32_t>(part.vertices.size());
    part.vertices.insert(part.vertices.end(), cube.vertices.begin(), cube.vertices.end());
    for (const maxslice::mesh::Triangle& t : cube.triangles) {
        part.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    const fs::path stl = dir / "floating.stl";
    ASSERT_TRUE(maxslice::io::write_stl_binary(stl, part).has_value());
    const fs::path program = dir / "p.gm";
    // Placed with its box centred on the plate's centre (0, 0): the cube spans x 20 to 30, y -5
    // to 5, z 20 to 30, grown by the machining stock (under 1 mm).
    const auto near_cube = [&](const std::smatch& m, std::size_t first, const std::string& err) {
        EXPECT_NEAR(std::stod(m[first]), 25.0, 6.5) << err;
        EXPECT_NEAR(std::stod(m[first + 1]), 0.0, 6.5) << err;
        EXPECT_NEAR(std::stod(m[first + 2]), 25.0, 6.5) << err;
    };
    {
        const CliRun r = run_cli({"slice", stl.string(), "--profile", kReference5, "--orient",
                                  "given", "-o", program.string()});
        EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
        EXPECT_FALSE(fs::exists(program));
        const std::regex warned(
            R"(warning: 1 body of ([0-9]+) mm3 in all float free of the rest of the part and )"
            R"(of the plate \(the first: [0-9]+ mm3 around \((-?[0-9.]+), (-?[0-9.]+), )"
            R"((-?[0-9.]+)\))");
        std::smatch m;
        ASSERT_TRUE(std::regex_search(r.err, m, warned)) << r.err;
        EXPECT_GE(std::stod(m[1]), 1000.0) << r.err;  // the cube, grown: 1000 to 1728 mm3
        EXPECT_LE(std::stod(m[1]), 1728.0) << r.err;
        near_cube(m, 2, r.err);
        EXPECT_NE(r.err.find("1 body floating free of the rest"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("under the 97%"), std::string::npos) << r.err;
    }
    const fs::path keeping =
        replaced_copy(kReference5, dir, "keeping.toml", "leave_out_free_bodies = true",
                      "leave_out_free_bodies = false");
    const CliRun r = run_cli({"slice", stl.string(), "--profile", keeping.string(), "--orient",
                              "given", "-o", program.string()});
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_FALSE(fs::exists(program));
    const std::regex said(R"(layers rest on nothing \(the first: a ([0-9.]+) mm2 section at )"
                          R"(\((-?[0-9.]+), (-?[0-9.]+), (-?[0-9.]+)\))");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.err, m, said)) << r.err;
    // The section's centroid within a track of the cube.
    EXPECT_GT(std::stod(m[1]), 0.0);
    near_cube(m, 2, r.err);
    EXPECT_NE(r.err.find("what may help: another base"), std::string::npos) << r.err;
    const std::regex load(
        R"(; ([0-9]+) layers, ([0-9]+) mm3 \(([0-9.]+)% of the part\), stand on it )");
    ASSERT_TRUE(std::regex_search(r.err, m, load)) << r.err;
    // The cube grown by under 1 mm a side: 10 to 21 mm (12 mm x sqrt 3) along its region's
    // direction, in 0.5 mm layers (a slice may cut it in two pieces); 1000 to 1728 mm3; the
    // block below (40 x 20 x 10 mm, grown) is most of the rest.
    EXPECT_GE(std::stoi(m[1]), 20) << r.err;
    EXPECT_LE(std::stoi(m[1]), 84) << r.err;
    EXPECT_GE(std::stod(m[2]), 1000.0) << r.err;
    EXPECT_LE(std::stod(m[2]), 1728.0) << r.err;
    EXPECT_GT(std::stod(m[3]), 10.0) << r.err;
    EXPECT_LT(std::stod(m[3]), 25.0) << r.err;
}

// A nozzle with a 75 degree half angle cannot reach under the portal's beam: no build order,
// exit 2, nothing written. (The reference 30 degree nozzle builds it as given: its beam is
// closed from one column with the head leaned up over the other, decision 0029.)
TEST(FiveAxis, AWideNozzleIsRefusedWithoutAProgram) {
    const fs::path dir = temp_dir("wide_nozzle");
    const fs::path profile = wide_nozzle_profile(dir);
    const fs::path part = export_fixture(maxslice::test::portal_frame(), dir);
    const fs::path program = dir / "p.gm";
    const CliRun r = run_cli({"slice", part.string(), "--profile", profile.string(), "-o",
                              program.string(), "--orient", "given"});
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("maxslice: error:"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("no collision-free build order"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(program));
}

// The portal frame has no collision-free order as given with a nozzle of 75 degree half angle
// (its beam cannot be reached from beside the columns). By default the job then stands it on
// another candidate base, says so, and writes a program that `maxslice verify` passes with the
// part placed along that direction; --orient given and --direction keep the refusal.
// The machine time a job's summary gives ("build time      129.0 min ..."), minutes.
double build_minutes(const std::string& out) {
    const std::string key = "build time      ";
    const auto at = out.find(key);
    return at == std::string::npos ? NAN : std::stod(out.substr(at + key.size()));
}

// The wall with a boss as given holds under 99.5 % of its finished part with the 2.5 mm
// track (its boss is built sideways onto the wall's face, and tracks over the wall's beads are
// cut to what carries them); the finer track builds it as given. With the default search the
// job first looks for another base where the 2.5 mm track meets the figures (decision 0031):
// standing on its boss side, it does, in a fraction of the finer program's machine time.
TEST(FiveAxis, APartShortAsGivenWithItsTrackIsStoodWhereTheTrackMeetsTheFigures) {
    const fs::path dir = temp_dir("short_as_given");
    const fs::path part = export_fixture(maxslice::test::wall_boss(), dir);
    const CliRun given = run_cli({"slice", part.string(), "--profile", kReference5.string(), "-o",
                                  (dir / "given.gm").string(), "--orient", "given"});
    ASSERT_EQ(given.exit_code, 0) << given.out << given.err;
    EXPECT_NE(given.out.find("process         finer 1"), std::string::npos) << given.out;
    const CliRun r = run_cli({"slice", part.string(), "--profile", kReference5.string(), "-o",
                              (dir / "moved.gm").string()});
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const Figures f = read_figures(r.out);
    expect_clean(f, r.out);
    EXPECT_GE(f.finished_pct, 100.0 * maxslice::verify::kFinishedInsideTarget) << r.out;
    EXPECT_EQ(r.out.find("process         finer"), std::string::npos) << r.out;
    EXPECT_NE(r.err.find("the part as given falls short: its program with the 2.50 mm track"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.out.find("orientation     along "), std::string::npos) << r.out;
    EXPECT_LT(build_minutes(r.out), 0.5 * build_minutes(given.out)) << r.out << given.out;
}

// Where no base meets the figures, the default search keeps another base only when its
// verified program builds faster than the part as given and holds no less of the finished part
// (decision 0047). The portal frame with a profile without a finer process and without
// machining stock: as given its beads hold under 99.5 % of the finished part, and so do every
// other base's; one of them builds faster holding more.
TEST(FiveAxis, WhereNoBaseMeetsTheFiguresAFasterBaseHoldingNoLessIsKept) {
    const fs::path dir = temp_dir("no_base_meets");
    std::string text = slurp(kReference5);
    const std::size_t finer = text.find("[[process.finer]]");
    ASSERT_NE(finer, std::string::npos);
    text.resize(finer);
    const fs::path main_only = dir / "main_only.toml";
    std::ofstream(main_only) << text;
    const fs::path profile = zeroed_copy(main_only, dir, {"machining_stock_mm"}, "_no_stock");
    const fs::path part = export_fixture(maxslice::test::portal_frame(), dir);
    const CliRun given = run_cli({"slice", part.string(), "--profile", profile.string(), "-o",
                                  (dir / "given.gm").string(), "--orient", "given"});
    ASSERT_EQ(given.exit_code, 0) << given.out << given.err;
    const Figures g = read_figures(given.out);
    expect_clean(g, given.out);
    ASSERT_LT(g.finished_pct, 100.0 * maxslice::verify::kFinishedInsideTarget) << given.out;
    const CliRun r = run_cli(
        {"slice", part.string(), "--profile", profile.string(), "-o", (dir / "kept.gm").string()});
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const Figures f = read_figures(r.out);
    expect_clean(f, r.out);
    EXPECT_NE(r.err.find("no base meets the figures with the 2.50 mm track"), std::string::npos)
        << r.err;
    EXPECT_NE(r.out.find("orientation     along "), std::string::npos) << r.out;
    EXPECT_LT(build_minutes(r.out), build_minutes(given.out)) << r.out << given.out;
    EXPECT_GE(f.finished_pct, g.finished_pct) << r.out << given.out;
}

// Among the bases that build, the search keeps the one with the shortest verified build time
// (decision 0015): with --orient auto the job's build time is no longer than the one each axis
// base gets on its own (--orient given --direction, the same track) where that meets the
// figures, and the base kept meets them too. The wall with a boss on the A/C cell, the prism on
// the 3-axis cell: each builds on several axis bases.
void expect_the_shortest_base(const PlannerFixture& fixture, const fs::path& profile) {
    SCOPED_TRACE(fixture.name + " with " + profile.filename().string());
    const fs::path dir = temp_dir("shortest");
    const fs::path part = export_fixture(fixture, dir);
    const CliRun r = run_cli({"slice", part.string(), "--profile", profile.string(), "-o",
                              (dir / "auto.gm").string(), "--orient", "auto", "--finer", "off"});
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const Figures kept = read_figures(r.out);
    expect_clean(kept, r.out);
    EXPECT_GE(kept.finished_pct, 100.0 * maxslice::verify::kFinishedInsideTarget) << r.out;
    EXPECT_LT(kept.excess_pct, 5.0) << r.out;
    const double minutes = build_minutes(r.out);
    ASSERT_TRUE(std::isfinite(minutes)) << r.out;
    int meeting = 0;  // axis bases that build and meet the figures
    for (const char* direction : {"1,0,0", "-1,0,0", "0,1,0", "0,-1,0", "0,0,1", "0,0,-1"}) {
        SCOPED_TRACE(direction);
        const CliRun g = run_cli({"slice", part.string(), "--profile", profile.string(), "-o",
                                  (dir / "given.gm").string(), "--orient", "given", "--direction",
                                  direction, "--finer", "off"});
        if (g.exit_code != 0) continue;
        const Figures f = read_figures(g.out);
        if (!f.finished_line || f.finished_pct < 100.0 * maxslice::verify::kFinishedInsideTarget ||
            !(f.excess_pct < 5.0)) {
            continue;
        }
        ++meeting;
        // Summaries print minutes to 0.1.
        EXPECT_LE(minutes, build_minutes(g.out) + 0.05) << r.out << g.out;
    }
    EXPECT_GE(meeting, 2) << "the part builds on several bases";
}

TEST(FiveAxis, TheSearchKeepsTheBaseWithTheShortestVerifiedBuildTime) {
    expect_the_shortest_base(maxslice::test::wall_boss(), kReference5);
    expect_the_shortest_base(maxslice::test::vertical_prism(), kProfiles / "reference_lmd.toml");
}

// A plate 1 mm thick standing on its edge: no 2.5 mm track fits in its layers, so along the
// bases that stand it up its program deposits nothing, and takes no time at all. Such a base
// is refused, not kept as the shortest: with --orient auto the plate is laid flat and built.
TEST(FiveAxis, ABaseWhereNoTrackFitsIsNotTheShortest) {
    const fs::path dir = temp_dir("trackless");
    const fs::path plate = dir / "plate.stl";
    ASSERT_TRUE(maxslice::io::write_stl_binary(plate, maxslice::test::box({0, 0, 0}, {40, 1, 40}))
                    .has_value());
    const fs::path profile = net_shape_copy(kReference5, dir);
    const CliRun r = run_cli({"slice", plate.string(), "--profile", profile.string(), "-o",
                              (dir / "p.gm").string(), "--orient", "auto", "--finer", "off"});
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    expect_clean(read_figures(r.out), r.out);
    EXPECT_TRUE(r.out.find("orientation     along +Y") != std::string::npos ||
                r.out.find("orientation     along -Y") != std::string::npos)
        << r.out;
    EXPECT_GT(build_minutes(r.out), 0.0) << r.out;
}

TEST(FiveAxis, APartThatCannotBeBuiltAsGivenIsStoodOnAnotherBase) {
    const fs::path dir = temp_dir("fallback");
    const fs::path wide = wide_nozzle_profile(dir);
    const fs::path part = export_fixture(maxslice::test::portal_frame(), dir);
    const fs::path program = dir / "p.gm";
    const CliRun r =
        run_cli({"slice", part.string(), "--profile", wide.string(), "-o", program.string()});
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.err.find("the part as given cannot be built: no collision-free build order"),
              std::string::npos)
        << r.err;
    const std::string line = "orientation     along ";
    const std::size_t at = r.out.find(line);
    ASSERT_NE(at, std::string::npos) << r.out;
    const std::string name = r.out.substr(at + line.size(), 2);
    ASSERT_TRUE(name[0] == '+' || name[0] == '-') << r.out;
    const std::map<char, std::string> axis{{'X', "1,0,0"}, {'Y', "0,1,0"}, {'Z', "0,0,1"}};
    ASSERT_TRUE(axis.contains(name[1])) << r.out;
    std::string direction = axis.at(name[1]);
    if (name[0] == '-') {
        for (std::size_t k = direction.size(); k-- > 0;) {
            if (direction[k] == '1') direction.insert(k, "-");
        }
    }
    const CliRun v = run_cli({"verify", program.string(), "--model", part.string(), "--profile",
                              wide.string(), "--direction", direction});
    EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
    // The job prints the replay command with that direction; the verifier's coverage then is
    // the job's, and a replay of the model as the file has it is warned as misplaced.
    const std::smatch m = [&] {
        std::smatch found;
        std::regex_search(
            r.out, found,
            std::regex(R"(verify with +maxslice verify \S+ --model \S+ --direction (\S+))"));
        return found;
    }();
    ASSERT_EQ(m.size(), 2u) << r.out;
    const CliRun printed = run_cli({"verify", program.string(), "--model", part.string(),
                                    "--profile", wide.string(), "--direction", m[1].str()});
    EXPECT_EQ(printed.exit_code, 0) << printed.out << printed.err;
    std::smatch cov;
    ASSERT_TRUE(std::regex_search(printed.out, cov, std::regex(R"(coverage +([0-9.]+)%)")))
        << printed.out;
    EXPECT_NEAR(std::stod(cov[1].str()), read_figures(r.out).coverage_pct, 0.01) << printed.out;
    EXPECT_EQ(printed.err.find("is the model placed"), std::string::npos) << printed.err;
    const CliRun as_file =
        run_cli({"verify", program.string(), "--model", part.string(), "--profile", wide.string()});
    EXPECT_NE(as_file.err.find("is the model placed as the program builds it?"), std::string::npos)
        << as_file.out << as_file.err;
    for (const std::vector<std::string>& keep :
         {std::vector<std::string>{"--orient", "given"},
          std::vector<std::string>{"--direction", "0,0,1"}}) {
        const fs::path none = dir / "none.gm";
        std::vector<std::string> args{"slice",       part.string(), "--profile",
                                      wide.string(), "-o",          none.string()};
        args.insert(args.end(), keep.begin(), keep.end());
        const CliRun g = run_cli(args);
        EXPECT_EQ(g.exit_code, 2) << g.err;
        EXPECT_FALSE(fs::exists(none));
    }
}

// `--timings` of a table-tilt job names the stages that take its time: the base kept planned
// and ordered, the other bases the search tried, the program's paths, writing and replay; and
// of a job refused, what it spent up to the refusal. The portal with a nozzle too wide for it as
// given: refused with --orient given, built on another base by the default search.
TEST(FiveAxis, TimingsNameThePlanTheOrderAndTheSearchAlsoOfARefusedJob) {
    const fs::path dir = temp_dir("timings");
    const fs::path wide = wide_nozzle_profile(dir);
    const fs::path part = export_fixture(maxslice::test::portal_frame(), dir);
    // The stage names and their seconds; "search" with the count of other bases.
    const auto stages = [](const std::string& err) {
        std::map<std::string, double> out;
        const std::regex line(R"(timing (\S+) ([0-9.]+)(?: \(([0-9]+) other bases\))?)");
        for (auto it = std::sregex_iterator(err.begin(), err.end(), line);
             it != std::sregex_iterator(); ++it) {
            out[(*it)[1].str()] = std::stod((*it)[2].str());
            if ((*it)[3].matched) out["other bases"] = std::stod((*it)[3].str());
        }
        return out;
    };
    const fs::path program = dir / "p.gm";
    const CliRun built = run_cli(
        {"slice", part.string(), "--profile", wide.string(), "-o", program.string(), "--timings"});
    ASSERT_EQ(built.exit_code, 0) << built.err;
    const auto b = stages(built.err);
    for (const char* name :
         {"load", "validate", "near-net", "plan", "order", "search", "paths", "write", "verify"}) {
        EXPECT_TRUE(b.contains(name)) << name << "\n" << built.err;
    }
    EXPECT_FALSE(b.contains("slice")) << built.err;  // the plan slices
    EXPECT_GE(b.contains("other bases") ? b.at("other bases") : 0.0, 1.0) << built.err;
    EXPECT_GT(b.contains("search") ? b.at("search") : 0.0, 0.0) << built.err;

    const fs::path none = dir / "none.gm";
    const CliRun refused = run_cli({"slice", part.string(), "--profile", wide.string(), "-o",
                                    none.string(), "--orient", "given", "--timings"});
    ASSERT_EQ(refused.exit_code, 2) << refused.err;
    EXPECT_FALSE(fs::exists(none));
    const auto r = stages(refused.err);
    for (const char* name : {"load", "validate", "near-net", "plan", "order"}) {
        EXPECT_TRUE(r.contains(name)) << name << "\n" << refused.err;
    }
    for (const char* name : {"search", "paths", "write", "verify"}) {
        EXPECT_FALSE(r.contains(name)) << name << "\n" << refused.err;
    }
    EXPECT_GT(r.contains("order") ? r.at("order") : 0.0, 0.0) << refused.err;
}

// The bearing seat's boss is built sideways 12 mm above the plate: along the seed's horizontal
// direction the head's 30 mm body would reach under the plate's level (decision 0016). The
// planner leans the boss's direction up until the head clears the plate (decision 0029): with
// the profile's 300 x 300 x 20 mm plate (decision 0028) the part is built as given, on its own
// base, and the verifier (which models the plate, independently of the planner) passes the
// program; without a substrate in the profile the head never reaches below the plate's level
// either, and the job has nothing to warn of.
TEST(FiveAxis, AHeadThatWouldMeetTheSubstrateLeansTheSidewaysRegionUp) {
    const fs::path dir = temp_dir("substrate");
    const fs::path part = export_fixture(maxslice::test::bearing_seat(), dir);
    const fs::path program = dir / "p.gm";
    const CliRun r = run_cli({"slice", part.string(), "--profile", kReference5.string(), "-o",
                              program.string(), "--orient", "given"});
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    expect_clean(read_figures(r.out), r.out);
    EXPECT_EQ(r.err.find("cannot be built"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("regions         3 (1 splits)"), std::string::npos) << r.out;
    const CliRun v = run_cli(
        {"verify", program.string(), "--model", part.string(), "--profile", kReference5.string()});
    EXPECT_EQ(v.exit_code, 0) << v.out << v.err;

    // The plan says how far the boss leans and why, and its direction rises.
    const fs::path plan_file = dir / "plan.json";
    const CliRun p = run_cli(
        {"plan", part.string(), "--profile", kReference5.string(), "--plan", plan_file.string()});
    ASSERT_EQ(p.exit_code, 0) << p.out << p.err;
    const auto plan = nlohmann::json::parse(slurp(plan_file));
    bool split = false;
    for (const auto& d : plan.at("decisions")) {
        if (d.at("kind") != "split") continue;
        split = true;
        const auto& head = d.at("head");
        EXPECT_GT(head.at("lean_deg").get<double>(), 0.0) << d.dump();
        EXPECT_TRUE(head.at("clears").get<bool>()) << d.dump();
        EXPECT_LT(head.at("sideways_margin_mm").get<double>(), 0.0) << d.dump();
        const double nz = d.at("split_plane").at("normal").at(2).get<double>();
        EXPECT_NEAR(std::asin(nz) * 180.0 / std::numbers::pi, head.at("lean_deg").get<double>(),
                    1.5)
            << d.dump();
    }
    EXPECT_TRUE(split) << p.out;

    std::string text = slurp(kReference5);
    const std::size_t from = text.find("\n[machine.substrate]\n");
    ASSERT_NE(from, std::string::npos);
    const std::size_t to = text.find("\n\n", from + 1);
    ASSERT_NE(to, std::string::npos);
    text.erase(from, to - from);
    ASSERT_EQ(text.find("substrate]"), std::string::npos);
    const fs::path no_plate = dir / "no_plate.toml";
    std::ofstream(no_plate) << text;
    const CliRun plain = run_cli({"slice", part.string(), "--profile", no_plate.string(), "-o",
                                  program.string(), "--orient", "given"});
    ASSERT_EQ(plain.exit_code, 0) << plain.out << plain.err;
    expect_clean(read_figures(plain.out), plain.out);
    EXPECT_EQ(plain.err.find("below the plate's level"), std::string::npos) << plain.err;
}

// The RS-274 dialects name the base the program builds on in their header; `maxslice verify`
// without --direction places the model by it (the gm dialect has no comments: it needs the
// --direction the job prints). With a nozzle of 75 degree half angle the portal frame is stood
// on another base.
TEST(FiveAxis, AnRsProgramSaysWhichBaseItBuildsOn) {
    const fs::path dir = temp_dir("header_base");
    const fs::path part = export_fixture(maxslice::test::portal_frame(), dir);
    const fs::path profile = wide_nozzle_profile(dir, kProfiles / "linuxcnc_5axis_ac.toml");
    const fs::path program = dir / "p.ngc";
    const CliRun r =
        run_cli({"slice", part.string(), "--profile", profile.string(), "-o", program.string()});
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    ASSERT_NE(r.out.find("orientation     along "), std::string::npos) << r.out;
    const std::string text = slurp(program);
    EXPECT_NE(text.find("(part file direction built upwards "), std::string::npos)
        << text.substr(0, 400);
    const CliRun v = run_cli(
        {"verify", program.string(), "--model", part.string(), "--profile", profile.string()});
    EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
    EXPECT_NE(v.out.find("as the program's header says"), std::string::npos) << v.out;
    std::smatch cov;
    ASSERT_TRUE(std::regex_search(v.out, cov, std::regex(R"(coverage +([0-9.]+)%)"))) << v.out;
    EXPECT_NEAR(std::stod(cov[1].str()), read_figures(r.out).coverage_pct, 0.01) << v.out;
    EXPECT_EQ(v.err.find("is the model placed"), std::string::npos) << v.err;
    // An explicit --direction wins over the header: +Z as the file stands is misplaced.
    const CliRun z = run_cli({"verify", program.string(), "--model", part.string(), "--profile",
                              profile.string(), "--direction", "0,0,1"});
    EXPECT_EQ(z.out.find("as the program's header says"), std::string::npos) << z.out;
    EXPECT_NE(z.err.find("is the model placed"), std::string::npos) << z.out << z.err;
}

// A wedge standing on a strip 0.5 mm wide: no 2.5 mm track fits on the plate, and the wider
// layers above would rest on nothing (the toolpath stage cuts them, decision 0013, and most of
// the part went missing; the angle block of the shared set in inches had 174 beads in mid-air).
// As given, the job plans it again with the footing laid from the plate (decision 0017): the
// pad under the strip carries the layers above, and the 2.5 mm track builds it where it
// stands. Without a footing (footing_mm = 0) --orient given with the 2.5 mm track alone
// refuses, naming the strip, and the search stands it on a face.
TEST(FiveAxis, APartStandingOnAnEdgeStandsOnAFooting) {
    const fs::path dir = temp_dir("edge");
    maxslice::test::RampSpec spec;
    spec.base_length = 0.5;
    spec.lean_deg = 30.0;
    const fs::path part = export_fixture(maxslice::test::ramp_45(spec), dir);
    const fs::path program = dir / "p.gm";
    const CliRun r = run_cli({"slice", part.string(), "--profile", kReference5.string(), "-o",
                              program.string(), "--orient", "given", "--finer", "off"});
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("footing         1.00 mm: "), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("orientation     "), std::string::npos) << r.out;
    const Figures f = read_figures(r.out);
    expect_clean(f, r.out);
    EXPECT_GE(f.coverage_pct, 97.0) << r.out;

    const fs::path bare = zeroed_copy(kReference5, dir, {"footing_mm"}, "_no_footing");
    const fs::path none = dir / "none.gm";
    const CliRun g = run_cli({"slice", part.string(), "--profile", bare.string(), "-o",
                              none.string(), "--orient", "given", "--finer", "off"});
    EXPECT_EQ(g.exit_code, 2) << g.out << g.err;
    EXPECT_NE(g.err.find("the part stands on 1 piece(s) where no 2.50 mm track fits"),
              std::string::npos)
        << g.err;
    EXPECT_FALSE(fs::exists(none));
    const CliRun face = run_cli({"slice", part.string(), "--profile", bare.string(), "-o",
                                 program.string(), "--finer", "off"});
    ASSERT_EQ(face.exit_code, 0) << face.out << face.err;
    EXPECT_NE(face.err.find("the part as given cannot be built: stands on 1 piece(s) where no "
                            "track fits"),
              std::string::npos)
        << face.err;
    const Figures ff = read_figures(face.out);
    expect_clean(ff, face.out);
    // Standing on a face, only the sharp edge narrower than a track stays bare (95 %).
    EXPECT_GE(ff.coverage_pct, 90.0) << face.out;
}

// A written program with one deposit block moved 5 mm down into the part, and one with a travel
// down through it: `maxslice verify` exits 2 and names the collision at that line; the
// unchanged program passes.
TEST(FiveAxis, APlantedCollisionIsCaughtByVerify) {
    const fs::path dir = temp_dir("planted");
    const fs::path part = export_fixture(maxslice::test::arch(), dir);
    const fs::path good = dir / "good.gm";
    const CliRun r =
        run_cli({"slice", part.string(), "--profile", kReference5.string(), "-o", good.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::vector<std::string> lines = split_lines(slurp(good));
    const std::vector<GmMove> moves = gm_moves(lines);
    std::vector<GmMove> deposits;
    for (const GmMove& m : moves) {
        if (m.power > 0.0) deposits.push_back(m);
    }
    ASSERT_GT(deposits.size(), 1000u);

    // The arch's near-net shape (decision 0025) is built on another base: every replay takes
    // the job's --direction, as a user does.
    const std::vector<std::string> replay = replay_options(r.out);
    const VerifyRun control = run_verify(good, part, kReference5, dir / "good.json", replay);
    ASSERT_EQ(control.run.exit_code, 0) << control.run.out << control.run.err;

    // 1. A deposit block late in the build (many layers below it) 5 mm down.
    {
        const GmMove& d = deposits[deposits.size() * 4 / 5];
        ASSERT_GT(d.z, 10.0);
        std::vector<std::string> bad = lines;
        std::istringstream cols(lines[d.index]);
        double power = 0.0, powder = 0.0;
        cols >> power >> powder;
        bad[d.index] = gm_line(power, powder, d.x, d.y, d.z - 5.0, d.a, d.c, d.f);
        ASSERT_NE(bad[d.index], lines[d.index]);
        const fs::path program = dir / "deposit_down.gm";
        std::ofstream(program, std::ios::binary) << join_lines(bad);
        const VerifyRun v =
            run_verify(program, part, kReference5, dir / "deposit_down.json", replay);
        const int line = static_cast<int>(d.index) + 1;
        EXPECT_EQ(v.run.exit_code, kExitUnsafe) << v.run.out << v.run.err;
        EXPECT_NE(v.run.err.find("maxslice: error: verification failed"), std::string::npos)
            << v.run.err;
        EXPECT_NE(collisions_line(v.run.out).find("line " + std::to_string(line)),
                  std::string::npos)
            << "planted at line " << line << "\n"
            << v.run.out;
        ASSERT_TRUE(v.report.is_object());
        EXPECT_EQ(v.report.value("passed", true), false);
        EXPECT_GE(v.report["contact"].value("count", 0), 1);
        EXPECT_EQ(v.report["contact"]["first"].value("line", -1), line);
    }
    // 2. After a wire late in the build: a travel 5 mm straight down into the part and back.
    {
        const GmMove& d = deposits[deposits.size() * 4 / 5];
        std::size_t off = d.index + 1;
        while (off < lines.size() && !lines[off].ends_with(" M9")) ++off;
        ASSERT_LT(off, lines.size());
        // The last deposit of that wire: where the head is at the M9.
        const auto last = std::find_if(moves.rbegin(), moves.rend(),
                                       [&](const GmMove& m) { return m.index < off; });
        ASSERT_NE(last, moves.rend());
        std::vector<std::string> bad = lines;
        const double travel = 2540.0;
        bad.insert(bad.begin() + static_cast<std::ptrdiff_t>(off) + 1,
                   {gm_line(0.0, 0.0, last->x, last->y, last->z - 5.0, last->a, last->c, travel),
                    gm_line(0.0, 0.0, last->x, last->y, last->z, last->a, last->c, travel)});
        const fs::path program = dir / "travel_down.gm";
        std::ofstream(program, std::ios::binary) << join_lines(bad);
        const VerifyRun v =
            run_verify(program, part, kReference5, dir / "travel_down.json", replay);
        const int line = static_cast<int>(off) + 2;  // 1-based, right after the M9
        EXPECT_EQ(v.run.exit_code, kExitUnsafe) << v.run.out << v.run.err;
        EXPECT_NE(collisions_line(v.run.out).find("line " + std::to_string(line)),
                  std::string::npos)
            << "planted at line " << line << "\n"
            << v.run.out;
        ASSERT_TRUE(v.report.is_object());
        EXPECT_EQ(v.report.value("passed", true), false);
        EXPECT_EQ(v.report["contact"]["first"].value("line", -1), line);
        // A travel lays nothing: no unsupported bead comes from it.
        EXPECT_EQ(v.report["unsupported"].value("count", -1), 0);
    }
}

// --no-verify writes the same program without replaying it and says so: the program of the
// first plan, which for this part is the one the verifier keeps. (The L bracket as given now
// meets the profile's plate, decision 0028: its verified job builds it on another base, which
// --no-verify, replaying nothing, cannot know; the T keeps its base.)
TEST(FiveAxis, NoVerifyWritesTheProgramAndSaysSo) {
    const fs::path dir = temp_dir("no_verify");
    const fs::path part = export_fixture(maxslice::test::t_shape_arms(), dir);
    const fs::path checked = dir / "checked.gm";
    const fs::path unchecked = dir / "unchecked.gm";
    const CliRun a = run_cli(
        {"slice", part.string(), "--profile", kReference5.string(), "-o", checked.string()});
    ASSERT_EQ(a.exit_code, 0) << a.err;
    const CliRun b = run_cli({"slice", part.string(), "--profile", kReference5.string(), "-o",
                              unchecked.string(), "--no-verify"});
    ASSERT_EQ(b.exit_code, 0) << b.err;
    ASSERT_TRUE(fs::exists(unchecked));
    EXPECT_TRUE(std::regex_search(b.out, std::regex(R"((^|\n)verified +no\b)"))) << b.out;
    EXPECT_FALSE(read_figures(b.out).verified) << b.out;
    EXPECT_FALSE(read_figures(b.out).coverage_line) << b.out;
    EXPECT_TRUE(read_figures(a.out).verified) << a.out;
    EXPECT_EQ(a.out.find("orientation     "), std::string::npos) << a.out;
    EXPECT_EQ(slurp(checked), slurp(unchecked));
    EXPECT_EQ(a.err.find("--adaptive"), std::string::npos) << a.err;

    // --adaptive has no effect on a table-tilt machine: said, and the same program written.
    const fs::path adaptive = dir / "adaptive.gm";
    const CliRun c = run_cli({"slice", part.string(), "--profile", kReference5.string(), "-o",
                              adaptive.string(), "--adaptive"});
    ASSERT_EQ(c.exit_code, 0) << c.err;
    EXPECT_NE(c.err.find("--adaptive is not used on a table-tilt machine"), std::string::npos)
        << c.err;
    EXPECT_EQ(slurp(checked), slurp(adaptive));
}

// Every part of the shared set with the 5-axis reference profile (--repair): a program the
// verifier passes, or a refusal with a reason and no file; never a crash or an internal error.
// Coverage is only asserted positive: parts with features narrower than the track cannot reach
// 97%. Where the job's verifier refused a program, --no-verify writes it and `maxslice verify`
// refuses it too. The parts MANIFEST.md says are in other units run a second time with
// --units (the bunny in metres once nested the planner's walks until the stack overflowed).
// (About six minutes on two cores, mostly the searched bases of the larger meshes; the ASan run
// skips the EverySharedModel tests.)
TEST(FiveAxis, EverySharedModelIsBuiltOrRefusedCleanly) {
    const fs::path dir = temp_dir("shared");
    const std::map<std::string, std::string> stated_units = {{"bunny.bin.stl", "m"},
                                                             {"angle_block.STL", "in"},
                                                             {"featuretype.STL", "in"},
                                                             {"idler_riser.STL", "in"}};
    std::vector<std::pair<fs::path, std::string>> parts;  // path, --units or ""
    for (const auto& e : fs::recursive_directory_iterator(kTestData / "meshes")) {
        if (!e.is_regular_file()) continue;
        parts.emplace_back(e.path(), "");
        const auto u = stated_units.find(e.path().filename().string());
        if (u != stated_units.end()) parts.emplace_back(e.path(), u->second);
    }
    std::sort(parts.begin(), parts.end());
    ASSERT_GE(parts.size(), 20u + stated_units.size());
    int written = 0, refused = 0;
    for (const auto& [part, units] : parts) {
        SCOPED_TRACE(part.string() + (units.empty() ? "" : " --units " + units));
        const fs::path program = dir / "p.gm";
        fs::remove(program);
        std::vector<std::string> args = {"slice",         part.string(),        "--repair",
                                         "--profile",     kReference5.string(), "-o",
                                         program.string()};
        if (!units.empty()) args.insert(args.end(), {"--units", units});
        const CliRun r = run_cli(args, 300);
        ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 2) << "exit " << r.exit_code << "\n"
                                                          << r.out << r.err;
        if (r.exit_code == 2) {
            ++refused;
            EXPECT_FALSE(fs::exists(program)) << "no program is written when the job fails";
            EXPECT_NE(r.err.find("maxslice: error:"), std::string::npos) << r.err;
            // The job's own refusal (a note may say what a finer process gave).
            const std::size_t error = r.err.find("maxslice: error:");
            const std::string refusal = r.err.substr(error, r.err.find('\n', error) - error);
            if (refusal.find("the verifier refused the program") != std::string::npos) {
                std::vector<std::string> nv_args = args;
                nv_args.push_back("--no-verify");
                const CliRun nv = run_cli(nv_args, 300);
                ASSERT_EQ(nv.exit_code, 0) << nv.err;
                ASSERT_TRUE(fs::exists(program));
                std::vector<std::string> v_args = {"verify",    program.string(),
                                                   "--model",   part.string(),
                                                   "--profile", kReference5.string()};
                if (!units.empty()) v_args.insert(v_args.end(), {"--units", units});
                const CliRun v = run_cli(v_args, 300);
                EXPECT_EQ(v.exit_code, kExitUnsafe) << "slice's verifier refused it\n"
                                                    << v.out << v.err;
            }
            continue;
        }
        ++written;
        EXPECT_TRUE(fs::exists(program));
        const Figures f = read_figures(r.out);
        expect_clean(f, r.out);
        // What the job guarantees (decision 0026): at least 97 % of the finished part inside
        // beads (expect_clean). The figures of the near-net shape it deposits (decision 0025)
        // are not a rule: where the program holds under 99.5 % of the finished part or has 5 %
        // excess, the job tried the profile's finer process (decisions 0019, 0030) and took it
        // or said it does no better, and a coverage under 97 % is warned with its figure.
        // Where the finished part is open, its figure is an estimate and the near-net shape's
        // coverage (under 97 %) decides instead, as it decides whether the program is written.
        const bool short_of_target =
            f.finished_estimated ? f.coverage_pct < 97.0
                                 : f.finished_pct < 100.0 * maxslice::verify::kFinishedInsideTarget;
        if (short_of_target || f.excess_pct >= 5.0) {
            EXPECT_TRUE(r.out.find("process         finer 1") != std::string::npos ||
                        r.err.find("the profile's finer processes do no better") !=
                            std::string::npos)
                << r.out << r.err;
        }
        if (f.coverage_pct < 97.0) {
            std::smatch warned;
            ASSERT_TRUE(std::regex_search(
                r.err, warned,
                std::regex(
                    R"(warning: the beads cover ([0-9.]+)% of the near-net shape's volume)")))
                << r.out << r.err;
            EXPECT_NEAR(std::stod(warned[1].str()), f.coverage_pct, 0.05 + 1e-6) << r.err;
        }
    }
    // Most parts of the set are either too fine for the 2.5 mm track or have a build; several
    // of them must give a program (a planner that refuses everything fails here).
    EXPECT_GE(written, 6) << refused << " refused";
    RecordProperty("written", written);
    RecordProperty("refused", refused);
}
