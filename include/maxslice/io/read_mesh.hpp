#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "maxslice/core/result.hpp"
#include "maxslice/core/units.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"

namespace maxslice::io {

/// The file formats maxslice reads.
enum class Format { kStlBinary, kStlAscii, kObj, kPly, kOff, k3mf, kStep, kIges };

/// Short name ("stl-binary", "obj", "step", ...).
[[nodiscard]] std::string_view format_name(Format format);

/// How to read a part file.
struct ImportOptions {
    /// Overrides the unit the file's numbers are in. Files that declare a unit (3MF, STEP,
    /// IGES) are converted to mm from their own unit unless this is set.
    std::optional<core::LengthUnit> units;
    /// Tessellation of STEP/IGES solids: largest chord deviation (mm) and angle (degrees).
    double chord_deviation_mm = 0.05;
    double angular_deviation_deg = 15.0;
};

/// A part read from a file: an indexed mesh in millimetres (vertices merged where their
/// coordinates are bit-identical), and what the reader noticed along the way.
struct ImportedMesh {
    mesh::TriangleMesh mesh;
    Format format = Format::kStlBinary;
    core::LengthUnit source_unit = core::LengthUnit::kMillimetre;
    bool unit_declared = false;         ///< the file itself named its unit
    std::size_t solids = 0;             ///< STEP/IGES: solids tessellated; else objects
    std::vector<std::string> warnings;  ///< accepted oddities, one line each
};

/// Reads a part file; the format comes from the content (and the extension where the
/// content is ambiguous). Errors (code kIo or kInvalidInput) name the file and, where
/// known, the line or byte offset.
[[nodiscard]] core::Result<ImportedMesh> read_mesh(const std::filesystem::path& path,
                                                   const ImportOptions& options = {});

/// Writes a binary STL (for previews and tests).
[[nodiscard]] core::Result<void> write_stl_binary(const std::filesystem::path& path,
                                                  const mesh::TriangleMesh& mesh);

}  // namespace maxslice::io
