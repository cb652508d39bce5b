// Bodies that float free (decision 0036): a body of the mesh (a connected component) that
// stands neither on the plate nor touches any other body can have nothing deposited under it:
// without supports, material is laid only on material. It is left out of the plan, which
// lists it.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "free_bodies.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"

namespace maxslice::plan::detail {
namespace {

// Bodies closer than this (mm) touch: beyond the rounding of a mesh's coordinates.
constexpr double kTouchMm = 0.05;
// Bodies whose boxes lie within a track of another's are tested triangle by triangle, at
// most this many (each test reads the whole mesh a few times); the rest count as touching.
constexpr std::size_t kMaxTested = 64;

// The distance between two boxes (0 when they meet).
double box_gap(const core::Box3d& a, const core::Box3d& b) {
    const double dx = std::max({a.min.x - b.max.x, 0.0, b.min.x - a.max.x});
    const double dy = std::max({a.min.y - b.max.y, 0.0, b.min.y - a.max.y});
    const double dz = std::max({a.min.z - b.max.z, 0.0, b.min.z - a.max.z});
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

// Whether triangle abc meets the box centred at c with half sizes h: the separating axis
// test (the box's three axes, the triangle's normal, and the nine cross products of their
// edges; Akenine-Moller, "Fast 3D triangle-box overlap testing", 2001).
bool triangle_meets_box(core::Vec3d a, core::Vec3d b, core::Vec3d d, const core::Vec3d& c,
                        const core::Vec3d& h) {
    a = a - c;
    b = b - c;
    d = d - c;
    const core::Vec3d v[3] = {a, b, d};
    const auto apart = [&](const core::Vec3d& axis) {
        const double p0 = core::dot(v[0], axis), p1 = core::dot(v[1], axis),
                     p2 = core::dot(v[2], axis);
        const double r = h.x * std::abs(axis.x) + h.y * std::abs(axis.y) + h.z * std::abs(axis.z);
        return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
    };
    const core::Vec3d e[3] = {b - a, d - b, a - d};
    const core::Vec3d box_axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const core::Vec3d& u : box_axes) {
        if (apart(u)) return false;
        for (const core::Vec3d& f : e) {
            if (apart(core::cross(u, f))) return false;
        }
    }
    return !apart(core::cross(e[0], e[1]));
}

}  // namespace

FreeBodies free_bodies(const mesh::TriangleMesh& mesh, const core::Vec3d& direction,
                       const PlanSettings& s) {
    FreeBodies out;
    const std::vector<std::uint32_t> body = mesh::vertex_bodies(mesh);
    // One body (most parts): nothing to compare, no pass over the triangles.
    if (std::all_of(mesh.triangles.begin(), mesh.triangles.end(), [&](const mesh::Triangle& t) {
            return body[t[0]] == body[mesh.triangles.front()[0]];
        })) {
        return out;
    }
    // Bodies in the order of their first triangles.
    std::vector<int> index(mesh.vertices.size(), -1);
    struct Body {
        core::Box3d box;
        double lowest = 1e300;  // along the base direction
        double volume = 0.0;
    };
    std::vector<Body> bodies;
    std::vector<int> of_triangle(mesh.triangles.size());
    const core::Vec3d d = core::normalized(direction);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const mesh::Triangle& tri = mesh.triangles[t];
        int& b = index[body[tri[0]]];
        if (b < 0) {
            b = static_cast<int>(bodies.size());
            bodies.emplace_back();
        }
        of_triangle[t] = b;
        Body& bb = bodies[static_cast<std::size_t>(b)];
        for (int k = 0; k < 3; ++k) {
            const core::Vec3d& x = mesh.corner(t, k);
            bb.box.add(x);
            bb.lowest = std::min(bb.lowest, core::dot(x, d));
        }
        bb.volume +=
            core::dot(mesh.corner(t, 0), core::cross(mesh.corner(t, 1), mesh.corner(t, 2))) / 6.0;
    }
    if (bodies.size() < 2) return out;
    double plate = 1e300;
    for (const Body& b : bodies) plate = std::min(plate, b.lowest);
    std::vector<char> free(bodies.size(), 0);
    std::size_t tested = 0;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        // On the plate: its lowest point within half a layer of the part's, or within the
        // footing's height (decision 0017: pads from the plate up to it carry what starts
        // there, a sphere's underside a millimetre up).
        if (bodies[i].lowest - plate <= std::max(0.5 * s.layer_mm, s.footing_mm)) continue;
        double gap = 1e300;
        for (std::size_t j = 0; j < bodies.size(); ++j) {
            if (j != i) gap = std::min(gap, box_gap(bodies[i].box, bodies[j].box));
        }
        if (gap < s.track_width_mm) {
            // Boxes that close may still hold bodies far apart (a cube beside a pyramid's
            // slope): the largest of a track, half a track, ... down to kTouchMm that no
            // triangle of another body meets, grown onto this body's box (a box holding every
            // point that near the body), is a lower bound of the gap.
            if (++tested > kMaxTested) continue;
            const core::Vec3d c = bodies[i].box.center();
            double found = 0.0;
            for (double r = s.track_width_mm; r >= kTouchMm && found == 0.0; r *= 0.5) {
                const core::Vec3d h = bodies[i].box.size() * 0.5 + core::Vec3d{r, r, r};
                bool near = false;
                for (std::size_t t = 0; t < mesh.triangles.size() && !near; ++t) {
                    if (of_triangle[t] == static_cast<int>(i)) continue;
                    near = triangle_meets_box(mesh.corner(t, 0), mesh.corner(t, 1),
                                              mesh.corner(t, 2), c, h);
                }
                if (!near) found = r;
            }
            if (found == 0.0) continue;
            gap = std::max(gap, found);
        }
        free[i] = 1;
        out.bodies.push_back({bodies[i].volume, bodies[i].box, gap});
    }
    if (out.bodies.empty()) return out;
    out.rest.vertices = mesh.vertices;  // the slicer reads only the vertices triangles use
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        if (free[static_cast<std::size_t>(of_triangle[t])] == 0)
            out.rest.triangles.push_back(mesh.triangles[t]);
    }
    return out;
}

}  // namespace maxslice::plan::detail
