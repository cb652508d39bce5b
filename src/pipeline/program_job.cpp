#include "maxslice/pipeline/program_job.hpp"

#include <fmt/format.h>

#include <cmath>

#include "maxslice/core/units.hpp"
#include "maxslice/machine/program_builder.hpp"
#include "maxslice/machine/speed_law.hpp"

namespace maxslice::pipeline {

using core::Vec3d;

Vec3d plate_center(const machine::MachineProfile& machine) {
    if (machine.table) return {machine.table->c_offset_x_mm, machine.table->c_offset_y_mm, 0.0};
    Vec3d c{};
    if (const auto* x = machine.find_axis("X")) c.x = 0.5 * (x->min + x->max);
    if (const auto* y = machine.find_axis("Y")) c.y = 0.5 * (y->min + y->max);
    return c;
}

mesh::TriangleMesh place_on_plate(mesh::TriangleMesh part, const Vec3d& direction,
                                  const Vec3d& plate_center) {
    // Rodrigues rotation taking d onto +Z (a half turn about X when d points down).
    const Vec3d d = core::normalized(direction);
    const Vec3d z{0.0, 0.0, 1.0};
    const Vec3d axis = core::cross(d, z);
    const double s = core::norm(axis), c = core::dot(d, z);
    std::array<double, 12> m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    if (s > 1e-12) {
        const Vec3d k = axis / s;
        const double v = 1.0 - c;
        m = {c + k.x * k.x * v,       k.x * k.y * v - k.z * s, k.x * k.z * v + k.y * s, 0.0,
             k.y * k.x * v + k.z * s, c + k.y * k.y * v,       k.y * k.z * v - k.x * s, 0.0,
             k.z * k.x * v - k.y * s, k.z * k.y * v + k.x * s, c + k.z * k.z * v,       0.0};
    } else if (c < 0.0) {
        m = {1, 0, 0, 0, 0, -1, 0, 0, 0, 0, -1, 0};
    }
    mesh::transform(part, m);
    const core::Box3d box = mesh::bounding_box(part);
    if (!box.empty()) {
        const Vec3d shift{plate_center.x - box.center().x, plate_center.y - box.center().y,
                          -box.min.z};
        mesh::transform(part, {1, 0, 0, shift.x, 0, 1, 0, shift.y, 0, 0, 1, shift.z});
    }
    return part;
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
