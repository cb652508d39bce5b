#pragma once
// Small meshes for the mesh module's own tests, built in code.

#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "maxslice/mesh/triangle_mesh.hpp"

namespace maxslice::mesh::test {

/// The 12 triangles of the cube [0,1]^3 as a soup (9 numbers per triangle), outward.
template <class Real>
std::vector<Real> cube_soup() {
    // Corner k has coordinates (k & 1, (k >> 1) & 1, (k >> 2) & 1).
    static constexpr std::array<std::array<int, 3>, 12> kFaces = {{
        {0, 2, 1},
        {1, 2, 3},  // z = 0
        {4, 5, 6},
        {5, 7, 6},  // z = 1
        {0, 1, 4},
        {1, 5, 4},  // y = 0
        {2, 6, 3},
        {3, 6, 7},  // y = 1
        {0, 4, 2},
        {2, 4, 6},  // x = 0
        {1, 3, 5},
        {3, 7, 5},  // x = 1
    }};
    std::vector<Real> soup;
    for (const auto& f : kFaces) {
        for (int k : f) {
            soup.push_back(static_cast<Real>(k & 1));
            soup.push_back(static_cast<Real>((k >> 1) & 1));
            soup.push_back(static_cast<Real>((k >> 2) & 1));
        }
    }
    return soup;
}

/// A tetrahedron with corners (0,0,0), (1,0,0), (0,1,0), (0,0,1) as a soup, outward.
template <class Real>
std::vector<Real> tetrahedron_soup() {
    return {0, 0, 0, 0, 1, 0, 1, 0, 0,  //
            0, 0, 0, 1, 0, 0, 0, 0, 1,  //
            0, 0, 0, 0, 0, 1, 0, 1, 0,  //
            1, 0, 0, 0, 1, 0, 0, 0, 1};
}

inline TriangleMesh unit_cube() {
    const std::vector<double> soup = cube_soup<double>();
    return weld_exact(std::span<const double>(soup));
}

inline TriangleMesh tetrahedron() {
    const std::vector<double> soup = tetrahedron_soup<double>();
    return weld_exact(std::span<const double>(soup));
}

}  // namespace maxslice::mesh::test

namespace maxslice::mesh::test {

/// A mesh whose triangles share no vertices (every corner its own vertex).
inline TriangleMesh unwelded(const TriangleMesh& m) {
    TriangleMesh out;
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const auto base = static_cast<std::uint32_t>(out.vertices.size());
        for (int k = 0; k < 3; ++k) out.vertices.push_back(m.corner(t, k));
        out.triangles.push_back({base, base + 1, base + 2});
    }
    return out;
}

/// m moved by (dx, dy, dz).
inline TriangleMesh moved(TriangleMesh m, double dx, double dy, double dz) {
    transform(m, {1, 0, 0, dx, 0, 1, 0, dy, 0, 0, 1, dz});
    return m;
}

/// Two unit cubes, [0,1]^3 and [1,2]x[1,2]x[0,1], welded so that they share the edge
/// x = y = 1 (four triangles on one edge).
inline TriangleMesh two_cubes_sharing_an_edge() {
    std::vector<double> soup = cube_soup<double>();
    std::vector<double> other = cube_soup<double>();
    for (std::size_t i = 0; i < other.size(); i += 3) {
        other[i] += 1.0;
        other[i + 1] += 1.0;
    }
    soup.insert(soup.end(), other.begin(), other.end());
    return weld_exact(std::span<const double>(soup));
}

/// The unit cube with every triangle reversed.
inline TriangleMesh inside_out_cube() {
    TriangleMesh m = unit_cube();
    for (Triangle& t : m.triangles) std::swap(t[1], t[2]);
    return m;
}

/// The unit cube where the triangles of the face z = 0 use a copy of the corner (0,0,0)
/// moved by gap along x: a crack that an exact weld leaves open.
inline TriangleMesh cube_with_crack(double gap) {
    TriangleMesh m = unit_cube();
    std::uint32_t origin = 0;
    while (m.vertices[origin] != core::Vec3d{0, 0, 0}) ++origin;
    const auto copy = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.push_back({gap, 0, 0});
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const bool bottom = m.corner(t, 0).z == 0 && m.corner(t, 1).z == 0 && m.corner(t, 2).z == 0;
        if (!bottom) continue;
        for (std::uint32_t& v : m.triangles[t]) {
            if (v == origin) v = copy;
        }
    }
    return m;
}

/// A closed double cone (bipyramid) with n segments around the z axis, radius 1, apexes at
/// z = +-1; the apexes are vertices 0 and 1, each used by n triangles.
inline TriangleMesh bipyramid(int n) {
    TriangleMesh m;
    m.vertices.push_back({0, 0, 1});
    m.vertices.push_back({0, 0, -1});
    for (int i = 0; i < n; ++i) {
        const double a = 2.0 * 3.14159265358979323846 * i / n;
        m.vertices.push_back({std::cos(a), std::sin(a), 0});
    }
    for (int i = 0; i < n; ++i) {
        const auto p = static_cast<std::uint32_t>(2 + i);
        const auto q = static_cast<std::uint32_t>(2 + (i + 1) % n);
        m.triangles.push_back({0, p, q});
        m.triangles.push_back({1, q, p});
    }
    return m;
}

}  // namespace maxslice::mesh::test
