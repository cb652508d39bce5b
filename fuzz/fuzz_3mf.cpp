// libFuzzer harness: 3MF (lib3mf, then maxslice's build item and component collector), in
// this process. An input that starts with a zip signature is read as it is (the container
// itself is fuzzed, and crash inputs replay byte for byte); any other input is the model
// XML, packed here as 3D/3dmodel.model into an uncompressed zip with the 3MF content types
// and relationships, so that mutations reach the XML instead of breaking the deflate
// stream or the CRC.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_read.hpp"

namespace {

std::uint32_t crc32(std::string_view bytes) {
    std::uint32_t crc = 0xFFFFFFFFu;
    for (const char ch : bytes) {
        crc ^= static_cast<unsigned char>(ch);
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

void put16(std::string& out, std::uint32_t v) {
    out += static_cast<char>(v & 0xFF);
    out += static_cast<char>((v >> 8) & 0xFF);
}

void put32(std::string& out, std::uint32_t v) {
    put16(out, v & 0xFFFF);
    put16(out, v >> 16);
}

/// A zip archive of uncompressed entries (names and contents).
std::string stored_zip(const std::array<std::pair<std::string_view, std::string_view>, 3>& files) {
    std::string zip;
    std::string directory;
    for (const auto& [name, data] : files) {
        const auto offset = static_cast<std::uint32_t>(zip.size());
        const std::uint32_t crc = crc32(data);
        const auto size = static_cast<std::uint32_t>(data.size());
        const auto name_size = static_cast<std::uint32_t>(name.size());
        put32(zip, 0x04034b50);  // local file header
        put16(zip, 20);
        put16(zip, 0);
        put16(zip, 0);  // stored
        put16(zip, 0);
        put16(zip, 0x21);  // 1980-01-01
        put32(zip, crc);
        put32(zip, size);
        put32(zip, size);
        put16(zip, name_size);
        put16(zip, 0);
        zip += name;
        zip += data;
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
        put16(directory, 0);
        put16(directory, 0);
        put16(directory, 0);
        put16(directory, 0);
        put32(directory, 0);
        put32(directory, offset);
        directory += name;
    }
    const auto directory_offset = static_cast<std::uint32_t>(zip.size());
    zip += directory;
    put32(zip, 0x06054b50);  // end of central directory
    put16(zip, 0);
    put16(zip, 0);
    put16(zip, static_cast<std::uint32_t>(files.size()));
    put16(zip, static_cast<std::uint32_t>(files.size()));
    put32(zip, static_cast<std::uint32_t>(directory.size()));
    put32(zip, directory_offset);
    put16(zip, 0);
    return zip;
}

constexpr std::string_view kContentTypes =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Types xmlns=\"http://schemas.openxmlformats.org/"
    "package/2006/content-types\"><Default Extension=\"rels\" ContentType=\"application/"
    "vnd.openxmlformats-package.relationships+xml\"/><Default Extension=\"model\" "
    "ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/></Types>";
constexpr std::string_view kRelationships =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Relationships xmlns=\"http://schemas."
    "openxmlformats.org/package/2006/relationships\"><Relationship Target=\"/3D/3dmodel.model\" "
    "Id=\"rel0\" Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/>"
    "</Relationships>";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    std::string packed;
    if (input.substr(0, 4) != std::string_view("PK\x03\x04", 4)) {
        packed = stored_zip({{{"[Content_Types].xml", kContentTypes},
                              {"_rels/.rels", kRelationships},
                              {"3D/3dmodel.model", input}}});
    }
    const std::string_view bytes = packed.empty() ? input : std::string_view(packed);
    return maxslice::fuzz::check_raw(maxslice::io::detail::read_3mf(maxslice::fuzz::write_input(
        reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), ".3mf")));
}
