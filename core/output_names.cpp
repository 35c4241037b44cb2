#include "core/output_names.h"

#include <algorithm>
#include <cctype>
#include <map>

#include <fmt/format.h>

namespace littoral {

namespace {

bool portable(unsigned char c) { return std::isalnum(c) || c == '.' || c == '_' || c == '-'; }

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

// Windows device names, reserved with any extension ("nul.exr" is the NUL device there).
bool reservedDeviceName(std::string_view name) {
    std::string stem = lower(name.substr(0, name.find('.')));
    static const char* kNames[] = {"con", "prn", "aux", "nul"};
    for (const char* n : kNames)
        if (stem == n) return true;
    if (stem.size() == 4 && (stem.rfind("com", 0) == 0 || stem.rfind("lpt", 0) == 0) && stem[3] >= '1' && stem[3] <= '9')
        return true;
    return false;
}

}  // namespace

std::string printableName(std::string_view name) {
    std::string s;
    for (size_t i = 0; i < name.size() && s.size() < 80; ++i) {
        const unsigned char c = static_cast<unsigned char>(name[i]);
        if (c < 0x20 || c >= 0x7f || c == '\\') s += fmt::format("\\x{:02x}", c);
        else s += static_cast<char>(c);
    }
    if (s.size() >= 80) s += "...";
    return s;
}

std::string outputNameProblem(std::string_view name) {
    if (name.empty()) return "must not be empty";
    if (name.size() > kMaxOutputNameLength)
        return fmt::format("is {} characters long; at most {} are allowed", name.size(), kMaxOutputNameLength);
    for (size_t i = 0; i < name.size(); ++i) {
        const unsigned char c = static_cast<unsigned char>(name[i]);
        if (portable(c)) continue;
        std::string what;
        if (c == '/' || c == '\\') what = "a path separator";
        else if (c == 0) what = "a NUL byte";
        else if (c < 0x20 || c == 0x7f) what = fmt::format("the control character \\x{:02x}", c);
        else if (c >= 0x80) what = fmt::format("the non-ASCII byte \\x{:02x}", c);
        else if (c == ' ') what = "a space";
        else what = fmt::format("the character '{}'", static_cast<char>(c));
        return fmt::format("contains {} at position {}; names become file names, so only letters, digits, '.', '_' "
                           "and '-' are allowed",
                           what, i + 1);
    }
    if (name == "." || name == "..") return "is a relative folder reference, not a name";
    if (name[0] == '.') return "must not start with '.' (a hidden file, or a step out of the output folder)";
    if (name[0] == '-') return "must not start with '-' (it would read as an option)";
    if (reservedDeviceName(name)) return "is a reserved device name on Windows (CON, PRN, AUX, NUL, COM1-9, LPT1-9)";
    return "";
}

void checkOutputName(std::string_view name, std::string_view what, const SourceLoc& where) {
    const std::string problem = outputNameProblem(name);
    if (!problem.empty())
        throw InputError(where, fmt::format("{} name '{}' {}", what, printableName(name), problem));
}

std::vector<std::string> sensorOutputFiles(std::string_view sensor) {
    const std::string s(sensor);
    return {s + ".exr", s + ".img", s + ".hdr", s + ".png", s + "_truth.exr", s + "_material.png", s + "_rgb.png",
            s + "_legend.csv", s + "_psf.exr", s + "_noisy.exr", s + "_detector.json",
            s + "_geo.img", s + "_geo.hdr",
            // Water-leaving products (sensor water_products; render/water_products.cpp).
            s + "_water_leaving.img", s + "_water_leaving.hdr", s + "_sky_reflected.img", s + "_sky_reflected.hdr",
            s + "_glint.img", s + "_glint.hdr", s + "_other.img", s + "_other.hdr", s + "_ed0.img", s + "_ed0.hdr",
            s + "_rrs.img", s + "_rrs.hdr",
            // The radiance as a GeoTIFF (scenes with scene.origin; pipelines/lib_geotiff.cpp).
            s + ".tif",
            // The standard error of the radiance (samples_per_pixel >= 2; render/render_job.cpp).
            s + "_stderr.img", s + "_stderr.hdr"};
}

std::vector<std::string> probeOutputFiles() { return {"probes.csv", "probes.json", "kd.csv"}; }

std::optional<OutputClash> findOutputClash(const std::vector<std::string>& sensors, bool withProbes) {
    std::map<std::string, size_t> owner;  // lower-cased file name -> sensor index
    if (withProbes)
        for (const auto& f : probeOutputFiles()) owner[lower(f)] = SIZE_MAX;
    for (size_t i = 0; i < sensors.size(); ++i)
        for (const auto& f : sensorOutputFiles(sensors[i])) {
            auto [it, inserted] = owner.emplace(lower(f), i);
            if (inserted) continue;
            if (it->second == SIZE_MAX) return OutputClash{i, i, f};
            if (it->second != i) return OutputClash{it->second, i, f};
        }
    return std::nullopt;
}

}  // namespace littoral
