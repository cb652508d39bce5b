#include "maxslice/pipeline/program_job.hpp"

#include <fmt/format.h>

#include <cmath>

#include "maxslice/core/units.hpp"
#include "maxslice/machine/program_builder.hpp"
#include "maxslice/machine/speed_law.hpp"

namespace maxslice::pipeline {

using core::Vec3d;

mesh::TriangleMesh place_on_plate(mesh::TriangleMesh part, const Vec3d& direction,
                                  const Vec3d& plate_center) {
    return mesh::placed_on_plate(std::move(part), direction, plate_center);
}

path::PathSettings path_settings(const machine::ProcessProfile& process) {
    path::PathSettings s;
    s.track_width_mm = process.track_width_mm;
    s.overlap = process.overlap;
    s.contour_passes = process.contour_passes;
    return s;
}

core::Result<PlannedProgram> plan_program(const SliceStack& stack,
                                          const machine::Profiles& profiles,
                                          const std::string& part_name,
                                          const core::Progress* progress) {
    const path::PathSettings settings = path_settings(profiles.process);
    if (auto ok = path::validate(settings); !ok) return std::unexpected(ok.error());
    PlannedProgram out;
    out.program.part_name = part_name;
    out.toolpaths.reserve(stack.slices.size());
    std::vector<const geom2d::WireTree*> regions;
    regions.reserve(stack.slices.size());
    for (const slice::Slice& s : stack.slices) regions.push_back(&s.wires);
    auto planned = path::plan_layers(regions, settings, geom2d::Point2{}, progress);
    if (!planned) return std::unexpected(planned.error());
    // Every layer at the feed that lays its thickness (adaptive layers vary).
    const machine::SpeedLaw law = machine::SpeedLaw::of(profiles.process);
    std::vector<Vec3d> points;
    std::vector<double> feeds;
    for (std::size_t i = 0; i < stack.slices.size(); ++i) {
        const slice::Slice& s = stack.slices[i];
        auto tp = std::move((*planned)[i]);
        const double area = s.area_mm2();
        out.region_area_mm2 += area;
        out.uncovered_mm2 += tp.uncovered_mm2;
        if (tp.uncovered_mm2 > 0.01 * area) ++out.layers_with_uncovered;
        // The bead of this layer fills [bottom, top]: the melt pool runs at the top.
        const double lift = s.span.top - s.span.cut;
        const int layer = s.index;
        if (!tp.strokes.empty() && !out.program.moves.empty()) {
            // Rise to the new layer's height above the last point before moving across.
            Vec3d up = out.program.moves.back().position;
            up.z = s.plane.to_3d(tp.strokes.front().points.front(), lift).z;
            if (up.z > out.program.moves.back().position.z) {
                machine::append_travel(out.program, up, profiles.process, layer);
            }
        }
        for (const path::Stroke& stroke : tp.strokes) {
            points.clear();
            for (const geom2d::Point2& q : stroke.points) points.push_back(s.plane.to_3d(q, lift));
            if (points.size() < 2) continue;
            feeds.assign(points.size() - 1, law.feed_mm_min(s.thickness()));
            machine::append_wire(out.program, points, feeds, profiles.process, layer, 0,
                                 s.plane.normal);
        }
        out.toolpaths.push_back(std::move(tp));
    }
    auto summary = machine::summarize(out.program, profiles.process);
    if (!summary) return std::unexpected(summary.error());
    out.summary = *summary;
    return out;
}

}  // namespace maxslice::pipeline
