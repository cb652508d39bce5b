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
    /// The unit the file's numbers are in, overriding whatever the file declares (3MF model
    /// unit, STEP/IGES length unit). Unset: files that declare a unit are converted to mm
    /// from it, files that cannot (STL, OBJ, PLY, OFF) are taken as mm.
    /// See docs/decisions/0002-import.md.
    std::optional<core::LengthUnit> units;
    /// Tessellation of STEP/IGES solids: largest chord deviation (mm, > 0) and largest angle
    /// between neighbouring facet normals (degrees, in (0, 90]).
    double chord_deviation_mm = 0.05;
    double angular_deviation_deg = 10.0;
    /// Files read through a third-party library (OBJ: assimp, 3MF: lib3mf, STEP/IGES: Open
    /// CASCADE) are read in a child process, so that a crash of the library refuses the file;
    /// a read taking longer than this (seconds) is stopped and refused. <= 0: no limit.
    double library_time_limit_s = 600.0;
};

/// A part read from a file: an indexed mesh in millimetres (vertices merged where their
/// coordinates are bit-identical), and what the reader noticed along the way.
struct ImportedMesh {
    mesh::TriangleMesh mesh;
    Format format = Format::kStlBinary;
    /// The unit the file's numbers were taken to be in (the override, else the declared
    /// unit, else mm).
    core::LengthUnit source_unit = core::LengthUnit::kMillimetre;
    bool unit_declared = false;         ///< the file itself named its unit
    std::size_t solids = 0;             ///< STEP/IGES: solids tessellated (placed instances);
                                        ///< 3MF: mesh objects placed; else 'solid' blocks/meshes
    std::vector<std::string> warnings;  ///< accepted oddities, one line each
};

/// Reads a part file; the format comes from the content (and the extension where the
/// content is ambiguous). Never throws. Errors have code kIo (cannot open or read) or
/// kInvalidInput (malformed, unsupported content, no triangles, no solid), context
/// "file <path>", and a message naming, where known, the line or byte offset.
/// Triangles keep the file's vertex order (stored STL normals are ignored); degenerate or
/// open geometry is passed through for mesh validation to report.
[[nodiscard]] core::Result<ImportedMesh> read_mesh(const std::filesystem::path& path,
                                                   const ImportOptions& options = {});

/// The format read_mesh would use for this file (reads at most the first few KiB and the
/// size). Errors as for read_mesh.
[[nodiscard]] core::Result<Format> detect_format(const std::filesystem::path& path);

/// Writes a binary STL (for previews and tests), coordinates in mm as 32-bit floats.
/// Errors: kIo when the file cannot be written; kInvalidInput for more than 2^32-1
/// triangles.
[[nodiscard]] core::Result<void> write_stl_binary(const std::filesystem::path& path,
                                                  const mesh::TriangleMesh& mesh);

}  // namespace maxslice::io
