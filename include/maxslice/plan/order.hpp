#pragma once
// Collision control and build order (METHOD.md sections 7 and 8): the nozzle cone, the
// queries "does depositing S2 hit S1", and a topological order of the hierarchy graph in
// which no layer's nozzle meets material deposited before it. See
// docs/decisions/0008-build-order.md.

#include <limits>
#include <string>
#include <vector>

#include "maxslice/core/progress.hpp"
#include "maxslice/core/result.hpp"
#include "maxslice/core/vec3.hpp"
#include "maxslice/plan/planner.hpp"

namespace maxslice::plan {

/// The nozzle together with its powder stream: a cone with its apex at the melt pool, its
/// axis along the layer's build direction, half-angle theta/2 and length H, and optionally a
/// cylinder for the head body above it (METHOD.md section 7). mm and degrees.
struct Nozzle {
    double half_angle_deg = 30.0;  ///< theta/2, in (0, 85]
    double cone_length_mm = 40.0;  ///< H, > 0
    double standoff_mm = 10.0;     ///< melt pool to nozzle tip, in (0, H]
    double body_radius_mm = 0.0;   ///< head body above the cone (0: no body)
    double body_length_mm = 0.0;   ///< its length, >= 0
    /// The smallest clearance accepted between the nozzle (the cone above the standoff, the
    /// body) and deposited material; it also covers the spacing of the points the check
    /// samples. >= 0. The powder stream (the cone between the melt pool and the nozzle tip,
    /// t <= standoff) needs only to stay clear of material (clearance 0).
    double clearance_mm = 1.0;
};

/// Checks ranges; errors (kInvalidInput) name the setting ("nozzle.half_angle_deg").
[[nodiscard]] core::Result<void> validate(const Nozzle& nozzle);

/// Signed clearance (mm) between the nozzle standing with its apex at `apex` and axis
/// `axis` (unit) and the point x: negative inside the cone or the body, the distance to
/// the cone's side (or the body's side) outside. Points at or below the apex's plane
/// (material under the melt pool) and beyond the nozzle's length are out of reach: +inf.
[[nodiscard]] double nozzle_clearance(const Nozzle& nozzle, const core::Vec3d& apex,
                                      const core::Vec3d& axis, const core::Vec3d& x);

/// Settings of the ordering.
struct OrderSettings {
    Nozzle nozzle;
    /// Spacing (mm) of the points sampled on each layer (its boundary and inside, on its
    /// bottom and top faces); 0 = half a track width.
    double sample_spacing_mm = 0.0;
};

/// Two layers the nozzle cannot serve in any order: depositing `layer` would hit `other`,
/// which must be deposited before it (it is an ancestor in the hierarchy graph, or the
/// rest of the order puts it first).
struct Conflict {
    int layer = -1;          ///< the layer being deposited
    int other = -1;          ///< the deposited layer its nozzle hits
    core::Vec3d apex;        ///< where the nozzle stands (on `layer`'s top)
    core::Vec3d hit;         ///< a point of `other` inside the nozzle
    double margin_mm = 0.0;  ///< the clearance there (< the nozzle's clearance_mm, < 0 in
                             ///< the powder stream)
    std::string reason;      ///< one line, for people
    bool in_stream = false;  ///< the hit lies in the powder stream, below the nozzle tip
};

/// A run of consecutive layers of one side (a branch of the hierarchy graph: a chain of
/// layers each deposited on the one before) in the build order (METHOD.md section 8).
struct Section {
    int id = 0;
    int side = 0;  ///< the branch's id
    int region = 0;
    std::vector<int> layers;  ///< in build order
};

/// The build order of a plan.
struct BuildOrder {
    std::vector<int> order;  ///< layer ids in build sequence (partial when conflicts exist)
    /// Per layer id: the smallest margin (mm) between its nozzle and the material deposited
    /// before it: the clearance to the head, or to the powder stream plus the nozzle's
    /// clearance_mm (the stream needs only to stay clear), so at least clearance_mm for every
    /// ordered layer; +inf when nothing is in reach; NaN for a layer not ordered.
    std::vector<double> margin_mm;
    std::vector<int> side_of;     ///< per layer id: its branch
    std::vector<int> section_of;  ///< per layer id: its section (-1 when not ordered)
    std::vector<Section> sections;
    int jumps = 0;      ///< region changes along the order
    int min_jumps = 0;  ///< regions with layers, minus one: the fewest jumps possible
    /// Pairs the graph leaves unordered that the nozzle orders (the first must go first).
    int collision_edges = 0;
    std::vector<Conflict> conflicts;  ///< non-empty: no collision-free order exists

    [[nodiscard]] bool complete() const { return conflicts.empty(); }
    /// The smallest margin over the ordered layers (+inf when none is in reach of anything).
    [[nodiscard]] double smallest_margin_mm() const;
};

/// Orders the plan's layers (METHOD.md sections 7 and 8): every layer after its parents in
/// the hierarchy graph; a layer whose nozzle would hit a layer the graph leaves unordered
/// goes before it; among the layers free to go, the one that continues the current side,
/// then the current region, then the current direction, then the lowest id. Sides that
/// stand on separate bases (an arch's legs) are so grown in turn, each as far as the other
/// side's nozzle allows (the distance-angle method: the clearance is d_min, the cone's
/// half-angle the angle). When no order exists, conflicts name the layers and the order
/// holds the layers placed before the ordering got stuck. Candidate pairs come from a grid
/// over the layers' boxes; the exact test samples points of the deposited layer against the
/// cone swept over the other layer's top. Deterministic, parallel over layers. Errors:
/// invalid nozzle (kInvalidInput), cancelled (kCancelled).
[[nodiscard]] core::Result<BuildOrder> order_layers(const Plan& plan, const OrderSettings& settings,
                                                    const core::Progress* progress = nullptr);

}  // namespace maxslice::plan
