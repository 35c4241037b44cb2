#pragma once
// The Scene IR: the one hand-off from scene generation to the renderer.
//
// On disk it is a directory holding `scene.json` and the PLY meshes it names (paths relative to
// the directory). `render/` reads only this; it never sees YAML or scene-generation code.
// Writing an IR, reading it back and writing it again gives byte-identical files.
//
// Conventions: metres; world frame x = east, y = north, z = up; angles in radians; wavelengths
// in micrometres; spectral quantities as tabulated Spectrum (the renderer averages them over its
// bands, and refuses a band that a spectrum does not cover).
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/cox_munk_fit.h"
#include "core/error.h"
#include "core/kinds.h"
#include "core/mesh.h"
#include "core/names.h"
#include "core/spectrum.h"
#include "core/vec.h"

namespace littoral::ir {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

inline constexpr int kFormatVersion = 2;

// Phase function of one scattering constituent: a phase-function kind by name and its parameter
// values (core/phase_functions.h describes each kind: "isotropic", "henyey-greenstein" {g},
// "petzold", "fournier-forand" {backscatter_fraction}, "rayleigh" {k}). All are normalised over
// the sphere. scene.json writes a parameter when it is required or differs from its default.
struct PhaseFunction {
    std::string type = "isotropic";
    ParamValues params;
    bool operator==(const PhaseFunction&) const = default;
};

// One scattering constituent of a layer (pure water, particles, ...): its scattering coefficient
// b_i(lambda) and phase function. A layer's phase function is the mixture sum b_i p_i / sum b_i.
struct Scatterer {
    std::string name;
    Spectrum scattering = Spectrum::constant(0.0);  // b_i, m^-1
    PhaseFunction phase;
};

// A horizontal slab of water zBottom <= z < zTop (world z, metres) with its own IOPs. A medium's
// layers are ordered top to bottom, contiguous, the first reaching up without limit and the last
// down without limit (a homogeneous medium is one layer with both bounds infinite).
struct Layer {
    double zTop = kInfinity, zBottom = -kInfinity;
    Spectrum absorption = Spectrum::constant(0.0);  // a, m^-1
    std::vector<Scatterer> scatterers;               // empty = non-scattering
};

// A medium: refractive index and a stack of layers. "air" with n = 1 and no absorption or
// scattering is implicit when a mesh side names no medium.
struct Medium {
    // The dirsig estimator's solver for the medium's in-scattered radiance (Table 10.4). MediumPM:
    // the volume photon map; Attenuation: none, scattering counts as loss (Beer–Lambert with
    // c = a + b), chosen explicitly. Unset: the same as Attenuation, with a warning at run time
    // when the medium scatters (a scene file's scattering water defaults to MediumPM instead).
    enum class Solver { MediumPM, Attenuation };
    std::string name;
    Spectrum refractiveIndex = Spectrum::constant(1.0);
    std::vector<Layer> layers{Layer{}};
    std::optional<Solver> solver;
    SourceLoc origin;  // where a scene file defined it (not serialised; for messages)

    // A homogeneous medium with one scatterer (none if b is the constant 0).
    static Medium homogeneous(std::string name, double n, Spectrum a, Spectrum b, PhaseFunction phase = {});
};

// "" if the layers of `m` are ordered, contiguous and cover all z; otherwise what is wrong.
std::string checkLayers(const Medium& m);

// How a surface interacts with light, and which radiometry solver evaluates it (Table 10.4).
struct Material {
    enum class Type {
        Lambertian,      // diffuse reflectance `reflectance`
        Textured,        // Lambertian, reflectance modulated by a texture draped in plan view
        Dielectric,      // smooth Fresnel interface between the mesh's two media
        RoughDielectric, // Cox–Munk microfacet interface (wind speed, wind azimuth)
        Black,           // absorbs everything (r = 0)
        Periodic,        // a side wall of a horizontally periodic domain: rays leave through it and
                         // re-enter through the opposite wall (SceneIR::domain)
        Classified,      // a classification map: the material at a point is the one its class names,
                         // looked up where the ray lands (`texture`, extent, `classMaterials`)
    };
    // The dirsig estimator's per-material solver (Table 10.4). Unset: the estimator's default for
    // the material type (Classic for diffuse materials, Fresnel for interfaces); other estimators
    // refuse a material that sets one.
    enum class Solver { Classic, Generic, Fresnel, SurfacePM };
    std::string name;
    Type type = Type::Lambertian;
    std::optional<Solver> solver;
    Spectrum reflectance = Spectrum::constant(0.0);
    // Textured: image path relative to the IR directory (single channel float or 8-bit; the
    // value multiplies `reflectance`), draped over the plan-view rectangle [x0, x1] x [y0, y1].
    std::string texture;
    double textureX0 = 0, textureY0 = 0, textureX1 = 1, textureY1 = 1;
    // Classified: `texture` is the class map, an 8- or 16-bit single-channel integer image whose
    // pixels cover [textureX0, textureX1] x [textureY0, textureY1] in plan view (row 0 north, column 0
    // west, pixel-is-area); raster value v selects the material classMaterials[v] ("" for a value the
    // map does not use). The renderer reads the class at each hit point's (x, y): class boundaries
    // are as sharp as the map, whatever the mesh. Named materials must be diffuse (lambertian or
    // textured).
    std::vector<std::string> classMaterials;
    // RoughDielectric: Cox–Munk wind speed at 12.5 m (m/s) and the azimuth the wind blows toward,
    // counter-clockwise from +x (east), radians; which Cox–Munk fit gives the slope variances,
    // whether the Gram–Charlier terms are on (clean sea only) and the microfacet shadowing term
    // (render/rough_dielectric.h).
    double windSpeed = 0.0;
    double windAzimuth = 0.0;
    CoxMunkSea sea = CoxMunkSea::Clean;
    CoxMunkSlopes slopes = CoxMunkSlopes::Anisotropic;  // scene.json writes it only when isotropic
    bool gramCharlier = false;
    // Smith's term for the light's side by default: G = 1 gains energy toward grazing incidence
    // (+4 % transmitted at an 80 deg sun, U = 7.23 m/s; render/rough_dielectric.h).
    MicrofacetShadowing shadowing = MicrofacetShadowing::SmithLight;
    SourceLoc origin;  // where a scene file defined it (not serialised; for messages)
};

// A triangle mesh with up to 65536 material slots (per-face index into `materials`) and the media
// on either side: `inside` is behind the faces (opposite to the outward normal), `outside` in
// front. Empty medium name = air.
struct Mesh {
    std::string name;
    std::string file;                     // relative to the IR directory, e.g. "meshes/water.ply"
    std::vector<std::string> materials;   // names of Material entries
    std::string inside, outside;          // Medium names or ""
    bool closed = false;                  // true when validated as a closed volume
    TriMesh data;                         // loaded geometry (not serialised in scene.json)
};

// Another placement of a mesh: world = R * local + t, R given row-major.
struct Instance {
    std::string mesh;
    double rotation[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    Vec3 translation;
};

// The sun: a disc of angular half-width `halfAngle` at (zenith, azimuth); azimuth counter-clockwise
// from +x (east) toward +y (north). Irradiance on a plane normal to the beam, W m^-2 um^-1.
struct Sun {
    bool enabled = true;
    double zenith = 0.0;
    double azimuth = 0.0;
    double halfAngle = 0.5 * 0.53 * 3.14159265358979323846 / 180.0;
    Spectrum irradiance = Spectrum::constant(0.0);
    Vec3 direction() const;  // unit vector pointing from the scene toward the sun
};

// Sky: a uniform dome of radiance `radiance` (W m^-2 sr^-1 um^-1) over the upper hemisphere.
struct Sky {
    Spectrum radiance = Spectrum::constant(0.0);
};

// A camera. Pinhole: position, look direction, up hint; image width x height; focal length and
// pixel pitch (metres) set the field of view. Orthographic: `pixelSize` metres per pixel on the
// image plane. `medium` names the medium the camera sits in ("" = air).
// A sensor's point-spread function on the radiance (render/sensor_model.h): "gaussian" (fwhmPx)
// or "kernel" (width x height values, odd sizes, non-negative, normalised when applied).
inline constexpr int kMaxPsfSide = 101;  // px: a kernel's widest side
struct SensorPsf {
    std::string type;
    double fwhmPx = 0;
    int width = 0, height = 0;
    std::vector<double> values;
};

// A sensor's detector (render/sensor_model.h): SI units.
struct SensorDetector {
    double apertureDiameter = 0;   // m
    double integrationTime = 0;    // s
    double quantumEfficiency = 0;  // (0, 1]
    double readNoise = 0;          // electrons rms
    double fullWell = 0;           // electrons
    int bits = 12;
    uint64_t seed = 1;
};

struct Sensor {
    enum class Type { Pinhole, Orthographic };
    std::string name;
    Type type = Type::Pinhole;
    Point3 position;
    Vec3 forward{0, 0, -1};
    Vec3 up{0, 1, 0};
    int width = 0, height = 0;
    double focalLength = 0.0;  // m (pinhole)
    double pixelPitch = 0.0;   // m (pinhole)
    double pixelSize = 0.0;    // m (orthographic)
    int samplesPerPixel = 1;
    std::string medium;
    std::optional<SensorPsf> psf;
    std::optional<SensorDetector> detector;
    // Water-leaving products (render/water_products.cpp): the radiance split by where the ray met
    // the sea surface (water-leaving, sky-reflected, glint, other), Ed(0+) there and Rrs. Needs a
    // sensor in the air and a scene with water.
    bool waterProducts = false;
};

// A point radiometer. Quantities: "Ed", "Eu" (plane irradiances, down/up-welling),
// "Eod", "Eou" (scalar irradiances), "Lu" (nadir-viewing upwelling radiance).
struct Probe {
    std::string name;
    Point3 position;
    std::vector<std::string> quantities;
    std::string medium;
    std::optional<int> samples;  // sample paths per quantity; unset: render.probe_samples
};

// Which radiance estimator renders the scene (render.estimator):
//   Dirsig  the dissertation's per-material radiometry solvers (Classic, Generic, Fresnel, and the
//           photon-mapped SurfacePM / MediumPM);
//   Path    an unbiased volumetric path tracer, the reference the others are checked against.
enum class Estimator { Dirsig, Path };

// Render settings. `bands`, `seed`, `threads` and `estimator` are always defined; every other
// setting is optional and held by its key in scene.json (e.g. "surface_photons") in `settings`:
// unset means "the estimator's default". Each estimator declares the settings it reads, with
// their types, defaults and ranges (render/*_estimator.cpp, registered in core/kinds.h's
// estimatorKinds()); render::makeRenderConfig checks the values against them, and a setting that
// is set but that no part of the chosen estimator reads is an error naming it.
// An output band with a spectral response (core/spectral_response.h): the weighted mean of some
// of render.bands, which are then the internal sub-bands the renderer renders. `nominal` is the
// band written into the outputs' metadata (a Gaussian's centre +- FWHM / 2).
struct ResponseBand {
    std::string kind;  // rectangle | gaussian | table
    Band nominal;
    std::vector<std::pair<int, double>> weights;  // (index into bands, weight); weights sum to 1
};

struct RenderSettings {
    std::vector<Band> bands{Band{0.4, 0.6}};
    std::vector<ResponseBand> responseBands;  // empty: the bands above are the output bands
    uint64_t seed = 1;
    int threads = 0;  // 0 = all cores
    Estimator estimator = Estimator::Dirsig;
    ParamValues settings;  // scene.json key -> value, in the order scene.json writes them
    // Where a scene file set each key (scene-file key path under `render:`, e.g. "photons.surface",
    // -> location); not serialised. Lets errors found later (e.g. "not read by this estimator")
    // point at the scene file.
    std::map<std::string, SourceLoc> locations;
};

// The plan-view domain of the scene, and whether it repeats horizontally (water.horizontal:
// periodic): then the faces of material type Periodic on its side walls wrap rays around.
struct Domain {
    double x0 = -45, x1 = 45, y0 = -30, y1 = 30;
    bool periodic = false;
};

// The scene's georeferencing (scene.origin; bathymetry/geo_frame.h): the local frame is an
// east-north-up tangent plane about the origin ("local-cartesian") or UTM grid metres about it
// ("utm", in utmZone, x = E - E0, y = N - N0).
struct GeoReference {
    std::string frame;  // local-cartesian | utm
    double latitudeDeg = 0, longitudeDeg = 0, altitudeM = 0;
    int utmZone = 0;  // utm: 1..60
};

struct SceneIR {
    std::string name = "scene";
    RenderSettings render;
    Domain domain;
    Sun sun;
    Sky sky;
    std::vector<Medium> media;
    std::vector<Material> materials;
    std::vector<Mesh> meshes;
    std::vector<Instance> instances;
    std::vector<Sensor> sensors;
    std::optional<GeoReference> geo;  // set when the scene file gives scene.origin
    std::vector<Probe> probes;
    // Free-form provenance (generator, seed, wave statistics ...), written as strings.
    std::map<std::string, std::string> metadata;

    const Material* findMaterial(const std::string& n) const;
    const Medium* findMedium(const std::string& n) const;
    const Sensor* findSensor(const std::string& n) const;  // nullptr if none
    const Mesh* findMesh(const std::string& n) const;
};

// Writes dir/scene.json and every mesh's PLY (creating dir/meshes/ as needed). Atomic per file.
void writeIR(const SceneIR& scene, const std::filesystem::path& dir);
// Reads dir/scene.json and loads every mesh. Throws InputError naming the file and the JSON
// path (e.g. "scene.json: materials[2].type") on unknown keys, wrong types, dangling names.
SceneIR readIR(const std::filesystem::path& dir);

// The names and paths of an IR read from disk (called by fromJsonText): scene, sensor and probe
// names are output names (core/output_names.h) and the sensors' output files are distinct;
// mesh and texture files are relative paths inside the IR folder. InputError naming `file` and
// the JSON path of the offending entry.
void validateNamesAndPaths(const SceneIR& scene, const std::string& fileForErrors);

// Serialisation of scene.json alone (meshes not touched), used by the round-trip test.
std::string toJsonText(const SceneIR& scene);
SceneIR fromJsonText(const std::string& text, const std::string& fileForErrors);

}  // namespace littoral::ir

namespace littoral {
template <> struct EnumNames<ir::Material::Type> {
    static constexpr std::string_view what = "material type";
    static constexpr EnumName<ir::Material::Type> table[] = {{ir::Material::Type::Lambertian, "lambertian"},
                                                             {ir::Material::Type::Textured, "textured"},
                                                             {ir::Material::Type::Dielectric, "dielectric"},
                                                             {ir::Material::Type::RoughDielectric, "rough-dielectric"},
                                                             {ir::Material::Type::Black, "black"},
                                                             {ir::Material::Type::Periodic, "periodic"},
                                                             {ir::Material::Type::Classified, "classified"}};
};
template <> struct EnumNames<ir::Material::Solver> {
    static constexpr std::string_view what = "radiometry solver";
    static constexpr EnumName<ir::Material::Solver> table[] = {{ir::Material::Solver::Classic, "classic"},
                                                               {ir::Material::Solver::Generic, "generic"},
                                                               {ir::Material::Solver::Fresnel, "fresnel"},
                                                               {ir::Material::Solver::SurfacePM, "surface-pm"}};
};
template <> struct EnumNames<ir::Medium::Solver> {
    static constexpr std::string_view what = "medium solver";
    static constexpr EnumName<ir::Medium::Solver> table[] = {{ir::Medium::Solver::MediumPM, "medium-pm"},
                                                               {ir::Medium::Solver::Attenuation, "attenuation"}};
};
template <> struct EnumNames<ir::Sensor::Type> {
    static constexpr std::string_view what = "sensor type";
    static constexpr EnumName<ir::Sensor::Type> table[] = {{ir::Sensor::Type::Pinhole, "pinhole"},
                                                           {ir::Sensor::Type::Orthographic, "orthographic"}};
};
template <> struct EnumNames<ir::Estimator> {
    static constexpr std::string_view what = "estimator";
    static constexpr EnumName<ir::Estimator> table[] = {{ir::Estimator::Dirsig, "dirsig"},
                                                        {ir::Estimator::Path, "path"}};
};
}  // namespace littoral
