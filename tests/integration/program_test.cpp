// Programs as a process engineer gets them from the CLI: parsed back and checked for the
// properties that matter on the cell (laser only while depositing, feeds, limits), accepted
// by LinuxCNC's own interpreter, refused cleanly for bad profiles, identical bytes for any
// thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"

namespace fs = std::filesystem;
using maxslice::test::CliRun;
using maxslice::test::kExample;
using maxslice::test::kSource;
using maxslice::test::kTestData;
using maxslice::test::run_cli;
using maxslice::test::shell_quote;
using maxslice::test::slurp;

namespace {

const fs::path kReference = kSource / "examples/profiles/reference_lmd.toml";
const fs::path kLinuxCnc = kSource / "examples/profiles/linuxcnc_generic.toml";

fs::path temp_dir(const std::string& name) {
    return maxslice::test::fresh_temp_dir("program_test", name);
}

// One line of GM code: power and powder columns, then the block.
struct GmLine {
    double power = 0.0;
    double powder = 0.0;
    std::string block;
};

std::vector<GmLine> read_gm(const std::string& text) {
    std::vector<GmLine> out;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream ls(line);
        GmLine g;
        ls >> g.power >> g.powder;
        EXPECT_FALSE(ls.fail()) << "no power/powder columns: " << line;
        std::getline(ls, g.block);
        g.block.erase(0, g.block.find_first_not_of(' '));
        out.push_back(g);
    }
    return out;
}

double word(const std::string& block, char letter) {
    const auto pos = block.find(std::string(" ") + letter);
    if (pos == std::string::npos) return NAN;
    return std::stod(block.substr(pos + 2));
}

}  // namespace

TEST(Program, GmLaserIsOnOnlyWhileDepositing) {
    const fs::path dir = temp_dir("gm");
    const CliRun r = run_cli({"slice", kExample.string(), "--profile", kReference.string(), "-o",
                              (dir / "p.gm").string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto lines = read_gm(slurp(dir / "p.gm"));
    ASSERT_GT(lines.size(), 1000u);
    EXPECT_EQ(lines[0].block, "G21");
    EXPECT_EQ(lines[1].block, "G90");
    bool on = false;
    int wires = 0, deposits = 0;
    double last_z = 0.0;
    for (const GmLine& g : lines) {
        if (g.block == "M8") {
            EXPECT_FALSE(on) << "M8 twice";
            on = true;
            ++wires;
        } else if (g.block == "M9") {
            EXPECT_TRUE(on) << "M9 without M8";
            on = false;
        } else if (g.block.rfind("G1", 0) == 0) {
            const double f = word(g.block, 'F');
            if (on) {
                ++deposits;
                EXPECT_DOUBLE_EQ(g.power, 700.0) << g.block;
                EXPECT_DOUBLE_EQ(g.powder, 8.0) << g.block;
                EXPECT_DOUBLE_EQ(f, 381.0) << g.block;
            } else {
                EXPECT_DOUBLE_EQ(g.power, 0.0) << g.block;
                EXPECT_DOUBLE_EQ(f, 2540.0) << g.block;
            }
            const double z = word(g.block, 'Z');
            EXPECT_GE(z, last_z - 1e-9) << "the head never goes down: " << g.block;
            last_z = z;
        } else if (g.block.rfind("G4", 0) == 0) {
            EXPECT_TRUE(on) << "dwell after laser on";
        }
    }
    EXPECT_FALSE(on) << "laser left on at the end";
    EXPECT_GT(wires, 60);
    EXPECT_GT(deposits, wires);
}

TEST(Program, LinuxCncProgramsOfEverySharedMeshPassRs274) {
    if (!fs::exists("/usr/bin/rs274")) GTEST_SKIP() << "rs274 (linuxcnc-uspace) not installed";
    const fs::path dir = temp_dir("rs274");
    int written = 0;
    for (const auto& e : fs::recursive_directory_iterator(kTestData / "meshes")) {
        if (!e.is_regular_file()) continue;
        const fs::path ngc = dir / (e.path().stem().string() + ".ngc");
        const CliRun r = run_cli({"slice", e.path().string(), "--profile", kLinuxCnc.string(),
                                  "--repair", "-o", ngc.string()},
                                 300);
        // Parts bigger than the gantry, or too small for a 2.5 mm bead, are refused with a
        // reason; everything written must be accepted by the controller's interpreter.
        ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 2) << e.path() << "\n" << r.err;
        if (r.exit_code != 0) {
            EXPECT_FALSE(fs::exists(ngc)) << "no program is written when the job fails";
            continue;
        }
        ++written;
        const std::string cmd = "rs274 -g " + shell_quote(ngc.string()) + " " +
                                shell_quote((dir / "canon.txt").string()) + " </dev/null 2>" +
                                shell_quote((dir / "rs274.err").string());
        const int status = std::system(cmd.c_str());
        EXPECT_EQ(status, 0) << e.path() << "\n" << slurp(dir / "rs274.err");
        EXPECT_NE(slurp(dir / "canon.txt").find("PROGRAM_END"), std::string::npos);
        fs::remove(ngc);
    }
    EXPECT_GE(written, 10);
}

TEST(Program, BadProfilesExitTwoNamingTheKey) {
    const fs::path dir = temp_dir("bad_profiles");
    const std::string good = slurp(kReference);
    struct Case {
        std::string name, from, to, key;
    };
    const std::vector<Case> cases = {
        {"missing", "track_width_mm = 2.5\n", "", "track_width_mm"},
        {"negative_width", "track_width_mm = 2.5", "track_width_mm = -2.5", "track_width_mm"},
        {"overlap", "overlap = 0.3", "overlap = 1.0", "overlap"},
        {"dialect", "dialect = \"gm\"", "dialect = \"heidenhain\"", "dialect"},
        {"layer_above_width", "layer_height_mm = 0.5", "layer_height_mm = 3.0", "layer_height_mm"},
    };
    for (const Case& c : cases) {
        std::string text = good;
        const auto pos = text.find(c.from);
        ASSERT_NE(pos, std::string::npos) << c.name;
        text.replace(pos, c.from.size(), c.to);
        const fs::path file = dir / (c.name + ".toml");
        std::ofstream(file) << text;
        const CliRun r = run_cli({"slice", kExample.string(), "--profile", file.string(), "-o",
                                  (dir / "p.gm").string()});
        EXPECT_EQ(r.exit_code, 2) << c.name << "\n" << r.err;
        EXPECT_NE(r.err.find(c.key), std::string::npos) << c.name << "\n" << r.err;
        EXPECT_FALSE(fs::exists(dir / "p.gm")) << c.name;
    }
    const CliRun r =
        run_cli({"slice", kExample.string(), "--layer", "3", "-o", (dir / "p.gm").string()});
    EXPECT_EQ(r.exit_code, 2) << "a layer thicker than the bead\n" << r.err;
}

TEST(Program, SameBytesForAnyThreadCount) {
    const fs::path dir = temp_dir("determinism");
    const std::string part = (kTestData / "meshes/trimesh/plate_holes.STL").string();
    for (const std::string t : {"1", "2"}) {
        for (const std::string dialect : {"gm", "linuxcnc"}) {
            const CliRun r = run_cli({"slice", part, "--threads", t, "--dialect", dialect, "-o",
                                      (dir / (dialect + t)).string()});
            ASSERT_EQ(r.exit_code, 0) << r.err;
        }
    }
    EXPECT_EQ(slurp(dir / "gm1"), slurp(dir / "gm2"));
    EXPECT_EQ(slurp(dir / "linuxcnc1"), slurp(dir / "linuxcnc2"));
    EXPECT_GT(slurp(dir / "gm1").size(), 10000u);
}
