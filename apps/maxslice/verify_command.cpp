#include "verify_command.hpp"

#include "cli_common.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>
#include <string_view>

#include "maxslice/core/files.hpp"
#include "maxslice/core/units.hpp"
#include "maxslice/io/read_mesh.hpp"
#include "maxslice/machine/profile.hpp"
#include "maxslice/machine/writer.hpp"
#include "maxslice/mesh/validation.hpp"
#include "maxslice/pipeline/near_net_job.hpp"
#include "maxslice/verify/verify.hpp"

namespace maxslice::app {
namespace {

// Why the model's surface does not bound its solid the right way round, or "".
std::string misoriented_model(const mesh::ValidationReport& r) {
    if (r.unbalanced_edges.count > 0) {
        return fmt::format(
            "has {} edges used more often one way than the other (inconsistent "
            "orientation)",
            r.unbalanced_edges.count);
    }
    if (r.inside_out_shells.count > 0) {
        return fmt::format("has {} inside-out {}", r.inside_out_shells.count,
                           r.inside_out_shells.count == 1 ? "body" : "bodies");
    }
    if (r.inward_pieces.count > 0) {
        return "has a body that faces inwards where bodies touch";
    }
    if (r.volume_mm3 < 0.0) return "is inside out (negative volume)";
    return {};
}

// A replay with more than this share of its material outside the model and less than this
// share of the model covered is most likely of a model placed otherwise than the program
// builds it: warned. (The job's own programs of closed meshes stay under 7 % excess, stop 13;
// a portal frame built upside down and replayed as the file has it: 24 % and 76 %.)
constexpr double kMisplacedExcess = 0.10;
constexpr double kMisplacedCoverage = 0.90;

// The base direction a program's header names (machine::kBaseDirectionTag, written by the
// dialects with comments), looked for in its first lines; nullopt when there is none or it
// does not read as three finite numbers, not all zero.
std::optional<core::Vec3d> header_direction(const std::string& text) {
    constexpr std::size_t kHeaderBytes = 4096;
    const std::string_view head = std::string_view(text).substr(0, kHeaderBytes);
    const std::size_t at = head.find(machine::kBaseDirectionTag);
    if (at == std::string_view::npos) return std::nullopt;
    const std::size_t begin = at + machine::kBaseDirectionTag.size();
    const std::size_t end = head.find('\n', begin);
    const std::string numbers(
        head.substr(begin, end == std::string_view::npos ? end : end - begin));
    double v[3] = {0.0, 0.0, 0.0};
    const char* p = numbers.c_str();
    for (int k = 0; k < 3; ++k) {
        char* next = nullptr;
        v[k] = std::strtod(p, &next);
        if (next == p || !std::isfinite(v[k])) return std::nullopt;
        p = next;
        if (k < 2) {
            if (*p != ',') return std::nullopt;
            ++p;
        }
    }
    if (v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0) return std::nullopt;
    return core::Vec3d{v[0], v[1], v[2]};
}

core::Result<std::string> read_text(const std::string& file) {
    if (auto ok = core::check_input_file(file, "program"); !ok) return std::unexpected(ok.error());
    std::ifstream in(file, std::ios::binary);
    if (!in) return core::fail(core::ErrorCode::kIo, "cannot open", "file " + file);
    std::ostringstream s;
    s << in.rdbuf();
    if (in.bad()) return core::fail(core::ErrorCode::kIo, "read failed", "file " + file);
    return s.str();
}

// The profiles with the process that made the program (decision 0019): the finer process
// `finer` when given, else the one whose laser power the program deposits with (the main
// process when none fits). Says which it took when that is a finer one, and warns when the
// program's powers belong to another process than the one replayed, or to none.
core::Result<machine::Profiles> process_of_program(const std::string& text, int finer,
                                                   const verify::VerifySettings& settings,
                                                   machine::Profiles profiles) {
    int found = -1;
    auto dialect = settings.dialect ? core::Result<verify::ProgramDialect>(*settings.dialect)
                                    : verify::dialect_of(profiles.machine);
    if (dialect) {
        // A program the replay cannot read is reported by verify_program below.
        if (const auto replay = verify::replay_program(text, profiles, *dialect)) {
            found = verify::process_of(*replay, profiles);
            if (found < 0 && !replay->laser_powers_w.empty()) {
                std::fprintf(
                    stderr,
                    "maxslice: warning: the program deposits with %.1f W, the power of "
                    "none of the profile's processes: its beads are replayed with the "
                    "%s process's %.2f mm track\n",
                    replay->laser_powers_w.front(), finer > 0 ? "given" : "main",
                    finer > 0
                        ? profiles.process.finer[static_cast<std::size_t>(finer - 1)].track_width_mm
                        : profiles.process.track_width_mm);
            }
        }
    }
    const int use = finer > 0 ? finer : std::max(found, 0);
    if (finer > 0 && found >= 0 && found != finer) {
        std::fprintf(stderr,
                     "maxslice: warning: the program deposits with the laser power of the "
                     "profile's %s, not of finer process %d (--finer): its beads are replayed "
                     "with the wrong track\n",
                     found == 0 ? "main process" : fmt::format("finer process {}", found).c_str(),
                     finer);
    }
    if (use == 0) return profiles;
    auto chosen = machine::with_finer_process(profiles, use);
    if (!chosen) return std::unexpected(core::with_context(chosen.error(), "--finer"));
    if (finer == 0) {
        std::printf(
            "process         finer %d: %.2f mm track, by the program's laser power "
            "(%.0f W)\n",
            use, chosen->process.track_width_mm, chosen->process.laser_power_w);
    }
    return chosen;
}

}  // namespace

CLI::App* add_verify_command(CLI::App& app, VerifyCommandOptions& opts) {
    CLI::App* cmd = app.add_subcommand(
        "verify",
        "Replay a program independently of the planner: lay beads, check the nozzle against "
        "deposited material, support, axis limits; measure coverage and excess");
    cmd->add_option("PROGRAM", opts.program, "Program file (gm, linuxcnc, fanuc or siemens)")
        ->required();
    cmd->add_option("--model", opts.model,
                    "The shape the program deposits: the part, or its near-net shape (placed as "
                    "the job does)")
        ->required();
    cmd->add_option("--finished", opts.finished,
                    "The finished part, when --model is its near-net shape (same file frame; "
                    "placed as --model is): its share inside beads and the smallest stock");
    cmd->add_option("--profile", opts.profiles, "Machine/process profile TOML file(s)")->required();
    cmd->add_option("--json", opts.json_file, "Write the report as JSON to this file");
    cmd->add_option("--dialect", opts.dialect,
                    "Program dialect: gm, linuxcnc, fanuc or siemens (default: the profile's)");
    cmd->add_option("--direction", opts.direction,
                    "Base (build) direction X,Y,Z of the part (default: the one the program's "
                    "header names, else 0,0,1)")
        ->delimiter(',')
        ->expected(3);
    cmd->add_option("--voxel", opts.voxel_mm, "Voxel edge in mm (default: automatic)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--clearance", opts.clearance_mm,
                    "Gap the nozzle above its tip and the head body must keep from material, mm "
                    "(default: the profile's [machine.nozzle] clearance_mm; 0: contact only)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--units", opts.units,
                    "Unit of the model file's numbers: mm, in, m, cm, um, ft");
    cmd->add_option("--min-coverage", opts.min_coverage_pct,
                    "Coverage of the model (percent) the program must reach (default 97, as "
                    "`slice` builds to)")
        ->check(CLI::Range(0.0, 100.0));
    cmd->add_option("--max-excess", opts.max_excess_pct,
                    "Excess (percent of the model) the program must stay under (default 5, as "
                    "`slice` builds to)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--finer", opts.finer,
                    "The program was made with the profile's finer process N "
                    "([[process.finer]]; the job's 'verify with' line names it)")
        ->check(CLI::PositiveNumber);
    return cmd;
}

int run_verify(const VerifyCommandOptions& opts) {
    std::vector<std::filesystem::path> files(opts.profiles.begin(), opts.profiles.end());
    auto profiles = machine::load_profiles(files);
    if (!profiles) return report_error(profiles.error());
    if (opts.finer > 0 && opts.finer > static_cast<int>(profiles->process.finer.size())) {
        return report_error(core::with_context(
            machine::with_finer_process(*profiles, opts.finer).error(), "--finer"));
    }

    if (!opts.json_file.empty()) {
        std::vector<std::filesystem::path> inputs(files.begin(), files.end());
        inputs.emplace_back(opts.program);
        inputs.emplace_back(opts.model);
        if (!opts.finished.empty()) inputs.emplace_back(opts.finished);
        if (auto ok = core::check_output_not_input(opts.json_file, "--json", inputs); !ok) {
            return report_error(ok.error());
        }
    }
    verify::VerifySettings settings;
    settings.voxel_mm = opts.voxel_mm;
    settings.clearance_mm = opts.clearance_mm;
    settings.min_coverage = opts.min_coverage_pct / 100.0;
    settings.max_excess = opts.max_excess_pct / 100.0;
    if (!opts.dialect.empty()) {
        auto d = verify::parse_dialect(opts.dialect);
        if (!d) return report_error(core::with_context(d.error(), "--dialect"));
        settings.dialect = *d;
    }
    io::ImportOptions import;
    if (!opts.units.empty()) {
        auto u = core::parse_unit(opts.units);
        if (!u) {
            return report_error({core::ErrorCode::kInvalidInput,
                                 "unknown unit '" + opts.units + "' (use mm, in, m, cm, um or ft)",
                                 "--units"});
        }
        import.units = *u;
    }
    auto model = io::read_mesh(opts.model, import);
    if (!model) return report_error(model.error());
    // The replay measures coverage and excess against what the model's surface encloses by
    // its winding: a body that faces inwards encloses nothing there (the job refuses such a
    // model; a replay only says so).
    if (const std::string why = misoriented_model(mesh::validate(model->mesh)); !why.empty()) {
        std::fprintf(stderr,
                     "maxslice: warning: the model %s: coverage and excess are measured against "
                     "what its surface encloses, which leaves that material out\n",
                     why.c_str());
    }
    std::optional<mesh::TriangleMesh> finished;
    if (!opts.finished.empty()) {
        auto f = io::read_mesh(opts.finished, import);
        if (!f) return report_error(core::with_context(f.error(), "--finished"));
        if (const std::string why = misoriented_model(mesh::validate(f->mesh)); !why.empty()) {
            std::fprintf(stderr,
                         "maxslice: warning: the finished part %s: its share inside beads is "
                         "measured against what its surface encloses, which leaves that "
                         "material out\n",
                         why.c_str());
        }
        finished = std::move(f->mesh);
    }
    auto text = read_text(opts.program);
    if (!text) return report_error(text.error());
    if (auto chosen = process_of_program(*text, opts.finer, settings, *profiles); !chosen) {
        return report_error(chosen.error());
    } else {
        profiles = std::move(*chosen);
    }
    core::Vec3d direction{0.0, 0.0, 1.0};
    if (!opts.direction.empty()) {
        direction = {opts.direction[0], opts.direction[1], opts.direction[2]};
    } else if (const auto d = header_direction(*text)) {
        direction = *d;
        std::printf("placement       the model stands along %s, as the program's header says\n",
                    fmt::format("{},{},{}", d->x, d->y, d->z).c_str());
    }
    // A profile with a machining stock or fill: the job deposited the near-net shape of the part
    // it read (decision 0025). Without --finished, --model is that part, and the replay is
    // against its near-net shape, made as the job makes it (the same bytes), placed as the job
    // places it (place_model: its lowest point on the plate, its XY box centred).
    // A model whose near-net shape cannot be made (a part in other units outgrows the field's
    // bound; the job refuses such a part) is still replayed, against the model itself: the
    // safety checks do not depend on it, and the figures then say how far the program is
    // from that model. The warning names why and what the figures are of.
    if (!finished) {
        const nearnet::NearNetSettings near = pipeline::near_net_settings(profiles->process);
        if (!near.off()) {
            auto shape = nearnet::near_net(model->mesh, near);
            if (!shape && shape.error().code != core::ErrorCode::kInvalidInput) {
                return report_error(core::with_context(shape.error(), "--model"));
            }
            if (shape) {
                std::printf(
                    "near-net shape  the model grown by %.2f mm, holes under %.2f mm filled "
                    "(the profile's machining stock and fill)\n",
                    near.stock_mm, near.fill_below_mm);
                finished = std::move(model->mesh);
                model->mesh = std::move(shape->mesh);
            } else {
                std::printf(
                    "near-net shape  none: the program is replayed against the model itself\n");
                std::fprintf(stderr,
                             "maxslice: warning: --model: the near-net shape the profile asks for "
                             "(%.2f mm stock, holes under %.2f mm filled) cannot be made: %s; the "
                             "program is replayed against the model itself, without the stock "
                             "(a slice job refuses this model)\n",
                             near.stock_mm, near.fill_below_mm, shape.error().message.c_str());
            }
        }
    }
    // The finished part moves with the model: the job places what it deposits (decision 0026).
    std::optional<mesh::TriangleMesh> placed_finished;
    if (finished) {
        auto f =
            verify::place_like(std::move(*finished), model->mesh, direction, profiles->machine);
        if (!f) return report_error(core::with_context(f.error(), "--finished"));
        placed_finished = std::move(*f);
    }
    auto placed = verify::place_model(std::move(model->mesh), direction, profiles->machine);
    if (!placed) return report_error(placed.error());
    auto report = verify::verify_program(*text, *placed, *profiles, settings,
                                         placed_finished ? &*placed_finished : nullptr);
    if (!report) return report_error(core::with_context(report.error(), "file " + opts.program));

    std::fputs(verify::report_text(*report).c_str(), stdout);
    // Most of the material outside the model: the model is likely placed otherwise than the
    // program builds it (a job that stood the part on another base prints the --direction to
    // replay it with).
    if (report->model_open_columns == 0 && report->excess > kMisplacedExcess &&
        report->coverage < kMisplacedCoverage) {
        std::fprintf(stderr,
                     "maxslice: warning: %.0f%% of the deposited material lies outside the model "
                     "and %.0f%% of the model is covered: is the model placed as the program "
                     "builds it? A program that `maxslice slice` built on another base (its "
                     "\"orientation\" line) is replayed with the --direction it printed\n",
                     100.0 * report->excess, 100.0 * report->coverage);
    }
    if (!opts.json_file.empty()) {
        if (auto ok = core::write_file_atomic(opts.json_file, verify::report_json(*report)); !ok) {
            return report_error(core::with_context(ok.error(), "--json"));
        }
    }
    if (!report->accepted()) {
        const bool unsafe = !report->passed(), mismatch = !report->matches_part();
        std::fprintf(stderr, "maxslice: error: verification failed (%s): the program %s%s%s\n",
                     fmt::format("{}", fmt::join(verify::failed_checks(*report), ", ")).c_str(),
                     unsafe ? "is not safe to run" : "", unsafe && mismatch ? " and " : "",
                     mismatch ? "does not build the part (--min-coverage and --max-excess "
                                "state other figures)"
                              : "");
        return kExitRefused;
    }
    if (!report->coverage_judged()) {
        std::fprintf(stderr,
                     "maxslice: warning: the model is not closed or has a body inside out: "
                     "coverage and excess are estimates, and not judged\n");
    }
    return kExitOk;
}

}  // namespace maxslice::app
