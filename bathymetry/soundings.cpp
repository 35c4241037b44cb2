// Soundings -> local frame -> TIN (tin.cpp). The CSV reader is in soundings_csv.cpp.
#include <cmath>
#include <fstream>

#include <fmt/format.h>

#include "bathymetry/geo_frame.h"
#include "bathymetry/tin_build.h"
#include "core/error.h"

namespace littoral::bathymetry {

std::unique_ptr<Terrain> fromSoundings(const std::vector<Sounding>& soundings, const GeoFrame& frame,
                                       const SoundingsOptions& options, const std::string& sourceName) {
    detail::TinInput in;
    in.points.reserve(soundings.size());
    in.labels.reserve(soundings.size());
    const std::string src = sourceName.empty() ? "soundings" : sourceName;
    for (size_t i = 0; i < soundings.size(); ++i) {
        const Sounding& s = soundings[i];
        const std::string label = s.line > 0 ? fmt::format("{}:{}", src, s.line) : fmt::format("sounding {}", i + 1);
        if (!std::isfinite(s.depth)) throw InputError(fmt::format("{}: depth {} is not finite", label, s.depth));
        Point3 p;
        try {
            // Plan position at the frame's origin height; elevation from the depth, so z = 0 is the
            // still-water level whatever the frame (see terrain.h).
            p = frame.toLocal(s.latDeg, s.lonDeg, frame.origin().h);
        } catch (const InputError& e) {
            throw InputError(fmt::format("{}: {}", label, e.message()));
        }
        p.z = -s.depth;
        in.points.push_back(p);
        in.labels.push_back(label);
    }
    for (size_t c = 0; c < options.shorelines.size(); ++c) {
        std::vector<Point3> line;
        for (size_t k = 0; k < options.shorelines[c].size(); ++k) {
            const auto& v = options.shorelines[c][k];
            Point3 p;
            try {
                p = frame.toLocal(v.latDeg, v.lonDeg, frame.origin().h);
            } catch (const InputError& e) {
                throw InputError(fmt::format("shoreline {} vertex {}: {}", c + 1, k + 1, e.message()));
            }
            p.z = options.constraintZ;
            line.push_back(p);
        }
        in.constraints.push_back(std::move(line));
    }
    if (!std::isfinite(options.constraintZ))
        throw InputError(fmt::format("soundings.constraint_z = {}: must be a finite number", options.constraintZ));
    in.outside = options.outside;
    in.mergeDistance = options.mergeDistance;
    in.sourceName = src;
    return detail::buildTin(std::move(in));
}

std::unique_ptr<Terrain> fromSoundings(const std::filesystem::path& csv, const GeoFrame& frame,
                                       const SoundingsOptions& options) {
    return fromSoundings(readSoundingsCsv(csv), frame, options, csv.string());
}

}  // namespace littoral::bathymetry
