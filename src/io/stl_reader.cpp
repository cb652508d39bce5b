// STL, binary and ASCII. ASCII: the whole text is in memory, numbers are read with from_chars
// and corners go into one float soup that mesh::weld_exact turns into an indexed mesh. Binary:
// the records are read and welded a block at a time (mesh::BlockWelder).
//
// Binary or ASCII is decided from the content, never from the header alone: many binary
// writers start the 80-byte header with "solid". A file is read as ASCII only when it
// starts with "solid" (after an optional UTF-8 BOM and white space) and contains no binary
// control bytes; everything else must have the binary layout 84 + 50 n bytes.
//
// Stored facet normals are ignored: the vertex order (counter-clockwise from outside)
// defines the orientation. They are only compared with the winding to warn when many
// point the other way, which usually means the winding is what is wrong.

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "readers.hpp"

namespace maxslice::io::detail {
namespace {

constexpr std::size_t kHeaderBytes = 84;  // 80-byte header + uint32 triangle count
constexpr std::size_t kRecordBytes = 50;  // normal, 3 corners (12 floats) + uint16 attribute
// mesh::weld_exact indexes corners with uint32.
constexpr std::uint64_t kMaxTriangles = 1'400'000'000;

bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
}

char lower(char c) {
    return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
}

bool iequals(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (lower(a[i]) != b[i]) return false;
    }
    return true;
}

std::string_view skip_bom(std::string_view s) {
    if (s.size() >= 3 && s.substr(0, 3) == "\xEF\xBB\xBF") s.remove_prefix(3);
    return s;
}

bool starts_with_solid(std::string_view s) {
    s = skip_bom(s);
    std::size_t i = 0;
    while (i < s.size() && is_space(s[i])) ++i;
    if (s.size() - i < 5 || !iequals(s.substr(i, 5), "solid")) return false;
    return s.size() - i == 5 || is_space(s[i + 5]);
}

// ASCII STL never holds control bytes other than white space (0x1A is the old DOS
// end-of-file mark); binary STL nearly always does, starting with the triangle count.
bool looks_like_text(std::string_view s) {
    for (const char ch : s) {
        const auto c = static_cast<unsigned char>(ch);
        if (c < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\f' && c != '\v' &&
            c != 0x1A) {
            return false;
        }
    }
    return true;
}

// The first word after the "solid" line, when that line is text: "facet" or "endsolid" there
// is what an ASCII writer puts; a binary header that starts with "solid" (80 bytes, then the
// triangle count) has no reason to.
bool first_facet_is_text(std::string_view s) {
    s = skip_bom(s);
    const std::size_t eol = s.find('\n');
    if (eol == std::string_view::npos || !looks_like_text(s.substr(0, eol))) return false;
    std::size_t i = eol + 1;
    while (i < s.size() && is_space(s[i])) ++i;
    std::size_t end = i;
    while (end < s.size() && !is_space(s[end])) ++end;
    const std::string_view word = s.substr(i, end - i);
    return iequals(word, "facet") || iequals(word, "endsolid");
}

// Where a control byte sits in a text that should have none: "line 3, column 7, byte 0x01".
core::Error control_byte_error(std::string_view text) {
    std::size_t line = 1;
    std::size_t column = 1;
    for (const char ch : text) {
        const auto c = static_cast<unsigned char>(ch);
        if (c < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\f' && c != '\v' &&
            c != 0x1A) {
            return core::Error{
                core::ErrorCode::kInvalidInput,
                fmt::format("line {}, column {}: control byte \\x{:02X} in an ASCII STL (the file "
                            "starts with 'solid' and its first facet is text, so it is read as "
                            "ASCII); a text file holds no such byte: the file is damaged, export "
                            "it again",
                            line, column, c),
                {}};
        }
        if (ch == '\n') {
            ++line;
            column = 1;
        } else {
            ++column;
        }
    }
    return core::Error{core::ErrorCode::kInternal, "no control byte", {}};
}

// A token for a message: at most 40 characters, non-printable bytes as \xNN.
std::string quote(std::string_view token) {
    std::string out = "'";
    for (std::size_t i = 0; i < token.size() && i < 40; ++i) {
        const auto c = static_cast<unsigned char>(token[i]);
        if (c >= 0x20 && c < 0x7F) {
            out.push_back(static_cast<char>(c));
        } else {
            out += fmt::format("\\x{:02X}", c);
        }
    }
    if (token.size() > 40) out += "...";
    return out + "'";
}

std::uint32_t load_u32_le(const char* p) {
    std::uint32_t v;
    std::memcpy(&v, p, 4);
    if constexpr (std::endian::native == std::endian::big) v = std::byteswap(v);
    return v;
}

// Counts stored normals that point against the winding normal. Zero, NaN or missing normals
// say nothing and are not counted.
bool normal_opposes_winding(const float* n, const float* c) {
    const float ux = c[3] - c[0], uy = c[4] - c[1], uz = c[5] - c[2];
    const float vx = c[6] - c[0], vy = c[7] - c[1], vz = c[8] - c[2];
    const float wx = uy * vz - uz * vy, wy = uz * vx - ux * vz, wz = ux * vy - uy * vx;
    return n[0] * wx + n[1] * wy + n[2] * wz < 0.0f;
}

void warn_opposite_normals(RawImport& out, std::size_t opposite, std::size_t total) {
    if (opposite == 0) return;
    out.warnings.push_back(fmt::format(
        "{} of {} stored facet normals point against the vertex winding; stored normals are "
        "ignored and the winding defines the outside{}",
        opposite, total,
        opposite * 2 > total ? " (most disagree: the part may come out inside-out)" : ""));
}

// The binary layout check and the record loop, for records that are either in memory or
// read from the file in blocks: fetch(first, count) returns count records from record
// `first` on (always called in order), has_replacement_char() looks for EF BF BD in the
// whole file (only on the error path).
template <class Fetch, class HasReplacementChar>
core::Result<RawImport> read_binary(std::uint64_t size, std::string_view header,
                                    bool header_says_solid, Fetch&& fetch,
                                    HasReplacementChar&& has_replacement_char) {
    const std::string not_ascii =
        header_says_solid ? "the header starts with 'solid' but the file holds binary bytes, so "
                            "it is read as binary STL"
                          : "the file does not start with 'solid', so it is read as binary STL";
    if (size < kHeaderBytes || header.size() < kHeaderBytes) {
        return core::fail(core::ErrorCode::kInvalidInput,
                          fmt::format("not an STL file: {}, which needs at least 84 bytes, and "
                                      "the file has {}",
                                      not_ascii, size));
    }
    const std::uint64_t declared = load_u32_le(header.data() + 80);
    const std::uint64_t body = size - kHeaderBytes;
    if (body % kRecordBytes != 0) {
        std::string msg = fmt::format(
            "damaged binary STL: {} bytes is not 84 + 50 x n (the header says {} triangles = "
            "{} bytes; {} bytes are left after the last whole 50-byte triangle record)",
            size, declared, kHeaderBytes + declared * kRecordBytes, body % kRecordBytes);
        if (has_replacement_char()) {
            msg +=
                "; it contains the bytes EF BF BD (the Unicode replacement character), the mark "
                "of a binary file passed through a text conversion: export or copy it again in "
                "binary mode";
        } else {
            msg += "; the file is truncated or has extra bytes: export it again";
        }
        if (header_says_solid) msg += " (" + not_ascii + ")";
        return core::fail(core::ErrorCode::kInvalidInput, msg);
    }
    const std::uint64_t records = body / kRecordBytes;
    RawImport out;
    out.format = Format::kStlBinary;
    out.solids = 1;
    if (records != declared) {
        out.warnings.push_back(
            fmt::format("the binary STL header says {} triangles but the file holds {}; reading {}",
                        declared, records, records));
    }
    if (records == 0) {
        return core::fail(core::ErrorCode::kInvalidInput,
                          "no triangles: the binary STL has a header and no triangle records");
    }
    if (records > kMaxTriangles) {
        return core::fail(core::ErrorCode::kInvalidInput,
                          fmt::format("{} triangles is more than the {} maxslice can index",
                                      records, kMaxTriangles));
    }
    const auto n = static_cast<std::size_t>(records);

    // Read and welded a block at a time: the records and their corners stay in the cache and
    // no buffer the size of the file is ever touched (first touches of fresh pages cost more
    // than the parsing; measured on a VM: 12 us a page).
    mesh::BlockWelder welder(n);
    std::vector<float> xyz;
    std::size_t opposite = 0;
    constexpr std::size_t kBlock = 4096;  // records per fetch (200 KB)
    for (std::size_t first = 0; first < n; first += kBlock) {
        const std::size_t count = std::min(kBlock, n - first);
        auto block = fetch(first, count);
        if (!block) return std::unexpected(block.error());
        xyz.resize(count * 9);
        std::uint32_t exponent_all_ones = 0;
        const char* rec = *block;
        for (std::size_t t = 0; t < count; ++t, rec += kRecordBytes) {
            float* c = xyz.data() + 9 * t;
            std::memcpy(c, rec + 12, 36);
            float normal[3];
            std::memcpy(normal, rec, 12);
            if constexpr (std::endian::native == std::endian::big) {
                for (int k = 0; k < 9; ++k) {
                    c[k] = std::bit_cast<float>(std::byteswap(std::bit_cast<std::uint32_t>(c[k])));
                }
                for (float& f : normal) {
                    f = std::bit_cast<float>(std::byteswap(std::bit_cast<std::uint32_t>(f)));
                }
            }
            for (int k = 0; k < 9; ++k) {
                const auto bits = std::bit_cast<std::uint32_t>(c[k]);
                exponent_all_ones |=
                    static_cast<std::uint32_t>((bits & 0x7F800000u) == 0x7F800000u);
            }
            opposite += static_cast<std::size_t>(normal_opposes_winding(normal, c));
        }
        if (exponent_all_ones != 0) {
            for (std::size_t i = 0; i < count * 9; ++i) {
                if (std::isfinite(xyz[i])) continue;
                const std::size_t t = first + i / 9;
                return core::fail(
                    core::ErrorCode::kInvalidInput,
                    fmt::format("triangle {} (byte offset {}): vertex {} has a NaN "
                                "or infinite coordinate",
                                t + 1, kHeaderBytes + t * kRecordBytes + 12 + 12 * (i % 9 / 3),
                                i % 9 / 3 + 1));
            }
        }
        welder.add(xyz);
    }
    warn_opposite_normals(out, opposite, n);
    out.mesh = std::move(welder).finish();
    return out;
}

core::Result<RawImport> read_binary_in_memory(std::string_view bytes, bool header_says_solid) {
    return read_binary(
        bytes.size(), bytes.substr(0, std::min(bytes.size(), kHeaderBytes)), header_says_solid,
        [&](std::size_t first, std::size_t) -> core::Result<const char*> {
            return bytes.data() + kHeaderBytes + first * kRecordBytes;
        },
        [&] { return bytes.find("\xEF\xBF\xBD") != std::string_view::npos; });
}

// Whitespace-separated tokens with the line each starts on.
class Lexer {
public:
    explicit Lexer(std::string_view text) : p_(text.data()), end_(text.data() + text.size()) {}

    std::string_view next() {
        skip_space();
        token_line_ = line_;
        const char* start = p_;
        while (p_ < end_ && !is_space(*p_)) ++p_;
        return {start, static_cast<std::size_t>(p_ - start)};
    }
    std::string_view peek() {
        const char* p = p_;
        const std::size_t line = line_;
        const std::size_t token_line = token_line_;
        const std::string_view t = next();
        p_ = p;
        line_ = line;
        token_line_ = token_line;
        return t;
    }
    /// The rest of the current line without surrounding white space (a solid's name).
    std::string_view rest_of_line() {
        while (p_ < end_ && (*p_ == ' ' || *p_ == '\t')) ++p_;
        const char* start = p_;
        while (p_ < end_ && *p_ != '\n') ++p_;
        const char* stop = p_;
        while (stop > start && is_space(stop[-1])) --stop;
        return {start, static_cast<std::size_t>(stop - start)};
    }
    /// The line the last token started on (1-based).
    [[nodiscard]] std::size_t line() const { return token_line_; }

private:
    void skip_space() {
        while (p_ < end_ && is_space(*p_)) {
            if (*p_ == '\n') ++line_;
            ++p_;
        }
    }

    const char* p_;
    const char* end_;
    std::size_t line_ = 1;
    std::size_t token_line_ = 1;
};

class AsciiParser {
public:
    explicit AsciiParser(std::string_view text) : lex_(text) {
        xyz_.reserve(std::min<std::size_t>(text.size() / 200 * 9, std::size_t{1} << 28));
    }

    core::Result<RawImport> parse() {
        RawImport out;
        out.format = Format::kStlAscii;
        std::string_view tok = lex_.next();  // "solid": checked by the caller
        lex_.rest_of_line();
        std::size_t blocks = 1;
        bool open_block = true;
        bool missing_endsolid = false;
        while (true) {
            tok = lex_.next();
            if (tok.empty()) {
                missing_endsolid = missing_endsolid || open_block;
                break;
            }
            if (iequals(tok, "facet")) {
                if (!open_block) {
                    return error(lex_.line(), "'facet' after 'endsolid' without a new 'solid'");
                }
                if (auto ok = parse_facet(); !ok) return std::unexpected(ok.error());
            } else if (iequals(tok, "endsolid")) {
                if (!open_block) return error(lex_.line(), "'endsolid' without 'solid'");
                lex_.rest_of_line();  // the name need not match the 'solid' line's
                open_block = false;
            } else if (iequals(tok, "solid")) {
                missing_endsolid = missing_endsolid || open_block;
                ++blocks;
                open_block = true;
                lex_.rest_of_line();
            } else {
                return error(lex_.line(),
                             fmt::format("expected 'facet' or 'endsolid', found {}", quote(tok)));
            }
        }
        const std::size_t triangles = xyz_.size() / 9;
        if (triangles == 0) {
            return core::fail(core::ErrorCode::kInvalidInput,
                              "no triangles: the ASCII STL has no facets");
        }
        out.solids = blocks;
        if (blocks > 1) {
            out.warnings.push_back(fmt::format(
                "{} 'solid' blocks in one ASCII STL; all their triangles are read as one part",
                blocks));
        }
        if (missing_endsolid) {
            out.warnings.push_back(
                "the ASCII STL has no 'endsolid' after its last facet; the file may be "
                "truncated");
        }
        warn_opposite_normals(out, opposite_normals_, triangles);
        out.mesh = mesh::weld_exact(std::span<const float>(xyz_));
        return out;
    }

private:
    std::unexpected<core::Error> error(std::size_t line, const std::string& what) const {
        return core::fail(core::ErrorCode::kInvalidInput, fmt::format("line {}: {}", line, what));
    }

    core::Result<void> expect(std::string_view keyword, std::string_view after) {
        const std::string_view tok = lex_.next();
        if (iequals(tok, keyword)) return {};
        return error(lex_.line(),
                     fmt::format("expected '{}' after '{}', found {}", keyword, after,
                                 tok.empty() ? std::string("the end of the file") : quote(tok)));
    }

    core::Result<void> parse_facet() {
        const std::size_t facet_line = lex_.line();
        float normal[3] = {0.0f, 0.0f, 0.0f};
        std::string_view tok = lex_.next();
        if (iequals(tok, "normal")) {
            // Up to three numbers; missing, NaN, zero or out-of-range components are
            // accepted (normals are ignored; those say nothing), text that is not a number
            // is not.
            for (int k = 0; k < 3; ++k) {
                const std::string_view t = lex_.peek();
                if (t.empty() || iequals(t, "outer") || iequals(t, "vertex") ||
                    iequals(t, "endfacet")) {
                    break;
                }
                lex_.next();
                float v = 0.0f;
                const NumberRead got = parse_number(t, v);
                if (got == NumberRead::kOutOfRange) continue;
                if (got != NumberRead::kOk) {
                    return error(
                        lex_.line(),
                        fmt::format("facet normal component {} is not a number", quote(t)));
                }
                normal[k] = v;
            }
            tok = lex_.next();
        }
        if (!iequals(tok, "outer")) {
            return error(lex_.line(), fmt::format("expected 'outer loop' in the facet at line "
                                                  "{}, found {}",
                                                  facet_line,
                                                  tok.empty() ? std::string("the end of the file")
                                                              : quote(tok)));
        }
        if (auto ok = expect("loop", "outer"); !ok) return ok;
        float corners[9];
        std::size_t count = 0;
        while (true) {
            tok = lex_.next();
            if (iequals(tok, "vertex")) {
                const std::size_t vertex_line = lex_.line();
                float c[3];
                for (float& v : c) {
                    const std::string_view t = lex_.next();
                    const NumberRead got = t.empty() ? NumberRead::kNotANumber : parse_number(t, v);
                    if (got == NumberRead::kOutOfRange) {
                        return error(vertex_line, number_problem("vertex coordinate", t, got,
                                                                 /*single_precision=*/true) +
                                                      " (ASCII STL holds 32-bit floats)");
                    }
                    if (got != NumberRead::kOk) {
                        return error(
                            vertex_line,
                            fmt::format("a vertex needs 3 numbers; found {}",
                                        t.empty() ? std::string("the end of the file") : quote(t)));
                    }
                    if (!std::isfinite(v)) {
                        return error(vertex_line,
                                     fmt::format("vertex coordinate {} is not finite", quote(t)));
                    }
                }
                if (count < 3) std::copy(c, c + 3, corners + 3 * count);
                ++count;
            } else if (iequals(tok, "endloop")) {
                break;
            } else if (tok.empty()) {
                return error(lex_.line(), fmt::format("the file ends inside the facet that "
                                                      "starts at line {}",
                                                      facet_line));
            } else {
                return error(lex_.line(),
                             fmt::format("expected 'vertex' or 'endloop', found {}", quote(tok)));
            }
        }
        if (count != 3) {
            return error(facet_line,
                         fmt::format("facet has {} vertices; STL facets must be triangles (3 "
                                     "vertices)",
                                     count));
        }
        if (auto ok = expect("endfacet", "endloop"); !ok) return ok;
        xyz_.insert(xyz_.end(), corners, corners + 9);
        opposite_normals_ += static_cast<std::size_t>(normal_opposes_winding(normal, corners));
        return {};
    }

    Lexer lex_;
    std::vector<float> xyz_;
    std::size_t opposite_normals_ = 0;
};

}  // namespace

bool stl_is_ascii(std::string_view head) {
    return starts_with_solid(head) && (looks_like_text(head) || first_facet_is_text(head));
}

core::Result<RawImport> read_stl(std::string_view bytes) {
    if (bytes.empty()) {
        return core::fail(core::ErrorCode::kInvalidInput, "the file is empty (0 bytes)");
    }
    const bool solid = starts_with_solid(bytes);
    try {
        if (stl_is_ascii(bytes)) {
            // Text with a stray control byte is a damaged ASCII file, not a binary one: say
            // where the byte is rather than measure the text against the binary layout.
            if (!looks_like_text(bytes)) return std::unexpected(control_byte_error(bytes));
            return AsciiParser(skip_bom(bytes)).parse();
        }
        return read_binary_in_memory(bytes, solid);
    } catch (const std::bad_alloc&) {
        return core::fail(core::ErrorCode::kInvalidInput, "not enough memory for the mesh");
    }
}

core::Result<RawImport> read_stl_file(const std::filesystem::path& path, std::string_view head,
                                      std::uint64_t size) {
    const bool solid = starts_with_solid(head);
    if (size <= head.size() || stl_is_ascii(head)) {
        // Small files and (probable) ASCII: the whole text in memory; read_stl checks again
        // that all of it is text.
        if (size <= head.size()) return read_stl(head);
        auto bytes = read_file(path);
        if (!bytes) return std::unexpected(bytes.error());
        return read_stl(bytes->view());
    }
    // Binary: the records are read in blocks straight into the corner array, so a large file
    // is never held in memory twice.
    auto file = PositionalFile::open(path);
    if (!file) return std::unexpected(file.error());
    std::vector<char> block;
    std::uint64_t expected_offset = kHeaderBytes;
    try {
        return read_binary(
            size, head.substr(0, std::min(head.size(), kHeaderBytes)), solid,
            [&](std::size_t first, std::size_t count) -> core::Result<const char*> {
                const std::uint64_t offset = kHeaderBytes + std::uint64_t{first} * kRecordBytes;
                if (offset != expected_offset) {
                    return core::fail(core::ErrorCode::kInternal, "STL blocks out of order");
                }
                block.resize(count * kRecordBytes);
                auto got = file->read_at(offset, block.data(), block.size());
                if (!got) return std::unexpected(got.error());
                if (*got != block.size()) {
                    return core::fail(core::ErrorCode::kIo,
                                      "the file got shorter while it was read");
                }
                expected_offset = offset + block.size();
                return block.data();
            },
            [&] {
                auto whole = read_file(path);
                return whole && whole->view().find("\xEF\xBF\xBD") != std::string_view::npos;
            });
    } catch (const std::bad_alloc&) {
        return core::fail(core::ErrorCode::kInvalidInput, "not enough memory for the mesh");
    }
}

}  // namespace maxslice::io::detail
