#include "maxslice/core/units.hpp"

#include <algorithm>
#include <cctype>
#include <string>

namespace maxslice::core {

std::optional<LengthUnit> parse_unit(std::string_view text) {
    std::string t(text);
    std::transform(t.begin(), t.end(), t.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (t == "mm" || t == "millimeter" || t == "millimetre") return LengthUnit::kMillimetre;
    if (t == "in" || t == "inch" || t == "inches") return LengthUnit::kInch;
    if (t == "m" || t == "meter" || t == "metre") return LengthUnit::kMetre;
    if (t == "cm" || t == "centimeter" || t == "centimetre") return LengthUnit::kCentimetre;
    if (t == "um" || t == "micron" || t == "micrometer" || t == "micrometre") {
        return LengthUnit::kMicron;
    }
    if (t == "ft" || t == "foot" || t == "feet") return LengthUnit::kFoot;
    return std::nullopt;
}

}  // namespace maxslice::core
