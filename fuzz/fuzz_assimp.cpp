// libFuzzer harness: OBJ, PLY and OFF (assimp, after maxslice's OBJ check). The first byte
// picks the extension so one corpus covers the three.
#include "fuzz_read.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    constexpr const char* kExtensions[] = {".obj", ".ply", ".off"};
    return maxslice::fuzz::read_as(data + 1, size - 1, kExtensions[data[0] % 3]);
}
