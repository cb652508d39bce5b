#pragma once
// Shared internals of the mesh module: deterministic reductions and per-triangle terms.

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <optional>
#include <vector>

#include "maxslice/core/vec3.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"

namespace maxslice::mesh::detail {

/// Items per block of a deterministic reduction. Fixed, so that the result does not depend on
/// the number of threads.
inline constexpr std::size_t kReduceBlock = std::size_t{1} << 15;

/// Runs f(acc, i) for i in [0, n) in fixed blocks of kReduceBlock items, each block with its
/// own accumulator (a copy of init), blocks possibly in parallel; returns the accumulators in
/// block order. Combining them in that order gives a result independent of the thread count.
template <class Acc, class F>
std::vector<Acc> block_partials(std::size_t n, const Acc& init, F&& f) {
    const std::size_t blocks = (n + kReduceBlock - 1) / kReduceBlock;
    std::vector<Acc> partial(blocks, init);
    auto run = [&](std::size_t b) {
        const std::size_t end = std::min(n, (b + 1) * kReduceBlock);
        Acc& acc = partial[b];
        for (std::size_t i = b * kReduceBlock; i < end; ++i) f(acc, i);
    };
    if (blocks <= 1) {
        for (std::size_t b = 0; b < blocks; ++b) run(b);
    } else {
        tbb::parallel_for(std::size_t{0}, blocks, run);
    }
    return partial;
}

/// Sum of f(i) over [0, n), the same for any number of threads.
template <class F>
double deterministic_sum(std::size_t n, F&& f) {
    double s = 0.0;
    for (double p : block_partials(n, 0.0, [&](double&acc, std::size_t i) { acc += f(i); })) {
        s += p;
    }
    return s;
}

/// Six times the signed volume of the tetrahedron (o, a, b, c).
inline double six_volume_term(const core::Vec3d& o, const core::Vec3d& a, const core::Vec3d& b,
                              const core::Vec3d& c) {
    return core::dot(a - o, core::cross(b - o, c - o));
}

/// Twice the area of the triangle (a, b, c).
inline double twice_area_term(const core::Vec3d& a, const core::Vec3d& b, const core::Vec3d& c) {
    return core::norm(core::cross(b - a, c - a));
}

/// The degenerate-triangle test of is_degenerate() for finite corners whose twice_area_term()
/// is already known.
inline bool degenerate_with_area(double twice_area, const core::Vec3d& a, const core::Vec3d& b,
                                 const core::Vec3d& c, double area_per_length2) {
    const core::Vec3d ab = b - a;
    const core::Vec3d ac = c - a;
    const core::Vec3d bc = c - b;
    const double longest2 = std::max({core::dot(ab, ab), core::dot(ac, ac), core::dot(bc, bc)});
    return 0.5 * twice_area <= area_per_length2 * longest2;
}

/// Closed shells that repair() would turn the right way out: negative volume and not inside
/// an odd number of other closed shells (so not a void), in bodies without non-manifold
/// edges; the same analysis on a copy of the mesh (repair.cpp).
struct InsideOutShells {
    std::size_t count = 0;
    std::optional<core::Vec3d> example;  ///< a point on the first one (mm)
};
[[nodiscard]] InsideOutShells inside_out_shells(const TriangleMesh& mesh);
/// Pieces of surface (triangles connected through two-sided edges) whose inside is empty: the
/// point just behind a piece's largest triangle, on the side its winding calls inside, has a
/// winding number under 1/2 about the whole surface. For closed surfaces where bodies touch
/// along non-manifold edges, which inside_out_shells does not look at. At most the 64
/// largest pieces are tested (each test is a pass over the mesh).
[[nodiscard]] InsideOutShells inward_pieces(const TriangleMesh& mesh);

}  // namespace maxslice::mesh::detail
