#include "maxslice/pipeline/near_net_job.hpp"

#include <fmt/format.h>

#include <chrono>
#include <utility>

#include "maxslice/mesh/validation.hpp"

namespace maxslice::pipeline {

nearnet::NearNetSettings near_net_settings(const machine::ProcessProfile& process) {
    return {process.machining_stock_mm, process.fill_below_mm};
}

core::Result<std::optional<NearNetPart>> near_net_part(const PreparedPart& part,
                                                       const machine::ProcessProfile& process,
                                                       const core::Progress* progress,
                                                       StageTimes* times) {
    const nearnet::NearNetSettings settings = near_net_settings(process);
    if (settings.off()) return std::optional<NearNetPart>{};
    const auto start = std::chrono::steady_clock::now();
    auto shape = nearnet::near_net(part.imported.mesh, settings, progress);
    if (!shape) return std::unexpected(shape.error());
    NearNetPart out;
    out.settings = settings;
    out.report = shape->report;
    out.finished = part.imported.mesh;
    out.built = part;
    out.built.imported.mesh = std::move(shape->mesh);
    out.built.report = mesh::validate(out.built.imported.mesh);
    out.built.repaired_report.reset();
    if (times != nullptr) {
        times->near_net_s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    return std::optional<NearNetPart>{std::move(out)};
}

std::string near_net_line(const NearNetPart& part) {
    const nearnet::NearNetSettings& s = part.settings;
    const std::string fill =
        s.fill_below_mm > 0.0
            ? fmt::format("holes, slots and inside corners under {:.2f} mm filled", s.fill_below_mm)
            : std::string("no fill");
    const nearnet::NearNetReport& r = part.report;
    const std::string caps =
        r.capped_holes > 0
            ? fmt::format("; the surface's {} open edges closed by {} caps for the fields' sign",
                          r.open_edges, r.capped_holes)
            : std::string();
    return fmt::format(
        "near-net shape  {:.2f} mm machining stock, {}: {:+.1f}% volume over the finished part "
        "({:.3f} mm voxels{})\n",
        s.stock_mm, fill, 100.0 * r.added_fraction(), r.voxel_mm, caps);
}

}  // namespace maxslice::pipeline
