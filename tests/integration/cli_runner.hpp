#pragma once
// Runs the maxslice CLI as a separate process and captures its exit code and output.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "support/text_files.hpp"

namespace maxslice::test {

struct CliRun {
    int exit_code = -1;  ///< the process's exit status, or 128 + signal number
    std::string out;
    std::string err;
};

/// A fresh, empty folder under the system's temporary folder, maxslice_<suite>_<name>_<pid>,
/// removed when the test process ends. The process id keeps two test runs at the same time
/// (two checkouts, or ctest -j over one) out of each other's files.
inline std::filesystem::path fresh_temp_dir(const std::string& suite, const std::string& name) {
    struct Cleanup {
        std::vector<std::filesystem::path> dirs;
        ~Cleanup() {
            for (const auto& d : dirs) {
                std::error_code ec;
                std::filesystem::remove_all(d, ec);
            }
        }
    };
    static Cleanup cleanup;
    const std::filesystem::path d =
        std::filesystem::temp_directory_path() /
        ("maxslice_" + suite + "_" + name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    cleanup.dirs.push_back(d);
    return d;
}

/// The shared test data, the source tree and its bundled example part.
inline const std::filesystem::path kTestData = MAXSLICE_TESTDATA_DIR;
inline const std::filesystem::path kSource = MAXSLICE_SOURCE_DIR;
inline const std::filesystem::path kExample = kSource / "examples/parts/flanged_bushing.stl";

/// Runs `maxslice args...` with a time limit (a hang shows as exit code 124). `shell_prefix`
/// runs in the same shell first (a limit such as "ulimit -f 64; trap '' XFSZ;").
inline CliRun run_cli(const std::vector<std::string>& args, int timeout_s = 300,
                      const std::string& shell_prefix = {}) {
    static int counter = 0;
    const auto dir = std::filesystem::temp_directory_path();
    const auto stem =
        "maxslice_cli_" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
    const auto out_file = dir / (stem + ".out");
    const auto err_file = dir / (stem + ".err");
    std::string cmd =
        shell_prefix + "timeout " + std::to_string(timeout_s) + " " + shell_quote(MAXSLICE_CLI);
    for (const auto& a : args) cmd += " " + shell_quote(a);
    cmd += " >" + shell_quote(out_file.string()) + " 2>" + shell_quote(err_file.string()) +
           " </dev/null";
    const int status = std::system(cmd.c_str());
    CliRun run;
    if (WIFEXITED(status)) {
        run.exit_code = WEXITSTATUS(status);
    } else if (WIFSIGNALED(status)) {
        run.exit_code = 128 + WTERMSIG(status);
    }
    run.out = slurp(out_file);
    run.err = slurp(err_file);
    std::filesystem::remove(out_file);
    std::filesystem::remove(err_file);
    return run;
}

}  // namespace maxslice::test
