#pragma once
// The scene file: what the user wrote, parsed and checked, before any geometry is generated.
//
// loadSceneFile() reads the YAML, checks every section strictly (unknown keys with "did you
// mean", types, ranges, referenced files) and returns a SceneSpec. Sections that produce
// geometry (water.surface, bathymetry, objects, texture_classes) are parsed by their own
// modules' section parsers; this file owns scene, sun, sky, sensors, probes, materials,
// water.optics and render. applyCommonSections() turns the non-geometric part into Scene IR.
// Documentation of every key: docs/scene-format.md.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/scene_ir.h"
#include "core/spectrum.h"
#include "scenegen/yaml_reader.h"

namespace littoral::scenegen {

struct GeoOrigin {
    double latitude = 0, longitude = 0, altitude = 0;  // degrees, degrees, metres
};

struct SceneSection {
    std::string name = "scene";
    std::optional<GeoOrigin> origin;
    // Plan-view domain [x0, x1] x [y0, y1], metres, local frame (x east, y north).
    double x0 = -45, x1 = 45, y0 = -30, y1 = 30;
};

struct SunSection {
    bool enabled = true;
    double zenith = 0;           // radians
    double compassAzimuth = 0;   // radians clockwise from north (as the user gave it)
    std::optional<std::string> dateTimeUtc;  // ISO 8601 "YYYY-MM-DDTHH:MM:SSZ" when set
    double halfAngle = 0.5 * 0.53 * 3.14159265358979323846 / 180.0;
    std::optional<Spectrum> irradiance;  // normal to the beam, W m^-2 um^-1
};

struct SkySection {
    std::string model = "uniform";  // uniform | simple
    std::optional<Spectrum> radiance;           // uniform
    double hemisphereIrradiance = 1.0;          // simple: E_h, W m^-2 um^-1 on a horizontal plane
    double skyFraction = 1.0;                   // simple: F_u
    // simple: the plane on which the sun's share (1 - F_u) E_h is measured: "horizontal" (the sun
    // puts (1 - F_u) E_h on a horizontal plane, (1 - F_u) E_h / cos(theta_s) normal to its beam) or
    // "normal" (DIRSIG's Eq. 4.5: (1 - F_u) E_h normal to the beam).
    std::string sunPlane = "horizontal";
};

struct SensorSection {
    std::string name;
    std::string type;  // frame | pinhole | orthographic
    SourceLoc loc;
    // frame (dissertation Table 10.1): the sensor looks at `target` from elevation, compass
    // azimuth and range; the GSD along the optical axis sets the IFOV = gsd / range.
    double elevation = 0, compassAzimuth = 0, range = 0, gsd = 0;
    Vec3 target;
    // pinhole / orthographic
    Vec3 position, direction{0, 0, -1}, up{0, 1, 0};
    ParamValues optics;  // the parameters of the sensor type (core/sensor_types.h): IR key -> IR value (m)
    int width = 0, height = 0;
    int samplesPerPixel = 1;
    std::string medium = "auto";  // auto | air | water
    std::optional<ir::SensorPsf> psf;            // render/sensor_model.h
    std::optional<ir::SensorDetector> detector;  // its seed defaults to render.seed
    bool detectorSeedGiven = false;
    bool waterProducts = false;  // water_products: true (render/water_products.cpp)
    SourceLoc waterProductsLoc;
};

struct ProbeSection {
    std::string name;
    SourceLoc loc;
    Vec3 position;
    std::vector<std::string> quantities;
    std::string medium = "auto";
    std::optional<int> samples;  // overrides render.probe_samples for this probe
    size_t entry = 0;            // index of its `probes` entry (an array entry makes many probes)
};
// At most this many probes in one `line` or `grid` entry.
inline constexpr long long kMaxArrayProbes = 100000;

struct MaterialSection {
    std::string name;
    std::string type;    // lambertian | black | dielectric
    std::string solver;  // classic | generic | surface-pm, or "" when not given
    Spectrum reflectance = Spectrum::constant(0.0);
    // dielectric: the index of the object's inside (required) and its absorption coefficient, m^-1.
    // The IR gets a smooth Dielectric material and a medium of the same name.
    std::optional<Spectrum> refractiveIndex;
    Spectrum absorption = Spectrum::constant(0.0);
    SourceLoc loc;
};

// The IOPs of one water layer (or of the whole water body): total absorption and the scattering
// constituents (each with its b(lambda) and phase function).
struct LayerOptics {
    Spectrum absorption = Spectrum::constant(0.0);  // m^-1
    std::vector<ir::Scatterer> scatterers;
    bool phaseGiven = false;     // `phase` or a scatterer's phase was written in the file (not the default)
    std::string phaseKey;        // which: "phase" or "scatterers[].phase"

    std::string preset;          // the named IOP set used, if any
    SourceLoc loc;
};

struct WaterOptics {
    Spectrum refractiveIndex = Spectrum::constant(1.34);
    LayerOptics iops;                     // homogeneous water (no `layers`)
    // Depth-stratified water: layer i spans depths [depths[i], depths[i+1]) metres below the
    // still-water level; the last layer continues downward without limit.
    std::vector<double> layerTops;        // depth of each layer's top (first = 0)
    std::vector<LayerOptics> layers;
    // "" (none given) | medium-pm | attenuation. The dirsig estimator's scattering water with none
    // given takes medium-pm (solverDefaulted), so that its in-scattered light is rendered.
    std::string solver;
    bool solverDefaulted = false;
    SourceLoc loc, solverLoc;
};

struct RenderSection {
    ir::RenderSettings settings;
};

struct SceneSpec {
    std::filesystem::path file;
    SceneSection scene;
    SunSection sun;
    SkySection sky;
    std::vector<SensorSection> sensors;
    std::vector<ProbeSection> probes;
    std::vector<MaterialSection> materials;
    bool hasWater = false;
    double waterLevel = 0.0;
    bool periodic = false;  // water.horizontal: periodic
    WaterOptics waterOptics;
    // Geometry-producing sections, kept as checked YAML nodes for their modules' parsers.
    std::optional<YamlNode> waterSurface, bathymetry, objects, textureClasses;
    RenderSection render;
};

// A spectral value in a scene file: a number (constant), {wavelengths_um: [...], values: [...]}
// (linear between samples), or {file: name.csv} with "wavelength_um, value" rows. Values are
// range-checked against [min, max] (`unit` names them in messages).
Spectrum parseSpectrum(const YamlNode& node, double min, double max, std::string_view unit);

// The text of a spectrum file: rows "wavelength_um, value" (comma or blank separated), '#'
// comments, one optional header row, UTF-8. Wavelengths in [0.2, 20] um, strictly increasing;
// values in [min, max]. InputError at file:line naming the problem.
Spectrum parseSpectrumCsv(std::string_view text, const std::string& fileForErrors, double min, double max,
                          std::string_view unit);

// Parses and validates a scene file. Throws InputError (file:line:column) on any mistake.
SceneSpec loadSceneFile(const std::filesystem::path& file);
SceneSpec parseScene(const YamlNode& root, const std::filesystem::path& file);


// Fills sun, sky, media ("water" when the scene has water), materials, sensors, probes and render
// settings of the IR from the spec. Geometry (meshes) is added by the scene assembler.
void applyCommonSections(const SceneSpec& spec, ir::SceneIR* ir);

// Frame-camera placement (Table 10.1): camera position, forward, up and pinhole intrinsics.
ir::Sensor placeSensor(const SensorSection& s, double waterLevel, bool hasWater);

}  // namespace littoral::scenegen
