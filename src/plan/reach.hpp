// Build directions chosen by reach (docs/method.md section 5, docs/decisions/0029): whether
// the head, standing anywhere on a region about to be split off, clears what is built before
// that region and the plate. Private to plan.
#pragma once

#include <functional>
#include <span>
#include <vector>

#include "box_tree.hpp"
#include "head_profile.hpp"
#include "maxslice/core/result.hpp"
#include "maxslice/core/vec3.hpp"
#include "maxslice/geom2d/polygon.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"
#include "maxslice/plan/nozzle.hpp"
#include "maxslice/slice/plane_frame.hpp"

namespace maxslice::plan::detail {

/// Points of material (mm, part frame) with a tree over them.
class PointCloud {
public:
    PointCloud() = default;
    explicit PointCloud(std::vector<core::Vec3d> points);
    [[nodiscard]] const std::vector<core::Vec3d>& points() const { return points_; }
    [[nodiscard]] const BoxTree& tree() const { return tree_; }

private:
    std::vector<core::Vec3d> points_;
    BoxTree tree_;
};

/// Points along the closed paths (plane frame, um), lifted onto `frame` moved by `lift_mm`
/// along its normal, no two neighbours further apart than spacing_mm.
[[nodiscard]] std::vector<core::Vec3d> boundary_points(const geom2d::Paths2& paths,
                                                       const slice::PlaneFrame& frame,
                                                       double spacing_mm, double lift_mm = 0.0);

/// Grid points spacing_mm apart inside the paths (positive winding), on `frame` moved by
/// lift_mm along its normal.
[[nodiscard]] std::vector<core::Vec3d> interior_points(const geom2d::Paths2& paths,
                                                       const slice::PlaneFrame& frame,
                                                       double spacing_mm, double lift_mm = 0.0);

/// What the head must clear while a region is built: the part's surface on or below the
/// plane `built_below` (what the regions under the split have laid, the other bases
/// included), more material given as points (the top face of the layer the region grows
/// from), and the plate (everything below `plate`).
struct ReachScene {
    const PointCloud* surface = nullptr;
    slice::PlaneFrame built_below;
    const PointCloud* extra = nullptr;
    slice::PlaneFrame plate;
};

/// The smallest margin of the head (HeadProfile::margin: the hardware's gap, the stream's
/// gap plus the clearance) standing with its apex at any of `apexes` and its axis along
/// `axis` (unit), over the scene's material and the plate; `enough` when nothing comes
/// closer than that (the search stops looking further than it).
[[nodiscard]] double reach_margin(const Nozzle& nozzle, const ReachScene& scene,
                                  std::span<const core::Vec3d> apexes, const core::Vec3d& axis,
                                  double enough);

/// ns turned towards n by lean_deg (both unit; ns across n): a sideways direction leaning up.
[[nodiscard]] core::Vec3d leaned(const core::Vec3d& ns, const core::Vec3d& n, double lean_deg);

/// The build direction of a region split off sideways (decision 0029).
struct ReachChoice {
    core::Vec3d direction;        ///< the direction kept
    double lean_deg = 0.0;        ///< its lean from the seed's N_s towards the old direction
    double turn_deg = 0.0;        ///< N_s turned about L's normal by this first (signed)
    double margin_mm = 0.0;       ///< the head's smallest margin along it (capped)
    double seed_margin_mm = 0.0;  ///< along N_s itself
    bool clears = false;          ///< margin_mm >= the nozzle's clearance
    /// > 0: found in a sample of the sphere (no lean or turn of N_s kept the clearance),
    /// this far from N_s (deg).
    double searched_deg = 0.0;
};

/// Directions within max_tilt_deg of `up` (unit), neighbours about step_deg apart: `up`,
/// then rings of polar angle every step_deg, each ring's azimuths counted from the part of
/// `ns` across `up` (a part turned about `up` gets the same directions turned with it).
[[nodiscard]] std::vector<core::Vec3d> sphere_sample(const core::Vec3d& up, const core::Vec3d& ns,
                                                     double max_tilt_deg, double step_deg);

/// A direction to try: the seed's N_s (lean_deg 0) or N_s leaned by lean_deg, after turning
/// it about L's normal by turn_deg.
struct ReachCandidate {
    core::Vec3d direction;
    double lean_deg = 0.0;
    double turn_deg = 0.0;
};

/// Tries the candidates in turn (the first is N_s itself; turned ones, turn_deg != 0, only
/// while no candidate not turned keeps the clearance), and keeps the first along which the
/// head, standing on every apex apexes_along(direction) gives, keeps the nozzle's clearance
/// plus slack_mm (the samples' error) from the scene; none: of those within slack_mm of the
/// largest margin, if that keeps the clearance, the least turned, then the most leaned; else
/// the first with clears = false (decision 0037).
/// Errors: those of apexes_along; kInvalidInput for no candidate.
[[nodiscard]] core::Result<ReachChoice> choose_by_reach(
    const Nozzle& nozzle, const ReachScene& scene, std::span<const ReachCandidate> candidates,
    double slack_mm,
    const std::function<core::Result<std::vector<core::Vec3d>>(const core::Vec3d&)>& apexes_along);

}  // namespace maxslice::plan::detail
