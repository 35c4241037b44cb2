#include "pipelines/lib_validate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <tuple>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "column/column_solver.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/units.h"
#include "pipelines/lib_column.h"
#include "pipelines/lib_embedded.h"
#include "pipelines/lib_plot.h"
#include "pipelines/lib_scene.h"
#include "pipelines/reference/gordon_ding.h"
#include "pipelines/reference/mobley1993.h"
#include "scenegen/scene_file.h"
#include "scenegen/yaml_reader.h"

namespace littoral::pipelines {

namespace fs = std::filesystem;
namespace m93 = reference::mobley1993;
namespace gd = reference::gordon_ding;

namespace {

// One comparison: a measured value (with its standard error, 0 for a deterministic solver)
// against a reference, passing when |measured - reference| <= tolerance (absolute, same units).
struct Check {
    std::string label;
    std::string series;  // what the case's chart groups it under ("Ed"), and where on its x axis
    double x = NAN;
    double measured = 0, stderr_ = 0, reference = 0, tolerance = 0;
    std::string why;  // how the tolerance was derived
    // Within: |measured - reference| <= tolerance. AtLeast / AtMost: measured exceeds / stays
    // below the reference by at least the tolerance (a margin, e.g. 2 standard errors).
    enum class Bound { Within, AtLeast, AtMost } bound = Bound::Within;
    bool pass() const {
        if (!std::isfinite(measured)) return false;
        switch (bound) {
            case Bound::AtLeast: return measured - tolerance >= reference;
            case Bound::AtMost: return measured + tolerance <= reference;
            case Bound::Within: break;
        }
        return std::abs(measured - reference) <= tolerance;
    }
    const char* relation() const { return bound == Bound::AtLeast ? ">=" : bound == Bound::AtMost ? "<=" : "="; }
};

struct CaseResult {
    std::vector<Check> checks;
    std::vector<Chart> charts;
    std::vector<std::string> notes;
};

struct ProbeCell {
    double value = NAN, stderr_ = NAN;
};
using ProbeTable = std::map<std::string, std::map<std::string, ProbeCell>>;  // probe -> quantity -> band 0

struct Context {
    fs::path root;  // OUT/cases
    bool quick = false;
    int threads = 0;
    std::map<std::string, ProbeTable> runs;  // memo: scene name -> probes
};

struct Case {
    std::string name, category, title, reference;
    bool quick;          // part of --quick
    double quickCost;    // rough seconds at --quick on 2 cores (for the ETA)
    std::function<CaseResult(Context&)> run;
};

// The built-in scene files of data_synthetic/: a bare name is one of mobley1993/ (Mobley et al.
// 1993), a name with a folder is taken as it is (e.g. "columns/stratified_60m").
std::string embeddedPath(const std::string& name) {
    return name.find('/') == std::string::npos ? "mobley1993/" + name : name;
}
std::string embeddedScene(const std::string& name) { return embeddedSceneText(embeddedPath(name)); }

// Writes `yaml` as OUT/cases/<run>/scene.yaml, runs it (build and render, as `littoral run`) into
// that folder and returns its probes (band 0). Memoised by run name.
const ProbeTable& runProbes(Context& c, const std::string& run, const std::string& yaml) {
    if (auto it = c.runs.find(run); it != c.runs.end()) return it->second;
    const fs::path dir = c.root / run;
    writeTextFileAtomic(dir / "scene.yaml", yaml);
    publishStagedOutputs();  // read back by the build
    RunOptions ro;
    ro.scene = (dir / "scene.yaml").string();
    ro.out = dir.string();
    ro.threads = c.threads;
    ro.progress = false;
    (void)runScene(ro);
    publishStagedOutputs();
    ProbeTable t;
    const auto j = nlohmann::json::parse(readTextFile(dir / "probes.json"));
    for (const auto& p : j["probes"])
        t[p["probe"].get<std::string>()][p["quantity"].get<std::string>()] =
            ProbeCell{p["value"][0].get<double>(), p["stderr"][0].get<double>()};
    return c.runs[run] = std::move(t);
}

// The column solver on an embedded scene at `depths` with n streams per half: {depth -> row}.
std::map<double, column::DepthResult> solveEmbedded(const std::string& scene, const std::vector<double>& depths, int streams) {
    const std::string file = "data_synthetic/" + embeddedPath(scene) + ".yaml";  // names it in messages; it reads no files
    const scenegen::SceneSpec spec = scenegen::parseScene(scenegen::YamlNode::loadString(embeddedScene(scene), file), file);
    ColumnOptions o;
    o.depths = depths;
    o.streams = streams;
    const ColumnScene cs = columnScene(spec, o);
    column::SolverOptions so;
    so.streamsPerHalf = streams;
    so.radiance = false;
    const column::ColumnResult r = column::solveColumn(cs.bands.at(0), cs.depths, so);
    std::map<double, column::DepthResult> m;
    for (const auto& d : r.depths) m[d.depth] = d;
    return m;
}

double quantityOf(const column::DepthResult& d, const std::string& q) {
    return q == "Ed" ? d.Ed : q == "Eu" ? d.Eu : q == "Eod" ? d.Eod : q == "Eou" ? d.Eou : d.Lu;
}

const m93::Cell& cellOf(const m93::Row& r, const std::string& q) { return q == "Ed" ? r.Ed : q == "Eou" ? r.Eou : r.Lu; }

// ---------------------------------------------------------------------------------------------
// Charts shared by the cases.

// Measured values with error bars and their references, against a case-chosen x (depth, say).
Chart valuesChart(const std::string& file, const std::string& title, const std::string& xLabel, const std::string& yLabel,
                  const std::vector<Check>& checks, bool logY) {
    std::map<std::string, std::vector<std::pair<double, const Check*>>> bySeries;
    for (const Check& c : checks) bySeries[c.series].push_back({c.x, &c});
    PlotSpec p = plotSpec(title, xLabel, yLabel, false, logY);
    int colour = 0;
    for (const auto& [q, pts] : bySeries) {
        PlotSeries m = plotSeries(q + " Littoral"), r = plotSeries(q + " reference");
        m.colour = r.colour = colour++;
        m.line = false;
        r.dashed = true;
        r.markers = false;
        for (const auto& [x, c] : pts) {
            m.x.push_back(x), m.y.push_back(c->measured), m.yErr.push_back(c->stderr_);
            r.x.push_back(x), r.y.push_back(c->reference);
        }
        p.series.push_back(std::move(r)), p.series.push_back(std::move(m));
    }
    return {file, p};
}

// Every check's relative difference (%) with its tolerance band: for cases with many cells.
Chart relativeChart(const std::string& file, const std::string& title, const std::vector<Check>& checks) {
    PlotSpec p = plotSpec(title, "check (in the order of the table below)", "(measured - reference) / reference, %");
    PlotSeries d = plotSeries("measured, +-1 standard error"), hi = plotSeries("+ tolerance"), lo = plotSeries("- tolerance");
    d.line = false;
    hi.dashed = lo.dashed = true;
    hi.markers = lo.markers = false;
    for (size_t i = 0; i < checks.size(); ++i) {
        const Check& c = checks[i];
        const double s = 100.0 / std::abs(c.reference);
        d.x.push_back(i + 1.0), d.y.push_back((c.measured - c.reference) * s), d.yErr.push_back(c.stderr_ * s);
        hi.x.push_back(i + 1.0), hi.y.push_back(c.tolerance * s);
        lo.x.push_back(i + 1.0), lo.y.push_back(-c.tolerance * s);
    }
    p.series = {d, hi, lo};
    return {file, p};
}

// ---------------------------------------------------------------------------------------------
// The cases' own scenes: horizontally periodic water under a flat surface over a planar floor.

struct FlatScene {
    std::string comment, name;
    double halfX = 5, halfY = 5;                 // domain [-halfX, halfX] x [-halfY, halfY], m
    double sunZenith = 0, sunAzimuth = 0, sunDiameter = 0.01, sunIrradiance = 1, skyRadiance = 0;
    std::string optics;                          // the water.optics flow map
    double floorDepth = 10, floorSpacing = 5;    // m
    std::string floorMaterial = "{name: floor, type: black}";
    std::string otherMaterials, objects, probes;  // YAML list items, each "  - {...}\n"
    std::string render = "{bands: [[0.5, 0.51]], estimator: path, probe_batches: 16}";
};

std::string flatSceneYaml(const FlatScene& f) {
    std::string s = fmt::format("# littoral validate: {}\nscene: {{name: {}, domain: {{x: [{:g}, {:g}], y: [{:g}, {:g}]}}}}\n",
                                f.comment, f.name, -f.halfX, f.halfX, -f.halfY, f.halfY);
    s += fmt::format("sun: {{zenith_deg: {:g}, azimuth_deg: {:g}, angular_diameter_deg: {:g}, irradiance: {:.6f}}}\n", f.sunZenith,
                     f.sunAzimuth, f.sunDiameter, f.sunIrradiance);
    s += fmt::format("sky: {{radiance: {:.6f}}}\n", f.skyRadiance);
    s += "water:\n  level_m: 0\n  horizontal: periodic\n  surface: {model: flat}\n  optics: " + f.optics + "\n";
    const std::string floorName = f.floorMaterial.substr(7, f.floorMaterial.find(',') - 7);  // "{name: X, ..."
    s += fmt::format("bathymetry: {{type: planar_slope, z0_m: {:g}, spacing_m: {:g}, material: {}}}\n", -f.floorDepth,
                     f.floorSpacing, floorName);
    s += "materials:\n  - " + f.floorMaterial + "\n" + f.otherMaterials;
    if (!f.objects.empty()) s += "objects:\n" + f.objects;
    s += "probes:\n" + f.probes;
    if (f.render.front() == '{') return s + "render: " + f.render + "\n";
    return s + "render:\n" + f.render;
}

// ---------------------------------------------------------------------------------------------
// Analytic: the unscattered sun in purely absorbing water under a flat surface.
// Ed(z) = E cos(theta0) T(theta0) exp(-a z / cos(theta_w)) and Eod = Ed / cos(theta_w), with T the
// Fresnel transmittance of unpolarised light, from the column solver's Fresnel (column/, which
// shares no code with the renderer it checks here).

double fresnelTransmittance(double theta0, double n) { return 1 - column::fresnelReflectance(std::cos(theta0), 1.0, n); }

std::string directSunScene(double zenithDeg, double a, const std::vector<double>& depths, int samples) {
    FlatScene f;
    f.comment = "the direct sun in purely absorbing water (Beer-Lambert through a flat surface).";
    f.name = "validate-direct-sun";
    f.sunZenith = zenithDeg;
    f.optics = fmt::format("{{refractive_index: 1.34, absorption_per_m: {:g}, scattering_per_m: 0}}", a);
    f.floorDepth = 12;
    for (double z : depths)
        f.probes += fmt::format("  - {{name: z{:g}, position: [0, 0, {:g}], quantities: [Ed, Eod], samples: {}}}\n", z, -z, samples);
    f.render = "{bands: [[0.5, 0.51]], estimator: path, probe_batches: 10}";
    return flatSceneYaml(f);
}

CaseResult directSunCase(Context& c) {
    const double zenith = 40, a = 0.4, n = 1.34;
    const std::vector<double> depths = {0.5, 2, 4, 8};
    const ProbeTable& t = runProbes(c, "direct-sun", directSunScene(zenith, a, depths, 64));
    const double t0 = deg2rad(zenith), muW = std::sqrt(1 - std::pow(std::sin(t0) / n, 2));
    CaseResult r;
    for (double z : depths) {
        const double ed = std::cos(t0) * fresnelTransmittance(t0, n) * std::exp(-a * z / muW);
        for (const auto& [q, ref] : {std::pair<std::string, double>{"Ed", ed}, {"Eod", ed / muW}}) {
            const ProbeCell& m = t.at(fmt::format("z{:g}", z)).at(q);
            // The sun is a 0.01 deg disc: its cosine spread changes Ed by < 1e-8; 1e-4 allows the
            // float arithmetic of a long path, plus 3 standard errors of the (noise-free) estimate.
            r.checks.push_back({fmt::format("{} at {:g} m", q, z), q, z, m.value, m.stderr_, ref,
                                1e-4 * ref + 3 * m.stderr_, "1e-4 relative + 3 standard errors"});
        }
    }
    r.charts.push_back(valuesChart("profile.png", "Direct sun in absorbing water (a = 0.4 m^-1, sun 40 deg)", "depth, m",
                                   "irradiance, W m^-2 um^-1", r.checks, true));
    return r;
}


// ---------------------------------------------------------------------------------------------
// Published: Mobley et al. (1993), problems 1 and 6, through `littoral run` on the scene files of
// data_synthetic/mobley1993/ (compiled in). A cell passes within max(3 s/mean, 3 se/mean) + the
// table's rounding (pipelines/reference/mobley1993.h); so that a noisy run cannot pass, each cell's
// standard error must also be below max(s/mean, noiseFloor) of its value (a second check).

struct MobleyProblem {
    std::string scene;
    int problem;
    double w0;
    std::vector<double> taus;
    double noiseFloor = 0.01;
};

std::string tauProbe(double tau) { return fmt::format("tau{:g}", tau); }

CaseResult mobleyCase(Context& c, const MobleyProblem& p) {
    const ProbeTable& t = runProbes(c, p.scene, embeddedScene(p.scene));
    CaseResult r;
    std::vector<Check> noise;
    for (double tau : p.taus) {
        const m93::Row* row = m93::find(p.problem, p.w0, tau);
        if (!row) throw InternalError(fmt::format("no Mobley row {} {} {}", p.problem, p.w0, tau));
        for (const std::string q : {"Ed", "Eou", "Lu"}) {
            const m93::Cell& cell = cellOf(*row, q);
            const ProbeCell& m = t.at(tauProbe(tau)).at(q);
            r.checks.push_back({fmt::format("{} at tau {:g}", q, tau), q, tau, m.value, m.stderr_, cell.mean,
                                m93::toleranceWithRounding(cell, m.stderr_) * cell.mean,
                                fmt::format("max(3 s/mean, 3 se/mean) + rounding; s/mean {:.3f}", cell.sOverMean)});
            noise.push_back({fmt::format("{} at tau {:g}: standard error / value", q, tau), "", NAN, m.stderr_ / m.value, 0, 0,
                             std::max(cell.sOverMean, p.noiseFloor),
                             fmt::format("at most max(s/mean, {:g}): the run resolves the models' spread", p.noiseFloor)});
        }
    }
    r.charts.push_back(valuesChart("profile.png", fmt::format("Mobley et al. (1993) problem {}, albedo {:g}", p.problem, p.w0),
                                   "optical depth", "Ed, Eou (W m^-2 um^-1); Lu (W m^-2 sr^-1 um^-1)", r.checks, true));
    r.charts.push_back(relativeChart("difference.png", "Difference from the published model means", r.checks));
    r.checks.insert(r.checks.end(), noise.begin(), noise.end());
    return r;
}

// Published, 1-D: the column solver against the same table. A deterministic solver's error is its
// discretisation's: a cell passes within 3 s/mean + rounding + |8-stream - 16-stream| (the change
// from the default 8 to 16 Gauss directions per side of the Snell-window edge bounds the default's
// quadrature error).
CaseResult columnMobleyCase(Context&) {
    CaseResult r;
    const std::vector<MobleyProblem> problems = {{"problem1_albedo09", 1, 0.9, {1, 5, 10}},
                                                 {"problem1_albedo02", 1, 0.2, {1, 5, 10}},
                                                 {"problem6", 6, 0.2, {1, 5}}};
    for (const auto& p : problems) {
        const auto base = solveEmbedded(p.scene, p.taus, 8), fine = solveEmbedded(p.scene, p.taus, 16);
        for (double tau : p.taus) {
            const m93::Row* row = m93::find(p.problem, p.w0, tau);
            for (const std::string q : {"Ed", "Eou", "Lu"}) {
                const m93::Cell& cell = cellOf(*row, q);
                const double v = quantityOf(base.at(tau), q), conv = std::abs(quantityOf(fine.at(tau), q) - v);
                r.checks.push_back({fmt::format("problem {} w0 {:g}: {} at tau {:g}", p.problem, p.w0, q, tau), q, tau, v, 0,
                                    cell.mean, (3 * cell.sOverMean + m93::roundingHalfUnit(cell)) * cell.mean + conv,
                                    "3 s/mean + rounding + |8 - 16 streams|"});
            }
        }
    }
    r.charts.push_back(relativeChart("difference.png", "littoral column against Mobley et al. (1993)", r.checks));
    return r;
}

// 3-D against 1-D: the path estimator's probes against the column solver at the same depths, on
// problems 1 (albedo 0.2) and 6. A cell passes within 3 standard errors of the path estimate + the
// column's |8 - 16 streams|. So that a noisy cell cannot pass, each path cell's standard error must
// also be below 10 % of its value. Problem 1's tau = 10 probe gets 10x (quick) or 50x the samples of
// the published scene file: at albedo 0.2 its light comes from rare paths that climb toward the
// sun, and with 20 000 samples the batch error underestimates the spread (Lu read 3.23e-8 +- 0.11e-8
// there, against 3.68e-8 +- 0.19e-8 with 400 000 samples and the column's 3.76e-8).
std::string withDeepSamples(const std::string& yaml, bool quick) {
    const std::string probe = "name: tau10, position: [0, 0, -10], quantities: [Ed, Eou, Lu], samples: ";
    return replacedOnce(yaml, probe + "20000", probe + (quick ? "200000" : "1000000"));
}

// A probe of a column case: its name, the x of its checks (the optical depth), its depth in metres,
// the quantities compared and, if not 0, their own cap on the standard error (else the case's).
struct ColumnProbe {
    std::string name;
    double tau = 0, z = 0;
    std::vector<std::string> quantities;
    double noiseCap = 0;
};

// Runs `yaml` as `run` and checks each probe cell against the column solver on the embedded `scene`
// at the same depth: within k standard errors (3; 4.1 for a se from 10 progressive passes, Student's
// t of 9 degrees of freedom at the same confidence) + the column's |8 - 16 streams| change (the
// 16-stream value is the reference); so that a noisy cell cannot pass, its standard error must also
// stay below `noiseCap` of its value, or the probe's own cap (a check of its own, in `noise`).
void checkAgainstColumn(Context& c, const std::string& run, const std::string& yaml, const std::string& scene,
                        const std::vector<ColumnProbe>& probes, double noiseCap, CaseResult& r, std::vector<Check>& noise,
                        double k = 3) {
    const ProbeTable& t = runProbes(c, run, yaml);
    std::vector<double> depths;
    for (const ColumnProbe& p : probes) depths.push_back(p.z);
    std::sort(depths.begin(), depths.end());
    depths.erase(std::unique(depths.begin(), depths.end()), depths.end());  // a probe may list its quantities twice
    const auto base = solveEmbedded(scene, depths, 8), fine = solveEmbedded(scene, depths, 16);
    for (const ColumnProbe& p : probes)
        for (const std::string& q : p.quantities) {
            const ProbeCell& m = t.at(p.name).at(q);
            const double v = quantityOf(fine.at(p.z), q), conv = std::abs(v - quantityOf(base.at(p.z), q));
            r.checks.push_back({fmt::format("{}: {} at {:g} m", run, q, p.z), q, p.tau, m.value, m.stderr_, v,
                                k * m.stderr_ + conv, fmt::format("{:g} se + |8 - 16 streams|", k)});
            const double cap = p.noiseCap > 0 ? p.noiseCap : noiseCap;
            noise.push_back({fmt::format("{}: {} at {:g} m: standard error / value", run, q, p.z), "", NAN,
                             m.stderr_ / m.value, 0, 0, cap, fmt::format("at most {:g} %", 100 * cap)});
        }
}

CaseResult pathVsColumnCase(Context& c) {
    CaseResult r;
    std::vector<Check> noise;
    const std::vector<std::string> all = {"Ed", "Eou", "Lu"};
    checkAgainstColumn(c, "problem1_albedo02-deep", withDeepSamples(embeddedScene("problem1_albedo02"), c.quick),
                       "problem1_albedo02", {{"tau1", 1, 1, all}, {"tau5", 5, 5, all}, {"tau10", 10, 10, all}}, 0.1, r,
                       noise);
    checkAgainstColumn(c, "problem6", embeddedScene("problem6"), "problem6", {{"tau1", 1, 1, all}, {"tau5", 5, 4.999, all}},
                       0.1, r, noise);
    r.charts.push_back(relativeChart("difference.png", "Path estimator (3-D) against the column solver (1-D)", r.checks));
    r.checks.insert(r.checks.end(), noise.begin(), noise.end());
    return r;
}

// ---------------------------------------------------------------------------------------------
// 3-D against 1-D on the hard columns of issue 19: the path estimator's forward irradiance tallies
// (render/forward_tally.h; these columns are horizontally invariant) against the column solver, on
// Petzold water at albedo 0.9 (Mobley et al.'s problem 2), the same water under a Cox-Munk sea at an
// 80 deg sun (problem 5) and a stratified column to 60 m. Each cell within 3 se + the solver's
// |8 - 16 streams| change; each se at most 1.5 %, except the stratified column's upwelling light at
// 25-59 m, where it falls by up to 3 x 10^3 from 5 m: at most 4.5 % (measured 1.2-3.1 % at the
// default 10^6 photons split by depth; a se from 20 batches scatters by 16 %). Lu is left out
// (backward paths in Petzold water are heavy-tailed). Not part of --quick: the same three runs,
// with caps of 1 % and 1.25 % and the pilot's choices checked, are CI's ForwardTallies tests
// (tests/pipelines/forward_tally_test.cpp), and running them twice cost CI 77 test-seconds.

// An embedded scene's text with its probes reading Ed and Eou only (`samples` set for Lu dropped).
std::string irradiancesOnly(const std::string& scene) {
    std::string text = embeddedScene(scene);
    for (const char* n : {"25000", "80000", "200000"})
        text = replacedOnce(text, std::string("[Ed, Eou, Lu], samples: ") + n, "[Ed, Eou]");
    return text;
}

CaseResult forwardVsColumnCase(Context& c) {
    CaseResult r;
    std::vector<Check> noise;
    const std::vector<std::string> both = {"Ed", "Eou"}, ed = {"Ed"}, eou = {"Eou"};
    const std::vector<ColumnProbe> taus = {{"tau1", 1, 1, both}, {"tau5", 5, 5, both}, {"tau10", 10, 10, both}};
    checkAgainstColumn(c, "problem2_albedo09", embeddedScene("problem2_albedo09"), "problem2_albedo09", taus, 0.015, r,
                       noise);
    checkAgainstColumn(c, "problem5", irradiancesOnly("problem5"), "problem5", taus, 0.015, r, noise);
    checkAgainstColumn(c, "stratified_60m", embeddedScene("columns/stratified_60m"), "columns/stratified_60m",
                       {{"z5", 5, 5, both}, {"z15", 15, 15, both}, {"z25", 25, 25, ed}, {"z40", 40, 40, ed},
                        {"z59", 59, 59, ed}, {"z25", 25, 25, eou, 0.045}, {"z40", 40, 40, eou, 0.045},
                        {"z59", 59, 59, eou, 0.045}},
                       0.015, r, noise);
    r.charts.push_back(relativeChart("difference.png", "Forward tallies (3-D) against the column solver (1-D)", r.checks));
    r.checks.insert(r.checks.end(), noise.begin(), noise.end());
    return r;
}

// The same columns with the dirsig estimator's photon maps (problem 5, its Ed and Eou from the
// volume map's collisions: photons.probe_collisions; and the stratified column split by depth:
// photons.depth_splitting, gathered), Ed and Eou against the column solver. The standard errors are
// the spread of 10 progressive passes: 4.1 se (Student's t, 9 degrees of freedom) + the |8 - 16
// streams| change; se at most 0.8 % in Ed and 1.5 % in Eou for problem 5 (measured 0.24-1.02 %),
// 4 % on the stratified column (measured 0.4-3.1 %). About 2 min of CPU: not part of --quick.
CaseResult photonMapsVsColumnCase(Context& c) {
    CaseResult r;
    std::vector<Check> noise;
    const std::vector<std::string> ed = {"Ed"}, eou = {"Eou"}, lu = {"Lu"}, both = {"Ed", "Eou"};
    // Problems 5 and 2: Ed, Eou and (from every record below each probe) Lu, the collisions'.
    for (const auto& [name, edSe] : {std::pair{"problem5_photon_maps", 0.008}, std::pair{"problem2_photon_maps", 0.005}}) {
        const std::string rel = std::string("mobley1993/") + name;
        checkAgainstColumn(c, name, embeddedScene(rel), rel,
                           {{"tau1", 1, 1, ed}, {"tau5", 5, 5, ed}, {"tau10", 10, 10, ed}, {"tau1", 1, 1, eou, 0.015},
                            {"tau5", 5, 5, eou, 0.015}, {"tau10", 10, 10, eou, 0.015}, {"tau1", 1, 1, lu, 0.06},
                            {"tau5", 5, 5, lu, 0.06}, {"tau10", 10, 10, lu, 0.06}},
                           edSe, r, noise, 4.1);
    }
    checkAgainstColumn(c, "stratified_60m_photon_maps", embeddedScene("columns/stratified_60m_photon_maps"),
                       "columns/stratified_60m_photon_maps",
                       {{"z5", 5, 5, both}, {"z15", 15, 15, both}, {"z25", 25, 25, both}, {"z40", 40, 40, both},
                        {"z59", 59, 59, both}},
                       0.025, r, noise, 4.1);
    r.charts.push_back(relativeChart("difference.png", "Photon maps (3-D) against the column solver (1-D)", r.checks));
    r.checks.insert(r.checks.end(), noise.begin(), noise.end());
    return r;
}

// ---------------------------------------------------------------------------------------------
// Published: instrument self-shading (Gordon and Ding 1992). Opaque black cylinders of radius R
// float with their bottoms 1 cm below a flat surface in homogeneous water (a = 0.5, b = 1 m^-1,
// Petzold), sun only; a probe 2 mm under each bottom's centre reads Lu, and one in open water the
// unshaded Lu. eps = 1 - Lu(shaded) / Lu(open) against eps_sun = 1 - exp(-k' a R),
// k' = k''(theta0) / tan(theta_w) (pipelines/reference/gordon_ding.h). Gordon and Ding fitted k''
// to their Monte Carlo results and put the fit's accuracy at 10-15 %: a point passes within 20 %
// of eps + 3 standard errors of the measured eps (from the two probes' errors); so that the noise
// cannot carry a point, 3 standard errors must also stay below that 20 % (a second check).

const double kShadeA = 0.5, kShadeB = 1.0;
const double kShadeRadii[] = {0.1, 0.2, 0.4};

// A closed cylinder of radius r from z = 0 to z = h as an OBJ (n sides, outward faces).
std::string cylinderObj(double r, double h, int n) {
    std::string s = "# littoral validate: an instrument housing\n";
    for (int i = 0; i < n; ++i) {
        const double p = 2 * kPi * i / n;
        s += fmt::format("v {:.6f} {:.6f} 0\nv {:.6f} {:.6f} {:g}\n", r * std::cos(p), r * std::sin(p), r * std::cos(p),
                         r * std::sin(p), h);
    }
    s += fmt::format("v 0 0 0\nv 0 0 {:g}\n", h);
    const int lo = 2 * n + 1, hi = 2 * n + 2;  // centres (OBJ indices are 1-based)
    for (int i = 0; i < n; ++i) {
        const int a0 = 2 * i + 1, a1 = 2 * i + 2, b0 = 2 * ((i + 1) % n) + 1, b1 = b0 + 1;
        s += fmt::format("f {} {} {}\nf {} {} {}\nf {} {} {}\nf {} {} {}\n", a0, b0, b1, a0, b1, a1, lo, b0, a0, hi, a1, b1);
    }
    return s;
}

std::string selfShadingScene(double zenithDeg, int samples) {
    FlatScene f;
    f.comment = fmt::format("instrument self-shading (Gordon and Ding 1992), sun at {:g} deg.", zenithDeg);
    f.name = "validate-self-shading";
    f.halfX = f.halfY = 15;
    f.sunZenith = zenithDeg;
    f.optics = fmt::format("{{refractive_index: {}, absorption_per_m: {}, scattering_per_m: {}, phase: {{type: petzold}}}}",
                           gd::kWaterIndex, kShadeA, kShadeB);
    f.floorSpacing = 15;
    f.otherMaterials = "  - {name: housing, type: black}\n";
    for (size_t i = 0; i < std::size(kShadeRadii); ++i) {
        const double y = -10 + 7.5 * i;
        f.objects += fmt::format("  - {{name: r{}, mesh: cylinder_{}.obj, materials: [housing], position_m: [0, {:g}], draft_m: 0.01}}\n",
                                 i, i, y);
        f.probes += fmt::format("  - {{name: r{}, position: [0, {:g}, -0.012], quantities: [Lu], samples: {}}}\n", i, y, samples);
    }
    f.probes += fmt::format("  - {{name: open, position: [0, 12.5, -0.012], quantities: [Lu], samples: {}}}\n", samples);
    return flatSceneYaml(f);
}

CaseResult selfShadingCase(Context& c) {
    CaseResult r;
    std::vector<Check> noise;
    const int samples = c.quick ? 100000 : 400000;
    PlotSpec p = plotSpec("Self-shading error of Lu against a R (Gordon and Ding 1992)", "a R", "epsilon");
    int colour = 0;
    for (double zenith : {20.0, 40.0, 60.0}) {
        const std::string run = fmt::format("self-shading-sun{:g}", zenith);
        for (size_t i = 0; i < std::size(kShadeRadii); ++i)
            writeTextFileAtomic(c.root / run / fmt::format("cylinder_{}.obj", i), cylinderObj(kShadeRadii[i], 0.3, 48));
        const ProbeTable& t = runProbes(c, run, selfShadingScene(zenith, samples));
        const ProbeCell& open = t.at("open").at("Lu");
        PlotSeries m = plotSeries(fmt::format("Littoral, sun {:g} deg", zenith)), pred = plotSeries(fmt::format("Gordon & Ding, sun {:g} deg", zenith));
        m.line = false;
        pred.markers = false, pred.dashed = true;
        m.colour = pred.colour = colour++;
        for (int k = 0; k <= 40; ++k) pred.x.push_back(0.22 * k / 40), pred.y.push_back(gd::epsilonSun(gd::Quantity::Lu, zenith, 1.0, 0.22 * k / 40));
        for (size_t i = 0; i < std::size(kShadeRadii); ++i) {
            const ProbeCell& s = t.at(fmt::format("r{}", i)).at("Lu");
            const double ratio = s.value / open.value, eps = 1 - ratio;
            const double se = ratio * std::hypot(s.stderr_ / s.value, open.stderr_ / open.value);
            const double aR = kShadeA * kShadeRadii[i], ref = gd::epsilonSun(gd::Quantity::Lu, zenith, kShadeA, kShadeRadii[i]);
            r.checks.push_back({fmt::format("eps(Lu), sun {:g} deg, a R = {:g}", zenith, aR), "", aR, eps, se, ref,
                                0.2 * ref + 3 * se, "20 % (the fit's stated 10-15 %) + 3 se"});
            noise.push_back({fmt::format("eps(Lu), sun {:g} deg, a R = {:g}: 3 standard errors", zenith, aR), "", NAN, 3 * se,
                             0, 0, 0.2 * ref, "below 20 % of eps"});
            m.x.push_back(aR), m.y.push_back(eps), m.yErr.push_back(se);
        }
        p.series.push_back(pred), p.series.push_back(m);
    }
    r.charts.push_back({"epsilon.png", p});
    r.checks.insert(r.checks.end(), noise.begin(), noise.end());
    return r;
}

// ---------------------------------------------------------------------------------------------
// Published (Section 10.4, Fig. 10.19): the surface and volumetric shadows of a floating box. Sun
// at 45 deg with 90 % of the hemisphere irradiance (5.0) in the disc, a = b = 0.2 m^-1, isotropic
// phase function. Six black 2 m x 2 m x 1 m boxes, bottoms 0.5, 1.5, 2.2, 3.0, 3.5 and 4.0 m deep
// (the first floats with 0.5 m above the water; the others are submerged), 10 m apart across the
// sun so that their shadows do not meet, over black water 15 m deep. The dissertation shows that
// the volumetric shadow weakens as the box is lowered and that the 0.5 m box also shades the
// interface; it gives no numbers, so the checks are those two statements, with margins of
// standard errors:
//  - depth of contrast: c = 1 - Lu(edge) / Lu(open), Lu just under the surface 5 cm beyond each
//    box's anti-sun edge against a probe 15 m up-sun of the boxes; each box's c must exceed the
//    next deeper one's by 2 standard errors of the difference (single scattering predicts ratios
//    exp(-c (1 + 1/cos theta_w) dd) between neighbours, 0.42-0.65 here);
//  - surface shadow: Ed 2 cm under the surface 0.25 m beyond the floating box (inside the 0.5 m
//    shadow its freeboard casts at 45 deg) must miss at least 80 % of the direct sun's share of
//    Ed, E_sun T(45 deg) / Ed(open) with T from Fresnel's equations; beside the 1.5 m box (submerged,
//    so no shadow on the interface) Ed must stay within 3 % of the open water's.

const double kBoxBottoms[] = {0.5, 1.5, 2.2, 3.0, 3.5, 4.0};

std::string boxShadowScene(int luSamples) {
    FlatScene f;
    f.comment = "the floating-box shadow series (dissertation Section 10.4, Fig. 10.19).";
    f.name = "validate-box-shadows";
    f.halfX = f.halfY = 30;
    f.sunZenith = 45, f.sunAzimuth = 270, f.sunDiameter = 0.53;
    f.sunIrradiance = 4.5 / std::cos(deg2rad(45.0)), f.skyRadiance = 0.5 / kPi;  // 90 % of E = 5.0 in the disc
    f.optics = "{refractive_index: 1.34, absorption_per_m: 0.2, scattering_per_m: 0.2, phase: {type: isotropic}}";
    f.floorDepth = 15, f.floorSpacing = 30;
    f.otherMaterials = "  - {name: hull, type: black}\n";
    for (size_t i = 0; i < std::size(kBoxBottoms); ++i) {
        const double y = -25 + 10.0 * i;
        f.objects += fmt::format("  - {{name: box{}, mesh: box.obj, materials: [hull], position_m: [0, {:g}], z_m: {:g}}}\n", i, y,
                                 -kBoxBottoms[i]);
        f.probes += fmt::format("  - {{name: edge{}, position: [1.05, {:g}, -0.012], quantities: [Lu], samples: {}}}\n", i, y, luSamples);
        if (i < 2)
            f.probes += fmt::format("  - {{name: surface{}, position: [1.25, {:g}, -0.02], quantities: [Ed], samples: 4000}}\n", i, y);
    }
    f.probes += fmt::format("  - {{name: open, position: [-15, 0, -0.012], quantities: [Lu], samples: {}}}\n", luSamples);
    f.probes += "  - {name: open-ed, position: [-15, 0, -0.02], quantities: [Ed], samples: 4000}\n";
    return flatSceneYaml(f);
}

// Contrast (and its standard error) of box i against the open water.
std::pair<double, double> boxContrast(const ProbeTable& t, size_t i) {
    const ProbeCell &e = t.at(fmt::format("edge{}", i)).at("Lu"), &o = t.at("open").at("Lu");
    const double ratio = e.value / o.value;
    return {1 - ratio, ratio * std::hypot(e.stderr_ / e.value, o.stderr_ / o.value)};
}

CaseResult boxShadowCase(Context& c) {
    writeTextFileAtomic(c.root / "box-shadows" / "box.obj", boxObj(2, 2, 1));
    const ProbeTable& t = runProbes(c, "box-shadows", boxShadowScene(c.quick ? 60000 : 300000));
    CaseResult r;
    PlotSpec p = plotSpec("Depth of contrast of the volumetric shadow (Lu 5 cm beyond the box)", "box bottom depth, m",
                          "1 - Lu(shadow) / Lu(open)");
    PlotSeries m = plotSeries("Littoral (path estimator), +-1 standard error");
    for (size_t i = 0; i < std::size(kBoxBottoms); ++i) {
        const auto [ci, si] = boxContrast(t, i);
        m.x.push_back(kBoxBottoms[i]), m.y.push_back(ci), m.yErr.push_back(si);
        if (i + 1 == std::size(kBoxBottoms)) break;
        const auto [cn, sn] = boxContrast(t, i + 1);
        Check k{fmt::format("contrast at {:g} m - contrast at {:g} m", kBoxBottoms[i], kBoxBottoms[i + 1]), "", NAN, ci - cn,
                std::hypot(si, sn), 0, 2 * std::hypot(si, sn), "falls as the box is lowered: > 0 by 2 se"};
        k.bound = Check::Bound::AtLeast;
        r.checks.push_back(k);
    }
    p.series.push_back(m);
    r.charts.push_back({"contrast.png", p});
    const double edOpen = t.at("open-ed").at("Ed").value;
    const double directShare = 4.5 * fresnelTransmittance(deg2rad(45.0), 1.34) / edOpen;
    const ProbeCell &s0 = t.at("surface0").at("Ed"), &s1 = t.at("surface1").at("Ed");
    Check shade{"Ed beside the 0.5 m box / Ed(open)", "", NAN, s0.value / edOpen, s0.stderr_ / edOpen, 1 - 0.8 * directShare,
                2 * s0.stderr_ / edOpen, fmt::format("at most 1 - 0.8 x the direct share {:.3f}, by 2 se", directShare)};
    shade.bound = Check::Bound::AtMost;
    r.checks.push_back(shade);
    r.checks.push_back({"Ed beside the 1.5 m box / Ed(open)", "", NAN, s1.value / edOpen, s1.stderr_ / edOpen, 1.0, 0.03,
                        "no shadow on the interface: within 3 %"});
    return r;
}

// ---------------------------------------------------------------------------------------------
// Published (Chapter 8, after Reinersman and Carder 2004): the shadow of a periodic barge. Barges
// 10 m wide, 20 m apart (a 30 m period), 40 m long, 2 m draft and 1 m freeboard, reflectance 0.1,
// over a bottom 20 m down; 532 nm; sun at 30 deg in the west carrying 79 % of Ed, a uniform sky
// 21 %; the waters of Tables 8.1 and 8.2 (pure water, Rayleigh-like, plus particles and
// chlorophyll, Petzold). The chapter's results are contour plots; the checks are its stated
// physics, each made quantitative:
//  - the shadow column bends behind the ship along the refracted sun: at 4 m and 8 m the direct
//    sun's edges lie at x = -5 + (z - 2) tan(theta_w) (under the west keel corner) and
//    x = 5 + f tan(theta_0) + z tan(theta_w) (past the east side and its freeboard f). Ed is read
//    0.15 m and 0.45 m either side of each predicted edge (bargeEdgeChecks);
//  - the Ed perturbation 1 - Ed / Ed(open) at the centre of the shadow falls with depth (in-scatter
//    fills the column), by 2 standard errors at every step;
//  - light reflected from the barge's underside: 1 cm under its keel, the water above a probe is
//    1 cm deep and the underside fills the upper hemisphere, so Ed = r Eu, r = 0.1 (Lambertian
//    reflection); within 3 % + 3 standard errors.

// depths: where the perturbation is read (turbid water's light is 1e-6 of the surface's at 15 m,
// beyond what the path estimator resolves there; issue 19), keel: whether the Ed = r Eu check runs
// (under the keel in turbid water the path estimator's Eu is still 20 % noisy at 400 000 samples).
struct BargeWater {
    std::string name;
    double absorption, particleScattering, bottom;
    std::vector<double> depths;
    bool edges, keel;
};
const BargeWater kBargeA{"A (clear, chl 0.3)", 0.05172 + 0.01304 + 0.00439734, 0.1448 + 0.03486, 0.15, {2.5, 6, 10, 15}, true, true};
const BargeWater kBargeB{"B (turbid, chl 5)", 0.05172 + 0.1150 + 0.07329, 0.8391 + 0.581, 0.05, {2.5, 3.5, 5, 7}, false, false};
const double kBargeDraft = 2, kBargeFreeboard = 1, kBargeSunDeg = 30, kBargeN = 1.34;

double bargeTanW() {
    const double s = std::sin(deg2rad(kBargeSunDeg)) / kBargeN;
    return s / std::sqrt(1 - s * s);
}
// The direct sun's shadow edges at depth z (west, east), x in m.
std::pair<double, double> bargeEdges(double z) {
    return {-5 + (z - kBargeDraft) * bargeTanW(), 5 + kBargeFreeboard * std::tan(deg2rad(kBargeSunDeg)) + z * bargeTanW()};
}
const double kBargeEdgeDepths[] = {4, 8};
const double kBargeOffsets[] = {-0.45, -0.15, 0.15, 0.45};

std::string bargeProbes(const BargeWater& w, int edgeSamples, int samples, int keelSamples) {
    std::string p;
    auto add = [&](const std::string& name, double x, double z, const char* q, int n) {
        p += fmt::format("  - {{name: {}, position: [{:.4f}, 0, {:g}], quantities: [{}], samples: {}}}\n", name, x, -z, q, n);
    };
    for (double z : kBargeEdgeDepths) {
        if (!w.edges) break;
        const auto [west, east] = bargeEdges(z);
        for (size_t k = 0; k < std::size(kBargeOffsets); ++k) {
            add(fmt::format("w{:g}_{}", z, k), west + kBargeOffsets[k], z, "Ed", edgeSamples);
            add(fmt::format("e{:g}_{}", z, k), east + kBargeOffsets[k], z, "Ed", edgeSamples);
        }
    }
    for (double z : w.depths) {
        const auto [west, east] = bargeEdges(z);
        add(fmt::format("mid{:g}", z), 0.5 * (std::max(west, -5.0) + east), z, "Ed", samples);
        add(fmt::format("open{:g}", z), -12, z, "Ed", samples);
    }
    if (w.keel) add("keel", 0, kBargeDraft + 0.01, "Ed, Eu", keelSamples);
    return p;
}

std::string bargeScene(const BargeWater& w, bool quick) {
    FlatScene f;
    f.comment = "the periodic barge of the dissertation's Chapter 8, water " + w.name + ".";
    f.name = "validate-barge";
    f.halfX = 15, f.halfY = 30;
    f.sunZenith = kBargeSunDeg, f.sunAzimuth = 270, f.sunDiameter = 0.53;
    f.sunIrradiance = 0.79 / std::cos(deg2rad(kBargeSunDeg)), f.skyRadiance = 0.21 / kPi;  // 79 % direct, 21 % sky
    f.optics = fmt::format("{{refractive_index: {}, absorption_per_m: {:.6f}, scatterers: [{{name: pure-water, scattering_per_m: "
                           "0.00218, phase: {{type: pure-water}}}}, {{name: particles, scattering_per_m: {:.6f}, phase: {{type: petzold}}}}]}}",
                           kBargeN, w.absorption, w.particleScattering);
    f.floorDepth = 20, f.floorSpacing = 15;
    f.floorMaterial = fmt::format("{{name: bottom, reflectance: {}}}", w.bottom);
    f.otherMaterials = "  - {name: hull, reflectance: 0.1}\n";
    f.objects = fmt::format("  - {{name: barge, mesh: barge.obj, materials: [hull], position_m: [0, 0], z_m: {}}}\n", -kBargeDraft);
    f.probes = bargeProbes(w, quick ? 3000 : 12000, quick ? 12000 : 50000, quick ? 100000 : 400000);
    f.render = "{bands: [[0.527, 0.537]], estimator: path, probe_batches: 16}";
    return flatSceneYaml(f);
}

// The unscattered sun's Ed at depth z in the open water: E cos(theta0) T(theta0) exp(-c z / cos theta_w).
double bargeDirectEd(const BargeWater& w, double z) {
    const double t0 = deg2rad(kBargeSunDeg), c = w.absorption + w.particleScattering + 0.00218;
    const double muW = 1 / std::sqrt(1 + bargeTanW() * bargeTanW());
    return 0.79 * fresnelTransmittance(t0, kBargeN) * std::exp(-c * z / muW);
}

// At each predicted edge: the step in Ed across it (probes 0.15 m either side) holds the whole jump
// of the unscattered sun, D = bargeDirectEd (its penumbra is < 0.1 m), and is larger than the steps
// beside it (0.15 to 0.45 m out), where only scattered light changes. An edge 0.15 m or more from
// its prediction fails the first; a shadow column that did not bend (2.4 m off at 8 m) fails both.
void bargeEdgeChecks(const BargeWater& w, const ProbeTable& t, CaseResult* r) {
    for (double z : kBargeEdgeDepths)
        for (const char side : {'w', 'e'}) {
            ProbeCell ed[4];
            for (int k = 0; k < 4; ++k) ed[k] = t.at(fmt::format("{}{:g}_{}", side, z, k)).at("Ed");
            auto step = [&](int a, int b) {
                return std::pair{std::abs(ed[b].value - ed[a].value), std::hypot(ed[a].stderr_, ed[b].stderr_)};
            };
            const auto across = step(1, 2), left = step(0, 1), right = step(2, 3);
            const auto beside = left.first > right.first ? left : right;
            const std::string edge = fmt::format("{} shadow edge at {:g} m", side == 'w' ? "west" : "east", z);
            Check jump{edge + ": step in Ed across the predicted edge", "", NAN, across.first, across.second,
                       bargeDirectEd(w, z), 2 * across.second, "at least the unscattered sun's Ed there, by 2 se"};
            Check sharp{edge + ": step across - largest step beside", "", NAN, across.first - beside.first,
                        std::hypot(across.second, beside.second), 0, 2 * std::hypot(across.second, beside.second),
                        "> 0 by 2 se"};
            jump.bound = sharp.bound = Check::Bound::AtLeast;
            r->checks.push_back(jump);
            r->checks.push_back(sharp);
        }
}

CaseResult bargeCase(Context& c, const BargeWater& w, const std::string& run) {
    writeTextFileAtomic(c.root / run / "barge.obj", boxObj(10, 40, kBargeDraft + kBargeFreeboard));
    const ProbeTable& t = runProbes(c, run, bargeScene(w, c.quick));
    CaseResult r;
    if (w.edges) bargeEdgeChecks(w, t, &r);
    PlotSpec p = plotSpec("Ed perturbation at the centre of the barge's shadow, water " + w.name, "depth, m", "1 - Ed / Ed(open)");
    PlotSeries m = plotSeries("Littoral (path estimator), +-1 standard error");
    double prev = NAN, prevSe = 0, prevZ = 0;
    for (double z : w.depths) {
        const ProbeCell &e = t.at(fmt::format("mid{:g}", z)).at("Ed"), &o = t.at(fmt::format("open{:g}", z)).at("Ed");
        const double d = 1 - e.value / o.value, se = e.value / o.value * std::hypot(e.stderr_ / e.value, o.stderr_ / o.value);
        m.x.push_back(z), m.y.push_back(d), m.yErr.push_back(se);
        if (std::isfinite(prev)) {
            Check k{fmt::format("perturbation at {:g} m - at {:g} m", prevZ, z), "", NAN, prev - d, std::hypot(prevSe, se), 0,
                    2 * std::hypot(prevSe, se), "falls with depth: > 0 by 2 se"};
            k.bound = Check::Bound::AtLeast;
            r.checks.push_back(k);
        }
        prev = d, prevSe = se, prevZ = z;
    }
    p.series.push_back(m);
    r.charts.push_back({"perturbation.png", p});
    if (!w.keel) return r;
    const ProbeCell &ed = t.at("keel").at("Ed"), &eu = t.at("keel").at("Eu");
    const double ratio = ed.value / eu.value, se = ratio * std::hypot(ed.stderr_ / ed.value, eu.stderr_ / eu.value);
    r.checks.push_back({"Ed / Eu 1 cm under the keel", "", NAN, ratio, se, 0.1, 0.003 + 3 * se,
                        "the underside's reflectance 0.1 (Lambertian): 3 % + 3 se"});
    r.checks.push_back({"Ed / Eu 1 cm under the keel: 3 standard errors / 0.1", "", NAN, 3 * se / 0.1, 0, 0, 0.25,
                        "the noise stays below a quarter of r"});
    return r;
}

// ---------------------------------------------------------------------------------------------
// Solver against solver: the dirsig estimator with its volume and surface photon maps against the
// path estimator, on one scene of forward-peaked, high-albedo water (HG g = 0.9, albedo 0.8) over
// a sandy bottom 6 m down, sun at 30 deg. Both are consistent estimators of the same field: a
// probe passes within 3 standard errors of the difference (the maps' noise is in the dirsig
// errors: independent progressive passes) + 1 % for the photon maps' kernel bias (a field varying
// as exp(-K z) with K < 0.5 m^-1 changes by < (K r)^2 / 10 = 1e-3 over a 0.15 m kernel; 1 % also
// covers the surface map's radius at the bottom). So that noise cannot carry a probe, the
// difference's standard error must also stay below 5 % of the path value (a second check).

std::string pmVsPathScene(bool photonMaps, bool quick) {
    FlatScene f;
    f.comment = "photon maps against the path estimator in forward-peaked water.";
    f.name = "validate-pm-vs-path";
    f.halfX = f.halfY = 0.5;
    f.sunZenith = 30;
    f.optics = std::string("{refractive_index: 1.34, absorption_per_m: 0.1, scattering_per_m: 0.4, phase: {type: henyey-greenstein, "
                           "g: 0.9}") + (photonMaps ? ", solver: medium-pm}" : "}");
    f.floorDepth = 6, f.floorSpacing = 1;
    f.floorMaterial = photonMaps ? "{name: sand, reflectance: 0.3, solver: surface-pm}" : "{name: sand, reflectance: 0.3}";
    const int samples = photonMaps ? 320 : (quick ? 40000 : 200000);
    for (const char* z : {"2", "5"})
        f.probes += fmt::format("  - {{name: z{}, position: [0, 0, -{}], quantities: [Ed, Eou, Lu], samples: {}}}\n", z, z, samples);
    f.render = photonMaps ? fmt::format("  bands: [[0.5, 0.51]]\n  estimator: dirsig\n  photons: {{surface: {}, volume: {}}}\n"
                                        "  search_radius_m: {{surface: 0.15, volume: 0.15}}\n  progressive: {{passes: 8, alpha: 0.99}}\n"
                                        "  probe_batches: 8\n",
                                        quick ? 20000 : 80000, quick ? 150000 : 600000)
                          : "{bands: [[0.5, 0.51]], estimator: path, probe_batches: 16}";
    return flatSceneYaml(f);
}

CaseResult pmVsPathCase(Context& c) {
    const ProbeTable& path = runProbes(c, "pm-vs-path-path", pmVsPathScene(false, c.quick));
    const ProbeTable& pm = runProbes(c, "pm-vs-path-photon-maps", pmVsPathScene(true, c.quick));
    CaseResult r;
    std::vector<Check> noise;
    for (const auto& [probe, z] : {std::pair<std::string, double>{"z2", 2}, {"z5", 5}})
        for (const std::string q : {"Ed", "Eou", "Lu"}) {
            const ProbeCell &a = pm.at(probe).at(q), &b = path.at(probe).at(q);
            r.checks.push_back({fmt::format("{} at {:g} m (photon maps vs path)", q, z), q, z, a.value, a.stderr_, b.value,
                                3 * std::hypot(a.stderr_, b.stderr_) + 0.01 * b.value, "3 se of the difference + 1 %"});
            noise.push_back({fmt::format("{} at {:g} m: standard error of the difference / value", q, z), "", NAN,
                             std::hypot(a.stderr_, b.stderr_) / b.value, 0, 0, 0.05, "at most 5 %"});
        }
    r.charts.push_back(valuesChart("profile.png", "Photon maps (points) against the path estimator (line), HG 0.9, albedo 0.8",
                                   "depth, m", "Ed, Eou (W m^-2 um^-1); Lu (W m^-2 sr^-1 um^-1)", r.checks, true));
    r.checks.insert(r.checks.end(), noise.begin(), noise.end());
    return r;
}

// ---------------------------------------------------------------------------------------------
// The suite.

std::vector<Case> suite() {
    const MobleyProblem p1w02{"problem1_albedo02", 1, 0.2, {1, 5, 10}}, p6{"problem6", 6, 0.2, {1, 5}};
    const MobleyProblem p1w09{"problem1_albedo09", 1, 0.9, {1, 5, 10}};
    const MobleyProblem p1w09pm{"problem1_albedo09_photon_maps", 1, 0.9, {1, 5, 10}, 0.05};
    const MobleyProblem p6pm{"problem6_photon_maps", 6, 0.2, {1, 5}, 0.05};
    auto mobley = [](MobleyProblem p) { return [p](Context& c) { return mobleyCase(c, p); }; };
    const std::string m93 = "Mobley et al. (1993), Appl. Opt. 32(36) 7484, Table 3 (model means and spread)";
    return {
        {"direct-sun", "analytic", "Direct sun in purely absorbing water: Beer-Lambert through a Fresnel interface",
         "Fresnel's equations and Snell's law; exp(-a z / cos theta_w)", true, 1.5, directSunCase},
        {"mobley-p1-albedo0.2", "published", "Mobley (1993) problem 1, albedo 0.2: path estimator", m93, true, 2.5, mobley(p1w02)},
        {"mobley-p6", "published", "Mobley (1993) problem 6, shallow bottom: path estimator", m93, true, 15, mobley(p6)},
        {"mobley-column", "published (1-D)", "Mobley (1993) problems 1 and 6: the column solver", m93, true, 1, columnMobleyCase},
        {"path-vs-column", "3-D against 1-D", "Path estimator against the column solver, problems 1 (albedo 0.2) and 6",
         "the column solver (column/, no shared transport code)", true, 1, pathVsColumnCase},
        {"forward-vs-column", "3-D against 1-D",
         "Forward irradiance tallies against the column solver: Petzold albedo 0.9 and a stratified column to 60 m",
         "the column solver (column/, no shared transport code)", false, 6, forwardVsColumnCase},
        {"photon-maps-vs-column", "3-D against 1-D",
         "Photon maps against the column solver: problems 2 and 5 (with Lu) and the stratified column split by depth",
         "the column solver (column/, no shared transport code)", false, 50, photonMapsVsColumnCase},
        {"photon-maps-vs-path", "solver against solver", "Photon maps against the path estimator, HG 0.9 water over sand",
         "the path estimator on the same scene", true, 12, pmVsPathCase},
        {"self-shading", "published", "Instrument self-shading of Lu at three sun zeniths",
         "Gordon and Ding (1992), Limnol. Oceanogr. 37(3) 491", true, 20, selfShadingCase},
        {"barge-clear", "published (qualitative)", "The shadow of a periodic barge in clear water (Tables 8.1, 8.2, A)",
         "Goodenough (2010) dissertation, Chapter 8 (after Reinersman and Carder 2004)", true, 15,
         [](Context& c) { return bargeCase(c, kBargeA, "barge-clear"); }},
        {"barge-turbid", "published (qualitative)", "The shadow of a periodic barge in turbid water (Tables 8.1, 8.2, B)",
         "Goodenough (2010) dissertation, Chapter 8 (after Reinersman and Carder 2004)", false, 60,
         [](Context& c) { return bargeCase(c, kBargeB, "barge-turbid"); }},
        {"box-shadows", "published (qualitative)", "Surface and volumetric shadows of a floating box lowered 0.5-4.0 m",
         "Goodenough (2010) dissertation, Section 10.4, Fig. 10.19", true, 15, boxShadowCase},
        {"mobley-p1-albedo0.9", "published", "Mobley (1993) problem 1, albedo 0.9: path estimator", m93, false, 32, mobley(p1w09)},
        {"mobley-p1-albedo0.9-photon-maps", "published", "Mobley (1993) problem 1, albedo 0.9: photon maps", m93, false, 75,
         mobley(p1w09pm)},
        {"mobley-p6-photon-maps", "published", "Mobley (1993) problem 6: photon maps", m93, false, 56, mobley(p6pm)},
    };
}

struct CaseRecord {
    const Case* c;
    CaseResult result;
    double seconds = 0;
    std::string error;  // the case could not run (its checks then count as failed)
    bool pass() const {
        return error.empty() && !result.checks.empty() &&
               std::all_of(result.checks.begin(), result.checks.end(), [](const Check& k) { return k.pass(); });
    }
};

std::string duration(double s) {
    if (s < 90) return fmt::format("{:.0f} s", s);
    return fmt::format("{:.0f} min {:02.0f} s", std::floor(s / 60), std::fmod(s, 60.0));
}

nlohmann::json summaryJson(const std::vector<CaseRecord>& recs, const ValidateOptions& o, double seconds) {
    nlohmann::json j = {{"quick", o.quick}, {"seconds", seconds}};
    bool all = true;
    j["cases"] = nlohmann::json::array();
    for (const auto& r : recs) {
        nlohmann::json c = {{"name", r.c->name},      {"category", r.c->category}, {"title", r.c->title},
                            {"reference", r.c->reference}, {"seconds", r.seconds},  {"pass", r.pass()}};
        if (!r.error.empty()) c["error"] = r.error;
        c["notes"] = r.result.notes;
        c["checks"] = nlohmann::json::array();
        for (const Check& k : r.result.checks)
            c["checks"].push_back({{"label", k.label},         {"measured", k.measured}, {"stderr", k.stderr_},
                                   {"reference", k.reference}, {"relation", k.relation()}, {"tolerance", k.tolerance}, {"tolerance_basis", k.why},
                                   {"pass", k.pass()}});
        c["plots"] = nlohmann::json::array();
        for (const Chart& ch : r.result.charts) c["plots"].push_back("cases/" + r.c->name + "/" + ch.file);
        all = all && r.pass();
        j["cases"].push_back(c);
    }
    j["pass"] = all;
    return j;
}

std::string html(const std::string& s) {
    std::string o;
    for (char ch : s) o += ch == '<' ? "&lt;" : ch == '>' ? "&gt;" : ch == '&' ? "&amp;" : ch == '"' ? "&quot;" : std::string(1, ch);
    return o;
}

std::string verdict(bool pass) { return pass ? "<span class=pass>pass</span>" : "<span class=fail>FAIL</span>"; }

std::string caseSection(const CaseRecord& r) {
    std::string s = fmt::format("<h2 id=\"{0}\">{0} {1}</h2>\n<p><b>{2}</b> &middot; {3} &middot; reference: {4} &middot; {5}</p>\n",
                                html(r.c->name), verdict(r.pass()), html(r.c->category), html(r.c->title),
                                html(r.c->reference), duration(r.seconds));
    if (!r.error.empty()) s += "<p class=fail>the case could not run: " + html(r.error) + "</p>\n";
    for (const auto& n : r.result.notes) s += "<p class=note>" + html(n) + "</p>\n";
    for (const Chart& ch : r.result.charts)
        s += fmt::format("<img src=\"cases/{}/{}\" alt=\"{}\">\n", html(r.c->name), html(ch.file), html(ch.spec.title));
    s += "<table><tr><th>check</th><th>measured</th><th>std. error</th><th></th><th>reference</th><th>|difference|</th>"
         "<th>tolerance or margin</th><th>basis</th><th></th></tr>\n";
    for (const Check& k : r.result.checks)
        s += fmt::format("<tr><td>{}</td><td>{:.5g}</td><td>{:.2g}</td><td>{}</td><td>{:.5g}</td><td>{:.3g}</td><td>{:.3g}</td><td>{}</td>"
                         "<td>{}</td></tr>\n",
                         html(k.label), k.measured, k.stderr_, html(k.relation()), k.reference, std::abs(k.measured - k.reference),
                         k.tolerance, html(k.why), verdict(k.pass()));
    return s + "</table>\n";
}

std::string reportHtml(const std::vector<CaseRecord>& recs, const ValidateOptions& o, double seconds) {
    int failed = 0;
    for (const auto& r : recs) failed += !r.pass();
    std::string s = R"(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>Littoral validation report</title>
<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}table{border-collapse:collapse;margin:0.5em 0 1.5em}
td,th{border:1px solid #ccc;padding:2px 6px;font-size:90%}th{background:#eee}.pass{color:#161;font-weight:bold}
.fail{color:#b00;font-weight:bold}.note{color:#555}img{max-width:100%;display:block;margin:0.5em 0}</style></head><body>
)";
    s += fmt::format("<h1>Littoral validation report</h1>\n<p>{} setting, {} case(s), {} failed, {} in all. "
                     "Each check compares a measured value with an independent reference within the tolerance shown "
                     "(its basis beside it); <code>summary.json</code> holds the same numbers.</p>\n",
                     o.quick ? "--quick" : "full", recs.size(), failed, duration(seconds));
    s += "<table><tr><th>case</th><th>category</th><th>checks passed</th><th>time</th><th></th></tr>\n";
    for (const auto& r : recs) {
        const long ok = std::count_if(r.result.checks.begin(), r.result.checks.end(), [](const Check& k) { return k.pass(); });
        s += fmt::format("<tr><td><a href=\"#{0}\">{0}</a></td><td>{1}</td><td>{2} / {3}</td><td>{4}</td><td>{5}</td></tr>\n",
                         html(r.c->name), html(r.c->category), ok, r.result.checks.size(), duration(r.seconds), verdict(r.pass()));
    }
    s += "</table>\n";
    for (const auto& r : recs) s += caseSection(r);
    return s + "</body></html>\n";
}

std::vector<const Case*> selectCases(const std::vector<Case>& all, const ValidateOptions& o) {
    std::vector<const Case*> sel;
    for (const auto& name : o.cases) {
        const auto it = std::find_if(all.begin(), all.end(), [&](const Case& c) { return c.name == name; });
        if (it == all.end()) {
            std::string known;
            for (const auto& c : all) known += (known.empty() ? "" : ", ") + c.name;
            throw InputError(fmt::format("--case: unknown validation case '{}'; the cases are {}", name, known));
        }
    }
    for (const auto& c : all)
        if (o.cases.empty() ? (c.quick || !o.quick) : std::count(o.cases.begin(), o.cases.end(), c.name) > 0) sel.push_back(&c);
    return sel;
}

CaseRecord runCase(const Case& c, Context& ctx, const fs::path& out) {
    CaseRecord rec{&c, {}, 0, ""};
    const auto t0 = std::chrono::steady_clock::now();
    const log::Level level = log::level();
    log::setLevel(std::max(level, log::Level::Warn));  // the runs' own progress lines would bury the suite's
    Progress::setEnabled(false);
    try {
        rec.result = c.run(ctx);
    } catch (const InputError& e) {
        rec.error = e.where().str().empty() ? e.message() : e.where().str() + ": " + e.message();
    } catch (const std::exception& e) {
        rec.error = e.what();
    }
    log::setLevel(level);
    rec.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (const std::string why = drawCharts(out / "cases" / c.name, rec.result.charts); !why.empty()) rec.result.notes.push_back(why);
    publishStagedOutputs();  // each case's outputs are complete when the next one starts
    return rec;
}

}  // namespace

std::vector<ValidationCaseInfo> validationCases() {
    std::vector<ValidationCaseInfo> v;
    for (const auto& c : suite()) v.push_back({c.name, c.category, c.quick});
    return v;
}

// An earlier validation into the same folder: its report, summary, cases/ and runs/ go first, so
// that the folder never holds two runs' cases (the command holds the folder's lock).
void removeEarlierValidation(const fs::path& out) {
    std::error_code ec;
    bool any = false;
    for (const char* f : {"report.html", "summary.json"}) any = fs::remove(out / f, ec) || any;
    for (const char* d : {"cases", "runs"})
        if (fs::is_directory(out / d, ec)) any = fs::remove_all(out / d, ec) > 0 || any;
    if (any) log::info("removed the report, summary, cases/ and runs/ of an earlier validation in {}", out.string());
}

ValidateOutcome runValidation(const ValidateOptions& o) {
    const std::vector<Case> all = suite();
    const std::vector<const Case*> sel = selectCases(all, o);
    const fs::path out(o.out);
    removeEarlierValidation(out);
    Context ctx{out / "runs", o.quick, o.threads, {}};
    const double scale = o.quick ? 1.0 : 4.0;  // the full setting's cases take about 4x their quick cost
    double totalCost = 0, doneCost = 0;
    for (const Case* c : sel) totalCost += c->quickCost * scale;
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<CaseRecord> recs;
    for (size_t i = 0; i < sel.size(); ++i) {
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double left = doneCost > 0 ? elapsed / doneCost * (totalCost - doneCost) : totalCost - doneCost;
        if (o.progress)
            std::fprintf(stderr, "validate [%zu/%zu] %s (%s): elapsed %s, about %s left\n", i + 1, sel.size(), sel[i]->name.c_str(),
                         sel[i]->category.c_str(), duration(elapsed).c_str(), duration(left).c_str());
        recs.push_back(runCase(*sel[i], ctx, out));
        doneCost += sel[i]->quickCost * scale;
        if (o.progress)
            std::fprintf(stderr, "  %s in %s%s\n", recs.back().pass() ? "passed" : "FAILED", duration(recs.back().seconds).c_str(),
                         recs.back().error.empty() ? "" : (": " + recs.back().error).c_str());
    }
    ValidateOutcome res;
    res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    writeTextFileAtomic(out / "summary.json", summaryJson(recs, o, res.seconds).dump(2) + "\n");
    writeTextFileAtomic(out / "report.html", reportHtml(recs, o, res.seconds));
    for (const auto& r : recs) {
        ++res.cases;
        res.failedCases += !r.pass();
        for (const Check& k : r.result.checks) ++res.checks, res.failedChecks += !k.pass();
        res.summary += fmt::format("  {:<34} {:<22} {:>3} checks  {:>9}  {}\n", r.c->name, r.c->category, r.result.checks.size(),
                                   duration(r.seconds), r.pass() ? "pass" : "FAIL");
        for (const Check& k : r.result.checks)
            if (!k.pass())
                res.summary += fmt::format("      failed: {}: {:.5g} +- {:.2g} against {:.5g} (tolerance {:.3g})\n", k.label, k.measured,
                                           k.stderr_, k.reference, k.tolerance);
    }
    res.summary = fmt::format("validate ({}): {} of {} cases passed, {} of {} checks, in {}\n", o.quick ? "quick" : "full",
                              res.cases - res.failedCases, res.cases, res.checks - res.failedChecks, res.checks, duration(res.seconds)) +
                  res.summary + fmt::format("  {}\n  {}\n", (out / "report.html").string(), (out / "summary.json").string());
    return res;
}

}  // namespace littoral::pipelines
