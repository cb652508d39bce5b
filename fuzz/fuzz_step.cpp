// libFuzzer harness: STEP and IGES, through read_mesh. Open CASCADE runs in a child process
// there (it dereferences null handles on some damaged files), so this harness checks what
// the program sees: the child's crash or time-out becomes a refusal, the result that comes
// back through the pipe is well formed. The fuzzer sees the coverage of this process only.
// The first byte picks the extension (the content decides the format anyway when it
// carries a STEP or IGES signature).
#include <pthread.h>
#include <signal.h>

#include "fuzz_read.hpp"

namespace {

// In the reader's child, a signal must end the child as it does in the maxslice program (the
// parent then refuses the file): without this, libFuzzer's and AddressSanitizer's handlers,
// inherited through fork, would report an Open CASCADE crash in the child as a crash of the
// harness. Sanitizer reports on maxslice's own code in the child (occt_reader.cpp) still are.
void default_signals_in_child() {
    for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) ::signal(sig, SIG_DFL);
}

const bool kAtFork = ::pthread_atfork(nullptr, nullptr, default_signals_in_child) == 0;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (!kAtFork || size == 0) return 0;
    return maxslice::fuzz::read_as(data + 1, size - 1, (data[0] & 1) != 0 ? ".igs" : ".step");
}
