// maxslice-read-part: the program read_mesh reads OBJ (assimp), 3MF (lib3mf), STEP and IGES
// (Open CASCADE) files in, a process of its own, so that a crash, a hang or a runaway
// allocation of the library refuses the file instead of ending or blocking maxslice
// (isolated.cpp says how). Not meant to be run by hand: read_mesh starts it as
//   maxslice-read-part <caller pid> <format number> <path> <chord mm> <angle deg>
// and takes the mesh from descriptor 3.
#include <charconv>
#include <string>
#include <string_view>

#include "readers.hpp"

namespace {

using maxslice::core::ErrorCode;
using maxslice::core::Result;
using maxslice::io::Format;
using maxslice::io::ImportOptions;
using maxslice::io::detail::RawImport;

bool parse(std::string_view text, double& out) {
    const auto r = std::from_chars(text.data(), text.data() + text.size(), out);
    return r.ec == std::errc() && r.ptr == text.data() + text.size();
}

Result<RawImport> read_part(std::span<const std::string_view> args) {
    namespace detail = maxslice::io::detail;
    int format_number = -1;
    ImportOptions options;
    if (args.size() != 4 ||
        std::from_chars(args[0].data(), args[0].data() + args[0].size(), format_number).ec !=
            std::errc() ||
        !parse(args[2], options.chord_deviation_mm) ||
        !parse(args[3], options.angular_deviation_deg)) {
        return maxslice::core::fail(ErrorCode::kInternal,
                                    "maxslice-read-part was started with arguments it does not "
                                    "know: rebuild maxslice");
    }
    const std::filesystem::path path{std::string(args[1])};
    const auto format = static_cast<Format>(format_number);
    switch (format) {
        case Format::kObj: {
            auto bytes = detail::read_file(path);
            if (!bytes) return std::unexpected(bytes.error());
            return detail::read_with_assimp(bytes->view(), format);
        }
        case Format::k3mf: return detail::read_3mf(path);
        case Format::kStep:
        case Format::kIges: return detail::read_cad(path, format, options);
        default: break;
    }
    return maxslice::core::fail(ErrorCode::kInternal,
                                "maxslice-read-part does not read this format: rebuild maxslice");
}

}  // namespace

#if MAXSLICE_ADDRESS_SANITIZER
// In a sanitizer build a crash signal ends this program as in any other build (the caller
// refuses the file: Open CASCADE dereferences null handles on damaged files), instead of
// being reported as a bug of maxslice; the sanitizer's reports on maxslice's own code still
// are (isolated.cpp). Options in ASAN_OPTIONS come on top of these.
extern "C" const char* __asan_default_options() {
    return "handle_segv=0:handle_sigbus=0:handle_sigfpe=0:handle_sigill=0";
}
#endif

int main(int argc, char** argv) {
    maxslice::io::detail::serve_isolated(argc, argv, read_part);
}
