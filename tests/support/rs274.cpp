#include "support/rs274.hpp"

#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

#include "support/text_files.hpp"

namespace maxslice::test {

namespace fs = std::filesystem;

fs::path find_rs274() {
    if (const char* env = std::getenv("MAXSLICE_RS274")) return env;
    for (const char* p : {"/usr/bin/rs274", "/usr/lib/linuxcnc/bin/rs274"}) {
        if (fs::exists(p)) return p;
    }
    return {};
}

std::optional<Rs274Run> run_rs274(const std::string& program) {
    const fs::path rs274 = find_rs274();
    if (rs274.empty()) return std::nullopt;
    static std::atomic<int> runs{0};
    const fs::path dir =
        fs::temp_directory_path() /
        ("maxslice_rs274_" + std::to_string(::getpid()) + "_" + std::to_string(runs.fetch_add(1)));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path ngc = dir / "program.ngc", canon = dir / "canon.txt", err = dir / "err.txt";
    std::ofstream(ngc, std::ios::binary) << program;
    const std::string cmd =
        "cd " + shell_quote(dir.string()) + " && HOME=" + shell_quote(dir.string()) +
        " timeout 120 " + shell_quote(rs274.string()) + " -g " + shell_quote(ngc.string()) + " " +
        shell_quote(canon.string()) + " </dev/null >/dev/null 2>" + shell_quote(err.string());
    Rs274Run run;
    run.status = std::system(cmd.c_str());
    run.canon = slurp(canon);
    run.errors = slurp(err);
    std::error_code ec;
    fs::remove_all(dir, ec);
    return run;
}

std::vector<std::array<double, 6>> canonical_moves(const std::string& canon, bool traverses) {
    std::vector<std::array<double, 6>> moves;
    std::istringstream lines(canon);
    for (std::string line; std::getline(lines, line);) {
        std::size_t at = line.find("STRAIGHT_FEED(");
        if (at != std::string::npos) {
            at += 14;
        } else if (traverses && (at = line.find("STRAIGHT_TRAVERSE(")) != std::string::npos) {
            at += 18;
        } else {
            continue;
        }
        std::string args = line.substr(at);
        for (char& ch : args) {
            if (ch == ',' || ch == ')') ch = ' ';
        }
        std::istringstream in(args);
        std::array<double, 6> v{};
        for (double& x : v) in >> x;
        if (in.fail()) v.fill(std::numeric_limits<double>::quiet_NaN());
        moves.push_back(v);
    }
    return moves;
}

bool only_executing(const std::string& errors) {
    return errors.find_first_not_of("executing\n") == std::string::npos;
}

}  // namespace maxslice::test
