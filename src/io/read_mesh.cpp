#include "maxslice/io/read_mesh.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <exception>

#include "maxslice/core/files.hpp"
#include "maxslice/core/tolerances.hpp"
#include "readers.hpp"

namespace maxslice::io {
namespace {

// Enough to see any format's signature and the first line of an IGES file.
constexpr std::size_t kSniffBytes = 4096;
// The longest error or warning message read_mesh returns.
constexpr std::size_t kMaxMessageChars = 600;

// The end of the time-out message of the mesh readers that run in the reader program
// (assimp, lib3mf): they do no tessellation, so no option makes them faster.
constexpr std::string_view kSlowLibraryReader =
    "the reader took too long on this file, which is damaged or far larger than it looks; "
    "check it, or export it again";

// The STEP/IGES reader's: it tessellates.
constexpr std::string_view kSlowCadReader =
    "reading and tessellating the solids took too long; a coarser tessellation (a larger "
    "--chord-deviation) may help if the part is large or finely curved, else the file is "
    "damaged";

// Reads an OBJ, 3MF, STEP or IGES file in the reader program maxslice-read-part
// (read_part_main.cpp, which takes these arguments), a process of its own (isolated.cpp).
core::Result<detail::RawImport> read_in_reader_program(const std::filesystem::path& path,
                                                       Format format,
                                                       const ImportOptions& options) {
#ifdef MAXSLICE_PART_READER_BUILD_PATH
    const char* build_path = MAXSLICE_PART_READER_BUILD_PATH;
#else
    const char* build_path = nullptr;
#endif
    auto program = detail::find_companion("the part reader program", "MAXSLICE_PART_READER",
                                          "maxslice-read-part", build_path);
    if (!program) return std::unexpected(program.error());
    const bool cad = format == Format::kStep || format == Format::kIges;
    const std::string_view library = cad                      ? "Open CASCADE"
                                     : format == Format::k3mf ? "lib3mf"
                                                              : "assimp";
    const detail::ReaderCommand command{*program,
                                        {std::to_string(static_cast<int>(format)), path.string(),
                                         fmt::format("{}", options.chord_deviation_mm),
                                         fmt::format("{}", options.angular_deviation_deg)}};
    return detail::run_isolated(command, options.library_time_limit_s, library,
                                cad ? kSlowCadReader : kSlowLibraryReader);
}

std::string lower_extension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

std::optional<Format> format_from_extension(const std::string& ext) {
    if (ext == ".stl") return Format::kStlBinary;
    if (ext == ".obj") return Format::kObj;
    if (ext == ".ply") return Format::kPly;
    if (ext == ".off") return Format::kOff;
    if (ext == ".3mf") return Format::k3mf;
    if (ext == ".step" || ext == ".stp" || ext == ".p21") return Format::kStep;
    if (ext == ".iges" || ext == ".igs") return Format::kIges;
    return std::nullopt;
}

bool is_stl(Format f) {
    return f == Format::kStlBinary || f == Format::kStlAscii;
}

bool same_family(Format a, Format b) {
    return a == b || (is_stl(a) && is_stl(b));
}

bool starts_with_ci(std::string_view s, std::string_view prefix) {
    if (s.size() < prefix.size()) return false;
    for (std::size_t i = 0; i < prefix.size(); ++i) {
        if (std::tolower(static_cast<unsigned char>(s[i])) !=
            std::tolower(static_cast<unsigned char>(prefix[i]))) {
            return false;
        }
    }
    return true;
}

std::string_view skip_bom_and_space(std::string_view s) {
    if (s.size() >= 3 && s.substr(0, 3) == "\xEF\xBB\xBF") s.remove_prefix(3);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    return s;
}

// An IGES file is 80-column records with the section letter in column 73; the first is 'S'
// (or 'F'/'C' for the rarer compressed and binary forms, which are not read).
bool looks_like_iges(std::string_view head) {
    const std::size_t eol = head.find_first_of("\r\n");
    const std::string_view first = head.substr(0, eol);
    return first.size() >= 73 && first[72] == 'S';
}

bool looks_like_off(std::string_view s) {
    // OFF, COFF, NOFF, CNOFF, STOFF, 4OFF, nOFF ... followed by white space or a digit.
    std::size_t i = 0;
    while (i < s.size() && i < 8 && std::isalnum(static_cast<unsigned char>(s[i]))) ++i;
    const std::string_view word = s.substr(0, i);
    return word.size() >= 3 && word.substr(word.size() - 3) == "OFF" &&
           (i == s.size() || std::isspace(static_cast<unsigned char>(s[i])));
}

bool looks_like_solid(std::string_view s) {
    return starts_with_ci(s, "solid") &&
           (s.size() == 5 || std::isspace(static_cast<unsigned char>(s[5])));
}

std::string extension_note(const std::filesystem::path& path, Format content) {
    const std::string ext = lower_extension(path);
    const auto by_name = format_from_extension(ext);
    if (!by_name || same_family(*by_name, content)) return {};
    return fmt::format("the file name ends in '{}' but the content is {}; read as {}", ext,
                       format_name(content), format_name(content));
}

core::Result<void> check_options(const ImportOptions& options) {
    if (!(options.chord_deviation_mm > 0.0) || !std::isfinite(options.chord_deviation_mm)) {
        return core::fail(core::ErrorCode::kInvalidInput,
                          fmt::format("the chord deviation must be a positive length in mm, "
                                      "not {}",
                                      options.chord_deviation_mm),
                          "import options");
    }
    if (!(options.angular_deviation_deg > 0.0) || !(options.angular_deviation_deg <= 90.0)) {
        return core::fail(core::ErrorCode::kInvalidInput,
                          fmt::format("the angular deviation must be in (0, 90] degrees, not {}",
                                      options.angular_deviation_deg),
                          "import options");
    }
    return {};
}

// Applies the unit (the override, the declared one, or mm), refuses non-finite results and
// warns about implausible sizes.
core::Result<ImportedMesh> finish(detail::RawImport raw, const ImportOptions& options) {
    ImportedMesh out;
    out.format = raw.format;
    out.solids = raw.solids;
    out.unit_declared = raw.declared_unit.has_value() || !raw.declared_unit_text.empty();
    out.warnings = std::move(raw.warnings);

    double scale = 1.0;
    if (!raw.converted_to_mm) {
        out.source_unit =
            options.units.value_or(raw.declared_unit.value_or(core::LengthUnit::kMillimetre));
        scale = core::mm_per_unit(out.source_unit);
    } else if (!options.units) {
        out.source_unit = raw.declared_unit.value_or(core::LengthUnit::kMillimetre);
    } else if (raw.declared_unit) {
        // Open CASCADE already converted from the declared unit: undo that, apply the override.
        out.source_unit = *options.units;
        scale = core::mm_per_unit(*options.units) / core::mm_per_unit(*raw.declared_unit);
    } else {
        return core::fail(
            core::ErrorCode::kInvalidInput,
            fmt::format("--units cannot be applied: the file declares the length units '{}', "
                        "not one unit maxslice knows; leave --units out to use the file's own "
                        "units",
                        raw.declared_unit_text.empty() ? "(none)" : raw.declared_unit_text));
    }
    if (options.units && raw.declared_unit && *options.units != *raw.declared_unit) {
        out.warnings.push_back(fmt::format("the file declares '{}'; --units {} overrides it",
                                           core::unit_name(*raw.declared_unit),
                                           core::unit_name(*options.units)));
    }
    out.mesh = std::move(raw.mesh);
    if (scale != 1.0) mesh::scale(out.mesh, scale);

    // Every vertex of a welded mesh is used by a triangle, so the vertex box is the part's.
    core::Vec3d lo{INFINITY, INFINITY, INFINITY};
    core::Vec3d hi{-INFINITY, -INFINITY, -INFINITY};
    bool finite = true;
    for (const core::Vec3d& v : out.mesh.vertices) {
        finite = finite && core::is_finite(v);
        lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
        hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
    }
    if (!finite) {
        return core::fail(core::ErrorCode::kInvalidInput,
                          "a vertex coordinate is not finite once converted to mm");
    }
    const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 0.0});
    const std::string unit_hint =
        options.units ? fmt::format("it was read with --units {}; check that unit",
                                    core::unit_name(*options.units))
                      : std::string("if the file is not in mm, give its unit with --units");
    if (extent < core::kImplausiblySmallPartMm) {
        out.warnings.push_back(
            fmt::format("the part is only {:.6g} mm across (largest extent): {} (e.g. --units m or "
                        "--units in)",
                        extent, unit_hint));
    } else if (extent > core::kImplausiblyLargePartMm) {
        out.warnings.push_back(
            fmt::format("the part is {:.6g} mm across (largest extent): {} (e.g. --units um)",
                        extent, unit_hint));
    }
    return out;
}

core::Result<ImportedMesh> read_impl(const std::filesystem::path& path,
                                     const ImportOptions& options) {
    if (auto ok = check_options(options); !ok) return std::unexpected(ok.error());
    std::uint64_t size = 0;
    auto head = detail::read_file_head(path, kSniffBytes, size);
    if (!head) return std::unexpected(head.error());
    auto format = detail::sniff_format(head->view(), size, path);
    if (!format) return std::unexpected(format.error());

    core::Result<detail::RawImport> raw = core::fail(core::ErrorCode::kInternal, "unread");
    switch (*format) {
        case Format::kStlBinary:
        case Format::kStlAscii: raw = detail::read_stl_file(path, head->view(), size); break;
        case Format::kPly:
        case Format::kOff: {
            auto bytes = size <= kSniffBytes ? std::move(head) : detail::read_file(path);
            if (!bytes) return std::unexpected(bytes.error());
            raw = *format == Format::kPly ? detail::read_ply(bytes->view())
                                          : detail::read_off(bytes->view());
            break;
        }
        case Format::kObj:
        case Format::k3mf:
        case Format::kStep:
        case Format::kIges: raw = read_in_reader_program(path, *format, options); break;
    }
    if (!raw) return std::unexpected(raw.error());
    const std::string note = extension_note(path, raw->format);
    auto done = finish(std::move(*raw), options);
    if (done && !note.empty()) done->warnings.insert(done->warnings.begin(), note);
    return done;
}

}  // namespace

namespace detail {

core::Result<Format> sniff_format(std::string_view head, std::uint64_t file_size,
                                  const std::filesystem::path& path) {
    if (file_size == 0) {
        return core::fail(core::ErrorCode::kInvalidInput, "the file is empty (0 bytes)");
    }
    const std::string ext = lower_extension(path);
    const auto by_name = format_from_extension(ext);
    const std::string_view text = skip_bom_and_space(head);
    if (head.size() >= 4 && head.substr(0, 4) == std::string_view("PK\x03\x04", 4)) {
        return Format::k3mf;  // the only zip container maxslice reads
    }
    if (starts_with_ci(text, "ISO-10303-21")) return Format::kStep;
    const bool utf16 = head.size() >= 2 && ((static_cast<unsigned char>(head[0]) == 0xFE &&
                                             static_cast<unsigned char>(head[1]) == 0xFF) ||
                                            (static_cast<unsigned char>(head[0]) == 0xFF &&
                                             static_cast<unsigned char>(head[1]) == 0xFE));
    if (utf16) {
        if (by_name == Format::kObj) return Format::kObj;
        return core::fail(core::ErrorCode::kInvalidInput,
                          "the file is UTF-16 text, which maxslice reads only for OBJ; save it "
                          "as UTF-8 or ASCII");
    }
    if (starts_with_ci(text, "ply") && text.size() > 3 && (text[3] == '\n' || text[3] == '\r')) {
        return Format::kPly;
    }
    if (looks_like_off(text)) return Format::kOff;
    if (looks_like_iges(head)) return Format::kIges;
    // No other format starts with "solid"; read_stl still checks it is really text.
    if (looks_like_solid(text)) return Format::kStlAscii;
    if (by_name) return *by_name;
    if (file_size >= 84 && (file_size - 84) % 50 == 0) return Format::kStlBinary;
    return core::fail(core::ErrorCode::kInvalidInput,
                      fmt::format("unrecognised file format{}: maxslice reads STL, OBJ, PLY, OFF, "
                                  "3MF, STEP and IGES",
                                  ext.empty() ? "" : " ('" + ext + "')"));
}

}  // namespace detail

core::Result<ImportedMesh> read_mesh(const std::filesystem::path& path,
                                     const ImportOptions& options) {
    const std::string context = "file " + path.string();
    try {
        auto result = read_impl(path, options);
        // Messages quote the file (tokens) and the libraries (which quote it too): each is
        // one line, control bytes escaped, cut to a readable length.
        if (!result) {
            core::Error e = core::with_context(result.error(), context);
            e.message = core::printable(e.message, kMaxMessageChars);
            return std::unexpected(std::move(e));
        }
        for (std::string& w : result->warnings) w = core::printable(w, kMaxMessageChars);
        return result;
    } catch (const std::bad_alloc&) {
        return core::fail(core::ErrorCode::kIo, "not enough memory to read the file", context);
    } catch (const std::exception& e) {
        return core::fail(core::ErrorCode::kInvalidInput,
                          fmt::format("the file could not be read: {}", e.what()), context);
    } catch (...) {
        return core::fail(core::ErrorCode::kInvalidInput, "the file could not be read", context);
    }
}

core::Result<Format> detect_format(const std::filesystem::path& path) {
    const std::string context = "file " + path.string();
    try {
        std::uint64_t size = 0;
        auto head = detail::read_file_head(path, kSniffBytes, size);
        if (!head) return std::unexpected(core::with_context(head.error(), context));
        auto format = detail::sniff_format(head->view(), size, path);
        if (!format) return std::unexpected(core::with_context(format.error(), context));
        if (*format == Format::kStlAscii || *format == Format::kStlBinary) {
            // The reader's rule, on what was read.
            return detail::stl_is_ascii(head->view()) ? Format::kStlAscii : Format::kStlBinary;
        }
        return format;
    } catch (const std::exception& e) {
        return core::fail(core::ErrorCode::kIo, e.what(), context);
    }
}

}  // namespace maxslice::io
