// The near-net shape on narrow-band signed distance fields (OpenVDB). This file is the only
// place that includes OpenVDB (docs/decisions/0025-near-net-shape.md).
//
// With X the finished part, r = fill_below_mm / 2 and s = stock_mm, the deposit is the closing
// of X by a ball of radius r, grown by s: dilate(close(X, r), s).
// 1. The closing, on a coarse grid (voxel ~ r / 4: it only has to find what is narrower than
//    2 r): with D the signed distance of X (negative inside), Y = {D <= r} is X dilated by r;
//    D1 is Y's own signed distance (a rebuild: where the dilated surfaces of two walls merge,
//    D - r is no longer a distance); C = {D1 <= -r} is Y eroded by r. C's surface is only as
//    good as the coarse grid, so the deposit keeps X itself too: X u C. Where X's surface is
//    flat, C's coarse surface stands out of it by up to about a third of a coarse voxel, in
//    scattered bumps; grown, they would hang below a flat underside as islands in the air. So
//    C is taken a little deeper, at D1 <= -(r + e), e = half a coarse voxel but at most s:
//    the band of width e it then leaves along the walls of a filled hole is within s of both
//    sides, and the growth fills it. Fills that open at the plate are carried down to it
//    (fills_down_to_the_plate).
// 2. The growth, on the fine grid (voxel ~ s / 2): the union's distance is the smaller of X's
//    and C's (exact outside, which is all the isovalue s > 0 needs), meshed at s.
// The closing adds nothing when r <= s (a hole narrower than 2 s is filled by the stock alone:
// dilate(close(X, r), s) = dilate(X, s) then), and is skipped.

#include "maxslice/nearnet/near_net.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <new>
#include <numbers>
#include <optional>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/LevelSetRebuild.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <openvdb/util/NullInterrupter.h>

#include "maxslice/core/units.hpp"
#include "maxslice/geom2d/polygon.hpp"
#include "maxslice/mesh/holes.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"
#include "maxslice/mesh/validation.hpp"

namespace maxslice::nearnet {
namespace {

using core::ErrorCode;

// The fine voxel is this share of the stock: the field resolves the grown surface to a small
// fraction of the stock. (Without stock it is the closing's voxel.)
constexpr double kVoxelsPerStock = 2.0;
// The closing's voxel is this share of the fill radius: enough to tell a hole of diameter
// 2 r from a wider one; its surface is not kept where X's own is outside it.
constexpr double kVoxelsPerFillRadius = 4.0;
// The closing's voxel is at least this many fine voxels: on a large part (a fine voxel
// coarsened by the surface bound) its band, r deep on both sides of the rebuild, would cost
// several times the growth's; the threshold is then found to about a coarse voxel.
constexpr double kCoarseOverFine = 2.0;
// The closing is taken this many coarse voxels deeper than its radius (at most the stock),
// below its surface's error where X's surface is flat (header, step 1).
constexpr double kClosingDepthVoxels = 0.5;
// A finer voxel is never needed: the machine takes off stock, it does not deposit to 20 um.
constexpr double kMinVoxelMm = 0.05;
// Bound on the fine grid's voxels at the surface (its band is a few voxels deep): a larger
// part gets a coarser voxel, so that the work, the memory (~100 MB) and the mesh (~2 triangles
// a surface voxel before simplification) stay bounded whatever the part.
constexpr double kMaxSurfaceVoxels = 2.5e5;
// The coarsest fine voxel accepted, in stocks. The field is exact at the voxels, and the
// surface between them cuts chords of the rounded stock around convex edges, about h^2 / (4 s)
// deep (half the stock at this bound; flat faces keep the whole stock). Beyond it the field
// cannot resolve the stock, and the part is refused rather than given less stock than asked.
constexpr double kMaxVoxelsInStock = 2.0;
// Voxels of band beyond what the isovalues need (interpolation at the surface).
constexpr double kBandMarginVoxels = 2.0;
// The near-net shape's volume is at least this share of the finished part's: it holds the part
// grown by the stock, and its surface lies within a fraction of a voxel of the grown one.
constexpr double kLeastVolumeShare = 0.99;
// volumeToMesh's adaptivity: facets merged where the surface is flat to this share of a voxel;
// the mesh stays closed and the deviation far below the stock.
constexpr double kAdaptivity = 0.05;

// A voxel of the closing counts as a fill, or as air under one, when its centre lies at least
// this many voxels outside the part (not on its surface, where the closing's coarse surface
// stands out by up to a third of a voxel).
constexpr double kFillClearOfPartVoxels = 0.25;
// How far inside C (in voxels) a fill carried down to the plate puts the voxel on the plate:
// with the voxel under it a voxel outside, C's surface lies within a thousandth of a voxel of
// the plate.
constexpr double kOnPlateVoxels = 1e-3;

// Beyond this the plan's integer micrometres would overflow: the grids keep the part's axes.
constexpr double kMaxPlanMm = 1e6;

// The part's plan angle about Z (radians in [0, pi)), which turns with the part: the long side
// of the hull of its vertices' XY projection (geom2d::long_side_angle, the raster's rule).
double plan_angle(const mesh::TriangleMesh& part) {
    geom2d::Path2 plan;
    plan.reserve(part.vertices.size());
    for (const core::Vec3d& v : part.vertices) {
        if (!(std::abs(v.x) < kMaxPlanMm && std::abs(v.y) < kMaxPlanMm)) return 0.0;
        plan.push_back({core::mm_to_um(v.x), core::mm_to_um(v.y)});
    }
    return geom2d::long_side_angle({plan});
}

// The grids' frame is the part's own: turned about Z to the long side of its plan (plan_angle,
// modulo a quarter turn, by which the square lattice maps onto itself), then by the quarter
// turn that puts the vertices' mean in the frame's first quadrant (the long side is a line
// without a direction; OpenVDB's adaptive mesher, merging within leaves counted from the
// index origin, does not map onto itself by a half turn of the lattice), centred on the part's
// box in that frame in X and Y, at its lowest point in Z. The voxels then fall on the part the
// same way however it is turned about Z, and so does the near-net shape (the planner's verdict
// would otherwise change with the voxels' fall on a filled hole or a grazing face); small
// coordinates keep the float precision of the fields and of the extracted points. In X and Y
// the voxel centres lie half a voxel off the box's middle: a face a whole number of voxels
// from the middle (common in parts drawn in round numbers) is not grown onto a plane of
// voxels, where the turn's rounding would decide on which side of the isovalue each voxel
// falls.
class GridFrame {
public:
    explicit GridFrame(const mesh::TriangleMesh& part) {
        const double angle = std::fmod(plan_angle(part), 0.5 * std::numbers::pi);
        const geom2d::PlaneTurn turn = geom2d::plane_turn(angle);
        c_ = turn.c;
        s_ = turn.s;
        // The quarter turn of the frame that puts the vertices' mean, seen from the box's
        // middle, in its first quadrant (none where the mean is at the middle: the part is then
        // symmetric enough that the other quarter turns give the same voxels, up to a mirror;
        // four quarter turns are the frame again). A quarter turn maps the box onto the turned
        // frame's box, so its middle and lowest point turn with it.
        const Box b = box(part);
        core::Vec3d middle = (b.lo + b.hi) * 0.5;
        core::Vec3d seen = b.mean - middle;
        for (int k = 0; k < 4 && !(seen.x > kMeanTie && seen.y > -kMeanTie); ++k) {
            const double c = c_;
            c_ = -s_;
            s_ = c;
            seen = {seen.y, -seen.x, 0.0};
            middle = {middle.y, -middle.x, middle.z};
        }
        origin_ = {middle.x, middle.y, b.lo.z};
    }
    // A point of the part in the index space of a grid of `voxel`.
    [[nodiscard]] core::Vec3d to_index(const core::Vec3d& p, double voxel) const {
        return (turned(p) - origin_) * (1.0 / voxel) + kCellShift;
    }
    // A point a grid of `voxel` gives (its index times the voxel) in the part's frame.
    [[nodiscard]] core::Vec3d to_part(const core::Vec3d& q, double voxel) const {
        const core::Vec3d t = q - kCellShift * voxel + origin_;
        return {c_ * t.x - s_ * t.y, s_ * t.x + c_ * t.y, t.z};
    }
    // A point a grid of `from` gives, in the index space of a grid of `to`.
    [[nodiscard]] static core::Vec3d reindexed(const core::Vec3d& q, double from, double to) {
        return (q - kCellShift * from) * (1.0 / to) + kCellShift;
    }

private:
    static constexpr core::Vec3d kCellShift{0.5, 0.5, 0.0};
    // Below this (mm) the vertices' mean is on an axis of the frame (float noise: ~1e-5 mm).
    static constexpr double kMeanTie = 1e-3;
    struct Box {
        core::Vec3d lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
                       std::numeric_limits<double>::max()};
        core::Vec3d hi = -lo;
        core::Vec3d mean;  // of the vertices
    };
    // The part's box and the mean of its vertices, in the frame.
    [[nodiscard]] Box box(const mesh::TriangleMesh& part) const {
        Box b;
        core::Vec3d sum;
        for (const core::Vec3d& v : part.vertices) {
            const core::Vec3d t = turned(v);
            b.lo = {std::min(b.lo.x, t.x), std::min(b.lo.y, t.y), std::min(b.lo.z, t.z)};
            b.hi = {std::max(b.hi.x, t.x), std::max(b.hi.y, t.y), std::max(b.hi.z, t.z)};
            sum = sum + t;
        }
        if (!part.vertices.empty())
            b.mean = sum * (1.0 / static_cast<double>(part.vertices.size()));
        return b;
    }
    [[nodiscard]] core::Vec3d turned(const core::Vec3d& p) const {
        return {c_ * p.x + s_ * p.y, -s_ * p.x + c_ * p.y, p.z};
    }
    double c_ = 1.0;
    double s_ = 0.0;
    core::Vec3d origin_;
};

// Our mesh as OpenVDB's mesh adapter wants it: corners in the grid's index space (the grids'
// frame, in voxels), read on the fly in double.
class IndexSpaceMesh {
public:
    IndexSpaceMesh(const mesh::TriangleMesh& m, const GridFrame& frame, double voxel)
        : mesh_(m), frame_(frame), voxel_(voxel) {}
    [[nodiscard]] std::size_t polygonCount() const { return mesh_.triangles.size(); }
    [[nodiscard]] std::size_t pointCount() const { return mesh_.vertices.size(); }
    [[nodiscard]] std::size_t vertexCount(std::size_t) const { return 3; }
    void getIndexSpacePoint(std::size_t n, std::size_t v, openvdb::Vec3d& pos) const {
        const core::Vec3d p = frame_.to_index(mesh_.corner(n, static_cast<int>(v)), voxel_);
        pos = openvdb::Vec3d(p.x, p.y, p.z);
    }

private:
    const mesh::TriangleMesh& mesh_;
    const GridFrame& frame_;
    double voxel_;
};

// Cancels OpenVDB's long loops when the caller cancels the job.
class Interrupter : public openvdb::util::NullInterrupter {
public:
    explicit Interrupter(const core::Progress* progress) : progress_(progress) {}
    using openvdb::util::NullInterrupter::wasInterrupted;  // the overload without a percent
    bool wasInterrupted(int /*percent*/ = -1) override {
        return progress_ != nullptr && progress_->cancelled();
    }

private:
    const core::Progress* progress_;
};

// The fine voxel for a part of surface `area_mm2`: a share of the stock (or of the fill radius
// without stock), coarsened to keep the surface voxels under the bound.
double fine_voxel(double area_mm2, double stock, double radius) {
    const double share = stock > 0.0 ? stock / kVoxelsPerStock : radius / kVoxelsPerFillRadius;
    return std::max({share, std::sqrt(area_mm2 / kMaxSurfaceVoxels), kMinVoxelMm});
}

// volumeToMesh's points and polygons as our mesh: quads split along a fixed diagonal, points
// taken back to the part's frame, unused points dropped, normals outward.
mesh::TriangleMesh to_mesh(const std::vector<openvdb::Vec3s>& points,
                           const std::vector<openvdb::Vec3I>& triangles,
                           const std::vector<openvdb::Vec4I>& quads, const GridFrame& frame,
                           double voxel) {
    mesh::TriangleMesh out;
    std::vector<std::uint32_t> index(points.size(), std::numeric_limits<std::uint32_t>::max());
    const auto vertex = [&](unsigned i) {
        if (index[i] == std::numeric_limits<std::uint32_t>::max()) {
            index[i] = static_cast<std::uint32_t>(out.vertices.size());
            const openvdb::Vec3s& p = points[i];
            out.vertices.push_back(frame.to_part(core::Vec3d{p.x(), p.y(), p.z()}, voxel));
        }
        return index[i];
    };
    out.triangles.reserve(triangles.size() + 2 * quads.size());
    // OpenVDB winds its polygons clockwise seen from outside a level set (normals point
    // into the negative region): reversed here to the mesh's counter-clockwise rule.
    // The adaptive mesher collapses corners of some polygons into one point: a triangle with a
    // repeated corner has no area, and its two other edges are one edge both ways, so leaving it
    // out keeps the surface closed.
    const auto add = [&](unsigned a, unsigned b, unsigned c) {
        if (a == b || b == c || c == a) return;
        out.triangles.push_back({vertex(a), vertex(b), vertex(c)});
    };
    for (const openvdb::Vec3I& t : triangles) add(t[0], t[2], t[1]);
    for (const openvdb::Vec4I& q : quads) {
        add(q[0], q[2], q[1]);
        add(q[0], q[3], q[2]);
    }
    return out;
}

// Points and polygons of a mesh made by volumeToMesh, in another grid's index space.
struct IndexPolygons {
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec4I> polygons;  // triangles with index 3 = INVALID_IDX
};

// The closing's fills carried down to the plate. A ball's round end leaves the mouth of a
// filled hole, slot or inside corner open at the plate to a height of up to r - sqrt(r^2 -
// w^2 / 4) + e (w its width): the fill would start above the plate as an overhang over the
// hole, built in the air or by a region of its own, at a height the voxels decide (the cylinder
// with holes turned 113 degrees about Z: 5 regions, against 1 as drawn). In every column of
// the coarse grid whose lowest fill (inside C, clearly outside X) lies within that height and
// has only air under it, the air down to the plate joins C, and the voxel under the plate
// stays out of it (the near-net shape keeps its lowest point). Nothing else changes: a chamfer
// at the plate, or the gap under an overhang near it, has no fill above it and stays as the
// part has it. `part` is X's distance and `closed` D1 (C = {D1 <= -depth}), on one grid whose
// index z is the height over the part's lowest point in voxels.
void fills_down_to_the_plate(const openvdb::FloatGrid& part, openvdb::FloatGrid& closed,
                             double depth, double voxel) {
    const openvdb::CoordBBox box = closed.evalActiveVoxelBoundingBox();
    if (box.empty()) return;
    const int top = static_cast<int>(std::ceil(depth / voxel));  // r + e: the highest mouth
    const float fill_at_most = static_cast<float>(-depth);
    const float air_above = static_cast<float>(kFillClearOfPartVoxels * voxel);
    // Inside C above the plate; on the plate only just inside, and a voxel outside under it,
    // so that C's surface there lies on the plate.
    const float inside = static_cast<float>(-depth - 0.5 * voxel);
    const float on_plate = static_cast<float>(-depth - kOnPlateVoxels * voxel);
    const float outside = static_cast<float>(-depth + voxel);
    openvdb::FloatGrid::ConstAccessor x = part.getConstAccessor();
    openvdb::FloatGrid::Accessor c = closed.getAccessor();
    for (int i = box.min().x(); i <= box.max().x(); ++i) {
        for (int j = box.min().y(); j <= box.max().y(); ++j) {
            int k = 0;
            while (k <= top && x.getValue({i, j, k}) > air_above &&
                   c.getValue({i, j, k}) > fill_at_most) {
                ++k;
            }
            // The fill over air from the plate up: k is its lowest voxel.
            if (k == 0 || k > top || x.getValue({i, j, k}) <= air_above) continue;
            for (int q = 0; q < k; ++q) c.setValue({i, j, q}, q == 0 ? on_plate : inside);
            c.setValue({i, j, -1}, std::max(c.getValue({i, j, -1}), outside));
        }
    }
}

core::Result<IndexPolygons> closing(const mesh::TriangleMesh& finished, const GridFrame& frame,
                                    double radius, double depth, double voxel, double fine_voxel,
                                    Interrupter& interrupter, std::size_t& active) {
    const openvdb::math::Transform::Ptr xform =
        openvdb::math::Transform::createLinearTransform(voxel);
    const IndexSpaceMesh adapter(finished, frame, voxel);
    const float margin = static_cast<float>(kBandMarginVoxels);
    openvdb::FloatGrid::Ptr field = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
        interrupter, adapter, *xform, static_cast<float>(radius / voxel) + margin, margin);
    if (interrupter.wasInterrupted()) {
        return core::fail(ErrorCode::kCancelled, "cancelled", "near-net shape");
    }
    active = std::max(active, static_cast<std::size_t>(field->activeVoxelCount()));
    const openvdb::FloatGrid::Ptr part = field;
    field = openvdb::tools::levelSetRebuild(*part, static_cast<float>(radius), margin,
                                            static_cast<float>(radius / voxel) + margin,
                                            xform.get(), &interrupter);
    if (interrupter.wasInterrupted()) {
        return core::fail(ErrorCode::kCancelled, "cancelled", "near-net shape");
    }
    active = std::max(active, static_cast<std::size_t>(field->activeVoxelCount()));
    fills_down_to_the_plate(*part, *field, depth, voxel);
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(*field, points, triangles, quads, -depth, 0.0, true);
    IndexPolygons out;
    out.points.reserve(points.size());
    for (const openvdb::Vec3s& p : points) {
        const core::Vec3d q =
            GridFrame::reindexed(core::Vec3d{p.x(), p.y(), p.z()}, voxel, fine_voxel);
        out.points.emplace_back(static_cast<float>(q.x), static_cast<float>(q.y),
                                static_cast<float>(q.z));
    }
    out.polygons = std::move(quads);
    for (const openvdb::Vec3I& t : triangles) {
        out.polygons.emplace_back(t[0], t[1], t[2], openvdb::util::INVALID_IDX);
    }
    return out;
}

core::Result<NearNet> compute(const mesh::TriangleMesh& part, const NearNetSettings& settings,
                              const core::Progress* progress) {
    // An open surface (a scan with holes) has no inside for the fields' sign: the flood fill
    // that finds it runs through a hole wider than the band into the part, and the deposit
    // would be a hollow shell around the surface. Its holes are capped first.
    mesh::ValidationReport report = mesh::validate(part);
    const std::size_t open_edges = report.boundary_edges.count;
    std::optional<mesh::CappedMesh> capped;
    if (open_edges > 0) {
        capped = mesh::cap_holes(part);
        report = mesh::validate(capped->mesh);
    }
    const mesh::TriangleMesh& finished = capped ? capped->mesh : part;
    if (report.nonfinite_vertices.count > 0) {
        return core::fail(ErrorCode::kInvalidInput,
                          "the part has non-finite coordinates: no near-net shape",
                          "near-net shape");
    }
    const double stock = settings.stock_mm;
    const double radius = 0.5 * settings.fill_below_mm;
    const double voxel = fine_voxel(report.area_mm2, stock, radius);
    if (stock > 0.0 && voxel > kMaxVoxelsInStock * stock) {
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("the part's {:.0f} mm2 of surface needs {:.3f} mm voxels to stay within "
                        "the bound of {:.2g} voxels, coarser than the {} mm stock can be resolved "
                        "with: a larger stock, or a part in other units (--units), helps",
                        report.area_mm2, voxel, kMaxSurfaceVoxels, stock),
            "near-net shape");
    }
    const GridFrame frame(finished);
    openvdb::initialize();
    Interrupter interrupter(progress);
    NearNet out;
    out.report.voxel_mm = voxel;
    out.report.finished_volume_mm3 = report.volume_mm3;
    out.report.open_edges = open_edges;
    if (capped) out.report.capped_holes = capped->caps;
    const float margin = static_cast<float>(kBandMarginVoxels);
    const float ex_band = static_cast<float>(stock / voxel) + margin;
    const openvdb::math::Transform::Ptr xform =
        openvdb::math::Transform::createLinearTransform(voxel);

    if (progress != nullptr) progress->report("near-net", 0.0);
    const IndexSpaceMesh adapter(finished, frame, voxel);
    openvdb::FloatGrid::Ptr field = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
        interrupter, adapter, *xform, ex_band, margin);
    if (interrupter.wasInterrupted()) {
        return core::fail(ErrorCode::kCancelled, "cancelled", "near-net shape");
    }
    out.report.active_voxels = static_cast<std::size_t>(field->activeVoxelCount());
    if (radius > stock) {
        if (progress != nullptr) progress->report("near-net", 0.3);
        const double coarse = std::max(radius / kVoxelsPerFillRadius, kCoarseOverFine * voxel);
        const double depth = radius + std::min(kClosingDepthVoxels * coarse, stock);
        auto closed = closing(finished, frame, radius, depth, coarse, voxel, interrupter,
                              out.report.active_voxels);
        if (!closed) return std::unexpected(closed.error());
        const openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec4I> c(
            closed->points, closed->polygons);
        openvdb::FloatGrid::Ptr grown = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
            interrupter, c, *xform, ex_band, margin);
        if (interrupter.wasInterrupted()) {
            return core::fail(ErrorCode::kCancelled, "cancelled", "near-net shape");
        }
        openvdb::tools::csgUnion(*field, *grown);
        out.report.active_voxels =
            std::max(out.report.active_voxels, static_cast<std::size_t>(field->activeVoxelCount()));
    }
    if (progress != nullptr) progress->report("near-net", 0.7);
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(*field, points, triangles, quads, stock, kAdaptivity, true);
    field.reset();
    out.mesh = to_mesh(points, triangles, quads, frame, voxel);
    if (out.mesh.triangles.empty()) {
        return core::fail(ErrorCode::kInternal, "the distance field gave an empty surface",
                          "near-net shape");
    }
    out.report.near_net_volume_mm3 = mesh::signed_volume(out.mesh);
    // The deposit holds the finished part grown: a smaller volume means the fields took some of
    // the part's inside for outside (a surface the caps could not close, bodies overlapping
    // inside out), and the deposit would leave it out.
    if (out.report.near_net_volume_mm3 < kLeastVolumeShare * out.report.finished_volume_mm3) {
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("the near-net shape encloses {:.0f} mm3, {:.1f}% of the finished part's "
                        "{:.0f} mm3: its distance field took some of the part's inside for "
                        "outside ({} open edges{}); repair the model's surface, or set "
                        "machining_stock_mm = 0 and fill_below_mm = 0 to deposit the part as "
                        "the file gives it",
                        out.report.near_net_volume_mm3,
                        100.0 * out.report.near_net_volume_mm3 / out.report.finished_volume_mm3,
                        out.report.finished_volume_mm3, out.report.open_edges,
                        out.report.capped_holes > 0
                            ? fmt::format(", {} holes capped", out.report.capped_holes)
                            : std::string()),
            "near-net shape");
    }
    if (progress != nullptr) progress->report("near-net", 1.0);
    return out;
}

}  // namespace

core::Result<void> validate(const NearNetSettings& s) {
    if (!(s.stock_mm >= 0.0 && s.stock_mm <= NearNetSettings::kMaxStockMm)) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("machining stock {} mm is out of range [0, {}] mm",
                                      s.stock_mm, NearNetSettings::kMaxStockMm),
                          "near-net shape");
    }
    if (!(s.fill_below_mm >= 0.0 && s.fill_below_mm <= NearNetSettings::kMaxFillMm)) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("fill threshold {} mm is out of range [0, {}] mm",
                                      s.fill_below_mm, NearNetSettings::kMaxFillMm),
                          "near-net shape");
    }
    return {};
}

core::Result<NearNet> near_net(const mesh::TriangleMesh& finished, const NearNetSettings& settings,
                               const core::Progress* progress) {
    if (auto ok = validate(settings); !ok) return std::unexpected(ok.error());
    if (settings.off()) {
        NearNet out;
        out.mesh = finished;
        return out;
    }
    if (finished.empty()) {
        return core::fail(ErrorCode::kInvalidInput, "the part has no triangles", "near-net shape");
    }
    // Exceptions do not cross the library boundary: OpenVDB throws on bad input and out of
    // memory.
    try {
        return compute(finished, settings, progress);
    } catch (const std::bad_alloc&) {
        return core::fail(ErrorCode::kInvalidInput, "out of memory making the distance field",
                          "near-net shape");
    } catch (const std::exception& e) {
        return core::fail(ErrorCode::kInternal, std::string("OpenVDB: ") + e.what(),
                          "near-net shape");
    }
}

}  // namespace maxslice::nearnet
