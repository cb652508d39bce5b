#pragma once
// What the next slice tells about the one below (METHOD.md section 3).

#include <vector>

#include "maxslice/core/result.hpp"
#include "maxslice/core/vec3.hpp"
#include "maxslice/geom2d/polygon.hpp"
#include "maxslice/slice/plane_frame.hpp"

namespace maxslice::plan {

/// Settings of the neighbour analysis, in mm and degrees.
struct AnalysisSettings {
    double track_width_mm = 2.5;        ///< pieces narrower than a track are slivers
    double self_supporting_deg = 20.0;  ///< phi_self: L is grown by h * tan(phi_self)
    double min_piece_area_mm2 = 1.0;    ///< pieces smaller than this are dropped
    /// The height h of the allowance is at most this (mm; 0: no limit). Layers further apart
    /// have empty sections between them (a gap): nothing bridges it, so L is grown by no more
    /// than over the walk's look-back height.
    double max_allowance_height_mm = 0.0;
};

/// How the upper slice U stands on the lower slice L.
enum class Support {
    kCarried,    ///< dA empty: U rests on L (within the self-supporting allowance)
    kOverhang,   ///< dA = dA_1 .. dA_n, part of U sticks out over L
    kUnrelated,  ///< dA = U: U does not touch L at all (another body or branch)
};

/// One overhang piece dA_i with the quantities of METHOD.md section 3.
struct OverhangPiece {
    geom2d::Paths2 region;  ///< dA_i in L's plane frame (um), outers CCW, holes CW
    double area_mm2 = 0.0;
    core::Vec3d C;              ///< C_i: centroid of dA_i on U's plane (mm, part frame)
    core::Vec3d P;              ///< P_i: the point of L closest to C_i, on L's plane
    core::Vec3d V;              ///< V_i = C_i - P_i
    double ang_deg = 0.0;       ///< Ang_i: angle between V_i and L's normal N_b
    bool touches_lower = true;  ///< false when the piece does not meet L (floating)
    /// The boundary line between the piece and the carried part (where dA_i meets L grown):
    /// the centre of its bounding box in L's plane (mm, part frame); the split point of
    /// METHOD.md section 5. Equal to P when the piece does not touch L.
    core::Vec3d contact_center;
};

/// The analysis of one pair of neighbouring slices.
struct NeighbourAnalysis {
    Support support = Support::kCarried;
    std::vector<OverhangPiece> pieces;  ///< largest Ang_i first (ties: larger area first)
};

/// Compares the upper slice U (region `upper` in its own plane frame) with the lower slice L
/// (region `lower` in frame `lower_plane`): U is projected onto L's plane along N_b (L's
/// normal); dA = U - (L grown by h * tan(phi_self)), where h is the distance between the two
/// planes along N_b at U's centroid; slivers narrower than a track are removed (a
/// morphological opening by half a track) and pieces below the area tolerance dropped. An
/// overhang piece whose centroid lies inside L (a ring all round L, a mushroom's cap) is
/// cut into four quadrants about its centroid so that each part points one way. Regions use
/// the positive winding rule (as WireTree paths). Errors: non-positive or non-finite
/// settings (kInvalidInput).
[[nodiscard]] core::Result<NeighbourAnalysis> analyse_neighbours(
    const geom2d::Paths2& lower, const slice::PlaneFrame& lower_plane, const geom2d::Paths2& upper,
    const slice::PlaneFrame& upper_plane, const AnalysisSettings& settings);

/// Whether an overhang piece (um, L's plane frame) rests on `below`, the part's whole section
/// on L's plane (the material of every region's cell, not L's alone), `h_mm` under U: what of
/// the piece lies beyond `below` grown by h tan(phi_self) (h at most the settings' cap) is
/// smaller than the area tolerance. A piece that touches nothing of L but rests so stands on
/// material another region lays (a tip where L's cell cuts a wall at a slant).
[[nodiscard]] bool rests_on_section(const geom2d::Paths2& piece, const geom2d::Paths2& below,
                                    double h_mm, const AnalysisSettings& settings);

/// Angle between two vectors in degrees, in [0, 180]; 0 when either is zero.
[[nodiscard]] double angle_deg(const core::Vec3d& a, const core::Vec3d& b);

/// A region's loops (um, in frame `from`) moved onto the plane of frame `to` along to's normal
/// (orthogonal projection), in to's frame.
[[nodiscard]] geom2d::Paths2 project_paths(const geom2d::Paths2& region,
                                           const slice::PlaneFrame& from,
                                           const slice::PlaneFrame& to);

}  // namespace maxslice::plan
