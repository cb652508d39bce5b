#pragma once
// A 3MF package built in memory: a zip of stored (uncompressed) entries holding the three
// parts lib3mf needs. Used by the 3MF reader tests and the 3MF fuzz harness (which packs
// mutated model XML with it, so that mutations reach the XML instead of breaking the
// deflate stream or the CRC).
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace maxslice::test {

namespace zip_detail {

inline std::uint32_t crc32(std::string_view bytes) {
    std::uint32_t crc = 0xFFFFFFFFu;
    for (const char ch : bytes) {
        crc ^= static_cast<unsigned char>(ch);
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

inline void put16(std::string& out, std::uint32_t v) {
    out.push_back(static_cast<char>(v & 0xFF));
    out.push_back(static_cast<char>((v >> 8) & 0xFF));
}

inline void put32(std::string& out, std::uint32_t v) {
    put16(out, v & 0xFFFF);
    put16(out, v >> 16);
}

}  // namespace zip_detail

/// A zip archive of stored entries (method 0): names and contents.
inline std::string stored_zip(
    const std::vector<std::pair<std::string_view, std::string_view>>& entries) {
    using zip_detail::put16;
    using zip_detail::put32;
    std::string out;
    std::string directory;
    for (const auto& [name, data] : entries) {
        const auto offset = static_cast<std::uint32_t>(out.size());
        const std::uint32_t crc = zip_detail::crc32(data);
        const auto size = static_cast<std::uint32_t>(data.size());
        const auto name_size = static_cast<std::uint32_t>(name.size());
        put32(out, 0x04034b50);  // local file header
        put16(out, 20);          // version needed
        put16(out, 0);           // flags
        put16(out, 0);           // stored
        put16(out, 0);           // time
        put16(out, 0x21);        // date: 1980-01-01
        put32(out, crc);
        put32(out, size);
        put32(out, size);
        put16(out, name_size);
        put16(out, 0);  // extra
        out += name;
        out += data;
        put32(directory, 0x02014b50);  // central directory header
        put16(directory, 20);
        put16(directory, 20);
        put16(directory, 0);
        put16(directory, 0);
        put16(directory, 0);
        put16(directory, 0x21);
        put32(directory, crc);
        put32(directory, size);
        put32(directory, size);
        put16(directory, name_size);
        put16(directory, 0);  // extra
        put16(directory, 0);  // comment
        put16(directory, 0);  // disk
        put16(directory, 0);  // internal attributes
        put32(directory, 0);  // external attributes
        put32(directory, offset);
        directory += name;
    }
    const auto directory_at = static_cast<std::uint32_t>(out.size());
    out += directory;
    put32(out, 0x06054b50);  // end of central directory
    put16(out, 0);
    put16(out, 0);
    put16(out, static_cast<std::uint32_t>(entries.size()));
    put16(out, static_cast<std::uint32_t>(entries.size()));
    put32(out, static_cast<std::uint32_t>(directory.size()));
    put32(out, directory_at);
    put16(out, 0);
    return out;
}

/// A 3MF package whose 3D/3dmodel.model is `model_xml`, with the content types and the
/// relationship that point to it.
inline std::string three_mf_package(std::string_view model_xml) {
    constexpr std::string_view kContentTypes =
        R"(<?xml version="1.0" encoding="UTF-8"?>)"
        R"(<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">)"
        R"(<Default Extension="rels" )"
        R"(ContentType="application/vnd.openxmlformats-package.relationships+xml"/>)"
        R"(<Default Extension="model" )"
        R"(ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/></Types>)";
    constexpr std::string_view kRelationships =
        R"(<?xml version="1.0" encoding="UTF-8"?>)"
        R"(<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">)"
        R"(<Relationship Target="/3D/3dmodel.model" Id="rel0" )"
        R"(Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>)";
    return stored_zip({{"[Content_Types].xml", kContentTypes},
                       {"_rels/.rels", kRelationships},
                       {"3D/3dmodel.model", model_xml}});
}

}  // namespace maxslice::test
