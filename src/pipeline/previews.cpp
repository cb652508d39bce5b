#include "maxslice/pipeline/previews.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <tuple>

#include "maxslice/core/files.hpp"
#include "maxslice/core/units.hpp"
#include "output.hpp"

namespace maxslice::pipeline {

core::Result<void> detail::write_text(const std::filesystem::path& file, std::string_view text) {
    return core::write_file_atomic(file, text, core::Durability::kFlushed);
}

namespace {

using nlohmann::ordered_json;

using detail::write_text;

ordered_json vec(const core::Vec3d& v) {
    return detail::vec_json(v);
}

ordered_json box_json(const core::Box3d& b) {
    if (b.empty()) return nullptr;
    return {{"min", vec(b.min)}, {"max", vec(b.max)}, {"size", vec(b.size())}};
}

ordered_json defect(const mesh::DefectCount& d) {
    ordered_json j{{"count", d.count}};
    if (d.example) j["example"] = vec(*d.example);
    return j;
}

// Bounds (um) of all wires of all slices, in the shared (u, v) frame.
struct Bounds2 {
    double x0 = std::numeric_limits<double>::infinity(), y0 = x0;
    double x1 = -std::numeric_limits<double>::infinity(), y1 = x1;
    [[nodiscard]] bool empty() const { return x0 > x1; }
};

Bounds2 stack_bounds(const SliceStack& stack) {
    Bounds2 b;
    for (const auto& s : stack.slices) {
        for (const auto& n : s.wires.nodes) {
            for (const auto& p : n.wire) {
                b.x0 = std::min(b.x0, static_cast<double>(p.x));
                b.y0 = std::min(b.y0, static_cast<double>(p.y));
                b.x1 = std::max(b.x1, static_cast<double>(p.x));
                b.y1 = std::max(b.y1, static_cast<double>(p.y));
            }
        }
    }
    if (b.empty()) b = {0.0, 0.0, 1000.0, 1000.0};
    return b;
}

// One slice as an SVG path (even-odd fill), in mm, y up turned to SVG's y down by negating.
void append_slice_path(fmt::memory_buffer& out, const slice::Slice& s, double dx, double dy) {
    fmt::format_to(std::back_inserter(out), "<path fill-rule=\"evenodd\" d=\"");
    for (const auto& n : s.wires.nodes) {
        bool first = true;
        for (const auto& p : n.wire) {
            fmt::format_to(std::back_inserter(out), "{}{:.3f} {:.3f} ", first ? "M" : "L",
                           core::um_to_mm(p.x) + dx, -core::um_to_mm(p.y) + dy);
            first = false;
        }
        fmt::format_to(std::back_inserter(out), "Z ");
    }
    fmt::format_to(std::back_inserter(out), "\"/>\n");
}

}  // namespace

std::string info_json(const PreparedPart& part) {
    const auto& r = part.report;
    const auto& im = part.imported;
    ordered_json j;
    j["format"] = io::format_name(im.format);
    j["units"] = {{"source", core::unit_name(im.source_unit)},
                  {"declared_in_file", im.unit_declared}};
    j["triangles"] = r.triangles;
    j["vertices"] = r.vertices;
    j["bodies"] = r.bodies;
    j["solids"] = im.solids;
    j["bounding_box_mm"] = box_json(r.bounding_box);
    j["volume_mm3"] = r.volume_mm3;
    j["surface_area_mm2"] = r.area_mm2;
    j["closed_manifold"] = r.closed_manifold();
    j["inside_out"] = r.inside_out();
    j["defects"] = {{"nonfinite_vertices", defect(r.nonfinite_vertices)},
                    {"degenerate_triangles", defect(r.degenerate_triangles)},
                    {"duplicate_triangles", defect(r.duplicate_triangles)},
                    {"boundary_edges", defect(r.boundary_edges)},
                    {"nonmanifold_edges", defect(r.nonmanifold_edges)},
                    {"misoriented_edges", defect(r.misoriented_edges)}};
    j["repairs"] = part.repairs;
    if (part.repaired_report) {
        const auto& a = *part.repaired_report;
        j["after_repair"] = {{"triangles", a.triangles},
                             {"bodies", a.bodies},
                             {"volume_mm3", a.volume_mm3},
                             {"closed_manifold", a.closed_manifold()},
                             {"defects", a.defects()}};
    }
    j["warnings"] = part.warnings;
    return j.dump(2) + "\n";
}

std::string info_text(const PreparedPart& part) {
    const auto& r = part.report;
    const auto& b = r.bounding_box;
    fmt::memory_buffer out;
    auto it = std::back_inserter(out);
    fmt::format_to(it, "format      {} (units: {}{})\n", io::format_name(part.imported.format),
                   core::unit_name(part.imported.source_unit),
                   part.imported.unit_declared ? ", declared in the file" : "");
    fmt::format_to(it, "triangles   {}\nvertices    {}\nbodies      {}\n", r.triangles, r.vertices,
                   r.bodies);
    if (!b.empty()) {
        fmt::format_to(it, "bounding    ({:.4f}, {:.4f}, {:.4f}) - ({:.4f}, {:.4f}, {:.4f}) mm\n",
                       b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z);
        fmt::format_to(it, "size        {:.4f} x {:.4f} x {:.4f} mm\n", b.size().x, b.size().y,
                       b.size().z);
    }
    fmt::format_to(it, "volume      {:.6g} mm3\narea        {:.6g} mm2\n", r.volume_mm3,
                   r.area_mm2);
    const auto defects = r.defects();
    fmt::format_to(it, "valid       {}\n",
                   defects.empty() ? "yes: closed, manifold, consistently oriented" : "no");
    for (const auto& d : defects) fmt::format_to(it, "  defect    {}\n", d);
    for (const auto& d : part.repairs) fmt::format_to(it, "  repaired  {}\n", d);
    if (part.repaired_report) {
        const auto& a = *part.repaired_report;
        fmt::format_to(
            it, "after repair: {} triangles, {} bodies, volume {:.6g} mm3, {}\n", a.triangles,
            a.bodies, a.volume_mm3,
            a.defects().empty() ? "valid" : fmt::format("{} defects remain", a.defects().size()));
    }
    for (const auto& w : part.imported.warnings) fmt::format_to(it, "  warning   {}\n", w);
    return fmt::to_string(out);
}

core::Result<void> write_slices_json(const std::filesystem::path& file, const SliceStack& stack,
                                     const PreparedPart& part) {
    ordered_json j;
    j["version"] = 1;
    j["units"] = "mm";
    j["part"] = {{"format", io::format_name(part.imported.format)},
                 {"triangles", part.report.triangles},
                 {"volume_mm3", part.report.volume_mm3}};
    j["base"] = {{"origin", vec(stack.base.origin)},
                 {"normal", vec(stack.base.normal)},
                 {"u", vec(stack.base.u)},
                 {"v", vec(stack.base.v)}};
    double volume = 0.0;
    ordered_json layers = ordered_json::array();
    for (const auto& s : stack.slices) {
        ordered_json tree = ordered_json::array();
        for (std::size_t i = 0; i < s.wires.nodes.size(); ++i) {
            const auto& n = s.wires.nodes[i];
            tree.push_back({{"id", i},
                            {"parent", n.parent},
                            {"children", n.children},
                            {"hole", n.is_hole},
                            {"depth", n.depth},
                            {"points", n.wire.size()},
                            {"area_mm2", core::um2_to_mm2(geom2d::signed_area_um2(n.wire))}});
        }
        const double area = s.area_mm2();
        volume += area * s.thickness();
        layers.push_back(
            {{"index", s.index},
             {"bottom_mm", s.span.bottom},
             {"top_mm", s.span.top},
             {"cut_mm", s.span.cut},
             {"thickness_mm", s.thickness()},
             {"plane", {{"origin", vec(s.plane.origin)}, {"normal", vec(s.plane.normal)}}},
             {"area_mm2", area},
             {"outers", s.wires.outer_count()},
             {"holes", s.wires.hole_count()},
             {"gaps_closed", s.gaps_closed},
             {"roots", s.wires.roots},
             {"tree", std::move(tree)}});
    }
    j["layer_count"] = stack.slices.size();
    j["sliced_volume_mm3"] = volume;
    j["layers"] = std::move(layers);
    return write_text(file, j.dump(1) + "\n");
}

namespace {

// The tracks of one layer: deposits as wide strokes, idle moves as thin dashed lines.
void append_toolpath(fmt::memory_buffer& out, const path::LayerToolpath& tp, double width_mm,
                     double dx, double dy) {
    auto it = std::back_inserter(out);
    auto xy = [&](const geom2d::Point2& p) {
        return fmt::format("{:.3f},{:.3f}", core::um_to_mm(p.x) + dx, -core::um_to_mm(p.y) + dy);
    };
    // The bead footprint (track width, faint), then the track centre lines (thin, dark).
    for (const auto& [colour, opacity, width] :
         {std::tuple{"#1f77b4", 0.25, width_mm}, std::tuple{"#0b3c6e", 1.0, 0.12}}) {
        fmt::format_to(it,
                       "<g fill=\"none\" stroke=\"{}\" stroke-opacity=\"{}\" "
                       "stroke-width=\"{:.3f}\" stroke-linecap=\"round\" "
                       "stroke-linejoin=\"round\">\n",
                       colour, opacity, width);
        for (const path::Stroke& st : tp.strokes) {
            fmt::format_to(it, "<polyline points=\"");
            for (const auto& p : st.points) fmt::format_to(it, "{} ", xy(p));
            fmt::format_to(it, "\"/>\n");
        }
        fmt::format_to(it, "</g>\n");
    }
    fmt::format_to(it,
                   "<g fill=\"none\" stroke=\"#d62728\" stroke-width=\"0.15\" "
                   "stroke-dasharray=\"0.8 0.5\">\n");
    for (std::size_t i = 1; i < tp.strokes.size(); ++i) {
        fmt::format_to(it, "<line x1=\"{:.3f}\" y1=\"{:.3f}\" x2=\"{:.3f}\" y2=\"{:.3f}\"/>\n",
                       core::um_to_mm(tp.strokes[i - 1].points.back().x) + dx,
                       -core::um_to_mm(tp.strokes[i - 1].points.back().y) + dy,
                       core::um_to_mm(tp.strokes[i].points.front().x) + dx,
                       -core::um_to_mm(tp.strokes[i].points.front().y) + dy);
    }
    fmt::format_to(it, "</g>\n");
}

}  // namespace

core::Result<void> write_layer_svgs(const std::filesystem::path& dir, const SliceStack& stack,
                                    const std::vector<path::LayerToolpath>* toolpaths,
                                    double track_width_mm) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) return core::fail(core::ErrorCode::kIo, ec.message(), dir.string());
    const Bounds2 b = stack_bounds(stack);
    const double margin = 2.0;
    const double w = core::um_to_mm(static_cast<std::int64_t>(b.x1 - b.x0)) + 2 * margin;
    const double h = core::um_to_mm(static_cast<std::int64_t>(b.y1 - b.y0)) + 2 * margin;
    const double dx = -core::um_to_mm(static_cast<std::int64_t>(b.x0)) + margin;
    const double dy = core::um_to_mm(static_cast<std::int64_t>(b.y1)) + margin;
    for (const auto& s : stack.slices) {
        fmt::memory_buffer out;
        fmt::format_to(std::back_inserter(out),
                       "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.3f}mm\" "
                       "height=\"{:.3f}mm\" viewBox=\"0 0 {:.3f} {:.3f}\">\n"
                       "<title>layer {} of {}: {:.3f}-{:.3f} mm, area {:.3f} mm2, {} outer, {} "
                       "holes</title>\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
                       "<g fill=\"{}\" stroke=\"#2d3047\" stroke-width=\"0.1\">\n",
                       w, h, w, h, s.index + 1, stack.slices.size(), s.span.bottom, s.span.top,
                       s.area_mm2(), s.wires.outer_count(), s.wires.hole_count(),
                       toolpaths != nullptr ? "#f0c9a8" : "#c8553d");
        append_slice_path(out, s, dx, dy);
        fmt::format_to(std::back_inserter(out), "</g>\n");
        if (toolpaths != nullptr && static_cast<std::size_t>(s.index) < toolpaths->size()) {
            append_toolpath(out, (*toolpaths)[static_cast<std::size_t>(s.index)], track_width_mm,
                            dx, dy);
        }
        fmt::format_to(std::back_inserter(out), "</svg>\n");
        auto ok = write_text(dir / fmt::format("layer_{:05d}.svg", s.index + 1),
                             std::string_view(out.data(), out.size()));
        if (!ok) return ok;
    }
    return {};
}

core::Result<void> write_contact_sheet(const std::filesystem::path& file, const SliceStack& stack) {
    const Bounds2 b = stack_bounds(stack);
    const double margin = 2.0;
    const double cw = core::um_to_mm(static_cast<std::int64_t>(b.x1 - b.x0)) + 2 * margin;
    const double ch = core::um_to_mm(static_cast<std::int64_t>(b.y1 - b.y0)) + 2 * margin + 4;
    const std::size_t n = stack.slices.size();
    const auto cols = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(n))));
    const std::size_t rows = cols == 0 ? 0 : (n + cols - 1) / cols;
    fmt::memory_buffer out;
    auto it = std::back_inserter(out);
    fmt::format_to(it,
                   "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {:.3f} {:.3f}\" "
                   "width=\"1600\" height=\"{:.0f}\">\n<rect width=\"100%\" height=\"100%\" "
                   "fill=\"white\"/>\n",
                   cw * static_cast<double>(cols), ch * static_cast<double>(rows),
                   1600.0 * static_cast<double>(rows) /
                       static_cast<double>(std::max<std::size_t>(cols, 1)) * ch / cw);
    for (std::size_t i = 0; i < n; ++i) {
        const auto& s = stack.slices[i];
        const double ox = cw * static_cast<double>(i % cols);
        const double oy = ch * static_cast<double>(i / cols);
        const double dx = ox - core::um_to_mm(static_cast<std::int64_t>(b.x0)) + margin;
        const double dy = oy + core::um_to_mm(static_cast<std::int64_t>(b.y1)) + margin;
        fmt::format_to(it,
                       "<text x=\"{:.2f}\" y=\"{:.2f}\" font-size=\"{:.2f}\" "
                       "font-family=\"sans-serif\">{} ({:.2f} mm)</text>\n",
                       ox + margin, oy + ch - 1, std::min(3.0, cw / 12), s.index + 1, s.span.cut);
        fmt::format_to(it, "<g fill=\"#c8553d\" stroke=\"#2d3047\" stroke-width=\"{:.3f}\">\n",
                       std::max(0.05, cw / 400));
        append_slice_path(out, s, dx, dy);
        fmt::format_to(it, "</g>\n");
    }
    fmt::format_to(it, "</svg>\n");
    return write_text(file, std::string_view(out.data(), out.size()));
}

}  // namespace maxslice::pipeline
