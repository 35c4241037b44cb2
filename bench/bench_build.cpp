// Building the synthetic coastal site with a 30,000-triangle wave surface, the seabed and all
// objects, every validity check included (issue 4 benchmark). Reports wall time per stage as
// counters (seconds). Run: build/bin/bench_build --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <filesystem>

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

}  // namespace

BENCHMARK_MAIN();
