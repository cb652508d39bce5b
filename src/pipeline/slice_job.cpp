#include "maxslice/pipeline/slice_job.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>

#include "maxslice/core/tolerances.hpp"

#include "maxslice/mesh/repair.hpp"

namespace maxslice::pipeline {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string where(const mesh::DefectCount& d) {
    if (!d.example) return {};
    return fmt::format(", e.g. near ({:.3f}, {:.3f}, {:.3f}) mm", d.example->x, d.example->y,
                       d.example->z);
}

// The defects that make a mesh unsliceable, in the order a person should fix them.
core::Result<void> check_sliceable(const mesh::ValidationReport& r, bool repaired) {
    const auto refuse = [](std::string msg) {
        return core::fail(core::ErrorCode::kInvalidInput, std::move(msg));
    };
    if (r.triangles == 0) return refuse("the mesh has no triangles");
    if (r.nonfinite_vertices.count > 0) {
        return refuse(fmt::format("{} vertices have NaN or infinite coordinates",
                                  r.nonfinite_vertices.count));
    }
    const std::string hint = repaired ? "" : "; rerun with --repair to fix the orientation";
    // Misoriented edges that are balanced (as often one way as the other) are where closed
    // bodies touch: the slicer's positive fill rule builds their union.
    if (r.unbalanced_edges.count > 0) {
        return refuse(
            fmt::format("inconsistent orientation: {} edges are used twice in the same "
                        "direction{}{}",
                        r.unbalanced_edges.count, where(r.unbalanced_edges), hint));
    }
    if (r.inside_out_shells.count > 0) {
        return refuse(fmt::format(
            "{} of the {} bodies {} inside out (facing inwards, not a void in another body){}: "
            "every layer would leave {} out{}",
            r.inside_out_shells.count, r.bodies, r.inside_out_shells.count == 1 ? "is" : "are",
            where(r.inside_out_shells), r.inside_out_shells.count == 1 ? "it" : "them",
            repaired ? ""
                     : fmt::format("; rerun with --repair to turn {} outside out",
                                   r.inside_out_shells.count == 1 ? "it" : "them")));
    }
    if (r.inward_pieces.count > 0) {
        return refuse(fmt::format(
            "{} {} of surface where closed bodies touch {} inwards{}: a body that touches "
            "another is inside out, and every layer would leave it out; turn it outside out in "
            "the CAD export (--repair does not reorient bodies that share edges)",
            r.inward_pieces.count, r.inward_pieces.count == 1 ? "piece" : "pieces",
            r.inward_pieces.count == 1 ? "faces" : "face", where(r.inward_pieces)));
    }
    const double diag = core::norm(r.bounding_box.size());
    // A volume this small against the box means the triangles enclose nothing (a sheet,
    // a soup of loose faces).
    if (!(std::abs(r.volume_mm3) > 1e-9 * diag * diag * diag)) {
        return refuse(
            fmt::format("the mesh encloses no volume ({} triangles, {} open edges): "
                        "it is a surface, not a solid",
                        r.triangles, r.boundary_edges.count));
    }
    if (r.volume_mm3 < 0.0) {
        return refuse(
            fmt::format("the mesh is inside-out (volume {:.6g} mm3){}", r.volume_mm3, hint));
    }
    return {};
}

}  // namespace

core::Result<PreparedPart> read_part(const std::filesystem::path& path,
                                     const PrepareSettings& settings, StageTimes* times) {
    auto t0 = Clock::now();
    auto imported = io::read_mesh(path, settings.import);
    if (!imported) return std::unexpected(imported.error());
    if (times != nullptr) times->load_s = seconds_since(t0);
    t0 = Clock::now();
    PreparedPart part;
    part.imported = std::move(*imported);
    part.warnings = part.imported.warnings;
    part.report = mesh::validate(part.imported.mesh);
    if (settings.repair) {
        const mesh::RepairReport rr = mesh::repair(part.imported.mesh, mesh::RepairOptions{});
        part.repairs = rr.lines();
        part.repaired_report = mesh::validate(part.imported.mesh);
    }
    if (times != nullptr) times->validate_s = seconds_since(t0);
    return part;
}

core::Result<PreparedPart> prepare_part(const std::filesystem::path& path,
                                        const PrepareSettings& settings, StageTimes* times) {
    auto part = read_part(path, settings, times);
    if (!part) return part;
    const std::string context = "file " + path.filename().string();
    const mesh::ValidationReport& final_report = part->final_report();
    if (auto ok = check_sliceable(final_report, settings.repair); !ok) {
        return std::unexpected(core::with_context(
            ok.error(), settings.repair ? context + " (after repair)" : context));
    }
    for (const std::string& d : final_report.defects()) {
        part->warnings.push_back(settings.repair ? d + " (after repair)" : d);
    }
    return part;
}

core::Result<void> validate(const SliceSettings& s) {
    if (!core::is_finite(s.direction) || core::norm(s.direction) < 1e-9) {
        return core::fail(core::ErrorCode::kInvalidInput,
                          "the slicing direction must be a non-zero vector", "--direction");
    }
    return slice::validate(s.layers);
}

core::Result<SliceStack> slice_part(const mesh::TriangleMesh& mesh, const SliceSettings& settings,
                                    const core::Progress* progress, StageTimes* times,
                                    slice::VertexUse use) {
    if (auto ok = validate(settings); !ok) return std::unexpected(ok.error());
    const auto t0 = Clock::now();
    SliceStack stack;
    const slice::FrameExtent fe = slice::base_frame_and_extent(mesh, settings.direction, use);
    stack.base = fe.frame;
    const double lo = fe.lo, hi = fe.hi;
    if (auto ok =
            settings.layers.adaptive
                ? slice::check_layer_count(hi - lo, settings.layers.min_layer_mm, "--min-layer")
                : slice::check_layer_count(hi - lo, settings.layers.layer_mm, "--layer");
        !ok) {
        return std::unexpected(ok.error());
    }
    const std::vector<slice::LayerSpan> layers =
        settings.layers.adaptive ? slice::adaptive_layers(mesh, stack.base, lo, hi, settings.layers)
                                 : slice::uniform_layers(lo, hi, settings.layers.layer_mm);
    if (layers.empty()) {
        return core::fail(core::ErrorCode::kInvalidInput,
                          fmt::format("the part has no extent along the slicing direction "
                                      "({:.6g} mm)",
                                      hi - lo));
    }
    auto slices = slice::slice_mesh(mesh, fe, layers, progress, settings.max_gap_mm);
    if (!slices) return std::unexpected(slices.error());
    stack.slices = std::move(*slices);
    const slice::Slice* first_open = nullptr;
    for (const slice::Slice& s : stack.slices) {
        if (s.open_chains > 0) {
            ++stack.layers_with_open_chains;
            if (first_open == nullptr) first_open = &s;
        }
    }
    if (first_open != nullptr) {
        return core::fail(
            core::ErrorCode::kInvalidInput,
            fmt::format(
                "{} contour(s) could not be closed (a hole in the surface wider than "
                "{} mm); {} layers are affected: close the mesh's holes, or rerun with --repair "
                "to bridge every gap",
                first_open->open_chains, settings.max_gap_mm, stack.layers_with_open_chains),
            fmt::format("layer {} at {:.3f} mm", first_open->index + 1, first_open->span.cut));
    }
    if (times != nullptr) times->slice_s = seconds_since(t0);
    return stack;
}

}  // namespace maxslice::pipeline
