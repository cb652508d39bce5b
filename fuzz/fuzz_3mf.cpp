// libFuzzer harness: 3MF (lib3mf). Seed it with real .3mf files: the zip container must
// survive for the XML inside to be reached.
#include "fuzz_read.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return maxslice::fuzz::read_as(data, size, ".3mf");
}
