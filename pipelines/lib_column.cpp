#include "pipelines/lib_column.h"

#include <chrono>
#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/cox_munk_fit.h"
#include "core/error.h"
#include "core/units.h"
#include "pipelines/lib_plot.h"
#include "scenegen/assembly_sections.h"
#include "scenegen/surface_section.h"

namespace littoral::pipelines {

namespace fs = std::filesystem;

namespace {

// The surface must be flat: a wave mesh is not horizontally homogeneous. A Cox-Munk roughness is
// taken in its isotropic form (slopes: isotropic), with Smith's light-side normalisation (each ray
// meets one facet; shadowing: smith-light, the default; docs/column.md); the result is
// the total mean-square slope, 0 for a flat surface.
double checkSurface(const scenegen::SceneSpec& spec, std::vector<std::string>* notes) {
    if (!spec.waterSurface) return 0.0;  // the default: flat
    const scenegen::YamlNode& s = *spec.waterSurface;
    const surfaces::WaveParams w = scenegen::parseWaterSurface(s);
    if (w.model != surfaces::WaveModel::Flat)
        (s.has("model") ? s["model"] : s)
            .fail(fmt::format("littoral column needs a flat surface (model: flat); model {} makes a wave mesh, which is "
                              "not horizontally homogeneous", surfaces::waveModelName(w.model)));
    const auto rough = scenegen::parseSurfaceRoughness(s, w, "interface");
    if (!rough) return 0.0;
    const scenegen::YamlNode r = s["roughness"];
    if (rough->slopes != CoxMunkSlopes::Isotropic)
        (r.has("slopes") ? r["slopes"] : r)
            .fail("littoral column solves the isotropic Cox-Munk surface only: give slopes: isotropic (sigma^2 = 0.003 + "
                  "0.00512 U); the anisotropic upwind/crosswind distribution couples the azimuthal Fourier modes, which "
                  "the column solves one at a time (use littoral run for it)");
    if (rough->shadowing != MicrofacetShadowing::SmithLight)
        r["shadowing"].fail(fmt::format("littoral column's rough surface is Smith's light-side normalisation (each ray meets "
                                        "one facet, reflectance + transmittance = 1, docs/column.md), not shadowing: {}; "
                                        "remove 'shadowing' or give shadowing: smith-light",
                                        nameOf(rough->shadowing)));
    notes->push_back(fmt::format("rough surface: isotropic Cox-Munk slopes, U = {} m/s, sigma^2 = {:.5f}; wind direction "
                                 "ignored (isotropic)", rough->windSpeed, coxMunkCleanTotalMss(rough->windSpeed)));
    return coxMunkCleanTotalMss(rough->windSpeed);
}

// No bottom (infinitely deep), or a flat planar_slope of a lambertian or black material.
column::IrBottom checkBottom(const scenegen::SceneSpec& spec) {
    column::IrBottom b;
    if (!spec.bathymetry) return b;
    const scenegen::YamlNode& n = *spec.bathymetry;
    const scenegen::BathymetrySpec bs = scenegen::parseBathymetry(n);
    if (bs.kind != scenegen::BathymetrySpec::Kind::PlanarSlope)
        n["type"].fail("littoral column needs a horizontal bottom: bathymetry type planar_slope with zero slopes (or no "
                       "bathymetry: infinitely deep)");
    for (const char* k : {"slope_x", "slope_y"})
        if (n.has(k) && n[k].asDouble() != 0.0)
            n[k].fail("littoral column needs a horizontal bottom: a sloped seabed is not a plane-parallel column");
    const double depth = spec.waterLevel - bs.planar.z0;
    if (!(depth > 0)) n.fail(fmt::format("the bottom at z = {} m is not below the water level {} m", bs.planar.z0, spec.waterLevel));
    b.depth = depth;
    for (const auto& m : spec.materials)
        if (m.name == bs.material) {
            if (m.type == "black") return b;
            if (m.type != "lambertian")
                throw InputError(m.loc, fmt::format("material '{}': littoral column takes a lambertian or black bottom, "
                                                    "not {}", m.name, m.type));
            b.reflectance = m.reflectance;
            return b;
        }
    n.fail(fmt::format("bathymetry material '{}' is not defined under materials", bs.material));
}

void checkColumnScene(const scenegen::SceneSpec& spec, std::vector<std::string>* notes) {
    const SourceLoc at{spec.file.string()};
    if (!spec.hasWater) throw InputError(at, "littoral column needs a water section");
    if (!spec.periodic)
        throw InputError(spec.waterOptics.loc.file.empty() ? at : spec.waterOptics.loc,
                         "littoral column treats the water as horizontally unbounded; say so with water.horizontal: "
                         "periodic (a bounded basin is a 3-D scene: use littoral run)");
    if (spec.objects) spec.objects->fail("littoral column cannot place objects: they break horizontal homogeneity");
    if (spec.textureClasses)
        spec.textureClasses->fail("littoral column takes one bottom material; texture classes vary it horizontally");
    if (!spec.sensors.empty())
        notes->push_back(fmt::format("{} sensor(s) ignored: the column writes profiles and radiance tables, not images",
                                     spec.sensors.size()));
    if (spec.sun.enabled)
        notes->push_back("the sun is a point source (its angular diameter is ignored)");
    if (!spec.waterOptics.solver.empty())
        notes->push_back(fmt::format("water.optics.solver {} ignored (a renderer setting)", spec.waterOptics.solver));
    notes->push_back("render settings other than bands (estimator, samples, seed, threads) are the renderer's and ignored");
}

std::vector<double> columnDepths(const scenegen::SceneSpec& spec, const ColumnOptions& o, const column::IrBottom& bottom,
                                 std::vector<std::string>* notes) {
    std::vector<double> z = o.depths;
    if (z.empty()) {
        const double zmax = bottom.depth ? std::min(*bottom.depth, o.maxDepth) : o.maxDepth;
        for (int i = 0; i * o.step <= zmax + 1e-9; ++i) z.push_back(i * o.step);
        if (bottom.depth && *bottom.depth <= o.maxDepth) z.push_back(*bottom.depth);
    }
    for (const double t : spec.waterOptics.layerTops) z.push_back(t);
    for (const auto& p : spec.probes) {
        const double d = spec.waterLevel - p.position.z;
        if (d < 0) {
            notes->push_back(fmt::format("probe '{}' is above the water: ignored", p.name));
            continue;
        }
        if (bottom.depth && d > *bottom.depth) throw InputError(p.loc, fmt::format("probe '{}' lies below the bottom", p.name));
        z.push_back(d);
    }
    for (double d : z)
        if (bottom.depth && d > *bottom.depth + 1e-9)
            throw InputError(fmt::format("--depths: {} m lies below the bottom at {} m", d, *bottom.depth));
    std::sort(z.begin(), z.end());
    std::vector<double> u;
    for (double d : z)
        if (u.empty() || d > u.back() + 1e-9) u.push_back(d);
    return u;
}

}  // namespace

ColumnScene columnScene(const scenegen::SceneSpec& spec, const ColumnOptions& o) {
    ColumnScene cs;
    cs.name = spec.scene.name;
    checkColumnScene(spec, &cs.notes);
    const double mss = checkSurface(spec, &cs.notes);
    const column::IrBottom bottom = checkBottom(spec);
    ir::SceneIR ir;
    scenegen::applyCommonSections(spec, &ir);
    cs.depths = columnDepths(spec, o, bottom, &cs.notes);
    if (!ir.render.responseBands.empty())
        throw InputError(SourceLoc{spec.file.string()},
                         "render.bands: the column solver reads rectangular bands [lo, hi] only; a band with a spectral "
                         "response (centre_um and fwhm_um, or response) is for run and render");
    for (size_t b = 0; b < ir.render.bands.size(); ++b) {
        try {
            cs.bands.push_back(column::columnBandFromIr(ir, spec.waterLevel, bottom, static_cast<int>(b)));
            cs.bands.back().surfaceMeanSquareSlope = mss;
        } catch (const InputError& e) {
            if (!e.where().file.empty()) throw;
            throw InputError(SourceLoc{spec.file.string()}, e.message());
        }
    }
    return cs;
}

namespace {

std::string profilesCsv(const std::vector<column::ColumnResult>& results) {
    std::string s = "band_lo_um,band_hi_um,depth_m,Ed,Eu,Eod,Eou,Lu,Ed_direct,Kd_per_m,Ku_per_m\n";
    for (const auto& r : results)
        for (const auto& d : r.depths)
            s += fmt::format("{},{},{},{:.8e},{:.8e},{:.8e},{:.8e},{:.8e},{:.8e},{:.6g},{:.6g}\n", r.band.lo, r.band.hi, d.depth,
                             d.Ed, d.Eu, d.Eod, d.Eou, d.Lu, d.EdDirect, d.Kd, d.Ku);
    return s;
}

std::string radianceCsv(const std::vector<column::ColumnResult>& results) {
    std::string s = "band_lo_um,band_hi_um,depth_m,travel,theta_deg,phi_deg,radiance\n";
    for (const auto& r : results) {
        const int n = r.streams.size();
        for (const auto& d : r.depths)
            for (size_t row = 0; row < d.radiance.size(); ++row) {
                const bool up = static_cast<int>(row) >= n;
                const double theta = rad2deg(std::acos(r.streams.mu[row % static_cast<size_t>(n)]));
                for (size_t a = 0; a < r.azimuthsDeg.size(); ++a)
                    s += fmt::format("{},{},{},{},{:.6f},{:g},{:.8e}\n", r.band.lo, r.band.hi, d.depth, up ? "up" : "down",
                                     theta, r.azimuthsDeg[a], d.radiance[row][a]);
            }
    }
    return s;
}

nlohmann::json profilesJson(const ColumnScene& cs, const std::vector<column::ColumnResult>& results, const ColumnOptions& o) {
    nlohmann::json j;
    j["scene"] = cs.name;
    j["solver"] = {{"method", "discrete ordinates, adding-doubling, delta-M + TMS"},
                   {"streams_per_half", o.streams},
                   {"directions_per_hemisphere", results.empty() ? 0 : results[0].streams.size()},
                   {"legendre_order", 2 * o.streams}};
    j["notes"] = cs.notes;
    j["bands"] = nlohmann::json::array();
    for (const auto& r : results) {
        nlohmann::json b = {{"band_um", {r.band.lo, r.band.hi}},
                            {"sun_zenith_in_water_deg", rad2deg(r.sunZenithWater)},
                            {"Ed_above", r.EdAbove},
                            {"Lw_nadir", r.LwNadir},
                            {"Rrs_per_sr", r.Rrs}};
        b["depths"] = nlohmann::json::array();
        for (const auto& d : r.depths)
            b["depths"].push_back({{"depth_m", d.depth}, {"Ed", d.Ed}, {"Eu", d.Eu}, {"Eod", d.Eod}, {"Eou", d.Eou},
                                   {"Lu", d.Lu}, {"Ed_direct", d.EdDirect}, {"Kd_per_m", d.Kd}, {"Ku_per_m", d.Ku}});
        j["bands"].push_back(b);
    }
    return j;
}

Chart profilesChart(const std::vector<column::ColumnResult>& results) {
    PlotSpec p = plotSpec("Irradiance profiles (littoral column)", "irradiance, W m^-2 um^-1", "depth, m", true, false);
    p.invertY = true;
    for (const auto& r : results)
        for (const char* q : {"Ed", "Eu", "Eod", "Eou"}) {
            PlotSeries s = plotSeries(fmt::format("{} {:g}-{:g} um", q, r.band.lo, r.band.hi));
            s.markers = false;
            s.dashed = q[1] == 'o';
            for (const auto& d : r.depths) {
                s.y.push_back(d.depth);
                s.x.push_back(q == std::string("Ed") ? d.Ed : q == std::string("Eu") ? d.Eu : q == std::string("Eod") ? d.Eod : d.Eou);
            }
            p.series.push_back(std::move(s));
        }
    return {"profiles.png", p};
}

std::string summary(const std::vector<column::ColumnResult>& results, const ColumnScene& cs) {
    std::string s;
    for (const auto& r : results) {
        s += fmt::format("band {:g}-{:g} um: Ed(0+) {:.5e}  Rrs {:.5e} sr^-1  (sun {:.2f} deg in water)\n", r.band.lo,
                         r.band.hi, r.EdAbove, r.Rrs, rad2deg(r.sunZenithWater));
        s += fmt::format("  {:>8} {:>12} {:>12} {:>12} {:>12} {:>12} {:>9}\n", "depth_m", "Ed", "Eu", "Eod", "Eou", "Lu", "Kd");
        for (const auto& d : r.depths)
            s += fmt::format("  {:8.3f} {:12.5e} {:12.5e} {:12.5e} {:12.5e} {:12.5e} {:9.4f}\n", d.depth, d.Ed, d.Eu, d.Eod,
                             d.Eou, d.Lu, d.Kd);
    }
    for (const auto& n : cs.notes) s += "note: " + n + "\n";
    return s;
}

}  // namespace

std::string runColumn(const ColumnOptions& o) {
    const scenegen::SceneSpec spec = scenegen::loadSceneFile(o.scene);
    const ColumnScene cs = columnScene(spec, o);
    checkOutputFolder(o.out, "--out");
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<column::ColumnResult> results;
    column::SolverOptions so;
    so.streamsPerHalf = o.streams;
    so.azimuths = o.azimuths;
    for (const auto& b : cs.bands) results.push_back(column::solveColumn(b, cs.depths, so));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const OutputFolderLock lock(o.out);
    const fs::path out(o.out);
    writeTextFileAtomic(out / "profiles.csv", profilesCsv(results));
    writeTextFileAtomic(out / "profiles.json", profilesJson(cs, results, o).dump(2) + "\n");
    writeTextFileAtomic(out / "radiance.csv", radianceCsv(results));
    const std::string why = drawCharts(out, {profilesChart(results)});
    std::string s = summary(results, cs);
    if (!why.empty()) s += "warning: " + why + "\n";
    s += fmt::format("solved {} band(s) at {} depth(s) in {:.3f} s\n", results.size(), cs.depths.size(), seconds);
    for (const char* f : {"profiles.csv", "profiles.json", "radiance.csv", "profiles.png"}) s += fmt::format("  {}\n", (out / f).string());
    return s;
}

}  // namespace littoral::pipelines
