#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "maxslice/core/progress.hpp"
#include "maxslice/core/result.hpp"
#include "maxslice/core/tolerances.hpp"
#include "maxslice/io/read_mesh.hpp"
#include "maxslice/mesh/validation.hpp"
#include "maxslice/slice/layers.hpp"
#include "maxslice/slice/slicer.hpp"

namespace maxslice::pipeline {

/// Wall-clock seconds spent in each stage of a job (reported, never asserted).
struct StageTimes {
    double load_s = 0.0;      ///< read and weld
    double validate_s = 0.0;  ///< validation (and repair)
    double near_net_s = 0.0;  ///< the near-net shape (when the process asks for one)
    double slice_s = 0.0;     ///< layer heights, cutting and wire trees (3-axis jobs)
    /// Table-tilt jobs: the base kept, planned (its slicing included) and ordered; `search_s`
    /// what the other bases tried took (their plans, orders and program checks), `bases` how
    /// many were tried in all (0: none recorded). A job that tries again (a finer process,
    /// another base for the figures) adds each attempt's, `attempts` counting them.
    double plan_s = 0.0;
    double order_s = 0.0;
    double search_s = 0.0;
    int bases = 0;
    int attempts = 0;
    double paths_s = 0.0;   ///< toolpaths and the move list (program jobs only)
    double write_s = 0.0;   ///< program text and its file (program jobs only)
    double verify_s = 0.0;  ///< the verifier's replay of the program (when run)
};

/// A part read, checked and (with repair) mended: the input of every later stage.
struct PreparedPart {
    io::ImportedMesh imported;
    mesh::ValidationReport report;      ///< of the mesh as read
    std::vector<std::string> repairs;   ///< what --repair changed, one line each
    std::vector<std::string> warnings;  ///< import warnings and accepted defects
    std::optional<mesh::ValidationReport> repaired_report;  ///< after --repair

    /// The report of the mesh the job works on: after --repair when it was repaired.
    [[nodiscard]] const mesh::ValidationReport& final_report() const {
        return repaired_report ? *repaired_report : report;
    }
};

/// How to read and check a part.
struct PrepareSettings {
    io::ImportOptions import;
    bool repair = false;  ///< apply the safe repairs (weld, drop degenerate/duplicate, orient)
};

/// Reads and validates a part and, with settings.repair, repairs it; `report` describes the
/// mesh as read. Refuses only files that cannot be read.
[[nodiscard]] core::Result<PreparedPart> read_part(const std::filesystem::path& path,
                                                   const PrepareSettings& settings,
                                                   StageTimes* times = nullptr);

/// Reads, validates and (optionally) repairs a part (read_part), then refuses (kInvalidInput) a
/// mesh that cannot be sliced: no triangles, non-finite coordinates, no enclosed volume, and
/// without repair an inside-out or inconsistently oriented mesh; the message names the defect, its
/// count and a coordinate, and says whether --repair would help.
[[nodiscard]] core::Result<PreparedPart> prepare_part(const std::filesystem::path& path,
                                                      const PrepareSettings& settings,
                                                      StageTimes* times = nullptr);

/// Settings of the slicing stage.
struct SliceSettings {
    core::Vec3d direction{0.0, 0.0, 1.0};
    slice::LayerSettings layers;
    /// Widest gap (mm) in an open surface's section that the slicer bridges; the CLI lifts
    /// the limit with --repair (every gap bridged, nearest first, and reported).
    double max_gap_mm = core::kSliceGapCloseMm;
};

/// Checks the settings (direction non-zero and finite, layer ranges).
[[nodiscard]] core::Result<void> validate(const SliceSettings& settings);

/// The slices of a part along one direction, from its lowest point up.
struct SliceStack {
    slice::PlaneFrame base;
    std::vector<slice::Slice> slices;
    int layers_with_open_chains = 0;  ///< layers where a chain could not be closed
};

/// Slices the part. Layers whose open chains could not be closed make the job fail with the
/// first such layer named (an open mesh with holes wider than the closing tolerance).
/// `use`: kAllUsed for a mesh from read_part or prepare_part (welded or repaired: every
/// vertex is used), which spares the slicer a look at every triangle.
[[nodiscard]] core::Result<SliceStack> slice_part(const mesh::TriangleMesh& mesh,
                                                  const SliceSettings& settings,
                                                  const core::Progress* progress = nullptr,
                                                  StageTimes* times = nullptr,
                                                  slice::VertexUse use = slice::VertexUse::kCheck);

}  // namespace maxslice::pipeline
