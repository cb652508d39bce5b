// libFuzzer harness: the verifier's program parser (verify::replay_program), which reads the
// programs `maxslice verify` is given. The first byte picks one of the bundled profiles and
// with it the dialect (gm, linuxcnc, fanuc, siemens) and the [machine.codes] templates.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string_view>
#include <vector>

#include "maxslice/core/vec3.hpp"
#include "maxslice/machine/profile.hpp"
#include "maxslice/verify/replay.hpp"

namespace {

struct Setup {
    maxslice::machine::Profiles profiles;
    maxslice::verify::ProgramDialect dialect;
};

std::vector<Setup> load_setups() {
    std::vector<Setup> setups;
    for (const char* name : {"reference_lmd.toml", "linuxcnc_5axis_ac.toml", "fanuc_5axis_ac.toml",
                             "siemens_5axis_bc.toml"}) {
        const std::filesystem::path file = std::filesystem::path(MAXSLICE_PROFILE_DIR) / name;
        auto profiles = maxslice::machine::load_profiles({&file, 1});
        if (!profiles) {
            std::fprintf(stderr, "fuzz_program: %s: %s\n", file.c_str(),
                         profiles.error().message.c_str());
            std::abort();
        }
        auto dialect = maxslice::verify::dialect_of(profiles->machine);
        if (!dialect) std::abort();
        setups.push_back({std::move(*profiles), *dialect});
    }
    return setups;
}

void check(bool ok, const char* what) {
    if (!ok) {
        std::fprintf(stderr, "maxslice fuzz: invariant broken: %s\n", what);
        std::abort();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::vector<Setup> setups = load_setups();
    if (size == 0) return 0;
    const Setup& setup = setups[data[0] % setups.size()];
    const std::string_view text(reinterpret_cast<const char*>(data) + 1, size - 1);
    const auto replay = maxslice::verify::replay_program(text, setup.profiles, setup.dialect);
    if (!replay) {
        const auto code = replay.error().code;
        check(code == maxslice::core::ErrorCode::kInvalidInput ||
                  code == maxslice::core::ErrorCode::kUnsupported,
              "refusal code is kInvalidInput or kUnsupported");
        check(!replay.error().message.empty(), "refusal has a message");
        return 0;
    }
    for (const auto& block : replay->blocks) {
        check(block.line >= 1 && block.line <= replay->line_count, "block line in the text");
    }
    return 0;
}
