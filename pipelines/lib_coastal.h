#pragma once
// The dissertation's coastal simulations A-J (Table 10.1, spec/seed-ch05-10.md §3) as named runs
// of the synthetic coastal site: `littoral coastal A --out DIR`.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "render/image_output.h"

namespace littoral::pipelines {

// One row of Table 10.1 with the image size Littoral gives it (the table states none).
struct CoastalConfiguration {
    char id;
    const char* description;
    double sunZenithDeg;      // sun azimuth 315 deg in every row
    double sensorElevationDeg, sensorAzimuthDeg, rangeM, gsdM;
    const char* water;        // `low`, `moderate`, `high`: the Table 10.3 presets (HG g = 0.88)
    double windSpeed;         // m/s (Table 10.2 surfaces)
    int width, height;        // pixels
    bool atDeepestTarget;     // the view's axis passes through the deepest step target (H)
};
const std::vector<CoastalConfiguration>& coastalConfigurations();
// The configuration with this letter (case-insensitive); InputError listing A-J otherwise.
const CoastalConfiguration& coastalConfiguration(const std::string& id);

// A demonstration of the dissertation's Section 10.4 as a named run of `littoral coastal`: its
// scene file (data_synthetic/<scene>.yaml, built in) and the box mesh it floats.
struct CoastalDemonstration {
    const char* name;           // "cube", "shadows"
    const char* description;
    const char* scene;          // built-in scene (pipelines/lib_embedded.h)
    const char* meshReference;  // the mesh path in that scene file, replaced by the written box
    double sizeX, sizeY, height;
};
// The demonstration of this name, or nullptr.
const CoastalDemonstration* coastalDemonstration(const std::string& name);

struct CoastalOptions {
    std::string configuration;  // A-J, or a demonstration's name
    std::string out;
    bool full = false;          // the dissertation's 50 M + 70 M photons; else quick settings
    uint64_t seed = 2010;
    bool seedGiven = false;     // --seed on the command line (refused with a demonstration)
    int threads = 0;
    bool progress = true;
    render::PreviewOptions preview = [] {
        render::PreviewOptions p;
        p.blurSigma = render::kDissertationBlurSigma;  // gamma 0.65, then the Gaussian kernel
        return p;
    }();
};

// The render section of a configuration's scene at quick or full settings, with or without the
// photon maps.
std::string coastalRenderSection(bool full, bool photonMaps);

// Writes the synthetic site configured as options.configuration (with or without photon maps)
// into dir; returns its scene file.
std::filesystem::path writeCoastalSite(const CoastalOptions& options, const std::filesystem::path& dir, bool photonMaps);

// InputError, before anything is written, for a name that is neither A-J nor a demonstration, and
// for --full with a demonstration (it has one setting).
void checkCoastalName(const CoastalOptions& options);

// Writes the site configured as `configuration` into out/site and runs it into out (a
// demonstration: its scene file and mesh into out/scene, then runs it into out). H is
// rendered twice, as in Fig. 10.7: with photon maps into out/photon-maps and without (Classic
// solvers, scattering counted as loss) into out/no-photon-maps. Returns the runs' summaries.
std::string runCoastal(const CoastalOptions& options);

}  // namespace littoral::pipelines
