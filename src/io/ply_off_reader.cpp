// PLY (ASCII and binary) and OFF, read here rather than through assimp. Assimp 5.2.5 loops
// forever on a PLY file whose header is cut short, aborts on an assertion when an OFF face
// list is shorter than its header says, silently drops OFF faces with more than 9 corners
// and silently clamps out-of-range OFF indices to the last vertex (measured; see
// docs/decisions/0002-import.md). Both formats are small: every count is checked against
// what the file holds before anything is allocated from it, every index against the vertex
// count, every coordinate for being finite, and polygons are cut by ear clipping
// (polygon_soup.cpp).

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "polygon_soup.hpp"
#include "readers.hpp"

namespace maxslice::io::detail {
namespace {

std::unexpected<core::Error> invalid(std::string message) {
    return core::fail(core::ErrorCode::kInvalidInput, std::move(message));
}

bool is_blank(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

bool parse_integer(std::string_view t, std::int64_t& value) {
    if (t.size() > 1 && t.front() == '+') t.remove_prefix(1);
    const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
    return !t.empty() && ec == std::errc{} && ptr == t.data() + t.size();
}

// Whitespace-separated tokens with line numbers; '#' starts a comment when enabled (OFF).
class TextTokens {
public:
    TextTokens(std::string_view text, std::size_t first_line, bool comments)
        : s_(text), line_(first_line), comments_(comments) {}

    /// The next token, empty at the end; line() is its line.
    std::string_view next() {
        skip();
        token_line_ = line_;
        const std::size_t start = pos_;
        while (pos_ < s_.size() && !is_blank(s_[pos_]) && s_[pos_] != '\n' &&
               !(comments_ && s_[pos_] == '#')) {
            ++pos_;
        }
        return s_.substr(start, pos_ - start);
    }
    /// Moves past the end of the current line (the rest of a vertex or face line).
    void skip_line() {
        while (pos_ < s_.size() && s_[pos_] != '\n') ++pos_;
    }
    /// True when only blanks (and a comment) remain on the current line.
    bool line_done() {
        std::size_t p = pos_;
        while (p < s_.size() && is_blank(s_[p])) ++p;
        return p >= s_.size() || s_[p] == '\n' || (comments_ && s_[p] == '#');
    }
    [[nodiscard]] std::size_t line() const { return token_line_; }
    [[nodiscard]] std::size_t remaining_bytes() const { return s_.size() - pos_; }

private:
    void skip() {
        while (pos_ < s_.size()) {
            const char c = s_[pos_];
            if (c == '\n') {
                ++line_;
                ++pos_;
            } else if (is_blank(c)) {
                ++pos_;
            } else if (comments_ && c == '#') {
                while (pos_ < s_.size() && s_[pos_] != '\n') ++pos_;
            } else {
                break;
            }
        }
    }

    std::string_view s_;
    std::size_t pos_ = 0;
    std::size_t line_ = 1;
    std::size_t token_line_ = 1;
    bool comments_ = false;
};

RawImport finish(PolygonSoup& soup, Format format, std::size_t polygons) {
    RawImport out;
    out.format = format;
    out.solids = 1;
    if (soup.short_faces() > 0) {
        out.warnings.push_back(fmt::format("ignored {} with fewer than 3 corners",
                                           count_of(soup.short_faces(), "face")));
    }
    if (soup.fanned_faces() > 0) {
        out.warnings.push_back(fmt::format(
            "{} of {} polygons cross themselves or have no area; they were fanned from a corner",
            soup.fanned_faces(), polygons));
    }
    out.mesh = mesh::weld_exact(std::span<const double>(soup.xyz()));
    return out;
}

core::Result<void> check_polygon(std::size_t corners, std::size_t face, std::size_t line) {
    if (corners > kMaxPolygonCorners) {
        return invalid(
            fmt::format("{}face {} has {} corners; maxslice reads at most {} per "
                        "polygon",
                        line > 0 ? fmt::format("line {}: ", line) : std::string(), face + 1,
                        corners, kMaxPolygonCorners));
    }
    return {};
}

// ---------------------------------------------------------------------------- OFF

core::Result<RawImport> read_off_impl(std::string_view text) {
    TextTokens tok(text, 1, true);
    std::string_view t = tok.next();
    if (t.size() >= 3 && t.substr(t.size() - 3) == "OFF") {
        // ST, C, N prefixes add per-vertex data after x y z, which is skipped with the rest of
        // the line; 4 (homogeneous) and n (dimension) change what the numbers mean.
        const std::string_view prefix = t.substr(0, t.size() - 3);
        if (prefix.find('4') != std::string_view::npos ||
            prefix.find('n') != std::string_view::npos) {
            return invalid(
                fmt::format("line {}: {} files (homogeneous or n-dimensional "
                            "coordinates) are not supported",
                            tok.line(), shown(t)));
        }
        for (const char c : prefix) {
            if (c != 'S' && c != 'T' && c != 'C' && c != 'N') {
                return invalid(
                    fmt::format("line {}: {} is not an OFF header", tok.line(), shown(t)));
            }
        }
        t = tok.next();
    }
    std::int64_t counts[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
        if (k == 2 && tok.line_done()) break;  // the edge count may be left out
        if (k > 0) t = tok.next();
        if (!parse_integer(t, counts[k]) || counts[k] < 0) {
            return invalid(
                fmt::format("line {}: expected the vertex, face and edge counts, "
                            "found {}",
                            tok.line(), t.empty() ? "the end" : shown(t)));
        }
    }
    tok.skip_line();
    const auto nv = static_cast<std::uint64_t>(counts[0]);
    const auto nf = static_cast<std::uint64_t>(counts[1]);
    // Every vertex and face takes at least two bytes ("0\n"): larger counts cannot be true,
    // and must not size an allocation.
    if (nv + nf > tok.remaining_bytes() / 2 + 1 || nv > UINT32_MAX) {
        return invalid(
            fmt::format("the header says {} vertices and {} faces, more than the "
                        "file's {} bytes can hold",
                        nv, nf, text.size()));
    }
    if (nf == 0) return invalid("no triangles: the OFF file has no faces");
    std::vector<core::Vec3d> vertices;
    vertices.reserve(nv);
    for (std::uint64_t i = 0; i < nv; ++i) {
        double c[3];
        for (int k = 0; k < 3; ++k) {
            t = tok.next();
            if (t.empty()) {
                return invalid(fmt::format("the file ends after {} of {} vertices", i, nv));
            }
            if (const NumberRead got = parse_number(t, c[k]); got != NumberRead::kOk) {
                return invalid(fmt::format(
                    "line {}: {}", tok.line(),
                    number_problem("vertex coordinate", t, got, /*single_precision=*/false)));
            }
            if (!std::isfinite(c[k])) {
                return invalid(fmt::format("line {}: vertex coordinate {} is not finite",
                                           tok.line(), shown(t)));
            }
            if (k < 2 && tok.line_done()) {
                return invalid(fmt::format("line {}: a vertex needs 3 coordinates", tok.line()));
            }
        }
        tok.skip_line();  // colours, normals, texture coordinates
        vertices.push_back({c[0], c[1], c[2]});
    }
    PolygonSoup soup(vertices);
    std::vector<std::uint32_t> polygon;
    for (std::uint64_t f = 0; f < nf; ++f) {
        t = tok.next();
        std::int64_t corners = 0;
        if (t.empty()) return invalid(fmt::format("the file ends after {} of {} faces", f, nf));
        const std::size_t line = tok.line();
        if (!parse_integer(t, corners) || corners < 0) {
            return invalid(fmt::format("line {}: {} is not a corner count", line, shown(t)));
        }
        if (auto ok = check_polygon(static_cast<std::size_t>(corners), f, line); !ok) {
            return std::unexpected(ok.error());
        }
        polygon.clear();
        for (std::int64_t k = 0; k < corners; ++k) {
            if (tok.line_done()) {
                return invalid(
                    fmt::format("line {}: the face has {} of its {} corners", line, k, corners));
            }
            t = tok.next();
            std::int64_t index = 0;
            if (!parse_integer(t, index)) {
                return invalid(fmt::format("line {}: {} is not a vertex index", line, shown(t)));
            }
            if (index < 0 || static_cast<std::uint64_t>(index) >= nv) {
                return invalid(
                    fmt::format("line {}: vertex index {} is out of range (the file "
                                "has {} vertices, numbered from 0)",
                                line, index, nv));
            }
            polygon.push_back(static_cast<std::uint32_t>(index));
        }
        tok.skip_line();  // an optional face colour
        soup.add(polygon);
    }
    if (soup.xyz().empty()) {
        return invalid("no triangles: every face of the OFF file has fewer than 3 corners");
    }
    return finish(soup, Format::kOff, nf);
}

// ---------------------------------------------------------------------------- PLY

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

std::optional<PlyType> ply_type(std::string_view name) {
    if (name == "char" || name == "int8") return PlyType::kInt8;
    if (name == "uchar" || name == "uint8") return PlyType::kUint8;
    if (name == "short" || name == "int16") return PlyType::kInt16;
    if (name == "ushort" || name == "uint16") return PlyType::kUint16;
    if (name == "int" || name == "int32") return PlyType::kInt32;
    if (name == "uint" || name == "uint32") return PlyType::kUint32;
    if (name == "float" || name == "float32") return PlyType::kFloat32;
    if (name == "double" || name == "float64") return PlyType::kFloat64;
    return std::nullopt;
}

std::size_t ply_size(PlyType t) {
    switch (t) {
        case PlyType::kInt8:
        case PlyType::kUint8: return 1;
        case PlyType::kInt16:
        case PlyType::kUint16: return 2;
        case PlyType::kInt32:
        case PlyType::kUint32:
        case PlyType::kFloat32: return 4;
        case PlyType::kFloat64: return 8;
    }
    return 1;
}

bool ply_integral(PlyType t) {
    return t != PlyType::kFloat32 && t != PlyType::kFloat64;
}

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::kFloat32;
    bool list = false;
    PlyType count_type = PlyType::kUint8;
};

struct PlyElement {
    std::string name;
    std::uint64_t count = 0;
    std::vector<PlyProperty> properties;
};

enum class PlyFormat { kAscii, kBinaryLittle, kBinaryBig };

// What a property means to maxslice.
enum class Role { kSkip, kX, kY, kZ, kFaceList };

template <class T>
T load(const char* p, bool swap) {
    std::array<char, sizeof(T)> b;
    std::memcpy(b.data(), p, sizeof(T));
    if (swap) std::reverse(b.begin(), b.end());
    return std::bit_cast<T>(b);
}

double load_value(const char* p, PlyType t, bool swap) {
    switch (t) {
        case PlyType::kInt8: return static_cast<double>(load<std::int8_t>(p, swap));
        case PlyType::kUint8: return static_cast<double>(load<std::uint8_t>(p, swap));
        case PlyType::kInt16: return static_cast<double>(load<std::int16_t>(p, swap));
        case PlyType::kUint16: return static_cast<double>(load<std::uint16_t>(p, swap));
        case PlyType::kInt32: return static_cast<double>(load<std::int32_t>(p, swap));
        case PlyType::kUint32: return static_cast<double>(load<std::uint32_t>(p, swap));
        case PlyType::kFloat32: return static_cast<double>(load<float>(p, swap));
        case PlyType::kFloat64: return load<double>(p, swap);
    }
    return 0.0;
}

core::Result<RawImport> read_ply_impl(std::string_view bytes) {
    // Header: lines up to "end_header".
    std::size_t pos = 0;
    std::size_t line_no = 0;
    auto next_line = [&](std::string_view& line) {
        if (pos >= bytes.size()) return false;
        std::size_t eol = bytes.find('\n', pos);
        if (eol == std::string_view::npos) eol = bytes.size();
        line = bytes.substr(pos, eol - pos);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        pos = std::min(bytes.size(), eol + 1);
        ++line_no;
        return true;
    };
    std::string_view line;
    if (!next_line(line) || line != "ply") return invalid("line 1: a PLY file starts with 'ply'");
    std::optional<PlyFormat> format;
    std::vector<PlyElement> elements;
    bool ended = false;
    while (next_line(line)) {
        TextTokens tok(line, line_no, false);
        const std::string_view key = tok.next();
        if (key.empty() || key == "comment" || key == "obj_info") continue;
        if (key == "end_header") {
            ended = true;
            break;
        }
        if (key == "format") {
            const std::string_view kind = tok.next();
            const std::string_view version = tok.next();
            if (kind == "ascii") {
                format = PlyFormat::kAscii;
            } else if (kind == "binary_little_endian") {
                format = PlyFormat::kBinaryLittle;
            } else if (kind == "binary_big_endian") {
                format = PlyFormat::kBinaryBig;
            } else {
                return invalid(fmt::format("line {}: unknown PLY format {}", line_no, shown(kind)));
            }
            if (version != "1.0") {
                return invalid(fmt::format("line {}: PLY version {} (only 1.0 is known)", line_no,
                                           shown(version)));
            }
        } else if (key == "element") {
            PlyElement e;
            e.name = std::string(tok.next());
            std::int64_t count = -1;
            if (e.name.empty() || !parse_integer(tok.next(), count) || count < 0) {
                return invalid(
                    fmt::format("line {}: an element needs a name and a count", line_no));
            }
            e.count = static_cast<std::uint64_t>(count);
            elements.push_back(std::move(e));
        } else if (key == "property") {
            if (elements.empty()) {
                return invalid(fmt::format("line {}: a property before any element", line_no));
            }
            PlyProperty p;
            std::string_view type = tok.next();
            if (type == "list") {
                p.list = true;
                const auto count_type = ply_type(tok.next());
                if (!count_type || !ply_integral(*count_type)) {
                    return invalid(
                        fmt::format("line {}: a list needs an integer count type", line_no));
                }
                p.count_type = *count_type;
                type = tok.next();
            }
            const auto t = ply_type(type);
            if (!t) {
                return invalid(fmt::format("line {}: unknown PLY type {}", line_no, shown(type)));
            }
            p.type = *t;
            p.name = std::string(tok.next());
            if (p.name.empty()) {
                return invalid(fmt::format("line {}: a property needs a name", line_no));
            }
            elements.back().properties.push_back(std::move(p));
        } else {
            return invalid(fmt::format("line {}: unknown PLY header line {}", line_no, shown(key)));
        }
    }
    if (!ended) return invalid("the PLY header has no 'end_header' line: the file is cut short");
    if (!format) return invalid("the PLY header has no 'format' line");

    // Which element holds the vertices and which the faces.
    const PlyElement* vertex = nullptr;
    const PlyElement* face = nullptr;
    for (const PlyElement& e : elements) {
        if (e.count > 0 && e.properties.empty()) {
            return invalid(
                fmt::format("PLY element '{}' has {} entries but no properties", e.name, e.count));
        }
        if (e.name == "vertex") vertex = &e;
        if (e.name == "face") face = &e;
    }
    auto roles_of = [](const PlyElement* e, bool is_vertex) {
        std::vector<Role> roles;
        if (e == nullptr) return roles;
        for (const PlyProperty& p : e->properties) {
            Role r = Role::kSkip;
            if (is_vertex && !p.list) {
                if (p.name == "x") r = Role::kX;
                if (p.name == "y") r = Role::kY;
                if (p.name == "z") r = Role::kZ;
            }
            if (!is_vertex && p.list && ply_integral(p.type) &&
                (p.name == "vertex_indices" || p.name == "vertex_index")) {
                r = Role::kFaceList;
            }
            roles.push_back(r);
        }
        return roles;
    };
    const std::vector<Role> vertex_roles = roles_of(vertex, true);
    const std::vector<Role> face_roles = roles_of(face, false);
    auto has = [](const std::vector<Role>& roles, Role r) {
        return std::find(roles.begin(), roles.end(), r) != roles.end();
    };
    if (vertex == nullptr || !has(vertex_roles, Role::kX) || !has(vertex_roles, Role::kY) ||
        !has(vertex_roles, Role::kZ)) {
        return invalid("the PLY file has no 'vertex' element with x, y and z properties");
    }
    if (face == nullptr || face->count == 0 || !has(face_roles, Role::kFaceList)) {
        return invalid(
            "no triangles: the PLY file has no 'face' element with a vertex_indices "
            "list");
    }
    const std::string_view body = bytes.substr(pos);
    // Every value takes at least one byte: larger counts cannot be true, and must not size an
    // allocation.
    for (const PlyElement& e : elements) {
        if (e.count > body.size()) {
            return invalid(
                fmt::format("PLY element '{}' claims {} entries but only {} bytes "
                            "follow the header",
                            e.name, e.count, body.size()));
        }
    }
    const std::uint64_t nv = vertex->count;
    if (nv > UINT32_MAX) return invalid("too many PLY vertices");

    std::vector<core::Vec3d> vertices;
    vertices.reserve(nv);
    // Polygons in file order, flattened: corners[starts[f] .. starts[f + 1]).
    std::vector<std::uint32_t> corners;
    std::vector<std::size_t> starts{0};
    starts.reserve(face->count + 1);
    std::size_t face_no = 0;

    // Where a value is, for messages: "line N: " (ASCII) or "byte N: " (binary); only
    // formatted when something is wrong.
    auto where = [&](std::size_t n) {
        return fmt::format("{} {}: ", *format == PlyFormat::kAscii ? "line" : "byte", n);
    };
    auto add_index = [&](double value, std::size_t at) -> core::Result<void> {
        if (!(value >= 0.0) || value >= static_cast<double>(nv) || value != std::floor(value)) {
            return invalid(
                fmt::format("{}face {}: vertex index {} is out of range (the file has "
                            "{} vertices, numbered from 0)",
                            where(at), face_no + 1, value, nv));
        }
        corners.push_back(static_cast<std::uint32_t>(value));
        return {};
    };
    auto check_coord = [&](double v, std::size_t at) -> core::Result<void> {
        if (!std::isfinite(v)) {
            return invalid(fmt::format("{}a vertex coordinate is NaN or infinite", where(at)));
        }
        return {};
    };

    if (*format == PlyFormat::kAscii) {
        TextTokens tok(body, line_no + 1, false);
        for (const PlyElement& e : elements) {
            const bool is_vertex = &e == vertex;
            const bool is_face = &e == face;
            const std::vector<Role>& roles = is_vertex ? vertex_roles : face_roles;
            for (std::uint64_t n = 0; n < e.count; ++n) {
                core::Vec3d v{};
                for (std::size_t k = 0; k < e.properties.size(); ++k) {
                    const PlyProperty& p = e.properties[k];
                    const Role role = (is_vertex || is_face) ? roles[k] : Role::kSkip;
                    std::string_view t = tok.next();
                    if (t.empty()) {
                        return invalid(
                            fmt::format("the PLY data ends in entry {} of {} of "
                                        "element '{}'",
                                        n + 1, e.count, e.name));
                    }
                    std::uint64_t items = 1;
                    if (p.list) {
                        std::int64_t c = 0;
                        if (!parse_integer(t, c) || c < 0 ||
                            static_cast<std::uint64_t>(c) > tok.remaining_bytes()) {
                            return invalid(
                                fmt::format("{}{} is not a list length that fits the "
                                            "file",
                                            where(tok.line()), shown(t)));
                        }
                        items = static_cast<std::uint64_t>(c);
                        if (role == Role::kFaceList) {
                            if (auto ok = check_polygon(items, face_no, tok.line()); !ok) {
                                return std::unexpected(ok.error());
                            }
                        }
                        t = items > 0 ? tok.next() : std::string_view();
                    }
                    for (std::uint64_t it = 0; it < items; ++it) {
                        if (it > 0) t = tok.next();
                        double value = 0.0;
                        const NumberRead got =
                            t.empty() ? NumberRead::kNotANumber : parse_number(t, value);
                        if (got == NumberRead::kOutOfRange) {
                            return invalid(where(tok.line()) +
                                           number_problem("value", t, got,
                                                          /*single_precision=*/false));
                        }
                        if (got != NumberRead::kOk) {
                            return invalid(fmt::format("{}{} is not a number", where(tok.line()),
                                                       t.empty() ? "the end" : shown(t)));
                        }
                        if (role == Role::kFaceList) {
                            if (auto ok = add_index(value, tok.line()); !ok) {
                                return std::unexpected(ok.error());
                            }
                        } else if (role == Role::kX || role == Role::kY || role == Role::kZ) {
                            if (auto ok = check_coord(value, tok.line()); !ok) {
                                return std::unexpected(ok.error());
                            }
                            (role == Role::kX ? v.x : role == Role::kY ? v.y : v.z) = value;
                        }
                    }
                }
                if (is_vertex) vertices.push_back(v);
                if (is_face) {
                    starts.push_back(corners.size());
                    ++face_no;
                }
            }
        }
    } else {
        const bool swap =
            (*format == PlyFormat::kBinaryBig) != (std::endian::native == std::endian::big);
        std::size_t at = 0;
        for (const PlyElement& e : elements) {
            const bool is_vertex = &e == vertex;
            const bool is_face = &e == face;
            const std::vector<Role>& roles = is_vertex ? vertex_roles : face_roles;
            for (std::uint64_t n = 0; n < e.count; ++n) {
                core::Vec3d v{};
                const std::size_t entry_at = bytes.size() - body.size() + at;
                for (std::size_t k = 0; k < e.properties.size(); ++k) {
                    const PlyProperty& p = e.properties[k];
                    const Role role = (is_vertex || is_face) ? roles[k] : Role::kSkip;
                    std::uint64_t items = 1;
                    if (p.list) {
                        const std::size_t cs = ply_size(p.count_type);
                        if (body.size() - at < cs) {
                            return invalid(
                                fmt::format("the PLY data ends in entry {} of {} of "
                                            "element '{}'",
                                            n + 1, e.count, e.name));
                        }
                        const double c = load_value(body.data() + at, p.count_type, swap);
                        at += cs;
                        if (c < 0.0) return invalid(where(entry_at) + "a negative list length");
                        items = static_cast<std::uint64_t>(c);
                        if (role == Role::kFaceList) {
                            if (auto ok = check_polygon(items, face_no, 0); !ok) {
                                return std::unexpected(ok.error());
                            }
                        }
                    }
                    const std::size_t size = ply_size(p.type);
                    if (items > (body.size() - at) / size) {
                        return invalid(
                            fmt::format("the PLY data ends in entry {} of {} of "
                                        "element '{}'",
                                        n + 1, e.count, e.name));
                    }
                    for (std::uint64_t it = 0; it < items; ++it, at += size) {
                        if (role == Role::kSkip) continue;
                        const double value = load_value(body.data() + at, p.type, swap);
                        if (role == Role::kFaceList) {
                            if (auto ok = add_index(value, entry_at); !ok) {
                                return std::unexpected(ok.error());
                            }
                        } else {
                            if (auto ok = check_coord(value, entry_at); !ok) {
                                return std::unexpected(ok.error());
                            }
                            (role == Role::kX ? v.x : role == Role::kY ? v.y : v.z) = value;
                        }
                    }
                }
                if (is_vertex) vertices.push_back(v);
                if (is_face) {
                    starts.push_back(corners.size());
                    ++face_no;
                }
            }
        }
    }
    PolygonSoup soup(vertices);
    for (std::size_t f = 0; f + 1 < starts.size(); ++f) {
        soup.add(
            std::span<const std::uint32_t>(corners).subspan(starts[f], starts[f + 1] - starts[f]));
    }
    if (soup.xyz().empty()) {
        return invalid("no triangles: every face of the PLY file has fewer than 3 corners");
    }
    return finish(soup, Format::kPly, face_no);
}

template <class F>
core::Result<RawImport> guarded(F&& f) {
    try {
        return f();
    } catch (const std::bad_alloc&) {
        return invalid("not enough memory for the mesh");
    }
}

}  // namespace

core::Result<RawImport> read_off(std::string_view bytes) {
    return guarded([&] { return read_off_impl(bytes); });
}

core::Result<RawImport> read_ply(std::string_view bytes) {
    return guarded([&] { return read_ply_impl(bytes); });
}

}  // namespace maxslice::io::detail
