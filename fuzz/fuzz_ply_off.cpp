// libFuzzer harness: PLY (ASCII and binary) and OFF, maxslice's own readers. The first byte
// picks the reader so that one corpus covers both.
#include "fuzz_read.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const std::string_view bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
    return maxslice::fuzz::check_raw((data[0] & 1) != 0 ? maxslice::io::detail::read_off(bytes)
                                                        : maxslice::io::detail::read_ply(bytes));
}
