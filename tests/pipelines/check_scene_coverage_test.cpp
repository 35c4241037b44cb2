// check-scene refuses everything `run` refuses before rendering (issue 20), and a hand-edited IR's
// render-time mistake names scene.json and the key.
//
// Scene files. For every case below, `check-scene`, `build` and `run` all exit 1 with one error
// located in the scene file (file:line:column, at the entry or key), and `build` and `run` leave
// no output folder behind (the renderer's checks run before the IR is written).
//
// How the cases were enumerated: every `throw InputError` in render/*.cpp, and in the core code
// the renderer calls to make its scene (core/phase_functions.cpp, core/spectrum.cpp,
// core/kinds.cpp, core/cox_munk_fit.h, ir::checkLayers), was tried from a scene file, and sorted:
//  - refused by the renderer's own checks (render::preflightRenderJob: the scene on its bands,
//    each sensor's view, each probe's plan; render::makeRenderConfig: the estimator's solvers and
//    its cross-setting rules): every one is a case here;
//  - a value range the scene parser checks at the key first (reflectance, refractive index,
//    absorption and scattering, phase parameters, wind speeds, sensor optics and image sizes, sun
//    and sky, each render setting's range, docs/scene-format.md gives them): cases here are those
//    the hostile report found passing check-scene (f13, f15, f16: the Fournier-Forand range;
//    i08, i09: a frame's `up`), the others are the parser's and render_settings_cli_test's;
//  - refused by the assembler first (a probe or camera inside an object, a view that misses the
//    scene's box): one case each;
//  - not reachable from a scene file, which the parser and assembler write consistently:
//    non-finite vectors (YAML numbers are finite), empty or inverted bands, instance transforms
//    (scenes make none), mesh material slots and media, a periodic wall without a periodic domain,
//    a classified material without a class map, more than 16 scatterers per layer (a scene makes
//    at most 3), phase mixtures and tables (no scene key). A hand-edited IR reaches them: the IR
//    cases below take the report's n05-n25 and one of each way such an error is located.
// One refusal of `run` is not one of check-scene: a scene with no sensors and no probes may be
// built for its geometry alone, so check-scene and build warn and run refuses
// (NothingToRenderIsRefusedByRunBeforeWriting).
//
// Hand-edited IRs. Each case builds the small scene, edits its scene.json (nlohmann::json), and
// checks that `render IR --out out` exits 1 with an error naming scene.json and the IR key path
// and leaves nothing in out.
//
// Both tables in docs/reliability.md are generated from these lists: the test fails when one is
// out of date and prints the table to paste (or rewrites it with LITTORAL_WRITE_DOCS=1).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using littoral::testing_support::CommandResult;
using littoral::testing_support::replacedOnce;
using littoral::testing_support::runLittoral;
using littoral::testing_support::scratchDir;
using littoral::testing_support::writeTextFile;
using Json = nlohmann::json;

namespace {

// The small valid scene (flat water over a flat seabed at -2 m, one nadir frame sensor on line 8,
// one probe on line 10, the material on line 6, the render settings on line 11).
const char* const kCoverageBase = littoral::testing_support::kSmallScene;
const std::string kFrame =
    "{name: nadir, type: frame, elevation_deg: 90, azimuth_deg: 0, range_m: 50, gsd_m: 0.5, width: 16, height: 12}";
const std::string kProbe = "{name: p, position: [0, 0, -1], quantities: [Ed]}";
const std::string kRender = "render: {probe_samples: 64, hemisphere_samples: 4}";
const std::string kWater = "water: {optics: {preset: coastal}}";
const std::string kSeabed = "bathymetry: {type: planar_slope, z0_m: -2, material: floor}";
const std::string kFloor = "{name: floor, reflectance: 0.2}";

struct Case {
    std::string name;
    std::string what;      // the table's description
    std::string from, to;  // the edit of kCoverageBase
    std::string where;     // ":line:column" of the error
    std::string message;   // a fragment of the error
};

// A 4 x 4 class map of value 0, written once with oiiotool; the path is relative to each case's
// scene file (coverage/<case>/), so the error columns do not depend on where the build is.
std::string classMap() {
    static const bool written = [] {
        const fs::path p = scratchDir("coverage", "map") / "map.png";
        const std::string cmd = "oiiotool --pattern constant:color=0 4x4 1 -d uint8 -o '" + p.string() + "' >/dev/null";
        return std::system(cmd.c_str()) == 0;
    }();
    EXPECT_TRUE(written);
    return "../map/map.png";
}

// A closed unit cube (OBJ), written once; relative to each case's scene file as classMap().
std::string cubeMesh() {
    static const bool written = [] {
        writeTextFile(scratchDir("coverage", "mesh"), "cube.obj",
                      "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
                      "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
                      "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
                      "f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n");
        return true;
    }();
    EXPECT_TRUE(written);
    return "../mesh/cube.obj";
}

// The render line, followed by an object (a closed cube at (3, 3, 1)) on line 13.
std::string withCube(const std::string& material) {
    return kRender + "\nobjects:\n  - {name: box, mesh: " + cubeMesh() + ", materials: [" + material +
           "], position_m: [3, 3], z_m: 1}";
}

const std::vector<Case>& cases() {
    static const std::vector<Case> c{
        // Probes (render::checkProbe).
        {"probe_on_seabed", "a probe exactly on the seabed (its lower hemisphere would read 0)",
         "position: [0, 0, -1]", "position: [0, 0, -2]", ":10:5", "closer than 0.0001 m"},
        {"probe_wrong_medium", "a probe in air declared `medium: water`", "position: [0, 0, -1]",
         "position: [0, 0, 1], medium: water", ":10:5", "lies in air above the water surface, but its medium is water (medium: water)"},
        {"probe_batches", "`probes[].samples` fewer than `render.probe_batches`", "quantities: [Ed]}",
         "quantities: [Ed], samples: 2}", ":10:5", "2 samples cannot form 16 batches"},
        {"probe_far_away", "a probe at z = 1e300 (Embree asserted on the ray origin: SIGABRT)", "position: [0, 0, -1]",
         "position: [0, 0, 1e300]", ":10:5",
         "probe 'p': position (0, 0, 1e+300) lies beyond 1e+09 m from the origin; positions must be finite and "
         "within 1e+09 m in each coordinate"},
        {"probe_inside_object", "a probe inside a closed opaque object", kProbe + "\n" + kRender,
         "{name: p, position: [3, 3, 1], quantities: [Ed]}\n" + withCube("floor"), ":10:5",
         "probe 'p' at (3, 3, 1) is inside object 'box': it would measure nothing"},
        {"probe_rrs_in_water", "a probe under water asking for `Rrs` (it needs the sea surface below it, in the air)",
         "quantities: [Ed]}", "quantities: [Ed, Rrs]}", ":10:5",
         "probe 'p': quantity Rrs needs a probe in the air with the sea surface straight below it"},
        // Sensors (render::Camera, render::renderTruth).
        {"water_products_under_water", "`water_products: true` on a sensor under water", kFrame,
         "{name: nadir, type: pinhole, position: [0, 0, -1], direction: [0, 0, -1], focal_length_mm: 5, "
         "pixel_pitch_um: 10, width: 8, height: 8, water_products: true}",
         ":8:156", "water_products needs a sensor in the air (this one is in the water)"},
        {"pinhole_sees_nothing", "a pinhole camera whose view misses the scene", kFrame,
         "{name: nadir, type: pinhole, position: [0, 0, 5], direction: [0, 0, 1], focal_length_mm: 5, "
         "pixel_pitch_um: 10, width: 8, height: 8}",
         ":8:5", "sensor 'nadir' at (0, 0, 5) looking along (0, 0, 1) sees nothing of the scene"},
        {"pinhole_rays_miss", "a pinhole whose field of view holds the scene but none of whose pixel rays meets it",
         kFrame,
         "{name: nadir, type: pinhole, position: [0, 0, 5], direction: [0, 0, -1], focal_length_mm: 0.001, "
         "pixel_pitch_um: 100000, width: 8, height: 8}",
         ":8:5", "sensor 'nadir': empty view: none of the 8 x 8 pixel rays meets any geometry"},
        {"camera_wrong_medium", "a pinhole camera under water declared `medium: air`", kFrame,
         "{name: nadir, type: pinhole, position: [0, 0, -1], direction: [0, 0, -1], focal_length_mm: 5, "
         "pixel_pitch_um: 100, width: 8, height: 8, medium: air}",
         ":8:5", "declared in medium 'air', but the interfaces around its position (0, 0, -1) put it in 'water'"},
        {"frame_up_parallel", "a nadir frame sensor with `up: [0, 0, 1]` (parallel to the view)",
         "width: 16, height: 12}", "width: 16, height: 12, up: [0, 0, 1]}", ":8:119",
         "sensors[0].up: 'up' (0, 0, 1) must not be parallel to the view direction (0, 0, -1)"},
        {"frame_up_zero", "a nadir frame sensor with `up: [0, 0, 0]`", "width: 16, height: 12}",
         "width: 16, height: 12, up: [0, 0, 0]}", ":8:119", "sensors[0].up: 'up' must be non-zero"},
        // Surfaces and media on the bands (render::Scene).
        {"rough_equal_indices", "a rough water surface over water of refractive index 1 (no interface to be rough)",
         kWater,
         "water: {surface: {model: flat, size: 12, spacing: 1, roughness: {wind_speed: 5}}, optics: {preset: coastal, "
         "refractive_index: 1.0}}",
         ":4:65",
         "water.surface.roughness: a rough surface needs water of another refractive index than the air's (1), but "
         "water.optics.refractive_index is 1 in band 0"},
        {"class_mean_reflectance", "a texture class whose `mean` times its reflectance exceeds 1", kSeabed,
         "bathymetry: {type: planar_slope, z0_m: -2}\ntexture_classes: {map: " + classMap() +
             ", extent: {x: [-5, 5], y: [-5, 5]}, classes: [{index: 0, name: c0, reflectance: 0.9, mean: 10}]}",
         ":6:84", "material 'c0': reflectance 9 outside [0, 1]"},
        {"class_reflectance_bands", "a texture class whose reflectance table does not cover the render bands",
         kSeabed,
         "bathymetry: {type: planar_slope, z0_m: -2}\ntexture_classes: {map: " + classMap() +
             ", extent: {x: [-5, 5], y: [-5, 5]}, classes: [{index: 0, name: c0, reflectance: {wavelengths_um: "
             "[0.5, 0.55], values: [0.2, 0.2]}}]}",
         ":6:84", "material 'c0' reflectance: band [0.4, 0.6] um lies outside the tabulated range [0.5, 0.55] um"},
        {"ff_backscatter_1e-4", "a Fournier-Forand `backscatter_fraction` of 1e-4 (f13; the function cannot be "
                                "sampled below 0.002)",
         kWater,
         "water: {optics: {absorption_per_m: 0.1, scattering_per_m: 0.5, phase: {type: fournier-forand, "
         "backscatter_fraction: 0.0001}}}",
         ":4:117", "water.optics.phase.backscatter_fraction: 0.0001 is out of range; allowed [0.002, 0.4999]"},
        {"ff_backscatter_0.0019", "a Fournier-Forand `backscatter_fraction` of 0.0019 (f15)", kWater,
         "water: {optics: {absorption_per_m: 0.1, scattering_per_m: 0.5, phase: {type: fournier-forand, "
         "backscatter_fraction: 0.0019}}}",
         ":4:117", "water.optics.phase.backscatter_fraction: 0.0019 is out of range; allowed [0.002, 0.4999]"},
        {"ff_particle_phase", "a constituents' Fournier-Forand `particle_phase` of 0.001 (f16)", kWater,
         "water: {optics: {constituents: {chlorophyll_mg_m3: 1, particle_phase: {type: fournier-forand, "
         "backscatter_fraction: 0.001}}}}",
         ":4:117",
         "water.optics.constituents.particle_phase.backscatter_fraction: 0.001 is out of range; allowed [0.002, "
         "0.4999]"},
        // The estimator's settings and solvers (render::makeRenderConfig).
        {"render_batches", "`render.probe_batches` above `render.probe_samples`", kRender,
         "render: {probe_samples: 8, probe_batches: 16, hemisphere_samples: 4}", ":11:43",
         "render.probe_batches: 16 batches cannot be formed from 8 probe samples"},
        {"surface_pm_without_photons", "`solver: surface-pm` without `render.photons.surface`", kFloor,
         "{name: floor, reflectance: 0.2, solver: surface-pm}", ":6:13",
         "material 'floor': the surface-pm solver needs the surface photon map: set render.photons.surface"},
        {"depth_splitting_path", "`render.photons.depth_splitting` with `render.estimator: path`", kRender,
         "render: {estimator: path, probe_samples: 64, photons: {depth_splitting: true}}", ":11:73",
         "render.photons.depth_splitting: is set, but the 'path' estimator does not read it"},
        {"depth_splitting_no_volume_map", "`render.photons.depth_splitting` where no medium uses the volume photon map",
         kWater + "\n", "water: {optics: {preset: coastal, solver: attenuation}}\n", ":11:79",
         "render.photons.depth_splitting: is set, but the 'dirsig' estimator does not read it; photon maps"},
        {"depth_splitting_not_boolean", "`render.photons.depth_splitting: maybe`", kRender,
         "render: {probe_samples: 64, hemisphere_samples: 4, photons: {volume: 10000, depth_splitting: maybe}}", ":11:94",
         "render.photons.depth_splitting: expected true or false, found 'maybe'"},
        {"probe_collisions_one_pass", "`render.photons.probe_collisions` in a run of one pass", kRender,
         "render: {probe_samples: 64, hemisphere_samples: 4, photons: {volume: 10000, probe_collisions: true}}", ":11:95",
         "render.photons.probe_collisions: needs at least 2 progressive passes"},
        {"probe_collisions_not_invariant", "`render.photons.probe_collisions` in a scene that varies across the plane",
         kRender, "render: {probe_samples: 64, hemisphere_samples: 4, photons: {volume: 10000, probe_collisions: true}, progressive: {passes: 2}}", ":11:95",
         "render.photons.probe_collisions: applies only to a horizontally invariant scene"},
        {"path_material_solver", "a material `solver` with `render.estimator: path`", kFloor + "]\nsensors:",
         "{name: floor, reflectance: 0.2, solver: generic}]\nsensors:", ":6:13",
         "material 'floor': the path estimator does not use per-material solvers"},
    };
    return c;
}

// The second edit of a case (after from/to): the render line of path_material_solver.
std::string secondEdit(const Case& c, std::string text) {
    if (c.name == "path_material_solver") return replacedOnce(text, kRender, "render: {estimator: path, probe_samples: 64}");
    if (c.name == "depth_splitting_no_volume_map")
        return replacedOnce(text, kRender, "render: {probe_samples: 64, hemisphere_samples: 4, photons: {depth_splitting: true}}");
    return text;
}

// A hand edit of the IR that `render` must refuse, naming scene.json and the key.
struct IrCase {
    std::string name;
    std::string what;                  // the table's description of the edit
    std::function<void(Json&)> edit;   // applied to scene.json
    std::string message;               // follows "scene.json: error: "
};

Json& layer0(Json& j) { return j["media"][0]["layers"][0]; }
Json& bulk(Json& j) { return layer0(j)["scatterers"][0]; }
Json& airWater(Json& j) { return j["materials"][1]; }  // air-water-interface (materials[0] is floor)

const std::vector<IrCase>& irCases() {
    static const std::vector<IrCase> c{
        // The hostile report's n05-n25.
        {"forward_zero", "`sensors[0].forward: [0, 0, 0]` (n05)", [](Json& j) { j["sensors"][0]["forward"] = {0, 0, 0}; },
         "sensors[0]: sensor 'nadir': forward vector (0, 0, 0) must be finite and non-zero"},
        {"sun_half_angle_zero", "`sun.half_angle_rad: 0` (n08)", [](Json& j) { j["sun"]["half_angle_rad"] = 0; },
         "sun.half_angle_rad: 0 rad must lie in (0, pi/2)"},
        {"progressive_passes_zero", "`render.progressive_passes: 0` with a surface photon map (n11)",
         [](Json& j) {
             j["materials"][0]["solver"] = "surface-pm";
             j["render"]["surface_photons"] = 100;
             j["render"]["progressive_passes"] = 0;
         },
         "render.progressive_passes: 0 is out of range; allowed [1, 100000]"},
        {"bands_empty", "`render.bands_um: []` (n12)", [](Json& j) { j["render"]["bands_um"] = Json::array(); },
         "render.bands_um: at least one band is required"},
        {"reflectance_2", "`materials[0].reflectance: 2` (n13)", [](Json& j) { j["materials"][0]["reflectance"] = 2; },
         "materials[0]: material 'floor': reflectance 2 outside [0, 1]"},
        {"absorption_negative", "`media[0].layers[0].absorption_per_m: -0.5` (n19)",
         [](Json& j) { layer0(j)["absorption_per_m"] = -0.5; },
         "media[0]: medium 'water': absorption coefficient -0.5 in band 0 (need a >= 0)"},
        {"hemisphere_samples_zero", "`render.hemisphere_samples: 0` (n20)",
         [](Json& j) { j["render"]["hemisphere_samples"] = 0; },
         "render.hemisphere_samples: 0 is out of range; allowed [1, 1048576]"},
        {"rough_wind_zero", "the interface made `rough-dielectric` with `wind_speed_mps: 0` (n23)",
         [](Json& j) { airWater(j).update({{"type", "rough-dielectric"}, {"wind_speed_mps", 0}}); },
         "materials[1].wind_speed_mps: 0 is outside the allowed range [0.01, 14] m/s"},
        {"hg_g_1", "Henyey-Greenstein `g: 1` (n24)", [](Json& j) { bulk(j)["phase"]["g"] = 1.0; },
         "media[0]: medium 'water' scatterer 'bulk' phase: henyey-greenstein g = 1 is out of range; allowed [-0.999, "
         "0.999]"},
        {"refractive_index_0.5", "`media[0].refractive_index: 0.5` (n25)",
         [](Json& j) { j["media"][0]["refractive_index"] = 0.5; },
         "media[0]: medium 'water': refractive index 0.5 in band 0 (need n >= 1)"},
        // The renderer's other checks a hand edit can reach.
        {"sun_zenith_4", "`sun.zenith_rad: 4`", [](Json& j) { j["sun"]["zenith_rad"] = 4; },
         "sun.zenith_rad: 4 rad must lie in [0, pi]"},
        {"sun_irradiance_negative", "`sun.irradiance: -1`", [](Json& j) { j["sun"]["irradiance"] = -1; },
         "sun.irradiance: negative or non-finite value"},
        {"sky_radiance_negative", "`sky.radiance: -1`", [](Json& j) { j["sky"]["radiance"] = -1; },
         "sky.radiance: negative or non-finite value"},
        {"rough_equal_indices", "a rough interface over water of index 1",
         [](Json& j) {
             airWater(j).update({{"type", "rough-dielectric"}, {"wind_speed_mps", 5}});
             j["media"][0]["refractive_index"] = 1.0;
         },
         "meshes[0]: mesh 'water': rough interface 'air-water-interface' between media of equal refractive index (1) "
         "in band 0"},
        {"sensor_far_away", "`sensors[0].position_m: [0, 0, 1e300]` (SIGABRT in Embree)",
         [](Json& j) { j["sensors"][0]["position_m"] = {0, 0, 1e300}; },
         "sensors[0]: sensor 'nadir': position (0, 0, 1e+300) lies beyond 1e+09 m from the origin"},
        {"probe_far_away", "`probes[0].position_m: [0, 0, 1e300]` (SIGABRT in Embree)",
         [](Json& j) { j["probes"][0]["position_m"] = {0, 0, 1e300}; },
         "probes[0]: probe 'p': position (0, 0, 1e+300) lies beyond 1e+09 m from the origin"},
        {"probe_batches", "`render.probe_batches: 100` above the 64 probe samples",
         [](Json& j) { j["render"]["probe_batches"] = 100; },
         "render.probe_batches: 100 batches cannot be formed from 64 probe samples"},
        {"surface_pm_without_photons", "`solver: surface-pm` without `render.surface_photons`",
         [](Json& j) { j["materials"][0]["solver"] = "surface-pm"; },
         "materials[0] 'floor': the surface-pm solver needs the surface photon map"},
        {"path_medium_solver", "`render.estimator: path` with `media[0].solver: medium-pm`",
         [](Json& j) {
             j["render"]["estimator"] = "path";
             j["render"].erase("hemisphere_samples");
             j["media"][0]["solver"] = "medium-pm";
         },
         "media[0] 'water': the path estimator does not use medium solvers"},
        {"instance_singular", "an instance with an all-zero rotation",
         [](Json& j) {
             j["instances"] = Json::array({{{"mesh", "water"}, {"rotation", Json::array({0, 0, 0, 0, 0, 0, 0, 0, 0})},
                                            {"translation_m", {0, 0, 0}}}});
         },
         "instances[0] (mesh 'water'): a column of the rotation has length 0"},
        {"instance_far_away", "an instance translated by 1e30 m (rendered silently, far outside the domain)",
         [](Json& j) {
             j["instances"] = Json::array({{{"mesh", "water"}, {"rotation", Json::array({1, 0, 0, 0, 1, 0, 0, 0, 1})},
                                            {"translation_m", {1e30, 0, 0}}}});
         },
         "instances[0] (mesh 'water', placed): vertex 0 at (1e+30"},
        {"psf_negative", "a sensor's PSF kernel with a negative value",
         [](Json& j) {
             j["sensors"][0]["psf"] = {{"type", "kernel"}, {"width", 3}, {"height", 1}, {"values", {1, -1, 1}}};
         },
         "sensors[0].psf.values[1]: a PSF value must be finite and >= 0"},
        {"detector_qe", "a sensor's detector with `quantum_efficiency: 2`",
         [](Json& j) {
             j["sensors"][0]["detector"] = {{"aperture_diameter_m", 0.01}, {"integration_time_s", 0.001},
                                            {"quantum_efficiency", 2},      {"read_noise_e", 10},
                                            {"full_well_e", 1e5},           {"bits", 12},
                                            {"seed", 1}};
         },
         "sensors[0].detector.quantum_efficiency: 2 is out of range; allowed [1e-06, 1]"},
        {"response_weights", "a response band whose weights sum to 0.5 (it would scale the radiance)",
         [](Json& j) {
             j["render"]["response_bands"] = Json::array(
                 {{{"kind", "gaussian"}, {"nominal_um", {0.45, 0.55}}, {"weights", Json::array({Json::array({0, 0.5})})}}});
         },
         "render.response_bands[0].weights: the weights sum to 0.5, not 1"},
        {"geo_zone_61", "a UTM geo reference in zone 61",
         [](Json& j) {
             j["geo"] = {{"frame", "utm"}, {"latitude_deg", 36.2}, {"longitude_deg", -75.75}, {"altitude_m", 0},
                         {"utm_zone", 61}};
         },
         "geo.utm_zone: expected a UTM zone in [1, 60]"},
        {"nothing_to_render", "`sensors: []` and `probes: []`",
         [](Json& j) {
             j["sensors"] = Json::array();
             j["probes"] = Json::array();
         },
         "sensors, probes: both are empty: there is nothing to render"},
    };
    return c;
}

std::string sceneTable() {
    std::ostringstream t;
    t << "| case | scene file | at | error of `check-scene`, `build` and `run` (exit 1, nothing written) |\n"
      << "|---|---|---|---|\n";
    for (const Case& c : cases())
        t << "| `" << c.name << "` | " << c.what << " | `" << (c.where.empty() ? "file" : c.where) << "` | `... " << c.message
          << " ...` |\n";
    return t.str();
}

std::string irTable() {
    std::ostringstream t;
    t << "| case | edit of `scene.json` | error of `render IR --out out` (exit 1, nothing in out) |\n|---|---|---|\n";
    for (const IrCase& c : irCases())
        t << "| `" << c.name << "` | " << c.what << " | `IR/scene.json: error: " << c.message << " ...` |\n";
    return t.str();
}

const std::string kEnd = "<!-- generated: end -->\n";
const std::string kSceneBegin = "<!-- generated by tests/pipelines/check_scene_coverage_test.cpp: begin -->\n";
const std::string kIrBegin = "<!-- generated by tests/pipelines/check_scene_coverage_test.cpp (hand-edited IRs): begin -->\n";

// Compares the block after `begin` in docs/reliability.md with `want` (rewrites it with
// LITTORAL_WRITE_DOCS=1).
void expectGeneratedBlock(const std::string& begin, const std::string& want) {
    const fs::path doc = fs::path(LITTORAL_SOURCE_DIR) / "docs" / "reliability.md";
    std::ifstream in(doc);
    std::stringstream ss;
    ss << in.rdbuf();
    std::string text = ss.str();
    const size_t b = text.find(begin);
    ASSERT_NE(b, std::string::npos) << "docs/reliability.md lacks the block " << begin;
    const size_t from = b + begin.size(), e = text.find(kEnd, from);
    ASSERT_NE(e, std::string::npos);
    const std::string now = text.substr(from, e - from);
    if (now != want && std::getenv("LITTORAL_WRITE_DOCS")) {
        text.replace(from, now.size(), want);
        std::ofstream(doc) << text;
        return;
    }
    EXPECT_EQ(now, want) << "docs/reliability.md is out of date; paste:\n" << want;
}

// Runs `littoral ARGS` for every entry, two at a time (most of each command's time is the
// dynamic linker's, on a machine with few cores), and returns the results in order.
std::vector<CommandResult> runAll(const std::vector<std::string>& args) {
    std::vector<CommandResult> results(args.size());
    std::atomic<size_t> next{0};
    auto work = [&] {
        for (size_t i; (i = next++) < args.size();) results[i] = runLittoral(args[i]);
    };
    std::thread other(work);
    work();
    other.join();
    return results;
}

}  // namespace

TEST(CheckSceneCoverage, EveryRenderTimeRefusalIsRefusedByCheckSceneBuildAndRun) {
    ASSERT_TRUE(fs::exists(littoral::testing_support::littoralBinary())) << "build the littoral target first";
    // The base scene itself is valid (else every case would pass for the wrong reason).
    {
        const fs::path scene = writeTextFile(scratchDir("coverage", "base"), "base.yaml", kCoverageBase);
        const auto r = runLittoral("--quiet check-scene " + scene.string());
        ASSERT_EQ(r.status, 0) << r.output;
    }
    // Each case's scene file <case>/<case>.yaml through check-scene, build and run (their outputs
    // into <case>/out-<command>).
    const std::vector<std::string> commands = {"check-scene", "build", "run"};
    std::vector<std::string> args;
    std::vector<fs::path> scenes;
    for (const Case& c : cases()) {
        const fs::path dir = scratchDir("coverage", c.name);
        scenes.push_back(writeTextFile(dir, c.name + ".yaml", secondEdit(c, replacedOnce(kCoverageBase, c.from, c.to))));
        for (const std::string& cmd : commands)
            args.push_back("--quiet " + cmd + " " + scenes.back().string() +
                           (cmd == "check-scene" ? "" : " --out " + (dir / ("out-" + cmd)).string()));
    }
    const std::vector<CommandResult> results = runAll(args);
    for (size_t i = 0; i < cases().size(); ++i) {
        const Case& c = cases()[i];
        for (size_t k = 0; k < commands.size(); ++k) {
            SCOPED_TRACE(c.name + " " + commands[k]);
            const CommandResult& r = results[i * commands.size() + k];
            EXPECT_EQ(r.status, 1) << r.output;
            EXPECT_NE(r.output.find(c.name + ".yaml" + c.where + ": error: "), std::string::npos) << r.output;
            EXPECT_NE(r.output.find(c.message), std::string::npos) << r.output;
            EXPECT_FALSE(fs::exists(scenes[i].parent_path() / ("out-" + commands[k]))) << "output left behind";
        }
    }
}

TEST(CheckSceneCoverage, UpIsJudgedByItsDirectionAlone) {
    // The parser and the renderer scale `up` by its largest component before they compare it with
    // the view: [0, 1e200, 0] (whose length overflows) and [0, 1e-10, 0] are north like [0, 1, 0].
    const struct {
        std::string name, from, to;
    } accepted[] = {
        {"frame_up_huge", "width: 16, height: 12}", "width: 16, height: 12, up: [0, 1e200, 0]}"},
        {"pinhole_up_tiny", kFrame,
         "{name: nadir, type: pinhole, position: [0, 0, 5], direction: [0, 0, -1], up: [0, 1e-10, 0], "
         "focal_length_mm: 5, pixel_pitch_um: 100, width: 8, height: 8}"},
    };
    for (const auto& a : accepted) {
        SCOPED_TRACE(a.name);
        const fs::path dir = scratchDir("coverage", a.name);
        const fs::path scene = writeTextFile(dir, a.name + ".yaml", replacedOnce(kCoverageBase, a.from, a.to));
        const auto check = runLittoral("--quiet check-scene " + scene.string());
        EXPECT_EQ(check.status, 0) << check.output;
        const auto run = runLittoral("--quiet run " + scene.string() + " --out " + (dir / "out").string());
        EXPECT_EQ(run.status, 0) << run.output;
        EXPECT_TRUE(fs::exists(dir / "out" / "nadir.exr")) << run.output;
    }
}

TEST(CheckSceneCoverage, NothingToRenderIsRefusedByRunBeforeWriting) {
    // A scene without sensors and probes may be built for its geometry: check-scene and build
    // warn; run refuses before it writes the IR.
    std::string text = replacedOnce(kCoverageBase, "sensors:\n  - " + kFrame + "\n", "");
    text = replacedOnce(text, "probes:\n  - " + kProbe + "\n", "");
    const fs::path dir = scratchDir("coverage", "nothing_to_render");
    const fs::path scene = writeTextFile(dir, "nothing.yaml", text);
    const auto check = runLittoral("--quiet check-scene " + scene.string());
    EXPECT_EQ(check.status, 0) << check.output;
    EXPECT_NE(check.output.find("warning: the scene has no sensors and no probes"), std::string::npos) << check.output;
    const auto build = runLittoral("--quiet build " + scene.string() + " --out " + (dir / "ir").string());
    EXPECT_EQ(build.status, 0) << build.output;
    const auto run = runLittoral("--quiet run " + scene.string() + " --out " + (dir / "out").string());
    EXPECT_EQ(run.status, 1) << run.output;
    EXPECT_NE(run.output.find("nothing.yaml: error: sensors, probes: the scene has neither, so run has nothing to "
                              "render"),
              std::string::npos)
        << run.output;
    EXPECT_FALSE(fs::exists(dir / "out")) << "run wrote its output before refusing";
}

TEST(CheckSceneCoverage, RenderTimeErrorsInAHandEditedIrNameSceneJsonAndTheKey) {
    ASSERT_TRUE(fs::exists(littoral::testing_support::littoralBinary())) << "build the littoral target first";
    const fs::path base = scratchDir("coverage-ir", "base");
    const fs::path scene = writeTextFile(base, "base.yaml", kCoverageBase);
    const auto built = runLittoral("--quiet build " + scene.string() + " --out " + (base / "ir").string());
    ASSERT_EQ(built.status, 0) << built.output;
    Json original;
    std::ifstream(base / "ir" / "scene.json") >> original;
    std::vector<std::string> args;
    for (const IrCase& c : irCases()) {
        const fs::path dir = scratchDir("coverage-ir", c.name);
        fs::copy(base / "ir", dir / "ir", fs::copy_options::recursive);
        Json j = original;
        c.edit(j);
        std::ofstream(dir / "ir" / "scene.json") << j.dump(1) << "\n";
        args.push_back("--quiet render " + (dir / "ir").string() + " --out " + (dir / "out").string());
    }
    const std::vector<CommandResult> results = runAll(args);
    for (size_t i = 0; i < irCases().size(); ++i) {
        const IrCase& c = irCases()[i];
        SCOPED_TRACE(c.name);
        const fs::path dir = base.parent_path() / c.name;
        const CommandResult& r = results[i];
        EXPECT_EQ(r.status, 1) << r.output;
        EXPECT_NE(r.output.find((dir / "ir" / "scene.json").string() + ": error: " + c.message), std::string::npos)
            << r.output;
        EXPECT_FALSE(fs::exists(dir / "out")) << "output left behind: " << r.output;
    }
}

TEST(CheckSceneCoverage, TheReliabilityTablesAreGeneratedFromTheCases) {
    expectGeneratedBlock(kSceneBegin, sceneTable());
    expectGeneratedBlock(kIrBegin, irTable());
}
