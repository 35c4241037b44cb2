#include "surfaces/wave_report.h"

#include <cmath>

#include <fmt/format.h>

#include "core/units.h"

namespace littoral::surfaces {

namespace {
nlohmann::json num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json measured(const SurfaceStats& s) {
    return {{"mean_height", num(s.meanHeight)},
            {"rms_height", num(s.rmsHeight)},
            {"rms_slope", num(s.rmsSlope)},
            {"rms_slope_x", num(s.rmsSlopeX)},
            {"rms_slope_y", num(s.rmsSlopeY)},
            {"rms_slope_total", num(s.rmsSlopeTotal)},
            {"correlation_length", num(s.correlationLength)},
            {"correlation_length_upwind", num(s.correlationLengthUpwind)},
            {"correlation_length_crosswind", num(s.correlationLengthCrosswind)},
            {"mss_upwind", num(s.mssUpwind)},
            {"mss_crosswind", num(s.mssCrosswind)}};
}
}  // namespace

nlohmann::json waveStatsJson(const WaveSurface& s) {
    const WaveParams& p = s.params;
    const PredictedStats& pr = s.predicted;
    nlohmann::json j;
    j["model"] = waveModelName(p.model);
    j["description"] = s.description;
    j["wind_speed"] = isWindDriven(p.model) ? nlohmann::json(p.windSpeed) : nlohmann::json(nullptr);
    // Compass direction the wind (sinusoid: the waves) comes from, degrees clockwise from north.
    j["wind_from_deg"] = isWindDriven(p.model) ? nlohmann::json(compassFromDirection(p.windDirection)) : nlohmann::json(nullptr);
    j["waves_from_deg"] = p.model == WaveModel::Sinusoid ? nlohmann::json(compassFromDirection(p.windDirection))
                                                         : nlohmann::json(nullptr);
    if (s.beaufort)
        j["beaufort"] = {{"number", s.beaufort->number},
                         {"description", s.beaufort->waves},
                         {"name", s.beaufort->name},
                         {"sea_state", s.beaufort->seaState}};
    else
        j["beaufort"] = nullptr;
    j["grid"] = {{"nx", s.field.nx - 1}, {"ny", s.field.ny - 1},
                 {"spacing_x", s.spacingX}, {"spacing_y", s.spacingY},
                 {"x0", s.field.x0}, {"y0", s.field.y0}, {"x1", s.field.x1}, {"y1", s.field.y1},
                 {"periodic", s.field.periodic}, {"seed", p.seed}};
    j["predicted"] = {{"rms_height", num(pr.rmsHeight)},
                      {"rms_slope", num(pr.rmsSlope)},
                      {"correlation_length", num(pr.correlationLength)},
                      {"significant_wave_height", num(pr.significantWaveHeight)},
                      {"peak_wavelength", num(pr.peakWavelength)},
                      {"mss_upwind", num(pr.mssUpwind)},
                      {"mss_crosswind", num(pr.mssCrosswind)},
                      {"mss_upwind_resolved", num(pr.mssUpwindResolved)},
                      {"mss_crosswind_resolved", num(pr.mssCrosswindResolved)},
                      {"cox_munk", {{"sea", isWindDriven(p.model) ? nlohmann::json(std::string(nameOf(pr.coxMunkSea)))
                                                                  : nlohmann::json(nullptr)},
                                    {"mss_upwind", num(pr.coxMunkUpwind)},
                                    {"mss_crosswind", num(pr.coxMunkCrosswind)},
                                    {"mss_total", num(pr.coxMunkTotal)}}},
                      {"expected_on_grid", {{"rms_height", num(pr.expectedRmsHeight)},
                                            {"rms_slope", num(pr.expectedRmsSlope)},
                                            {"correlation_length", num(pr.expectedCorrelationLength)}}}};
    j["actual"] = measured(s.actual);
    j["grid_measured"] = measured(s.grid);
    j["mesh"] = {{"triangles", s.mesh.numTriangles()},
                 {"vertices", s.mesh.numVertices()},
                 {"target_triangles", p.triangles},
                 {"max_deviation", s.meshMaxDeviation}};
    j["timing_s"] = {{"synthesis", s.seconds.synthesis},
                     {"facetization", s.seconds.facetization},
                     {"statistics", s.seconds.statistics}};
    return j;
}

std::string waveSummary(const WaveSurface& s) {
    const PredictedStats& pr = s.predicted;
    std::string out = s.description + "\n";
    if (s.beaufort)
        out += fmt::format("Beaufort force {} ({}): {}\n", s.beaufort->number, s.beaufort->name, s.beaufort->waves);
    out += fmt::format("grid {} x {} at {:.4g} m, {} triangles / {} vertices after facetization (max deviation {:.3g} m)\n",
                       s.field.nx - 1, s.field.ny - 1, s.spacingX, s.mesh.numTriangles(), s.mesh.numVertices(),
                       s.meshMaxDeviation);
    out += fmt::format("{:<24}{:>12}{:>12}{:>12}\n", "", "predicted", "grid", "mesh");
    out += fmt::format("{:<24}{:>12.4g}{:>12.4g}{:>12.4g}\n", "RMS height (m)", pr.rmsHeight, s.grid.rmsHeight, s.actual.rmsHeight);
    out += fmt::format("{:<24}{:>12.4g}{:>12.4g}{:>12.4g}\n", "RMS slope (per axis)", pr.rmsSlope, s.grid.rmsSlope, s.actual.rmsSlope);
    out += fmt::format("{:<24}{:>12.4g}{:>12.4g}{:>12.4g}\n", "correlation length (m)", pr.correlationLength,
                       s.grid.correlationLength, s.actual.correlationLength);
    out += fmt::format("{:<24}{:>12.4g}{:>12.4g}{:>12.4g}\n", "mss upwind", pr.mssUpwindResolved, s.grid.mssUpwind, s.actual.mssUpwind);
    out += fmt::format("{:<24}{:>12.4g}{:>12.4g}{:>12.4g}\n", "mss crosswind", pr.mssCrosswindResolved, s.grid.mssCrosswind,
                       s.actual.mssCrosswind);
    if (s.beaufort)
        out += fmt::format("Cox-Munk (1954, {} sea) mss: upwind {:.4g}, crosswind {:.4g}, total {:.4g}\n",
                           nameOf(pr.coxMunkSea), pr.coxMunkUpwind, pr.coxMunkCrosswind, pr.coxMunkTotal);
    return out;
}

}  // namespace littoral::surfaces
