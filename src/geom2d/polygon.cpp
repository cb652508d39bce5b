#include "maxslice/geom2d/polygon.hpp"

#include <cmath>

#include "maxslice/core/units.hpp"

namespace maxslice::geom2d {

double signed_area_um2(const Path2& path) {
    const std::size_t n = path.size();
    if (n < 3) return 0.0;
    // Shoelace formula relative to the first point keeps the products small.
    const Point2 o = path[0];
    double twice = 0.0;
    for (std::size_t i = 1; i + 1 < n; ++i) {
        const double ax = static_cast<double>(path[i].x - o.x);
        const double ay = static_cast<double>(path[i].y - o.y);
        const double bx = static_cast<double>(path[i + 1].x - o.x);
        const double by = static_cast<double>(path[i + 1].y - o.y);
        twice += ax * by - ay * bx;
    }
    return 0.5 * twice;
}

double signed_area_mm2(const Paths2& paths) {
    double sum = 0.0;
    for (const auto& p : paths) sum += signed_area_um2(p);
    return core::um2_to_mm2(sum);
}

double perimeter_mm(const Path2& path) {
    double len = 0.0;
    for (std::size_t i = 0; i < path.size(); ++i) {
        const Point2& a = path[i];
        const Point2& b = path[(i + 1) % path.size()];
        len += std::hypot(static_cast<double>(b.x - a.x), static_cast<double>(b.y - a.y));
    }
    return len / core::kMicronsPerMm;
}

}  // namespace maxslice::geom2d
