// Files maxslice ships beside its program (the STEP/IGES reader module, the part reader
// program), found where a build or an installation puts them.
#include <fmt/format.h>

#include <cstdlib>
#include <string>
#include <system_error>
#include <vector>

#include "readers.hpp"

namespace maxslice::io::detail {

core::Result<std::filesystem::path> find_companion(std::string_view what, const char* env,
                                                   std::string_view name, const char* build_path) {
    std::vector<std::filesystem::path> candidates;
    const char* chosen = std::getenv(env);
    if (chosen != nullptr && *chosen != '\0') {
        candidates.emplace_back(chosen);  // an explicit choice: no silent fallback
    } else {
        std::error_code ec;
        const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
        if (!ec) {
            const std::filesystem::path bin = self.parent_path();
            candidates.push_back(bin / name);
#ifdef MAXSLICE_INSTALL_LIBDIR
            // Installed: <prefix>/bin/maxslice and <prefix>/<libdir>/maxslice/ (cmake --install).
            candidates.push_back(bin.parent_path() / MAXSLICE_INSTALL_LIBDIR / "maxslice" / name);
#endif
        }
        if (build_path != nullptr) candidates.emplace_back(build_path);
    }
    std::string tried;
    for (const std::filesystem::path& candidate : candidates) {
        std::error_code ec;
        if (std::filesystem::is_regular_file(candidate, ec)) return candidate;
        if (!tried.empty()) tried += ", ";
        tried += candidate.string();
    }
    return core::fail(core::ErrorCode::kUnsupported,
                      fmt::format("{} {} is not installed (looked for {}): rebuild maxslice, or "
                                  "set {} to its path",
                                  what, name, tried, env));
}

}  // namespace maxslice::io::detail
