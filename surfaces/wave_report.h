#pragma once
// The stats.json document of `littoral waves` (see docs/waves.md for every key) and a short
// human-readable summary in the layout of the dissertation's Tables 9.5 / 10.2.
#include <string>

#include <nlohmann/json.hpp>

#include "surfaces/wave_surface.h"

namespace littoral::surfaces {

// Lengths in metres, slopes dimensionless ("radians"), angles in degrees, times in seconds.
// Undefined values (NaN) are written as null.
nlohmann::json waveStatsJson(const WaveSurface& s);
std::string waveSummary(const WaveSurface& s);

}  // namespace littoral::surfaces
