// Issue 18's benchmark: the path-traced nadir view of the coastal site (configuration C: sun at
// 30 deg, 6 m/s wave mesh of about 30 000 facets, Low water scattering with HG g = 0.88, 450 x 300
// pixels at 0.2 m, three bands over 0.4-0.6 um), rendered twice side by side in one run:
//
//   with     the in-water sun connection (facet beams and next-event estimation at every vertex in
//            water: the default);
//   without  no sun estimate at points in water (render::setInWaterSunEstimates(false)): the
//            estimator stays unbiased, because the rays it samples from such points count the
//            solar disc when they reach it, but it finds a 0.53 deg disc through a wave facet by
//            chance only.
//
// For each: the wall time, the rays cast (closest-hit and shadow) per second, and the per-pixel
// noise: the median over the pixels that see the seabed under water (truth: first opaque surface
// below z = 0) of the standard error over the radiance, with the time to 2 % per-pixel noise
// extrapolated as time x (median / 0.02)^2 (the error of an unbiased estimate falls as one over the
// square root of the samples). The two images' means over those pixels are printed with their
// standard errors: they must agree (both are unbiased).
//
// Usage: bench_nadir_connection [SAMPLES_PER_PIXEL (default 8)] [OUT_DIR (default
// out/bench-nadir-connection)]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"
#include "core/stats.h"
#include "pipelines/lib_coastal.h"
#include "render/render_job.h"
#include "render/sun_connection.h"
#include "scenegen/assemble.h"

namespace fs = std::filesystem;
using namespace littoral;

namespace {

struct Run {
    double seconds = 0, rays = 0;
    render::SensorImage image;
};
struct Stats {
    double rmsRelSe = 0, medianRelSe = 0, mean = 0, meanSe = 0;
};

std::string replacedOnce(std::string text, const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    if (at == std::string::npos) throw InternalError("bench_nadir_connection: the coastal scene has no '" + from + "'");
    return text.replace(at, from.size(), to);
}

Run renderOnce(const ir::SceneIR& ir, const fs::path& irDir, const fs::path& out, bool connection) {
    render::setInWaterSunEstimates(connection);
    statsReset();
    render::RenderJobOptions opts;
    opts.progress = false;
    opts.tileCheckpoint = false;
    const auto t0 = std::chrono::steady_clock::now();
    auto job = render::runRenderJob(ir, irDir, out, opts);
    Run r;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.rays = static_cast<double>(statCounter("rays cast").value + statCounter("shadow rays").value);
    render::setInWaterSunEstimates(true);
    r.image = std::move(job.images.at(0));
    return r;
}

// Over the pixels `keep` (band 0): the RMS standard error over the mean radiance (which counts
// the rare large samples a heavy-tailed estimate makes, where a median would not), the median of
// se / L, and the mean with its standard error.
Stats statsOf(const render::SensorImage& im, const std::vector<size_t>& keep) {
    const render::Film& L = im.film;
    const render::Film& se = *im.standardError;
    std::vector<double> rel;
    double sum = 0, var = 0;
    for (size_t i : keep) {
        const int x = static_cast<int>(i % static_cast<size_t>(L.width)), y = static_cast<int>(i / static_cast<size_t>(L.width));
        const double v = L.at(x, y, 0), s = se.at(x, y, 0);
        sum += v;
        var += s * s;
        if (v > 0) rel.push_back(s / v);
    }
    Stats st;
    const double n = static_cast<double>(keep.size());
    st.mean = sum / n;
    st.meanSe = std::sqrt(var) / n;
    st.rmsRelSe = std::sqrt(var / n) / st.mean;
    if (!rel.empty()) {
        std::nth_element(rel.begin(), rel.begin() + static_cast<ptrdiff_t>(rel.size() / 2), rel.end());
        st.medianRelSe = rel[rel.size() / 2];
    }
    return st;
}

// The seabed pixels under water (truth: the first opaque surface lies below z = 0) without sun
// glint: pixels of the reference image above 4x its median are left out (the disc reflected by a
// facet, as noisy for both renders: not what the connection is about). *glint gets their number.
std::vector<size_t> seabedPixels(const render::SensorImage& ref, size_t* glint) {
    const render::Film& L = ref.film;
    std::vector<size_t> seabed;
    std::vector<double> values;
    for (int y = 0; y < L.height; ++y)
        for (int x = 0; x < L.width; ++x) {
            const size_t i = ref.truth.index(x, y);
            if (!(ref.truth.hitDepth[i] > 0)) continue;
            seabed.push_back(i);
            values.push_back(L.at(x, y, 0));
        }
    std::vector<double> sorted = values;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<ptrdiff_t>(sorted.size() / 2), sorted.end());
    const double limit = 4 * sorted[sorted.size() / 2];
    std::vector<size_t> keep;
    for (size_t k = 0; k < seabed.size(); ++k)
        if (values[k] <= limit) keep.push_back(seabed[k]);
    *glint = seabed.size() - keep.size();
    return keep;
}

}  // namespace

int main(int argc, char** argv) {
    const int spp = argc > 1 ? std::atoi(argv[1]) : 8;
    const fs::path out = argc > 2 ? fs::path(argv[2]) : fs::path("out/bench-nadir-connection");
    log::setLevel(log::Level::Warn);
    fs::remove_all(out);
    pipelines::CoastalOptions co;
    co.configuration = "C";
    const fs::path site = pipelines::writeCoastalSite(co, out / "site", false);
    publishStagedOutputs();
    // The path estimator over the same bands and seed, spp samples per pixel.
    std::string yaml = readTextFile(site);
    yaml = replacedOnce(yaml, pipelines::coastalRenderSection(false, false),
                        "render:\n  bands: {range_um: [0.4, 0.6], count: 3}\n  seed: 1\n  estimator: path\n");
    yaml = replacedOnce(yaml, "water_products: true}", fmt::format("samples_per_pixel: {}}}", spp));
    // The dirsig solvers of Table 10.4 go (the path estimator refuses them): every material and the
    // water are then rendered by the path estimator's own transport, scattering included.
    yaml = std::regex_replace(yaml, std::regex(", solver: [a-z-]+"), "");
    yaml = std::regex_replace(yaml, std::regex("\n +solver: [a-z-]+\n"), "\n");
    const fs::path scene = site.parent_path() / "scene_path.yaml";
    writeTextFileAtomic(scene, yaml);
    publishStagedOutputs();
    const auto built = scenegen::buildScene(scene.string(), out / "ir");
    publishStagedOutputs();

    const Run with = renderOnce(built.ir, out / "ir", out / "with", true);
    const Run without = renderOnce(built.ir, out / "ir", out / "without", false);
    size_t glint = 0;
    const std::vector<size_t> keep = seabedPixels(with.image, &glint);
    const Stats a = statsOf(with.image, keep), b = statsOf(without.image, keep);
    std::printf("coastal C nadir, path estimator, %d samples per pixel: %zu seabed pixels under water (%zu glint pixels "
                "left out)\n",
                spp, keep.size(), glint);
    std::printf("| | wall time | rays/s | per-pixel se / L: RMS (median) | time to 2 %% per pixel | seabed mean radiance |\n");
    std::printf("|---|---|---|---|---|---|\n");
    for (const auto& [name, r, st] : {std::tuple{"with the connection", &with, a}, std::tuple{"without", &without, b}})
        std::printf("| %s | %.1f s | %.2f M/s | %.3f (%.3f) | %.3g s | %.4f +- %.4f |\n", name, r->seconds,
                    r->rays / r->seconds * 1e-6, st.rmsRelSe, st.medianRelSe, r->seconds * std::pow(st.rmsRelSe / 0.02, 2),
                    st.mean, st.meanSe);
    std::printf("means differ by %.1f combined standard errors; time to 2 %% per pixel, without / with: %.3g\n",
                std::abs(a.mean - b.mean) / std::hypot(a.meanSe, b.meanSe),
                (without.seconds * b.rmsRelSe * b.rmsRelSe) / (with.seconds * a.rmsRelSe * a.rmsRelSe));
    return 0;
}
