// Runs a harness without libFuzzer (for compilers without it, or to replay a corpus):
//   <harness>_replay [--mutations=N] [--seed=S] FILE_OR_DIR...
// Each file is passed as is, then N times mutated (bit flips, byte overwrites, truncation,
// a block duplicated or removed) with a fixed seed, so a failure is reproducible from the
// printed seed and index. Build it with sanitizers: a crash or report is the bug.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

std::vector<std::uint8_t> read_all(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void mutate(std::vector<std::uint8_t>& d, std::mt19937_64& rng) {
    const int edits = 1 + static_cast<int>(rng() % 8);
    for (int e = 0; e < edits && !d.empty(); ++e) {
        const std::size_t at = rng() % d.size();
        switch (rng() % 6) {
            case 0: d[at] ^= static_cast<std::uint8_t>(1u << (rng() % 8)); break;
            case 1: d[at] = static_cast<std::uint8_t>(rng()); break;
            case 2: d.resize(at); break;
            case 3: {
                const std::size_t len = std::min<std::size_t>(d.size() - at, 1 + rng() % 64);
                d.insert(d.begin() + static_cast<std::ptrdiff_t>(at),
                         d.begin() + static_cast<std::ptrdiff_t>(at),
                         d.begin() + static_cast<std::ptrdiff_t>(at + len));
                break;
            }
            case 4: {
                const std::size_t len = std::min<std::size_t>(d.size() - at, 1 + rng() % 64);
                d.erase(d.begin() + static_cast<std::ptrdiff_t>(at),
                        d.begin() + static_cast<std::ptrdiff_t>(at + len));
                break;
            }
            default: {  // an "interesting" value: digits and signs matter to text formats
                constexpr std::uint8_t kValues[] = {'0',  '9', '-',  '+',  '.',  'e', ' ',
                                                    '\n', '/', 0x00, 0xFF, 0x7F, 0x80};
                d[at] = kValues[rng() % sizeof(kValues)];
                break;
            }
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    long mutations = 0;
    std::uint64_t seed = 1;
    std::vector<std::filesystem::path> inputs;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg.rfind("--mutations=", 0) == 0) {
            mutations = std::strtol(arg.c_str() + 12, nullptr, 10);
        } else if (arg.rfind("--seed=", 0) == 0) {
            seed = std::strtoull(arg.c_str() + 7, nullptr, 10);
        } else if (std::filesystem::is_directory(arg)) {
            for (const auto& e : std::filesystem::recursive_directory_iterator(arg)) {
                if (e.is_regular_file()) inputs.push_back(e.path());
            }
        } else {
            inputs.emplace_back(arg);
        }
    }
    std::size_t runs = 0;
    for (const auto& path : inputs) {
        const std::vector<std::uint8_t> original = read_all(path);
        std::fprintf(stderr, "%s (%zu bytes)\n", path.c_str(), original.size());
        LLVMFuzzerTestOneInput(original.data(), original.size());
        ++runs;
        std::mt19937_64 rng(seed);
        for (long m = 0; m < mutations; ++m) {
            std::vector<std::uint8_t> d = original;
            mutate(d, rng);
            LLVMFuzzerTestOneInput(d.data(), d.size());
            ++runs;
        }
    }
    std::fprintf(stderr, "%zu inputs run\n", runs);
    return 0;
}
