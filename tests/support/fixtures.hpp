#pragma once
// Meshes built in code for tests. Every fixture is closed, manifold, consistently oriented
// (counter-clockwise seen from outside) and shares its vertices (no cracks, no T-junctions).
// Each comes with its exact volume and cross-section area as functions of its parameters:
// for polygons these are the areas of the polygons actually built (a regular n-gon, not
// the circle it approximates), so tolerances in tests measure the code under test only.
//
// Heights convention: a cross-section "at z" is the section of the plane z = const taken
// just above it (a box cut at its bottom face has its full area, at its top face none),
// which is the convention of slice::cut_mesh.
#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "maxslice/core/vec3.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"

namespace maxslice::test {

/// A point of a planar cap (mm).
struct CapPoint {
    double x = 0.0;
    double y = 0.0;
    constexpr bool operator==(const CapPoint&) const = default;
};

/// A planar region in the XY plane triangulated without overlaps: triangles run
/// counter-clockwise and share vertices (a vertex lying on an edge is a vertex of that
/// edge). Its boundary is the set of directed edges not matched by a reversed edge.
struct Cap {
    std::vector<CapPoint> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

/// Builds a cap from pieces, merging vertices with bit-identical coordinates (pieces that
/// must join compute their common points with the same expressions).
class CapBuilder {
public:
    std::uint32_t vertex(CapPoint p);
    /// A counter-clockwise triangle.
    void triangle(CapPoint a, CapPoint b, CapPoint c);
    /// A convex counter-clockwise quad, split along a-c.
    void quad(CapPoint a, CapPoint b, CapPoint c, CapPoint d);
    /// Adds all triangles of another cap.
    void add(const Cap& cap);
    [[nodiscard]] const Cap& cap() const { return cap_; }

private:
    Cap cap_;
};

/// Points i = 0..n-1 of a regular n-gon at angles 2 pi i / n, counter-clockwise.
[[nodiscard]] std::vector<CapPoint> regular_polygon(CapPoint center, double radius, int n);
/// Axis-aligned rectangle [x0, x1] x [y0, y1] as two triangles.
[[nodiscard]] Cap rectangle_cap(double x0, double y0, double x1, double y1);
/// A fan from center to a closed counter-clockwise rim around it (star-shaped region).
[[nodiscard]] Cap fan_cap(CapPoint center, std::span<const CapPoint> rim);
/// The region between two concentric regular n-gons (same angles), as a strip of quads.
[[nodiscard]] Cap annulus_cap(CapPoint center, double r_outer, double r_inner, int n);
/// The square [x0, x1] x [y0, y0 + (x1 - x0)] minus a centred regular n-gon of radius r
/// (n a multiple of 8). The square's boundary is sampled on the same rays as the n-gon, and
/// a point on a side is computed from that side's coordinates alone, so cells that share a
/// side share its points exactly.
[[nodiscard]] Cap holed_cell_cap(double x0, double y0, double x1, double r, int n);

/// Area of a cap (sum of its triangles' areas), mm^2.
[[nodiscard]] double cap_area(const Cap& cap);
/// Length of the intersection of the line y = const with the cap, mm.
[[nodiscard]] double cap_chord(const Cap& cap, double y);

/// Extrudes a cap along +Z through the given increasing levels: the bottom at levels
/// front (reversed), the top at levels back, side walls along the cap's boundary with a
/// ring of vertices at every level.
[[nodiscard]] mesh::TriangleMesh extrude(const Cap& cap, std::span<const double> levels);
[[nodiscard]] mesh::TriangleMesh extrude(const Cap& cap, double z0, double z1);

/// Reverses every triangle (the cavity shell of a hollow part has inward normals).
[[nodiscard]] mesh::TriangleMesh inverted(mesh::TriangleMesh mesh);
/// Both meshes in one (vertices not shared).
[[nodiscard]] mesh::TriangleMesh merged(mesh::TriangleMesh a, const mesh::TriangleMesh& b);
/// The mesh rotated by angle_deg about the axis through center (right-hand rule). Angles that
/// are multiples of 45 degrees use exact sines and cosines (0, +-1, +-sqrt(1/2)).
[[nodiscard]] mesh::TriangleMesh rotated(mesh::TriangleMesh mesh, const core::Vec3d& axis,
                                         double angle_deg, const core::Vec3d& center = {});
[[nodiscard]] mesh::TriangleMesh translated(mesh::TriangleMesh mesh, const core::Vec3d& offset);

// ---- Fixtures and their analytic values ----------------------------------------------------

/// Area of a regular n-gon with circumradius r: n/2 r^2 sin(2 pi / n).
[[nodiscard]] double regular_polygon_area(double r, int n);

/// Axis-aligned box (12 triangles).
[[nodiscard]] mesh::TriangleMesh box(const core::Vec3d& min, const core::Vec3d& max);
[[nodiscard]] mesh::TriangleMesh unit_cube();
/// The unit cube with an extra ring of vertices on its side walls at z = 0.5, so that a
/// plane can pass exactly through vertices in the middle of the part.
[[nodiscard]] mesh::TriangleMesh unit_cube_with_mid_ring();
[[nodiscard]] double box_volume(const core::Vec3d& min, const core::Vec3d& max);
[[nodiscard]] double box_area_at(const core::Vec3d& min, const core::Vec3d& max, double z);

/// Regular-n-gon prism on z = 0 centred on the Z axis (fan caps with a centre vertex).
[[nodiscard]] mesh::TriangleMesh cylinder(double radius, double height, int segments = 64);
[[nodiscard]] double cylinder_volume(double radius, double height, int segments = 64);
[[nodiscard]] double cylinder_area_at(double radius, double height, int segments, double z);

/// A cylinder with a coaxial hole (two regular n-gons at the same angles).
[[nodiscard]] mesh::TriangleMesh tube(double r_outer, double r_inner, double height,
                                      int segments = 64);
[[nodiscard]] double tube_volume(double r_outer, double r_inner, double height, int segments = 64);
[[nodiscard]] double tube_area_at(double r_outer, double r_inner, double height, int segments,
                                  double z);

/// A plate of n_holes square cells of side `cell` in a row along +X from the origin, each
/// with a centred circular hole (regular `segments`-gon of radius hole_radius), thickness
/// along +Z from 0.
struct PlateSpec {
    int n_holes = 5;
    double cell = 10.0;
    double hole_radius = 3.0;
    double thickness = 2.0;
    int segments = 32;  ///< multiple of 8
};
[[nodiscard]] mesh::TriangleMesh plate_with_holes(const PlateSpec& spec = {});
[[nodiscard]] double plate_volume(const PlateSpec& spec = {});
[[nodiscard]] double plate_area_at(const PlateSpec& spec, double z);

/// A T-shaped prism standing on its stem: the stem [-stem_width/2, stem_width/2] x
/// [0, stem_height] below the bar [-bar_width/2, bar_width/2] x [stem_height, stem_height +
/// bar_height] in the XZ plane, extruded over y in [0, depth]; then shifted by
/// (bar_width / 2, 0, 0) so the bounding box starts at the origin.
struct TSpec {
    double stem_width = 4.0;
    double stem_height = 10.0;
    double bar_width = 16.0;
    double bar_height = 4.0;
    double depth = 6.0;
};
[[nodiscard]] mesh::TriangleMesh t_shape(const TSpec& spec = {});
[[nodiscard]] double t_shape_volume(const TSpec& spec = {});
[[nodiscard]] double t_shape_area_at(const TSpec& spec, double z);

/// A hollow cube [0, size]^3 whose cubic cavity has walls `wall` thick, with a solid cube
/// floating in the cavity at `gap` from the cavity walls (an island in a hole).
struct NestedSpec {
    double size = 20.0;
    double wall = 3.0;
    double gap = 3.0;
};
[[nodiscard]] mesh::TriangleMesh nested_boxes(const NestedSpec& spec = {});
[[nodiscard]] double nested_boxes_volume(const NestedSpec& spec = {});
[[nodiscard]] double nested_boxes_area_at(const NestedSpec& spec, double z);

/// The cube [0, size]^3 turned 45 degrees about the X axis around its centre, then moved up
/// so its lowest edge lies on z = 0 (height size * sqrt(2), sections are rectangles).
[[nodiscard]] mesh::TriangleMesh cube_tilted_45(double size = 10.0);
[[nodiscard]] double cube_tilted_45_volume(double size = 10.0);
[[nodiscard]] double cube_tilted_45_area_at(double size, double z);

/// The cylinder(radius, length, segments) turned to lie along +X (x in [0, length]) on
/// z = 0, touching it along one edge (height 2 * radius).
[[nodiscard]] mesh::TriangleMesh cylinder_on_side(double radius, double length, int segments = 64);
[[nodiscard]] double cylinder_on_side_area_at(double radius, double length, int segments, double z);

// ---- A catalogue for property tests ---------------------------------------------------------

/// Expected topology of a cross-section: how many outer and hole wires, and the deepest
/// level of the containment tree (0: outers only, 1: holes, 2: islands in holes ...).
struct SectionShape {
    int outers = 0;
    int holes = 0;
    int max_depth = 0;
    constexpr bool operator==(const SectionShape&) const = default;
};

/// A fixture with its analytic values, for tests that loop over all of them.
struct Fixture {
    std::string name;
    mesh::TriangleMesh mesh;
    double volume_mm3 = 0.0;
    std::function<double(double z)> area_at;         ///< section area just above z, mm^2
    std::function<SectionShape(double z)> shape_at;  ///< section topology just above z
    std::vector<double> vertex_heights;              ///< z of every vertex level, sorted
};

[[nodiscard]] Fixture unit_cube_fixture();
[[nodiscard]] Fixture cylinder_fixture();            ///< r 10, h 20, 64 segments
[[nodiscard]] Fixture cylinder_with_hole_fixture();  ///< tube 10 / 3, h 15
[[nodiscard]] Fixture thin_tube_fixture();           ///< tube 10 / 9, h 20
[[nodiscard]] Fixture plate_with_holes_fixture();    ///< PlateSpec{}
[[nodiscard]] Fixture t_shape_fixture();             ///< TSpec{}
[[nodiscard]] Fixture nested_boxes_fixture();        ///< NestedSpec{}
[[nodiscard]] Fixture cube_tilted_45_fixture();      ///< size 10
[[nodiscard]] Fixture cylinder_on_side_fixture();    ///< r 10, length 30, 64 segments
/// All of the above.
[[nodiscard]] std::vector<Fixture> all_fixtures();

}  // namespace maxslice::test
