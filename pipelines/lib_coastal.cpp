#include "pipelines/lib_coastal.h"

#include <cctype>
#include <cstring>
#include <filesystem>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "pipelines/lib_embedded.h"
#include "pipelines/lib_scene.h"
#include "scenegen/synthetic_site.h"

namespace littoral::pipelines {
namespace {

namespace fs = std::filesystem;

// Rows of Table 10.1: sun zenith (azimuth 315), sensor elevation, azimuth, range and GSD, IOPs,
// wind. The table gives no image sizes: the nadir and 60-deg views cover the 90 m x 60 m site
// (rows = 60 m sin(elevation) / GSD), F's 30-deg view the same ground depth, and H's 10-deg view
// from a floating vessel 11.5 m x 6.5 m around the deepest step target.
const std::vector<CoastalConfiguration> kConfigurations = {
    {'A', "backscatter", 30, 60, 315, 500, 0.2, "low", 6.0, 450, 260, false},
    {'B', "specular", 30, 60, 135, 500, 0.2, "low", 6.0, 450, 260, false},
    {'C', "nadir", 30, 90, 270, 500, 0.2, "low", 6.0, 450, 300, false},
    {'D', "nadir, low sun", 60, 90, 270, 500, 0.1, "low", 6.0, 900, 600, false},
    {'E', "surface detail", 30, 60, 180, 500, 0.2, "low", 6.0, 450, 260, false},
    {'F', "surface detail, grazing", 60, 30, 180, 500, 0.2, "low", 6.0, 450, 150, false},
    {'G', "wind speed variation", 30, 60, 180, 500, 0.2, "low", 10.0, 450, 260, false},
    {'H', "rowboat", 48, 10, 262, 90, 0.018, "low", 6.0, 640, 360, true},
    {'I', "concentration variation, moderate", 60, 90, 270, 500, 0.1, "moderate", 6.0, 900, 600, false},
    {'J', "concentration variation, high", 60, 90, 270, 500, 0.1, "high", 6.0, 900, 600, false},
};

std::string sensorSection(const CoastalConfiguration& c, uint64_t seed) {
    double tx = 0, ty = 0;
    if (c.atDeepestTarget) {
        const auto targets = scenegen::siteTargets(seed);
        tx = targets.back().x;
        ty = targets.back().y;
    }
    return fmt::format("sensors:\n  - {{name: sim-{}, type: frame, elevation_deg: {}, azimuth_deg: {}, range_m: {}, "
                       "gsd_m: {},\n     target: [{:.3f}, {:.3f}, 0], width: {}, height: {}, water_products: true}}\n",
                       static_cast<char>(std::tolower(c.id)), c.sensorElevationDeg, c.sensorAzimuthDeg, c.rangeM,
                       c.gsdM, tx, ty, c.width, c.height);
}

scenegen::SiteOptions siteFor(const CoastalConfiguration& c, const CoastalOptions& o, bool photonMaps) {
    scenegen::SiteOptions so;
    so.seed = o.seed;
    so.scene.sunZenithDeg = c.sunZenithDeg;
    so.scene.sunAzimuthDeg = 315;
    so.scene.windSpeed = c.windSpeed;
    so.scene.sensors = sensorSection(c, o.seed);
    // Images only: under G's 10 m/s waves (rms height 1.24 m) a probe 1 m down would be in air.
    so.scene.probe = false;
    so.scene.optics = fmt::format("    preset: {}\n", c.water);
    so.scene.photonMaps = photonMaps;
    so.scene.render = coastalRenderSection(o.full, photonMaps);
    return so;
}

// `run` of `scene` into `out` with the command's threads, progress and preview.
RunOptions runOptions(const CoastalOptions& o, const fs::path& scene, const fs::path& out) {
    RunOptions ro;
    ro.scene = scene.string();
    ro.out = out.string();
    ro.threads = o.threads;
    ro.progress = o.progress;
    ro.preview = o.preview;
    return ro;
}

std::string runOne(const CoastalConfiguration& c, const CoastalOptions& o, const fs::path& out, bool photonMaps) {
    const RunOptions ro = runOptions(o, writeCoastalSite(o, out / "site", photonMaps), out);
    return fmt::format("configuration {} ({}{}), {} settings -> {}\n", c.id, c.description,
                       photonMaps ? "" : ", without photon maps", o.full ? "full" : "quick", out.string()) +
           runScene(ro);
}

}  // namespace

const std::vector<CoastalConfiguration>& coastalConfigurations() { return kConfigurations; }

const CoastalConfiguration& coastalConfiguration(const std::string& id) {
    if (id.size() == 1)
        for (const auto& c : kConfigurations)
            if (c.id == std::toupper(static_cast<unsigned char>(id[0]))) return c;
    throw InputError(fmt::format("coastal: unknown configuration '{}'; the configurations of Table 10.1 are A to J, and "
                                 "Section 10.4's demonstrations are 'cube' and 'shadows'",
                                 id));
}

const CoastalDemonstration* coastalDemonstration(const std::string& name) {
    static const CoastalDemonstration kDemonstrations[] = {
        {"cube", "the caustic of a floating epoxy cube (Section 10.4, Fig. 10.21)", "demos/floating_cube", "../objects/cube.ply",
         1, 1, 1},
        {"shadows", "the floating-box shadow series (Section 10.4, Fig. 10.19)", "demos/box_shadows",
         "../objects/box_2x2x1.obj", 2, 2, 1},
    };
    for (const auto& d : kDemonstrations)
        if (name == d.name) return &d;
    return nullptr;
}

void checkCoastalName(const CoastalOptions& o) {
    if (!coastalDemonstration(o.configuration)) {
        (void)coastalConfiguration(o.configuration);
        return;
    }
    if (o.full || o.seedGiven)
        throw InputError(fmt::format("coastal {}: {} applies to the configurations A to J; '{}' has one setting, the "
                                     "scene file data_synthetic/{}.yaml",
                                     o.configuration, o.full ? "--full" : "--seed", o.configuration,
                                     coastalDemonstration(o.configuration)->scene));
}

std::string coastalRenderSection(bool full, bool photonMaps) {
    // Table 10.3 tabulates the waters at 0.4, 0.5 and 0.6 um: three bands over that range.
    // Full: the dissertation's 50 M surface and 70 M volume photons, SR 0.4 m (§3.6). Quick: 1 M
    // of each, the same radius, fewer hemisphere rays for the Classic solver. Without photon maps
    // the photon settings are left out (no solver would read them, and the scene would be refused).
    std::string r = "render:\n  bands: {range_um: [0.4, 0.6], count: 3}\n  seed: 1\n";
    if (!full) r += "  hemisphere_samples: 16\n";
    if (!photonMaps) return r;
    r += full ? "  photons: {surface: 50000000, volume: 70000000}\n" : "  photons: {surface: 1000000, volume: 1000000}\n";
    r += "  search_radius_m: {surface: 0.4, volume: 0.4}\n";
    return r;
}

fs::path writeCoastalSite(const CoastalOptions& o, const fs::path& dir, bool photonMaps) {
    return scenegen::writeSyntheticSite(dir, siteFor(coastalConfiguration(o.configuration), o, photonMaps)).sceneFile;
}

// A Section 10.4 demonstration: its built-in scene file into out/scene with its mesh written beside
// it, then run into out.
std::string runDemonstration(const CoastalDemonstration& d, const CoastalOptions& o) {
    const fs::path out(o.out), sceneDir = out / "scene";
    std::string yaml = embeddedSceneText(d.scene);
    const std::string mesh = std::string(d.name) + ".obj";
    size_t n = 0;
    for (auto at = yaml.find(d.meshReference); at != std::string::npos; at = yaml.find(d.meshReference, at + mesh.size()), ++n)
        yaml.replace(at, std::strlen(d.meshReference), mesh);
    if (n == 0) throw InternalError(fmt::format("built-in scene {} names no mesh {}", d.scene, d.meshReference));
    writeTextFileAtomic(sceneDir / "scene.yaml", yaml);
    writeTextFileAtomic(sceneDir / mesh, boxObj(d.sizeX, d.sizeY, d.height));
    publishStagedOutputs();  // read back by the build below
    return fmt::format("{}: {} -> {}\n", d.name, d.description, out.string()) +
           runScene(runOptions(o, sceneDir / "scene.yaml", out));
}

std::string runCoastal(const CoastalOptions& o) {
    checkCoastalName(o);
    if (const CoastalDemonstration* d = coastalDemonstration(o.configuration)) return runDemonstration(*d, o);
    const CoastalConfiguration& c = coastalConfiguration(o.configuration);
    const fs::path out(o.out);
    if (c.id != 'H') return runOne(c, o, out, true);
    return runOne(c, o, out / "photon-maps", true) + runOne(c, o, out / "no-photon-maps", false);
}

}  // namespace littoral::pipelines
