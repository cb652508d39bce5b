#include "maxslice/verify/replay.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <new>
#include <optional>
#include <string>
#include <utility>

#include "maxslice/core/files.hpp"

namespace maxslice::verify {
namespace {

using core::ErrorCode;
using core::Vec3d;

/// A power written with 2 decimals is "on" when it exceeds the off power by more than this.
constexpr double kPowerOnMarginW = 1e-6;
/// Powers and powder feeds are written with 2 decimals, feeds with 1: a value within half the
/// last digit of a range's end lies in the range.
constexpr double kTwoDecimalsSlack = 0.005;
constexpr double kOneDecimalSlack = 0.05;
/// The longest piece of a program line quoted in a message.
constexpr std::size_t kQuotedChars = 80;

// Program bytes for a message: control and non-ASCII bytes escaped, long text cut.
std::string quote_block(std::string_view s) {
    return core::printable(s, kQuotedChars);
}

core::Error line_error(int line, ErrorCode code, std::string message) {
    return core::Error{code, std::move(message), fmt::format("line {}", line)};
}

char upper(char c) {
    return static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
}
bool is_space(char c) {
    return c == ' ' || c == '\t';
}
bool is_alpha(char c) {
    return std::isalpha(static_cast<unsigned char>(c)) != 0;
}

// Upper case, runs of blanks as one space, no blanks at either end; into `out` (a buffer
// reused from line to line).
void normalize_into(std::string_view s, std::string& out) {
    out.clear();
    for (char c : s) {
        if (is_space(c)) {
            if (!out.empty() && out.back() != ' ') out += ' ';
        } else {
            out += upper(c);
        }
    }
    while (!out.empty() && out.back() == ' ') out.pop_back();
}
std::string normalize(std::string_view s) {
    std::string out;
    normalize_into(s, out);
    return out;
}

// A number as RS-274 writes it: optional sign, digits, optional point and digits.
std::optional<double> parse_number(std::string_view s, std::size_t& pos) {
    std::size_t p = pos;
    bool negative = false;
    if (p < s.size() && (s[p] == '+' || s[p] == '-')) {
        negative = s[p] == '-';
        ++p;
    }
    const std::size_t start = p;
    while (p < s.size() && (std::isdigit(static_cast<unsigned char>(s[p])) != 0 || s[p] == '.')) {
        ++p;
    }
    if (p == start) return std::nullopt;
    double value = 0.0;
    const auto [end, ec] = std::from_chars(s.data() + start, s.data() + p, value);
    if (ec != std::errc{} || end != s.data() + p || !std::isfinite(value)) return std::nullopt;
    pos = p;
    return negative ? -value : value;
}

enum class Role { kLaserOn, kLaserOff, kPowderOn, kPowderOff, kStart, kEnd };

struct TemplateLine {
    std::string text;  // normalized, placeholders kept in lower case
    Role role = Role::kStart;
    bool literal = true;
};

// Normalizes a template block, keeping `{power}`-style placeholders as written.
std::string normalize_template(std::string_view s) {
    std::string out;
    bool in_placeholder = false;
    for (char c : s) {
        if (c == '{') in_placeholder = true;
        if (in_placeholder) {
            out += c;
            if (c == '}') in_placeholder = false;
        } else if (is_space(c)) {
            if (!out.empty() && out.back() != ' ') out += ' ';
        } else {
            out += upper(c);
        }
    }
    while (!out.empty() && out.back() == ' ') out.pop_back();
    return out;
}

// The values a matched template's placeholders stood for.
struct Captured {
    std::optional<double> power_w;  // {power}, or {power_pct} in W
    bool power_pct = false;         // it was a {power_pct}
    std::optional<double> powder_g_min;
};

// Matches a normalized line against a template; `got` receives the laser power that a {power}
// or {power_pct} placeholder stands for and the powder feed of a {powder}.
bool match_template(const TemplateLine& t, std::string_view line, double power_max_w,
                    Captured& got) {
    std::size_t i = 0, j = 0;
    const std::string_view tt = t.text;
    while (i < tt.size()) {
        if (tt[i] == '{') {
            const std::size_t close = tt.find('}', i);
            const std::string_view name = tt.substr(i + 1, close - i - 1);
            const auto v = parse_number(line, j);
            if (!v) return false;
            if (name == "power") got.power_w = *v;
            if (name == "power_pct") {
                got.power_w = *v * power_max_w / 100.0;
                got.power_pct = true;
            }
            if (name == "powder") got.powder_g_min = *v;
            i = close + 1;
            continue;
        }
        if (j >= line.size() || line[j] != tt[i]) return false;
        ++i;
        ++j;
    }
    return j == line.size();
}

// The G or M codes of one block, in place (a block is read per line of the program). RS-274
// allows one code per modal group, and there are fewer groups than kMax.
template <class T>
struct Codes {
    static constexpr std::size_t kMax = 16;
    std::array<T, kMax> code{};
    std::size_t count = 0;
    [[nodiscard]] bool push(T c) {
        if (count == kMax) return false;
        code[count++] = c;
        return true;
    }
    [[nodiscard]] const T* begin() const { return code.data(); }
    [[nodiscard]] const T* end() const { return code.data() + count; }
};

struct Words {
    std::array<std::optional<double>, 26> value;  // by letter
    Codes<double> g;                              // G codes in the block
    Codes<int> m;                                 // M codes
    bool traori = false;
    bool trafoof = false;

    [[nodiscard]] const std::optional<double>& operator[](char letter) const {
        return value[static_cast<std::size_t>(letter - 'A')];
    }
    [[nodiscard]] bool has_g(double code) const {
        for (double c : g) {
            if (std::abs(c - code) < 1e-9) return true;
        }
        return false;
    }
};

// Room for a block a line (the shortest move block takes more than kLeastBlockBytes): one
// allocation instead of a doubling vector's copies and the fresh pages each one touches (a
// 2-million-move program fills 400 MB of blocks; its verify spent 15 % of its time zeroing
// pages). Only a hint: a text of blank lines gets less, and no room is no error.
constexpr std::size_t kLeastBlockBytes = 16;
void reserve_blocks(std::string_view text, std::vector<ReplayBlock>& blocks) {
    const auto lines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
    try {
        blocks.reserve(std::min(lines, text.size() / kLeastBlockBytes) + 1);
    } catch (const std::bad_alloc&) {
        // grows as it goes
    }
}

class Replayer {
public:
    Replayer(const machine::Profiles& profiles, const machine::MachineKinematics& kin,
             ProgramDialect dialect)
        : profiles_(profiles), kin_(kin), dialect_(dialect) {
        const auto& codes = profiles.machine.codes;
        const std::pair<const machine::CodeTemplate*, Role> all[] = {
            {&codes.laser_on, Role::kLaserOn},    {&codes.laser_off, Role::kLaserOff},
            {&codes.powder_on, Role::kPowderOn},  {&codes.powder_off, Role::kPowderOff},
            {&codes.program_start, Role::kStart}, {&codes.program_end, Role::kEnd}};
        for (const auto& [tmpl, role] : all) {
            for (const std::string& b : tmpl->blocks) {
                TemplateLine t;
                t.text = normalize_template(b);
                t.role = role;
                t.literal = t.text.find('{') == std::string::npos;
                if (!t.text.empty()) templates_.push_back(std::move(t));
            }
        }
        table_ = machine::is_table_tilt(profiles.machine.kinematics);
        tilt_letter_ = profiles.machine.kinematics == machine::Kinematics::kTableBc ? 'B' : 'A';
        if (profiles.machine.table) pivot_ = profiles.machine.table->pivot_mm;
    }

    core::Result<Replay> run(std::string_view text) {
        Replay out;
        out.dialect = dialect_;
        reserve_blocks(text, out.blocks);
        int line_no = 0;
        std::size_t pos = 0;
        while (pos < text.size() && !ended_) {
            std::size_t eol = text.find('\n', pos);
            if (eol == std::string_view::npos) eol = text.size();
            std::string_view line = text.substr(pos, eol - pos);
            pos = eol + 1;
            ++line_no;
            if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
            if (auto ok = line_(line, line_no, out); !ok) {
                // The last line of a text without a final line break was cut off: it is not
                // read, and the program counts as cut (Replay::cut), not as malformed.
                if (pos >= text.size() && text.back() != '\n') break;
                return std::unexpected(ok.error());
            }
        }
        int lines = line_no;
        out.end_code = ended_;
        out.last_line = line_no;
        out.cut = !ended_ && !text.empty() && text.back() != '\n';
        out.laser_on_at_end = laser_on_;
        out.powder_on_at_end = powder_on_;
        out.end_tip_mm = kin_.forward(pose_).tip_mm;
        // Lines after the end code are counted but not read (the controller stops there).
        while (pos < text.size()) {
            std::size_t eol = text.find('\n', pos);
            if (eol == std::string_view::npos) eol = text.size();
            pos = eol + 1;
            ++lines;
        }
        out.line_count = lines;
        return out;
    }

private:
    core::Result<void> line_(std::string_view raw, int line_no, Replay& out) {
        std::string_view block = raw;
        if (dialect_ == ProgramDialect::kGm) {
            std::size_t p = 0;
            while (p < block.size() && is_space(block[p])) ++p;
            if (p == block.size()) return {};
            const auto power = parse_number(block, p);
            if (!power || p >= block.size() || !is_space(block[p])) {
                return std::unexpected(line_error(line_no, ErrorCode::kInvalidInput,
                                                  "gm line must start with the power and powder "
                                                  "columns: '" +
                                                      quote_block(raw) + "'"));
            }
            while (p < block.size() && is_space(block[p])) ++p;
            const auto powder = parse_number(block, p);
            if (!powder || (p < block.size() && !is_space(block[p]))) {
                return std::unexpected(line_error(line_no, ErrorCode::kInvalidInput,
                                                  "gm line must start with the power and powder "
                                                  "columns: '" +
                                                      quote_block(raw) + "'"));
            }
            const bool on = *power > profiles_.process.laser_power_off_w + kPowerOnMarginW;
            check_power(*power, false, on, line_no, out);
            check_powder(*powder, line_no, out);
            set_laser(on, out);
            if (on) note_power(*power, out);
            powder_on_ = *powder > 0.0;
            block = block.substr(p);
        }
        if (auto ok = strip_comments(block, line_no, stripped_); !ok) {
            return std::unexpected(ok.error());
        }
        normalize_into(stripped_, norm_);
        const std::string& norm = norm_;
        if (norm.empty()) return {};
        if (dialect_ == ProgramDialect::kFanuc && norm == "%") return {};
        if (match_codes(norm, line_no, out)) return {};
        auto words = parse_words(norm, line_no);
        if (!words) return std::unexpected(words.error());
        return apply(*words, line_no, raw, out);
    }

    // A laser power read from the program: below 0 or above the machine's maximum, or
    // switching on below its minimum, is out of range.
    void check_power(double w, bool pct, bool on, int line_no, Replay& out) {
        const auto& m = profiles_.machine;
        const double slack =
            pct ? kTwoDecimalsSlack * m.laser_power_max_w / 100.0 : kTwoDecimalsSlack;
        if (w < -slack) {
            out_of_range(line_no, fmt::format("laser power {:.2f} W is below 0", w), out);
        } else if (w > m.laser_power_max_w + slack) {
            out_of_range(line_no,
                         fmt::format("laser power {:.2f} W is above machine.laser_power_max_w = "
                                     "{:.2f}",
                                     w, m.laser_power_max_w),
                         out);
        } else if (on && w < m.laser_power_min_w - slack) {
            out_of_range(line_no,
                         fmt::format("laser power {:.2f} W is below machine.laser_power_min_w = "
                                     "{:.2f}",
                                     w, m.laser_power_min_w),
                         out);
        }
    }

    void check_powder(double g, int line_no, Replay& out) {
        const double max = profiles_.machine.powder_feed_max_g_min;
        if (g < -kTwoDecimalsSlack) {
            out_of_range(line_no, fmt::format("powder feed {:.2f} g/min is below 0", g), out);
        } else if (g > max + kTwoDecimalsSlack) {
            out_of_range(line_no,
                         fmt::format("powder feed {:.2f} g/min is above "
                                     "machine.powder_feed_max_g_min = {:.2f}",
                                     g, max),
                         out);
        }
    }

    // One finding per line: the first out-of-range value of a line counts.
    void out_of_range(int line_no, std::string detail, Replay& out) {
        if (line_no == out_of_range_line_) return;
        out_of_range_line_ = line_no;
        ReplayFault& f = out.out_of_range;
        if (f.count++ == 0) {
            f.line = line_no;
            f.tip_mm = kin_.forward(pose_).tip_mm;
            f.detail = std::move(detail);
        }
    }

    // The block without its comments, into `out` (a buffer reused from line to line).
    core::Result<void> strip_comments(std::string_view s, int line_no, std::string& out) const {
        const bool parens = dialect_ != ProgramDialect::kSiemens;
        const bool semicolon =
            dialect_ == ProgramDialect::kLinuxCnc || dialect_ == ProgramDialect::kSiemens;
        out.clear();
        for (std::size_t i = 0; i < s.size(); ++i) {
            if (semicolon && s[i] == ';') break;
            if (parens && s[i] == '(') {
                const std::size_t close = s.find(')', i);
                if (close == std::string_view::npos) {
                    return std::unexpected(
                        line_error(line_no, ErrorCode::kInvalidInput, "unclosed comment '('"));
                }
                out += ' ';
                i = close;
                continue;
            }
            out += s[i];
        }
        return {};
    }

    // Keeps the distinct powers (a program has one per process), at most kMaxPowers of them
    // and then a NaN, which matches no process.
    static void note_power(double w, Replay& out) {
        constexpr std::size_t kMaxPowers = 16;
        auto& powers = out.laser_powers_w;
        if (std::find(powers.begin(), powers.end(), w) != powers.end()) return;
        if (powers.size() < kMaxPowers) {
            powers.push_back(w);
        } else if (powers.size() == kMaxPowers) {
            powers.push_back(std::numeric_limits<double>::quiet_NaN());
        }
    }

    void set_laser(bool on, Replay& out) {
        if (on && !laser_on_) ++out.laser_on_count;
        laser_on_ = on;
    }

    // A line that is one of the profile's code blocks: sets the laser and powder state, checks
    // the values it sets and returns true.
    bool match_codes(const std::string& norm, int line_no, Replay& out) {
        for (const bool literal : {true, false}) {
            bool matched = false;
            for (const TemplateLine& t : templates_) {
                if (t.literal != literal) continue;
                Captured got;
                if (!match_template(t, norm, profiles_.machine.laser_power_max_w, got)) continue;
                matched = true;
                const bool on = !got.power_w || *got.power_w > profiles_.process.laser_power_off_w +
                                                                   kPowerOnMarginW;
                if (got.power_w) {
                    check_power(*got.power_w, got.power_pct, t.role == Role::kLaserOn && on,
                                line_no, out);
                }
                if (got.powder_g_min) check_powder(*got.powder_g_min, line_no, out);
                if (dialect_ == ProgramDialect::kGm) continue;  // gm: the columns rule
                switch (t.role) {
                    case Role::kLaserOn:
                        set_laser(on, out);
                        if (on && got.power_w) note_power(*got.power_w, out);
                        break;
                    case Role::kLaserOff: set_laser(false, out); break;
                    case Role::kPowderOn:
                        powder_on_ = !got.powder_g_min || *got.powder_g_min > 0.0;
                        break;
                    case Role::kPowderOff: powder_on_ = false; break;
                    case Role::kStart:
                    case Role::kEnd: break;
                }
            }
            if (matched) return true;
        }
        return false;
    }

    core::Result<Words> parse_words(const std::string& s, int line_no) const {
        Words w;
        std::size_t p = 0;
        while (p < s.size()) {
            if (s[p] == ' ') {
                ++p;
                continue;
            }
            if (!is_alpha(s[p])) {
                return std::unexpected(line_error(
                    line_no, ErrorCode::kInvalidInput,
                    fmt::format("unexpected '{}' in block '{}'",
                                quote_block(std::string_view(s).substr(p, 1)), quote_block(s))));
            }
            std::size_t q = p;
            while (q < s.size() && is_alpha(s[q])) ++q;
            if (q - p > 1) {
                const std::string_view kw = std::string_view(s).substr(p, q - p);
                if (dialect_ == ProgramDialect::kSiemens && kw == "TRAORI") {
                    w.traori = true;
                } else if (dialect_ == ProgramDialect::kSiemens && kw == "TRAFOOF") {
                    w.trafoof = true;
                } else {
                    return std::unexpected(line_error(
                        line_no, ErrorCode::kInvalidInput,
                        fmt::format("unknown word '{}' for dialect {} in block '{}'",
                                    quote_block(kw), dialect_name(dialect_), quote_block(s))));
                }
                p = q;
                continue;
            }
            const char letter = s[p];
            ++p;
            while (p < s.size() && s[p] == ' ') ++p;
            const auto v = parse_number(s, p);
            if (!v || (p < s.size() && !is_alpha(s[p]) && s[p] != ' ')) {
                return std::unexpected(
                    line_error(line_no, ErrorCode::kInvalidInput,
                               fmt::format("malformed number after '{}' in block '{}'", letter,
                                           quote_block(s))));
            }
            const auto too_many = [&] {
                return std::unexpected(
                    line_error(line_no, ErrorCode::kInvalidInput,
                               fmt::format("more than {} {} codes in block '{}'", Codes<int>::kMax,
                                           letter, quote_block(s))));
            };
            if (letter == 'G') {
                if (!w.g.push(*v)) return too_many();
            } else if (letter == 'M') {
                // A whole number in int range (M2.2e127 was undefined behaviour; fuzz_program).
                if (*v != std::floor(*v) || !(std::abs(*v) <= 1e9)) {
                    return std::unexpected(
                        line_error(line_no, ErrorCode::kInvalidInput,
                                   fmt::format("malformed M code in '{}'", quote_block(s))));
                }
                if (!w.m.push(static_cast<int>(*v))) return too_many();
            } else {
                auto& slot = w.value[static_cast<std::size_t>(letter - 'A')];
                if (slot) {
                    return std::unexpected(line_error(
                        line_no, ErrorCode::kInvalidInput,
                        fmt::format("word {} twice in block '{}'", letter, quote_block(s))));
                }
                slot = *v;
            }
        }
        return w;
    }

    core::Result<void> apply(const Words& w, int line_no, std::string_view raw, Replay& out) {
        const auto fail = [&](ErrorCode code, std::string msg) -> core::Result<void> {
            return std::unexpected(
                line_error(line_no, code, msg + " in '" + quote_block(normalize(raw)) + "'"));
        };
        const bool fanuc = dialect_ == ProgramDialect::kFanuc;
        const bool siemens = dialect_ == ProgramDialect::kSiemens;
        bool dwell = false;
        std::optional<bool> motion;  // rapid?
        for (const double g : w.g) {
            const auto is = [&](double c) { return std::abs(g - c) < 1e-9; };
            if (is(0)) {
                motion = true;
            } else if (is(1)) {
                motion = false;
            } else if (is(4)) {
                dwell = true;
            } else if (is(17) || is(90) || is(94)) {
                // plane XY, absolute, feed per minute: the only modes a program may use
            } else if (is(21) && !siemens) {
            } else if (is(71) && siemens) {
            } else if ((is(20) && !siemens) || (is(70) && siemens)) {
                return fail(ErrorCode::kUnsupported, "inch units are not supported");
            } else if (is(91)) {
                return fail(ErrorCode::kUnsupported,
                            "incremental distances (G91) are not supported");
            } else if (is(93) || is(95)) {
                return fail(ErrorCode::kUnsupported, "only feed per minute (G94) is supported");
            } else if (fanuc && is(43.4)) {
                if (!w['H']) return fail(ErrorCode::kInvalidInput, "G43.4 without H");
                tcp_ = true;
            } else if (fanuc && is(43)) {
                // Tool length compensation alone: X Y Z stay the tool tip in joint space.
                if (!w['H']) return fail(ErrorCode::kInvalidInput, "G43 without H");
            } else if (fanuc && is(49)) {
                tcp_ = false;
            } else {
                return fail(ErrorCode::kInvalidInput,
                            fmt::format("unsupported G code G{} for dialect {}", g,
                                        dialect_name(dialect_)));
            }
        }
        if (w.traori) tcp_ = true;
        if (w.trafoof) tcp_ = false;
        for (const int m : w.m) {
            if (m == 2 || m == 30) {
                ended_ = true;
            } else {
                return fail(ErrorCode::kInvalidInput,
                            fmt::format("unknown code M{} (not one of the profile's "
                                        "[machine.codes] blocks, each of which stands alone on "
                                        "its line)",
                                        m));
            }
        }
        // Allowed letters.
        for (char c = 'A'; c <= 'Z'; ++c) {
            if (!w[c]) continue;
            bool ok = false;
            switch (c) {
                case 'X':
                case 'Y':
                case 'Z':
                case 'F':
                case 'N': ok = true; break;
                case 'A': ok = profiles_.machine.kinematics == machine::Kinematics::kTableAc; break;
                case 'B': ok = profiles_.machine.kinematics == machine::Kinematics::kTableBc; break;
                case 'C': ok = table_; break;
                case 'P': ok = dwell && !fanuc && !siemens; break;
                case 'H': ok = fanuc && (w.has_g(43.4) || w.has_g(43)); break;
                case 'O': ok = fanuc; break;
                default: ok = false;
            }
            if (!ok) {
                return fail(ErrorCode::kInvalidInput,
                            fmt::format("word {} is not valid here (machine kinematics {}, "
                                        "dialect {})",
                                        c, machine::kinematics_name(profiles_.machine.kinematics),
                                        dialect_name(dialect_)));
            }
        }
        if (dwell) {
            double seconds = 0.0;
            std::optional<double> v;
            switch (dialect_) {
                case ProgramDialect::kGm: v = w['P'] ? std::optional(*w['P'] / 1000.0) : v; break;
                case ProgramDialect::kLinuxCnc: v = w['P']; break;
                case ProgramDialect::kFanuc: v = w['X']; break;
                case ProgramDialect::kSiemens: v = w['F']; break;
            }
            if (!v || *v < 0.0) return fail(ErrorCode::kInvalidInput, "dwell without a valid time");
            seconds = *v;
            const bool others = (w['X'] && !fanuc) || w['Y'] || w['Z'] || w['A'] || w['B'] ||
                                w['C'] || (w['F'] && !siemens) || motion;
            if (others) return fail(ErrorCode::kInvalidInput, "a dwell block must not move");
            ReplayBlock b;
            b.kind = ReplayBlock::Kind::kDwell;
            b.line = line_no;
            b.from = b.pose = pose_;
            const machine::ToolPose tp = kin_.forward(pose_);
            b.tip_mm = tp.tip_mm;
            b.direction = tp.direction;
            b.laser_on = laser_on_;
            b.dwell_s = seconds;
            b.pose_known = pose_known();
            b.tcp = tcp_;
            out.blocks.push_back(b);
            return {};
        }
        if (w['F']) {
            if (*w['F'] <= 0.0) return fail(ErrorCode::kInvalidInput, "feed must be positive");
            feed_ = *w['F'];
        }
        if (motion) motion_ = motion;
        const bool axes = w['X'] || w['Y'] || w['Z'] || w[tilt_letter_] || (table_ && w['C']);
        if (!axes) return {};
        if (!motion_) return fail(ErrorCode::kInvalidInput, "axis words before any G0 / G1");
        if (!*motion_ && feed_ <= 0.0) return fail(ErrorCode::kInvalidInput, "G1 without a feed");
        if (!*motion_) {
            const auto& m = profiles_.machine;
            if (feed_ < m.feed_min_mm_min - kOneDecimalSlack ||
                feed_ > m.feed_max_mm_min + kOneDecimalSlack) {
                out_of_range(line_no,
                             fmt::format("G1 feed F{:.1f} outside [machine.feed_min_mm_min, "
                                         "feed_max_mm_min] = [{:.1f}, {:.1f}]",
                                         feed_, m.feed_min_mm_min, m.feed_max_mm_min),
                             out);
            }
        }

        ReplayBlock b;
        b.line = line_no;
        b.rapid = *motion_;
        b.tcp = tcp_;
        b.from = pose_;
        machine::MachinePose next = pose_;
        if (table_) {
            if (w[tilt_letter_]) next.a_or_b_deg = *w[tilt_letter_];
            if (w['C']) next.c_deg = *w['C'];
        }
        if (tcp_) {
            // X Y Z are pivot + the part-frame tip; the machine's linear axes follow from the
            // tip and the new rotary values.
            Vec3d programmed = kin_.forward(pose_).tip_mm + pivot_;
            if (w['X']) programmed.x = *w['X'];
            if (w['Y']) programmed.y = *w['Y'];
            if (w['Z']) programmed.z = *w['Z'];
            const Vec3d m = linear_axes_for_tip(kin_, programmed - pivot_, next);
            next.x = m.x;
            next.y = m.y;
            next.z = m.z;
        } else {
            if (w['X']) next.x = *w['X'];
            if (w['Y']) next.y = *w['Y'];
            if (w['Z']) next.z = *w['Z'];
        }
        known_[0] = known_[0] || w['X'].has_value() || tcp_;
        known_[1] = known_[1] || w['Y'].has_value() || tcp_;
        known_[2] = known_[2] || w['Z'].has_value() || tcp_;
        known_[3] = known_[3] || !table_ || w[tilt_letter_].has_value();
        known_[4] = known_[4] || !table_ || w['C'].has_value();
        pose_ = next;
        b.pose = next;
        b.pose_known = pose_known();
        const machine::ToolPose tp = kin_.forward(next);
        b.tip_mm = tp.tip_mm;
        b.direction = tp.direction;
        b.feed_mm_min = b.rapid ? profiles_.machine.feed_max_mm_min : feed_;
        b.laser_on = laser_on_;
        out.blocks.push_back(b);
        return {};
    }

    [[nodiscard]] bool pose_known() const {
        return known_[0] && known_[1] && known_[2] && known_[3] && known_[4];
    }

    const machine::Profiles& profiles_;
    const machine::MachineKinematics& kin_;
    ProgramDialect dialect_;
    std::vector<TemplateLine> templates_;
    bool table_ = false;
    char tilt_letter_ = 'A';
    Vec3d pivot_{};
    machine::MachinePose pose_{};
    std::array<bool, 5> known_{};
    std::optional<bool> motion_;
    double feed_ = 0.0;
    bool laser_on_ = false;
    bool powder_on_ = false;
    int out_of_range_line_ = 0;  // the line last counted in Replay::out_of_range
    bool tcp_ = false;
    bool ended_ = false;
    std::string stripped_, norm_;  // the line being read, reused
};

}  // namespace

std::string_view dialect_name(ProgramDialect dialect) {
    switch (dialect) {
        case ProgramDialect::kGm: return "gm";
        case ProgramDialect::kLinuxCnc: return "linuxcnc";
        case ProgramDialect::kFanuc: return "fanuc";
        case ProgramDialect::kSiemens: return "siemens";
    }
    return "unknown";
}

core::Result<ProgramDialect> parse_dialect(std::string_view name) {
    for (const ProgramDialect d : {ProgramDialect::kGm, ProgramDialect::kLinuxCnc,
                                   ProgramDialect::kFanuc, ProgramDialect::kSiemens}) {
        if (dialect_name(d) == name) return d;
    }
    return core::fail(
        ErrorCode::kInvalidInput,
        fmt::format("unknown dialect '{}' (use gm, linuxcnc, fanuc or siemens)", name));
}

core::Result<ProgramDialect> dialect_of(const machine::MachineProfile& machine) {
    return parse_dialect(machine::dialect_name(machine.dialect));
}

core::Vec3d linear_axes_for_tip(const machine::MachineKinematics& kinematics,
                                const core::Vec3d& tip, machine::MachinePose pose) {
    pose.x = pose.y = pose.z = 0.0;
    const core::Vec3d t0 = kinematics.forward(pose).tip_mm;
    std::array<core::Vec3d, 3> col;
    for (int i = 0; i < 3; ++i) {
        machine::MachinePose e = pose;
        (i == 0 ? e.x : (i == 1 ? e.y : e.z)) = 1.0;
        col[static_cast<std::size_t>(i)] = kinematics.forward(e).tip_mm - t0;
    }
    const core::Vec3d d = tip - t0;
    return {core::dot(col[0], d), core::dot(col[1], d), core::dot(col[2], d)};
}

core::Result<Replay> replay_program(std::string_view program_text,
                                    const machine::Profiles& profiles, ProgramDialect dialect) {
    auto kin = machine::MachineKinematics::create(profiles.machine);
    if (!kin) return std::unexpected(kin.error());
    Replayer r(profiles, *kin, dialect);
    return r.run(program_text);
}

int process_of(const Replay& replay, const machine::Profiles& profiles) {
    if (replay.laser_powers_w.empty()) return -1;
    const auto matches = [&](const machine::ProcessProfile& p) {
        constexpr double kToleranceW = 0.5;
        return std::all_of(replay.laser_powers_w.begin(), replay.laser_powers_w.end(),
                           [&](double w) { return std::abs(w - p.laser_power_w) <= kToleranceW; });
    };
    if (matches(profiles.process)) return 0;
    const auto& finer = profiles.process.finer;
    for (std::size_t i = 0; i < finer.size(); ++i) {
        if (matches(finer[i])) return static_cast<int>(i) + 1;
    }
    return -1;
}

}  // namespace maxslice::verify
