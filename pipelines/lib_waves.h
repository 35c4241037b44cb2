#pragma once
// The `waves` command's options and their conversion to surfaces::WaveParams, shared by the
// command (pipelines/cmd_waves.cpp) and the Python module (python/), so that both take the same
// settings with the same checks and messages (named as the command's options).
#include <cstdint>
#include <optional>
#include <string>

#include "surfaces/wave_surface.h"

namespace littoral::pipelines {

struct WavesOptions {
    std::optional<double> wind;
    std::optional<double> windFromDeg, wavesFromDeg;
    std::optional<std::string> removedDirection;  // --direction: refused with an explanation
    std::optional<std::string> sea;
    std::string model = "beaufort";
    double size = 300.0;
    std::optional<double> sizeY;
    double spacing = 0.25;
    uint64_t seed = 500;
    std::optional<long long> triangles;  // default: surfaces::defaultTriangles
    std::string out;
    std::string stats;
    double fetch = 0.0, gamma = 3.3, amplitude = 0.5, wavelength = 2.0, phase = 0.0, time = 0.0, depth = 0.0;
};


// The wave parameters of the options; InputError naming the option for an unknown model or sea,
// a missing --wind, a direction option the model does not take, or an out-of-range direction.
surfaces::WaveParams toParams(const WavesOptions& o);

}  // namespace littoral::pipelines
