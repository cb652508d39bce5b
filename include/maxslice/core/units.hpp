#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <string_view>

namespace maxslice::core {

/// 2D geometry is stored in integer micrometres; 3D in double millimetres. These are the
/// only conversions between the two.
inline constexpr double kMicronsPerMm = 1000.0;

/// Millimetres to integer micrometres, rounded to nearest (halves away from zero, as
/// std::llround, but inline: this runs for every slice point). Callers keep |mm| < 1e6.
[[nodiscard]] constexpr std::int64_t mm_to_um(double mm) {
    const double um = mm * kMicronsPerMm;
    return static_cast<std::int64_t>(um >= 0.0 ? um + 0.5 : um - 0.5);
}
/// Integer micrometres to millimetres.
[[nodiscard]] constexpr double um_to_mm(std::int64_t um) {
    return static_cast<double>(um) / kMicronsPerMm;
}
/// Square micrometres (as double) to square millimetres.
[[nodiscard]] constexpr double um2_to_mm2(double um2) {
    return um2 / (kMicronsPerMm * kMicronsPerMm);
}

/// Length units a part file may be written in.
enum class LengthUnit { kMillimetre, kInch, kMetre, kCentimetre, kMicron, kFoot };

/// Millimetres per one unit.
[[nodiscard]] constexpr double mm_per_unit(LengthUnit unit) {
    switch (unit) {
        case LengthUnit::kMillimetre: return 1.0;
        case LengthUnit::kInch: return 25.4;
        case LengthUnit::kMetre: return 1000.0;
        case LengthUnit::kCentimetre: return 10.0;
        case LengthUnit::kMicron: return 0.001;
        case LengthUnit::kFoot: return 304.8;
    }
    return 1.0;
}

/// Short name as used on the command line and in reports ("mm", "in", "m", ...).
[[nodiscard]] constexpr std::string_view unit_name(LengthUnit unit) {
    switch (unit) {
        case LengthUnit::kMillimetre: return "mm";
        case LengthUnit::kInch: return "in";
        case LengthUnit::kMetre: return "m";
        case LengthUnit::kCentimetre: return "cm";
        case LengthUnit::kMicron: return "um";
        case LengthUnit::kFoot: return "ft";
    }
    return "mm";
}

/// Parses "mm", "in"/"inch", "m", "cm", "um"/"micron", "ft"/"foot"; nullopt otherwise.
[[nodiscard]] std::optional<LengthUnit> parse_unit(std::string_view text);

}  // namespace maxslice::core
