// libFuzzer harness: STEP and IGES, through read_mesh. Open CASCADE runs in the reader program
// maxslice-read-part there (it dereferences null handles on some damaged files), so this
// harness checks what the program sees: the reader's crash or time-out becomes a refusal, the
// result that comes back through the pipe is well formed, and a sanitizer report on
// maxslice's own code in the reader comes back as an internal error, which fails the harness
// (src/io/isolated.cpp). The fuzzer sees the coverage of this process only.
// The first byte picks the extension (the content decides the format anyway when it
// carries a STEP or IGES signature).
#include "fuzz_read.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    return maxslice::fuzz::read_as(data + 1, size - 1, (data[0] & 1) != 0 ? ".igs" : ".step");
}
