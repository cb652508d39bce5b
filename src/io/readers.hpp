#pragma once

// Private to src/io: the per-format readers behind read_mesh. No third-party header may be
// included here; each library stays inside its own .cpp file.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "maxslice/core/result.hpp"
#include "maxslice/core/units.hpp"
#include "maxslice/io/read_mesh.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"

// 1 in a build with AddressSanitizer (clang's -fsanitize=address, or GCC's), else 0: the
// reader program's memory bound and signal handling, and the tests of them, depend on it.
#if defined(__SANITIZE_ADDRESS__)
#define MAXSLICE_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MAXSLICE_ADDRESS_SANITIZER 1
#endif
#endif
#ifndef MAXSLICE_ADDRESS_SANITIZER
#define MAXSLICE_ADDRESS_SANITIZER 0
#endif

namespace maxslice::io::detail {

/// What a format reader hands back. Errors from the readers carry no context; read_mesh
/// adds "file <path>".
struct RawImport {
    mesh::TriangleMesh mesh;
    Format format = Format::kStlBinary;
    /// True when the library already converted the coordinates to mm from the declared unit
    /// (Open CASCADE); false when the coordinates are the file's own numbers.
    bool converted_to_mm = false;
    /// The length unit the file declares, when it declares exactly one that maxslice knows.
    std::optional<core::LengthUnit> declared_unit;
    /// The declared unit as the file names it ("INCH", "millimetre", "inch,mm"), or empty.
    std::string declared_unit_text;
    std::size_t solids = 0;
    std::vector<std::string> warnings;
};

/// A whole file in memory.
struct FileBytes {
    std::unique_ptr<char[]> data;
    std::size_t size = 0;
    [[nodiscard]] std::string_view view() const { return {data.get(), size}; }
};

/// Reads the whole file (kIo when it cannot be opened or read, or is not a regular file).
[[nodiscard]] core::Result<FileBytes> read_file(const std::filesystem::path& path);
/// Reads at most max_bytes from the start of the file and reports the file size.
[[nodiscard]] core::Result<FileBytes> read_file_head(const std::filesystem::path& path,
                                                     std::size_t max_bytes,
                                                     std::uint64_t& file_size);

/// A file read in blocks at given offsets (pread), for readers that stream.
class PositionalFile {
public:
    [[nodiscard]] static core::Result<PositionalFile> open(const std::filesystem::path& path);
    PositionalFile(PositionalFile&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }
    PositionalFile& operator=(PositionalFile&&) = delete;
    PositionalFile(const PositionalFile&) = delete;
    ~PositionalFile();
    /// Reads up to `bytes` bytes at `offset`; fewer only at the end of the file.
    [[nodiscard]] core::Result<std::size_t> read_at(std::uint64_t offset, char* out,
                                                    std::size_t bytes) const;

private:
    explicit PositionalFile(int fd) : fd_(fd) {}
    int fd_;
};

/// The format from the first bytes of a file, its size and its extension.
[[nodiscard]] core::Result<Format> sniff_format(std::string_view head, std::uint64_t file_size,
                                                const std::filesystem::path& path);

/// True when an STL file whose first bytes are `head` is read as ASCII: it starts with
/// "solid" (after an optional UTF-8 BOM and white space) and either holds no control byte or
/// has a text first line followed by "facet" or "endsolid" (a damaged text file, refused with
/// the place of the byte).
[[nodiscard]] bool stl_is_ascii(std::string_view head);

/// Binary or ASCII STL from the whole file (the two are told apart here, not by sniffing).
[[nodiscard]] core::Result<RawImport> read_stl(std::string_view bytes);
/// The same from a file whose first bytes (head) and size are known: ASCII is read whole,
/// binary records are streamed in blocks into the corner array.
[[nodiscard]] core::Result<RawImport> read_stl_file(const std::filesystem::path& path,
                                                    std::string_view head, std::uint64_t size);

/// OBJ through assimp (triangulation only; numbers and indices checked first by scan_obj).
[[nodiscard]] core::Result<RawImport> read_with_assimp(std::string_view bytes, Format format);

/// PLY (ASCII, binary either endianness) and OFF, read here (see ply_off_reader.cpp for why
/// not through assimp). Polygons are ear clipped.
[[nodiscard]] core::Result<RawImport> read_ply(std::string_view bytes);
[[nodiscard]] core::Result<RawImport> read_off(std::string_view bytes);

/// 3MF through lib3mf: every build item with its transform and component transforms,
/// in the model's unit.
[[nodiscard]] core::Result<RawImport> read_3mf(const std::filesystem::path& path);

/// Reads the model parts of a 3MF file (minizip and a tag scanner, no lib3mf) and refuses,
/// before lib3mf reads it, a build whose components expand to more than `max_placed`
/// triangles or object placements, or nest deeper than `max_depth` (kInvalidInput, naming
/// the counts). What it cannot follow counts as nothing; a bad zip is left to lib3mf.
[[nodiscard]] core::Result<void> check_3mf_expansion(const std::filesystem::path& path,
                                                     std::uint64_t max_placed, int max_depth);

/// STEP or IGES through Open CASCADE, in this process (the reader program's): solids only,
/// tessellated with the options' deviations, in mm. Loads the module libmaxslice_cad.so
/// (cad_plugin.cpp).
[[nodiscard]] core::Result<RawImport> read_cad(const std::filesystem::path& path, Format format,
                                               const ImportOptions& options);

/// The share of the machine's memory a reader child may use (its address-space limit; not
/// in sanitizer builds).
inline constexpr double kReaderMemoryShare = 0.5;

/// A reader program and its arguments (run_isolated adds the caller's pid before them).
struct ReaderCommand {
    std::filesystem::path program;
    std::vector<std::string> args;
};

/// Runs a reader program (one that calls serve_isolated) and takes the mesh it reads: a
/// crash (signal) or a run longer than time_limit_s (<= 0: no limit) of the library behind
/// it refuses the file (kInvalidInput) instead of ending or blocking the program, naming
/// `library`; `slow_because` ends the time-out message (what makes this reader slow on a
/// file, and what to do). The program is killed when the calling thread ends (the caller is
/// killed). kIo when the program cannot be started.
[[nodiscard]] core::Result<RawImport> run_isolated(const ReaderCommand& command,
                                                   double time_limit_s, std::string_view library,
                                                   std::string_view slow_because);

/// What a reader program runs: its arguments after the caller's pid.
using IsolatedReader =
    std::function<core::Result<RawImport>(std::span<const std::string_view> args)>;

/// The reader program's side of run_isolated, called from its main: checks that the caller
/// started it and is alive, asks to die with it, bounds its memory, runs the reader and
/// hands the result (or that it ran out of memory, or threw) to the caller. Never returns.
[[noreturn]] void serve_isolated(int argc, char** argv, const IsolatedReader& reader);

/// A file maxslice ships beside its program: `name` in the directory of the running program,
/// in lib/maxslice/ beside that directory (an installed maxslice), or at `build_path` (the
/// build tree it was built in), the first of them that exists; an environment variable
/// `env`, when set, names the file instead, with no fallback. kUnsupported naming every
/// place looked at when there is none; `what` says what the file is.
[[nodiscard]] core::Result<std::filesystem::path> find_companion(std::string_view what,
                                                                 const char* env,
                                                                 std::string_view name,
                                                                 const char* build_path);

/// Checks an OBJ text before assimp sees it: every 'v' number parses, every face index
/// points at a vertex. Counts faces with fewer than 3 corners and point/line elements.
struct ObjScan {
    std::size_t vertices = 0;
    std::size_t faces = 0;
    std::size_t short_faces = 0;  ///< 'f' with fewer than 3 corners
    std::size_t first_short_face_line = 0;
    std::size_t points = 0;  ///< 'p' elements
    std::size_t lines = 0;   ///< 'l' elements
    /// The text assimp reads, written by the scan: vertices, faces by their vertices' numbers,
    /// object and group names, each on its statement's first line, every other line blank
    /// (obj_scan.cpp).
    std::string geometry;
};
[[nodiscard]] core::Result<ObjScan> scan_obj(std::string_view text);

/// UTF-16 text (with a byte order mark) as UTF-8; nullopt when there is no UTF-16 BOM.
[[nodiscard]] std::optional<std::string> utf16_to_utf8(std::string_view bytes);

/// A token as an error message shows it: quoted, at most 40 characters, bytes outside
/// printable ASCII as \xNN.
[[nodiscard]] std::string shown(std::string_view token);

/// "1 face", "3 faces" (plural_form defaults to singular + "s").
[[nodiscard]] std::string count_of(std::size_t n, std::string_view singular,
                                   std::string_view plural_form = {});

/// What parse_number found: a number, text that is not one, or a number too large for the
/// type (underflow reads as zero, which is what the writer meant).
enum class NumberRead { kOk, kNotANumber, kOutOfRange };

/// Parses a decimal number the way from_chars does, also accepting a leading '+';
/// the whole token must be the number. `value` is set only for kOk.
[[nodiscard]] NumberRead parse_number(std::string_view token, double& value);
[[nodiscard]] NumberRead parse_number(std::string_view token, float& value);

/// "<what> '<token>' is not a number", or for kOutOfRange "<what> '<token>' is out of range:
/// its magnitude is above <the type's largest number>".
[[nodiscard]] std::string number_problem(std::string_view what, std::string_view token,
                                         NumberRead why, bool single_precision);

}  // namespace maxslice::io::detail
