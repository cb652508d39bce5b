// Writes the planner's fixtures (tests/support/planner_fixtures.hpp) as binary STL files, so
// the benchmark scripts can run the CLI on them: export_fixtures DIR.
#include <cstdio>
#include <filesystem>

#include "maxslice/io/read_mesh.hpp"
#include "support/planner_fixtures.hpp"

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: export_fixtures DIR\n");
        return 2;
    }
    const std::filesystem::path dir = argv[1];
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    for (const auto& f : maxslice::test::all_planner_fixtures()) {
        const auto file = dir / (f.name + ".stl");
        if (auto ok = maxslice::io::write_stl_binary(file, f.mesh); !ok) {
            std::fprintf(stderr, "export_fixtures: %s\n", ok.error().describe().c_str());
            return 1;
        }
        std::printf("%s\n", file.c_str());
    }
    return 0;
}
