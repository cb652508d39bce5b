#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "readers.hpp"

namespace maxslice::io::detail {
namespace {

// from_chars reports result_out_of_range both for overflow and for underflow below the
// smallest subnormal; strtod (on a terminated copy) tells the two apart. Underflow reads as
// zero, which is what the writer meant; overflow is out of range.
template <class Real>
NumberRead parse_out_of_range(std::string_view token, Real& value) {
    const std::string copy(token);
    char* end = nullptr;
    const double d = std::strtod(copy.c_str(), &end);
    if (end != copy.c_str() + copy.size()) return NumberRead::kNotANumber;
    if (std::isinf(d) || std::fabs(d) > static_cast<double>(std::numeric_limits<Real>::max())) {
        return NumberRead::kOutOfRange;
    }
    value = static_cast<Real>(d);
    return NumberRead::kOk;
}

template <class Real>
NumberRead parse_real(std::string_view token, Real& value) {
    if (token.size() > 1 && token.front() == '+' && token[1] != '-' && token[1] != '+') {
        token.remove_prefix(1);
    }
    if (token.empty()) return NumberRead::kNotANumber;
    const char* first = token.data();
    const char* last = first + token.size();
    const auto [ptr, ec] = std::from_chars(first, last, value, std::chars_format::general);
    if (ptr != last) return NumberRead::kNotANumber;
    if (ec == std::errc::result_out_of_range) return parse_out_of_range(token, value);
    return ec == std::errc{} ? NumberRead::kOk : NumberRead::kNotANumber;
}

void append_utf8(std::string& out, char32_t cp) {
    if (cp < 0x80) {
        out.push_back(static_cast<char>(cp));
    } else if (cp < 0x800) {
        out.push_back(static_cast<char>(0xC0 | (cp >> 6)));
        out.push_back(static_cast<char>(0x80 | (cp & 0x3F)));
    } else if (cp < 0x10000) {
        out.push_back(static_cast<char>(0xE0 | (cp >> 12)));
        out.push_back(static_cast<char>(0x80 | ((cp >> 6) & 0x3F)));
        out.push_back(static_cast<char>(0x80 | (cp & 0x3F)));
    } else {
        out.push_back(static_cast<char>(0xF0 | (cp >> 18)));
        out.push_back(static_cast<char>(0x80 | ((cp >> 12) & 0x3F)));
        out.push_back(static_cast<char>(0x80 | ((cp >> 6) & 0x3F)));
        out.push_back(static_cast<char>(0x80 | (cp & 0x3F)));
    }
}

}  // namespace

std::string shown(std::string_view token) {
    std::string out = "'";
    for (std::size_t i = 0; i < token.size() && i < 40; ++i) {
        const auto c = static_cast<unsigned char>(token[i]);
        out += (c >= 0x20 && c < 0x7F) ? std::string(1, static_cast<char>(c))
                                       : fmt::format("\\x{:02X}", c);
    }
    return out + (token.size() > 40 ? "...'" : "'");
}

std::string count_of(std::size_t n, std::string_view singular, std::string_view plural_form) {
    std::string out = std::to_string(n);
    out.push_back(' ');
    if (n == 1) {
        out.append(singular);
    } else if (plural_form.empty()) {
        out.append(singular);
        out.push_back('s');
    } else {
        out.append(plural_form);
    }
    return out;
}

NumberRead parse_number(std::string_view token, double& value) {
    return parse_real(token, value);
}
NumberRead parse_number(std::string_view token, float& value) {
    return parse_real(token, value);
}

std::string number_problem(std::string_view what, std::string_view token, NumberRead why,
                           bool single_precision) {
    if (why != NumberRead::kOutOfRange)
        return fmt::format("{} {} is not a number", what, shown(token));
    return fmt::format(
        "{} {} is out of range: its magnitude is above {:.6g}, the largest {} number", what,
        shown(token),
        single_precision ? static_cast<double>(std::numeric_limits<float>::max())
                         : std::numeric_limits<double>::max(),
        single_precision ? "single-precision (32-bit)" : "double-precision (64-bit)");
}

std::optional<std::string> utf16_to_utf8(std::string_view bytes) {
    if (bytes.size() < 2) return std::nullopt;
    const auto b0 = static_cast<unsigned char>(bytes[0]);
    const auto b1 = static_cast<unsigned char>(bytes[1]);
    bool big_endian = false;
    if (b0 == 0xFE && b1 == 0xFF) {
        big_endian = true;
    } else if (!(b0 == 0xFF && b1 == 0xFE)) {
        return std::nullopt;
    }
    auto unit_at = [&](std::size_t i) -> char32_t {
        const auto hi = static_cast<unsigned char>(bytes[big_endian ? i : i + 1]);
        const auto lo = static_cast<unsigned char>(bytes[big_endian ? i + 1 : i]);
        return static_cast<char32_t>((hi << 8) | lo);
    };
    std::string out;
    out.reserve(bytes.size() / 2);
    // A trailing odd byte cannot be a code unit and is dropped.
    const std::size_t end = bytes.size() & ~std::size_t{1};
    for (std::size_t i = 2; i < end; i += 2) {
        char32_t cp = unit_at(i);
        if (cp >= 0xD800 && cp < 0xDC00 && i + 2 < end) {
            const char32_t low = unit_at(i + 2);
            if (low >= 0xDC00 && low < 0xE000) {
                cp = 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
                i += 2;
            } else {
                cp = 0xFFFD;
            }
        } else if (cp >= 0xD800 && cp < 0xE000) {
            cp = 0xFFFD;  // a lone surrogate
        }
        append_utf8(out, cp);
    }
    return out;
}

}  // namespace maxslice::io::detail

namespace maxslice::io {

std::string_view format_name(Format format) {
    switch (format) {
        case Format::kStlBinary: return "stl-binary";
        case Format::kStlAscii: return "stl-ascii";
        case Format::kObj: return "obj";
        case Format::kPly: return "ply";
        case Format::kOff: return "off";
        case Format::k3mf: return "3mf";
        case Format::kStep: return "step";
        case Format::kIges: return "iges";
    }
    return "unknown";
}

}  // namespace maxslice::io
