// libFuzzer harness: STEP and IGES (Open CASCADE). The first byte picks the extension (the
// content decides the format anyway when it carries a STEP or IGES signature).
#include "fuzz_read.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    return maxslice::fuzz::read_as(data + 1, size - 1, (data[0] & 1) != 0 ? ".igs" : ".step");
}
