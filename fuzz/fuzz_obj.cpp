// libFuzzer harness: OBJ. maxslice's own scan (scan_obj: numbers, indices, corner counts,
// UTF-16) and then assimp's triangulation, called in this process (read_mesh runs assimp in
// a child process, where the fuzzer would neither see the coverage nor the sanitizer reports).
#include "fuzz_read.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    return maxslice::fuzz::check_raw(
        maxslice::io::detail::read_with_assimp(bytes, maxslice::io::Format::kObj));
}
