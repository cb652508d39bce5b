#pragma once
// An independent, brute-force check of a build order against the nozzle (METHOD.md section
// 7) for the order tests. Plain geometry only: it shares no code with src/plan/order.cpp
// (its own cone test, its own point-in-polygon test, its own sampling), so a bug there does
// not hide itself here.
//
// For every layer in build order the nozzle stands on points sampled along the layer's
// toolpath (path::plan_layer, strokes resampled at sample_step_mm, lifted to the layer's top
// plane) with its axis along the layer's top normal; every layer deposited before it is
// sampled on its bottom and top faces (its wires' vertices, its edges resampled and an
// interior grid at sample_step_mm). A sample of earlier material strictly above the apex's
// plane and more than tolerance_mm inside the head (stream, nozzle or body) is a collision;
// with a clearance, so is one closer than clearance_mm - tolerance_mm to the hardware (the
// nozzle above its standoff, the body: its rim and underside included).
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "maxslice/core/vec3.hpp"
#include "maxslice/plan/order.hpp"
#include "maxslice/plan/planner.hpp"

namespace maxslice::test {

/// The reference cell's head (examples/profiles/reference_5axis_ac.toml [machine.nozzle]).
[[nodiscard]] inline plan::Nozzle reference_head() {
    plan::Nozzle n;
    n.half_angle_deg = 30.0;
    n.cone_length_mm = 45.0;
    n.standoff_mm = 9.0;
    n.body_radius_mm = 30.0;
    n.body_length_mm = 120.0;
    n.clearance_mm = 1.0;
    return n;
}

/// Sampling and tolerance of the brute-force check (mm).
struct NozzleCheckSettings {
    /// Spacing of the apexes along the strokes, of the points along the wires' edges and of
    /// the interior grid (a sample is at most this far from any point of material).
    double sample_step_mm = 1.0;
    /// A point counts when its clearance is below -tolerance_mm: the nozzle shrunk by this
    /// much, to absorb the difference with the planner's own sampling.
    double tolerance_mm = 0.05;
    /// Stop after this many colliding pairs (0: find them all).
    int max_pairs = 0;
    /// The gap the hardware must keep (mm); 0: contact only.
    double clearance_mm = 0.0;
};

/// One pair (layer, other) whose deepest sample lies inside the nozzle.
struct NozzleCollision {
    int layer = -1;             ///< the layer being deposited
    int other = -1;             ///< the earlier layer whose material the nozzle meets
    core::Vec3d apex;           ///< where the nozzle stands (mm, on layer's top)
    core::Vec3d point;          ///< the deepest sample of `other` inside the nozzle (mm)
    double clearance_mm = 0.0;  ///< cone_clearance_mm there (negative: inside), or with a
                                ///< clearance, hardware_clearance_mm when that is what failed
};

/// "layer 12 hits layer 7 at (x, y, z) from apex (x, y, z), clearance -0.8 mm".
[[nodiscard]] std::string describe(const NozzleCollision& c);

/// Signed clearance (mm) of point x from the whole head (cone and body) with its apex at
/// `apex` and unit axis `axis`: with t the height of x above the apex along the axis and r
/// its distance from the axis, the Euclidean distance in the (t, r) plane to the cone's
/// triangle (apex, H on the axis, the rim) or the body's rectangle, whichever is nearer;
/// inside, minus the depth. +inf at or below the apex's plane (t <= 1e-6).
[[nodiscard]] double cone_clearance_mm(const plan::Nozzle& nozzle, const core::Vec3d& apex,
                                       const core::Vec3d& axis, const core::Vec3d& x);

/// The same for the hardware only: the cone between the standoff and H, and the body.
[[nodiscard]] double hardware_clearance_mm(const plan::Nozzle& nozzle, const core::Vec3d& apex,
                                           const core::Vec3d& axis, const core::Vec3d& x);

/// The same for the powder stream only: the cone up to the standoff.
[[nodiscard]] double stream_clearance_mm(const plan::Nozzle& nozzle, const core::Vec3d& apex,
                                         const core::Vec3d& axis, const core::Vec3d& x);

/// Apexes of a layer (mm, part frame): its toolpath (plan_layer with this track width, the
/// other path settings at their defaults) resampled at step_mm, lifted from the layer plane
/// to its top plane along the top's normal. Empty when the layer gets no tracks; fails the
/// calling test when plan_layer does.
[[nodiscard]] std::vector<core::Vec3d> nozzle_apexes(const plan::Layer& layer,
                                                     double track_width_mm, double step_mm);

/// Samples of a layer's material (mm, part frame): wire vertices, wire edges resampled at
/// step_mm and interior grid points step_mm apart (positive-winding crossing test), each
/// on the bottom face (the layer plane shifted by -thickness_max / 2) and on the top face
/// (projected onto the layer's top plane).
[[nodiscard]] std::vector<core::Vec3d> material_points(const plan::Layer& layer, double step_mm);

/// Whether the point (um, layer plane frame) lies inside the layer's wires: positive
/// winding number over all wires (outers counter-clockwise, holes clockwise).
[[nodiscard]] bool inside_wires(const geom2d::WireTree& wires, double x_um, double y_um);

/// Every pair (layer, earlier layer) of `order` (layer ids of `plan`, possibly partial) in
/// which depositing the layer puts the nozzle into the earlier one, the deepest sample per
/// pair, in build order. Empty when the order is collision-free.
[[nodiscard]] std::vector<NozzleCollision> brute_force_collisions(
    const plan::Plan& plan, std::span<const int> order, const plan::Nozzle& nozzle,
    double track_width_mm, const NozzleCheckSettings& settings = {});

/// The same over a BuildOrder's (complete or partial) order.
[[nodiscard]] std::vector<NozzleCollision> brute_force_collisions(
    const plan::Plan& plan, const plan::BuildOrder& order, const plan::Nozzle& nozzle,
    double track_width_mm, const NozzleCheckSettings& settings = {});

}  // namespace maxslice::test
