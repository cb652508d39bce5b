// Micro-benchmarks of the first two stages of a job: reading a part (parse + exact weld) and
// slicing it into uniform layers (cut + wire trees). Whole-process comparisons with the peer
// slicers are in compare_peers.sh; docs/benchmarks.md has the figures.
//
// Models: the lattice cone in MAXSLICE_TESTDATA_DIR (a real 0.5 M-triangle CAD export), a
// torus built here (2 M triangles, the shape of the peers' torus2m.stl, without any file),
// and any binary or ASCII STL named in the environment variable MAXSLICE_BENCH_MODELS
// (colon-separated paths), e.g. the torus2m.stl / bunny1m.stl that compare_peers.sh makes.
//
// Arguments of the slicing benchmarks: layer thickness in micrometres, worker threads
// (tbb::global_control). "Time" is wall clock (UseRealTime), since the slicer is parallel;
// "CPU" is the whole process's CPU time (all threads).
// BM_ReadFile is the floor for a reader: the file's bytes copied into memory from the page
// cache (the cache is warm after the first iteration), no parsing.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "maxslice/io/read_mesh.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"
#include "maxslice/slice/layers.hpp"
#include "maxslice/slice/slicer.hpp"

namespace {

using namespace maxslice;

const std::filesystem::path kLatticeCone =
    std::filesystem::path(MAXSLICE_TESTDATA_DIR) / "large" / "Spiral_lattice_cone_2_occt.stl";

constexpr int kTorusSteps = 1000;  // 2 x 1000 x 1000 triangles, as torus2m.stl

// A torus around the Z axis lying on z = 0 (major radius r_major, tube radius r_tube), with
// nu x nv quads split into two outward-facing, counter-clockwise triangles each. Same
// vertex positions and triangles as make_big_mesh.py torus, but indexed (no weld needed).
mesh::TriangleMesh make_torus(int nu, int nv, double r_major, double r_tube) {
    mesh::TriangleMesh m;
    m.vertices.reserve(static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv));
    for (int i = 0; i < nu; ++i) {
        const double u = 2.0 * std::numbers::pi * i / nu;
        for (int j = 0; j < nv; ++j) {
            const double v = 2.0 * std::numbers::pi * j / nv;
            const double ring = r_major + r_tube * std::cos(v);
            m.vertices.push_back(
                {ring * std::cos(u), ring * std::sin(u), r_tube + r_tube * std::sin(v)});
        }
    }
    const auto id = [nu, nv](int i, int j) {
        return static_cast<std::uint32_t>((i % nu) * nv + (j % nv));
    };
    m.triangles.reserve(2 * m.vertices.size());
    for (int i = 0; i < nu; ++i) {
        for (int j = 0; j < nv; ++j) {
            const std::uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1),
                                d = id(i, j + 1);
            m.triangles.push_back({a, b, c});
            m.triangles.push_back({a, c, d});
        }
    }
    return m;
}

// Meshes are made or read once per process and shared by the benchmarks that use them.
const mesh::TriangleMesh* cached_mesh(const std::string& key) {
    static std::map<std::string, std::unique_ptr<mesh::TriangleMesh>> cache;
    auto it = cache.find(key);
    if (it != cache.end()) return it->second.get();
    std::unique_ptr<mesh::TriangleMesh> m;
    if (key == "torus") {
        m = std::make_unique<mesh::TriangleMesh>(make_torus(kTorusSteps, kTorusSteps, 60.0, 20.0));
    } else {
        auto imported = io::read_mesh(key);
        if (!imported) {
            std::fprintf(stderr, "bench: cannot read %s: %s\n", key.c_str(),
                         imported.error().describe().c_str());
            return nullptr;
        }
        m = std::make_unique<mesh::TriangleMesh>(std::move(imported->mesh));
    }
    return cache.emplace(key, std::move(m)).first->second.get();
}

// The file's bytes read into memory with stdio: the cost any reader pays before parsing.
void BM_ReadFile(benchmark::State& state, const std::filesystem::path& path) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) {
        state.SkipWithError(("missing " + path.string()).c_str());
        return;
    }
    std::vector<char> buffer(size);
    for (auto _ : state) {
        std::FILE* f = std::fopen(path.c_str(), "rb");
        if (f == nullptr) {
            state.SkipWithError("cannot open");
            return;
        }
        const std::size_t got = std::fread(buffer.data(), 1, buffer.size(), f);
        std::fclose(f);
        benchmark::DoNotOptimize(got);
        benchmark::ClobberMemory();
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * size));
    state.counters["MB"] = static_cast<double>(size) / 1e6;
}

// io::read_mesh: open, parse, weld into an indexed mesh (the CLI's "load" stage).
void BM_ReadMesh(benchmark::State& state, const std::filesystem::path& path) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) {
        state.SkipWithError(("missing " + path.string()).c_str());
        return;
    }
    const tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(state.range(0)));
    std::size_t triangles = 0, vertices = 0;
    for (auto _ : state) {
        auto imported = io::read_mesh(path);
        if (!imported) {
            state.SkipWithError(imported.error().describe().c_str());
            return;
        }
        triangles = imported->mesh.triangles.size();
        vertices = imported->mesh.vertices.size();
        benchmark::DoNotOptimize(imported->mesh.triangles.data());
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * size));
    state.counters["triangles"] = static_cast<double>(triangles);
    state.counters["vertices"] = static_cast<double>(vertices);
}

// mesh::weld_exact alone, on the torus as a float triangle soup (what a binary STL holds).
void BM_WeldExact(benchmark::State& state) {
    const mesh::TriangleMesh* torus = cached_mesh("torus");
    std::vector<float> soup;
    soup.reserve(torus->triangles.size() * 9);
    for (const auto& t : torus->triangles) {
        for (const std::uint32_t v : t) {
            const core::Vec3d& p = torus->vertices[v];
            soup.insert(soup.end(), {static_cast<float>(p.x), static_cast<float>(p.y),
                                     static_cast<float>(p.z)});
        }
    }
    const tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(state.range(0)));
    for (auto _ : state) {
        mesh::TriangleMesh m = mesh::weld_exact(std::span<const float>(soup));
        benchmark::DoNotOptimize(m.vertices.data());
    }
    state.counters["triangles"] = static_cast<double>(torus->triangles.size());
}

struct LayerSetup {
    slice::PlaneFrame base;
    std::vector<slice::LayerSpan> layers;
};

LayerSetup horizontal_layers(const mesh::TriangleMesh& m, double layer_mm) {
    LayerSetup s;
    s.base = slice::base_frame(m, {0.0, 0.0, 1.0});
    const auto [lo, hi] = slice::extent_along(m, s.base);
    s.layers = slice::uniform_layers(lo, hi, layer_mm);
    return s;
}

// slice::slice_mesh with horizontal uniform layers: the CLI's "slice" stage (layer heights,
// cutting, chaining and the union into wire trees). Args: layer um, threads.
void BM_SliceMesh(benchmark::State& state, const std::string& model) {
    const mesh::TriangleMesh* m = cached_mesh(model);
    if (m == nullptr) {
        state.SkipWithError(("cannot load " + model).c_str());
        return;
    }
    const double layer_mm = static_cast<double>(state.range(0)) / 1000.0;
    const tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(state.range(1)));
    std::size_t layers = 0, wires = 0;
    for (auto _ : state) {
        const LayerSetup setup = horizontal_layers(*m, layer_mm);
        auto slices = slice::slice_mesh(*m, setup.base, setup.layers);
        if (!slices) {
            state.SkipWithError(slices.error().describe().c_str());
            return;
        }
        layers = slices->size();
        wires = 0;
        for (const auto& s : *slices) wires += s.wires.nodes.size();
        benchmark::DoNotOptimize(slices->data());
    }
    state.counters["triangles"] = static_cast<double>(m->triangles.size());
    state.counters["layers"] = static_cast<double>(layers);
    state.counters["wires"] = static_cast<double>(wires);
}

// slice::cut_mesh alone (raw loops, no union into wire trees), to split the slice stage.
void BM_CutMesh(benchmark::State& state, const std::string& model) {
    const mesh::TriangleMesh* m = cached_mesh(model);
    if (m == nullptr) {
        state.SkipWithError(("cannot load " + model).c_str());
        return;
    }
    const double layer_mm = static_cast<double>(state.range(0)) / 1000.0;
    const tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(state.range(1)));
    const LayerSetup setup = horizontal_layers(*m, layer_mm);
    std::vector<double> heights;
    heights.reserve(setup.layers.size());
    for (const auto& l : setup.layers) heights.push_back(l.cut);
    for (auto _ : state) {
        auto cuts = slice::cut_mesh(*m, setup.base, heights);
        if (!cuts) {
            state.SkipWithError(cuts.error().describe().c_str());
            return;
        }
        benchmark::DoNotOptimize(cuts->data());
    }
    state.counters["layers"] = static_cast<double>(heights.size());
}

std::vector<std::filesystem::path> extra_models() {
    std::vector<std::filesystem::path> out;
    const char* env = std::getenv("MAXSLICE_BENCH_MODELS");
    if (env == nullptr) return out;
    std::string_view rest(env);
    while (!rest.empty()) {
        const auto colon = rest.find(':');
        const std::string_view item = rest.substr(0, colon);
        if (!item.empty()) out.emplace_back(std::string(item));
        if (colon == std::string_view::npos) break;
        rest.remove_prefix(colon + 1);
    }
    return out;
}

void register_file_model(const std::string& name, const std::filesystem::path& path) {
    benchmark::RegisterBenchmark(("BM_ReadFile/" + name).c_str(), BM_ReadFile, path)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->MeasureProcessCPUTime();
    benchmark::RegisterBenchmark(("BM_ReadMesh/" + name).c_str(), BM_ReadMesh, path)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->MeasureProcessCPUTime()
        ->ArgName("threads")
        ->Arg(1)
        ->Arg(2);
    for (auto* fn : {&BM_SliceMesh, &BM_CutMesh}) {
        const std::string stage = fn == &BM_SliceMesh ? "BM_SliceMesh/" : "BM_CutMesh/";
        benchmark::RegisterBenchmark((stage + name).c_str(), *fn, path.string())
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime()
            ->MeasureProcessCPUTime()
            ->ArgNames({"layer_um", "threads"})
            ->ArgsProduct({{200, 500}, {1, 2}});
    }
}

void register_all() {
    register_file_model("lattice_cone", kLatticeCone);
    for (const auto& p : extra_models()) register_file_model(p.stem().string(), p);

    benchmark::RegisterBenchmark("BM_WeldExact/torus_inline_soup", BM_WeldExact)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->MeasureProcessCPUTime()
        ->ArgName("threads")
        ->Arg(1)
        ->Arg(2);
    for (auto* fn : {&BM_SliceMesh, &BM_CutMesh}) {
        const std::string stage = fn == &BM_SliceMesh ? "BM_SliceMesh/" : "BM_CutMesh/";
        benchmark::RegisterBenchmark((stage + "torus_inline").c_str(), *fn, std::string("torus"))
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime()
            ->MeasureProcessCPUTime()
            ->ArgNames({"layer_um", "threads"})
            ->ArgsProduct({{200, 500}, {1, 2}});
    }
}

}  // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    register_all();
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
