#pragma once
// Parts built in code for the multi-axis planner's tests (METHOD.md sections 3-8 and 13).
//
// Every part stands on the plate z = 0 with +Z up, is sized for the reference process (2.5 mm
// track, 0.5 mm layers: features several tracks wide) and is ONE closed, manifold, consistently
// outward-oriented body with shared vertices. Parts that combine primitives along different
// axes (boss on a block, cylinder across a column) are built from closed pieces that touch
// along identically triangulated faces and are fused into one body (see fused()), so no
// fixture relies on the slicer's union of overlapping loops.
//
// Analytic values are those of the polygons actually built (a regular n-gon, not the circle
// it approximates), so tests measure the code under test, not the faceting; the exceptions
// are the swept leaning column and helical ring, whose volumes are those of the smooth sweeps
// (see PlannerFixture::volume_accuracy). Sections "at z" are taken just above z, as in
// fixtures.hpp.
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "maxslice/core/vec3.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"
#include "support/fixtures.hpp"

namespace maxslice::test {

/// A part for the planner's tests with the values a test compares against.
struct PlannerFixture {
    std::string name;
    std::string description;  ///< the shape, and what the planner is expected to do with it
    mesh::TriangleMesh mesh;  ///< one closed, manifold, outward-oriented body (mm)
    double volume_mm3 = 0.0;  ///< analytic volume of the solid
    /// Largest relative difference between volume_mm3 and the mesh's volume that the
    /// construction allows: rounding only (1e-9) where volume_mm3 is that of the polygons
    /// built, the faceting error of a smooth sweep otherwise.
    double volume_accuracy = 1e-9;
    core::Box3d box;  ///< analytic bounding box (mm)
    /// Area (mm^2) of the horizontal section just above height z (mm); empty when the part
    /// has no simple closed form (leaning column).
    std::function<double(double z)> area_at;
};

// ---- Construction helpers --------------------------------------------------------------------

/// Triangulates a simple counter-clockwise polygon with holes (each hole a simple polygon
/// strictly inside it, given counter-clockwise; holes do not touch each other) by ear clipping,
/// preferring well-shaped ears. The cap's vertices are exactly the given points, so pieces that
/// list the same shared points join without T-junctions. Throws std::invalid_argument when the
/// input is not such a polygon.
[[nodiscard]] Cap polygon_cap(std::span<const CapPoint> outer,
                              std::span<const std::vector<CapPoint>> holes = {});

/// Fuses closed bodies that touch along faces triangulated identically on both sides (same
/// vertex coordinates, bit for bit): welds equal vertices, removes each pair of coincident
/// opposite triangles and the vertices left unused. The result is one closed body when the
/// pieces are connected through such faces.
[[nodiscard]] mesh::TriangleMesh fused(std::span<const mesh::TriangleMesh> bodies);

/// Extrudes a cap drawn in the (x, z) plane along +Y over [y0, y1] (mm).
[[nodiscard]] mesh::TriangleMesh extrude_xz(const Cap& profile, double y0, double y1);
/// Extrudes a cap drawn in the (y, z) plane along +X over [x0, x1] (mm).
[[nodiscard]] mesh::TriangleMesh extrude_yz(const Cap& profile, double x0, double x1);

/// A block 20 x 20 x 10 whose bottom edge along Y is chamfered `run` mm in over the first
/// `rise` mm, as the rounded or chamfered bottom edge of a machined part is (the footing,
/// decision 0017). Volume 4000 - 10 run rise.
[[nodiscard]] mesh::TriangleMesh chamfered_block(double run, double rise);

// ---- 1. Vertical walls -----------------------------------------------------------------------

/// An L-profile prism: the union of [0, leg_length] x [0, leg_width] and [0, leg_width] x
/// [0, leg_length] in XY, extruded over z in [0, height]. Every layer rests fully on the one
/// below (METHOD.md section 3, case "dA empty").
struct PrismSpec {
    double leg_length = 40.0;  ///< mm
    double leg_width = 12.0;   ///< mm, less than leg_length
    double height = 30.0;      ///< mm
};
[[nodiscard]] PlannerFixture vertical_prism(const PrismSpec& spec = {});

/// A cylinder (regular `segments`-gon of radius `radius` centred on the Z axis) over z in
/// [0, height] with `holes` vertical through-holes (regular `hole_segments`-gons of radius
/// hole_radius) centred on the circle of radius hole_circle_radius at angles 360 k / holes
/// degrees from +X. Holes are deposited, not machined (section 13).
struct HoledCylinderSpec {
    double radius = 30.0;              ///< mm
    double height = 20.0;              ///< mm
    int holes = 4;                     ///< at least 1
    double hole_radius = 4.0;          ///< mm
    double hole_circle_radius = 15.0;  ///< mm, distance of the hole centres from the axis
    int segments = 64;                 ///< of the outer polygon, a multiple of 4
    int hole_segments = 32;            ///< of each hole, a multiple of 4
};
[[nodiscard]] PlannerFixture cylinder_with_holes(const HoledCylinderSpec& spec = {});

// ---- 2. Slopes -------------------------------------------------------------------------------

/// A wedge whose sloped face leans out over its base: in the (x, z) plane the trapezoid
/// (0, 0), (base_length, 0), (base_length + height tan(lean), height), (0, height), extruded
/// over y in [0, depth]. The face at x = 0 is vertical; the sloped face overhangs by lean
/// degrees from vertical (45: the section grows by one layer height per layer, a slight
/// change, section 4).
struct RampSpec {
    double base_length = 10.0;  ///< mm, along X at z = 0
    double height = 20.0;       ///< mm
    double depth = 20.0;        ///< mm, along Y
    double lean_deg = 45.0;     ///< overhang of the sloped face from vertical, in [0, 60]
};
[[nodiscard]] PlannerFixture ramp_45(const RampSpec& spec = {});

/// An upright cone or frustum on its base, centred on the Z axis: regular `segments`-gon
/// sections whose circumradius falls linearly from base_radius at z = 0 to top_radius at
/// z = height (0: a pointed cone). Its slopes lean inwards: no overhang.
struct ConeSpec {
    double base_radius = 20.0;  ///< mm
    double top_radius = 0.0;    ///< mm, in [0, base_radius)
    double height = 20.0;       ///< mm
    int segments = 64;          ///< a multiple of 4
};
[[nodiscard]] PlannerFixture cone(const ConeSpec& spec = {});

// ---- 3. A boss sticking out sideways ---------------------------------------------------------

/// The bearing seat of METHOD.md sections 5 and 13: the block [0, block_length] x
/// [0, block_width] x [0, block_height] with a horizontal cylindrical boss (regular
/// `segments`-gon of radius boss_radius) on its face x = block_length, along +X over
/// [block_length, block_length + boss_length], its axis at y = block_width / 2 and at
/// mid-height z = block_height / 2. The boss's lowest point is at block_height / 2 -
/// boss_radius > 0: it does not touch the plate. Build: Z, 90 degrees for the boss, Z again.
struct BearingSeatSpec {
    double block_length = 20.0;  ///< mm, along X
    double block_width = 30.0;   ///< mm, along Y
    double block_height = 40.0;  ///< mm
    double boss_radius = 8.0;    ///< mm, less than block_width / 2 and block_height / 2
    double boss_length = 15.0;   ///< mm, how far the boss sticks out along +X
    int segments = 32;           ///< a multiple of 4
};
[[nodiscard]] PlannerFixture bearing_seat(const BearingSeatSpec& spec = {});

// ---- 4. Horizontal members on a column -------------------------------------------------------

/// A column [-column_width/2, column_width/2] x [-column_depth/2, column_depth/2] x
/// [0, column_height] with a horizontal cylinder (regular `segments`-gon of radius
/// cylinder_radius, axis along X in the plane y = 0) lying across its top and overhanging it
/// by overhang_left along -X and overhang_right along +X (either may be 0). The cylinder rests
/// in a cradle: its lowest cradle_deg of arc on either side of the bottom is embedded in the
/// column, whose top is the chord at the ends of that arc (z = column_height); so the axis is
/// at column_height + cylinder_radius cos(cradle_deg). The overhanging ends do not touch the
/// plate.
struct ColumnCylinderSpec {
    double column_width = 16.0;    ///< mm, along X
    double column_depth = 20.0;    ///< mm, along Y, more than 2 cylinder_radius sin(cradle)
    double column_height = 30.0;   ///< mm, the cradle's chord
    double cylinder_radius = 8.0;  ///< mm
    double overhang_left = 20.0;   ///< mm, along -X beyond the column
    double overhang_right = 20.0;  ///< mm, along +X beyond the column
    double cradle_deg = 45.0;      ///< a multiple of 360 / segments in (0, 90)
    int segments = 32;             ///< a multiple of 4
};
[[nodiscard]] PlannerFixture cylinder_on_column(const ColumnCylinderSpec& spec = {});
/// Height of the cylinder's axis above the plate (mm).
[[nodiscard]] double cylinder_on_column_axis_height(const ColumnCylinderSpec& spec = {});

/// A column with two horizontal arms at its top (a T), built with t_shape(): the column
/// [0, column_width] wide below z = column_height, the arms column_height to column_height +
/// arm_thickness high and arm_length long on each side, extruded over y in [0, depth]; the
/// bounding box starts at the origin (the column spans x in [arm_length, arm_length +
/// column_width]).
struct TArmsSpec {
    double column_width = 12.0;   ///< mm
    double column_height = 30.0;  ///< mm, where the arms start
    double arm_length = 15.0;     ///< mm, beyond the column on each side
    double arm_thickness = 8.0;   ///< mm
    double depth = 15.0;          ///< mm, along Y
};
[[nodiscard]] PlannerFixture t_shape_arms(const TArmsSpec& spec = {});

/// An inverted L (a gamma): the column [0, column_width] x [0, column_height] and, on top of
/// it, the arm [0, column_width + arm_length] x [column_height, column_height + arm_thickness]
/// in the (x, z) plane, extruded over y in [0, depth]. The arm reaches out along +X and does not
/// touch the plate.
struct LBracketSpec {
    double column_width = 12.0;   ///< mm
    double column_height = 30.0;  ///< mm, where the arm starts
    double arm_length = 25.0;     ///< mm, beyond the column
    double arm_thickness = 8.0;   ///< mm
    double depth = 15.0;          ///< mm, along Y
};
[[nodiscard]] PlannerFixture l_bracket(const LBracketSpec& spec = {});

// ---- 5. A freeform column --------------------------------------------------------------------

/// A regular `segments`-gon of radius `radius` swept along a planar cubic Bezier spine
/// B(t), t in [0, 1], with control points (0, 0, 0), (0, 0, height / 3), B3 - height / 3 *
/// (tan(lean_deg), 0, 1) and B3 = (top_offset, 0, height). Its z is exactly t * height, its
/// tangent is vertical at the base and leans lean_deg from vertical towards +X at the top,
/// growing monotonically in between. `rings` + 1 rings at equal steps of t, each perpendicular
/// to the spine (so the bottom ring lies flat on z = 0), flat caps at both ends. The section
/// 4 example: a gradual tilt of the build direction.
struct LeaningColumnSpec {
    double radius = 8.0;   ///< mm, well below the spine's radius of curvature (> 70 mm)
    double height = 60.0;  ///< mm, z of the spine's top
    /// mm, x of the spine's top, in [h, 2 h] for h = height / 3 * tan(lean_deg) (the lean
    /// then grows monotonically)
    double top_offset = 25.0;
    double lean_deg = 40.0;  ///< tangent at the top, from vertical, in [0, 60]
    int segments = 32;       ///< a multiple of 4
    int rings = 60;          ///< spine steps, at least 2
};
[[nodiscard]] PlannerFixture leaning_column(const LeaningColumnSpec& spec = {});
/// The spine point B(t) (mm), t in [0, 1]; its height is t * spec.height.
[[nodiscard]] core::Vec3d leaning_column_spine(const LeaningColumnSpec& spec, double t);
/// The unit tangent of the spine at t in [0, 1] (the ideal local build direction).
[[nodiscard]] core::Vec3d leaning_column_axis(const LeaningColumnSpec& spec, double t);
/// The spine sampled at `samples` + 1 equal steps of t (mm), from the base to the top.
[[nodiscard]] std::vector<core::Vec3d> leaning_column_spine_polyline(const LeaningColumnSpec& spec,
                                                                     int samples);

// ---- 6. Several bases, frames, narrow gaps ---------------------------------------------------

/// Two legs leaning towards each other that join at the top (METHOD.md section 8): in the
/// (x, z) plane the feet are [0, foot_width] and [span - foot_width, span] on z = 0, each leg
/// is a parallelogram whose outer face runs from the outer foot corner to the crown's corner
/// (span / 2 -+ crown_width / 2, height); the inner faces meet at the soffit's apex (span / 2,
/// arch_soffit_height(spec)). Extruded over y in [0, depth]. Below the apex a section has two
/// separate pieces, above it one.
struct ArchSpec {
    double span = 60.0;        ///< mm, outer width at the base
    double height = 40.0;      ///< mm
    double foot_width = 12.0;  ///< mm, horizontal width of each leg
    double crown_width = 8.0;  ///< mm, flat top, less than foot_width
    double depth = 15.0;       ///< mm, along Y
};
[[nodiscard]] PlannerFixture arch(const ArchSpec& spec = {});
/// Height of the apex under the crown where the two legs' inner faces meet (mm).
[[nodiscard]] double arch_soffit_height(const ArchSpec& spec = {});

/// Two columns and a beam on top: in the (x, z) plane the columns [0, column_width] and
/// [span - column_width, span] below z = column_height and the beam [0, span] from
/// column_height to column_height + beam_thickness, extruded over y in [0, depth]. The beam's
/// middle bridges the opening between the columns.
struct PortalSpec {
    double span = 50.0;           ///< mm, outer width
    double column_width = 10.0;   ///< mm
    double column_height = 30.0;  ///< mm, where the beam starts
    double beam_thickness = 8.0;  ///< mm
    double depth = 15.0;          ///< mm, along Y
};
[[nodiscard]] PlannerFixture portal_frame(const PortalSpec& spec = {});
/// The portal of issues 23 and 24: two 10 x 10 x 40 columns 50 mm apart (centre to centre)
/// under a 60 x 10 x 8 beam. Built upside down (beam first), the 5-axis cells' head body (80 mm
/// across) reaches over one column while the tip is at the other's foot; as given, the beam
/// must be closed from both columns (a bridge between bases).
[[nodiscard]] PlannerFixture tall_portal();

/// Two parallel walls with a deep narrow slot between them on a common base: in the (x, z)
/// plane the base [0, 2 wall_thickness + slot_width] x [0, base_height] and the walls
/// [0, wall_thickness] and [wall_thickness + slot_width, 2 wall_thickness + slot_width] from
/// base_height to height, extruded over y in [0, depth]. The slot is the nozzle's tightest
/// spot (collision control, section 7).
struct SlotSpec {
    double wall_thickness = 10.0;  ///< mm
    double slot_width = 5.0;       ///< mm, two tracks
    double base_height = 6.0;      ///< mm, the slot's floor
    double height = 36.0;          ///< mm, top of the walls
    double depth = 20.0;           ///< mm, along Y
};
[[nodiscard]] PlannerFixture slot(const SlotSpec& spec = {});

// ---- 7. Parts as given, with the plate in the machine (issue 24) --------------------------

/// A cube [0, size]^3 with a horizontal through-hole along Y (regular `segments`-gon of
/// diameter hole_diameter) centred at x = z = size / 2. Below the hole's top a section has two
/// separate pieces; the hole's roof bridges them.
struct CrossHoleBlockSpec {
    double size = 40.0;           ///< mm
    double hole_diameter = 20.0;  ///< mm, less than size
    int segments = 32;            ///< a multiple of 4
};
[[nodiscard]] PlannerFixture cross_hole_block(const CrossHoleBlockSpec& spec = {});

/// A plate [0, plate_length] x [0, plate_width] x [0, plate_thickness] with an upright tab
/// (tab_width along X, tab_thickness along Y, tab_height high) standing on its middle; a
/// horizontal hole (regular `segments`-gon of diameter hole_diameter) runs through the tab's
/// thickness (along Y), its axis hole_height above the plate's top, centred in the tab's width.
struct TabWithHoleSpec {
    double plate_length = 60.0;    ///< mm, along X
    double plate_width = 40.0;     ///< mm, along Y
    double plate_thickness = 8.0;  ///< mm
    double tab_width = 30.0;       ///< mm, along X, less than plate_length
    double tab_thickness = 8.0;    ///< mm, along Y, less than plate_width
    double tab_height = 35.0;      ///< mm, above the plate's top
    double hole_diameter = 10.0;   ///< mm
    double hole_height = 20.0;     ///< mm, of the hole's axis above the plate's top
    int segments = 32;             ///< a multiple of 4
};
[[nodiscard]] PlannerFixture tab_with_hole(const TabWithHoleSpec& spec = {});

/// A ring wound along a right-handed helix about the Z axis, as a coil spring with a ground
/// end: the square section [radius - section / 2, radius + section / 2] in radius by `section`
/// in height, in the vertical half-plane at angle theta from +X, is centred at height
/// pitch * theta / 2 pi for theta in [0, 2 pi turns] and cut off by the plate z = 0. So the
/// first (section / 2 / pitch) of a turn stands on the plate on a flat face (the ground end,
/// the part's footing), and the rest hangs above it at the helix angle atan(pitch / (2 pi
/// radius)) from horizontal. `segments_per_turn` equal steps of theta per turn (the ground end
/// ends on a step); flat caps at both ends, in their half-planes. The volume is that of the
/// smooth sweep; the chords make the mesh smaller by about (1 - sin(d) / d) for the step d,
/// which is volume_accuracy.
struct HelicalRingSpec {
    double radius = 25.0;  ///< mm, of the section's centre
    double pitch = 12.0;   ///< mm, rise per turn, more than section (turns stay apart)
    double section = 6.0;  ///< mm, side of the square section, less than radius
    int turns = 2;         ///< at least 1
    /// at least 8; the ground end, segments_per_turn * section / (2 pitch) steps, a whole number
    int segments_per_turn = 72;
};
[[nodiscard]] PlannerFixture helical_ring(const HelicalRingSpec& spec = {});
/// Angle (radians) over which the helical ring's ground end stands on the plate.
[[nodiscard]] double helical_ring_ground_angle(const HelicalRingSpec& spec = {});

/// A wall [0, wall_length] x [0, wall_thickness] x [0, wall_height] standing on the plate with
/// a horizontal cylindrical boss (regular `segments`-gon of diameter boss_diameter) on its face
/// y = wall_thickness, along +Y over boss_length, its axis at x = wall_length / 2 and at
/// mid-height. The boss hangs above the plate: only the wall touches it.
struct WallBossSpec {
    double wall_length = 60.0;     ///< mm, along X
    double wall_thickness = 10.0;  ///< mm, along Y
    double wall_height = 50.0;     ///< mm
    double boss_diameter = 20.0;   ///< mm, less than wall_length and wall_height
    double boss_length = 15.0;     ///< mm, how far the boss sticks out along +Y
    int segments = 32;             ///< a multiple of 4
};
[[nodiscard]] PlannerFixture wall_boss(const WallBossSpec& spec = {});

/// A base plate (base_length x depth x base_height) with a column at its -X end carrying an
/// arm along +X at its top, and a post at post_x standing on the base, taller than the arm:
/// profile in the XZ plane extruded along +Y over depth. The arm is split off sideways along
/// +X; the post lies beyond that split plane but does not grow from the arm (decision 0035).
struct ArmAndPostSpec {
    double base_length = 80.0;    ///< mm, along X
    double base_height = 5.0;     ///< mm
    double depth = 10.0;          ///< mm, along Y
    double column_width = 10.0;   ///< mm, the column and the post alike
    double column_height = 25.0;  ///< mm above the base
    double arm_length = 20.0;     ///< mm beyond the column
    double arm_thickness = 5.0;   ///< mm
    double post_x = 60.0;         ///< mm, the post's -X face
    double post_height = 40.0;    ///< mm above the base, above the arm's top
};
[[nodiscard]] PlannerFixture arm_and_post(const ArmAndPostSpec& spec = {});

/// A hook: a column on a base slab, an arm along +X at its top, and a finger hanging down
/// from the arm's end, clear of the base. The arm is built sideways; the finger then grows
/// from the arm's last layers towards the plate, beyond the table's tilt range.
struct HookSpec {
    double base_length = 30.0;    ///< mm, along X
    double base_height = 5.0;     ///< mm
    double depth = 10.0;          ///< mm, along Y
    double column_width = 10.0;   ///< mm
    double column_height = 40.0;  ///< mm above the base
    double arm_length = 30.0;     ///< mm beyond the column
    double arm_thickness = 8.0;   ///< mm
    double finger_width = 8.0;    ///< mm along X, at the arm's end
    double finger_length = 20.0;  ///< mm below the arm
};
[[nodiscard]] PlannerFixture hook(const HookSpec& spec = {});

/// Every fixture above with its default spec.
[[nodiscard]] std::vector<PlannerFixture> all_planner_fixtures();

}  // namespace maxslice::test
