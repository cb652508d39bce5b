#include "model_voxels.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace maxslice::verify::detail {
namespace {

struct Hit {
    std::uint32_t column = 0;
    double z = 0.0;
    int sign = 0;
};

// Edge function of the counter-clockwise edge a -> b at p: > 0 inside.
double edge(double ax, double ay, double bx, double by, double px, double py) {
    return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}

bool top_left(double ax, double ay, double bx, double by) {
    const double dx = bx - ax, dy = by - ay;
    return dy > 0.0 || (dy == 0.0 && dx < 0.0);
}

}  // namespace

ModelVoxels voxelize_model(const mesh::TriangleMesh& mesh, const core::Vec3d& origin, double voxel,
                           int nx, int ny, int nz) {
    ModelVoxels out;
    out.grid = BitGrid(nx, ny, nz);
    BitGrid& grid = out.grid;
    std::vector<Hit> hits;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        core::Vec3d p[3] = {mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2)};
        // Projected area; skip triangles seen edge-on from below.
        double area = edge(p[0].x, p[0].y, p[1].x, p[1].y, p[2].x, p[2].y);
        if (area == 0.0 || !std::isfinite(area)) continue;
        // Outward normal facing down: the column enters the solid here.
        const int sign = area < 0.0 ? 1 : -1;
        if (area < 0.0) {
            std::swap(p[1], p[2]);
            area = -area;
        }
        const double xmin = std::min({p[0].x, p[1].x, p[2].x});
        const double xmax = std::max({p[0].x, p[1].x, p[2].x});
        const double ymin = std::min({p[0].y, p[1].y, p[2].y});
        const double ymax = std::max({p[0].y, p[1].y, p[2].y});
        const int i0 = std::max(0, ceil_index((xmin - origin.x) / voxel - 0.5));
        const int i1 = std::min(nx - 1, floor_index((xmax - origin.x) / voxel - 0.5));
        const int j0 = std::max(0, ceil_index((ymin - origin.y) / voxel - 0.5));
        const int j1 = std::min(ny - 1, floor_index((ymax - origin.y) / voxel - 0.5));
        for (int i = i0; i <= i1; ++i) {
            const double x = origin.x + (i + 0.5) * voxel;
            for (int j = j0; j <= j1; ++j) {
                const double y = origin.y + (j + 0.5) * voxel;
                double w[3];
                bool inside = true;
                for (int e = 0; e < 3 && inside; ++e) {
                    const core::Vec3d& a = p[(e + 1) % 3];
                    const core::Vec3d& b = p[(e + 2) % 3];
                    w[e] = edge(a.x, a.y, b.x, b.y, x, y);
                    inside = w[e] > 0.0 || (w[e] == 0.0 && top_left(a.x, a.y, b.x, b.y));
                }
                if (!inside) continue;
                const double z = (w[0] * p[0].z + w[1] * p[1].z + w[2] * p[2].z) / area;
                hits.push_back({static_cast<std::uint32_t>(i * ny + j), z, sign});
            }
        }
    }
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
        if (a.column != b.column) return a.column < b.column;
        if (a.z != b.z) return a.z < b.z;
        return a.sign < b.sign;
    });
    for (std::size_t s = 0; s < hits.size();) {
        std::size_t e = s;
        while (e < hits.size() && hits[e].column == hits[s].column) ++e;
        const int i = static_cast<int>(hits[s].column / static_cast<std::uint32_t>(ny));
        const int j = static_cast<int>(hits[s].column % static_cast<std::uint32_t>(ny));
        int winding = 0;
        double enter = 0.0;
        bool inverted = false;
        for (std::size_t h = s; h < e; ++h) {
            const int before = winding;
            winding += hits[h].sign;
            // Below 0 once every crossing at this height is counted (an edge seen from below
            // is left and entered at the same height).
            if (winding < 0 && (h + 1 == e || hits[h + 1].z != hits[h].z)) inverted = true;
            if (before <= 0 && winding > 0) enter = hits[h].z;
            if (before > 0 && winding <= 0) {
                const int k0 = std::max(0, ceil_index((enter - origin.z) / voxel - 0.5));
                const int k1 = std::min(nz - 1, floor_index((hits[h].z - origin.z) / voxel - 0.5));
                if (k0 <= k1) grid.set_run(i, j, k0, k1);
            }
        }
        ++out.columns;
        if (winding != 0) ++out.open_columns;
        if (inverted) ++out.inverted_columns;
        s = e;
    }
    return out;
}

}  // namespace maxslice::verify::detail
