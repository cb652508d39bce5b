// libFuzzer harness: 3MF (lib3mf, then maxslice's build item and component collector), in
// this process. An input that starts with a zip signature is read as it is (the container
// itself is fuzzed, and crash inputs replay byte for byte); any other input is the model
// XML, packed here as 3D/3dmodel.model into an uncompressed zip with the 3MF content types
// and relationships, so that mutations reach the XML instead of breaking the deflate
// stream or the CRC.
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_read.hpp"
#include "support/three_mf_package.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    std::string packed;
    if (input.substr(0, 4) != std::string_view("PK\x03\x04", 4)) {
        packed = maxslice::test::three_mf_package(input);
    }
    const std::string_view bytes = packed.empty() ? input : std::string_view(packed);
    return maxslice::fuzz::check_raw(maxslice::io::detail::read_3mf(maxslice::fuzz::write_input(
        reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), ".3mf")));
}
