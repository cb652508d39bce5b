#include "maxslice/machine/profile.hpp"

#include "maxslice/core/files.hpp"

#include "maxslice/machine/speed_law.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <toml++/toml.h>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <tuple>

namespace maxslice::machine {
namespace {

using core::ErrorCode;

// Profiles are the edge where people type numbers: every value is range-checked here, with
// ranges wide enough for any DED cell and narrow enough to catch a unit mistake (a track
// width in micrometres, a feed in mm/s scaled wrongly by 1000).

struct Range {
    double lo = 0.0;
    double hi = 0.0;
    bool lo_open = false;  // lo itself is excluded
    bool hi_open = false;
    std::string_view unit;
};

bool in_range(double v, const Range& r) {
    if (!std::isfinite(v)) return false;
    if (r.lo_open ? !(v > r.lo) : !(v >= r.lo)) return false;
    if (r.hi_open ? !(v < r.hi) : !(v <= r.hi)) return false;
    return true;
}

std::string range_text(const Range& r) {
    return fmt::format("{}{}, {}{}{}{}", r.lo_open ? '(' : '[', r.lo, r.hi, r.hi_open ? ')' : ']',
                       r.unit.empty() ? "" : " ", r.unit);
}

core::Result<void> check_range(std::string_view key, double value, const Range& r) {
    if (!std::isfinite(value)) {
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("{} = {} is not a finite number (allowed: {})", key, value, range_text(r)));
    }
    if (!in_range(value, r)) {
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("{} = {} is out of range (allowed: {})", key, value, range_text(r)));
    }
    return {};
}

constexpr double kMaxFeedMmMin = 100000.0;  // 1.7 m/s: beyond any DED feed
constexpr double kMaxPowerW = 100000.0;     // 100 kW
constexpr double kMaxPowderGMin = 1000.0;
constexpr double kMaxAxisTravelMm = 100000.0;  // 100 m from the program origin
constexpr double kMaxDwellMs = 60000.0;
constexpr std::size_t kMaxBlockChars = 120;  // keeps written lines short
constexpr double kMaxNozzleMm = 1000.0;      // a head a metre long is a unit mistake

// A number key of a table: its name, the member it fills and its range.
template <class Profile>
struct NumberKey {
    std::string_view key;
    double Profile::*member;
    Range range;
};

constexpr std::array<NumberKey<ProcessProfile>, 12> kProcessNumbers{{
    {"track_width_mm", &ProcessProfile::track_width_mm, {0.0, 50.0, true, false, "mm"}},
    {"layer_height_mm", &ProcessProfile::layer_height_mm, {0.0, 20.0, true, false, "mm"}},
    {"h_min_mm", &ProcessProfile::h_min_mm, {0.0, 20.0, true, false, "mm"}},
    {"h_max_mm", &ProcessProfile::h_max_mm, {0.0, 20.0, true, false, "mm"}},
    {"overlap", &ProcessProfile::overlap, {0.0, 1.0, false, true, ""}},
    {"laser_power_w", &ProcessProfile::laser_power_w, {0.0, kMaxPowerW, true, false, "W"}},
    {"laser_power_off_w", &ProcessProfile::laser_power_off_w, {0.0, kMaxPowerW, false, false, "W"}},
    {"powder_feed_g_min",
     &ProcessProfile::powder_feed_g_min,
     {0.0, kMaxPowderGMin, false, false, "g/min"}},
    {"deposition_feed_mm_min",
     &ProcessProfile::deposition_feed_mm_min,
     {0.0, kMaxFeedMmMin, true, false, "mm/min"}},
    {"travel_feed_mm_min",
     &ProcessProfile::travel_feed_mm_min,
     {0.0, kMaxFeedMmMin, true, false, "mm/min"}},
    {"dwell_after_laser_on_ms",
     &ProcessProfile::dwell_after_laser_on_ms,
     {0.0, kMaxDwellMs, false, false, "ms"}},
    {"self_supporting_angle_deg",
     &ProcessProfile::self_supporting_angle_deg,
     {0.0, 90.0, false, true, "deg"}},
}};
constexpr std::string_view kContourPassesKey = "contour_passes";
constexpr std::string_view kFinerKey = "finer";
constexpr Range kContourPassesRange{0.0, 100.0, false, false, ""};
constexpr std::string_view kCatchEfficiencyKey = "powder_catch_efficiency";
constexpr Range kCatchEfficiencyRange{0.0, 1.0, true, false, ""};
// Optional: the footing's height (decision 0017); a profile without it keeps the default.
constexpr std::string_view kFootingKey = "footing_mm";
constexpr std::string_view kFreeBodiesKey = "leave_out_free_bodies";
constexpr Range kFootingRange{0.0, 50.0, false, false, "mm"};
// Optional: the near-net shape (decision 0025); absent = 0 = off. [process] only: the
// finer processes build the same near-net shape. The ranges are nearnet::NearNetSettings'.
constexpr std::string_view kStockKey = "machining_stock_mm";
constexpr Range kStockRange{0.0, 20.0, false, false, "mm"};
constexpr std::string_view kFillKey = "fill_below_mm";
constexpr Range kFillRange{0.0, 100.0, false, false, "mm"};
// The speed law (METHOD.md section 10): measured (feed, track height) pairs.
constexpr std::string_view kSpeedHeightKey = "speed_height";
constexpr std::size_t kMaxSpeedPoints = 64;
/// The law must lay the nominal layer at the nominal feed within this share.
constexpr double kSpeedLawNominalTolerance = 0.02;

constexpr std::array<NumberKey<MachineProfile>, 5> kMachineNumbers{{
    {"feed_min_mm_min",
     &MachineProfile::feed_min_mm_min,
     {0.0, kMaxFeedMmMin, true, false, "mm/min"}},
    {"feed_max_mm_min",
     &MachineProfile::feed_max_mm_min,
     {0.0, kMaxFeedMmMin, true, false, "mm/min"}},
    {"laser_power_min_w", &MachineProfile::laser_power_min_w, {0.0, kMaxPowerW, false, false, "W"}},
    {"laser_power_max_w", &MachineProfile::laser_power_max_w, {0.0, kMaxPowerW, true, false, "W"}},
    {"powder_feed_max_g_min",
     &MachineProfile::powder_feed_max_g_min,
     {0.0, kMaxPowderGMin, false, false, "g/min"}},
}};
constexpr Range kAxisRange{-kMaxAxisTravelMm, kMaxAxisTravelMm, false, false, "mm"};
// A tilt beyond a full turn either way is a unit mistake; C may turn on for many turns (a
// continuous axis), but not for thousands.
constexpr Range kTiltAxisRange{-360.0, 360.0, false, false, "deg"};
constexpr Range kCAxisRange{-100000.0, 100000.0, false, false, "deg"};

// [machine.table]: the pivot anywhere in the travel range, the C axis within 10 m of it, a
// retract of up to a metre.
constexpr Range kPivotRange = kAxisRange;
constexpr Range kCOffsetRange{-10000.0, 10000.0, false, false, "mm"};
constexpr Range kRetractRange{0.0, 1000.0, true, false, "mm"};
constexpr Range kDirectionRange{-1.0, 1.0, false, false, ""};

// The collision model of METHOD.md section 7. The half-angle stops short of 90 deg, where the
// cone would be a plane; body_radius_mm may be below the cone's top radius (a slim head).
constexpr std::array<NumberKey<NozzleProfile>, 6> kNozzleNumbers{{
    {"half_angle_deg", &NozzleProfile::half_angle_deg, {0.0, 85.0, true, false, "deg"}},
    {"cone_length_mm", &NozzleProfile::cone_length_mm, {0.0, kMaxNozzleMm, true, false, "mm"}},
    {"standoff_mm", &NozzleProfile::standoff_mm, {0.0, kMaxNozzleMm, true, false, "mm"}},
    {"body_radius_mm", &NozzleProfile::body_radius_mm, {0.0, kMaxNozzleMm, false, false, "mm"}},
    {"body_length_mm", &NozzleProfile::body_length_mm, {0.0, kMaxNozzleMm, false, false, "mm"}},
    {"clearance_mm", &NozzleProfile::clearance_mm, {0.0, 50.0, false, false, "mm"}},
}};

constexpr double kMaxSubstrateMm = 10000.0;  // a plate over 10 m is a unit mistake
constexpr std::array<NumberKey<SubstrateProfile>, 3> kSubstrateNumbers{{
    {"size_x_mm", &SubstrateProfile::size_x_mm, {0.0, kMaxSubstrateMm, true, false, "mm"}},
    {"size_y_mm", &SubstrateProfile::size_y_mm, {0.0, kMaxSubstrateMm, true, false, "mm"}},
    {"thickness_mm", &SubstrateProfile::thickness_mm, {0.0, kMaxSubstrateMm, true, false, "mm"}},
}};

constexpr std::array<std::string_view, 3> kXyzAxes{"X", "Y", "Z"};
constexpr std::array<std::string_view, 5> kAcAxes{"X", "Y", "Z", "A", "C"};
constexpr std::array<std::string_view, 5> kBcAxes{"X", "Y", "Z", "B", "C"};
constexpr std::array<std::string_view, 3> kRotaryAxes{"A", "B", "C"};

struct KinematicsName {
    std::string_view name;
    Kinematics kinematics;
};
constexpr std::array<KinematicsName, 3> kKinematicsNames{{
    {"xyz", Kinematics::kXyz},
    {"xyzac-trt", Kinematics::kTableAc},
    {"xyzbc-trt", Kinematics::kTableBc},
}};

// The axes of a kinematics, in the order of MachineProfile::axes.
std::span<const std::string_view> axis_names(Kinematics k) {
    switch (k) {
        case Kinematics::kXyz: return kXyzAxes;
        case Kinematics::kTableAc: return kAcAxes;
        case Kinematics::kTableBc: return kBcAxes;
    }
    return kXyzAxes;
}

const Range& axis_range(std::string_view axis_name) {
    if (axis_name == "C") return kCAxisRange;
    if (axis_name == "A" || axis_name == "B") return kTiltAxisRange;
    return kAxisRange;
}

// The key of the tilt axis's sign in [machine.table].
std::string_view tilt_direction_key(Kinematics k) {
    return k == Kinematics::kTableBc ? "b_direction" : "a_direction";
}

struct CodeKey {
    std::string_view key;
    CodeTemplate MachineCodes::*member;
    bool required;
};
constexpr std::array<CodeKey, 6> kCodeKeys{{
    {"laser_on", &MachineCodes::laser_on, true},
    {"laser_off", &MachineCodes::laser_off, true},
    {"powder_on", &MachineCodes::powder_on, true},
    {"powder_off", &MachineCodes::powder_off, true},
    {"program_start", &MachineCodes::program_start, false},
    {"program_end", &MachineCodes::program_end, false},
}};
constexpr std::array<std::string_view, 3> kPlaceholders{"power", "power_pct", "powder"};

std::string key_path(std::string_view prefix, std::string_view key) {
    return fmt::format("{}.{}", prefix, key);
}

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

// Levenshtein distance on lower-case names: a typo is usually one or two edits away.
std::size_t edit_distance(std::string_view a_in, std::string_view b_in) {
    const std::string a = lower(a_in);
    const std::string b = lower(b_in);
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diag = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diag = up;
        }
    }
    return row[b.size()];
}

std::string suggestion(std::string_view key, std::span<const std::string_view> known) {
    std::string_view best;
    std::size_t best_distance = std::max<std::size_t>(2, key.size() / 4) + 1;
    for (std::string_view k : known) {
        const std::size_t d = edit_distance(key, k);
        if (d < best_distance) {
            best_distance = d;
            best = k;
        }
    }
    if (best.empty()) {
        // "maximum" for "max": one name starts with the other.
        const std::string k = lower(key);
        for (std::string_view candidate : known) {
            const std::string c = lower(candidate);
            if (std::min(k.size(), c.size()) >= 3 && (k.starts_with(c) || c.starts_with(k))) {
                best = candidate;
                break;
            }
        }
    }
    return best.empty() ? std::string{} : fmt::format(" (did you mean `{}`?)", best);
}

std::string_view type_name(const toml::node& node) {
    switch (node.type()) {
        case toml::node_type::table: return "a table";
        case toml::node_type::array: return "an array";
        case toml::node_type::string: return "a string";
        case toml::node_type::integer: return "an integer";
        case toml::node_type::floating_point: return "a number";
        case toml::node_type::boolean: return "a boolean";
        case toml::node_type::date:
        case toml::node_type::time:
        case toml::node_type::date_time: return "a date/time";
        case toml::node_type::none: break;
    }
    return "nothing";
}

// Reads the keys of one TOML table; every error names the full key path.
class TableReader {
public:
    TableReader(const toml::table& table, std::string prefix)
        : table_(table), prefix_(std::move(prefix)) {}

    [[nodiscard]] std::string path(std::string_view key) const { return key_path(prefix_, key); }

    // Refuses keys outside `known`; checked before anything else so that a misspelt key is
    // reported as such rather than as the key it was meant to be going missing.
    [[nodiscard]] core::Result<void> only(std::span<const std::string_view> known) const {
        for (auto&& [k, node] : table_) {
            const std::string_view name = k.str();
            if (std::find(known.begin(), known.end(), name) != known.end()) continue;
            const std::string hint = suggestion(name, known);
            if (!hint.empty()) {
                return core::fail(ErrorCode::kInvalidInput,
                                  fmt::format("unknown key `{}`{}", path(name), hint));
            }
            std::string allowed;
            for (std::string_view a : known) {
                allowed += allowed.empty() ? "" : ", ";
                allowed += a;
            }
            return core::fail(
                ErrorCode::kInvalidInput,
                fmt::format("unknown key `{}`; allowed in [{}]: {}", path(name), prefix_, allowed));
        }
        return {};
    }

    [[nodiscard]] core::Result<const toml::node*> required(std::string_view key,
                                                           std::string_view expected) const {
        const toml::node* node = table_.get(key);
        if (node == nullptr) {
            return core::fail(ErrorCode::kInvalidInput,
                              fmt::format("missing key `{}` ({})", path(key), expected));
        }
        return node;
    }

    [[nodiscard]] core::Result<double> number(std::string_view key, const Range& range) const {
        const auto node = required(key, fmt::format("a number in {}", range_text(range)));
        if (!node) return std::unexpected(node.error());
        return as_number(key, **node, range);
    }

    [[nodiscard]] const toml::node* find(std::string_view key) const { return table_.get(key); }

    [[nodiscard]] core::Result<std::optional<double>> optional_number(std::string_view key,
                                                                      const Range& range) const {
        const toml::node* node = table_.get(key);
        if (node == nullptr) return std::optional<double>{};
        const auto v = as_number(key, *node, range);
        if (!v) return std::unexpected(v.error());
        return std::optional<double>{*v};
    }

    // A boolean, or nullopt when absent.
    [[nodiscard]] core::Result<std::optional<bool>> optional_boolean(std::string_view key) const {
        const toml::node* node = table_.get(key);
        if (node == nullptr) return std::optional<bool>{};
        if (const auto* b = node->as_boolean()) return std::optional<bool>{b->get()};
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("`{}` must be true or false, got {}", path(key), describe(*node)));
    }

    // An array of exactly `count` numbers (`pivot = [0, 0, -50]`); errors name the element.
    [[nodiscard]] core::Result<std::vector<double>> numbers(std::string_view key, std::size_t count,
                                                            const Range& range) const {
        const std::string expected =
            fmt::format("an array of {} numbers in {}", count, range_text(range));
        const auto node = required(key, expected);
        if (!node) return std::unexpected(node.error());
        const auto* a = (*node)->as_array();
        if (a == nullptr || a->size() != count) {
            return core::fail(ErrorCode::kInvalidInput,
                              fmt::format("`{}` must be {}, got {}", path(key), expected,
                                          a == nullptr ? describe(**node)
                                                       : fmt::format("{} elements", a->size())));
        }
        std::vector<double> out;
        for (std::size_t i = 0; i < count; ++i) {
            const auto v = as_number(fmt::format("{}[{}]", key, i), *a->get(i), range);
            if (!v) return std::unexpected(v.error());
            out.push_back(*v);
        }
        return out;
    }

    [[nodiscard]] core::Result<std::int64_t> integer(std::string_view key,
                                                     const Range& range) const {
        const auto node = required(key, fmt::format("an integer in {}", range_text(range)));
        if (!node) return std::unexpected(node.error());
        if (const auto* v = (*node)->as_integer()) return v->get();
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("`{}` must be an integer in {}, got {}", path(key),
                                      range_text(range), describe(**node)));
    }

    [[nodiscard]] core::Result<std::string> string(std::string_view key,
                                                   std::string_view expected) const {
        const auto node = required(key, expected);
        if (!node) return std::unexpected(node.error());
        if (const auto* v = (*node)->as_string()) return v->get();
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("`{}` must be {}, got {}", path(key), expected, describe(**node)));
    }

    [[nodiscard]] core::Result<const toml::table*> table(std::string_view key,
                                                         std::string_view expected) const {
        const auto node = required(key, expected);
        if (!node) return std::unexpected(node.error());
        return as_table(key, **node, expected);
    }

    // nullptr when the key is absent.
    [[nodiscard]] core::Result<const toml::table*> optional_table(std::string_view key,
                                                                  std::string_view expected) const {
        const toml::node* node = table_.get(key);
        if (node == nullptr) return nullptr;
        return as_table(key, *node, expected);
    }

    // A template is a string (one block, "" for none) or an array of strings (one block each).
    [[nodiscard]] core::Result<CodeTemplate> code(std::string_view key, bool is_required) const {
        constexpr std::string_view kExpected = "a string or an array of strings";
        const toml::node* node = table_.get(key);
        if (node == nullptr) {
            if (!is_required) return CodeTemplate{};
            return core::fail(
                ErrorCode::kInvalidInput,
                fmt::format("missing key `{}` ({}; \"\" for none)", path(key), kExpected));
        }
        CodeTemplate out;
        if (const auto* s = node->as_string()) {
            if (!s->get().empty()) out.blocks.push_back(s->get());
            return out;
        }
        if (const auto* a = node->as_array()) {
            for (std::size_t i = 0; i < a->size(); ++i) {
                const auto* s = a->get(i)->as_string();
                if (s == nullptr) {
                    return core::fail(ErrorCode::kInvalidInput,
                                      fmt::format("`{}[{}]` must be a string, got {}", path(key), i,
                                                  describe(*a->get(i))));
                }
                out.blocks.push_back(s->get());
            }
            return out;
        }
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("`{}` must be {}, got {}", path(key), kExpected, describe(*node)));
    }

private:
    [[nodiscard]] static std::string describe(const toml::node& node) {
        if (const auto* s = node.as_string()) return fmt::format("\"{}\"", s->get());
        if (const auto* b = node.as_boolean()) return b->get() ? "true" : "false";
        return std::string(type_name(node));
    }

    [[nodiscard]] core::Result<double> as_number(std::string_view key, const toml::node& node,
                                                 const Range& range) const {
        // Integers are fine where a number is expected (`track_width_mm = 3`).
        if (const auto* f = node.as_floating_point()) return f->get();
        if (const auto* i = node.as_integer()) return static_cast<double>(i->get());
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("`{}` must be a number in {}, got {}", path(key),
                                      range_text(range), describe(node)));
    }

    [[nodiscard]] core::Result<const toml::table*> as_table(std::string_view key,
                                                            const toml::node& node,
                                                            std::string_view expected) const {
        if (const auto* t = node.as_table()) return t;
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("`{}` must be {}, got {}", path(key), expected, describe(node)));
    }

    const toml::table& table_;
    std::string prefix_;
};

template <class T>
std::unexpected<core::Error> pass(const core::Result<T>& r) {
    return std::unexpected(r.error());
}

template <class Profile, std::size_t N>
std::vector<std::string_view> keys_of(const std::array<NumberKey<Profile>, N>& numbers) {
    std::vector<std::string_view> keys;
    for (const auto& f : numbers) keys.push_back(f.key);
    return keys;
}

// Reads every key of `numbers` from the reader's table into `out`.
template <class Profile, std::size_t N>
core::Result<void> read_numbers(const TableReader& reader,
                                const std::array<NumberKey<Profile>, N>& numbers, Profile& out) {
    for (const auto& f : numbers) {
        const auto v = reader.number(f.key, f.range);
        if (!v) return pass(v);
        out.*f.member = *v;
    }
    return {};
}

// Range-checks every key of `numbers` in `value`; errors name the key as "PREFIX.KEY".
template <class Profile, std::size_t N>
core::Result<void> check_numbers(std::string_view prefix, const Profile& value,
                                 const std::array<NumberKey<Profile>, N>& numbers) {
    for (const auto& f : numbers) {
        if (auto ok = check_range(key_path(prefix, f.key), value.*f.member, f.range); !ok) {
            return ok;
        }
    }
    return {};
}

// `speed_height = [[feed, height], ...]` (optional): each pair two numbers; ranges and order
// are validate()'s.
core::Result<std::vector<SpeedPoint>> read_speed_height(const TableReader& reader) {
    std::vector<SpeedPoint> out;
    const toml::node* node = reader.find(kSpeedHeightKey);
    if (node == nullptr) return out;
    const std::string key = reader.path(kSpeedHeightKey);
    const auto* a = node->as_array();
    if (a == nullptr || a->size() < 2 || a->size() > kMaxSpeedPoints) {
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("`{}` must be an array of 2 to {} [feed_mm_min, height_mm] pairs, got {}",
                        key, kMaxSpeedPoints,
                        a == nullptr ? std::string(type_name(*node))
                                     : fmt::format("{} elements", a->size())));
    }
    for (std::size_t i = 0; i < a->size(); ++i) {
        const auto* pair = a->get(i)->as_array();
        const auto number = [&](std::size_t j) -> std::optional<double> {
            if (pair == nullptr || pair->size() != 2) return std::nullopt;
            const toml::node* n = pair->get(j);
            if (const auto* f = n->as_floating_point()) return f->get();
            if (const auto* k = n->as_integer()) return static_cast<double>(k->get());
            return std::nullopt;
        };
        const auto feed = number(0), height = number(1);
        if (!feed || !height) {
            return core::fail(ErrorCode::kInvalidInput,
                              fmt::format("`{}[{}]` must be a pair of numbers [feed_mm_min, "
                                          "height_mm], got {}",
                                          key, i, std::string(type_name(*a->get(i)))));
        }
        out.push_back({*feed, *height});
    }
    return out;
}

core::Result<ProcessProfile> read_process(const toml::table& table, bool finer_allowed = true) {
    const TableReader reader(table, "process");
    std::vector<std::string_view> known = keys_of(kProcessNumbers);
    known.push_back(kContourPassesKey);
    known.push_back(kCatchEfficiencyKey);
    known.push_back(kFootingKey);
    known.push_back(kSpeedHeightKey);
    if (finer_allowed) {
        known.push_back(kFinerKey);
        known.push_back(kFreeBodiesKey);  // the part's, as the near-net shape
        known.push_back(kStockKey);
        known.push_back(kFillKey);
    } else {
        for (const std::string_view key : {kStockKey, kFillKey}) {
            if (table.contains(key)) {
                return core::fail(ErrorCode::kInvalidInput,
                                  fmt::format("{} belongs to [process] only: the near-net shape "
                                              "is the part's, and every finer process builds "
                                              "the same one (remove it here)",
                                              key));
            }
        }
    }
    if (auto ok = reader.only(known); !ok) return pass(ok);

    ProcessProfile p;
    if (auto ok = read_numbers(reader, kProcessNumbers, p); !ok) return pass(ok);
    const auto passes = reader.integer(kContourPassesKey, kContourPassesRange);
    if (!passes) return pass(passes);
    if (!in_range(static_cast<double>(*passes), kContourPassesRange)) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("process.{} = {} is out of range (allowed: {})",
                                      kContourPassesKey, *passes, range_text(kContourPassesRange)));
    }
    p.contour_passes = static_cast<int>(*passes);
    const auto efficiency = reader.optional_number(kCatchEfficiencyKey, kCatchEfficiencyRange);
    if (!efficiency) return pass(efficiency);
    p.powder_catch_efficiency = *efficiency;
    const auto footing = reader.optional_number(kFootingKey, kFootingRange);
    if (!footing) return pass(footing);
    if (*footing) p.footing_mm = **footing;
    const auto free_bodies = reader.optional_boolean(kFreeBodiesKey);
    if (!free_bodies) return pass(free_bodies);
    if (*free_bodies) p.leave_out_free_bodies = **free_bodies;
    for (const auto& [key, range, member] :
         {std::tuple{kStockKey, kStockRange, &ProcessProfile::machining_stock_mm},
          std::tuple{kFillKey, kFillRange, &ProcessProfile::fill_below_mm}}) {
        const auto value = reader.optional_number(key, range);
        if (!value) return pass(value);
        if (*value) p.*member = **value;
    }
    auto law = read_speed_height(reader);
    if (!law) return pass(law);
    p.speed_height = std::move(*law);

    if (auto ok = validate(p); !ok) return pass(ok);
    if (!finer_allowed || !table.contains(kFinerKey)) return p;
    // [[process.finer]]: an array of whole process tables, tracks narrowing one by one.
    const auto* finer = table[kFinerKey].as_array();
    if (finer == nullptr || finer->empty() || !finer->is_array_of_tables()) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("`process.{}` must be one or more tables "
                                      "([[process.{}]]), each a whole [process]",
                                      kFinerKey, kFinerKey));
    }
    double wider = p.track_width_mm;
    for (std::size_t i = 0; i < finer->size(); ++i) {
        const std::string where = fmt::format("[[process.{}]] number {}", kFinerKey, i + 1);
        auto f = read_process(*finer->get(i)->as_table(), false);
        if (!f) return std::unexpected(core::with_context(f.error(), where));
        if (!(f->track_width_mm < wider)) {
            return core::fail(ErrorCode::kInvalidInput,
                              fmt::format("its track_width_mm = {} must be narrower than the "
                                          "{} mm before it",
                                          f->track_width_mm, wider),
                              where);
        }
        wider = f->track_width_mm;
        f->machining_stock_mm = p.machining_stock_mm;
        f->fill_below_mm = p.fill_below_mm;
        f->leave_out_free_bodies = p.leave_out_free_bodies;
        p.finer.push_back(std::move(*f));
    }
    return p;
}

core::Result<std::vector<AxisLimits>> read_axes(const TableReader& machine, Kinematics kinematics) {
    const auto table = machine.table("axes", "a table of axes, e.g. X = { min = 0, max = 500 }");
    if (!table) return pass(table);
    const TableReader axes(**table, machine.path("axes"));
    const std::span<const std::string_view> names = axis_names(kinematics);
    for (auto&& [k, node] : **table) {
        const std::string_view name = k.str();
        const bool rotary =
            std::find(kRotaryAxes.begin(), kRotaryAxes.end(), name) != kRotaryAxes.end();
        if (!rotary || std::find(names.begin(), names.end(), name) != names.end()) continue;
        if (kinematics == Kinematics::kXyz) {
            return core::fail(ErrorCode::kInvalidInput,
                              fmt::format("`{}`: rotary axes need a tilting-rotary table "
                                          "(kinematics \"xyzac-trt\" or \"xyzbc-trt\"); "
                                          "kinematics \"xyz\" takes X, Y and Z",
                                          axes.path(name)));
        }
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("`{}`: kinematics \"{}\" takes the axes X, Y, Z, {}, C "
                                      "(axis {} belongs to \"{}\")",
                                      axes.path(name), kinematics_name(kinematics), names[3], name,
                                      name == "A" ? "xyzac-trt" : "xyzbc-trt"));
    }
    if (auto ok = axes.only(names); !ok) return pass(ok);

    std::vector<AxisLimits> out;
    constexpr std::array<std::string_view, 2> kLimitKeys{"min", "max"};
    for (std::string_view name : names) {
        const Range& range = axis_range(name);
        const auto axis =
            axes.table(name, fmt::format("a table {{ min = ..., max = ... }} in {}", range.unit));
        if (!axis) return pass(axis);
        const TableReader limits(**axis, axes.path(name));
        if (auto ok = limits.only(kLimitKeys); !ok) return pass(ok);
        const auto lo = limits.number("min", range);
        if (!lo) return pass(lo);
        const auto hi = limits.number("max", range);
        if (!hi) return pass(hi);
        out.push_back({std::string(name), *lo, *hi});
    }
    return out;
}

// [machine.table]: required for the table-tilt kinematics, every key required; refused for
// "xyz" (a table nobody reads would hide a wrong kinematics line).
core::Result<std::optional<TableProfile>> read_table(const TableReader& machine,
                                                     Kinematics kinematics) {
    constexpr std::string_view kExpected =
        "a table with pivot, c_offset, a_direction (b_direction for xyzbc-trt), c_direction "
        "and retract_mm";
    if (!is_table_tilt(kinematics)) {
        const auto table = machine.optional_table("table", kExpected);
        if (!table) return pass(table);
        if (*table == nullptr) return std::optional<TableProfile>{};
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("`{}` is only for the tilting-rotary table kinematics "
                                      "(\"xyzac-trt\", \"xyzbc-trt\"); kinematics \"{}\" has "
                                      "no rotary table",
                                      machine.path("table"), kinematics_name(kinematics)));
    }
    const auto table = machine.table(
        "table", fmt::format("kinematics \"{}\" needs {}", kinematics_name(kinematics), kExpected));
    if (!table) return pass(table);
    const TableReader reader(**table, machine.path("table"));
    const std::string_view tilt_key = tilt_direction_key(kinematics);
    const std::array<std::string_view, 5> known{"pivot", "c_offset", tilt_key, "c_direction",
                                                "retract_mm"};
    if (auto ok = reader.only(known); !ok) return pass(ok);

    TableProfile t;
    const auto pivot = reader.numbers("pivot", 3, kPivotRange);
    if (!pivot) return pass(pivot);
    t.pivot_mm = {(*pivot)[0], (*pivot)[1], (*pivot)[2]};
    const auto offset = reader.numbers("c_offset", 2, kCOffsetRange);
    if (!offset) return pass(offset);
    t.c_offset_x_mm = (*offset)[0];
    t.c_offset_y_mm = (*offset)[1];
    const auto sign = [&](std::string_view key) -> core::Result<int> {
        const auto v = reader.integer(key, kDirectionRange);
        if (!v) return pass(v);
        if (*v != 1 && *v != -1) {
            return core::fail(ErrorCode::kInvalidInput,
                              fmt::format("{} = {} must be 1 or -1 (the sense of the axis)",
                                          reader.path(key), *v));
        }
        return static_cast<int>(*v);
    };
    const auto tilt = sign(tilt_key);
    if (!tilt) return pass(tilt);
    t.tilt_direction = *tilt;
    const auto c = sign("c_direction");
    if (!c) return pass(c);
    t.c_direction = *c;
    const auto retract = reader.number("retract_mm", kRetractRange);
    if (!retract) return pass(retract);
    t.retract_mm = *retract;
    return std::optional<TableProfile>{t};
}

core::Result<void> check_table(const TableProfile& t, Kinematics kinematics) {
    const std::array<double, 3> pivot{t.pivot_mm.x, t.pivot_mm.y, t.pivot_mm.z};
    for (std::size_t i = 0; i < pivot.size(); ++i) {
        if (auto ok = check_range(fmt::format("machine.table.pivot[{}]", i), pivot[i], kPivotRange);
            !ok) {
            return ok;
        }
    }
    if (auto ok = check_range("machine.table.c_offset[0]", t.c_offset_x_mm, kCOffsetRange); !ok) {
        return ok;
    }
    if (auto ok = check_range("machine.table.c_offset[1]", t.c_offset_y_mm, kCOffsetRange); !ok) {
        return ok;
    }
    const auto sign = [](std::string_view key, int v) -> core::Result<void> {
        if (v == 1 || v == -1) return {};
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("machine.table.{} = {} must be 1 or -1 (the sense of the axis)", key, v));
    };
    if (auto ok = sign(tilt_direction_key(kinematics), t.tilt_direction); !ok) return ok;
    if (auto ok = sign("c_direction", t.c_direction); !ok) return ok;
    return check_range("machine.table.retract_mm", t.retract_mm, kRetractRange);
}

// An optional table of numbers under [machine] ([machine.nozzle], [machine.substrate]):
// nothing when it is absent, every key of `keys` required when it is there.
template <class Profile, std::size_t N>
core::Result<std::optional<Profile>> read_optional_numbers(
    const TableReader& machine, std::string_view key, std::string_view expected,
    const std::array<NumberKey<Profile>, N>& keys) {
    const auto table = machine.optional_table(key, expected);
    if (!table) return pass(table);
    if (*table == nullptr) return std::optional<Profile>{};
    const TableReader reader(**table, machine.path(key));
    if (auto ok = reader.only(keys_of(keys)); !ok) return pass(ok);
    Profile p;
    if (auto ok = read_numbers(reader, keys, p); !ok) return pass(ok);
    return std::optional<Profile>{p};
}

core::Result<MachineProfile> read_machine(const toml::table& table) {
    const TableReader reader(table, "machine");
    std::vector<std::string_view> known{"name",  "kinematics", "dialect", "axes",
                                        "codes", "nozzle",     "table",   "substrate"};
    for (const auto& f : kMachineNumbers) known.push_back(f.key);
    if (auto ok = reader.only(known); !ok) return pass(ok);

    MachineProfile m;
    const auto name = reader.string("name", "a string naming the machine");
    if (!name) return pass(name);
    m.name = *name;

    constexpr std::string_view kKinematicsExpected = "\"xyz\", \"xyzac-trt\" or \"xyzbc-trt\"";
    const auto kinematics = reader.string("kinematics", kKinematicsExpected);
    if (!kinematics) return pass(kinematics);
    const auto known_kinematics =
        std::find_if(kKinematicsNames.begin(), kKinematicsNames.end(),
                     [&](const KinematicsName& k) { return k.name == *kinematics; });
    if (known_kinematics == kKinematicsNames.end()) {
        std::vector<std::string_view> names;
        for (const auto& k : kKinematicsNames) names.push_back(k.name);
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("machine.kinematics = \"{}\" is unknown (allowed: {}){}", *kinematics,
                        kKinematicsExpected, suggestion(*kinematics, names)));
    }
    m.kinematics = known_kinematics->kinematics;

    constexpr std::string_view kDialectExpected = "\"gm\", \"linuxcnc\", \"fanuc\" or \"siemens\"";
    const auto dialect = reader.string("dialect", kDialectExpected);
    if (!dialect) return pass(dialect);
    const auto known_dialect = parse_dialect(*dialect);
    if (!known_dialect) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("machine.dialect = \"{}\" is unknown (allowed: {})", *dialect,
                                      kDialectExpected));
    }
    m.dialect = *known_dialect;

    const auto axes = read_axes(reader, m.kinematics);
    if (!axes) return pass(axes);
    m.axes = *axes;

    if (auto ok = read_numbers(reader, kMachineNumbers, m); !ok) return pass(ok);

    const auto codes = reader.table("codes", "a table of M-code templates");
    if (!codes) return pass(codes);
    const TableReader code_reader(**codes, reader.path("codes"));
    std::vector<std::string_view> code_keys;
    for (const auto& c : kCodeKeys) code_keys.push_back(c.key);
    if (auto ok = code_reader.only(code_keys); !ok) return pass(ok);
    for (const auto& c : kCodeKeys) {
        const auto t = code_reader.code(c.key, c.required);
        if (!t) return pass(t);
        m.codes.*c.member = *t;
    }

    auto nozzle = read_optional_numbers(reader, "nozzle", "a table of nozzle (collision) sizes",
                                        kNozzleNumbers);
    if (!nozzle) return pass(nozzle);
    m.nozzle = *nozzle;

    auto substrate = read_optional_numbers(reader, "substrate", "a table of substrate plate sizes",
                                           kSubstrateNumbers);
    if (!substrate) return pass(substrate);
    m.substrate = *substrate;

    auto table_geometry = read_table(reader, m.kinematics);
    if (!table_geometry) return pass(table_geometry);
    m.table = *table_geometry;

    if (auto ok = validate(m); !ok) return pass(ok);
    return m;
}

core::Result<void> check_block(std::string_view key, std::size_t index, std::string_view block) {
    const std::string where = fmt::format("machine.codes.{}[{}] = \"{}\"", key, index, block);
    if (block.empty()) {
        return core::fail(ErrorCode::kInvalidInput, where + " is an empty block");
    }
    if (block.size() > kMaxBlockChars) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("{} is longer than {} characters", where, kMaxBlockChars));
    }
    for (char c : block) {
        if (c < 0x20 || c > 0x7e) {
            return core::fail(ErrorCode::kInvalidInput,
                              where +
                                  " holds a tab, line break or non-ASCII character (one "
                                  "block per line: use an array for several)");
        }
    }
    for (std::size_t i = 0; i < block.size(); ++i) {
        if (block[i] == '}') {
            return core::fail(ErrorCode::kInvalidInput, where + " has a `}` without `{`");
        }
        if (block[i] != '{') continue;
        const std::size_t close = block.find('}', i);
        if (close == std::string_view::npos) {
            return core::fail(ErrorCode::kInvalidInput, where + " has a `{` without `}`");
        }
        const std::string_view name = block.substr(i + 1, close - i - 1);
        if (std::find(kPlaceholders.begin(), kPlaceholders.end(), name) == kPlaceholders.end()) {
            return core::fail(ErrorCode::kInvalidInput,
                              fmt::format("{} has an unknown placeholder {{{}}} (allowed: "
                                          "{{power}}, {{power_pct}}, {{powder}})",
                                          where, name));
        }
        i = close;
    }
    if (const auto word = motion_word(block)) {
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("{} moves the machine ({}): a code block may switch the "
                        "laser and powder, not move (the planner does not plan a move "
                        "written there: put moves in the program)",
                        where, *word));
    }
    return {};
}

core::Result<void> check_nozzle(const NozzleProfile& n) {
    if (auto ok = check_numbers("machine.nozzle", n, kNozzleNumbers); !ok) return ok;
    if (n.standoff_mm > n.cone_length_mm) {
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("machine.nozzle.standoff_mm = {} is above "
                        "machine.nozzle.cone_length_mm = {} (the tip lies within the cone)",
                        n.standoff_mm, n.cone_length_mm));
    }
    if ((n.body_radius_mm > 0.0) != (n.body_length_mm > 0.0)) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("machine.nozzle.body_radius_mm = {} and "
                                      "machine.nozzle.body_length_mm = {}: both 0 (no head body) "
                                      "or both above 0",
                                      n.body_radius_mm, n.body_length_mm));
    }
    return {};
}

core::Result<ProfileFile> parse_document(const toml::table& doc) {
    constexpr std::array<std::string_view, 2> kSections{"machine", "process"};
    for (auto&& [k, node] : doc) {
        const std::string_view name = k.str();
        if (std::find(kSections.begin(), kSections.end(), name) == kSections.end()) {
            return core::fail(ErrorCode::kInvalidInput,
                              fmt::format("unknown key `{}`{}; a profile holds the tables "
                                          "[machine] and/or [process]",
                                          name, suggestion(name, kSections)));
        }
        if (!node.is_table()) {
            return core::fail(
                ErrorCode::kInvalidInput,
                fmt::format("`{}` must be a table ([{}]), got {}", name, name, type_name(node)));
        }
    }
    ProfileFile out;
    if (const auto* t = doc["machine"].as_table()) {
        auto m = read_machine(*t);
        if (!m) return pass(m);
        out.machine = std::move(*m);
    }
    if (const auto* t = doc["process"].as_table()) {
        auto p = read_process(*t);
        if (!p) return pass(p);
        out.process = std::move(*p);
    }
    if (!out.machine && !out.process) {
        return core::fail(ErrorCode::kInvalidInput,
                          "the profile holds neither a [machine] nor a [process] table");
    }
    return out;
}

std::string format_value(double v) {
    // Fixed decimals, and never "-0.00".
    const double r = std::round(v * 100.0) / 100.0;
    return fmt::format("{:.2f}", r == 0.0 ? 0.0 : r);
}

}  // namespace

core::Vec3d plate_center(const MachineProfile& machine) {
    if (is_table_tilt(machine.kinematics) && machine.table) {
        return {machine.table->c_offset_x_mm, machine.table->c_offset_y_mm, 0.0};
    }
    core::Vec3d c{};
    if (const auto* x = machine.find_axis("X")) c.x = 0.5 * (x->min + x->max);
    if (const auto* y = machine.find_axis("Y")) c.y = 0.5 * (y->min + y->max);
    return c;
}

const AxisLimits* MachineProfile::find_axis(std::string_view axis_name) const {
    for (const auto& a : axes) {
        if (a.name == axis_name) return &a;
    }
    return nullptr;
}

namespace {

// The measured speed law: 2 to kMaxSpeedPoints pairs in range, feeds strictly increasing,
// heights strictly decreasing, and the law lays the nominal layer at the nominal feed.
core::Result<void> check_speed_height(const ProcessProfile& p) {
    if (p.speed_height.empty()) return {};
    const std::string key = key_path("process", kSpeedHeightKey);
    if (p.speed_height.size() < 2 || p.speed_height.size() > kMaxSpeedPoints) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("{} has {} pairs (allowed: 2 to {})", key,
                                      p.speed_height.size(), kMaxSpeedPoints));
    }
    for (std::size_t i = 0; i < p.speed_height.size(); ++i) {
        const SpeedPoint& q = p.speed_height[i];
        if (auto ok = check_range(fmt::format("{}[{}] feed", key, i), q.feed_mm_min,
                                  {0.0, kMaxFeedMmMin, true, false, "mm/min"});
            !ok) {
            return ok;
        }
        if (auto ok = check_range(fmt::format("{}[{}] height", key, i), q.height_mm,
                                  {0.0, 20.0, true, false, "mm"});
            !ok) {
            return ok;
        }
        if (i > 0 && (q.feed_mm_min <= p.speed_height[i - 1].feed_mm_min ||
                      q.height_mm >= p.speed_height[i - 1].height_mm)) {
            return core::fail(
                ErrorCode::kInvalidInput,
                fmt::format("{}[{}] = [{}, {}] after [{}, {}]: feeds must increase and heights "
                            "decrease (a faster track is lower)",
                            key, i, q.feed_mm_min, q.height_mm, p.speed_height[i - 1].feed_mm_min,
                            p.speed_height[i - 1].height_mm));
        }
    }
    const double nominal = SpeedLaw::of(p).height_mm(p.deposition_feed_mm_min);
    if (std::abs(nominal - p.layer_height_mm) > kSpeedLawNominalTolerance * p.layer_height_mm) {
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("{} lays {:.4g} mm at process.deposition_feed_mm_min = {} but "
                        "process.layer_height_mm is {}: they must agree within {:.0f}%",
                        key, nominal, p.deposition_feed_mm_min, p.layer_height_mm,
                        100.0 * kSpeedLawNominalTolerance));
    }
    return {};
}

}  // namespace

core::Result<void> validate(const ProcessProfile& p) {
    if (auto ok = check_numbers("process", p, kProcessNumbers); !ok) return ok;
    if (!in_range(static_cast<double>(p.contour_passes), kContourPassesRange)) {
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("process.{} = {} is out of range (allowed: {})", kContourPassesKey,
                        p.contour_passes, range_text(kContourPassesRange)));
    }
    if (p.powder_catch_efficiency) {
        if (auto ok = check_range(key_path("process", kCatchEfficiencyKey),
                                  *p.powder_catch_efficiency, kCatchEfficiencyRange);
            !ok) {
            return ok;
        }
    }
    if (auto ok = check_range(key_path("process", kFootingKey), p.footing_mm, kFootingRange); !ok) {
        return ok;
    }
    if (auto ok = check_range(key_path("process", kStockKey), p.machining_stock_mm, kStockRange);
        !ok) {
        return ok;
    }
    if (auto ok = check_range(key_path("process", kFillKey), p.fill_below_mm, kFillRange); !ok) {
        return ok;
    }
    if (p.h_min_mm > p.h_max_mm) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("process.h_min_mm = {} is above process.h_max_mm = {} "
                                      "(need h_min_mm <= layer_height_mm <= h_max_mm)",
                                      p.h_min_mm, p.h_max_mm));
    }
    if (p.layer_height_mm < p.h_min_mm || p.layer_height_mm > p.h_max_mm) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("process.layer_height_mm = {} is outside [process.h_min_mm, "
                                      "process.h_max_mm] = [{}, {}] mm",
                                      p.layer_height_mm, p.h_min_mm, p.h_max_mm));
    }
    if (p.layer_height_mm > p.track_width_mm) {
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("process.layer_height_mm = {} is above process.track_width_mm "
                        "= {} (a bead is wider than it is high)",
                        p.layer_height_mm, p.track_width_mm));
    }
    if (p.laser_power_off_w >= p.laser_power_w) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("process.laser_power_off_w = {} must be below "
                                      "process.laser_power_w = {}",
                                      p.laser_power_off_w, p.laser_power_w));
    }
    return check_speed_height(p);
}

core::Result<void> validate(const MachineProfile& m) {
    if (m.name.empty()) {
        return core::fail(ErrorCode::kInvalidInput, "machine.name is empty (name the machine)");
    }
    const std::span<const std::string_view> names = axis_names(m.kinematics);
    if (m.axes.size() != names.size()) {
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("machine.axes has {} axes; kinematics \"{}\" needs {}", m.axes.size(),
                        kinematics_name(m.kinematics), fmt::join(names, ", ")));
    }
    for (std::size_t i = 0; i < names.size(); ++i) {
        const AxisLimits& a = m.axes[i];
        if (a.name != names[i]) {
            return core::fail(ErrorCode::kInvalidInput,
                              fmt::format("machine.axes: axis {} is \"{}\", expected \"{}\"", i,
                                          a.name, names[i]));
        }
        const std::string prefix = fmt::format("machine.axes.{}", a.name);
        const Range& range = axis_range(a.name);
        if (auto ok = check_range(prefix + ".min", a.min, range); !ok) return ok;
        if (auto ok = check_range(prefix + ".max", a.max, range); !ok) return ok;
        if (!(a.min < a.max)) {
            return core::fail(
                ErrorCode::kInvalidInput,
                fmt::format("{}.min = {} must be below {}.max = {}", prefix, a.min, prefix, a.max));
        }
    }
    if (is_table_tilt(m.kinematics)) {
        if (!m.table) {
            return core::fail(
                ErrorCode::kInvalidInput,
                fmt::format("machine.table is missing: kinematics \"{}\" needs the "
                            "table geometry (pivot, c_offset, {}, c_direction, "
                            "retract_mm)",
                            kinematics_name(m.kinematics), tilt_direction_key(m.kinematics)));
        }
        if (auto ok = check_table(*m.table, m.kinematics); !ok) return ok;
    } else if (m.table) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("machine.table is only for the tilting-rotary table "
                                      "kinematics; kinematics \"{}\" has no rotary table",
                                      kinematics_name(m.kinematics)));
    }
    if (auto ok = check_numbers("machine", m, kMachineNumbers); !ok) return ok;
    if (m.feed_min_mm_min > m.feed_max_mm_min) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("machine.feed_min_mm_min = {} is above "
                                      "machine.feed_max_mm_min = {}",
                                      m.feed_min_mm_min, m.feed_max_mm_min));
    }
    if (m.laser_power_min_w > m.laser_power_max_w) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("machine.laser_power_min_w = {} is above "
                                      "machine.laser_power_max_w = {}",
                                      m.laser_power_min_w, m.laser_power_max_w));
    }
    for (const auto& c : kCodeKeys) {
        const CodeTemplate& t = m.codes.*c.member;
        for (std::size_t i = 0; i < t.blocks.size(); ++i) {
            if (auto ok = check_block(c.key, i, t.blocks[i]); !ok) return ok;
        }
    }
    // Only gm has a power column: elsewhere, without codes the laser would never switch.
    if (m.dialect != Dialect::kGm) {
        if (m.codes.laser_on.blocks.empty() || m.codes.laser_off.blocks.empty()) {
            return core::fail(ErrorCode::kInvalidInput,
                              fmt::format("machine.codes.laser_on and machine.codes.laser_off "
                                          "must not be empty for dialect \"{}\" (nothing else "
                                          "switches the laser)",
                                          dialect_name(m.dialect)));
        }
    }
    if (m.substrate) {
        if (auto ok = check_numbers("machine.substrate", *m.substrate, kSubstrateNumbers); !ok) {
            return ok;
        }
    }
    if (m.nozzle) {
        if (auto ok = check_nozzle(*m.nozzle); !ok) return ok;
    }
    return {};
}

core::Result<void> check_compatible(const MachineProfile& m, const ProcessProfile& p) {
    const auto feed = [&](std::string_view key, double value) -> core::Result<void> {
        if (value >= m.feed_min_mm_min && value <= m.feed_max_mm_min) return {};
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("process.{} = {} is outside the machine's feed range "
                                      "[machine.feed_min_mm_min, machine.feed_max_mm_min] = "
                                      "[{}, {}] mm/min",
                                      key, value, m.feed_min_mm_min, m.feed_max_mm_min));
    };
    if (auto ok = feed("deposition_feed_mm_min", p.deposition_feed_mm_min); !ok) return ok;
    if (auto ok = feed("travel_feed_mm_min", p.travel_feed_mm_min); !ok) return ok;
    const auto power = [&](std::string_view key, double value) -> core::Result<void> {
        if (value == 0.0 || (value >= m.laser_power_min_w && value <= m.laser_power_max_w)) {
            return {};
        }
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("process.{} = {} is outside the machine's power range "
                                      "[machine.laser_power_min_w, machine.laser_power_max_w] = "
                                      "[{}, {}] W (or 0)",
                                      key, value, m.laser_power_min_w, m.laser_power_max_w));
    };
    if (auto ok = power("laser_power_w", p.laser_power_w); !ok) return ok;
    if (auto ok = power("laser_power_off_w", p.laser_power_off_w); !ok) return ok;
    for (std::size_t i = 0; i < p.speed_height.size(); ++i) {
        const double f = p.speed_height[i].feed_mm_min;
        if (f < m.feed_min_mm_min || f > m.feed_max_mm_min) {
            return core::fail(
                ErrorCode::kInvalidInput,
                fmt::format("process.{}[{}] feed {} is outside the machine's feed "
                            "range [machine.feed_min_mm_min, "
                            "machine.feed_max_mm_min] = [{}, {}] mm/min",
                            kSpeedHeightKey, i, f, m.feed_min_mm_min, m.feed_max_mm_min));
        }
    }
    if (p.powder_feed_g_min > m.powder_feed_max_g_min) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("process.powder_feed_g_min = {} is above "
                                      "machine.powder_feed_max_g_min = {}",
                                      p.powder_feed_g_min, m.powder_feed_max_g_min));
    }
    for (std::size_t i = 0; i < p.finer.size(); ++i) {
        if (auto ok = check_compatible(m, p.finer[i]); !ok) {
            return std::unexpected(core::with_context(
                ok.error(), fmt::format("[[process.{}]] number {}", kFinerKey, i + 1)));
        }
    }
    return {};
}

core::Result<Profiles> with_finer_process(const Profiles& profiles, int n) {
    const auto& finer = profiles.process.finer;
    if (n < 0 || static_cast<std::size_t>(n) > finer.size()) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("the profile has no finer process {} (it has {}: "
                                      "[[process.{}]])",
                                      n, finer.size(), kFinerKey));
    }
    Profiles out{profiles.machine,
                 n == 0 ? profiles.process : finer[static_cast<std::size_t>(n - 1)]};
    out.process.finer.clear();
    return out;
}

core::Result<ProfileFile> parse_profile(std::string_view toml_text, std::string_view source) {
    const std::string context = fmt::format("profile {}", source);
    toml::table doc;
    try {
        doc = toml::parse(toml_text, source);
    } catch (const toml::parse_error& e) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("line {}, column {}: {}", e.source().begin.line,
                                      e.source().begin.column, e.description()),
                          context);
    }
    auto out = parse_document(doc);
    if (!out) return std::unexpected(core::with_context(out.error(), context));
    return out;
}

core::Result<ProfileFile> read_profile(const std::filesystem::path& file) {
    // A FIFO or a device would block the read or feed it without end.
    if (auto ok = core::check_input_file(file, "the profile"); !ok) {
        return std::unexpected(ok.error());
    }
    std::ifstream in(file, std::ios::binary);
    if (!in) {
        return core::fail(ErrorCode::kIo, "cannot open the file", "profile " + file.string());
    }
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) {
        return core::fail(ErrorCode::kIo, "cannot read the file", "profile " + file.string());
    }
    return parse_profile(text.str(), file.string());
}

core::Result<Profiles> load_profiles(std::span<const std::filesystem::path> files) {
    if (files.empty()) {
        return core::fail(ErrorCode::kInvalidInput, "no profile file given");
    }
    std::optional<MachineProfile> machine;
    std::optional<ProcessProfile> process;
    std::string machine_file;
    std::string process_file;
    std::string names;
    for (const auto& file : files) {
        names += names.empty() ? "" : " + ";
        names += file.string();
        auto f = read_profile(file);
        if (!f) return std::unexpected(f.error());
        if (f->machine) {
            if (machine) {
                return core::fail(ErrorCode::kInvalidInput,
                                  fmt::format("[machine] is given in both {} and {}", machine_file,
                                              file.string()));
            }
            machine = std::move(f->machine);
            machine_file = file.string();
        }
        if (f->process) {
            if (process) {
                return core::fail(ErrorCode::kInvalidInput,
                                  fmt::format("[process] is given in both {} and {}", process_file,
                                              file.string()));
            }
            process = std::move(f->process);
            process_file = file.string();
        }
    }
    if (!machine || !process) {
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("no [{}] table in the profiles given", machine ? "process" : "machine"),
            "profiles " + names);
    }
    if (auto ok = check_compatible(*machine, *process); !ok) {
        return std::unexpected(core::with_context(ok.error(), "profiles " + names));
    }
    return Profiles{std::move(*machine), std::move(*process)};
}

std::string_view dialect_name(Dialect dialect) {
    switch (dialect) {
        case Dialect::kGm: return "gm";
        case Dialect::kLinuxCnc: return "linuxcnc";
        case Dialect::kFanuc: return "fanuc";
        case Dialect::kSiemens: return "siemens";
    }
    return "gm";
}

std::optional<Dialect> parse_dialect(std::string_view name) {
    for (const Dialect d : {Dialect::kGm, Dialect::kLinuxCnc, Dialect::kFanuc, Dialect::kSiemens}) {
        if (dialect_name(d) == name) return d;
    }
    return std::nullopt;
}

std::string_view kinematics_name(Kinematics kinematics) {
    for (const auto& k : kKinematicsNames) {
        if (k.kinematics == kinematics) return k.name;
    }
    return "xyz";
}

bool is_table_tilt(Kinematics kinematics) {
    return kinematics == Kinematics::kTableAc || kinematics == Kinematics::kTableBc;
}

std::optional<std::string> motion_word(std::string_view block) {
    // The block as the controller reads its words: upper case, comments out, a placeholder as
    // the number it stands for.
    std::string s;
    for (std::size_t i = 0; i < block.size(); ++i) {
        const char c = block[i];
        if (c == ';') break;
        if (c == '(' || c == '{') {
            const std::size_t close = block.find(c == '(' ? ')' : '}', i);
            if (close == std::string_view::npos) break;
            if (c == '{') s += '0';
            i = close;
            continue;
        }
        s += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    }
    const auto alpha = [](char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0; };
    const auto ident = [&](char c) {
        return alpha(c) || c == '_' || std::isdigit(static_cast<unsigned char>(c)) != 0;
    };
    std::optional<std::string> motion, axis;
    bool macro_call = false;
    for (std::size_t i = 0; i < s.size();) {
        const char c = s[i];
        if (c == '$') {  // a Sinumerik system variable: $A_OUTA[1]
            ++i;
            while (i < s.size() && ident(s[i])) ++i;
            continue;
        }
        if (c == '<') {  // a LinuxCNC named parameter or subroutine: #<name>, o<name>
            const std::size_t close = s.find('>', i);
            i = close == std::string::npos ? s.size() : close + 1;
            continue;
        }
        if (!alpha(c)) {
            ++i;
            continue;
        }
        std::size_t j = i;
        while (j < s.size() && alpha(s[j])) ++j;
        if (j - i > 1) {  // a keyword (TRAORI, CALL, GOTO) or a name
            while (j < s.size() && ident(s[j])) ++j;
            i = j;
            continue;
        }
        while (j < s.size() && s[j] == ' ') ++j;
        const bool value = j < s.size() && (std::isdigit(static_cast<unsigned char>(s[j])) != 0 ||
                                            s[j] == '+' || s[j] == '-' || s[j] == '.' ||
                                            s[j] == '=' || s[j] == '[' || s[j] == '#');
        if (!value) {
            i = j;
            continue;
        }
        if (c == 'G') {
            std::size_t k = j;
            while (k < s.size() &&
                   (std::isdigit(static_cast<unsigned char>(s[k])) != 0 || s[k] == '.')) {
                ++k;
            }
            const std::string number = s.substr(j, k - j);
            const double g = std::atof(number.c_str());
            // A G number past any real code (or not finite) moves nothing known; the cast
            // below is only defined inside int's range.
            const int whole =
                std::isfinite(g) && g >= 0.0 && g < 1000.0 ? static_cast<int>(std::floor(g)) : -1;
            const bool moves = k == j || whole == 0 || whole == 1 || whole == 2 || whole == 3 ||
                               whole == 5 || whole == 28 || whole == 30 || whole == 33 ||
                               whole == 38 || whole == 73 || whole == 74 || whole == 76 ||
                               (whole >= 81 && whole <= 89);
            if (moves && !motion) motion = "G" + (k == j ? s.substr(j, 1) : number);
            if (whole == 65 || whole == 66) macro_call = true;
            i = k;
            continue;
        }
        if (std::string_view("XYZABCUVWIJK").find(c) != std::string_view::npos && !axis) {
            axis = std::string(1, c) + " word";
        }
        i = j;
    }
    if (motion) return motion;
    if (axis && !macro_call) return axis;
    return std::nullopt;
}

std::string expand_block(std::string_view block, double power_w, double powder_g_min,
                         double power_max_w) {
    std::string out;
    out.reserve(block.size() + 8);
    for (std::size_t i = 0; i < block.size(); ++i) {
        if (block[i] != '{') {
            out += block[i];
            continue;
        }
        const std::size_t close = block.find('}', i);
        if (close == std::string_view::npos) {
            out += block.substr(i);
            break;
        }
        const std::string_view name = block.substr(i + 1, close - i - 1);
        if (name == "power") {
            out += format_value(power_w);
        } else if (name == "power_pct") {
            out += format_value(power_max_w > 0.0 ? 100.0 * power_w / power_max_w : 0.0);
        } else if (name == "powder") {
            out += format_value(powder_g_min);
        } else {
            out += block.substr(i, close - i + 1);
        }
        i = close;
    }
    return out;
}

}  // namespace maxslice::machine
