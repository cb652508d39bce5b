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
#include "maxslice/plan/nozzle.hpp"
#include "maxslice/plan/planner.hpp"

namespace maxslice::plan {

/// Settings of the ordering.
struct OrderSettings {
    Nozzle nozzle;
    /// Spacing (mm) of the points sampled on each layer (its boundary and inside, on its
    /// bottom and top faces); 0 = half a track width.
    double sample_spacing_mm = 0.0;
    /// When the order is stuck, measure the collisions on the cycle whose margin the samples'
    /// cover leaves in doubt again on finer samples, and drop those that keep the clearance
    /// (decision 0043). Off: every such collision stands (for tests).
    bool measure_doubtful_again = true;
};

/// Two layers the nozzle cannot serve in any order: depositing `layer` would hit `other`,
/// which must be deposited before it (it is an ancestor in the hierarchy graph, or the
/// rest of the order puts it first).
struct Conflict {
    int layer = -1;    ///< the layer being deposited
    int other = -1;    ///< the deposited layer its nozzle hits
    core::Vec3d apex;  ///< where the nozzle stands (on `layer`'s top)
    core::Vec3d hit;   ///< a point of `other` inside the nozzle
    /// The gap there: to the hardware (< the nozzle's clearance_mm plus the sampling's
    /// cover) or, when in_stream, to the powder stream (< the cover).
    double margin_mm = 0.0;
    std::string reason;      ///< one line, for people
    bool in_stream = false;  ///< the hit lies in the powder stream, below the nozzle tip
    /// What was taken off the hardware's gap at the sample (mm): every point of `other`'s
    /// material lies within this of one of its samples. margin_mm + cover_mm is the gap at
    /// `hit` itself (for a hardware hit).
    double cover_mm = 0.0;
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
    /// before it: nozzle_margin_mm (the gap to the hardware, or to the powder stream plus the
    /// nozzle's clearance_mm) less the sampling's cover, so a lower bound of the true margin
    /// and at least clearance_mm for every ordered layer; +inf when nothing is in reach; NaN
    /// for a layer not ordered.
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

/// For people, when `order` has conflicts: the feature in the way (the region of the first
/// conflict's layer, where it was split off and how big its piece was), why no direction
/// served it (how far it was leaned and whether the head then cleared), the closest gap
/// among the conflicts, and what may help (a slimmer head, another base). Empty when the
/// order is complete.
/// Made in decision_text.cpp with the planner's other texts.
[[nodiscard]] std::string describe_refusal(const Plan& plan, const BuildOrder& order,
                                           const Nozzle& nozzle);

}  // namespace maxslice::plan
