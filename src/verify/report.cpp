#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

#include "maxslice/verify/verify.hpp"

namespace maxslice::verify {
namespace {

// JSON string escaping for the few free-text fields (details, names).
std::string json_string(std::string_view s) {
    std::string out = "\"";
    for (const char c : s) {
        switch (c) {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\n': out += "\\n"; break;
            case '\t': out += "\\t"; break;
            default:
                if (static_cast<unsigned char>(c) < 0x20) {
                    out += fmt::format("\\u{:04x}", static_cast<int>(c));
                } else {
                    out += c;
                }
        }
    }
    return out + "\"";
}

// Fixed decimals, never "-0.000".
std::string num(double v, int decimals) {
    std::string s = fmt::format("{:.{}f}", v, decimals);
    if (s.front() == '-' && s.find_first_not_of("0.", 1) == std::string::npos) s.erase(0, 1);
    return s;
}

std::string finding_json(const Finding& f) {
    std::string out = fmt::format("{{\"count\": {}", f.count);
    if (f.first) {
        const auto& p = f.first->point_mm;
        out += fmt::format(
            ", \"first\": {{\"line\": {}, \"point_mm\": [{}, {}, {}], \"detail\": {}}}",
            f.first->line, num(p.x, 3), num(p.y, 3), num(p.z, 3), json_string(f.first->detail));
    }
    return out + "}";
}

std::string finding_text(std::string_view name, const Finding& f) {
    if (f.count == 0) return fmt::format("{:<16}none\n", name);
    return fmt::format("{:<16}{} (first: line {}: {})\n", name, f.count, f.first->line,
                       f.first->detail);
}

// "coverage 44.00% below 97.00%; excess 74.00% not under 5.00%", or why the program does not
// match its part otherwise; "" when it matches.
std::string match_text(const Report& r) {
    if (r.deposits_nothing()) {
        return r.deposit_moves == 0
                   ? "the program deposits nothing"
                   : fmt::format(
                         "the program's beads fill no voxel of {:.4f} mm (deposits "
                         "nothing measurable: is the model's unit or the voxel right?)",
                         r.voxel_mm);
    }
    std::string out;
    if (r.coverage_low()) {
        out = fmt::format("coverage {:.2f}% below {:.2f}%", 100.0 * r.coverage,
                          100.0 * r.min_coverage);
    }
    if (r.excess_high()) {
        out += fmt::format("{}excess {:.2f}% not under {:.2f}%", out.empty() ? "" : "; ",
                           100.0 * r.excess, 100.0 * r.max_excess);
    }
    if (r.finished_given && r.finished_low()) {
        out +=
            fmt::format("{}finished part {:.2f}% inside beads, below {:.2f}%",
                        out.empty() ? "" : "; ", 100.0 * r.finished_inside, 100.0 * r.min_coverage);
    }
    return out;
}

}  // namespace

std::string finished_text(const Report& r) {
    return fmt::format("{:.2f}% inside beads, smallest stock {:.2f} mm", 100.0 * r.finished_inside,
                       r.smallest_stock_mm);
}

namespace {

// What the smallest stock's figure means where it needs saying: "" for a stock found within
// the search; else where the part reaches out of the beads, or that the stock is at least the
// search's limit.
std::string stock_note(const Report& r) {
    if (r.finished_volume_mm3 <= 0.0) return "";
    const auto& p = r.smallest_stock_at_mm;
    const bool at_limit =
        r.stock_limit_mm > 0.0 && std::abs(r.smallest_stock_mm) >= r.stock_limit_mm - 1e-9;
    if (r.smallest_stock_mm < 0.0) {
        return fmt::format(
            " (the {} reaches {}{:.2f} mm out of the beads at ({:.3f}, {:.3f}, "
            "{:.3f}))",
            r.finished_given ? "finished part" : "model", at_limit ? "at least " : "",
            -r.smallest_stock_mm, p.x, p.y, p.z);
    }
    if (at_limit) return fmt::format(" (at least: searched up to {:.2f} mm)", r.stock_limit_mm);
    return fmt::format(" (at ({:.3f}, {:.3f}, {:.3f}))", p.x, p.y, p.z);
}

std::string checks_json(const std::vector<std::string_view>& checks) {
    std::string out = "[";
    for (std::size_t i = 0; i < checks.size(); ++i) {
        out += fmt::format("{}\"{}\"", i > 0 ? ", " : "", checks[i]);
    }
    return out + "]";
}

}  // namespace

std::string report_json(const Report& r) {
    std::string out = "{\n";
    const auto field = [&](std::string_view key, const std::string& value, bool last = false) {
        out += fmt::format("  \"{}\": {}{}\n", key, value, last ? "" : ",");
    };
    field("passed", r.accepted() ? "true" : "false");
    field("safe", r.passed() ? "true" : "false");
    field("matches_part", r.matches_part() ? "true" : "false");
    field("failed_checks", checks_json(failed_checks(r)));
    field("dialect", json_string(r.dialect));
    field("kinematics", json_string(r.machine_kinematics));
    field("lines", std::to_string(r.lines));
    field("moves", std::to_string(r.moves));
    field("deposit_moves", std::to_string(r.deposit_moves));
    field("laser_on_count", std::to_string(r.laser_on_count));
    field("voxel_mm", num(r.voxel_mm, 4));
    field("sample_mm", num(r.sample_mm, 4));
    field("poses_checked", std::to_string(r.poses_checked));
    field("default_nozzle", r.default_nozzle ? "true" : "false");
    field("clearance_mm", num(r.clearance_mm, 3));
    field("contact", finding_json(r.collisions));
    field("clearance", finding_json(r.clearance));
    field("unsupported", finding_json(r.unsupported));
    field("unsupported_length_mm", num(r.unsupported_length_mm, 3));
    field("limit_violations", finding_json(r.limit_violations));
    field("out_of_range", finding_json(r.out_of_range));
    field("unfinished", finding_json(r.unfinished));
    field("left_on", finding_json(r.left_on));
    field("substrate", r.substrate ? "true" : "false");
    field("below_plate", finding_json(r.below_plate));
    field("below_plate_mm", num(r.below_plate_mm, 3));
    field("model_volume_mm3", num(r.model_volume_mm3, 3));
    field("deposited_volume_mm3", num(r.deposited_volume_mm3, 3));
    field("covered_volume_mm3", num(r.covered_volume_mm3, 3));
    field("excess_volume_mm3", num(r.excess_volume_mm3, 3));
    field("coverage", num(r.coverage, 6));
    field("excess", num(r.excess, 6));
    field("model_open_columns", std::to_string(r.model_open_columns));
    field("model_columns", std::to_string(r.model_columns));
    field("model_inverted_columns", std::to_string(r.model_inverted_columns));
    field("coverage_judged", r.coverage_judged() ? "true" : "false");
    field("min_coverage", num(r.min_coverage, 6));
    field("max_excess", num(r.max_excess, 6));
    field("finished_given", r.finished_given ? "true" : "false");
    field("finished_volume_mm3", num(r.finished_volume_mm3, 3));
    field("finished_inside_volume_mm3", num(r.finished_inside_volume_mm3, 3));
    field("finished_inside", num(r.finished_inside, 6));
    field("finished_inside_target", num(kFinishedInsideTarget, 6));
    field("smallest_stock_mm", num(r.smallest_stock_mm, 4));
    field("smallest_stock_at_mm",
          fmt::format("[{}, {}, {}]", num(r.smallest_stock_at_mm.x, 3),
                      num(r.smallest_stock_at_mm.y, 3), num(r.smallest_stock_at_mm.z, 3)));
    field("stock_limit_mm", num(r.stock_limit_mm, 4));
    field("finished_open_columns", std::to_string(r.finished_open_columns));
    field("finished_columns", std::to_string(r.finished_columns));
    field("finished_inverted_columns", std::to_string(r.finished_inverted_columns));
    field("finished_judged", r.finished_judged() ? "true" : "false");
    field("deposition_length_mm", num(r.deposition_length_mm, 3));
    field("idle_length_mm", num(r.idle_length_mm, 3));
    field("rotary_travel_deg", num(r.rotary_travel_deg, 3));
    field("deposit_time_s", num(r.deposit_time_s, 3));
    field("idle_time_s", num(r.idle_time_s, 3));
    field("dwell_time_s", num(r.dwell_time_s, 3));
    field("build_time_s", num(r.build_time_s, 3));
    field("bead_height_min_mm", num(r.bead_height_min_mm, 4));
    field("bead_height_max_mm", num(r.bead_height_max_mm, 4), true);
    return out + "}\n";
}

std::string report_text(const Report& r) {
    std::string out;
    auto it = std::back_inserter(out);
    const std::vector<std::string_view> failed = failed_checks(r);
    if (failed.empty()) {
        out += "verification    PASSED\n";
    } else {
        fmt::format_to(it, "verification    FAILED ({})\n", fmt::join(failed, ", "));
    }
    fmt::format_to(it,
                   "program         {} lines, {} moves ({} depositing), {} laser-on, "
                   "dialect {}, kinematics {}\n",
                   r.lines, r.moves, r.deposit_moves, r.laser_on_count, r.dialect,
                   r.machine_kinematics);
    fmt::format_to(it, "grid            voxel {:.4f} mm, poses every {:.3f} mm, {} poses checked\n",
                   r.voxel_mm, r.sample_mm, r.poses_checked);
    if (r.default_nozzle) {
        out += "nozzle          no [machine.nozzle] in the profile: default cone (30 deg, 40 mm)\n";
    }
    out += finding_text("contact", r.collisions);
    out += finding_text(fmt::format("clearance {:.2f}", r.clearance_mm), r.clearance);
    out += finding_text("unsupported", r.unsupported);
    out += finding_text("axis limits", r.limit_violations);
    out += finding_text("out of range", r.out_of_range);
    if (r.unfinished.count > 0) out += finding_text("unfinished", r.unfinished);
    if (r.left_on.count > 0) out += finding_text("left on", r.left_on);
    if (r.below_plate.count > 0) {
        fmt::format_to(it,
                       "plate level     the head reaches up to {:.1f} mm below the plate's level "
                       "in {} blocks (first: line {}: {}); the profile has no "
                       "[machine.substrate]: check the plate, clamps and table by hand\n",
                       r.below_plate_mm, r.below_plate.count, r.below_plate.first->line,
                       r.below_plate.first->detail);
    }
    fmt::format_to(it, "coverage        {:.2f}% of the model's {:.1f} mm3 inside beads\n",
                   100.0 * r.coverage, r.model_volume_mm3);
    fmt::format_to(it,
                   "excess          {:.2f}% ({:.1f} mm3 of {:.1f} mm3 deposited lies outside)\n",
                   100.0 * r.excess, r.excess_volume_mm3, r.deposited_volume_mm3);
    fmt::format_to(it, "finished part   {}{}\n", finished_text(r), stock_note(r));
    if (r.finished_given && !r.finished_judged()) {
        fmt::format_to(it,
                       "finished part   not closed or inside out in {} of {} voxel columns: "
                       "its share inside beads is an estimate\n",
                       r.finished_open_columns + r.finished_inverted_columns, r.finished_columns);
    }
    if (r.model_open_columns > 0) {
        fmt::format_to(it,
                       "model           not closed: {} of {} voxel columns cross its surface "
                       "unevenly; coverage and excess are estimates\n",
                       r.model_open_columns, r.model_columns);
    }
    if (r.model_inverted_columns > 0) {
        fmt::format_to(it,
                       "model           inside out in {} of {} voxel columns (a body facing "
                       "inwards): coverage and excess are estimates\n",
                       r.model_inverted_columns, r.model_columns);
    }
    if (const std::string why = match_text(r); !why.empty()) {
        fmt::format_to(it, "part match      no: {}\n", why);
    } else if (!r.coverage_judged()) {
        out += "part match      not judged: the verifier cannot tell the model's inside\n";
    } else {
        fmt::format_to(it, "part match      yes (coverage >= {:.2f}%, excess < {:.2f}%{})\n",
                       100.0 * r.min_coverage, 100.0 * r.max_excess,
                       r.finished_given ? fmt::format(", finished part >= {:.2f}% inside beads",
                                                      100.0 * r.min_coverage)
                                        : "");
    }
    fmt::format_to(it, "deposition      {:.1f} mm, bead height {:.3f} - {:.3f} mm\n",
                   r.deposition_length_mm, r.bead_height_min_mm, r.bead_height_max_mm);
    fmt::format_to(it, "idle travel     {:.1f} mm, rotary {:.1f} deg\n", r.idle_length_mm,
                   r.rotary_travel_deg);
    fmt::format_to(it, "build time      {:.1f} min (deposit {:.1f}, idle {:.1f}, dwell {:.1f})\n",
                   r.build_time_s / 60.0, r.deposit_time_s / 60.0, r.idle_time_s / 60.0,
                   r.dwell_time_s / 60.0);
    return out;
}

}  // namespace maxslice::verify
