// `maxslice verify PROGRAM --model PART [--finished PART] --profile FILE...`: the independent
// verifier
// (docs/verifier.md).
#pragma once

#include <string>
#include <vector>

#include "maxslice/verify/verify.hpp"

namespace CLI {
class App;
}

namespace maxslice::app {

/// The verify command's options, filled by CLI11.
struct VerifyCommandOptions {
    std::string program;
    std::string model;
    std::string finished;  ///< --finished: the finished part (empty: the model is it)
    std::vector<std::string> profiles;
    std::string json_file;
    std::string dialect;
    std::vector<double> direction;  ///< empty: the program's header, else +Z
    double voxel_mm = 0.0;
    std::optional<double> clearance_mm;  ///< --clearance (unset: the profile's)
    std::string units;
    int finer = 0;  ///< the profile's finer process the program was made with (0: the main one)
    double min_coverage_pct = 100.0 * verify::kMinCoverage;  ///< --min-coverage
    double max_excess_pct = 100.0 * verify::kMaxExcess;      ///< --max-excess
};

/// Adds the `verify` subcommand to `app`, binding its options to `opts` (which must outlive
/// the parse); returns the subcommand.
CLI::App* add_verify_command(CLI::App& app, VerifyCommandOptions& opts);

/// Runs the verification: prints the text report on stdout, writes the JSON report when asked.
/// Exit code (docs/verifier.md): 0 when the program is safe and builds the part, 3
/// (kExitRefused) when it is unsafe (Report::passed()) or does not build the part
/// (Report::matches_part()), 2 when the input is bad (with a message on stderr), 1 for an
/// internal error.
int run_verify(const VerifyCommandOptions& opts);

}  // namespace maxslice::app
