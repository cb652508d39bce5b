#include "support/fixtures.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "support/fixture_checks.hpp"

namespace maxslice::test {
namespace {

using core::Vec3d;
using mesh::TriangleMesh;

using detail::cross2;
using detail::require;

// Exact sine and cosine for multiples of 45 degrees, so that turned fixtures keep
// vertices exactly on the planes a test cuts through.
std::pair<double, double> sin_cos_deg(double angle_deg) {
    const double eighths = angle_deg / 45.0;
    if (eighths == std::round(eighths)) {
        const long k = ((static_cast<long>(std::round(eighths)) % 8) + 8) % 8;
        const double h = std::sqrt(0.5);
        static constexpr int kSin[8] = {0, 1, 2, 1, 0, -1, -2, -1};
        static constexpr int kCos[8] = {2, 1, 0, -1, -2, -1, 0, 1};
        auto value = [h](int code) {
            switch (code) {
                case 2: return 1.0;
                case 1: return h;
                case -1: return -h;
                case -2: return -1.0;
                default: return 0.0;
            }
        };
        return {value(kSin[k]), value(kCos[k])};
    }
    const double a = angle_deg * std::numbers::pi / 180.0;
    return {std::sin(a), std::cos(a)};
}

// Rim of a fixture's regular polygon: the same expressions for the mesh and for the
// analytic values computed from it.
CapPoint rim_point(CapPoint center, double radius, int i, int n) {
    const double a = 2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
    return {center.x + radius * std::cos(a), center.y + radius * std::sin(a)};
}

}  // namespace

// ---- Caps ------------------------------------------------------------------------------

std::uint32_t CapBuilder::vertex(CapPoint p) {
    // Linear search keeps the builder trivially exact; fixtures have at most a few hundred
    // cap vertices.
    for (std::size_t i = 0; i < cap_.vertices.size(); ++i) {
        if (cap_.vertices[i] == p) return static_cast<std::uint32_t>(i);
    }
    cap_.vertices.push_back(p);
    return static_cast<std::uint32_t>(cap_.vertices.size() - 1);
}

void CapBuilder::triangle(CapPoint a, CapPoint b, CapPoint c) {
    require(cross2(a, b, c) > 0.0, "cap triangle must be counter-clockwise and non-degenerate");
    cap_.triangles.push_back({vertex(a), vertex(b), vertex(c)});
}

void CapBuilder::quad(CapPoint a, CapPoint b, CapPoint c, CapPoint d) {
    triangle(a, b, c);
    triangle(a, c, d);
}

void CapBuilder::add(const Cap& cap) {
    for (const auto& t : cap.triangles) {
        triangle(cap.vertices[t[0]], cap.vertices[t[1]], cap.vertices[t[2]]);
    }
}

std::vector<CapPoint> regular_polygon(CapPoint center, double radius, int n) {
    require(n >= 3, "a polygon needs at least 3 sides");
    std::vector<CapPoint> out;
    out.reserve(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) out.push_back(rim_point(center, radius, i, n));
    return out;
}

Cap rectangle_cap(double x0, double y0, double x1, double y1) {
    require(x0 < x1 && y0 < y1, "rectangle must have positive extent");
    CapBuilder b;
    b.quad({x0, y0}, {x1, y0}, {x1, y1}, {x0, y1});
    return b.cap();
}

Cap fan_cap(CapPoint center, std::span<const CapPoint> rim) {
    CapBuilder b;
    for (std::size_t i = 0; i < rim.size(); ++i) {
        b.triangle(center, rim[i], rim[(i + 1) % rim.size()]);
    }
    return b.cap();
}

Cap annulus_cap(CapPoint center, double r_outer, double r_inner, int n) {
    require(0.0 < r_inner && r_inner < r_outer, "annulus needs 0 < r_inner < r_outer");
    const auto outer = regular_polygon(center, r_outer, n);
    const auto inner = regular_polygon(center, r_inner, n);
    CapBuilder b;
    for (std::size_t i = 0; i < outer.size(); ++i) {
        const std::size_t j = (i + 1) % outer.size();
        b.quad(inner[i], outer[i], outer[j], inner[j]);
    }
    return b.cap();
}

Cap holed_cell_cap(double x0, double y0, double x1, double r, int n) {
    require(n >= 8 && n % 8 == 0, "holed cell needs a multiple of 8 segments");
    const double y1 = y0 + (x1 - x0);
    const double h = 0.5 * (x1 - x0);
    require(0.0 < r && r < 0.9 * h, "hole radius must be well inside the cell");
    const double xm = 0.5 * (x0 + x1);
    const double ym = 0.5 * (y0 + y1);
    const CapPoint center{xm, ym};
    const int e = n / 8;  // rays per half side
    const int q = n / 4;  // rays per side
    // tan of the ray's angle from its side's centre, exactly odd in j.
    std::vector<double> tan_table(static_cast<std::size_t>(2 * e + 1));
    for (int j = 1; j < e; ++j) {
        const double t = std::tan(2.0 * std::numbers::pi * j / n);
        tan_table[static_cast<std::size_t>(e + j)] = t;
        tan_table[static_cast<std::size_t>(e - j)] = -t;
    }
    auto square_point = [&](int k) -> CapPoint {
        const int kk = ((k + e) % n + n) % n;
        const int side = kk / q;
        const int j = kk - side * q - e;
        const double t = tan_table[static_cast<std::size_t>(e + j)];
        switch (side) {
            case 0: return j == -e ? CapPoint{x1, y0} : CapPoint{x1, ym + h * t};
            case 1: return j == -e ? CapPoint{x1, y1} : CapPoint{xm - h * t, y1};
            case 2: return j == -e ? CapPoint{x0, y1} : CapPoint{x0, ym - h * t};
            default: return j == -e ? CapPoint{x0, y0} : CapPoint{xm + h * t, y0};
        }
    };
    CapBuilder b;
    for (int k = 0; k < n; ++k) {
        const CapPoint s0 = square_point(k);
        const CapPoint s1 = square_point(k + 1);
        const CapPoint c0 = rim_point(center, r, k, n);
        const CapPoint c1 = rim_point(center, r, (k + 1) % n, n);
        b.triangle(s0, s1, c1);
        b.triangle(s0, c1, c0);
    }
    return b.cap();
}

double cap_area(const Cap& cap) {
    double sum = 0.0;
    for (const auto& t : cap.triangles) {
        sum += 0.5 * cross2(cap.vertices[t[0]], cap.vertices[t[1]], cap.vertices[t[2]]);
    }
    return sum;
}

double cap_chord(const Cap& cap, double y) {
    // Triangles do not overlap, so the chord is the sum of each triangle's chord. An edge
    // counts as crossing when exactly one end lies above y: the line is taken just above y.
    double sum = 0.0;
    for (const auto& t : cap.triangles) {
        double xs[3];
        int count = 0;
        for (int i = 0; i < 3; ++i) {
            const CapPoint a = cap.vertices[t[static_cast<std::size_t>(i)]];
            const CapPoint b = cap.vertices[t[static_cast<std::size_t>((i + 1) % 3)]];
            if ((a.y > y) != (b.y > y)) {
                // A vertex on the line gives its own x, not an interpolated one.
                xs[count++] = a.y == y   ? a.x
                              : b.y == y ? b.x
                                         : a.x + (b.x - a.x) * (y - a.y) / (b.y - a.y);
            }
        }
        if (count == 2) sum += std::abs(xs[1] - xs[0]);
    }
    return sum;
}

// ---- Meshes ----------------------------------------------------------------------------

TriangleMesh extrude(const Cap& cap, std::span<const double> levels) {
    require(levels.size() >= 2, "extrude needs at least two levels");
    for (std::size_t i = 1; i < levels.size(); ++i) {
        require(levels[i - 1] < levels[i], "extrude levels must increase");
    }
    // Boundary: directed edges whose reverse is not in the cap.
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const auto& t : cap.triangles) {
        for (int i = 0; i < 3; ++i) {
            const auto key =
                std::pair{t[static_cast<std::size_t>(i)], t[static_cast<std::size_t>((i + 1) % 3)]};
            require(++directed[key] == 1, "cap uses a directed edge twice");
        }
    }
    std::vector<std::pair<std::uint32_t, std::uint32_t>> boundary;
    for (const auto& [edge, count] : directed) {
        if (!directed.contains({edge.second, edge.first})) boundary.push_back(edge);
    }

    TriangleMesh m;
    const std::size_t nv = cap.vertices.size();
    const std::size_t nl = levels.size();
    // index[level][cap vertex], created on first use so no vertex is left unused.
    std::vector<std::vector<std::int64_t>> index(nl, std::vector<std::int64_t>(nv, -1));
    auto at = [&](std::size_t level, std::uint32_t v) {
        auto& slot = index[level][v];
        if (slot < 0) {
            slot = static_cast<std::int64_t>(m.vertices.size());
            m.vertices.push_back({cap.vertices[v].x, cap.vertices[v].y, levels[level]});
        }
        return static_cast<std::uint32_t>(slot);
    };
    for (const auto& t : cap.triangles) {
        m.triangles.push_back({at(0, t[0]), at(0, t[2]), at(0, t[1])});
    }
    for (const auto& t : cap.triangles) {
        m.triangles.push_back({at(nl - 1, t[0]), at(nl - 1, t[1]), at(nl - 1, t[2])});
    }
    // The cap lies left of a boundary edge a -> b, so the outward side is to its right:
    // (a0, b0, b1) faces outward.
    for (const auto& [a, b] : boundary) {
        for (std::size_t l = 0; l + 1 < nl; ++l) {
            const auto a0 = at(l, a), b0 = at(l, b), a1 = at(l + 1, a), b1 = at(l + 1, b);
            m.triangles.push_back({a0, b0, b1});
            m.triangles.push_back({a0, b1, a1});
        }
    }
    return m;
}

TriangleMesh extrude(const Cap& cap, double z0, double z1) {
    const double levels[] = {z0, z1};
    return extrude(cap, levels);
}

TriangleMesh inverted(TriangleMesh m) {
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
    return m;
}

TriangleMesh merged(TriangleMesh a, const TriangleMesh& b) {
    const auto offset = static_cast<std::uint32_t>(a.vertices.size());
    a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
    for (const auto& t : b.triangles) {
        a.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    }
    return a;
}

TriangleMesh rotated(TriangleMesh m, const Vec3d& axis, double angle_deg, const Vec3d& center) {
    const Vec3d k = core::normalized(axis);
    require(core::norm(k) > 0.0, "rotation axis must not be zero");
    const auto [s, c] = sin_cos_deg(angle_deg);
    const double t = 1.0 - c;
    // Rodrigues' rotation matrix.
    const double r[3][3] = {
        {c + k.x * k.x * t, k.x * k.y * t - k.z * s, k.x * k.z * t + k.y * s},
        {k.y * k.x * t + k.z * s, c + k.y * k.y * t, k.y * k.z * t - k.x * s},
        {k.z * k.x * t - k.y * s, k.z * k.y * t + k.x * s, c + k.z * k.z * t},
    };
    for (Vec3d& p : m.vertices) {
        const Vec3d d = p - center;
        p = Vec3d{r[0][0] * d.x + r[0][1] * d.y + r[0][2] * d.z,
                  r[1][0] * d.x + r[1][1] * d.y + r[1][2] * d.z,
                  r[2][0] * d.x + r[2][1] * d.y + r[2][2] * d.z} +
            center;
    }
    return m;
}

TriangleMesh translated(TriangleMesh m, const Vec3d& offset) {
    for (Vec3d& p : m.vertices) p += offset;
    return m;
}

// ---- Fixtures --------------------------------------------------------------------------

double regular_polygon_area(double r, int n) {
    return 0.5 * n * r * r * std::sin(2.0 * std::numbers::pi / n);
}

TriangleMesh box(const Vec3d& min, const Vec3d& max) {
    return extrude(rectangle_cap(min.x, min.y, max.x, max.y), min.z, max.z);
}

TriangleMesh unit_cube() {
    return box({0, 0, 0}, {1, 1, 1});
}

TriangleMesh unit_cube_with_mid_ring() {
    const double levels[] = {0.0, 0.5, 1.0};
    return extrude(rectangle_cap(0, 0, 1, 1), levels);
}

double box_volume(const Vec3d& min, const Vec3d& max) {
    const Vec3d d = max - min;
    return d.x * d.y * d.z;
}

double box_area_at(const Vec3d& min, const Vec3d& max, double z) {
    return (z >= min.z && z < max.z) ? (max.x - min.x) * (max.y - min.y) : 0.0;
}

TriangleMesh cylinder(double radius, double height, int segments) {
    const auto rim = regular_polygon({0, 0}, radius, segments);
    return extrude(fan_cap({0, 0}, rim), 0.0, height);
}

double cylinder_volume(double radius, double height, int segments) {
    return regular_polygon_area(radius, segments) * height;
}

double cylinder_area_at(double radius, double height, int segments, double z) {
    return (z >= 0.0 && z < height) ? regular_polygon_area(radius, segments) : 0.0;
}

TriangleMesh tube(double r_outer, double r_inner, double height, int segments) {
    return extrude(annulus_cap({0, 0}, r_outer, r_inner, segments), 0.0, height);
}

double tube_volume(double r_outer, double r_inner, double height, int segments) {
    return (regular_polygon_area(r_outer, segments) - regular_polygon_area(r_inner, segments)) *
           height;
}

double tube_area_at(double r_outer, double r_inner, double height, int segments, double z) {
    return (z >= 0.0 && z < height) ? tube_volume(r_outer, r_inner, 1.0, segments) : 0.0;
}

TriangleMesh plate_with_holes(const PlateSpec& spec) {
    require(spec.n_holes >= 1, "plate needs at least one cell");
    CapBuilder b;
    for (int i = 0; i < spec.n_holes; ++i) {
        // Both neighbours compute a shared side as (i + 1) * cell.
        const double x0 = static_cast<double>(i) * spec.cell;
        const double x1 = static_cast<double>(i + 1) * spec.cell;
        b.add(holed_cell_cap(x0, 0.0, x1, spec.hole_radius, spec.segments));
    }
    return extrude(b.cap(), 0.0, spec.thickness);
}

double plate_volume(const PlateSpec& spec) {
    return plate_area_at(spec, 0.0) * spec.thickness;
}

double plate_area_at(const PlateSpec& spec, double z) {
    if (z < 0.0 || z >= spec.thickness) return 0.0;
    return spec.n_holes *
           (spec.cell * spec.cell - regular_polygon_area(spec.hole_radius, spec.segments));
}

TriangleMesh t_shape(const TSpec& spec) {
    require(spec.stem_width < spec.bar_width, "the bar must be wider than the stem");
    const double s = 0.5 * spec.stem_width;
    const double w = 0.5 * spec.bar_width;
    const double y0 = spec.stem_height;
    const double y1 = spec.stem_height + spec.bar_height;
    // Stem and the bar's three rectangles share the corners at the junction, so no vertex
    // lies inside another rectangle's edge.
    CapBuilder b;
    b.add(rectangle_cap(-s, 0.0, s, y0));
    b.add(rectangle_cap(-w, y0, -s, y1));
    b.add(rectangle_cap(-s, y0, s, y1));
    b.add(rectangle_cap(s, y0, w, y1));
    // Cap (x, y) extruded along z, then turned +90 degrees about X: (x, y, z) -> (x, -z, y).
    TriangleMesh m = rotated(extrude(b.cap(), 0.0, spec.depth), {1, 0, 0}, 90.0);
    return translated(std::move(m), {w, spec.depth, 0.0});
}

double t_shape_volume(const TSpec& spec) {
    return spec.depth * (spec.stem_width * spec.stem_height + spec.bar_width * spec.bar_height);
}

double t_shape_area_at(const TSpec& spec, double z) {
    if (z < 0.0) return 0.0;
    if (z < spec.stem_height) return spec.stem_width * spec.depth;
    if (z < spec.stem_height + spec.bar_height) return spec.bar_width * spec.depth;
    return 0.0;
}

TriangleMesh nested_boxes(const NestedSpec& spec) {
    const double a = spec.wall;
    const double b = spec.wall + spec.gap;
    const double s = spec.size;
    require(2.0 * b < s, "nested boxes do not fit");
    TriangleMesh m = box({0, 0, 0}, {s, s, s});
    m = merged(std::move(m), inverted(box({a, a, a}, {s - a, s - a, s - a})));
    return merged(std::move(m), box({b, b, b}, {s - b, s - b, s - b}));
}

double nested_boxes_volume(const NestedSpec& spec) {
    const double s = spec.size;
    const double c = s - 2.0 * spec.wall;
    const double i = s - 2.0 * (spec.wall + spec.gap);
    return s * s * s - c * c * c + i * i * i;
}

double nested_boxes_area_at(const NestedSpec& spec, double z) {
    const double s = spec.size;
    const double a = spec.wall;
    const double b = spec.wall + spec.gap;
    return box_area_at({0, 0, 0}, {s, s, s}, z) - box_area_at({a, a, a}, {s - a, s - a, s - a}, z) +
           box_area_at({b, b, b}, {s - b, s - b, s - b}, z);
}

TriangleMesh cube_tilted_45(double size) {
    const double h = 0.5 * size;
    TriangleMesh m = rotated(box({0, 0, 0}, {size, size, size}), {1, 0, 0}, 45.0, {h, h, h});
    // The lowest edge is at h - size * sqrt(1/2) after the turn (exact with the exact cosine).
    const double lowest = std::ranges::min(m.vertices, {}, &Vec3d::z).z;
    return translated(std::move(m), {0.0, 0.0, -lowest});
}

double cube_tilted_45_volume(double size) {
    return size * size * size;
}

double cube_tilted_45_area_at(double size, double z) {
    // The section of the diamond (half diagonal d) at height z is 2 (d - |z - d|) wide.
    const double d = size * std::sqrt(0.5);
    if (z < 0.0 || z >= 2.0 * d) return 0.0;
    return size * 2.0 * (d - std::abs(z - d));
}

TriangleMesh cylinder_on_side(double radius, double length, int segments) {
    // Turning +90 degrees about Y maps (x, y, z) -> (z, y, -x).
    TriangleMesh m = rotated(cylinder(radius, length, segments), {0, 1, 0}, 90.0);
    return translated(std::move(m), {0.0, 0.0, radius});
}

namespace {

// The end face of cylinder_on_side in the (y, z) plane: the rim (r cos a, r sin a) becomes
// (r sin a, r - r cos a).
Cap cylinder_on_side_profile(double radius, int segments) {
    std::vector<CapPoint> rim;
    for (int i = 0; i < segments; ++i) {
        const CapPoint p = rim_point({0, 0}, radius, i, segments);
        rim.push_back({p.y, radius - p.x});
    }
    return fan_cap({0.0, radius}, rim);
}

}  // namespace

double cylinder_on_side_area_at(double radius, double length, int segments, double z) {
    return length * cap_chord(cylinder_on_side_profile(radius, segments), z);
}

// ---- Catalogue -------------------------------------------------------------------------

namespace {

std::vector<double> vertex_heights(const TriangleMesh& m) {
    std::vector<double> zs;
    for (const Vec3d& p : m.vertices) zs.push_back(p.z);
    std::ranges::sort(zs);
    zs.erase(std::unique(zs.begin(), zs.end()), zs.end());
    return zs;
}

Fixture make(std::string name, TriangleMesh m, double volume, std::function<double(double)> area,
             std::function<SectionShape(double)> shape) {
    Fixture f;
    f.name = std::move(name);
    f.vertex_heights = vertex_heights(m);
    f.mesh = std::move(m);
    f.volume_mm3 = volume;
    f.area_at = std::move(area);
    f.shape_at = std::move(shape);
    return f;
}

std::function<SectionShape(double)> shape_between(double z0, double z1, SectionShape inside) {
    return [=](double z) { return (z >= z0 && z < z1) ? inside : SectionShape{}; };
}

// For parts that touch their lowest plane along an edge only (no area just above it).
std::function<SectionShape(double)> shape_strictly_between(double z0, double z1,
                                                           SectionShape inside) {
    return [=](double z) { return (z > z0 && z < z1) ? inside : SectionShape{}; };
}

}  // namespace

Fixture unit_cube_fixture() {
    return make(
        "unit_cube", unit_cube(), 1.0,
        [](double z) {
            return box_area_at({0, 0, 0}, {1, 1, 1}, z);
        },
        shape_between(0.0, 1.0, {1, 0, 0}));
}

Fixture cylinder_fixture() {
    return make(
        "cylinder", cylinder(10.0, 20.0, 64), cylinder_volume(10.0, 20.0, 64),
        [](double z) { return cylinder_area_at(10.0, 20.0, 64, z); },
        shape_between(0.0, 20.0, {1, 0, 0}));
}

Fixture cylinder_with_hole_fixture() {
    return make(
        "cylinder_with_hole", tube(10.0, 3.0, 15.0, 64), tube_volume(10.0, 3.0, 15.0, 64),
        [](double z) { return tube_area_at(10.0, 3.0, 15.0, 64, z); },
        shape_between(0.0, 15.0, {1, 1, 1}));
}

Fixture thin_tube_fixture() {
    return make(
        "thin_tube", tube(10.0, 9.0, 20.0, 64), tube_volume(10.0, 9.0, 20.0, 64),
        [](double z) { return tube_area_at(10.0, 9.0, 20.0, 64, z); },
        shape_between(0.0, 20.0, {1, 1, 1}));
}

Fixture plate_with_holes_fixture() {
    const PlateSpec spec{};
    return make(
        "plate_with_holes", plate_with_holes(spec), plate_volume(spec),
        [spec](double z) { return plate_area_at(spec, z); },
        shape_between(0.0, spec.thickness, {1, spec.n_holes, 1}));
}

Fixture t_shape_fixture() {
    const TSpec spec{};
    return make(
        "t_shape", t_shape(spec), t_shape_volume(spec),
        [spec](double z) { return t_shape_area_at(spec, z); },
        shape_between(0.0, spec.stem_height + spec.bar_height, {1, 0, 0}));
}

Fixture nested_boxes_fixture() {
    const NestedSpec spec{};
    const double s = spec.size;
    const double a = spec.wall;
    const double b = spec.wall + spec.gap;
    return make(
        "nested_boxes", nested_boxes(spec), nested_boxes_volume(spec),
        [spec](double z) { return nested_boxes_area_at(spec, z); },
        [=](double z) -> SectionShape {
            if (z < 0.0 || z >= s) return {};
            if (z < a || z >= s - a) return {1, 0, 0};
            if (z < b || z >= s - b) return {1, 1, 1};
            return {2, 1, 2};
        });
}

Fixture cube_tilted_45_fixture() {
    const double size = 10.0;
    return make(
        "cube_tilted_45", cube_tilted_45(size), cube_tilted_45_volume(size),
        [size](double z) { return cube_tilted_45_area_at(size, z); },
        shape_strictly_between(0.0, 2.0 * size * std::sqrt(0.5), {1, 0, 0}));
}

Fixture cylinder_on_side_fixture() {
    const Cap profile = cylinder_on_side_profile(10.0, 64);
    return make(
        "cylinder_on_side", cylinder_on_side(10.0, 30.0, 64), cylinder_volume(10.0, 30.0, 64),
        [profile](double z) { return 30.0 * cap_chord(profile, z); },
        shape_strictly_between(0.0, 20.0, {1, 0, 0}));
}

std::vector<Fixture> all_fixtures() {
    std::vector<Fixture> out;
    out.push_back(unit_cube_fixture());
    out.push_back(cylinder_fixture());
    out.push_back(cylinder_with_hole_fixture());
    out.push_back(thin_tube_fixture());
    out.push_back(plate_with_holes_fixture());
    out.push_back(t_shape_fixture());
    out.push_back(nested_boxes_fixture());
    out.push_back(cube_tilted_45_fixture());
    out.push_back(cylinder_on_side_fixture());
    return out;
}

}  // namespace maxslice::test
