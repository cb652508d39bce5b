// The maxslice command line: parse, call the library, map errors to exit codes.
// Exit codes: 0 success, 2 bad input (unreadable, invalid, unsliceable, bad options),
// 1 internal error.
#include <fmt/format.h>
#include <fmt/printf.h>
#include <tbb/global_control.h>
#include <unistd.h>
#include <CLI/CLI.hpp>
#if defined(MAXSLICE_WITH_MIMALLOC)
#include <mimalloc.h>
#endif

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cli_common.hpp"
#include "maxslice/core/files.hpp"
#include "maxslice/core/units.hpp"
#include "maxslice/machine/machine_moves.hpp"
#include "maxslice/machine/profile.hpp"
#include "maxslice/machine/program_builder.hpp"
#include "maxslice/machine/summary.hpp"
#include "maxslice/machine/writer.hpp"
#include "maxslice/pipeline/near_net_job.hpp"
#include "maxslice/pipeline/orient_job.hpp"
#include "maxslice/pipeline/plan_job.hpp"
#include "maxslice/pipeline/previews.hpp"
#include "maxslice/pipeline/program_job.hpp"
#include "maxslice/pipeline/slice_job.hpp"
#include "maxslice/slice/slicer.hpp"
#include "maxslice/verify/verify.hpp"
#include "reference_profile.hpp"
#include "verify_command.hpp"

namespace {

using namespace maxslice;

using app::kExitBadInput;
using app::kExitInternal;
using app::kExitOk;
using app::report_error;

// Options shared by every command that reads a part.
struct PartOptions {
    std::string path;
    std::string units;
    bool repair = false;
    double chord_mm = 0.05;
    int threads = 0;
    bool timings = false;

    void add_to(CLI::App& cmd) {
        cmd.add_option("PART", path, "Part file: STL, OBJ, PLY, OFF, 3MF, STEP or IGES")
            ->required();
        cmd.add_option("--units", units,
                       "Unit of the file's numbers: mm, in, m, cm, um, ft (overrides the file)");
        cmd.add_flag("--repair", repair,
                     "Apply safe repairs: weld near-coincident vertices, drop degenerate and "
                     "duplicate faces, fix orientation");
        cmd.add_option("--chord-deviation", chord_mm,
                       "STEP/IGES tessellation: largest chord deviation in mm")
            ->check(CLI::PositiveNumber);
        cmd.add_option("--threads", threads, "Worker threads (0 = all cores)")
            ->check(CLI::NonNegativeNumber);
        cmd.add_flag("--timings", timings, "Print stage times (seconds) to stderr");
    }

    [[nodiscard]] core::Result<pipeline::PrepareSettings> settings() const {
        pipeline::PrepareSettings s;
        s.repair = repair;
        s.import.chord_deviation_mm = chord_mm;
        if (!units.empty()) {
            auto u = core::parse_unit(units);
            if (!u) {
                return core::fail(core::ErrorCode::kInvalidInput,
                                  "unknown unit '" + units + "' (use mm, in, m, cm, um or ft)",
                                  "--units");
            }
            s.import.units = *u;
        }
        return s;
    }
};

void print_warnings(const pipeline::PreparedPart& part) {
    for (const auto& w : part.warnings) std::fprintf(stderr, "maxslice: warning: %s\n", w.c_str());
    for (const auto& r : part.repairs) std::fprintf(stderr, "maxslice: repaired: %s\n", r.c_str());
}

std::string timings_text(const pipeline::StageTimes& t, bool program = false) {
    std::string out =
        fmt::format("timing load {:.4f}\ntiming validate {:.4f}\n", t.load_s, t.validate_s);
    if (t.near_net_s > 0.0) out += fmt::format("timing near-net {:.4f}\n", t.near_net_s);
    if (t.bases > 0) {
        if (t.attempts > 1) {
            out += fmt::format(
                "timing attempts {} (a finer process or another base, one after another: each "
                "time below is their sum)\n",
                t.attempts);
        }
        out += fmt::format("timing plan {:.4f}\ntiming order {:.4f}\n", t.plan_s, t.order_s);
        if (t.bases > t.attempts) {
            out += fmt::format("timing search {:.4f} ({} other bases)\n", t.search_s,
                               t.bases - t.attempts);
        }
    } else {
        out += fmt::format("timing slice {:.4f}\n", t.slice_s);
    }
    if (program && t.paths_s > 0.0) {
        out += fmt::format("timing paths {:.4f}\ntiming write {:.4f}\n", t.paths_s, t.write_s);
    }
    if (t.verify_s > 0.0) out += fmt::format("timing verify {:.4f}\n", t.verify_s);
    return out;
}

void print_timings(const pipeline::StageTimes& t) {
    std::fputs(timings_text(t).c_str(), stderr);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// What a program job prints, kept until the job is done: a job whose process leaves the part
// under the coverage target is run again with a finer one, and only the run kept is printed
// (decision 0019). printf-style, as the rest of this file.
struct Printed {
    std::string out, err;  // stdout and stderr
    template <class... A>
    void print(const char* format, const A&... args) {
        out += fmt::sprintf(format, args...);
    }
    template <class... A>
    void warn(const char* format, const A&... args) {
        err += fmt::sprintf(format, args...);
    }
    std::string refusal;  // the last error's message up to its first detail
    // report_error's line and exit code, kept.
    int error(const core::Error& e) {
        err += fmt::format("maxslice: error: {}\n",
                           core::printable(e.describe(), app::kMaxMessageChars));
        refusal = e.message.substr(
            0, std::min({e.message.find(": "), e.message.find(" ("), e.message.find("; ")}));
        return e.code == core::ErrorCode::kInternal ? kExitInternal : kExitBadInput;
    }
    void flush() const {
        std::fputs(err.c_str(), stderr);
        std::fputs(out.c_str(), stdout);
    }
};

// Prints a command's report on stdout; a failed write (a full disk, a closed pipe) is an error,
// not a silent success.
int print_out(std::string_view text) {
    if (auto ok = core::write_stdout(text); !ok) return report_error(ok.error());
    return kExitOk;
}

// A one-line progress bar on stderr, only when stderr is a terminal.
std::unique_ptr<core::Progress> make_progress() {
    if (isatty(STDERR_FILENO) == 0) return nullptr;
    return std::make_unique<core::Progress>([](std::string_view stage, double f) {
        static thread_local int last = -1;
        const int pct = static_cast<int>(f * 100.0);
        if (pct == last) return;
        last = pct;
        std::fprintf(stderr, "\r%-10.*s %3d%%%s", static_cast<int>(stage.size()), stage.data(), pct,
                     pct >= 100 ? "\r                \r" : "");
    });
}

int run_info(const PartOptions& opt, bool json) {
    auto settings = opt.settings();
    if (!settings) return report_error(settings.error());
    pipeline::StageTimes times;
    // info reports what is wrong rather than refusing: read, validate, repair if asked.
    auto part = pipeline::read_part(opt.path, *settings, &times);
    if (!part) return report_error(part.error());
    const std::string text = json ? pipeline::info_json(*part) : pipeline::info_text(*part);
    if (opt.timings) print_timings(times);
    return print_out(text);
}

struct SliceOptions {
    double layer = 0.5;
    bool layer_given = false;
    std::vector<std::string> profiles;
    std::string output;
    std::string dialect;
    std::vector<double> direction{0.0, 0.0, 1.0};
    bool direction_given = false;
    std::string orient;  ///< given, auto, or empty: given, other orientations if it fails
    bool adaptive = false;
    double cusp = 0.1;
    std::optional<double> min_layer, max_layer;
    std::string svg_dir, contact_sheet, json_file;
    bool allow_overhangs = false;
    bool no_verify = false;
    std::string finer = "auto";  ///< auto, off, or N: the profile's finer processes (0019)
};

// The profiles for a program: the files given, or the built-in reference cell, with the
// command line's overrides applied and checked again.
core::Result<machine::Profiles> load_profiles(const SliceOptions& so) {
    machine::Profiles profiles;
    if (so.profiles.empty()) {
        auto file = machine::parse_profile(kReferenceProfileToml, "built-in reference_lmd.toml");
        if (!file) return std::unexpected(file.error());
        profiles = {*file->machine, *file->process};
    } else {
        std::vector<std::filesystem::path> files(so.profiles.begin(), so.profiles.end());
        auto loaded = machine::load_profiles(files);
        if (!loaded) return loaded;
        profiles = *loaded;
    }
    if (so.layer_given) {
        profiles.process.layer_height_mm = so.layer;
        if (auto ok = machine::validate(profiles.process); !ok) {
            return std::unexpected(core::with_context(ok.error(), "--layer"));
        }
    }
    if (!so.dialect.empty()) {
        const auto dialect = machine::parse_dialect(so.dialect);
        if (!dialect) {
            return core::fail(
                core::ErrorCode::kInvalidInput,
                "unknown dialect '" + so.dialect + "' (use gm, linuxcnc, fanuc or siemens)",
                "--dialect");
        }
        profiles.machine.dialect = *dialect;
    }
    return profiles;
}

// Refuses, before any work, an output flag given an empty path or the path of an input (the
// part or a profile): nothing a user had is overwritten. (The part's reader and the profile
// loader refuse an input that is not a regular file without blocking on it.)
int check_outputs(const CLI::App& cmd, std::initializer_list<const char*> flags,
                  const std::string& part, const std::vector<std::string>& profiles) {
    std::vector<std::filesystem::path> inputs{part};
    inputs.insert(inputs.end(), profiles.begin(), profiles.end());
    for (const char* flag : flags) {
        const CLI::Option* o = cmd.get_option(flag);
        if (o->count() == 0) continue;
        const auto path = o->as<std::string>();
        if (path.empty()) {
            return report_error(
                {core::ErrorCode::kInvalidInput, "the output path is empty: name a file", flag});
        }
        if (auto ok = core::check_output_not_input(path, flag, inputs); !ok) {
            return report_error(ok.error());
        }
    }
    return kExitOk;
}

// Writes an output file whole or not at all: a failure leaves the previous file as it was.
int write_text_file(const std::string& file, const std::string& text) {
    if (auto ok = core::write_file_atomic(file, text); !ok) return report_error(ok.error());
    return kExitOk;
}

// A program that deposits nothing is refused (every feature narrower than the track, or a
// part in other units); one that leaves more than 5% of the section area without a track is
// written with a loud warning: the program is not the part then.
int check_tracks(Printed& o, const machine::ProgramSummary& sum, double uncovered_mm2,
                 double area_mm2, int layers_with_uncovered, const machine::ProcessProfile& process,
                 const std::string& part) {
    if (sum.laser_on_count == 0) {
        return o.error(
            {core::ErrorCode::kInvalidInput,
             fmt::format("no track fits in any layer: every feature of the part is narrower than "
                         "the {:.2f} mm track (process.track_width_mm), or the part is in other "
                         "units (see --units); no program is written",
                         process.track_width_mm),
             part});
    }
    if (area_mm2 > 0.0 && uncovered_mm2 > 0.05 * area_mm2) {
        o.warn(
            "maxslice: warning: %.1f%% of the section area gets no track (features "
            "narrower than the %.2f mm track, process.track_width_mm); %d layers are "
            "affected\n",
            100.0 * uncovered_mm2 / area_mm2, process.track_width_mm, layers_with_uncovered);
    }
    return kExitOk;
}

// The independent verifier replays the program text before it is kept: a program that
// collides, deposits on nothing (unless --allow-overhangs) or leaves an axis' travel is never
// written (skipped with --no-verify). Whether the verifier's report lets the program be
// written (--allow-overhangs tolerates unsupported beads, nothing else):
bool verifier_keeps(const verify::Report& report, const SliceOptions& so) {
    return report.passed() || (so.allow_overhangs && report.passed_apart_from_support());
}

// "(2 collisions, 0 unsupported beads, 0 axis-limit violations, 0 closer than the 2.00 mm
// clearance)", with the program's other findings when it has them (values out of range, a
// cut end, the laser left on); with `first`, the first finding too ("...; first: program
// line L: what").
std::string verifier_counts(const verify::Report& report, bool first = false) {
    std::string what;
    for (const verify::Finding* f :
         {&report.collisions, &report.clearance, &report.unsupported, &report.limit_violations,
          &report.out_of_range, &report.unfinished, &report.left_on}) {
        if (first && f->first) {
            what = fmt::format("; first: program line {}: {}", f->first->line,
                               core::printable(f->first->detail));
            break;
        }
    }
    std::string others;
    for (const auto& [f, name] : {std::pair{&report.out_of_range, "values out of range"},
                                  std::pair{&report.unfinished, "unfinished"},
                                  std::pair{&report.left_on, "laser or powder left on"}}) {
        if (f->count > 0) others += fmt::format(", {} {}", f->count, name);
    }
    return fmt::format(
        "({} collisions, {} unsupported beads, {} axis-limit violations, {} closer than the "
        "{:.2f} mm clearance{}{})",
        report.collisions.count, report.unsupported.count, report.limit_violations.count,
        report.clearance.count, report.clearance_mm, others, what);
}

// Prints the verifier's report of a program it refused and the error.
int refuse_unverified(Printed& o, const verify::Report& report, const SliceOptions& so) {
    o.err += verify::report_text(report);
    return o.error({core::ErrorCode::kInvalidInput,
                    fmt::format("the verifier refused the program {}: nothing written",
                                verifier_counts(report)),
                    so.output});
}

// The program of the last plan (or planar stack) the orientation search asked about,
// written and replayed in the verifier: one the verifier refuses is not kept while another
// orientation builds (decision 0015).
template <class Planned>
struct Written {
    std::optional<Planned> program;
    std::string text;
    std::optional<verify::Report> report;
    bool kept = false;  // the verifier passed it (or --no-verify, or no track at all)
    double paths_s = 0.0, write_s = 0.0, verify_s = 0.0;
    // Beads the verifier found resting on nothing, left out before it passed the program.
    std::size_t left_out_beads = 0;
    double left_out_mm = 0.0;
    // Travels the verifier found meeting the part (or within the clearance), taken over it.
    std::size_t lifted_travels = 0;
};

// A program the verifier refuses only for a few beads on nothing (the toolpaths' support
// model and the verifier's voxels disagree at a track's end by a fraction of a voxel) has
// those beads left out and is replayed again, at most this many times (decision 0039).
constexpr int kLeaveOutRounds = 3;
// ... when they are at most this share of its deposit blocks: more is a plan that does not
// hold, and is refused.
constexpr double kLeaveOutShare = 0.01;
// A verifier's pose lies on the program's track within the written digits (0.001 mm and
// 0.001 deg at the table's reach); a track this close to one is the one it lies on.
constexpr double kLeaveOutWithinMm = 0.01;

// A program the verifier refuses only for travels that meet the part or come within the
// clearance (a straight travel between a layer's islands across material of other regions,
// built before and standing above the layer) has those travels taken over the part and is
// replayed again, at most this many times (decision 0048) ...
constexpr int kLiftRounds = 2;
// ... this far above the part's highest point along the head's direction (mm), at least the
// nozzle's clearance.
constexpr double kLiftMarginMm = 2.0;

bool travels_to_lift(const verify::Report& report) {
    const std::size_t faults = report.collisions.count + report.clearance.count;
    return faults > 0 && report.travel_fault_ends.size() == faults &&
           report.limit_violations.count == 0 && report.out_of_range.count == 0 &&
           report.unfinished.count == 0 && report.left_on.count == 0;
}

bool beads_to_leave_out(const verify::Report& report) {
    return report.passed_apart_from_support() && !report.unsupported_tips.empty() &&
           static_cast<double>(report.unsupported.count) <=
               kLeaveOutShare * static_cast<double>(report.deposit_moves);
}

// Writes w.program's text, naming the part file's `direction` it builds upwards, and replays
// it in the verifier (unless --no-verify); "" when it is kept, else the verifier's refusal
// for the orientation search. A program without any track is "kept": check_tracks refuses it
// whatever the orientation. `placed` is what the program deposits; `finished` (file frame),
// when the job deposits a near-net shape, the finished part: the verifier gets it placed as
// `built` (the deposited part in the file frame) is placed.
template <class Planned>
core::Result<std::string> write_and_verify(Written<Planned>& w, const core::Vec3d& direction,
                                           const mesh::TriangleMesh& placed,
                                           const machine::Profiles& profiles,
                                           const SliceOptions& so, const machine::WriteOptions& wo,
                                           const mesh::TriangleMesh* finished = nullptr,
                                           const mesh::TriangleMesh* built = nullptr) {
    w.program->program.base_direction = direction;
    w.kept = w.program->summary.laser_on_count == 0;
    if (w.kept) return std::string();
    auto t = std::chrono::steady_clock::now();
    auto text = machine::write_program(w.program->program, profiles.machine, profiles.process, wo);
    if (!text) return std::unexpected(text.error());
    w.text = std::move(*text);
    w.write_s = seconds_since(t);
    w.kept = so.no_verify;
    if (w.kept) return std::string();
    t = std::chrono::steady_clock::now();
    std::optional<mesh::TriangleMesh> placed_finished;
    if (finished != nullptr) {
        auto f = verify::place_like(*finished, *built, direction, profiles.machine);
        if (!f) return std::unexpected(core::with_context(f.error(), "placing the finished part"));
        placed_finished = std::move(*f);
    }
    const auto replay = [&]() -> core::Result<void> {
        auto r = verify::verify_program(w.text, placed, profiles, {},
                                        placed_finished ? &*placed_finished : nullptr);
        if (!r) return std::unexpected(core::with_context(r.error(), "verifying the program"));
        w.report = std::move(*r);
        return {};
    };
    // The program changed: summarized, written and replayed again.
    const auto again = [&]() -> core::Result<void> {
        auto summary = machine::summarize(w.program->program, profiles.process);
        if (!summary) return std::unexpected(summary.error());
        w.program->summary = *summary;
        auto text =
            machine::write_program(w.program->program, profiles.machine, profiles.process, wo);
        if (!text) return std::unexpected(text.error());
        w.text = std::move(*text);
        return replay();
    };
    if (auto ok = replay(); !ok) return std::unexpected(ok.error());
    const double lift_margin = std::max(
        kLiftMarginMm, profiles.machine.nozzle ? profiles.machine.nozzle->clearance_mm : 0.0);
    const auto top_along = [&](const core::Vec3d& d) {
        return slice::extent_along(placed, slice::PlaneFrame::from_normal({0.0, 0.0, 0.0}, d))
                   .second +
               lift_margin;
    };
    for (int round = 0; round < kLiftRounds && travels_to_lift(*w.report); ++round) {
        const std::size_t lifted = machine::lift_travels(
            w.program->program, w.report->travel_fault_ends, kLeaveOutWithinMm, top_along);
        if (lifted == 0) break;
        w.lifted_travels += lifted;
        if (auto ok = again(); !ok) return std::unexpected(ok.error());
    }
    for (int round = 0; round < kLeaveOutRounds && beads_to_leave_out(*w.report); ++round) {
        const double cut = machine::leave_out_deposits(
            w.program->program, w.report->unsupported_tips, profiles.process, kLeaveOutWithinMm);
        if (!(cut > 0.0)) break;
        w.left_out_beads += w.report->unsupported.count;
        w.left_out_mm += cut;
        if (auto ok = again(); !ok) return std::unexpected(ok.error());
    }
    w.verify_s = seconds_since(t);
    w.kept = verifier_keeps(*w.report, so);
    return w.kept ? std::string()
                  : "the verifier refused its program " + verifier_counts(*w.report, true);
}

// Why beads miss part of a part, and what builds it: "features narrower than the 2.50 mm track
// get no material: a narrower track builds them, e.g. examples/profiles/fine_5axis_ac.toml".
std::string narrow_features_hint(double track_width_mm) {
    // The bundled fine-track profile (0.80 mm) is the hint while the track is wider.
    constexpr double kFineProfileTrackMm = 0.8;
    return fmt::format(
        "features narrower than the {:.2f} mm track get no material: {}", track_width_mm,
        track_width_mm > kFineProfileTrackMm + 1e-9
            ? "a narrower track builds them, e.g. examples/profiles/fine_5axis_ac.toml"
            : "a narrower track (process.track_width_mm) builds them; or is the part in other "
              "units (--units)?");
}

void print_verification(Printed& o, const std::optional<verify::Report>& report,
                        double track_width_mm) {
    if (!report) {
        o.print("verified        no (--no-verify)\n");
        return;
    }
    o.print(
        "verified        %zu collisions, %zu unsupported beads, %zu limit violations, %zu closer "
        "than the %.2f mm clearance (%zu poses, %.3f mm voxels)\n",
        report->collisions.count, report->unsupported.count, report->limit_violations.count,
        report->clearance.count, report->clearance_mm, report->poses_checked, report->voxel_mm);
    o.print("coverage        %.2f%% of the part, excess %.2f%%%s\n", 100.0 * report->coverage,
            100.0 * report->excess,
            report->model_open_columns > 0
                ? " (estimates: the mesh is not closed, the verifier cannot tell its inside)"
                : "");
    // "finished part   99.87% inside beads, smallest stock 0.61 mm" (scripts parse it): the
    // finished part, or without a near-net shape the part itself (decision 0026).
    o.print("finished part   %s%s\n", verify::finished_text(*report).c_str(),
            report->finished_judged() ? "" : " (estimates: the mesh is not closed)");
    if (report->below_plate.count > 0) {
        o.warn(
            "maxslice: warning: the head reaches up to %.1f mm below the plate's level "
            "in %zu blocks (first: program line %d); the profile models no substrate "
            "([machine.substrate], docs/profiles.md): check the plate, clamps and table "
            "by hand\n",
            report->below_plate_mm, report->below_plate.count, report->below_plate.first->line);
    }
    // A program that leaves the finished part under the figure is not written (JobOutcome);
    // one that holds it with the near-net shape's coverage low is, with a warning.
    if (report->coverage < verify::kMinCoverage && report->model_open_columns == 0 &&
        report->finished_given && !report->finished_low()) {
        o.warn(
            "maxslice: warning: the beads cover %.1f%% of the near-net shape's volume, and "
            "hold %.2f%% of the finished part (%s)\n",
            100.0 * report->coverage, 100.0 * report->finished_inside,
            narrow_features_hint(track_width_mm).c_str());
    }
    o.print("build time      %.1f min (deposit %.1f, idle %.1f, dwell %.1f; verifier)\n",
            report->build_time_s / 60.0, report->deposit_time_s / 60.0, report->idle_time_s / 60.0,
            report->dwell_time_s / 60.0);
}

// "on nothing      2 beads ... left out": the beads the verifier found resting on nothing
// and the job left out before the replay that passed (decision 0039).
void print_left_out(Printed& o, std::size_t beads, double mm, std::size_t lifted = 0) {
    if (lifted > 0) {
        o.print(
            "over the part   %zu travels the verifier found meeting the part or within the "
            "clearance taken over it; the program replayed again\n",
            lifted);
    }
    if (beads == 0) return;
    o.print(
        "on nothing      %zu beads the verifier found resting on nothing left out (%.1f mm of "
        "track); the program replayed again\n",
        beads, mm);
}

// The orientation policy of a program job: --orient, or the default (the given direction,
// others when it cannot be built, unless --direction was given).
std::optional<pipeline::OrientPolicy> orient_policy(const SliceOptions& so) {
    if (so.orient == "given") return pipeline::OrientPolicy::kGiven;
    if (so.orient == "auto") return pipeline::OrientPolicy::kAuto;
    if (!so.orient.empty()) return std::nullopt;
    return so.direction_given ? pipeline::OrientPolicy::kGiven : pipeline::OrientPolicy::kFallback;
}

// How the refusal of a base whose program misses the figures begins (decision 0031).
constexpr std::string_view kShortOfFigures = "its program with the ";
std::string short_of_figures(double track_width_mm, const std::string& goal,
                             const std::string& figures) {
    return fmt::format("{}{:.2f} mm track {} ({})", kShortOfFigures, track_width_mm, goal, figures);
}

// The part as given, whose program misses the figures, for the search of the other bases
// (decisions 0031 and 0047): why it falls short, and what a base that misses them too must
// beat to be kept instead: a shorter verified build time holding no less of the part.
struct ShortAsGiven {
    std::string why;            // empty: not a search for the figures
    double build_time_s = 0.0;  // 0: only a base that meets the figures is kept
    double held = 1.0;          // the finished part (else the part) inside beads, [0, 1]

    [[nodiscard]] bool beaten_by(double build_time_s_other, double held_other) const {
        return build_time_s_other < build_time_s && held_other >= held;
    }
};

// Says which base direction a job kept when it is not the part as given: a warning and a
// summary line when the given one could not be built, the summary line with --orient auto;
// and how to replay the program when the verifier needs more than the part and the profile
// (the direction, or the profile's finer process `finer` when it is not 0).
void print_orientation(Printed& o, const std::vector<pipeline::OrientTry>& tries, int chosen,
                       const std::string& program, const std::string& part, int finer = 0) {
    const pipeline::OrientTry* kept =
        tries.empty() ? nullptr : &tries[static_cast<std::size_t>(chosen)];
    // The program builds the part placed along this direction: the verifier must place the
    // model the same way (shortest round-trip digits: the same placement bit for bit).
    const auto replay = [&] {
        o.print("verify with     maxslice verify %s --model %s%s%s (and the same --profile)\n",
                program.c_str(), part.c_str(),
                kept != nullptr && kept->source != "as given"
                    ? fmt::format(" --direction {},{},{}", kept->direction.x, kept->direction.y,
                                  kept->direction.z)
                          .c_str()
                    : "",
                finer > 0 ? fmt::format(" --finer {}", finer).c_str() : "");
    };
    if (kept == nullptr || kept->source == "as given") {
        if (finer > 0) replay();
        return;
    }
    // Axis candidates are named by their direction ("-Z", "+Z (as given)"); flat faces are not.
    const core::Vec3d& d = kept->direction;
    const std::string where =
        kept->source.starts_with('+') || kept->source.starts_with('-')
            ? kept->source
            : fmt::format("({:.4f}, {:.4f}, {:.4f}), {}", d.x, d.y, d.z, kept->source);
    if (tries.front().source != "as given") {
        o.print("orientation     along %s (--orient auto)\n", where.c_str());
        replay();
        return;
    }
    // A base refused for missing the figures (decision 0031) builds, short of them.
    const std::string& refusal = tries.front().refusal;
    const std::string why =
        (refusal.starts_with(kShortOfFigures) ? "the part as given falls short: "
                                              : "the part as given cannot be built: ") +
        refusal;
    o.warn(
        "maxslice: warning: %s; it is built standing along %s instead (--orient given "
        "keeps the file's orientation)\n",
        why.c_str(), where.c_str());
    o.print("orientation     along %s (%s)\n", where.c_str(), why.c_str());
    replay();
}

// What a job came to with one process: the lines it prints, the program to write (rc ==
// kExitOk), the previews to write, and whether the track was what failed the part
// (decision 0019): no track fits where the part stands or anywhere, or the program misses
// the coverage target (97 %) or the excess bound (5 %), so that a finer process may do better.
// A program that holds less than 97 % of the finished part inside its beads is not written
// (decision 0026): the job is refused with that figure unless a finer process does better.
struct JobOutcome {
    int rc = kExitOk;
    Printed printed;
    std::string program;
    std::function<core::Result<void>()> files;  // previews and JSON, when asked for
    bool track_limited = false;
    /// What a track_limited program misses (the note of a job that falls back says it).
    std::string goal = "misses 97% coverage with under 5% excess";
    std::string figures;  // "90.77% coverage, 0.05% excess", or why nothing was written
    std::optional<core::Error> short_of_part;  // the kept program leaves the finished part short
    bool kept_as_given = false;  // the program builds the part as given (no other base taken)
    /// The verified program's build time and the share of the finished part (else of the part)
    /// inside its beads, [0, 1] (NaN: not verified).
    double build_time_s = std::numeric_limits<double>::quiet_NaN();
    double held = std::numeric_limits<double>::quiet_NaN();
    /// Bodies the plan left out (decision 0036), worded for a refusal short of the part; empty
    /// when there are none.
    std::string left_out;

    JobOutcome done(int code) {
        rc = code;
        if (rc == kExitOk && short_of_part) rc = printed.error(*short_of_part);
        // The refusal's own words, for the note of a job that falls back.
        if (figures.empty() && rc != kExitOk) figures = "refused: " + printed.refusal;
        return std::move(*this);
    }

    // A kept program's figures: whether it misses the target, by the verifier (a closed
    // model) or, without its report, by the share of the section area without a track; and
    // whether it may be written at all: under 97 % of the finished part (of the part without a
    // near-net shape) inside its beads, where the verifier can tell, or of an open finished
    // part's closed near-net shape covered, it may not.
    void note_figures(const std::optional<verify::Report>& report, double uncovered_mm2,
                      double area_mm2, double track_width_mm) {
        const double open = area_mm2 > 0.0 ? uncovered_mm2 / area_mm2 : 0.0;
        short_of_part.reset();
        if (report) {
            build_time_s = report->build_time_s;
            held = report->finished_given ? report->finished_inside : report->coverage;
            figures = fmt::format("{:.2f}% coverage, {:.2f}% excess", 100.0 * report->coverage,
                                  100.0 * report->excess);
            if (report->finished_given) {
                figures += fmt::format(", {:.2f}% of the finished part inside beads",
                                       100.0 * report->finished_inside);
            }
            if (report->finished_given && report->finished_judged()) {
                // A near-net shape is judged by the finished part it holds (decision 0030):
                // the holes and stock it fills need not all be beads, the finished part does.
                track_limited =
                    report->finished_inside < verify::kFinishedInsideTarget ||
                    (report->model_open_columns == 0 && report->excess >= verify::kMaxExcess);
                goal = fmt::format(
                    "holds under {:.1f}% of the finished part inside its beads or "
                    "{:.0f}% excess or more",
                    100.0 * verify::kFinishedInsideTarget, 100.0 * verify::kMaxExcess);
            } else {
                track_limited =
                    (report->model_open_columns == 0 && (report->coverage < verify::kMinCoverage ||
                                                         report->excess >= verify::kMaxExcess)) ||
                    report->finished_low();
            }
            // An open finished part's figure is an estimate (the verifier cannot tell its
            // inside): the closed near-net shape's coverage judges the program then, as
            // `maxslice verify` does.
            const bool estimated =
                report->finished_given && !report->finished_judged() && report->coverage_low();
            if (report->finished_low() || estimated) {
                const std::string held =
                    estimated ? fmt::format(
                                    "covers {:.2f}% of the near-net shape (the finished "
                                    "part is open: {:.2f}% of it inside the beads, an "
                                    "estimate)",
                                    100.0 * report->coverage, 100.0 * report->finished_inside)
                              : fmt::format(
                                    "holds {:.2f}% of the {} inside its beads (smallest "
                                    "stock {:.2f} mm)",
                                    100.0 * report->finished_inside,
                                    report->finished_given ? "finished part" : "part",
                                    report->smallest_stock_mm);
                short_of_part = core::Error{
                    core::ErrorCode::kInvalidInput,
                    fmt::format("the program {}, under the {:.0f}% a written program must ({}); "
                                "nothing written",
                                held, 100.0 * verify::kMinCoverage,
                                left_out.empty()
                                    ? narrow_features_hint(track_width_mm)
                                    : left_out + "; or " + narrow_features_hint(track_width_mm)),
                    "verifying the program"};
            }
        } else {
            figures = fmt::format("{:.1f}% of the section area without a track", 100.0 * open);
            track_limited = open > 0.05;
        }
    }
};

// The search's estimate of a program (decision 0015): its build time before it is written and
// verified. A program that deposits nothing (no track fits along that base) would be the
// shortest of all: it is a refused base (when every base is, the job names the cause).
pipeline::ProgramVerdict estimated(const machine::ProgramSummary& summary) {
    if (summary.laser_on_count == 0) return {"no track fits in any layer"};
    return {{}, summary.build_time_s};
}

// The program of the shortest estimate so far, kept for the check: the search checks that base
// first (decision 0015), so its tracks are not planned twice. Keyed by the plan or stack it was
// made from, which the search holds in place until it has chosen.
template <class Planned>
class EstimateCache {
public:
    // The estimate of `p`, made from `key` in `paths_s`; kept when the shortest so far.
    pipeline::ProgramVerdict offer(const void* key, Planned p, double paths_s) {
        pipeline::ProgramVerdict v = estimated(p.summary);
        if (v.refusal.empty() && (!program_ || v.build_time_s < seconds_)) {
            key_ = key;
            program_ = std::move(p);
            seconds_ = v.build_time_s;
            paths_s_ = paths_s;
        }
        return v;
    }
    // The program made from `key`, taken out, with its paths time; nullopt when not kept.
    std::optional<std::pair<Planned, double>> take(const void* key) {
        if (!program_ || key_ != key) return std::nullopt;
        std::pair<Planned, double> out{std::move(*program_), paths_s_};
        program_.reset();
        key_ = nullptr;
        return out;
    }

private:
    const void* key_ = nullptr;
    std::optional<Planned> program_;
    double seconds_ = 0.0;
    double paths_s_ = 0.0;
};

// What the orientation search is told of a program written and replayed: the verifier's
// refusal ("" kept), its build time, and whether the program misses the figures, which the
// search weighs (decision 0015); `probe` gets the figures.
template <class Planned>
pipeline::ProgramVerdict verdict_of(std::string refusal, const Written<Planned>& w,
                                    double track_width_mm, JobOutcome& probe) {
    bool short_of = false;
    if (refusal.empty() && w.report) {
        probe.note_figures(w.report, w.program->uncovered_mm2, w.program->region_area_mm2,
                           track_width_mm);
        short_of = probe.track_limited;
    }
    return {std::move(refusal),
            w.report ? w.report->build_time_s : std::numeric_limits<double>::quiet_NaN(), short_of};
}

// A table-tilt machine: plan the placed part (regions, tilts, splits), order its layers with
// the nozzle check, turn them into moves and make the 5-axis program. `finer`: which of the
// profile's finer processes `profiles` holds (0: the main one). `part` is what is deposited;
// `finished`, when that is a near-net shape, the finished part (file frame). `given_short`,
// when its `why` is not empty (the part as given falls short): the bases other than the given
// one are searched, and one whose program misses the figures is refused like one that cannot be
// built, unless it beats the part as given (decision 0047).
JobOutcome run_multiaxis_slice(const PartOptions& opt, const SliceOptions& so,
                               const mesh::TriangleMesh& part, const machine::Profiles& profiles,
                               pipeline::StageTimes& times, const core::Vec3d& given,
                               pipeline::OrientPolicy policy, int finer,
                               const mesh::TriangleMesh* finished,
                               const ShortAsGiven& given_short) {
    const bool for_goal = !given_short.why.empty();
    JobOutcome r;
    Printed& o = r.printed;
    const auto done = [&](int rc) { return r.done(rc); };
    // A refusal of this part: the error with its reason, and the job's exit code.
    const auto refuse = [&](std::string why) {
        return done(o.error({core::ErrorCode::kInvalidInput, std::move(why), opt.path}));
    };
    const auto progress = make_progress();
    const std::string name = std::filesystem::path(opt.path).filename().string();
    Written<pipeline::MultiAxisProgram> w;
    double checks_s = 0.0;  // all of them, out of the planning time
    // The build time of a plan's program before it is written and verified: the search takes
    // the base with the shortest verified build time (decision 0015).
    EstimateCache<pipeline::MultiAxisProgram> estimates;
    const auto estimate =
        [&](const core::Vec3d&, const mesh::TriangleMesh& placed,
            const pipeline::PlannedPart& planned) -> core::Result<pipeline::ProgramVerdict> {
        const auto start = std::chrono::steady_clock::now();
        auto p = pipeline::plan_multiaxis_program(planned.plan, *planned.order, placed, profiles,
                                                  name, progress.get());
        checks_s += seconds_since(start);
        if (!p) return std::unexpected(p.error());
        return estimates.offer(&planned, std::move(*p), seconds_since(start));
    };
    const auto check =
        [&](const core::Vec3d& direction, const mesh::TriangleMesh& placed,
            const pipeline::PlannedPart& planned) -> core::Result<pipeline::ProgramVerdict> {
        const auto start = std::chrono::steady_clock::now();
        w = {};
        if (auto kept = estimates.take(&planned)) {
            w.program = std::move(kept->first);
            w.paths_s = kept->second;
        } else {
            auto p = pipeline::plan_multiaxis_program(planned.plan, *planned.order, placed,
                                                      profiles, name, progress.get());
            if (!p) return std::unexpected(p.error());
            w.program = std::move(*p);
            w.paths_s = seconds_since(start);
        }
        machine::WriteOptions wo;
        wo.clear_z_mm = machine::clear_height_mm(profiles.machine, placed.vertices);
        auto refusal = write_and_verify(w, direction, placed, profiles, so, wo, finished, &part);
        checks_s += seconds_since(start);
        if (!refusal) return std::unexpected(refusal.error());
        JobOutcome probe;
        pipeline::ProgramVerdict verdict =
            verdict_of(std::move(*refusal), w, profiles.process.track_width_mm, probe);
        // Looking for a base whose program meets the figures: one that misses them is a
        // refused try like the others (decision 0031), unless it builds faster than the part as
        // given and holds no less of it (decision 0047).
        if (for_goal && verdict.short_of_figures &&
            (probe.short_of_part || !given_short.beaten_by(verdict.build_time_s, probe.held))) {
            return short_of_figures(profiles.process.track_width_mm, probe.goal, probe.figures);
        }
        return verdict;
    };
    auto t0 = std::chrono::steady_clock::now();
    // A near-net shape is stood on the flat faces of its finished part (decision 0025).
    const std::vector<pipeline::OrientCandidate> candidates =
        finished != nullptr ? pipeline::orientation_candidates(*finished)
                            : std::vector<pipeline::OrientCandidate>{};
    auto oriented =
        pipeline::orient_multiaxis(part, given, for_goal ? pipeline::OrientPolicy::kOthers : policy,
                                   profiles, progress.get(), check, candidates, estimate);
    if (!oriented) return done(o.error(oriented.error()));
    if (for_goal) {
        // No other base meets the figures: the caller keeps the part as given, and nothing of
        // this search is used (its last program need not be the plan it hands back).
        if (oriented->tries.empty() ||
            !oriented->tries[static_cast<std::size_t>(oriented->chosen)].refusal.empty()) {
            r.track_limited = true;
            return refuse(
                "no other base meets the figures with this track, nor builds faster holding as "
                "much of the part");
        }
        // The part as given, tried before, heads the tries.
        oriented->tries.insert(
            oriented->tries.begin(),
            pipeline::OrientTry{core::normalized(given), "as given", given_short.why});
        ++oriented->chosen;
    }
    const mesh::TriangleMesh placed = std::move(oriented->placed);
    const pipeline::PlannedPart& planned = oriented->planned;
    // The base kept, planned and ordered; the rest of the search is the other bases' (their
    // plans, orders and program checks: all checks but the kept program's own).
    // Added to those of the job's earlier attempts (a finer process, another base).
    const double kept_check_s = w.kept ? w.paths_s + w.write_s + w.verify_s : 0.0;
    times.search_s +=
        std::max(0.0, seconds_since(t0) - planned.seconds - planned.order_seconds - kept_check_s);
    times.plan_s += planned.seconds;
    times.order_s += planned.order_seconds;
    // A search for the figures heads its tries with the part as given, tried before it.
    times.bases += std::max<int>(1, static_cast<int>(oriented->tries.size()) - (for_goal ? 1 : 0));
    ++times.attempts;
    const std::string tried = pipeline::other_tries(oriented->tries, oriented->chosen);
    const plan::Plan& plan = planned.plan;
    if (!plan.unsupported_layers.empty()) {
        const plan::Layer& l = plan.layers[static_cast<std::size_t>(plan.unsupported_layers[0])];
        const core::Vec3d at = plan::centroid_of(l);
        const core::Vec3d d = plan.regions[static_cast<std::size_t>(l.region)].direction;
        // How far the split that made the region lies: a region's cell takes in all of the
        // part beyond its split plane, features far from the overhang it was made for too.
        std::string split;
        for (const plan::Decision& dec : plan.decisions) {
            if (dec.new_region == l.region && dec.region != l.region) {
                const core::Vec3d& q = dec.split_plane.point;
                split = fmt::format(
                    ", {:.1f} mm from the split at ({:.1f}, {:.1f}, {:.1f}) that "
                    "made that region",
                    core::norm(at - q), q.x, q.y, q.z);
            }
        }
        return refuse(fmt::format(
            "{} layers rest on nothing (the first: a {:.2f} mm2 section at ({:.1f}, {:.1f}, "
            "{:.1f}), layer {} of region {}, built along ({:.3f}, {:.3f}, {:.3f}){}: a body or "
            "branch that starts there with nothing under it that the plan reaches from the "
            "plate; {}): no program without support is possible; what may help: another base "
            "(the default search, or --direction){}",
            plan.unsupported_layers.size(), l.area_mm2, at.x, at.y, at.z, l.id, l.region, d.x, d.y,
            d.z, split, plan::describe_hanging(plan, l.id, "part"), tried));
    }
    if (!plan.free_bodies.empty()) {
        o.warn("maxslice: warning: %s\n", plan::describe_free_bodies(plan).c_str());
    }
    if (!plan.bare_unsupported_layers.empty()) {
        const plan::Layer& l =
            plan.layers[static_cast<std::size_t>(plan.bare_unsupported_layers.front())];
        o.warn(
            "maxslice: warning: %zu layers where no %.2f mm track fits rest on nothing "
            "(the first: layer %d in region %d, %.1f mm2): nothing is laid there, and "
            "what stands on them gets tracks only over beads\n",
            plan.bare_unsupported_layers.size(), profiles.process.track_width_mm, l.id, l.region,
            l.area_mm2);
    }
    if (!oriented->bare_plate_layers.empty()) {
        const plan::Layer& l =
            plan.layers[static_cast<std::size_t>(oriented->bare_plate_layers.front())];
        const core::Vec3d at = plan::centroid_of(l);
        r.track_limited = true;
        return refuse(fmt::format(
            "the part stands on {} piece(s) where no {:.2f} mm track fits (the first: {:.1f} mm2 "
            "near ({:.3f}, {:.3f}, {:.3f}), an edge or a tip): nothing can be laid there, and what "
            "stands on it would rest on nothing; stand the part on a face (--direction) or use a "
            "narrower track (process.track_width_mm){}",
            oriented->bare_plate_layers.size(), profiles.process.track_width_mm, l.area_mm2, at.x,
            at.y, at.z, tried));
    }
    if (!planned.order->complete()) {
        const plan::Conflict& c = planned.order->conflicts.front();
        return refuse(fmt::format(
            "no collision-free build order exists with this nozzle ({} conflicts), so no program "
            "is written: {}. {}. See the partial order: maxslice plan PART --profile FILE --plan "
            "plan.json{}",
            planned.order->conflicts.size(), c.reason,
            plan::describe_refusal(planned.plan, *planned.order, planned.nozzle), tried));
    }
    print_orientation(o, oriented->tries, oriented->chosen, so.output, opt.path, finer);
    r.kept_as_given =
        oriented->tries.empty() ||
        oriented->tries[static_cast<std::size_t>(oriented->chosen)].source == "as given";
    // The search's last check is of the plan it keeps, so `w` is that plan's program;
    // otherwise (nothing kept: the given plan comes back with its refusal) it is made again here.
    if (!w.kept) {
        auto again = check(oriented->tries[static_cast<std::size_t>(oriented->chosen)].direction,
                           placed, planned);
        if (!again) return done(o.error(again.error()));
    }
    times.paths_s += w.paths_s;
    times.write_s += w.write_s;
    times.verify_s += w.verify_s;
    const pipeline::MultiAxisProgram* p = &*w.program;
    if (const int rc = check_tracks(o, p->summary, p->uncovered_mm2, p->region_area_mm2,
                                    p->layers_with_uncovered, profiles.process, opt.path);
        rc != kExitOk) {
        r.track_limited = p->summary.laser_on_count == 0;
        return done(rc);
    }
    if (!w.kept) return done(refuse_unverified(o, *w.report, so));
    const std::optional<verify::Report>& report = w.report;
    r.program = std::move(w.text);
    if (!plan.free_bodies.empty()) {
        double v = 0.0;
        for (const plan::FreeBody& b : plan.free_bodies) v += b.volume_mm3;
        r.left_out = fmt::format(
            "{} {} floating free of the rest, {:.0f} mm3, {} left out: nothing can be "
            "deposited under them (move or join them to the part)",
            plan.free_bodies.size(), plan.free_bodies.size() == 1 ? "body" : "bodies", v,
            plan.free_bodies.size() == 1 ? "is" : "are");
    }
    r.note_figures(report, p->uncovered_mm2, p->region_area_mm2, profiles.process.track_width_mm);

    const auto& sum = p->summary;
    o.print("regions         %zu (%d splits), %zu layers (%d tilted)\n", plan.regions.size(),
            plan.split_count(), plan.layers.size(), plan.tilted_layer_count());
    o.out += pipeline::footing_line(plan.footing);
    o.print("build order     %d jumps (fewest %d), %zu sections, %d section travels\n",
            planned.order->jumps, planned.order->min_jumps, planned.order->sections.size(),
            p->section_changes);
    o.print("program         %s (%s, %s, %zu moves)\n", so.output.c_str(),
            std::string(machine::dialect_name(profiles.machine.dialect)).c_str(),
            std::string(machine::kinematics_name(profiles.machine.kinematics)).c_str(),
            sum.move_count);
    o.print("deposition      %.1f mm in %d wires\n", sum.deposit_length_mm, sum.laser_on_count);
    o.print("idle travel     %.1f mm (before re-orientation moves)\n", sum.travel_length_mm);
    const pipeline::ThicknessReport& th = p->thickness;
    o.print("local thickness %.3f - %.3f mm; %zu of %zu segments off the speed window",
            th.thickness_min_mm, th.thickness_max_mm, th.clamped, th.segments);
    if (th.clamped > 0) {
        o.print(" (worst %.3f mm, layer %d at %.2f, %.2f, %.2f)", th.worst_error_mm, th.worst_layer,
                th.worst_at.x, th.worst_at.y, th.worst_at.z);
    }
    o.print("\n");
    o.print("uncovered       %.2f mm2 of %.1f mm2 (%d layers over 1%%)\n", p->uncovered_mm2,
            p->region_area_mm2, p->layers_with_uncovered);
    o.print("left out        %.1f mm of track in %d layers (no bead below it)\n", p->trimmed_mm,
            p->layers_trimmed);
    print_verification(o, report, profiles.process.track_width_mm);
    print_left_out(o, w.left_out_beads, w.left_out_mm, w.lifted_travels);
    return done(kExitOk);
}

// The layers of a program's process: its layer height, its h_min / h_max for adaptive layers
// (unless --min-layer / --max-layer).
void layers_of_process(pipeline::SliceSettings& ss, const machine::ProcessProfile& process,
                       const SliceOptions& so) {
    ss.layers.layer_mm = process.layer_height_mm;
    ss.layers.min_layer_mm = so.min_layer.value_or(process.h_min_mm);
    ss.layers.max_layer_mm =
        so.max_layer.value_or(so.adaptive ? process.h_max_mm : process.layer_height_mm);
}

// A program job with the profile's main process and, when its track is what fails the part,
// with its finer processes in turn (decision 0019): the first whose program meets the
// figures is kept, else the main process's job stands, with a note of what the finer ones
// gave. --finer off keeps the main process, --finer N takes finer process N at once.
// `other_bases` (the default orientation search): when the part as given misses the figures
// with the main process, the bases of the search are tried with it first, and the first whose
// program meets them is kept (decision 0031). attempt(profiles, finer, for_goal): for_goal
// (non-empty: why the part as given falls short) makes a program that misses the figures a
// refused base, and the part as given is not tried again.
core::Result<JobOutcome> with_finer_processes(
    const machine::Profiles& profiles, const SliceOptions& so,
    const std::function<JobOutcome(const machine::Profiles&, int, const ShortAsGiven&)>& attempt,
    bool other_bases) {
    const auto& finer = profiles.process.finer;
    const auto track = [](const machine::Profiles& p) { return p.process.track_width_mm; };
    if (so.finer != "auto" && so.finer != "off") {
        int n = 0;
        const auto [end, ec] =
            std::from_chars(so.finer.data(), so.finer.data() + so.finer.size(), n);
        if (ec != std::errc{} || end != so.finer.data() + so.finer.size() || n < 1) {
            return core::fail(
                core::ErrorCode::kInvalidInput,
                "unknown value '" + so.finer + "' (use auto, off or a number 1, 2, ...)",
                "--finer");
        }
        if (so.layer_given) {
            return core::fail(core::ErrorCode::kInvalidInput,
                              "--layer sets the main process's layer height; a finer process has "
                              "its own ([[process.finer]] layer_height_mm)",
                              "--finer " + so.finer);
        }
        auto p = machine::with_finer_process(profiles, n);
        if (!p) return std::unexpected(core::with_context(p.error(), "--finer"));
        return attempt(*p, n, {});
    }
    JobOutcome main = attempt(profiles, 0, {});
    // --layer is a choice of the main process's layers: the finer ones have their own.
    if (!main.track_limited || so.finer == "off" || so.layer_given) return main;
    const bool search_bases = other_bases && main.kept_as_given;
    if (finer.empty() && !search_bases) return main;
    // The part as given misses the figures with the main track: another base that meets them
    // with it builds in a fraction of the finer track's time (decision 0031).
    std::string bases;
    // Another base that misses the figures too, but builds faster and holds no less of the
    // part than the part as given (decision 0047): kept unless a finer process meets them.
    std::optional<JobOutcome> faster;
    if (search_bases) {
        JobOutcome moved = attempt(profiles, 0,
                                   {short_of_figures(track(profiles), main.goal, main.figures),
                                    main.build_time_s, main.held});
        if (moved.rc == kExitOk && !moved.kept_as_given) {
            if (!moved.track_limited) return moved;
            faster = std::move(moved);
        }
        bases = " as given, and no other base meets them with it";
    }
    std::string tried;
    for (int n = 1; n <= static_cast<int>(finer.size()); ++n) {
        auto p = machine::with_finer_process(profiles, n);
        if (!p) return std::unexpected(p.error());
        // The finer process's program kept: the note and the summary line say why.
        const auto noted = [&](JobOutcome f) {
            f.printed.err = fmt::format(
                "maxslice: note: the {:.2f} mm track {} ({}){}; the program uses the "
                "profile's finer process {} ({:.2f} mm track, {:.2f} mm layers; --finer off "
                "keeps the {:.2f} mm track)\n{}",
                track(profiles), main.goal, main.figures, bases, n, track(*p),
                p->process.layer_height_mm, track(profiles), f.printed.err);
            f.printed.out = fmt::format(
                "process         finer {}: {:.2f} mm track, {:.2f} mm layers (the {:.2f} mm "
                "track: {})\n{}",
                n, track(*p), p->process.layer_height_mm, track(profiles), main.figures,
                f.printed.out);
            return f;
        };
        JobOutcome f = attempt(*p, n, {});
        if (f.rc == kExitOk && !f.track_limited) return noted(std::move(f));
        // Short with this track as given too: another base may meet the figures with it.
        if (other_bases && f.rc == kExitOk && f.kept_as_given) {
            JobOutcome moved = attempt(*p, n, {short_of_figures(track(*p), f.goal, f.figures)});
            if (moved.rc == kExitOk && !moved.track_limited && !moved.kept_as_given) {
                return noted(std::move(moved));
            }
        }
        tried += fmt::format("{}the {:.2f} mm track (finer process {}): {}",
                             tried.empty() ? "" : "; ", track(*p), n, f.figures);
    }
    JobOutcome& kept = faster ? *faster : main;
    if (faster) {
        kept.printed.err += fmt::format(
            "maxslice: note: no base meets the figures with the {:.2f} mm track; the base kept "
            "builds in {:.1f} min and holds {:.2f}% of the part inside its beads, the part as "
            "given {:.1f} min and {:.2f}% (--orient given keeps it)\n",
            track(profiles), kept.build_time_s / 60.0, 100.0 * kept.held, main.build_time_s / 60.0,
            100.0 * main.held);
    }
    if (!finer.empty()) {
        kept.printed.err += fmt::format(
            "maxslice: note: the profile's finer processes do no better: {} (--finer N makes "
            "the program with finer process N)\n",
            tried);
    }
    return std::move(kept);
}

// Prints a job's lines and writes what it made: the program (-o) and the previews.
int finish_job(JobOutcome job, const SliceOptions& so) {
    std::fputs(job.printed.err.c_str(), stderr);
    if (job.rc != kExitOk) return job.rc;
    if (!so.output.empty()) {
        if (const int rc = write_text_file(so.output, job.program); rc != kExitOk) return rc;
    }
    if (job.files) {
        if (auto ok = job.files(); !ok) return report_error(ok.error());
    }
    return print_out(job.printed.out);
}

// Slices the part along one direction: the slices' previews and summary, and with a 3-axis
// profile and -o the planar program (the part standing on the plate). `finer` and `finished`
// as for run_multiaxis_slice.
JobOutcome run_planar_slice(const PartOptions& opt, const SliceOptions& so,
                            pipeline::PreparedPart part, const pipeline::SliceSettings& ss,
                            const std::optional<machine::Profiles>& profiles,
                            pipeline::StageTimes& times, const core::Vec3d& given,
                            pipeline::OrientPolicy policy, int finer,
                            const mesh::TriangleMesh* finished) {
    JobOutcome r;
    Printed& o = r.printed;
    const auto done = [&](int rc) { return r.done(rc); };
    const bool program_mode = !so.output.empty();
    const auto progress = make_progress();
    std::optional<pipeline::SliceStack> stack;
    std::optional<plan::PlanarCheck> check;
    std::vector<pipeline::OrientTry> tries;
    int chosen = 0;
    const plan::PlanSettings ps =
        profiles ? pipeline::plan_settings(*profiles) : plan::PlanSettings{};
    const std::string name = std::filesystem::path(opt.path).filename().string();
    Written<pipeline::PlannedProgram> w;
    core::Vec3d built_along = ss.direction;  // the file's direction the program builds upwards
    // The deposited part in the file frame, for placing the finished part alike (the job's
    // own copy is replaced by the placed one).
    const std::optional<mesh::TriangleMesh> built =
        finished != nullptr ? std::optional(part.imported.mesh) : std::nullopt;
    EstimateCache<pipeline::PlannedProgram> estimates;
    const auto write_stack =
        [&](const core::Vec3d& direction, const mesh::TriangleMesh& placed,
            const pipeline::SliceStack& s) -> core::Result<pipeline::ProgramVerdict> {
        w = {};
        const auto start = std::chrono::steady_clock::now();
        if (auto kept = estimates.take(&s)) {
            w.program = std::move(kept->first);
            w.paths_s = kept->second;
        } else {
            auto p = pipeline::plan_program(s, *profiles, name, progress.get());
            if (!p) return std::unexpected(p.error());
            w.program = std::move(*p);
            w.paths_s = seconds_since(start);
        }
        auto refusal =
            write_and_verify(w, direction, placed, *profiles, so, machine::WriteOptions{}, finished,
                             built ? &*built : nullptr);
        if (!refusal) return std::unexpected(refusal.error());
        JobOutcome probe;
        return verdict_of(std::move(*refusal), w, profiles->process.track_width_mm, probe);
    };
    // The build time of a stack's program before it is written and verified.
    const auto stack_time =
        [&](const core::Vec3d&, const mesh::TriangleMesh&,
            const pipeline::SliceStack& s) -> core::Result<pipeline::ProgramVerdict> {
        const auto start = std::chrono::steady_clock::now();
        auto p = pipeline::plan_program(s, *profiles, name, progress.get());
        if (!p) return std::unexpected(p.error());
        return estimates.offer(&s, std::move(*p), seconds_since(start));
    };
    if (program_mode) {
        // A 3-axis machine builds every layer along one direction: the part stands on the
        // plate along the given direction (or, when that has overhangs a planar build cannot
        // hold, or a program the verifier refuses, and --orient allows it, along another),
        // checked with the planner's analysis.
        // A near-net shape is stood on the flat faces of its finished part (decision 0025).
        const std::vector<pipeline::OrientCandidate> candidates =
            finished != nullptr ? pipeline::orientation_candidates(*finished)
                                : std::vector<pipeline::OrientCandidate>{};
        auto oriented = pipeline::orient_planar(
            part.imported.mesh, given, so.allow_overhangs ? pipeline::OrientPolicy::kGiven : policy,
            ss, *profiles, progress.get(), &times, write_stack, candidates, stack_time);
        if (!oriented) return done(o.error(oriented.error()));
        built_along = oriented->direction;
        part.imported.mesh = std::move(oriented->placed);
        stack = std::move(oriented->stack);
        check = std::move(oriented->check);
        tries = std::move(oriented->tries);
        chosen = oriented->chosen;
    } else {
        auto sliced = pipeline::slice_part(part.imported.mesh, ss, progress.get(), &times,
                                           slice::VertexUse::kAllUsed);  // read_part's mesh
        if (!sliced) return done(o.error(sliced.error()));
        stack = std::move(*sliced);
    }

    std::optional<pipeline::PlannedProgram> planned;
    std::pair<std::size_t, double> left_out{0, 0.0};  // beads on nothing left out, mm
    std::size_t lifted = 0;                           // travels taken over the part
    std::optional<verify::Report> report;
    if (program_mode) {
        // Refuse a part whose overhangs need a split, never deposit on air.
        if (check->overhangs > 0 && so.allow_overhangs) {
            o.warn(
                "maxslice: warning: --allow-overhangs: overhangs a planar build cannot "
                "hold from %.3f mm up are deposited on nothing\n",
                check->heights_mm.front());
        } else if (check->overhangs > 0) {
            const plan::OverhangPiece& p = check->examples.front();
            return done(o.error(
                {core::ErrorCode::kInvalidInput,
                 fmt::format("the part needs a multi-axis build: overhangs a planar build cannot "
                             "hold from {:.3f} mm up ({} of the first {} layers; first: a piece of "
                             "{:.1f} mm2 at "
                             "({:.3f}, {:.3f}, {:.3f}) with Ang = {:.1f} deg > beta {:.0f}{}); the "
                             "machine profile is 3-axis (kinematics xyz), so no program is "
                             "written. See where it splits: maxslice plan PART --orient auto{}",
                             check->heights_mm.front(), check->overhangs, check->checked_up_to,
                             p.area_mm2, p.C.x, p.C.y, p.C.z, p.ang_deg, ps.beta_deg,
                             p.touches_lower ? "" : ", floating",
                             pipeline::other_tries(tries, chosen)),
                 opt.path}));
        }
        print_orientation(o, tries, chosen, so.output, opt.path, finer);
        if (check->tilts_wanted > 0) {
            o.warn(
                "maxslice: warning: %d layers overhang by an angle between alpha (%.0f) and "
                "beta (%.0f) deg: a multi-axis build would tilt them\n",
                check->tilts_wanted, ps.alpha_deg, ps.beta_deg);
        }
    }
    if (program_mode) {
        // The search's last check is of the stack it keeps, so `w` is that stack's program;
        // otherwise (nothing kept) it is made again here.
        if (!w.kept) {
            auto again = write_stack(built_along, part.imported.mesh, *stack);
            if (!again) return done(o.error(again.error()));
        }
        times.paths_s = w.paths_s;
        times.write_s = w.write_s;
        times.verify_s = w.verify_s;
        const pipeline::PlannedProgram& p = *w.program;
        if (const int rc = check_tracks(o, p.summary, p.uncovered_mm2, p.region_area_mm2,
                                        p.layers_with_uncovered, profiles->process, opt.path);
            rc != kExitOk) {
            r.track_limited = p.summary.laser_on_count == 0;
            return done(rc);
        }
        if (!w.kept) return done(refuse_unverified(o, *w.report, so));
        r.program = std::move(w.text);
        r.note_figures(w.report, p.uncovered_mm2, p.region_area_mm2,
                       profiles->process.track_width_mm);
        report = std::move(w.report);
        planned = std::move(*w.program);
        left_out = {w.left_out_beads, w.left_out_mm};
        lifted = w.lifted_travels;
    }

    double volume = 0.0, hmin = 1e300, hmax = 0.0;
    std::size_t outers = 0, holes = 0;
    int gaps = 0;
    for (const auto& s : stack->slices) {
        volume += s.area_mm2() * s.thickness();
        hmin = std::min(hmin, s.thickness());
        hmax = std::max(hmax, s.thickness());
        outers = std::max(outers, s.wires.outer_count());
        holes = std::max(holes, s.wires.hole_count());
        gaps += s.gaps_closed;
    }
    const auto& n = stack->base.normal;
    o.print("layers          %zu along (%.4f, %.4f, %.4f)\n", stack->slices.size(), n.x, n.y, n.z);
    o.print("thickness       %.4f - %.4f mm\n", hmin, hmax);
    o.print("most wires      %zu outer, %zu holes in one layer\n", outers, holes);
    o.print("sliced volume   %.6g mm3 %s\n", volume,
            pipeline::volume_against_mesh(volume, part.final_report()).c_str());
    if (check) o.out += pipeline::footing_line(check->footing);
    if (gaps > 0) o.print("gaps closed     %d (open mesh)\n", gaps);
    if (planned) {
        const auto& sum = planned->summary;
        o.print("program         %s (%s, %zu moves)\n", so.output.c_str(),
                std::string(machine::dialect_name(profiles->machine.dialect)).c_str(),
                sum.move_count);
        o.print("deposition      %.1f mm in %d wires\n", sum.deposit_length_mm, sum.laser_on_count);
        o.print("idle travel     %.1f mm\n", sum.travel_length_mm);
        o.print("build time      %.1f min (deposit %.1f, travel %.1f, dwell %.1f)\n",
                sum.build_time_s / 60.0, sum.deposit_time_s / 60.0, sum.travel_time_s / 60.0,
                sum.dwell_time_s / 60.0);
        o.print("powder          %.1f g delivered while depositing%s\n", sum.powder_delivered_g,
                sum.deposited_mass_g
                    ? fmt::format(", {:.1f} g deposited", *sum.deposited_mass_g).c_str()
                    : "");
        o.print("uncovered       %.2f mm2 of %.1f mm2 (%d layers over 1%%)\n",
                planned->uncovered_mm2, planned->region_area_mm2, planned->layers_with_uncovered);
        print_verification(o, report, profiles->process.track_width_mm);
        print_left_out(o, left_out.first, left_out.second, lifted);
    }
    // The previews and the JSON are written when this job is the one kept.
    if (!so.json_file.empty() || !so.svg_dir.empty() || !so.contact_sheet.empty()) {
        struct Files {
            pipeline::SliceStack stack;
            std::optional<pipeline::PlannedProgram> planned;
            pipeline::PreparedPart part;
            double track_mm;
        };
        auto kept =
            std::make_shared<Files>(Files{std::move(*stack), std::move(planned), std::move(part),
                                          profiles ? profiles->process.track_width_mm : 0.0});
        r.files = [kept, &so]() -> core::Result<void> {
            if (!so.json_file.empty()) {
                auto ok = pipeline::write_slices_json(so.json_file, kept->stack, kept->part);
                if (!ok) return ok;
            }
            if (!so.svg_dir.empty()) {
                auto ok = pipeline::write_layer_svgs(
                    so.svg_dir, kept->stack, kept->planned ? &kept->planned->toolpaths : nullptr,
                    kept->track_mm);
                if (!ok) return ok;
            }
            if (!so.contact_sheet.empty()) {
                return pipeline::write_contact_sheet(so.contact_sheet, kept->stack);
            }
            return {};
        };
    }
    return done(kExitOk);
}

int run_slice(const PartOptions& opt, const SliceOptions& so) {
    auto settings = opt.settings();
    if (!settings) return report_error(settings.error());
    const auto policy = orient_policy(so);
    if (!policy) {
        return report_error({core::ErrorCode::kInvalidInput,
                             "unknown orientation '" + so.orient + "' (use given or auto)",
                             "--orient"});
    }
    pipeline::SliceSettings ss;
    ss.direction = {so.direction[0], so.direction[1], so.direction[2]};
    ss.layers.layer_mm = so.layer;
    ss.layers.adaptive = so.adaptive;
    ss.layers.cusp_mm = so.cusp;
    ss.layers.min_layer_mm = so.min_layer.value_or(so.layer * 0.4);
    ss.layers.max_layer_mm = so.max_layer.value_or(so.layer);
    if (opt.repair) ss.max_gap_mm = std::numeric_limits<double>::infinity();
    if (auto ok = pipeline::validate(ss); !ok) return report_error(ok.error());

    // A program is written for the profile's process: its layer height (unless --layer),
    // its h_min / h_max for adaptive layers, with the part standing on the plate.
    const bool program_mode = !so.output.empty();
    std::optional<machine::Profiles> profiles;
    if (program_mode || !so.profiles.empty()) {
        auto loaded = load_profiles(so);
        if (!loaded) return report_error(loaded.error());
        profiles = *loaded;
        layers_of_process(ss, profiles->process, so);
        if (auto ok = pipeline::validate(ss); !ok) return report_error(ok.error());
    }

    pipeline::StageTimes times;
    auto part = pipeline::prepare_part(opt.path, *settings, &times);
    if (!part) return report_error(part.error());
    print_warnings(*part);
    // The part read is the finished part; with the process's machining stock or fill the job
    // deposits its near-net shape and keeps the finished part for the verifier (decision 0025).
    std::optional<mesh::TriangleMesh> finished;
    std::string near_net_line;
    if (profiles) {
        // A part the table cannot bring under the nozzle as deposited (grown by the stock) in
        // any orientation the job may try is refused at once: the near-net shape of a part
        // that large takes the most time, or is itself refused for its size. The shape made,
        // each orientation checks it again before it is planned.
        if (program_mode && !pipeline::near_net_settings(profiles->process).off()) {
            if (auto ok =
                    pipeline::check_fits_machine(part->imported.mesh, ss.direction, *policy,
                                                 *profiles, profiles->process.machining_stock_mm);
                !ok) {
                return report_error(ok.error());
            }
        }
        const auto progress = make_progress();
        auto near = pipeline::near_net_part(*part, profiles->process, progress.get(), &times);
        if (!near) return report_error(core::with_context(near.error(), opt.path));
        if (*near) {
            near_net_line = pipeline::near_net_line(**near);
            finished = std::move((*near)->finished);
            *part = std::move((*near)->built);
        }
    }
    const mesh::TriangleMesh* finished_part = finished ? &*finished : nullptr;
    const core::Vec3d given = ss.direction;
    if (!program_mode) {
        JobOutcome job = run_planar_slice(opt, so, std::move(*part), ss, profiles, times, given,
                                          *policy, 0, finished_part);
        job.printed.out = near_net_line + job.printed.out;
        if (opt.timings) job.printed.err += timings_text(times, false);
        return finish_job(std::move(job), so);
    }
    const bool table_tilt = machine::is_table_tilt(profiles->machine.kinematics);
    if (table_tilt && so.adaptive) {
        std::fprintf(stderr,
                     "maxslice: warning: --adaptive is not used on a table-tilt machine: its "
                     "layers are the planner's (process.layer_height_mm, tilted where the "
                     "part leans, METHOD.md section 4)\n");
    }
    // One job with the main process or one of the finer ones (decision 0019).
    // The planar job takes the part; it gets a copy only when a finer run may follow.
    const bool may_retry =
        !profiles->process.finer.empty() && so.finer == "auto" && !so.layer_given;
    const auto attempt = [&](const machine::Profiles& p, int finer,
                             const ShortAsGiven& given_short) {
        if (table_tilt) {
            return run_multiaxis_slice(opt, so, part->imported.mesh, p, times, given, *policy,
                                       finer, finished_part, given_short);
        }
        pipeline::SliceSettings pss = ss;
        layers_of_process(pss, p.process, so);
        return run_planar_slice(opt, so, may_retry ? *part : std::move(*part), pss, p, times, given,
                                *policy, finer, finished_part);
    };
    auto job = with_finer_processes(*profiles, so, attempt,
                                    table_tilt && *policy == pipeline::OrientPolicy::kFallback);
    if (!job) return report_error(job.error());
    job->printed.out = near_net_line + job->printed.out;
    // Every stage's time, also of a job refused (what took the time is then the question).
    if (opt.timings) job->printed.err += timings_text(times, true);
    return finish_job(std::move(*job), so);
}

struct PlanOptions {
    double layer = 0.5;
    std::vector<std::string> profiles;
    std::optional<double> alpha, beta;
    std::string orient = "given";
    std::vector<double> direction{0.0, 0.0, 1.0};
    std::string plan_file, dot_file, svg_dir, mesh_out, order_out, sections_out;
    int max_regions = 64;
};

int run_plan(const PartOptions& opt, const PlanOptions& po, bool layer_given) {
    auto settings = opt.settings();
    if (!settings) return report_error(settings.error());
    SliceOptions so;
    so.profiles = po.profiles;
    so.layer = po.layer;
    so.layer_given = layer_given;
    auto profiles = load_profiles(so);
    if (!profiles) return report_error(profiles.error());
    pipeline::PlanJobSettings ps;
    ps.plan = pipeline::plan_settings(*profiles);
    if (po.alpha) ps.plan.alpha_deg = *po.alpha;
    if (po.beta) ps.plan.beta_deg = *po.beta;
    ps.plan.max_regions = po.max_regions;
    if (auto ok = plan::validate(ps.plan); !ok) {
        return report_error(
            core::with_context(ok.error(), "plan settings (profile, --alpha, --beta)"));
    }
    if (po.orient == "auto") {
        ps.orient = pipeline::Orient::kAuto;
    } else if (po.orient != "given") {
        return report_error({core::ErrorCode::kInvalidInput,
                             "unknown orientation '" + po.orient + "' (use given or auto)",
                             "--orient"});
    }
    ps.direction = {po.direction[0], po.direction[1], po.direction[2]};
    ps.tracks = pipeline::path_settings(profiles->process);
    // A table machine's plan is the program job's: the part placed on the plate along each
    // direction, in the table's part frame.
    std::string placed_line;
    if (machine::is_table_tilt(profiles->machine.kinematics)) {
        ps.plate_center = machine::plate_center(profiles->machine);
        placed_line =
            "frame           the table's part frame (the part placed on the plate along its base "
            "direction, which is +Z there, as a program job places it)\n";
    }

    pipeline::StageTimes times;
    auto part = pipeline::prepare_part(opt.path, *settings, &times);
    if (!part) return report_error(part.error());
    print_warnings(*part);
    const auto progress = make_progress();
    // The plan of what a program job deposits: the near-net shape when the process asks for it.
    std::string near_net_line;
    auto near = pipeline::near_net_part(*part, profiles->process, progress.get(), &times);
    if (!near) return report_error(core::with_context(near.error(), opt.path));
    if (*near) {
        near_net_line = pipeline::near_net_line(**near);
        // Stood on the flat faces of the finished part: the near-net shape's are meshed from
        // voxels and none is exactly flat where the part lies across the grid.
        if (ps.orient == pipeline::Orient::kAuto) {
            ps.candidates = pipeline::orientation_candidates((*near)->finished);
        }
        *part = std::move((*near)->built);
    }
    auto planned = pipeline::plan_mesh(part->imported.mesh, ps, progress.get());
    if (!planned) return report_error(planned.error());
    std::string nozzle_source;
    const plan::Nozzle nozzle = pipeline::nozzle_of(profiles->machine, &nozzle_source);
    if (auto ok = pipeline::order_plan(*planned, nozzle, nozzle_source, progress.get()); !ok) {
        return report_error(ok.error());
    }

    if (!po.plan_file.empty()) {
        if (const int rc = write_text_file(po.plan_file, pipeline::plan_json(*planned, *part));
            rc != kExitOk) {
            return rc;
        }
    }
    if (!po.dot_file.empty()) {
        if (const int rc = write_text_file(po.dot_file, pipeline::plan_dot(planned->plan));
            rc != kExitOk) {
            return rc;
        }
    }
    if (!po.mesh_out.empty()) {
        if (const int rc = write_text_file(po.mesh_out, pipeline::plan_ply(planned->plan));
            rc != kExitOk) {
            return rc;
        }
    }
    const std::pair<const std::string*, pipeline::PlanColour> previews[] = {
        {&po.order_out, pipeline::PlanColour::kOrder},
        {&po.sections_out, pipeline::PlanColour::kSection}};
    for (const auto& [file, colour] : previews) {
        if (file->empty()) continue;
        if (const int rc =
                write_text_file(*file, pipeline::plan_ply(planned->plan, colour, &*planned->order));
            rc != kExitOk) {
            return rc;
        }
    }
    if (!po.svg_dir.empty()) {
        if (auto ok = pipeline::write_plan_svgs(po.svg_dir, planned->plan); !ok) {
            return report_error(ok.error());
        }
        if (auto ok = pipeline::write_order_svgs(po.svg_dir, planned->plan, *planned->order); !ok) {
            return report_error(ok.error());
        }
    }
    if (const int rc = print_out(near_net_line + placed_line +
                                 pipeline::plan_summary(*planned, part->final_report()));
        rc != kExitOk) {
        return rc;
    }
    if (opt.timings) {
        times.plan_s = planned->seconds;  // with --orient auto, every candidate's
        times.order_s = planned->order_seconds;
        times.bases = 1;
        times.attempts = 1;
        print_timings(times);
    }
    if (!planned->order->complete()) {
        const plan::Conflict& c = planned->order->conflicts.front();
        return report_error(
            {core::ErrorCode::kInvalidInput,
             fmt::format("no collision-free build order exists with this nozzle "
                         "({} conflicts; the plan file holds the partial order): {}. {}",
                         planned->order->conflicts.size(), c.reason,
                         plan::describe_refusal(planned->plan, *planned->order, planned->nozzle)),
             "build order"});
    }
    return kExitOk;
}

int run(int argc, char** argv) {
    CLI::App app{"maxslice: multi-axis slicer for directed energy deposition"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "maxslice 0.1.0");

    PartOptions info_opt;
    bool info_json = false;
    CLI::App* info = app.add_subcommand("info", "Print a part's size, volume and mesh defects");
    info_opt.add_to(*info);
    info->add_flag("--json", info_json, "Print JSON instead of text");

    PartOptions slice_opt;
    SliceOptions so;
    CLI::App* slice = app.add_subcommand("slice", "Slice a part into layers along a direction");
    slice_opt.add_to(*slice);
    CLI::Option* layer_opt =
        slice->add_option("--layer", so.layer, "Layer thickness in mm (default: the profile's)")
            ->check(CLI::PositiveNumber);
    slice->add_option("-o,--output", so.output,
                      "Write the deposition program to this file (part placed on the plate)");
    slice->add_option("--profile", so.profiles,
                      "Machine/process profile TOML file(s) (default: the built-in reference "
                      "LMD cell, examples/profiles/reference_lmd.toml)");
    slice->add_option("--dialect", so.dialect,
                      "Program dialect: gm, linuxcnc, fanuc or siemens (default: the "
                      "machine profile's)");
    CLI::Option* direction_opt =
        slice->add_option("--direction", so.direction, "Slicing (build) direction X,Y,Z")
            ->delimiter(',')
            ->expected(3);
    slice->add_option("--orient", so.orient,
                      "Program jobs: given (stand the part along --direction, default +Z, and "
                      "nothing else) or auto (the candidates of maxslice plan --orient auto); "
                      "default: as given, and when that cannot be built the other candidates");
    slice->add_flag("--adaptive", so.adaptive, "Vary the thickness to bound the cusp height");
    slice->add_option("--cusp", so.cusp, "Largest cusp height in mm (with --adaptive)")
        ->check(CLI::PositiveNumber);
    slice->add_option("--min-layer", so.min_layer, "h_min in mm (default 0.4 x --layer)")
        ->check(CLI::PositiveNumber);
    slice->add_option("--max-layer", so.max_layer, "h_max in mm (default --layer)")
        ->check(CLI::PositiveNumber);
    slice->add_option("--svg", so.svg_dir, "Write one SVG per layer into this folder");
    slice->add_option("--contact-sheet", so.contact_sheet, "Write all layers into one SVG");
    slice->add_option("--json", so.json_file, "Write the slices' summary as JSON");
    slice->add_flag("--allow-overhangs", so.allow_overhangs,
                    "Write a 3-axis program even for a part whose overhangs need a multi-axis "
                    "build (they are deposited on nothing; for trials)");
    slice->add_flag("--no-verify", so.no_verify,
                    "Do not replay the written program in the independent verifier");
    slice->add_option("--finer", so.finer,
                      "The profile's finer processes ([[process.finer]]): auto (when the main "
                      "track's beads hold under 99.5% of the finished part, under 97% of a part "
                      "without a near-net shape, or lay nothing), off, or N (use finer process "
                      "N)");

    PartOptions plan_opt;
    PlanOptions po;
    CLI::App* plan_cmd = app.add_subcommand(
        "plan", "Plan a multi-axis build: overhangs, split regions, the hierarchy graph");
    plan_opt.add_to(*plan_cmd);
    CLI::Option* plan_layer_opt =
        plan_cmd->add_option("--layer", po.layer, "Layer thickness in mm (default: the profile's)")
            ->check(CLI::PositiveNumber);
    plan_cmd->add_option("--profile", po.profiles,
                         "Machine/process profile TOML file(s) (default: the built-in reference "
                         "LMD cell)");
    plan_cmd
        ->add_option("--alpha", po.alpha,
                     "Overhang angle Ang (deg) up to which nothing is done (default 30)")
        ->check(CLI::Range(0.0, 180.0));
    plan_cmd
        ->add_option("--beta", po.beta,
                     "Overhang angle Ang (deg) above which the part is split and built "
                     "sideways (default 60)")
        ->check(CLI::Range(0.0, 180.0));
    plan_cmd->add_option("--orient", po.orient,
                         "Base orientation: given (stand as the file has it, along --direction) "
                         "or auto (no layer on nothing, then fewest splits, then fewest tilts)");
    plan_cmd->add_option("--direction", po.direction, "Base (build) direction X,Y,Z when given")
        ->delimiter(',')
        ->expected(3);
    plan_cmd->add_option("--max-regions", po.max_regions, "Refuse parts needing more regions")
        ->check(CLI::PositiveNumber);
    plan_cmd->add_option("--plan", po.plan_file, "Write the plan as JSON (docs/plan-format.md)");
    plan_cmd->add_option("--dot", po.dot_file, "Write the hierarchy graph as Graphviz DOT");
    plan_cmd->add_option(
        "--svg", po.svg_dir,
        "Write one SVG per region and side views by build order and section into this folder");
    plan_cmd->add_option("--mesh-out", po.mesh_out,
                         "Write the layers' walls coloured by region as a PLY mesh");
    plan_cmd->add_option("--order-out", po.order_out,
                         "Write the layers' walls coloured by build order (blue first) as PLY");
    plan_cmd->add_option("--sections-out", po.sections_out,
                         "Write the layers' walls coloured by section of the build order as PLY");

    app::VerifyCommandOptions verify_opt;
    CLI::App* verify_cmd = app::add_verify_command(app, verify_opt);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? kExitOk : kExitBadInput;
    }

    if (verify_cmd->parsed()) return app::run_verify(verify_opt);
    if (slice->parsed()) {
        if (const int rc = check_outputs(*slice, {"--output", "--json", "--contact-sheet", "--svg"},
                                         slice_opt.path, so.profiles);
            rc != kExitOk) {
            return rc;
        }
    }
    if (plan_cmd->parsed()) {
        if (const int rc = check_outputs(
                *plan_cmd,
                {"--plan", "--dot", "--svg", "--mesh-out", "--order-out", "--sections-out"},
                plan_opt.path, po.profiles);
            rc != kExitOk) {
            return rc;
        }
    }
    so.layer_given = layer_opt->count() > 0;
    so.direction_given = direction_opt->count() > 0;
    const PartOptions& active =
        info->parsed() ? info_opt : (plan_cmd->parsed() ? plan_opt : slice_opt);
    std::optional<tbb::global_control> threads;
    if (active.threads > 0) {
        threads.emplace(tbb::global_control::max_allowed_parallelism,
                        static_cast<std::size_t>(active.threads));
    }
    if (info->parsed()) return run_info(info_opt, info_json);
    if (plan_cmd->parsed()) return run_plan(plan_opt, po, plan_layer_opt->count() > 0);
    return run_slice(slice_opt, so);
}

}  // namespace

#if defined(MAXSLICE_WITH_MIMALLOC)
namespace {
// mimalloc puts its segments on transparent huge pages, committed when they are reserved: a
// first touch of a 4 KiB page costs more than the work done on it in most stages
// (docs/decisions/0018-allocator.md). mimalloc reads these options when it starts, in its
// library constructor, which runs before anything of the program but its .preinit_array;
// setting them is a plain store, no allocation.
void tune_allocator() {
    mi_option_enable(mi_option_large_os_pages);
    mi_option_set(mi_option_eager_commit_delay, 0);
}
[[gnu::section(".preinit_array"), gnu::used]] void (*const tune_allocator_early)() = tune_allocator;
}  // namespace
#endif

int main(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "maxslice: internal error: %s\n", e.what());
        return kExitInternal;
    } catch (...) {
        std::fprintf(stderr, "maxslice: internal error\n");
        return kExitInternal;
    }
}
