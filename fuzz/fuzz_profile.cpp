// libFuzzer harness: the machine and process profile parser (machine::parse_profile: TOML
// through toml++, then every key read and validated).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "maxslice/machine/profile.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const auto parsed = maxslice::machine::parse_profile(text, "fuzz");
    if (!parsed && (parsed.error().code != maxslice::core::ErrorCode::kInvalidInput ||
                    parsed.error().message.empty())) {
        std::fprintf(stderr, "maxslice fuzz: refusal is not kInvalidInput with a message\n");
        std::abort();
    }
    return 0;
}
