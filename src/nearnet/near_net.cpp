// The near-net shape on a narrow-band signed distance field (OpenVDB). This file is the only
// place that includes OpenVDB (docs/decisions/0025-near-net-shape.md).
//
// With X the finished part, r = fill_below_mm / 2 and s = stock_mm, the deposit is the closing
// of X by a ball of radius r, grown by s. On distance fields, with D the signed distance of X
// (negative inside):
//   Y = {D <= r} is X dilated by r; D1 is Y's own signed distance (a rebuild: where the
//   dilated surfaces of two walls merge, D - r is no longer a distance);
//   the deposit is {D1 <= s - r}.
// For s <= r that is Y eroded by r - s: the closing by r grown by s, and inside corners of
// the closing rounded with radius up to r - s (more material there, never less). For s >= r
// it is X dilated by s: a hole narrower than 2 s is filled by the stock alone, and the
// closing adds nothing. Without fill (r = 0) it is {D <= s}, without a rebuild.
#include "maxslice/nearnet/near_net.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <new>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetRebuild.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <openvdb/util/NullInterrupter.h>

#include "maxslice/mesh/validation.hpp"

namespace maxslice::nearnet {
namespace {

using core::ErrorCode;

// Voxels across the smaller of the stock and the fill radius: the distance field resolves the
// stock to a small fraction of itself, and a fillet of the closing to a few facets.
constexpr double kVoxelsPerFeature = 2.0;
// The coarsest voxel still used: the stock (or fill radius) spans at least this many voxels.
// Below it the field would cut the grown surface into the finished part at sharp edges.
constexpr double kMinVoxelsPerFeature = 1.5;
// A finer voxel is never needed: the machine takes off stock, it does not deposit to 20 um.
constexpr double kMinVoxelMm = 0.05;
// Bound on the narrow band's voxels (floats, ~6 bytes each with the tree): ~200 MB and a few
// seconds on two cores. A larger part gets a coarser voxel down to kMinVoxelsPerFeature.
constexpr double kMaxBandVoxels = 3.0e7;
// Voxels of band beyond what the isovalues need (interpolation at the surface).
constexpr double kBandMarginVoxels = 2.0;

// Our mesh as OpenVDB's mesh adapter wants it: corners in the grid's index space (relative to
// the part's lower corner, in voxels), read on the fly in double.
class IndexSpaceMesh {
public:
    IndexSpaceMesh(const mesh::TriangleMesh& m, const core::Vec3d& origin, double voxel)
        : mesh_(m), origin_(origin), inv_voxel_(1.0 / voxel) {}
    [[nodiscard]] std::size_t polygonCount() const { return mesh_.triangles.size(); }
    [[nodiscard]] std::size_t pointCount() const { return mesh_.vertices.size(); }
    [[nodiscard]] std::size_t vertexCount(std::size_t) const { return 3; }
    void getIndexSpacePoint(std::size_t n, std::size_t v, openvdb::Vec3d& pos) const {
        const core::Vec3d p = (mesh_.corner(n, static_cast<int>(v)) - origin_) * inv_voxel_;
        pos = openvdb::Vec3d(p.x, p.y, p.z);
    }

private:
    const mesh::TriangleMesh& mesh_;
    core::Vec3d origin_;
    double inv_voxel_;
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

// The voxel edge for a part of surface `area_mm2` and the settings: kVoxelsPerFeature across
// the smaller non-zero of stock and fill radius, coarsened while the band's estimated voxels
// exceed the bound. 0 when even the coarsest allowed voxel exceeds it.
struct VoxelChoice {
    double voxel_mm = 0.0;
    double estimated_voxels = 0.0;
    double coarsest_mm = 0.0;
};

double band_voxels(double area_mm2, double voxel, double band_mm) {
    // Surface voxels times the band's thickness in voxels, both sides.
    return area_mm2 / (voxel * voxel) * (band_mm / voxel + 2.0 * kBandMarginVoxels);
}

VoxelChoice choose_voxel(double area_mm2, double stock, double radius) {
    const double feature =
        stock > 0.0 && radius > 0.0 ? std::min(stock, radius) : std::max(stock, radius);
    // The widest band the field needs: dilation by r (and the stock beyond it).
    const double band_mm = std::max(stock, radius) + std::abs(stock - radius);
    VoxelChoice c;
    c.coarsest_mm = feature / kMinVoxelsPerFeature;
    double voxel = std::max(feature / kVoxelsPerFeature, kMinVoxelMm);
    // Voxels fall with the square of the edge (and the band's depth with the edge): coarsen by
    // the cube root of the excess, then check.
    for (int i = 0; i < 8; ++i) {
        c.estimated_voxels = band_voxels(area_mm2, voxel, band_mm);
        if (c.estimated_voxels <= kMaxBandVoxels) break;
        voxel *= std::max(1.01, std::cbrt(c.estimated_voxels / kMaxBandVoxels));
    }
    if (voxel > c.coarsest_mm) {
        voxel = c.coarsest_mm;
        c.estimated_voxels = band_voxels(area_mm2, voxel, band_mm);
    }
    if (c.estimated_voxels <= kMaxBandVoxels) c.voxel_mm = voxel;
    return c;
}

// volumeToMesh's points and polygons as our mesh: quads split along a fixed diagonal, points
// shifted back to the part frame, unused points dropped, normals outward.
mesh::TriangleMesh to_mesh(const std::vector<openvdb::Vec3s>& points,
                           const std::vector<openvdb::Vec3I>& triangles,
                           const std::vector<openvdb::Vec4I>& quads, const core::Vec3d& origin) {
    mesh::TriangleMesh out;
    std::vector<std::uint32_t> index(points.size(), std::numeric_limits<std::uint32_t>::max());
    const auto vertex = [&](unsigned i) {
        if (index[i] == std::numeric_limits<std::uint32_t>::max()) {
            index[i] = static_cast<std::uint32_t>(out.vertices.size());
            const openvdb::Vec3s& p = points[i];
            out.vertices.push_back(origin + core::Vec3d{p.x(), p.y(), p.z()});
        }
        return index[i];
    };
    out.triangles.reserve(triangles.size() + 2 * quads.size());
    // OpenVDB winds its polygons clockwise seen from outside a level set (normals point
    // into the negative region): reversed here to the mesh's counter-clockwise rule.
    for (const openvdb::Vec3I& t : triangles) {
        out.triangles.push_back({vertex(t[0]), vertex(t[2]), vertex(t[1])});
    }
    for (const openvdb::Vec4I& q : quads) {
        const auto a = vertex(q[0]), b = vertex(q[1]), c = vertex(q[2]), d = vertex(q[3]);
        out.triangles.push_back({a, c, b});
        out.triangles.push_back({a, d, c});
    }
    return out;
}

core::Result<NearNet> compute(const mesh::TriangleMesh& finished, const NearNetSettings& settings,
                              const core::Progress* progress) {
    const mesh::ValidationReport report = mesh::validate(finished);
    if (report.nonfinite_vertices.count > 0) {
        return core::fail(ErrorCode::kInvalidInput,
                          "the part has non-finite coordinates: no near-net shape",
                          "near-net shape");
    }
    const double stock = settings.stock_mm;
    const double radius = 0.5 * settings.fill_below_mm;
    const VoxelChoice choice = choose_voxel(report.area_mm2, stock, radius);
    if (choice.voxel_mm <= 0.0) {
        return core::fail(
            ErrorCode::kInvalidInput,
            fmt::format("the part's {:.0f} mm2 of surface would need about {:.2g} voxels of "
                        "{:.3f} mm for a {} mm stock and {} mm fill (bound {:.2g}): a larger "
                        "stock or fill threshold, or a part in other units (--units), helps",
                        report.area_mm2, choice.estimated_voxels, choice.coarsest_mm, stock,
                        settings.fill_below_mm, kMaxBandVoxels),
            "near-net shape");
    }
    const double voxel = choice.voxel_mm;
    // The grid's index space starts at the part's lower corner: small index coordinates keep
    // the float precision of the field and of the extracted points.
    const core::Vec3d origin = report.bounding_box.min;
    openvdb::initialize();
    const openvdb::math::Transform::Ptr xform =
        openvdb::math::Transform::createLinearTransform(voxel);
    Interrupter interrupter(progress);
    const IndexSpaceMesh adapter(finished, origin, voxel);
    NearNet out;
    out.report.voxel_mm = voxel;
    out.report.finished_volume_mm3 = report.volume_mm3;

    const float in_band = static_cast<float>(kBandMarginVoxels);
    const float first_ex =
        static_cast<float>((radius > 0.0 ? radius : stock) / voxel + kBandMarginVoxels);
    if (progress != nullptr) progress->report("near-net", 0.0);
    openvdb::FloatGrid::Ptr field = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
        interrupter, adapter, *xform, first_ex, in_band);
    if (interrupter.wasInterrupted(0)) {
        return core::fail(ErrorCode::kCancelled, "cancelled", "near-net shape");
    }
    out.report.active_voxels = static_cast<std::size_t>(field->activeVoxelCount());
    double isovalue = stock;
    if (radius > 0.0) {
        if (progress != nullptr) progress->report("near-net", 0.4);
        const float ex =
            static_cast<float>(std::max(stock - radius, 0.0) / voxel + kBandMarginVoxels);
        const float in =
            static_cast<float>(std::max(radius - stock, 0.0) / voxel + kBandMarginVoxels);
        field = openvdb::tools::levelSetRebuild(*field, static_cast<float>(radius), ex, in,
                                                xform.get(), &interrupter);
        if (interrupter.wasInterrupted(0)) {
            return core::fail(ErrorCode::kCancelled, "cancelled", "near-net shape");
        }
        out.report.active_voxels =
            std::max(out.report.active_voxels, static_cast<std::size_t>(field->activeVoxelCount()));
        isovalue = stock - radius;
    }
    if (progress != nullptr) progress->report("near-net", 0.7);
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(*field, points, triangles, quads, isovalue, 0.0, true);
    field.reset();
    out.mesh = to_mesh(points, triangles, quads, origin);
    if (out.mesh.triangles.empty()) {
        return core::fail(ErrorCode::kInternal, "the distance field gave an empty surface",
                          "near-net shape");
    }
    out.report.near_net_volume_mm3 = mesh::signed_volume(out.mesh);
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
