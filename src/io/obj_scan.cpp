// A strict first look at OBJ text before assimp parses it. Assimp's number parser reads
// "3.1+e2" as 3.1 and stops, and its index checks report no line; both would let a damaged
// file through as a different shape or fail without saying where. This pass reads the file
// as statements (a line ends at LF, CR LF or a lone CR; a trailing backslash continues it),
// checks the 'v', 'f', 'p' and 'l' statements, and writes the text assimp reads itself: for
// each vertex "v x y z", for each face of 3 or more corners "f" and its vertices' numbers
// counted from 1 (relative indices resolved, texture and normal references dropped), and the
// names of objects and groups, each on its statement's first line so that line numbers stay
// the file's. Nothing of the file's own text reaches assimp but those names' tokens, so
// assimp never sees a statement this pass did not check. Everything else (texture
// coordinates, normals, smoothing groups, points, lines, shorter faces, materials, curves,
// unknown keywords) becomes blank lines: maxslice reads only faces, and assimp mishandles
// some of the rest (found by fuzz/fuzz_obj, docs/fuzzing.md): it writes through wild pointers
// on a material library with an unknown statement before a face, leaks the mesh of an object
// or group holding a one-point line after a face, and leaks it again when a face hidden
// behind a lone CR in a group's name points past the vertices. The points, lines and short
// faces are counted here for the warnings. Faces with more corners than the PLY and OFF
// readers take (kMaxPolygonCorners) are refused here, before anything triangulates them.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <string>

#include "polygon_soup.hpp"
#include "readers.hpp"

namespace maxslice::io::detail {
namespace {

bool is_blank(char c) {
    return c == ' ' || c == '\t' || c == '\f' || c == '\v' || c == '\r';
}

// One logical OBJ statement: its text (continuations joined with a space) and first line.
struct Statement {
    std::string_view text;
    std::string joined;  // only used when the statement was continued
    std::size_t line = 0;
};

class StatementReader {
public:
    explicit StatementReader(std::string_view text) : text_(text) {}

    bool next(Statement& st) {
        if (pos_ >= text_.size()) return false;
        st.line = line_;
        st.joined.clear();
        bool continued = false;
        while (pos_ < text_.size()) {
            // A line ends at LF, CR LF or a lone CR (classic Mac OS files), as assimp reads it.
            std::size_t eol = text_.find_first_of("\r\n", pos_);
            if (eol == std::string_view::npos) eol = text_.size();
            std::string_view piece = text_.substr(pos_, eol - pos_);
            pos_ = eol + 1;
            if (eol + 1 < text_.size() && text_[eol] == '\r' && text_[eol + 1] == '\n') ++pos_;
            ++line_;
            while (!piece.empty() && is_blank(piece.back())) piece.remove_suffix(1);
            if (!piece.empty() && piece.back() == '\\') {
                piece.remove_suffix(1);
                st.joined.append(piece);
                st.joined.push_back(' ');
                continued = true;
                continue;
            }
            if (continued) {
                st.joined.append(piece);
                st.text = st.joined;
            } else {
                st.text = piece;
            }
            return true;
        }
        st.text = st.joined;  // the file ended on a continuation
        return true;
    }

    /// The line the next statement starts on.
    [[nodiscard]] std::size_t line() const { return line_; }

private:
    std::string_view text_;
    std::size_t pos_ = 0;
    std::size_t line_ = 1;
};

// Names assimp is given (objects and groups); faces and vertices are written by the scan.
bool names_a_part(std::string_view keyword) {
    return keyword == "o" || keyword == "g";
}

// Splits a statement into its keyword and the whitespace-separated arguments.
class Tokens {
public:
    explicit Tokens(std::string_view s) : s_(s) {}
    std::string_view next() {
        while (pos_ < s_.size() && (is_blank(s_[pos_]) || s_[pos_] == '\n')) ++pos_;
        const std::size_t start = pos_;
        while (pos_ < s_.size() && !is_blank(s_[pos_]) && s_[pos_] != '\n') ++pos_;
        return s_.substr(start, pos_ - start);
    }

private:
    std::string_view s_;
    std::size_t pos_ = 0;
};

std::unexpected<core::Error> error_at(std::size_t line, const std::string& what) {
    return core::fail(core::ErrorCode::kInvalidInput, fmt::format("line {}: {}", line, what));
}

// Vertex, texture and normal counts: the file's totals (positive indices may point
// forward, as assimp resolves them after reading the whole file) and those read so far
// (negative indices are relative to them).
struct Counts {
    std::size_t total[3] = {0, 0, 0};
    std::size_t so_far[3] = {0, 0, 0};
};

constexpr const char* kKind[3] = {"vertex", "texture", "normal"};
constexpr const char* kKinds[3] = {"vertices", "texture coordinates", "normals"};

int kind_of(std::string_view keyword) {
    if (keyword == "v") return 0;
    if (keyword == "vt") return 1;
    if (keyword == "vn") return 2;
    return -1;
}

// One corner of a face, line or point: "7", "7/2", "7//3", "-1/-1/-1". Returns the vertex's
// number counted from 1 (a relative index resolved).
core::Result<std::size_t> check_corner(std::string_view corner, const Counts& counts,
                                       std::size_t line) {
    std::size_t begin = 0;
    std::size_t vertex = 0;
    for (int part = 0; part < 3 && begin <= corner.size(); ++part) {
        std::size_t end = corner.find('/', begin);
        if (end == std::string_view::npos) end = corner.size();
        const std::string_view text = corner.substr(begin, end - begin);
        begin = end + 1;
        if (text.empty() && part > 0) continue;  // "7//3" has no texture index
        std::int64_t i = 0;
        const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), i);
        if (text.empty() || ec != std::errc{} || ptr != text.data() + text.size()) {
            return error_at(line,
                            fmt::format("face corner {} is not made of indices", shown(corner)));
        }
        const char* kind = kKind[part];
        if (i == 0) {
            return error_at(line, fmt::format("{} index 0 in {}: OBJ indices start at 1 (or -1 "
                                              "for the last one)",
                                              kind, shown(corner)));
        }
        if (i > 0 && static_cast<std::uint64_t>(i) > counts.total[part]) {
            return error_at(line, fmt::format("{} index {} but the file has only {} {}", kind, i,
                                              counts.total[part], kKinds[part]));
        }
        if (i < 0 && static_cast<std::uint64_t>(-(i + 1)) >= counts.so_far[part]) {
            return error_at(line, fmt::format("relative {} index {} but only {} {} come before "
                                              "this line",
                                              kind, i, counts.so_far[part], kKinds[part]));
        }
        if (part == 0) {
            vertex = i > 0 ? static_cast<std::size_t>(i)
                           : counts.so_far[0] - static_cast<std::size_t>(-(i + 1));
        }
        if (end == corner.size()) return vertex;
    }
    if (begin <= corner.size()) {
        return error_at(line, fmt::format("face corner {} has more than 3 indices", shown(corner)));
    }
    return vertex;
}

// A 'v' statement's point. Assimp reads 3 numbers as x y z, 4 as x y z w (divided by w) and
// 6 as x y z r g b, and silently skips a vertex with any other count, or whose numbers it does
// not take for numbers (".5"): every later index would then name the wrong vertex, a
// different part without a word. So the point is read here and handed to assimp as
// "v x y z" in the shortest digits that give back the same float (assimp holds coordinates
// as 32-bit floats: a larger number would become infinite there, so the range is checked
// here where the line is known).
core::Result<std::array<float, 3>> vertex_of(Tokens& tokens, std::size_t line) {
    constexpr int kMaxNumbers = 7;  // enough to tell 6 from more
    std::array<float, kMaxNumbers> v{};
    int numbers = 0;
    for (std::string_view t = tokens.next(); !t.empty() && numbers < kMaxNumbers;
         t = tokens.next()) {
        float value = 0.0f;
        const NumberRead got = parse_number(t, value);
        if (got != NumberRead::kOk) {
            return error_at(line, number_problem("vertex coordinate", t, got,
                                                 /*single_precision=*/true));
        }
        if (!std::isfinite(value)) {
            return error_at(line, fmt::format("vertex coordinate {} is not finite", shown(t)));
        }
        v[static_cast<std::size_t>(numbers++)] = value;
    }
    if (numbers < 3) {
        return error_at(line, fmt::format("a vertex needs 3 coordinates, found {}", numbers));
    }
    if (numbers == 5 || numbers > 6) {
        return error_at(line, fmt::format("a vertex has {} numbers; OBJ vertices have 3 (x y z), "
                                          "4 (x y z w) or 6 (x y z r g b)",
                                          numbers > 6 ? "more than 6" : "5"));
    }
    std::array<float, 3> p{v[0], v[1], v[2]};
    if (numbers == 4) {
        if (v[3] == 0.0f)
            return error_at(line, "a vertex with weight w = 0 (x y z w) is at infinity");
        for (float& c : p) c /= v[3];
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
            return error_at(line, "a vertex divided by its weight w is beyond the float range");
        }
    }
    return p;
}

}  // namespace

core::Result<ObjScan> scan_obj(std::string_view text) {
    // OBJ is text; assimp's parser writes through a wild pointer on a NUL byte inside an
    // 'mtllib' name (found by fuzz/fuzz_obj, fuzz/corpus/fuzz_obj/crash-07342c0c...).
    if (const std::size_t nul = text.find('\0'); nul != std::string_view::npos) {
        const auto line = static_cast<std::size_t>(
            1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(nul), '\n'));
        return error_at(line, "a NUL byte: an OBJ file is text");
    }
    ObjScan scan;
    Counts counts;
    {
        StatementReader reader(text);
        Statement st;
        while (reader.next(st)) {
            Tokens tokens(st.text);
            const int kind = kind_of(tokens.next());
            if (kind >= 0) ++counts.total[kind];
        }
    }
    StatementReader reader(text);
    Statement st;
    std::string face;
    scan.geometry.reserve(text.size());
    while (reader.next(st)) {
        Tokens tokens(st.text);
        const std::string_view keyword = tokens.next();
        const int kind = kind_of(keyword);
        if (kind == 0) {
            auto point = vertex_of(tokens, st.line);
            if (!point) return std::unexpected(point.error());
            scan.geometry.append(fmt::format("v {} {} {}", (*point)[0], (*point)[1], (*point)[2]));
        } else if (names_a_part(keyword)) {
            scan.geometry.append(keyword);
            for (std::string_view t = tokens.next(); !t.empty(); t = tokens.next()) {
                scan.geometry.push_back(' ');
                scan.geometry.append(t);
            }
        }
        const std::size_t lines_taken = reader.line() - st.line;
        if (kind >= 0) {
            scan.geometry.append(lines_taken, '\n');
            ++counts.so_far[kind];
            continue;
        }
        if (keyword == "f" || keyword == "p" || keyword == "l") {
            std::size_t corners = 0;
            face.assign("f");
            for (std::string_view t = tokens.next(); !t.empty(); t = tokens.next()) {
                const auto vertex = check_corner(t, counts, st.line);
                if (!vertex) return std::unexpected(vertex.error());
                fmt::format_to(std::back_inserter(face), " {}", *vertex);
                ++corners;
            }
            if (keyword == "f" && corners > kMaxPolygonCorners) {
                return error_at(st.line, fmt::format("face has {} corners; maxslice reads at "
                                                     "most {} per polygon",
                                                     corners, kMaxPolygonCorners));
            }
            if (keyword == "p") {
                scan.points += corners;
            } else if (keyword == "l") {
                ++scan.lines;
            } else if (corners < 3) {
                if (scan.short_faces++ == 0) scan.first_short_face_line = st.line;
            } else {
                ++scan.faces;
                scan.geometry.append(face);
            }
        }
        scan.geometry.append(lines_taken, '\n');
    }
    scan.vertices = counts.total[0];
    return scan;
}

}  // namespace maxslice::io::detail
