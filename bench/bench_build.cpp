// Building the synthetic coastal site with a 30,000-triangle wave surface, the seabed and all
// objects, every validity check included (issue 4 benchmark). Reports wall time per stage as
// counters (seconds). BM_BuildFlatSea builds Mobley's problem 2 (a flat sea over a periodic
// column) as its scene file has it (`surface: {model: flat}`: a grid of four cells) and with the
// grid every model had before a flat sea got its own (300 m at 0.25 m, decimated to 30 000
// triangles), side by side. Run: build/bin/bench_build --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include "core/atomic_file.h"
#include "core/progress.h"
#include "render/estimator_settings.h"
#include "scenegen/assemble.h"
#include "scenegen/synthetic_site.h"

namespace {

namespace fs = std::filesystem;
using namespace littoral::scenegen;

fs::path siteDir() {
    static const fs::path dir = [] {
        const fs::path d = fs::temp_directory_path() / "littoral_bench_build_site";
        SiteOptions opt;
        opt.surfaceTriangles = 30000;
        writeSyntheticSite(d, opt);
        return d;
    }();
    return dir;
}

void BM_BuildSyntheticSite(benchmark::State& state) {
    littoral::render::registerEstimatorKinds();  // the scene reader reads their descriptors
    const fs::path site = siteDir();
    const fs::path out = fs::temp_directory_path() / "littoral_bench_build_ir";
    StageSeconds sum;
    int n = 0;
    size_t waterFaces = 0, surfaceFaces = 0;
    for (auto _ : state) {
        const AssembledScene s = buildScene(site / "scene.yaml", out);
        if (!s.valid) state.SkipWithError("the site failed its validity checks");
        const auto& t = s.seconds;
        sum.parse += t.parse;
        sum.surface += t.surface;
        sum.terrain += t.terrain;
        sum.textures += t.textures;
        sum.objects += t.objects;
        sum.waterPrism += t.waterPrism;
        sum.waterTerrain += t.waterTerrain;
        sum.waterBoolean += t.waterBoolean;
        sum.waterSolids += t.waterSolids;
        sum.validity += t.validity;
        sum.write += t.write;
        ++n;
        waterFaces = s.ir.findMesh("water")->data.numTriangles();
        surfaceFaces = s.validity["water"]["faces_by_role"]["interface"].get<size_t>();
    }
    auto avg = [n](double x) { return n ? x / n : 0.0; };
    state.counters["s_parse"] = avg(sum.parse);
    state.counters["s_surface"] = avg(sum.surface);
    state.counters["s_terrain"] = avg(sum.terrain);
    state.counters["s_textures"] = avg(sum.textures);
    state.counters["s_objects"] = avg(sum.objects);
    state.counters["s_prism"] = avg(sum.waterPrism);
    state.counters["s_terrain_solid"] = avg(sum.waterTerrain);
    state.counters["s_boolean"] = avg(sum.waterBoolean);
    state.counters["s_solids"] = avg(sum.waterSolids);
    state.counters["s_checks"] = avg(sum.validity);
    state.counters["s_write"] = avg(sum.write);
    state.counters["s_total"] = avg(sum.total());
    state.counters["water_faces"] = static_cast<double>(waterFaces);
    state.counters["interface_faces"] = static_cast<double>(surfaceFaces);
}
BENCHMARK(BM_BuildSyntheticSite)->Unit(benchmark::kSecond)->Iterations(2);

void BM_BuildFlatSea(benchmark::State& state) {
    littoral::render::registerEstimatorKinds();
    littoral::Progress::setEnabled(false);  // the old grid's wave stages would print progress
    std::string scene =
        littoral::readTextFile(fs::path(LITTORAL_SOURCE_DIR_BENCH) / "data_synthetic" / "mobley1993" / "problem2_albedo09.yaml");
    const std::string flat = "surface: {model: flat}";
    const size_t at = scene.find(flat);
    if (at == std::string::npos) {
        state.SkipWithError("problem2_albedo09.yaml no longer has a flat surface");
        return;
    }
    if (state.range(0) == 1) scene.replace(at, flat.size(), "surface: {model: flat, size: 300, spacing: 0.25, triangles: 30000}");
    // A folder per variant: a scene file one variant has built is an input of this process, which
    // writeFileAtomic then refuses to replace.
    const fs::path dir = fs::temp_directory_path() / ("littoral_bench_build_flat" + std::to_string(state.range(0)));
    fs::create_directories(dir);
    littoral::writeFileAtomic(dir / "scene.yaml", scene);
    size_t waterFaces = 0;
    for (auto _ : state) {
        const AssembledScene s = buildScene(dir / "scene.yaml", dir / "ir");
        if (!s.valid) state.SkipWithError("the flat sea failed its validity checks");
        waterFaces = s.ir.findMesh("water")->data.numTriangles();
    }
    state.counters["water_faces"] = static_cast<double>(waterFaces);
    state.SetLabel(state.range(0) == 1 ? "the old grid: 300 m at 0.25 m, 30000 triangles" : "flat: four cells");
}
BENCHMARK(BM_BuildFlatSea)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(4);

}  // namespace

BENCHMARK_MAIN();
