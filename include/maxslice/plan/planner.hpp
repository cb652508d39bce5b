#pragma once
// The multi-axis planner: regions, layers, decisions and the hierarchy graph
// (METHOD.md sections 3 to 6). See docs/decisions/0007-multi-axis-planner.md.

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "maxslice/core/progress.hpp"
#include "maxslice/core/result.hpp"
#include "maxslice/core/vec3.hpp"
#include "maxslice/geom2d/wire_tree.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"
#include "maxslice/plan/analysis.hpp"
#include "maxslice/plan/nozzle.hpp"
#include "maxslice/slice/layers.hpp"
#include "maxslice/slice/plane_frame.hpp"
#include "maxslice/slice/slicer.hpp"

namespace maxslice::plan {

/// Settings of the planner, in mm and degrees.
struct PlanSettings {
    double layer_mm = 0.5;              ///< layer thickness h
    double track_width_mm = 2.5;        ///< bead width (slivers narrower than this are ignored)
    double self_supporting_deg = 20.0;  ///< phi_self
    double alpha_deg = 30.0;            ///< Ang_i <= alpha: the process holds the overhang
    double beta_deg = 60.0;           ///< Ang_i > beta: turn the direction by 90 degrees (a split)
    double min_piece_area_mm2 = 0.0;  ///< area tolerance; 0 = one track width squared
    int max_regions = 64;             ///< a part needing more regions is refused
    double h_min_mm = 0.3;            ///< thinnest local thickness of a tilted (wedge) layer
    double h_max_mm = 0.7;            ///< thickest local thickness of a tilted layer
    /// Tilted layers start where the chain of section centroids over a track's height
    /// leans more than this from the build direction (0 = never tilt).
    double tilt_trigger_deg = 10.0;
    int max_tilt_tries = 8;  ///< halvings of a tilt that breaks [h_min, h_max] before giving up
    /// The largest angle (deg) between a region's direction and the base direction: the
    /// table's tilt range (decision 0032). A sideways direction beyond it is turned up to it.
    double max_tilt_deg = 180.0;
    /// The footing (decision 0017): the base region's layers whose top lies within this
    /// height of the plate are laid over the footprint of the part up to the first layer
    /// above it (every later section of that band united with their own), so a rounded or
    /// chamfered bottom edge, or a part touching the plate along a line or at a point, stands
    /// on a straight pad machined off with the plate; 0 = off.
    double footing_mm = 1.0;
    /// Lay the footing from the plate up whatever the walk finds (it is laid only where it
    /// saves a split at the plate otherwise): for a part whose first layers no track fits (a
    /// rounded near-net bottom edge, a part standing on an edge), which the program job plans
    /// again with it (decision 0017).
    bool footing_always = false;
    /// Bodies that float free of the rest and of the plate are left out of the plan and listed
    /// in Plan::free_bodies (decision 0036); false plans them, and their layers rest on nothing.
    bool leave_out_free_bodies = true;
    /// The head the machine builds with: a region split off sideways is built along the
    /// seed's N_s only where the head, standing on it, clears what is built before it and the
    /// plate; otherwise along N_s leaned up (decision 0029). Unset: N_s always.
    std::optional<Nozzle> head;
};

/// Checks ranges (positive sizes, 0 <= alpha <= beta < 180, phi_self in [0, 90), ...);
/// errors (kInvalidInput) name the setting.
[[nodiscard]] core::Result<void> validate(const PlanSettings& settings);

/// A half-space {x : (x - point) . normal >= 0} (mm, part frame; unit normal).
struct HalfSpace {
    core::Vec3d point;
    core::Vec3d normal;
    [[nodiscard]] bool contains(const core::Vec3d& x, double slack_mm = 0.0) const {
        return core::dot(x - point, normal) >= -slack_mm;
    }
};

/// A region: the solid intersected with a convex cell (METHOD.md section 5), built along
/// one direction from its base plane.
struct Region {
    int id = 0;
    int parent = -1;              ///< the region it was split from (-1: the base region)
    core::Vec3d direction;        ///< unit build direction
    slice::PlaneFrame base;       ///< base plane: heights of its layers are measured from it
    std::vector<HalfSpace> cell;  ///< the convex cell (empty: all of space)
    std::vector<int> layers;      ///< its layers' ids, from the base up
};

/// One layer: a slice of a region with the thickness of material under it.
struct Layer {
    int id = 0;
    int region = 0;
    int index_in_region = 0;
    slice::PlaneFrame plane;        ///< the cutting plane (mid-height), normal = build direction
    slice::LayerSpan span;          ///< heights above the region's base plane
    double thickness_min_mm = 0.0;  ///< local thickness range (planar layers: equal)
    double thickness_max_mm = 0.0;
    double thickness_mean_mm = 0.0;  ///< mean over the section (at its centroid for a wedge)
    slice::PlaneFrame top;           ///< the plane the layer's top lies on
    bool tilted = false;             ///< its top is not parallel to its bottom
    geom2d::WireTree wires;          ///< the section clipped to the region's cell (plane frame, um)
    double area_mm2 = 0.0;
    std::vector<int> parents;   ///< layers it is deposited directly on
    std::vector<int> children;  ///< layers deposited directly on it
    bool on_plate = false;      ///< the first layer of the base region stands on the plate
    /// Empty sections lie between it and the layer below it in its region (a body above a
    /// gap): it does not rest on that layer.
    bool after_gap = false;
};

/// What the planner decided at a layer, and why, as fields (describe() words it).
struct Decision {
    enum class Kind {
        kSplit,       ///< Ang > beta: a new region along N_s from a split plane
        kTiltWanted,  ///< alpha < Ang <= beta: a tilted layer is wanted (see docs)
        kFloating,    ///< a piece that does not touch the layer below: a split towards it
        kTilt,        ///< the centroid chain leans: tilted 3D layers start here
        kTiltGaveUp,  ///< no tilt kept the thickness in [h_min, h_max]: a planar layer there
        /// A floating piece straight above L: no sideways direction reaches it; left in its
        /// layer, where it rests on nothing (listed in unsupported_layers)
        kUnreachable,
    };
    Kind kind = Kind::kSplit;
    int region = 0;          ///< the region in which the overhang was found
    int layer = -1;          ///< the lower layer L (-1 when L is in the parent region)
    double height_mm = 0.0;  ///< U's cut height above the region's base plane
    OverhangPiece piece;     ///< the piece that caused it
    int new_region = -1;     ///< the region built sideways (splits)
    int continuation = -1;   ///< the region that carries on along the old direction
    /// Regions that carry on along the old direction beyond the split plane: the features
    /// there that do not grow from the piece (decision 0035), each past a plane of its own.
    std::vector<int> far_regions;
    std::vector<HalfSpace> far_planes;  ///< those planes, the new region's side inside
    HalfSpace split_plane;              ///< the split plane, normal N_s (splits)
    double lean_deg = 0.0;              ///< kTilt: how far the chain of centroids leans (deg)
    /// Splits with the head set (decision 0029): how far the new region's direction leans
    /// from N_s towards the old direction (deg), the head's smallest margin from what is
    /// built and the plate along it and along N_s (mm; capped a millimetre above the
    /// clearance), and whether it keeps the clearance. head_checked false: not checked.
    bool head_checked = false;
    double split_lean_deg = 0.0;
    /// How far N_s was turned about L's normal first (signed, deg; 0: not turned). A turn is
    /// tried only when no lean of N_s itself keeps the clearance.
    double split_turn_deg = 0.0;
    /// > 0: no lean or turn of N_s kept the clearance, and the direction was found in a
    /// sample of the sphere within the table's tilt range, this far from N_s (deg).
    double split_searched_deg = 0.0;
    /// Whether the head's reach moved the new region's direction off N_s (lean, turn or
    /// search).
    [[nodiscard]] bool moved_for_reach() const {
        return head_checked &&
               (split_lean_deg > 0.0 || split_turn_deg != 0.0 || split_searched_deg > 0.0);
    }
    double head_margin_mm = 0.0;
    double seed_margin_mm = 0.0;
    bool head_clears = true;
};

/// The footing laid at the plate (decision 0017): its layers are the part's footprint up to
/// the first layer above height_mm.
struct Footing {
    int layers = 0;          ///< footing layers (0: no footing was laid)
    double height_mm = 0.0;  ///< top of the last footing layer above the plate
    double added_mm3 = 0.0;  ///< volume the footing adds to the sections (outside the part)
};

/// A body of the mesh that floats free: on neither the plate nor touching any other
/// body (decision 0036). Nothing can be deposited under it; the plan leaves it out.
struct FreeBody {
    double volume_mm3 = 0.0;
    core::Box3d box;      ///< its bounding box (part frame, mm)
    double gap_mm = 0.0;  ///< a lower bound of its distance to the nearest other body
};

/// The plan of a part.
struct Plan {
    PlanSettings settings;
    core::Vec3d base_direction;
    std::vector<Region> regions;
    /// Ids are indices; regions' layers are contiguous. A slice whose section has several
    /// separate islands gives one layer per island (the same index_in_region).
    std::vector<Layer> layers;
    std::vector<Decision> decisions;
    /// Layers that rest on nothing: not on the plate and without parents (a body floating
    /// free of the rest of the part, material reached only through a gap). They cannot be
    /// built without support from this base; the summary and the plan file list them.
    std::vector<int> unsupported_layers;
    /// Layers without parents where no track fits (every feature of them narrower than the
    /// track): nothing is deposited there, as on any feature that narrow, so they rest on
    /// nothing without a bead on nothing; what stands on them gets tracks only over beads
    /// (decision 0013). Moved here from unsupported_layers by the pipeline, which knows the
    /// toolpaths (pipeline::PlanJobSettings::tracks); plan_part leaves it empty.
    std::vector<int> bare_unsupported_layers;
    /// Bodies left out of the plan: they float free of the rest and of the plate.
    std::vector<FreeBody> free_bodies;
    Footing footing;  ///< the footing at the plate, where one saves a split there

    [[nodiscard]] int split_count() const;
    [[nodiscard]] int tilt_wanted_count() const;
    [[nodiscard]] int tilted_layer_count() const;
    /// Sum over layers of area x mean thickness (mm^3).
    [[nodiscard]] double volume_mm3() const;
};

/// One line, for people, on what the planner decided at d and why, built from d's fields and
/// plan.settings; layers are named "L<id>" (ids of plan.layers). Every text a plan gives is
/// made here, when it is printed.
[[nodiscard]] std::string describe(const Plan& plan, const Decision& d);

/// One line for a run of `count` decisions, next to each other in plan.decisions, where the
/// tilt gave up (Decision::Kind::kTiltGaveUp) above layers first_layer .. last_layer.
[[nodiscard]] std::string describe_tilt_gave_up(const Plan& plan, int first_layer, int last_layer,
                                                std::size_t count);

/// One line, for people, on why region r of the plan exists: the base region, or the split
/// that made it (as a sideways region, or as the continuation on the near side).
[[nodiscard]] std::string describe(const Plan& plan, const Region& r);

/// The split that chose region `region`'s direction: the one that made it sideways, or, for
/// a region that carries on another's direction (a continuation or a far region), that
/// region's, followed back. *from (when given) is the region the split made. Null for the base
/// region and those carrying on its direction.
[[nodiscard]] const Decision* deciding_split(const Plan& plan, int region, int* from = nullptr);

/// Plans a part standing on the plate along base_direction (its lowest point on the base
/// plane): the base region is sliced in uniform layers; every pair of neighbouring layers is
/// analysed (analyse_neighbours); an overhang piece with Ang > beta (or one that does not
/// touch the layer below) splits the region at the lower layer L: what lies beyond the split
/// plane (normal N_s = the part of V_i normal to N_b, through the centre of the contact line)
/// and above L becomes a region built along N_s from the split plane, and what lies on the
/// near side above L a region that carries on along N_b; regions are planned recursively in
/// the order they are made. Then the hierarchy graph is built: within a region each layer
/// is deposited on the one below where they overlap; a region's first layer is deposited on
/// the layers of other regions it touches across its base plane. Acyclic by construction
/// (edges follow region creation order and heights; checked). Deterministic. Errors:
/// invalid settings, an empty mesh, more than max_regions regions (kInvalidInput, naming the
/// layer); cancelled (kCancelled).
[[nodiscard]] core::Result<Plan> plan_part(const mesh::TriangleMesh& mesh,
                                           const core::Vec3d& base_direction,
                                           const PlanSettings& settings,
                                           const core::Progress* progress = nullptr);

/// What a planar (single-direction) build of a slice stack would leave unsupported.
struct PlanarCheck {
    int overhangs = 0;     ///< layers with a piece over beta or floating: splits needed
    int tilts_wanted = 0;  ///< layers with a piece in (alpha, beta] only
    std::vector<OverhangPiece> examples;  ///< the first overhang piece of up to 3 layers
    std::vector<double> heights_mm;       ///< their slices' cut heights
    std::size_t checked_up_to = 0;        ///< slices checked (the check stops after the
                                          ///< block of 64 with the first overhang)
    Footing footing;  ///< laid by check_planar_on_footing where it saves an overhang
};

/// Checks a planar stack (consecutive slices of one direction, as slice_mesh makes them)
/// with the planner's neighbour analysis and look-back, without planning regions: what a
/// 3-axis program of it would deposit on nothing. Each layer is compared with the layer right
/// below and with the layer a track's height below, as the planner's walk does. Parallel over
/// layers; stops after the block of 64 layers that holds the first overhang; deterministic.
[[nodiscard]] core::Result<PlanarCheck> check_planar(std::span<const slice::Slice> slices,
                                                     const PlanSettings& settings);

/// check_planar, with the footing (decision 0017) where it saves an overhang at the plate, as
/// the planner lays it on its base region: when the stack's first overhang starts within a
/// track's height above settings.footing_mm (heights from the stack's base plane, the plate),
/// the slices whose layers' tops lie within footing_mm get the union of their section and
/// every later one up to and with the first above that height, and the stack is checked
/// again; if the overhang still starts there, the footing only moves it up: the slices are
/// left as they were and the first check is returned. Errors: those of check_planar.
[[nodiscard]] core::Result<PlanarCheck> check_planar_on_footing(std::vector<slice::Slice>& slices,
                                                                const PlanSettings& settings);

/// Where a layer is: the area centroid of its section on its plane (mm, part frame); the
/// plane's origin for an empty section.
[[nodiscard]] core::Vec3d centroid_of(const Layer& layer);

/// The layers in an order that respects the graph (Kahn's algorithm, smallest id first);
/// empty when the graph has a cycle.
[[nodiscard]] std::vector<int> topological_order(const Plan& plan);

/// What stands on a layer and on nothing the plate carries: the layer and every layer above
/// it in the graph that no path of the graph joins to a layer on the plate.
struct HangingLoad {
    int layers = 0;
    double volume_mm3 = 0.0;  ///< sum of area x mean thickness, as Plan::volume_mm3
};

/// The load hanging from layer `id` (a layer on nothing, say): what cannot be built without
/// it, nor with it while it rests on nothing.
[[nodiscard]] HangingLoad hanging_from(const Plan& plan, int id);

/// The bodies the plan left out (decision 0036), worded for people: how many, the first one's
/// volume, place and gap to the nearest other body; empty when there are none.
[[nodiscard]] std::string describe_free_bodies(const Plan& plan);

/// hanging_from(plan, id) for people: "N layers, V mm3 (P% of the <whole>), stand on it and on
/// nothing the plate carries", P against plan.volume_mm3().
[[nodiscard]] std::string describe_hanging(const Plan& plan, int id, std::string_view whole);

}  // namespace maxslice::plan
