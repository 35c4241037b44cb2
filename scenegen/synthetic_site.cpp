#include "scenegen/synthetic_site.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>

#include <fmt/format.h>

#include "bathymetry/terrain.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/rng.h"
#include "scenegen/mesh_io.h"
#include "scenegen/primitives.h"

namespace littoral::scenegen {
namespace {

namespace fs = std::filesystem;

// ---- site geometry (metres, local frame: x east, y north) ----
constexpr double kX0 = -45, kX1 = 45, kY0 = -30, kY1 = 30;

bathymetry::BarTrough siteProfile() {
    bathymetry::BarTrough b;
    b.dean.A = 0.22;  // m^(1/3): Dean (1987) A = 0.21 D^0.48 for D ~ 1.1 mm coarse sand
    b.dean.shorelineX = -22;
    b.dean.offshoreTowardPositiveX = true;
    b.dean.beachSlope = 0.08;
    b.dean.bermHeight = 1.2;
    b.barCrestDistance = 38;
    b.barHeight = 0.45;
    b.barWidth = 5;
    b.troughDistance = 24;
    b.troughDepth = 0.3;
    b.troughWidth = 4;
    return b;
}

// Pier: runs east from the beach along the south side.
constexpr double kPierX = -32, kPierY = -24, kPierLength = 26, kPierWidth = 2.5;
// Class indices of the classification map.
enum Class : uint8_t { DrySand = 0, WetSand = 1, Grass = 2, Trees = 3, Concrete = 4, SubmergedVegetation = 5 };

// Smooth value noise in [0, 1): random values on a lattice of `cell` metres (or pixels) from
// RandomStream(seed, pass, lattice index), blended with the smoothstep 3t^2 - 2t^3.
// With period > 0 the lattice wraps every `period` cells, so the noise tiles seamlessly.
double valueNoise(uint64_t seed, uint64_t pass, double x, double y, double cell, int64_t period = 0) {
    const double u = x / cell, v = y / cell;
    const double fu = std::floor(u), fv = std::floor(v);
    const auto i = static_cast<int64_t>(fu), j = static_cast<int64_t>(fv);
    auto lattice = [&](int64_t a, int64_t b) {
        if (period > 0) {
            a = ((a % period) + period) % period;
            b = ((b % period) + period) % period;
        }
        const uint64_t idx = (static_cast<uint64_t>(a + (1 << 20)) << 21) ^ static_cast<uint64_t>(b + (1 << 20));
        return RandomStream(seed, pass, idx).uniform();
    };
    auto s = [](double t) { return t * t * (3 - 2 * t); };
    const double tu = s(u - fu), tv = s(v - fv);
    const double a = lattice(i, j) * (1 - tu) + lattice(i + 1, j) * tu;
    const double b = lattice(i, j + 1) * (1 - tu) + lattice(i + 1, j + 1) * tu;
    return a * (1 - tv) + b * tv;
}

void writePng(const fs::path& target, int w, int h, const std::vector<uint8_t>& data) {
    imageio::writeFile(target, {w, h, 1, imageio::PixelType::UInt8, {}, {}}, data.data(), "png");
}

struct Target {
    double x = 0, y = 0, top = 0, height = 0;
};

struct ClassInfo {
    const char* name;
    double mean, stddev;
    const char* solver;
    std::array<double, 6> reflectance;  // at 0.35, 0.45, 0.55, 0.65, 0.75, 0.90 um
    double cellSmall, cellLarge;         // texture noise scales, pixels
};

// Reflectances: representative shapes (sand rising to the red; vegetation with a green peak and
// the red edge; water-darkened wet sand), in the spirit of the "borrowed" DIRSIG materials.
const ClassInfo kClasses[6] = {
    {"dry-sand", 1.0, 0.08, "surface-pm", {0.22, 0.30, 0.36, 0.40, 0.43, 0.46}, 2, 12},
    {"wet-sand", 1.0, 0.06, "surface-pm", {0.10, 0.14, 0.18, 0.20, 0.22, 0.24}, 3, 16},
    {"grass", 1.0, 0.15, "classic", {0.04, 0.05, 0.12, 0.07, 0.42, 0.48}, 2, 6},
    {"trees", 1.0, 0.25, "classic", {0.03, 0.04, 0.08, 0.05, 0.33, 0.38}, 4, 10},
    {"concrete", 1.0, 0.05, "surface-pm", {0.24, 0.27, 0.29, 0.30, 0.31, 0.32}, 2, 24},
    {"submerged-vegetation", 1.0, 0.20, "surface-pm", {0.02, 0.03, 0.07, 0.04, 0.18, 0.22}, 3, 8},
};

std::string spectrumYaml(const std::array<double, 6>& v) {
    return fmt::format("{{wavelengths_um: [0.35, 0.45, 0.55, 0.65, 0.75, 0.90], values: [{}]}}", fmt::join(v, ", "));
}

fs::path writeMesh(const fs::path& dir, const std::string& name, const TriMesh& m, std::vector<fs::path>* files) {
    const fs::path p = dir / name;
    writeMeshFile(p, m);
    files->push_back(p);
    return p;
}

PierParams sitePier() {
    PierParams pp;
    pp.length = kPierLength;
    pp.width = kPierWidth;
    pp.deckBottom = 1.6;
    pp.pilingRadius = 0.18;
    pp.pilingBottom = -5;
    return pp;
}

// Step targets: 2 m pedestals, tops 0.5, 1.25, 2.0, 2.75 m deep (0.75 m steps), in a row 9 m south
// of the centre line. `depthAt` is the seabed's depth (m, positive down).
std::vector<Target> placeTargets(uint64_t seed, double shorelineX, const std::function<double(double, double)>& depthAt) {
    std::vector<Target> targets;
    double xMin = shorelineX;
    for (int k = 0; k < 4; ++k) {
        Target t;
        t.top = 0.5 + 0.75 * k;
        RandomStream rs(seed, 11, static_cast<uint64_t>(k));
        t.y = -9.0 + 2.0 * (rs.uniform() - 0.5);  // jittered +-1 m
        // First position offshore where the seabed under the whole footprint is at least 0.35 m
        // below the target's top, and at least 4 m from the previous target.
        for (double x = xMin; x < kX1 - 3; x += 0.25) {
            double shallow = 1e9, deep = -1e9;
            for (double dx : {-1.0, 0.0, 1.0})
                for (double dy : {-1.0, 0.0, 1.0}) {
                    shallow = std::min(shallow, depthAt(x + dx, t.y + dy));
                    deep = std::max(deep, depthAt(x + dx, t.y + dy));
                }
            if (shallow >= t.top + 0.35) {
                t.x = x;
                t.height = deep - t.top + 0.5;  // the pedestal reaches 0.5 m into the seabed
                break;
            }
        }
        if (t.height <= 0) throw InternalError(fmt::format("synthetic site: no place deep enough for a target at {} m", t.top));
        xMin = t.x + 4.0;
        targets.push_back(t);
    }
    return targets;
}

// The ground class at (x, y) with terrain elevation z (m).
uint8_t classAt(uint64_t seed, double x, double y, double z, const std::vector<Target>& targets) {
    const bool pier = x >= kPierX - 0.2 && x <= kPierX + kPierLength + 0.2 && std::abs(y - kPierY) <= 0.5 * kPierWidth + 0.2;
    const bool slab = x >= kPierX - 6 && x <= kPierX && y >= kPierY - 3 && y <= kPierY + 3;
    bool nearTarget = false;
    for (const auto& t : targets) nearTarget = nearTarget || (std::abs(x - t.x) < 2.5 && std::abs(y - t.y) < 2.5);
    if (z > 0.6) {
        if (pier || slab) return Concrete;
        if (x < -34 && y > 8 && valueNoise(seed, 21, x, y, 4.0) > 0.55) return Trees;
        if (x < -28 + 4 * (valueNoise(seed, 22, x, y, 6.0) - 0.5) && y > 2) return Grass;
        return DrySand;
    }
    if (pier && z > -0.2) return Concrete;  // under the landward end of the pier deck
    if (z < -0.8 && !nearTarget && valueNoise(seed, 23, x, y, 5.0) * 0.7 + valueNoise(seed, 24, x, y, 1.5) * 0.3 > 0.62)
        return SubmergedVegetation;
    return WetSand;
}

void writeClassMap(const fs::path& dir, const SiteOptions& opt, const bathymetry::Terrain& terrain,
                   const std::vector<Target>& targets, SiteSummary& s) {
    const int W = static_cast<int>(std::lround((kX1 - kX0) / opt.mapResolution));
    const int H = static_cast<int>(std::lround((kY1 - kY0) / opt.mapResolution));
    std::vector<uint8_t> cls(static_cast<size_t>(W) * H);
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            const double x = kX0 + (i + 0.5) * opt.mapResolution, y = kY1 - (j + 0.5) * opt.mapResolution;
            cls[static_cast<size_t>(j) * W + i] = classAt(opt.seed, x, y, terrain.elevation(x, y), targets);
        }
    writePng(dir / "classes.png", W, H, cls);
    s.files.push_back(dir / "classes.png");
}

// Class textures: 64 x 64 grey noise, two octaves.
void writeClassTextures(const fs::path& dir, uint64_t seed, SiteSummary& s) {
    for (int k = 0; k < 6; ++k) {
        const auto& ci = kClasses[k];
        std::vector<uint8_t> tex(64 * 64);
        for (int j = 0; j < 64; ++j)
            for (int i = 0; i < 64; ++i) {
                // Lattices that wrap at 64 px, so the tile repeats over the ground without seams.
                const int64_t ps = std::max<int64_t>(1, std::lround(64.0 / ci.cellSmall));
                const int64_t pl = std::max<int64_t>(1, std::lround(64.0 / ci.cellLarge));
                const double a = valueNoise(seed, 100 + k, i, j, 64.0 / ps, ps);
                const double b = valueNoise(seed, 200 + k, i, j, 64.0 / pl, pl);
                tex[j * 64 + i] = static_cast<uint8_t>(std::clamp(255.0 * (0.6 * a + 0.4 * b), 0.0, 255.0));
            }
        const fs::path p = dir / "textures" / (std::string(ci.name) + ".png");
        writePng(p, 64, 64, tex);
        s.files.push_back(p);
    }
}

void writeSiteObjects(const fs::path& od, const std::vector<Target>& targets, SiteSummary& s) {
    writeMesh(od, "pier.ply", makePier(sitePier()), &s.files);
    writeMesh(od, "boat.ply", makeBoat(5.0, 2.0, 0.8), &s.files);
    writeMesh(od, "buoy.ply", makeBuoy(0.4, 1.8), &s.files);
    for (size_t k = 0; k < targets.size(); ++k)
        writeMesh(od, fmt::format("step_target_{}.ply", k + 1), makeStepTarget(2.0, targets[k].height), &s.files);
}

// The scene file's sections up to the water, its surface and optics.
std::string siteSceneAndWater(uint64_t seed, const SiteOptions& opt) {
    std::string y;
    y += fmt::format("# Synthetic coastal site (Littoral data_synthetic/gen_coastal_site, seed {}).\n", seed);
    y += "# 90 m x 60 m: beach and berm to the west, Dean-profile seabed with a sandbar, six ground classes,\n";
    y += "# a cement pier, a small boat, a buoy and four step targets 0.75 m apart in depth.\n";
    y += "scene:\n  name: synthetic-coastal-site\n  origin: {latitude: 36.1833, longitude: -75.7500, altitude: 0}\n";
    y += fmt::format("  domain: {{x: [{}, {}], y: [{}, {}]}}\n", kX0, kX1, kY0, kY1);
    const SiteScene& sc = opt.scene;
    y += fmt::format("sun: {{zenith_deg: {}, azimuth_deg: {}}}\n", sc.sunZenithDeg, sc.sunAzimuthDeg);
    y += "sky: {model: simple, hemisphere_irradiance: 1000, sky_fraction: 0.1}\n";
    if (sc.sensors.empty())
        y += "sensors:\n  - {name: sim-c-nadir, type: frame, elevation_deg: 90, azimuth_deg: 270, range_m: 500, gsd_m: 0.2,\n"
             "     target: [0, 0, 0], width: 450, height: 300}\n";
    else
        y += sc.sensors;
    if (sc.probe) y += "probes:\n  - {name: ed-1m, position: [20, 0, -1], quantities: [Ed, Eu]}\n";
    y += "water:\n  level_m: 0\n";
    // Table 10.2: Beaufort/RMS surface at 6 m/s, 0.25 m grid, decimated to 30,000 triangles; the
    // surface spans the domain exactly. The wind comes from the west (blows toward +x, offshore).
    y += fmt::format("  surface:\n    model: beaufort\n    wind_speed: {:.1f}\n    wind_from_deg: 270\n"
                     "    size: [{}, {}]\n    centre: [{}, {}]\n    spacing: 0.25\n    triangles: {}\n    seed: {}\n",
                     sc.windSpeed, kX1 - kX0, kY1 - kY0, 0.5 * (kX0 + kX1), 0.5 * (kY0 + kY1), opt.surfaceTriangles, seed);
    // Coastal water from its constituents, with pure sea water (Pope & Fry absorption, Morel
    // scattering): defined over the visible to 0.7 um, so that the three bands show depth as it is
    // seen in nature (red lost first). The dissertation's Table 10.3 waters are tabulated to 0.6 um
    // only; the coastal configurations (littoral coastal) use them. In-scattered light from the
    // volume photon map (Table 10.4: MediumPM for the water volume).
    y += "  optics:\n";
    y += sc.optics.empty() ? "    constituents: {chlorophyll_mg_m3: 0.5, sediment_g_m3: 0.2, cdom_440_per_m: 0.02}\n"
                           : sc.optics;
    y += sc.photonMaps ? "    solver: medium-pm\n" : "    solver: attenuation\n";
    return y;
}

// The scene file's bathymetry, materials and texture classes.
// A SurfacePM material or class takes the Classic solver in the non-photon-mapped rendering.
const char* siteSolver(const char* solver, const SiteScene& sc) {
    return !sc.photonMaps && std::string(solver) == "surface-pm" ? "classic" : solver;
}

std::string siteGround(const bathymetry::BarTrough& profile, const SiteScene& sc) {
    std::string y;
    y += "bathymetry:\n  type: bar_trough\n";
    y += fmt::format("  A: {}\n  shoreline_x_m: {}\n  offshore: \"+x\"\n  beach_slope: {}\n  berm_height_m: {}\n",
                     profile.dean.A, profile.dean.shorelineX, profile.dean.beachSlope, profile.dean.bermHeight);
    y += fmt::format("  bar_crest_m: {}\n  bar_height_m: {}\n  bar_width_m: {}\n  trough_m: {}\n  trough_depth_m: {}\n"
                     "  trough_width_m: {}\n  spacing_m: 1.0\n",
                     profile.barCrestDistance, profile.barHeight, profile.barWidth, profile.troughDistance,
                     profile.troughDepth, profile.troughWidth);
    y += "materials:\n";
    y += "  - {name: fiberglass, reflectance: 0.55, solver: generic}\n";
    y += "  - {name: aluminum, reflectance: 0.65, solver: generic}\n";
    y += fmt::format("  - {{name: pier-cement, reflectance: 0.33, solver: {}}}\n", siteSolver("surface-pm", sc));
    y += fmt::format("  - {{name: target-bright, reflectance: 0.80, solver: {}}}\n", siteSolver("surface-pm", sc));
    y += fmt::format("  - {{name: target-dark, reflectance: 0.05, solver: {}}}\n", siteSolver("surface-pm", sc));
    y += "  - {name: buoy-paint, reflectance: 0.45}\n";
    y += "texture_classes:\n  map: classes.png\n";
    y += fmt::format("  extent: {{x: [{}, {}], y: [{}, {}]}}\n  classes:\n", kX0, kX1, kY0, kY1);
    for (int k = 0; k < 6; ++k) {
        const auto& ci = kClasses[k];
        y += fmt::format("    - {{index: {}, name: {}, texture: textures/{}.png, mean: {}, stddev: {}, solver: {},\n"
                         "       reflectance: {}}}\n",
                         k, ci.name, ci.name, ci.mean, ci.stddev, siteSolver(ci.solver, sc), spectrumYaml(ci.reflectance));
    }
    return y;
}

// The scene file's objects and render settings.
std::string siteObjectsAndRender(const std::vector<Target>& targets, const SiteScene& sc) {
    std::string y;
    y += "objects:\n";
    y += fmt::format("  - {{name: pier, mesh: objects/pier.ply, materials: [pier-cement, pier-cement], "
                     "position_m: [{}, {}], heading_deg: 90, z_m: 0}}\n",
                     kPierX, kPierY);
    y += "  - {name: boat, mesh: objects/boat.ply, materials: [fiberglass, aluminum], position_m: [-8, 20], "
         "heading_deg: 30, draft_m: 0.25}\n";
    y += "  - {name: buoy, mesh: objects/buoy.ply, materials: [buoy-paint], position_m: [28, 12], draft_m: 0.9}\n";
    for (size_t k = 0; k < targets.size(); ++k)
        y += fmt::format("  - {{name: step-target-{}, mesh: objects/step_target_{}.ply, materials: [target-bright, "
                         "target-dark], position_m: [{:.2f}, {:.3f}], z_m: {}}}\n",
                         k + 1, k + 1, targets[k].x, targets[k].y, -targets[k].top);
    // Photon maps for the SurfacePM materials and the MediumPM water. The dissertation's
    // configuration C used 50 M surface and 70 M volume photons (bench_render_site measures that);
    // the demo uses fewer so that it renders in about a minute on 2 cores.
    // Three bands over 0.4-0.7 um (blue, green, red): a true-colour preview (core/colour.h).
    if (!sc.render.empty()) return y + sc.render;
    y += "render:\n  bands: {range_um: [0.4, 0.7], count: 3}\n  seed: 1\n"
         "  photons: {surface: 2000000, volume: 2000000}\n  search_radius_m: {surface: 0.4, volume: 0.4}\n";
    return y;
}

auto siteTerrain(const bathymetry::BarTrough& profile) {
    return bathymetry::makeBarTrough({kX0 - 10, kY0 - 10, kX1 + 10, kY1 + 10}, profile);
}

// The step targets on the site's seabed (placeTargets with the terrain's depth).
std::vector<Target> siteTargetsOn(uint64_t seed, const bathymetry::BarTrough& profile, const bathymetry::Terrain& terrain) {
    return placeTargets(seed, profile.dean.shorelineX, [&](double x, double y) { return -terrain.elevation(x, y); });
}

}  // namespace

std::vector<SiteTarget> siteTargets(uint64_t seed) {
    const auto profile = siteProfile();
    std::vector<SiteTarget> out;
    for (const auto& t : siteTargetsOn(seed, profile, *siteTerrain(profile))) out.push_back({t.x, t.y, t.top});
    return out;
}

std::vector<fs::path> writeObjectLibrary(const fs::path& dir) {
    createOutputFolder(dir);
    std::vector<fs::path> files;
    writeMesh(dir, "barge.ply", makeBarge(4.0, 12.0, 1.5), &files);    // slots: 0 hull, 1 deck
    writeMesh(dir, "boat.ply", makeBoat(5.0, 2.0, 0.8), &files);       // slots: 0 hull, 1 deck
    writeMesh(dir, "buoy.ply", makeBuoy(0.4, 1.8), &files);            // slot 0
    writeMesh(dir, "pier.ply", makePier(sitePier()), &files);          // slots: 0 deck, 1 pilings
    writeMesh(dir, "step_target.ply", makeStepTarget(2.0, 1.0), &files);  // slots: 0 bright, 1 dark
    writeMesh(dir, "cube.ply", makeBox(1.0, 1.0, 1.0), &files);         // slot 0 (a 1 m cube, base at z = 0)
    return files;
}

SiteSummary writeSyntheticSite(const fs::path& dir, const SiteOptions& opt) {
    SiteSummary s;
    createOutputFolder(dir / "textures");
    createOutputFolder(dir / "objects");
    const uint64_t seed = opt.seed;
    const auto profile = siteProfile();
    const auto terrain = siteTerrain(profile);
    const std::vector<Target> targets = siteTargetsOn(seed, profile, *terrain);
    for (const auto& t : targets) s.targetTopDepths.push_back(t.top);

    writeClassMap(dir, opt, *terrain, targets, s);
    writeClassTextures(dir, seed, s);
    writeSiteObjects(dir / "objects", targets, s);
    s.sceneFile = dir / "scene.yaml";
    writeTextFileAtomic(s.sceneFile, siteSceneAndWater(seed, opt) + siteGround(profile, opt.scene) +
                                          siteObjectsAndRender(targets, opt.scene));
    s.files.push_back(s.sceneFile);
    // The site is complete: publish it (inside a command's output set the files are only staged
    // until now), so its sizes can be read and the build that follows can read it.
    publishStagedOutputs();
    for (const auto& f : s.files) s.totalBytes += fs::file_size(f);
    return s;
}

}  // namespace littoral::scenegen
