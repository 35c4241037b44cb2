#pragma once
// The synthetic coastal site of the dissertation's Ch. 10 scene (spec/seed-ch05-10.md §3.1),
// about 90 m x 60 m: a beach and berm on the west, a Dean-profile seabed with a longshore sandbar,
// a six-class classification map (dry sand, wet sand, grass, trees, concrete, submerged
// vegetation) with per-class textures, a cement pier (lower right of the north-up image is the
// south; the pier runs offshore along the south side), a small boat (upper left: north, near
// shore), a buoy, and four bright/dark step targets, each 0.75 m deeper than the last.
//
// Everything random (vegetation and tree patches, texture noise, target jitter) comes from
// RandomStream(seed, ...), so the same seed writes byte-identical files.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace littoral::scenegen {

// What a configuration of the site changes in the written scene file (littoral coastal, Table 10.1);
// the defaults write the demo's scene.
struct SiteScene {
    double sunZenithDeg = 30, sunAzimuthDeg = 315;
    double windSpeed = 6.0;  // m/s, the Beaufort surface (Table 10.2: 6 or 10)
    std::string sensors;     // the whole `sensors:` section; empty = simulation C's nadir view
    bool probe = true;       // the Ed/Eu probe 1 m under the water 20 m offshore
    std::string optics;      // the `water.optics` entries, indented 4 spaces; empty = the constituents mix
    // false: the dissertation's non-photon-mapped rendering (Fig. 10.7): the SurfacePM classes and
    // materials take the Classic solver and the water counts scattering as loss (`attenuation`).
    bool photonMaps = true;
    std::string render;  // the whole `render:` section; empty = the demo's
};

struct SiteOptions {
    uint64_t seed = 2010;
    SiteScene scene;
    size_t surfaceTriangles = 30000;  // water.surface.triangles in the written scene
    double mapResolution = 0.25;      // m per classification pixel
};

struct SiteSummary {
    std::filesystem::path sceneFile;
    std::vector<std::filesystem::path> files;  // everything written
    std::vector<double> targetTopDepths;       // m below still water, shallow to deep
    uintmax_t totalBytes = 0;
};

struct SiteTarget {
    double x = 0, y = 0, topDepth = 0;  // centre of the top (the bright/dark edge), m below still water
};
// Where writeSyntheticSite places the step targets for this seed, shallow to deep.
std::vector<SiteTarget> siteTargets(uint64_t seed);

// Writes dir/scene.yaml, dir/classes.png, dir/textures/*.png, dir/objects/*.ply.
SiteSummary writeSyntheticSite(const std::filesystem::path& dir, const SiteOptions& options = {});

// The object files on their own (barge, boat, buoy, pier, step target, cube), for data_synthetic/objects.
std::vector<std::filesystem::path> writeObjectLibrary(const std::filesystem::path& dir);

}  // namespace littoral::scenegen
