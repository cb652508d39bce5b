// libFuzzer harness: 3MF (lib3mf, then maxslice's build item and component collector), in
// this process. Seed it with real .3mf files: the zip container must survive for the XML
// inside to be reached.
#include "fuzz_read.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return maxslice::fuzz::check_raw(
        maxslice::io::detail::read_3mf(maxslice::fuzz::write_input(data, size, ".3mf")));
}
