// The CLI as a person uses it: exit codes, one-line errors, outputs, determinism, and every
// shared test file (valid and malformed) handled without crash or hang. Under the asan
// preset the CLI itself is built with AddressSanitizer and UBSan, so these runs also check
// for memory errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "cli_runner.hpp"

namespace fs = std::filesystem;
using maxslice::test::CliRun;
using maxslice::test::kExample;
using maxslice::test::kSource;
using maxslice::test::kTestData;
using maxslice::test::run_cli;
using maxslice::test::slurp;

namespace {

fs::path temp_dir(const std::string& name) {
    return maxslice::test::fresh_temp_dir("cli_test", name);
}

std::vector<fs::path> files_under(const fs::path& dir) {
    std::vector<fs::path> out;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        if (e.is_regular_file()) out.push_back(e.path());
    }
    std::sort(out.begin(), out.end());
    return out;
}

// A failed run must say why in exactly one line on stderr, and nothing must have crashed.
void expect_clean_outcome(const CliRun& r, const std::string& what) {
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 2) << what << ": exit " << r.exit_code << "\n"
                                                      << r.err;
    EXPECT_EQ(r.err.find("AddressSanitizer"), std::string::npos) << what << "\n" << r.err;
    EXPECT_EQ(r.err.find("runtime error"), std::string::npos) << what << "\n" << r.err;
    if (r.exit_code == 2) {
        const auto first = r.err.find("maxslice: error: ");
        ASSERT_NE(first, std::string::npos) << what << "\n" << r.err;
        const std::string line = r.err.substr(first);
        EXPECT_EQ(std::count(line.begin(), line.end(), '\n'), 1) << what << "\n" << r.err;
        EXPECT_GT(line.size(), 30u) << what << ": message too short to act on: " << line;
    }
}

}  // namespace

TEST(Cli, HelpOnEveryCommand) {
    for (const std::vector<std::string>& args :
         {std::vector<std::string>{"--help"}, {"info", "--help"}, {"slice", "--help"}}) {
        const CliRun r = run_cli(args);
        EXPECT_EQ(r.exit_code, 0) << args[0];
        EXPECT_NE(r.out.find("Usage"), std::string::npos) << r.out;
    }
}

TEST(Cli, BadOptionsAndFilesExitTwoWithOneLine) {
    const std::string part = kExample.string();
    const std::vector<std::vector<std::string>> cases = {
        {"slice", part, "--layer", "-1"},
        {"slice", part, "--direction", "0,0,0"},
        {"slice", part, "--units", "furlong"},
        {"slice", part, "--adaptive", "--min-layer", "0.5", "--max-layer", "0.2"},
        {"slice", "/nonexistent/part.stl"},
        {"info", (kTestData / "malformed/stl-models/empty.stl").string()},
        {"slice", "--bogus-option", part},
        {},
    };
    for (const auto& args : cases) {
        const CliRun r = run_cli(args);
        std::string what;
        for (const auto& a : args) what += a + " ";
        EXPECT_EQ(r.exit_code, 2) << what << "\n" << r.err;
        EXPECT_EQ(r.err.find("Segmentation"), std::string::npos);
    }
}

TEST(Cli, InfoReportsTheExamplePart) {
    const CliRun r = run_cli({"info", kExample.string(), "--json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["triangles"].get<int>(), 96 * 6 * 2);
    EXPECT_EQ(j["bodies"].get<int>(), 1);
    EXPECT_TRUE(j["closed_manifold"].get<bool>());
    // Volume of the revolved profile, polygonal: the 96-gon area factor times the rings.
    const double k = 96.0 / 2.0 * std::sin(2.0 * M_PI / 96.0);
    const double expected = k * ((30 * 30 - 10 * 10) * 6.0 + (18 * 18 - 10 * 10) * 24.0);
    EXPECT_NEAR(j["volume_mm3"].get<double>(), expected, expected * 1e-6);
}

TEST(Cli, SliceWritesJsonAndSvgsThatAgreeWithThePart) {
    const fs::path dir = temp_dir("slice");
    const CliRun r =
        run_cli({"slice", kExample.string(), "--layer", "0.5", "--json", (dir / "s.json").string(),
                 "--svg", (dir / "svg").string(), "--contact-sheet", (dir / "sheet.svg").string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(slurp(dir / "s.json"));
    ASSERT_EQ(j["layer_count"].get<int>(), 60);
    const auto& layers = j["layers"];
    double volume = 0.0;
    for (const auto& l : layers) {
        volume += l["area_mm2"].get<double>() * l["thickness_mm"].get<double>();
        EXPECT_EQ(l["outers"].get<int>(), 1);
        EXPECT_EQ(l["holes"].get<int>(), 1);
        // The hole is the outer's child.
        const auto& tree = l["tree"];
        ASSERT_EQ(tree.size(), 2u);
        EXPECT_EQ(tree[1]["parent"].get<int>(), 0);
        EXPECT_TRUE(tree[1]["hole"].get<bool>());
    }
    EXPECT_NEAR(volume, j["part"]["volume_mm3"].get<double>(),
                0.005 * j["part"]["volume_mm3"].get<double>());
    EXPECT_EQ(std::distance(fs::directory_iterator(dir / "svg"), fs::directory_iterator{}), 60);
    const std::string svg = slurp(dir / "svg" / "layer_00001.svg");
    EXPECT_NE(svg.find("<path"), std::string::npos);
    EXPECT_NE(slurp(dir / "sheet.svg").find("</svg>"), std::string::npos);
}

#if defined(MAXSLICE_WITH_MIMALLOC)
TEST(Cli, TheProgramRunsOnMimallocWithHugePages) {
    // Decision 0018: the options are set before mimalloc starts (the program's
    // .preinit_array); set any later, they are ignored without a word. Its own report says
    // which are in force.
    ASSERT_EQ(::setenv("MIMALLOC_VERBOSE", "1", 1), 0);
    const CliRun r = run_cli({"info", kExample.string()});
    ::unsetenv("MIMALLOC_VERBOSE");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("mimalloc: option 'large_os_pages': 1"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("mimalloc: option 'eager_commit_delay': 0"), std::string::npos) << r.err;
}
#endif

TEST(Cli, SameBytesForAnyThreadCount) {
    const fs::path dir = temp_dir("determinism");
    const std::string part = (kTestData / "meshes/stl-models/gearwheel.bin.stl").string();
    for (const std::string t : {"1", "2", "2"}) {
        const CliRun r = run_cli({"slice", part, "--layer", "0.2", "--direction", "0.3,0.2,1",
                                  "--threads", t, "--json", (dir / ("t" + t + ".json")).string(),
                                  "--contact-sheet", (dir / ("t" + t + ".svg")).string()});
        ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    EXPECT_EQ(slurp(dir / "t1.json"), slurp(dir / "t2.json"));
    EXPECT_EQ(slurp(dir / "t1.svg"), slurp(dir / "t2.svg"));
    EXPECT_GT(slurp(dir / "t1.json").size(), 1000u);
}

TEST(Cli, EveryMalformedFileIsHandledCleanly) {
    const auto files = files_under(kTestData / "malformed");
    ASSERT_GT(files.size(), 30u);
    for (const auto& f : files) {
        expect_clean_outcome(run_cli({"info", f.string()}, 120), "info " + f.string());
        expect_clean_outcome(run_cli({"slice", f.string(), "--layer", "0.1"}, 120),
                             "slice " + f.string());
    }
}

TEST(Cli, MalformedFilesThatMustBeRefused) {
    // Files whose defect makes slicing meaningless: refusing them is the only honest answer.
    for (const char* name :
         {"stl-models/empty.stl", "stl-models/faceless.ascii.stl", "trimesh/stl_empty_bin.stl",
          "assimp/empty.obj", "assimp/testpoints.obj", "stl-models/singleFace.ascii.stl",
          "trimesh/soup.stl", "dodgy-step-files/Tsh001.stp", "dodgy-step-files/Ad005.stp"}) {
        const CliRun r = run_cli({"slice", (kTestData / "malformed" / name).string()}, 120);
        EXPECT_EQ(r.exit_code, 2) << name << "\n" << r.err;
        expect_clean_outcome(r, name);
    }
}

TEST(Cli, ValidOddFilesAreAccepted) {
    // Valid but unusual syntax: accepted (possibly with warnings) and sliced.
    for (const char* name :
         {"stl-models/wrongHeader.bin.stl", "stl-models/solidNameMismatch.ascii.stl",
          "stl-models/missingEndsolid.ascii.stl", "stl-models/wrongNormals.ascii.stl",
          "stl-models/notANumberNormal.ascii.stl", "trimesh/negative_indices.obj",
          "assimp/box_UTF16BE.obj"}) {
        const CliRun r =
            run_cli({"slice", (kTestData / "malformed" / name).string(), "--layer", "0.1"}, 120);
        EXPECT_EQ(r.exit_code, 0) << name << "\n" << r.err;
    }
}

TEST(Cli, EverySharedModelSlicesOrIsRefusedCleanly) {
    std::vector<fs::path> files = files_under(kTestData / "meshes");
    for (const auto& f : files_under(kTestData / "step")) files.push_back(f);
    ASSERT_GT(files.size(), 30u);
    for (const auto& f : files) {
        const CliRun r = run_cli({"slice", f.string(), "--layer", "0.5"}, 300);
        expect_clean_outcome(r, f.string());
    }
}

// Issue 23: `maxslice verify` exits 3 for a program that is unsafe or does not build the part
// it is checked against, 2 for bad input (an unreadable program, a profile whose code
// templates move the machine), 0 for a sound program; its errors quote program bytes
// escaped, on one short line.
TEST(Cli, VerifyRefusesUnsafeAndWrongProgramsWithExitThree) {
    const fs::path dir = temp_dir("verify_exit_codes");
    const fs::path gm_profile = kSource / "examples/profiles/reference_lmd.toml";
    const fs::path lc_profile = kSource / "examples/profiles/linuxcnc_generic.toml";
    const fs::path gm = dir / "p.gm", ngc = dir / "p.ngc";
    ASSERT_EQ(
        run_cli({"slice", kExample.string(), "--profile", gm_profile.string(), "-o", gm.string()})
            .exit_code,
        0);
    ASSERT_EQ(
        run_cli({"slice", kExample.string(), "--profile", lc_profile.string(), "-o", ngc.string()})
            .exit_code,
        0);
    const auto write = [&](const std::string& name, const std::string& text) {
        const fs::path f = dir / name;
        std::ofstream(f, std::ios::binary) << text;
        return f;
    };
    const auto verify = [&](const fs::path& program, const fs::path& profile,
                            std::vector<std::string> extra = {}, const fs::path& model = kExample) {
        std::vector<std::string> args = {"verify",       program.string(), "--model",
                                         model.string(), "--profile",      profile.string()};
        args.insert(args.end(), extra.begin(), extra.end());
        return run_cli(args);
    };
    const auto refused = [&](const CliRun& r, const std::string& check) {
        EXPECT_EQ(r.exit_code, 3) << check << "\n" << r.out << r.err;
        EXPECT_NE(r.err.find("maxslice: error: verification failed"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find(check), std::string::npos) << r.err;
        EXPECT_NE(r.out.find("verification    FAILED"), std::string::npos) << r.out;
    };

    const fs::path json = dir / "r.json";
    const CliRun ok = verify(gm, gm_profile, {"--json", json.string()});
    EXPECT_EQ(ok.exit_code, 0) << ok.out << ok.err;
    EXPECT_TRUE(nlohmann::json::parse(slurp(json)).at("passed").get<bool>());
    EXPECT_EQ(verify(ngc, lc_profile).exit_code, 0);

    const std::string text = slurp(gm), lc_text = slurp(ngc);
    // Cut in half, mid-line; the LinuxCNC program ending with the laser on and no M2.
    refused(verify(write("cut.gm", text.substr(0, text.size() / 2 + 5)), gm_profile), "unfinished");
    const std::size_t off = lc_text.rfind("\nM65 P0\nM68 E0 Q0\n");  // the last laser_off
    ASSERT_NE(off, std::string::npos);
    const CliRun on = verify(write("on.ngc", lc_text.substr(0, off + 1)), lc_profile);
    refused(on, "left_on");
    EXPECT_NE(on.err.find("unfinished"), std::string::npos) << on.err;
    // Empty and comments-only programs.
    refused(verify(write("empty.gm", ""), gm_profile), "nothing_deposited");
    refused(verify(write("comments.ngc", "(nothing)\n; still nothing\n"), lc_profile),
            "unfinished");
    // A grid too coarse to see the layers (the model read in metres, a voxel coarser than the
    // beads) gives no verdict: exit 2, saying why. Its near-net shape (the profile's 1 mm stock,
    // decision 0025) cannot be made at that size either, and the warning says so first.
    const auto unseen = [&](const CliRun& r, const std::string& where) {
        EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
        EXPECT_NE(r.err.find(where + ": the verifier cannot see this program's layers"),
                  std::string::npos)
            << r.err;
        EXPECT_EQ(r.out.find("verification    PASSED"), std::string::npos) << r.out;
    };
    const CliRun metres = verify(gm, gm_profile, {"--units", "m"});
    unseen(metres, "verify grid");
    EXPECT_NE(metres.err.find("warning: --model: the near-net shape the profile asks for (1.00 mm "
                              "stock, holes under 10.00 mm filled) cannot be made"),
              std::string::npos)
        << metres.err;
    EXPECT_NE(metres.err.find("(--units)"), std::string::npos) << metres.err;
    EXPECT_NE(metres.out.find("near-net shape  none: the program is replayed against the model "
                              "itself"),
              std::string::npos)
        << metres.out;
    unseen(verify(gm, gm_profile, {"--voxel", "1e9"}), "--voxel");
    // -700 W, 800 g/min on a machine whose maximum is 30.
    std::string negative = lc_text;
    for (auto at = negative.find("M68 E0 Q700.00"); at != std::string::npos;
         at = negative.find("M68 E0 Q700.00")) {
        negative.replace(at, 14, "M68 E0 Q-700.00");
    }
    refused(verify(write("negative.ngc", negative), lc_profile), "out_of_range");
    std::string powder = text;
    const std::size_t col = powder.find("700.00 8.00 ");
    ASSERT_NE(col, std::string::npos);
    powder.replace(col, 12, "700.00 800.00 ");
    refused(verify(write("powder.gm", powder), gm_profile), "out_of_range");
    // The wrong part: safe but not this part's program; a stated threshold lets it pass.
    const fs::path seat = kSource / "examples/parts/bearing_seat.stl";
    refused(verify(gm, gm_profile, {}, seat), "coverage");
    EXPECT_EQ(
        verify(gm, gm_profile, {"--min-coverage", "0", "--max-excess", "1000"}, seat).exit_code, 0);

    // A profile whose template moves the machine is refused by both commands, naming the key.
    std::string moving = slurp(gm_profile);
    const std::size_t codes = moving.find("[machine.codes]\n");
    ASSERT_NE(codes, std::string::npos);
    moving.insert(codes + 16, "program_end = [\"G0 X0 Y0 Z0\"]\n");
    const fs::path bad_profile = write("moving.toml", moving);
    for (const CliRun& r : {verify(gm, bad_profile),
                            run_cli({"slice", kExample.string(), "--profile", bad_profile.string(),
                                     "-o", (dir / "never.gm").string()})}) {
        EXPECT_EQ(r.exit_code, 2) << r.err;
        EXPECT_NE(r.err.find("machine.codes.program_end[0]"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("moves the machine (G0)"), std::string::npos) << r.err;
    }
    EXPECT_FALSE(fs::exists(dir / "never.gm"));

    // Escape sequences and a million-digit number: one short, escaped error line, exit 2.
    for (const std::string& bad :
         {std::string("0.00 0.00 G1 X\x1b[31mRED\n"),
          "0.00 0.00 G21\n0.00 0.00 G1 X" + std::string(1000000, '9') + " F100\n"}) {
        const CliRun r = verify(write("bad.gm", bad), gm_profile);
        EXPECT_EQ(r.exit_code, 2) << r.err.substr(0, 300);
        EXPECT_EQ(r.err.find('\x1b'), std::string::npos) << r.err.substr(0, 300);
        EXPECT_LT(r.err.size(), 1200U) << r.err.substr(0, 300);
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err.substr(0, 300);
    }
}

namespace {

// An axis-aligned box as ASCII STL, outward-facing triangles.
std::string box_stl(const std::array<double, 3>& lo, const std::array<double, 3>& hi) {
    std::string out = "solid box\n";
    const auto v = [&](int corner) {
        return std::array<double, 3>{corner & 1 ? hi[0] : lo[0], corner & 2 ? hi[1] : lo[1],
                                     corner & 4 ? hi[2] : lo[2]};
    };
    // Each face as two counter-clockwise triangles seen from outside.
    const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : faces) {
        for (const auto& t : {std::array{f[0], f[1], f[2]}, std::array{f[0], f[2], f[3]}}) {
            out += " facet normal 0 0 0\n  outer loop\n";
            for (const int c : t) {
                const auto p = v(c);
                out += "   vertex " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " +
                       std::to_string(p[2]) + "\n";
            }
            out += "  endloop\n endfacet\n";
        }
    }
    return out + "endsolid box\n";
}

}  // namespace

// `maxslice verify --model NEARNET --finished PART` (decision 0026): the finished part is
// placed as the model is (its own placement would drop it onto the plate, leaving no stock
// under it), reported with its share inside beads and the smallest stock, and a finished part
// that reaches out of the beads fails the check `finished_inside`.
// The near-net block is given by hand here, so the program deposits it as it is: the profile
// is the reference LMD cell without its own machining stock and fill (a copy with both 0;
// decision 0025), else the job and the replay would grow the given near-net shape again.
TEST(Cli, VerifyMeasuresTheFinishedPartInsideTheNearNetShape) {
    const fs::path dir = temp_dir("verify_finished");
    const auto write = [&](const std::string& name, const std::string& text) {
        const fs::path f = dir / name;
        std::ofstream(f, std::ios::binary) << text;
        return f;
    };
    const fs::path reference = kSource / "examples/profiles/reference_lmd.toml";
    std::string as_given = slurp(reference);
    for (const std::string key : {"machining_stock_mm = ", "fill_below_mm = "}) {
        const std::size_t at = as_given.find(key);
        ASSERT_NE(at, std::string::npos) << key;
        as_given.replace(at, as_given.find(' ', at + key.size()) - at, key + "0.0");
    }
    const fs::path profile = write("no_stock.toml", as_given);
    // The near-net block and a finished block 1 mm above its bottom, 2 mm inside its sides and
    // top; one reaching 1 mm out of its sides.
    const fs::path near = write("near.stl", box_stl({0, 0, 0}, {40, 30, 8}));
    const fs::path inside = write("inside.stl", box_stl({2, 2, 1}, {38, 28, 6}));
    const fs::path out = write("out.stl", box_stl({-1, 2, 1}, {41, 28, 6}));
    const fs::path program = dir / "p.gm";
    ASSERT_EQ(
        run_cli({"slice", near.string(), "--profile", profile.string(), "-o", program.string()})
            .exit_code,
        0);
    const fs::path json = dir / "r.json";
    const auto verify = [&](const fs::path& finished) {
        fs::remove(json);
        std::vector<std::string> args = {"verify",    program.string(), "--model", near.string(),
                                         "--profile", profile.string(), "--json",  json.string()};
        if (!finished.empty()) args.insert(args.end(), {"--finished", finished.string()});
        return run_cli(args);
    };
    const CliRun ok = verify(inside);
    EXPECT_EQ(ok.exit_code, 0) << ok.out << ok.err;
    nlohmann::json r = nlohmann::json::parse(slurp(json));
    const double voxel = r.at("voxel_mm").get<double>();
    EXPECT_TRUE(r.at("finished_given").get<bool>());
    EXPECT_GE(r.at("finished_inside").get<double>(), 0.995) << ok.out;
    // The thinnest stock is the 1 mm under the part, within a voxel (and the beads' own edge).
    EXPECT_GT(r.at("smallest_stock_mm").get<double>(), 1.0 - 2.0 * voxel) << ok.out;
    EXPECT_LT(r.at("smallest_stock_mm").get<double>(), 1.0 + voxel) << ok.out;
    EXPECT_NE(ok.out.find("finished part   "), std::string::npos) << ok.out;

    const CliRun short_of = verify(out);
    EXPECT_EQ(short_of.exit_code, 3) << short_of.out << short_of.err;
    r = nlohmann::json::parse(slurp(json));
    EXPECT_LT(r.at("finished_inside").get<double>(), 0.97) << short_of.out;
    EXPECT_LT(r.at("smallest_stock_mm").get<double>(), 0.0) << short_of.out;
    const auto failed = r.at("failed_checks").get<std::vector<std::string>>();
    EXPECT_NE(std::find(failed.begin(), failed.end(), "finished_inside"), failed.end());
    EXPECT_NE(short_of.out.find("part match      no: finished part"), std::string::npos)
        << short_of.out;

    // Without --finished the model is the finished part: its share inside is the coverage.
    const CliRun plain = verify({});
    EXPECT_EQ(plain.exit_code, 0) << plain.out << plain.err;
    r = nlohmann::json::parse(slurp(json));
    EXPECT_FALSE(r.at("finished_given").get<bool>());
    EXPECT_EQ(r.at("finished_inside"), r.at("coverage"));

    // With the shipped profile (1 mm stock) the job deposits the finished part's near-net shape;
    // `verify --model FINISHED` makes and places it as the job does: the job's figures again,
    // the finished part all inside its beads with stock around it.
    const fs::path built = dir / "built.gm";
    const CliRun job =
        run_cli({"slice", inside.string(), "--profile", reference.string(), "-o", built.string()});
    ASSERT_EQ(job.exit_code, 0) << job.out << job.err;
    std::smatch coverage, finished;
    ASSERT_TRUE(std::regex_search(job.out, coverage,
                                  std::regex(R"(\ncoverage +([0-9.]+)% of the part, excess )")))
        << job.out;
    ASSERT_TRUE(std::regex_search(
        job.out, finished,
        std::regex(R"(\nfinished part +([0-9.]+)% inside beads, smallest stock (-?[0-9.]+) mm)")))
        << job.out;
    fs::remove(json);
    const CliRun grown = run_cli({"verify", built.string(), "--model", inside.string(), "--profile",
                                  reference.string(), "--json", json.string()});
    EXPECT_EQ(grown.exit_code, 0) << grown.out << grown.err;
    EXPECT_NE(grown.out.find("near-net shape  the model grown by 1.00 mm"), std::string::npos)
        << grown.out;
    EXPECT_EQ(grown.err.find("is the model placed"), std::string::npos) << grown.err;
    r = nlohmann::json::parse(slurp(json));
    EXPECT_TRUE(r.at("finished_given").get<bool>());
    EXPECT_NEAR(100.0 * r.at("coverage").get<double>(), std::stod(coverage[1].str()), 0.005 + 1e-9);
    EXPECT_NEAR(100.0 * r.at("finished_inside").get<double>(), std::stod(finished[1].str()),
                0.005 + 1e-9);
    EXPECT_NEAR(r.at("smallest_stock_mm").get<double>(), std::stod(finished[2].str()),
                0.005 + 1e-9);
    EXPECT_GE(r.at("finished_inside").get<double>(), 0.995) << grown.out;
    EXPECT_GT(r.at("smallest_stock_mm").get<double>(), 0.0) << grown.out;
    EXPECT_LT(r.at("smallest_stock_mm").get<double>(), 1.0 + r.at("voxel_mm").get<double>())
        << grown.out;
}
