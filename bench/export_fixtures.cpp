// Writes the planner's fixtures (tests/support/planner_fixtures.hpp) as binary STL files, so
// the benchmark scripts can run the CLI on them: export_fixtures DIR [TURN_DEG]. With
// TURN_DEG each fixture is turned about Z by that many degrees through the middle of its box
// across Z, as the test FiveAxisSlow.EveryFixtureTurnedAboutZKeepsItsRegionsAndItsVerdict
// turns them.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "maxslice/io/read_mesh.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"
#include "support/fixtures.hpp"
#include "support/planner_fixtures.hpp"

int main(int argc, char** argv) {
    if (argc != 2 && argc != 3) {
        std::fprintf(stderr, "usage: export_fixtures DIR [TURN_DEG]\n");
        return 2;
    }
    double turn = 0.0;
    if (argc == 3) {
        const char* text = argv[2];
        const char* end = text + std::strlen(text);
        const auto [at, ec] = std::from_chars(text, end, turn);
        if (ec != std::errc() || at != end || !std::isfinite(turn)) {
            std::fprintf(stderr, "export_fixtures: TURN_DEG must be a number, not '%s'\n", text);
            return 2;
        }
    }
    const std::filesystem::path dir = argv[1];
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    for (auto f : maxslice::test::all_planner_fixtures()) {
        if (turn != 0.0) {
            const maxslice::core::Box3d box = maxslice::mesh::bounding_box(f.mesh);
            f.mesh = maxslice::test::rotated(
                f.mesh, {0.0, 0.0, 1.0}, turn,
                {0.5 * (box.min.x + box.max.x), 0.5 * (box.min.y + box.max.y), 0.0});
        }
        const auto file = dir / (f.name + ".stl");
        if (auto ok = maxslice::io::write_stl_binary(file, f.mesh); !ok) {
            std::fprintf(stderr, "export_fixtures: %s\n", ok.error().describe().c_str());
            return 1;
        }
        std::printf("%s\n", file.c_str());
    }
    return 0;
}
