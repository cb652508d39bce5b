// STEP and IGES files are read by occt_reader.cpp, built as a module of its own
// (libmaxslice_cad.so) so that Open CASCADE's libraries are loaded only when such a file is
// read: they resolve about 90,000 symbols when loaded (they are linked with BIND_NOW),
// ~30 ms that every run of maxslice, of any command on any format, paid while they were
// linked to the program. The module is loaded in the child process the file is read in
// (run_isolated), so the parent never maps Open CASCADE at all.
//
// Where the module is looked for, in order: $MAXSLICE_CAD_PLUGIN (a path to the file), the
// directory of the running program, lib/maxslice/ beside that directory (an installed
// maxslice: apps/maxslice/CMakeLists.txt), and the build tree it was built in.
#include <dlfcn.h>

#include <fmt/format.h>

#include <cstdlib>
#include <string>
#include <system_error>
#include <vector>

#include "readers.hpp"

namespace maxslice::io::detail {
namespace {

constexpr const char* kModuleName = "libmaxslice_cad.so";
constexpr const char* kEntryPoint = "maxslice_read_cad_v1";

using ReadCad = void (*)(const std::filesystem::path*, Format, const ImportOptions*,
                         core::Result<RawImport>*);

std::vector<std::filesystem::path> module_candidates() {
    std::vector<std::filesystem::path> out;
    if (const char* env = std::getenv("MAXSLICE_CAD_PLUGIN"); env != nullptr && *env != '\0') {
        out.emplace_back(env);
        return out;  // an explicit choice: no silent fallback to another build
    }
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const std::filesystem::path bin = self.parent_path();
        out.push_back(bin / kModuleName);
#ifdef MAXSLICE_CAD_PLUGIN_INSTALL_DIR
        // Installed: <prefix>/bin/maxslice and <prefix>/<libdir>/maxslice/ (cmake --install).
        out.push_back(bin.parent_path() / MAXSLICE_CAD_PLUGIN_INSTALL_DIR / kModuleName);
#endif
    }
#ifdef MAXSLICE_CAD_PLUGIN_BUILD_PATH
    out.emplace_back(MAXSLICE_CAD_PLUGIN_BUILD_PATH);
#endif
    return out;
}

core::Result<ReadCad> load_module() {
    std::string tried;
    for (const std::filesystem::path& candidate : module_candidates()) {
        if (!tried.empty()) tried += ", ";
        tried += candidate.string();
        std::error_code ec;
        if (!std::filesystem::is_regular_file(candidate, ec)) continue;
        void* handle = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (handle == nullptr) {
            const char* why = dlerror();
            return core::fail(core::ErrorCode::kUnsupported,
                              fmt::format("cannot load the STEP/IGES reader {}: {}",
                                          candidate.string(), why != nullptr ? why : "?"));
        }
        // Never closed: the child that loaded it ends with _exit.
        void* entry = dlsym(handle, kEntryPoint);
        if (entry == nullptr) {
            return core::fail(core::ErrorCode::kUnsupported,
                              fmt::format("{} is not maxslice's STEP/IGES reader of this version "
                                          "(no {}): rebuild maxslice",
                                          candidate.string(), kEntryPoint));
        }
        return reinterpret_cast<ReadCad>(entry);
    }
    return core::fail(core::ErrorCode::kUnsupported,
                      fmt::format("the STEP/IGES reader {} is not installed (looked for {}): "
                                  "rebuild maxslice, or set MAXSLICE_CAD_PLUGIN to its path",
                                  kModuleName, tried));
}

}  // namespace

core::Result<RawImport> read_cad(const std::filesystem::path& path, Format format,
                                 const ImportOptions& options) {
    return run_isolated(
        [&]() -> core::Result<RawImport> {
            auto read = load_module();
            if (!read) return std::unexpected(read.error());
            core::Result<RawImport> out = core::fail(core::ErrorCode::kInternal, "unread");
            (*read)(&path, format, &options, &out);
            return out;
        },
        options.library_time_limit_s, "Open CASCADE",
        "reading and tessellating the solids took too long; a coarser tessellation "
        "(a larger --chord-deviation) may help if the part is large or finely "
        "curved, else the file is damaged");
}

}  // namespace maxslice::io::detail
