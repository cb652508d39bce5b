#pragma once
// The planner's state and the steps that share it (docs/method.md sections 3 to 6). Each
// step lives in the file named for it:
//   planner.cpp          the driver: regions in the order they are made, then the graph
//   walk.cpp             the walk over a region's slices and the march of tilted 3D layers
//   neighbours.cpp       what the neighbour analysis of a layer pair asks for: a split, or a
//                        record of a wanted tilt or of an unreachable piece
//   split.cpp            the split plane and the sideways direction (section 5)
//   footing.cpp          the footing at the plate (decision 0017)
//   hierarchy_graph.cpp  one layer per piece and the hierarchy graph (section 6)
//   planar_check.cpp     the same analysis over a planar stack, without regions
//   decision_text.cpp    every text the planner writes for people (describe, refusals)
// Private to plan.

#include <cstddef>
#include <deque>
#include <expected>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "maxslice/core/progress.hpp"
#include "maxslice/core/result.hpp"
#include "maxslice/geom2d/polygon.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"
#include "maxslice/plan/analysis.hpp"
#include "maxslice/plan/planner.hpp"
#include "maxslice/slice/layers.hpp"
#include "maxslice/slice/plane_frame.hpp"
#include "maxslice/slice/slicer.hpp"
#include "reach.hpp"
#include "section_index.hpp"

namespace maxslice::plan::detail {

/// The look-back distance in layers: as many as make a track's height (at least one).
[[nodiscard]] int look_back_layers(const PlanSettings& s);

/// The neighbour analysis the planner's walk and the planar check both run.
[[nodiscard]] AnalysisSettings analysis_settings(const PlanSettings& s);

/// A refusal of the part or its settings (kInvalidInput).
[[nodiscard]] std::unexpected<core::Error> invalid(const std::string& message,
                                                   const std::string& context);

/// A region's uniform slices, cut in batches as the walk asks for them: a walk that stops
/// at a split (most do, in parts that split) does not pay for the slices above it. Each
/// plane's section depends only on its own height (slice::slice_mesh cuts planes
/// independently), so batches give the slices one call for all of them would.
class SliceStack {
public:
    SliceStack(const mesh::TriangleMesh& mesh, const slice::PlaneFrame& base,
               std::vector<slice::LayerSpan> spans)
        : mesh_(mesh), base_(base), spans_(std::move(spans)) {}

    [[nodiscard]] std::size_t size() const { return spans_.size(); }

    /// Slice i (index within the whole stack); valid as long as the stack.
    [[nodiscard]] core::Result<const slice::Slice*> at(std::size_t i);

private:
    // The first batch is small (many walks stop within it); batches double up to this.
    static constexpr std::size_t kMaxBatch = 128;
    const mesh::TriangleMesh& mesh_;
    slice::PlaneFrame base_;
    std::vector<slice::LayerSpan> spans_;
    std::deque<slice::Slice> slices_;  // a deque: later batches move no earlier slice
    std::size_t batch_ = 8;
};

/// The lower layer a region's first layer is analysed against (a continuation region's
/// first layer stands on its parent's last layer).
struct Seed {
    int layer = -1;
};

struct RegionJob {
    int region = 0;
    Seed seed;
};

/// What a walk or a march of a region asks for next. Planner::plan_region runs them in a
/// loop (they used to call each other: a bunny scan nested thousands of calls deep and
/// overflowed the stack).
struct Next {
    enum class Kind {
        kDone,    ///< walked to the top, or split after some layers
        kRewalk,  ///< split at the region's first layer: its cell changed, walk it again
        kMarch,   ///< tilted layers from layer `lower` up
        kResume,  ///< planar layers again from layer `lower`'s top
    };
    Kind kind = Kind::kDone;
    int lower = -1;
};

/// Plans regions in the order they are made (docs/method.md sections 3 to 5), then hands
/// the plan to the hierarchy graph (section 6). One use: run once.
class Planner {
public:
    Planner(const mesh::TriangleMesh& mesh, const PlanSettings& settings,
            const core::Progress* progress)
        : mesh_(mesh),
          s_(settings),
          progress_(progress),
          analysis_(analysis_settings(settings)),
          look_back_(look_back_layers(settings)) {}

    [[nodiscard]] core::Result<Plan> run(const core::Vec3d& base_direction);

private:
    // planner.cpp: slices one region and walks up its layers; stops at the first split (the
    // rest goes to the new regions).
    core::Result<void> plan_region(RegionJob job);

    // walk.cpp
    core::Result<Next> walk(const RegionJob& job, SliceStack& slices, int no_march_from);
    core::Result<Next> march(int rid, int lower);
    core::Result<geom2d::Paths2> section(int rid, const slice::PlaneFrame& plane, double thickness);
    void roll_back(int rid, int keep);

    // neighbours.cpp
    core::Result<std::optional<bool>> check_splits(int rid, int lower, const geom2d::Paths2& u,
                                                   const slice::Slice& s);
    [[nodiscard]] bool stands_on(const geom2d::Paths2& grounded, int rid, int ref,
                                 const OverhangPiece& p) const;
    [[nodiscard]] std::optional<geom2d::Paths2> grounded_from(int rid, int ref) const;
    core::Result<bool> rests_across_cell(int ref, const OverhangPiece& p);
    [[nodiscard]] std::int64_t ground_growth_um(const Layer& l) const;
    [[nodiscard]] bool split_before(int rid, int lower, const OverhangPiece& p) const;
    void record_unreachable(int rid, int lower, const slice::Slice& s, const OverhangPiece& p);
    void record_tilt(int rid, int lower, const slice::Slice& s, const OverhangPiece& p);
    void record_piece(Decision::Kind kind, int rid, int lower, const slice::Slice& s,
                      const OverhangPiece& p);

    // split.cpp
    core::Result<bool> split(int rid, int lower, const slice::Slice& s, const OverhangPiece& p);
    [[nodiscard]] core::Vec3d sideways_of(int lower, const OverhangPiece& p) const;
    [[nodiscard]] bool has_sideways(int lower, const OverhangPiece& p) const;
    [[nodiscard]] core::Vec3d within_tilt(const core::Vec3d& d) const;

    // far_features.cpp: the planes (own side in) that keep a region split off for piece p
    // above layer `lower` apart from features of its cell that do not grow from the piece.
    core::Result<std::vector<HalfSpace>> far_feature_bounds(const Region& child, int lower,
                                                            const OverhangPiece& p);

    // reach.cpp: the direction a region split off sideways is built along (decision 0029).
    // `separate`: only directions whose split plane leaves p's centroid in front of it (the
    // region split has not started, and its near side is walked again).
    core::Result<ReachChoice> direction_by_reach(int lower, const OverhangPiece& p,
                                                 const core::Vec3d& ns,
                                                 const std::vector<HalfSpace>& cell, bool separate);
    // Where no lean or turn of N_s keeps the clearance, a sample of the sphere (decision 0046).
    core::Result<std::optional<ReachChoice>> direction_by_sphere(const OverhangPiece& p,
                                                                 const core::Vec3d& ns,
                                                                 const std::vector<HalfSpace>& cell,
                                                                 const ReachScene& scene,
                                                                 double slack, bool separate);
    // The planes along candidate direction d on which the reach check samples the region
    // split off for piece p: its cell, and the planes' frames from its first layer up.
    struct ReachPlanes {
        std::vector<HalfSpace> cell;
        slice::PlaneFrame base;
        std::vector<double> heights;  // above base, along d
    };
    [[nodiscard]] ReachPlanes reach_planes(const OverhangPiece& p,
                                           const std::vector<HalfSpace>& cell,
                                           const core::Vec3d& d) const;
    // Whether region rid was split off with its direction leaned up from N_s for the head's
    // reach, or continues such a region after a later split: its layers do not tilt towards
    // the centroid chain (decision 0029).
    [[nodiscard]] bool leaned_by_reach(int rid) const;
    [[nodiscard]] double reach_spacing() const;
    ReachScene reach_scene(int lower, PointCloud& top);
    [[nodiscard]] std::vector<std::pair<int, int>> lineage(int lower) const;

    // footing.cpp
    bool retry_footing(int rid, int ref);
    void tally_footing();

    const mesh::TriangleMesh& mesh_;
    PlanSettings s_;
    const core::Progress* progress_;
    AnalysisSettings analysis_;
    int look_back_ = 1;  // layers in a track's height: the look-back distance
    enum class FootingState { kUntried, kOn, kDropped };
    FootingState footing_ = !(s_.footing_mm > 0.0)
                                ? FootingState::kDropped
                                : (s_.footing_always ? FootingState::kOn : FootingState::kUntried);
    // Per layer id: the area x thickness its footing pad adds, or -1 (not a footing layer).
    std::vector<double> footing_added_;
    Plan plan_;
    std::deque<RegionJob> jobs_;
    std::optional<SectionIndex> sections_;
    std::optional<PointCloud> surface_;  // the part's surface, for the reach of the head
};

/// The refusal of a piece that floats straight above the layer below (decision_text.cpp).
[[nodiscard]] std::string unreachable_refusal(const OverhangPiece& p);

/// The refusal of a part that needs more than max_regions regions (decision_text.cpp).
[[nodiscard]] std::string too_many_regions_refusal(int max_regions);

/// One layer per piece (hierarchy_graph.cpp).
void split_pieces(Plan& plan);

/// The hierarchy graph of a plan whose layers are pieces (hierarchy_graph.cpp): edges,
/// unsupported_layers; kInternal on a cycle.
[[nodiscard]] core::Result<void> build_graph(Plan& plan);

}  // namespace maxslice::plan::detail
