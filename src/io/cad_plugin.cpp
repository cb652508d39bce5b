// STEP and IGES files are read by occt_reader.cpp, built as a module of its own
// (libmaxslice_cad.so) so that Open CASCADE's libraries are loaded only when such a file is
// read: they resolve about 90,000 symbols when loaded (they are linked with BIND_NOW),
// ~30 ms that every run of maxslice, of any command on any format, paid while they were
// linked to the program. The module is loaded by the reader program the file is read in
// (maxslice-read-part, isolated.cpp), so maxslice never maps Open CASCADE at all.
//
// Where the module is looked for (find_companion): $MAXSLICE_CAD_PLUGIN (a path to the
// file), the directory of the running program, lib/maxslice/ beside that directory (an
// installed maxslice: apps/maxslice/CMakeLists.txt), and the build tree it was built in.
#include <dlfcn.h>

#include <fmt/format.h>

#include "readers.hpp"

namespace maxslice::io::detail {
namespace {

constexpr const char* kModuleName = "libmaxslice_cad.so";
constexpr const char* kEntryPoint = "maxslice_read_cad_v1";

using ReadCad = void (*)(const std::filesystem::path*, Format, const ImportOptions*,
                         core::Result<RawImport>*);

core::Result<ReadCad> load_module() {
#ifdef MAXSLICE_CAD_PLUGIN_BUILD_PATH
    const char* build_path = MAXSLICE_CAD_PLUGIN_BUILD_PATH;
#else
    const char* build_path = nullptr;
#endif
    auto path =
        find_companion("the STEP/IGES reader", "MAXSLICE_CAD_PLUGIN", kModuleName, build_path);
    if (!path) return std::unexpected(path.error());
    void* handle = dlopen(path->c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
        const char* why = dlerror();
        return core::fail(core::ErrorCode::kUnsupported,
                          fmt::format("cannot load the STEP/IGES reader {}: {}", path->string(),
                                      why != nullptr ? why : "?"));
    }
    // Never closed: the reader program that loaded it ends with _exit.
    void* entry = dlsym(handle, kEntryPoint);
    if (entry == nullptr) {
        return core::fail(core::ErrorCode::kUnsupported,
                          fmt::format("{} is not maxslice's STEP/IGES reader of this version "
                                      "(no {}): rebuild maxslice",
                                      path->string(), kEntryPoint));
    }
    return reinterpret_cast<ReadCad>(entry);
}

}  // namespace

core::Result<RawImport> read_cad(const std::filesystem::path& path, Format format,
                                 const ImportOptions& options) {
    auto read = load_module();
    if (!read) return std::unexpected(read.error());
    core::Result<RawImport> out = core::fail(core::ErrorCode::kInternal, "unread");
    (*read)(&path, format, &options, &out);
    return out;
}

}  // namespace maxslice::io::detail
