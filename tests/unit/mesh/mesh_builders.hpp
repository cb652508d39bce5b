#pragma once
// Small meshes for the mesh module's own tests, built in code.

#include <array>
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
