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
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/spectrum.h"
#include "core/vec.h"

namespace littoral::ir {

inline constexpr int kFormatVersion = 1;

// Phase function of a scattering medium.
struct PhaseFunction {
    enum class Type { Isotropic, HenyeyGreenstein, Petzold, Rayleigh };
    Type type = Type::Isotropic;
    double g = 0.0;  // HG asymmetry parameter (mean cosine), in (-1, 1)
};

// A homogeneous medium. "air" with n = 1 and no absorption or scattering is implicit when a mesh
// side names no medium.
struct Medium {
    std::string name;
    Spectrum refractiveIndex = Spectrum::constant(1.0);
    Spectrum absorption = Spectrum::constant(0.0);  // a, m^-1
    Spectrum scattering = Spectrum::constant(0.0);  // b, m^-1
    PhaseFunction phase;
};

// How a surface interacts with light, and which radiometry solver evaluates it (Table 10.4).
struct Material {
    enum class Type {
        Lambertian,      // diffuse reflectance `reflectance`
        Textured,        // Lambertian, reflectance modulated by a texture draped in plan view
        Dielectric,      // smooth Fresnel interface between the mesh's two media
        RoughDielectric, // Cox–Munk microfacet interface (wind speed, wind azimuth)
        Black,           // absorbs everything (r = 0)
    };
    enum class Solver { Classic, Generic, Fresnel, SurfacePM };
    std::string name;
    Type type = Type::Lambertian;
    Solver solver = Solver::Classic;
    Spectrum reflectance = Spectrum::constant(0.0);
    // Textured: image path relative to the IR directory (single channel float or 8-bit; the
    // value multiplies `reflectance`), draped over the plan-view rectangle [x0, x1] x [y0, y1].
    std::string texture;
    double textureX0 = 0, textureY0 = 0, textureX1 = 1, textureY1 = 1;
    // RoughDielectric: Cox–Munk wind speed at 12.5 m (m/s) and the azimuth the wind blows toward,
    // counter-clockwise from +x (east), radians.
    double windSpeed = 0.0;
    double windAzimuth = 0.0;
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
};

// A point radiometer. Quantities: "Ed", "Eu" (plane irradiances, down/up-welling),
// "Eod", "Eou" (scalar irradiances), "Lu" (nadir-viewing upwelling radiance).
struct Probe {
    std::string name;
    Point3 position;
    std::vector<std::string> quantities;
    std::string medium;
};

struct RenderSettings {
    std::vector<Band> bands{Band{0.4, 0.6}};
    uint64_t seed = 1;
    int threads = 0;                 // 0 = all cores
    int maxBounces = 8;              // path depth limit for the Generic solver and specular chains
    int hemisphereSamples = 64;      // Generic solver sky/background samples per shading point
    int maxSpecularDepth = 16;       // specular interface events (reflection/refraction/TIR) per path
    int probeSamples = 4096;         // rays per probe quantity (hemisphere or sphere integration)
    uint64_t surfacePhotons = 0;     // photon pass sizes (0 = no photon map)
    uint64_t volumePhotons = 0;
    double surfaceSearchRadius = 0.4;  // m
    double volumeSearchRadius = 0.4;   // m
    double marchStep = 0.1;            // m, ray-march step in scattering media
};

struct SceneIR {
    std::string name = "scene";
    RenderSettings render;
    Sun sun;
    Sky sky;
    std::vector<Medium> media;
    std::vector<Material> materials;
    std::vector<Mesh> meshes;
    std::vector<Instance> instances;
    std::vector<Sensor> sensors;
    std::vector<Probe> probes;
    // Free-form provenance (generator, seed, wave statistics ...), written as strings.
    std::map<std::string, std::string> metadata;

    const Material* findMaterial(const std::string& n) const;
    const Medium* findMedium(const std::string& n) const;
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
