// libFuzzer harness: STL, binary and ASCII (maxslice's own reader), through read_mesh: the
// sniffing, the streamed binary records, the units and the finite check.
#include "fuzz_read.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return maxslice::fuzz::read_as(data, size, ".stl");
}
