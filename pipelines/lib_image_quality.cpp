#include "pipelines/lib_image_quality.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"
#include "pipelines/lib_scene.h"
#include "pipelines/lib_plot.h"
#include "render/render_job.h"
#include "scenegen/assemble.h"
#include "scenegen/mesh_io.h"
#include "scenegen/primitives.h"
#include "scenegen/scene_file.h"

namespace littoral::pipelines {

namespace fs = std::filesystem;

namespace {

RegionStats stats(const std::vector<double>& v) {
    RegionStats s;
    s.pixels = static_cast<int>(v.size());
    if (v.size() < 2) return s;
    double sum = 0, sq = 0;
    for (double x : v) sum += x;
    s.mean = sum / static_cast<double>(v.size());
    for (double x : v) sq += (x - s.mean) * (x - s.mean);
    s.stddev = std::sqrt(sq / static_cast<double>(v.size() - 1));
    s.snr = s.stddev > 0 ? s.mean / s.stddev : INFINITY;
    return s;
}

// First position, walking from index `from` in direction `step`, where `f` crosses `level`
// (linear interpolation between bin centres); NaN if it never does.
double crossing(const std::vector<double>& x, const std::vector<double>& f, int from, int step, double level) {
    for (int i = from; i + step >= 0 && i + step < static_cast<int>(f.size()); i += step) {
        const double a = f[i] - level, b = f[i + step] - level;
        if (a == 0) return x[i];
        if ((a > 0) != (b > 0)) return x[i] + (x[i + step] - x[i]) * a / (a - b);
    }
    return NAN;
}

// Table 9.6 (digest seed-ch08-09.md Sec. 3.2): absorption and scattering, m^-1.
struct WaterType {
    const char* name;
    double a, b;
};
constexpr WaterType kWaters[] = {{"coastal", 0.038, 0.35}, {"bay", 0.143, 0.180}, {"turbid", 0.27, 0.95}};

const WaterType& waterType(const std::string& name) {
    for (const WaterType& w : kWaters)
        if (name == w.name) return w;
    throw InputError(fmt::format("--water {}: unknown water type; allowed: coastal, bay, turbid", name));
}

// The image's pixels within the edge's length: binned by their signed distance from the edge
// (sums and counts of `nb` ESF bins), and those of the bright and dark side regions.
struct EdgeSamples {
    std::vector<double> sum;
    std::vector<int> count;
    std::vector<double> bright, dark;
};

EdgeSamples sampleEdge(const std::vector<float>& plane, const PixelGrid& g, const EdgeGeometry& e,
                       const EdgeAnalysisOptions& o, int nb) {
    EdgeSamples s{std::vector<double>(nb, 0.0), std::vector<int>(nb, 0), {}, {}};
    for (int j = 0; j < g.height; ++j)
        for (int i = 0; i < g.width; ++i) {
            const double px = g.x0 + (i + 0.5) * g.pixel - e.cx, py = g.y0 - (j + 0.5) * g.pixel - e.cy;
            const double d = px * e.nx + py * e.ny, along = -px * e.ny + py * e.nx;
            if (std::abs(along) > e.halfLength) continue;
            const double v = plane[static_cast<size_t>(j) * g.width + i];
            if (d <= -o.margin && d >= -o.margin - o.regionWidth) s.bright.push_back(v);
            if (d >= o.margin && d <= o.margin + o.regionWidth) s.dark.push_back(v);
            const int b = static_cast<int>(std::floor((d + o.esfHalfRange) / o.binWidth));
            if (b >= 0 && b < nb) s.sum[b] += v, ++s.count[b];
        }
    return s;
}

// Oversampled ESF; an empty bin (possible far from the edge) takes its neighbours' mean.
void oversampledEsf(const EdgeSamples& s, const EdgeAnalysisOptions& o, EdgeMeasures* m) {
    for (int b = 0; b < static_cast<int>(s.count.size()); ++b) {
        const double x = -o.esfHalfRange + (b + 0.5) * o.binWidth;
        if (s.count[b] == 0) {
            if (std::abs(x) < 1.0)
                throw InputError(fmt::format("ESF bin at {:.3f} m from the edge holds no pixel: the edge must be slanted "
                                             "against the pixel grid",
                                             x));
            continue;
        }
        m->esfX.push_back(x);
        m->esf.push_back(s.sum[b] / s.count[b]);
    }
}

// Box-car mean over `width` neighbouring values (fewer at the ends).
std::vector<double> boxcar(const std::vector<double>& v, int width) {
    const int n = static_cast<int>(v.size()), h = width / 2;
    std::vector<double> sm(n);
    for (int i = 0; i < n; ++i) {
        double s = 0;
        int c = 0;
        for (int k = std::max(0, i - h); k <= std::min(n - 1, i + h); ++k) s += v[k], ++c;
        sm[i] = s / c;
    }
    return sm;
}

// The LSF as minus the derivative of the smoothed ESF `sm` (the ESF falls from bright to dark),
// normalised to unit area, and its FWHM. Returns the index of the LSF's peak.
int lineSpread(const std::vector<double>& sm, const EdgeAnalysisOptions& o, EdgeMeasures* m) {
    for (int i = 1; i + 1 < static_cast<int>(sm.size()); ++i) {
        m->lsfX.push_back(m->esfX[i]);
        m->lsf.push_back(-(sm[i + 1] - sm[i - 1]) / (m->esfX[i + 1] - m->esfX[i - 1]));
    }
    double area = 0;
    for (double v : m->lsf) area += v * o.binWidth;
    if (area != 0)
        for (double& v : m->lsf) v /= area;
    const int peak = static_cast<int>(std::max_element(m->lsf.begin(), m->lsf.end()) - m->lsf.begin());
    const double half = 0.5 * m->lsf[peak];
    m->fwhm = crossing(m->lsfX, m->lsf, peak, +1, half) - crossing(m->lsfX, m->lsf, peak, -1, half);
    return peak;
}

// Adds `why` to the measures' list of undefined ones.
void noteUndefined(EdgeMeasures* m, const std::string& why) { m->undefined += (m->undefined.empty() ? "" : "; ") + why; }

// 10-90% width and tails from the smoothed ESF `sm` between its plateaus (the outer quarter of
// the range on each side): robust against the derivative's noise. `tailSe` is the standard error
// of one tails window's mean (the pixels' spread over the pixels in a window).
void edgeWidthAndTails(const std::vector<double>& sm, int peak, const EdgeAnalysisOptions& o, double tailSe,
                       EdgeMeasures* m) {
    const int n = static_cast<int>(sm.size());
    double hi = 0, lo = 0;
    int ch = 0, cl = 0;
    for (int i = 0; i < n; ++i) {
        if (m->esfX[i] < -0.5 * o.esfHalfRange) hi += sm[i], ++ch;
        if (m->esfX[i] > 0.5 * o.esfHalfRange) lo += sm[i], ++cl;
    }
    hi /= std::max(ch, 1), lo /= std::max(cl, 1);
    const int peakEsf = peak + 1;  // lsf[i] sits at esfX[i + 1]
    m->width1090 = crossing(m->esfX, sm, peakEsf, +1, lo + 0.1 * (hi - lo)) -
                   crossing(m->esfX, sm, peakEsf, -1, lo + 0.9 * (hi - lo));
    if (std::isnan(m->width1090))
        noteUndefined(m, fmt::format("the ESF does not cross its 10 % and 90 % levels within {:g} m of the edge, so "
                                     "the 10-90 % width is undefined",
                                     o.esfHalfRange));
    // Tails: the share of the step still missing, on average, between tailFrom and 2 tailFrom on
    // either side of the LSF's peak (window means keep the ESF's noise down).
    const double xp = m->lsfX[peak];
    auto windowMean = [&](double a, double b) {
        double s = 0;
        int c = 0;
        for (int i = 0; i < n; ++i)
            if (m->esfX[i] >= a && m->esfX[i] <= b) s += sm[i], ++c;
        return c ? s / c : NAN;
    };
    const double eBright = windowMean(xp - 2 * o.tailFrom, xp - o.tailFrom);
    const double eDark = windowMean(xp + o.tailFrom, xp + 2 * o.tailFrom);
    const double step = hi - lo, tail = 1.0 - (eBright - eDark) / step;
    // A share lies in [0, 1]. An estimate outside it by less than 3 of its standard errors is noise
    // and is clipped; one farther out (or no window) means the windows measure noise, not tails.
    const double se = std::sqrt(2.0) * tailSe / std::abs(step);
    if (!(step > 0) || !std::isfinite(tail) || tail < -3 * se || tail > 1 + 3 * se) {
        m->tailFraction = NAN;
        noteUndefined(m, fmt::format("the tails estimate {:.3g} lies outside [0, 1] by more than 3 of its standard "
                                     "errors ({:.2g}), so the tails are undefined",
                                     tail, se));
    } else {
        m->tailFraction = std::clamp(tail, 0.0, 1.0);
    }
}

void checkStudyOptions(const ImageQualityOptions& o) {
    if (o.pixels < 24 || o.pixels > 2048) throw InputError(fmt::format("--pixels {}: allowed 24 to 2048", o.pixels));
    if (!(o.g > -1 && o.g < 1)) throw InputError(fmt::format("--g {}: allowed (-1, 1)", o.g));
    for (double d : o.depths)
        if (!(d > 0 && d <= 6)) throw InputError(fmt::format("--depths: {} m is not allowed; allowed (0, 6] m", d));
    for (double r : o.radii)
        if (!(r >= 0.01 && r <= 10)) throw InputError(fmt::format("--radii: {} m is not allowed; allowed [0.01, 10] m", r));
    for (double n : o.densities)
        if (!(n >= 10 && n <= 1e6))
            throw InputError(fmt::format("--densities: {} photons/m^3 is not allowed; allowed [10, 1e6]", n));
}

constexpr double kGsd = 0.25, kWaterDepth = 8.0, kHeadingDeg = 5.0;  // Sec. 3.1 of the digest

// What every run of the study shares: the water, the image and the step target in it.
struct StudySetup {
    const WaterType* water = nullptr;
    double side = 0;    // image footprint = one period of the domain, m
    double target = 0;  // the step target's side, m
    double volume = 0;  // water volume (less the thin target), m^3
    EdgeGeometry edge;
    PixelGrid grid;
};

StudySetup studySetup(const ImageQualityOptions& o, const WaterType& water) {
    StudySetup s;
    s.water = &water;
    s.side = o.pixels * kGsd;
    s.target = 0.75 * s.side;
    s.volume = s.side * s.side * kWaterDepth;
    const double th = kHeadingDeg * M_PI / 180;
    s.edge.nx = std::cos(th), s.edge.ny = -std::sin(th);  // object +x (the dark half) in world coordinates
    s.grid = PixelGrid{o.pixels, o.pixels, kGsd, -0.5 * s.side, 0.5 * s.side};
    for (double r : o.radii)
        if (0.5 * s.target - 2 * std::max(0.5, r + 0.25) < 0.5)
            throw InputError(fmt::format("--radii: {} m is too large for the {} m target of a {}-pixel image; allowed up "
                                         "to {:.2f} m (or more --pixels)",
                                         r, s.target, o.pixels, (0.5 * s.target - 0.5) / 2 - 0.25));
    return s;
}

// One run's parameters: the target's depth, the volume photon density and the search radius.
struct RunPoint {
    double depth, density, radius;
    std::string id;              // names the run's folder
    long long surfacePhotons, volumePhotons;
};

std::string runSceneYaml(const ImageQualityOptions& o, const StudySetup& s, const RunPoint& p) {
    return fmt::format(
        "# Chapter 9 image-quality study: step target {depth} m deep, {dens} volume photons/m^3, search "
        "radius {r} m\n"
        "# (written by `littoral study image-quality`; docs/image-quality.md)\n"
        "scene: {{name: iq-{id}, domain: {{x: [{h0}, {h1}], y: [{h0}, {h1}]}}}}\n"
        "sun: {{zenith_deg: 30, azimuth_deg: 180}}\n"
        "sky: {{model: simple, hemisphere_irradiance: 1000, sky_fraction: 0.2}}\n"
        "water:\n"
        "  level_m: 0\n"
        "  horizontal: periodic\n"
        "  surface: {{model: flat}}\n"
        "  optics: {{refractive_index: 1.34, absorption_per_m: {a}, scattering_per_m: {b}, phase: {{type: "
        "henyey-greenstein, g: {g}}}, solver: medium-pm}}\n"
        "bathymetry: {{type: planar_slope, z0_m: -{wd}, spacing_m: 2, material: ground}}\n"
        "materials:\n"
        "  - {{name: ground, reflectance: 0.1, solver: surface-pm}}\n"
        "  - {{name: target-bright, reflectance: 0.8, solver: surface-pm}}\n"
        "  - {{name: target-dark, reflectance: 0.02, solver: surface-pm}}\n"
        "objects:\n"
        "  - {{name: step, mesh: step_target.ply, materials: [target-bright, target-dark], position_m: [0, 0], "
        "heading_deg: {hd}, z_m: -{depth}}}\n"
        "sensors:\n"
        "  - {{name: nadir, type: orthographic, position: [0, 0, 30], direction: [0, 0, -1], up: [0, 1, 0], "
        "pixel_size_m: {gsd}, width: {px}, height: {px}, samples_per_pixel: {spp}}}\n"
        "render:\n"
        "  bands: [[0.4, 0.7]]\n"
        "  estimator: dirsig\n"
        "  seed: {seed}\n"
        "  photons: {{surface: {ns}, volume: {nv}}}\n"
        "  search_radius_m: {{surface: {r}, volume: {r}}}\n",
        fmt::arg("depth", p.depth), fmt::arg("dens", p.density), fmt::arg("r", p.radius), fmt::arg("id", p.id),
        fmt::arg("h0", -0.5 * s.side), fmt::arg("h1", 0.5 * s.side), fmt::arg("a", s.water->a),
        fmt::arg("b", s.water->b), fmt::arg("g", o.g), fmt::arg("wd", kWaterDepth), fmt::arg("hd", kHeadingDeg),
        fmt::arg("gsd", kGsd), fmt::arg("px", o.pixels), fmt::arg("spp", o.samplesPerPixel), fmt::arg("seed", o.seed),
        fmt::arg("ns", p.surfacePhotons), fmt::arg("nv", p.volumePhotons));
}

// Writes the run's scene and target mesh, builds and renders it, and measures the edge.
ImageQualityRow runOne(const ImageQualityOptions& o, const StudySetup& s, double depth, double density,
                       double radius, const fs::path& out) {
    const auto t0 = std::chrono::steady_clock::now();
    const RunPoint p{depth,
                     density,
                     radius,
                     fmt::format("d{:g}_n{:g}_r{:g}", depth, density, radius),
                     std::llround(o.surfacePerVolume * density * s.side * s.side),
                     std::llround(density * s.volume)};
    const fs::path dir = out / "runs" / p.id;
    createOutputFolder(dir);
    scenegen::writeMeshFile(dir / "step_target.ply", scenegen::makeStepTarget(s.target, 0.5));
    // The margin grows with the radius: the side regions keep a search radius and a pixel away
    // from the step edge and from the target's outer edges, so that neither the other half nor the
    // seabed around the target reaches them through the search disc (that is edge bias, measured
    // by the ESF, not noise).
    EdgeAnalysisOptions eo;
    eo.margin = std::max(0.5, radius + 0.25);
    eo.regionWidth = std::min(3.0, 0.5 * s.target - 2 * eo.margin);
    EdgeGeometry ed = s.edge;
    ed.halfLength = 0.5 * s.target - eo.margin;
    writeTextFileAtomic(dir / "scene.yaml", runSceneYaml(o, s, p));
    // The build reads the scene and its mesh from disk, the render the IR: they are renamed into
    // place but stay in the study's one output set (an interrupted or failed study leaves nothing).
    exposeStagedOutputs();
    checkRenderSettings(scenegen::loadSceneFile(dir / "scene.yaml"));
    const auto built = scenegen::buildScene(dir / "scene.yaml", dir / "ir");
    exposeStagedOutputs();
    render::RenderJobOptions jo;
    jo.tileCheckpoint = false;  // the study's runs are one output set: an interrupt leaves nothing
    jo.threads = o.threads;
    jo.progress = false;
    const auto res = render::runRenderJob(built.ir, dir / "ir", dir, jo);
    LITTORAL_CHECK(res.images.size() == 1);
    ImageQualityRow row{depth,
                        radius,
                        density,
                        p.surfacePhotons,
                        p.volumePhotons,
                        analyseEdge(res.images[0].film.bandPlane(0), s.grid, ed, eo),
                        0};
    row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return row;
}

// A measure as the CSV and the summary write it: 4 decimals, or `none` (empty in the CSV) if it is
// undefined for this run (EdgeMeasures::undefined says why).
std::string defined(double v, const char* none = "") { return std::isnan(v) ? none : fmt::format("{:.4f}", v); }

void writeTable(const std::vector<ImageQualityRow>& rows, const fs::path& out) {
    std::string csv =
        "depth_m,search_radius_m,volume_density_per_m3,surface_photons,volume_photons,bright_mean,bright_std,bright_snr,"
        "dark_mean,dark_std,dark_snr,fwhm_m,width_10_90_m,tail_fraction,seconds\n";
    for (const auto& r : rows)
        csv += fmt::format("{},{},{},{},{},{:.6g},{:.6g},{:.4g},{:.6g},{:.6g},{:.4g},{},{},{},{:.1f}\n", r.depth,
                           r.radius, r.density, r.surfacePhotons, r.volumePhotons, r.m.bright.mean, r.m.bright.stddev,
                           r.m.bright.snr, r.m.dark.mean, r.m.dark.stddev, r.m.dark.snr, defined(r.m.fwhm),
                           defined(r.m.width1090), defined(r.m.tailFraction), r.seconds);
    writeTextFileAtomic(out / "image_quality.csv", csv);
}

// SNR against the radius (per depth and density, both sides), FWHM and tails against the radius.
void addRadiusFigures(const ImageQualityOptions& o, const std::vector<ImageQualityRow>& rows, std::vector<Chart>* charts) {
    PlotSpec snr = plotSpec("SNR against search radius (" + o.water + fmt::format(", HG g = {})", o.g),
                            "search radius (m)", "SNR", true, true);
    PlotSpec fw = plotSpec("LSF FWHM and 10-90% edge width", "search radius (m)", "m");
    PlotSpec tail = plotSpec("Share of the LSF beyond 0.5 m of its peak", "search radius (m)", "fraction");
    for (double depth : o.depths)
        for (double density : o.densities) {
            PlotSeries sb = plotSeries(fmt::format("bright {:g} m, {:g}/m3", depth, density));
            PlotSeries sd = plotSeries(fmt::format("dark {:g} m, {:g}/m3", depth, density));
            PlotSeries f1 = plotSeries(fmt::format("FWHM {:g} m, {:g}/m3", depth, density));
            PlotSeries f2 = plotSeries(fmt::format("10-90 {:g} m, {:g}/m3", depth, density));
            PlotSeries t1 = plotSeries(fmt::format("{:g} m, {:g}/m3", depth, density));
            sd.dashed = f2.dashed = true;
            for (const auto& r : rows)
                if (r.depth == depth && r.density == density) {
                    sb.x.push_back(r.radius), sb.y.push_back(r.m.bright.snr);
                    sd.x.push_back(r.radius), sd.y.push_back(r.m.dark.snr);
                    f1.x.push_back(r.radius), f1.y.push_back(r.m.fwhm);
                    f2.x.push_back(r.radius), f2.y.push_back(r.m.width1090);
                    t1.x.push_back(r.radius), t1.y.push_back(r.m.tailFraction);
                }
            snr.series.push_back(sb), snr.series.push_back(sd);
            fw.series.push_back(f1), fw.series.push_back(f2);
            tail.series.push_back(t1);
        }
    charts->push_back({"snr_vs_radius.png", snr});
    charts->push_back({"fwhm_vs_radius.png", fw});
    charts->push_back({"tails_vs_radius.png", tail});
}

// SNR against the photon density, per depth and radius (only with several densities).
void addDensityFigure(const ImageQualityOptions& o, const std::vector<ImageQualityRow>& rows, std::vector<Chart>* charts) {
    if (o.densities.size() <= 1) return;
    PlotSpec sn = plotSpec("SNR against photon density", "volume photons per m^3", "SNR", true, true);
    for (double depth : o.depths)
        for (double radius : o.radii) {
            PlotSeries sb = plotSeries(fmt::format("bright {:g} m, SR {:g}", depth, radius));
            for (const auto& r : rows)
                if (r.depth == depth && r.radius == radius) sb.x.push_back(r.density), sb.y.push_back(r.m.bright.snr);
            sn.series.push_back(sb);
        }
    charts->push_back({"snr_vs_density.png", sn});
}

// Per depth, the ESFs and LSFs of the densest runs: a table and two figures.
void writeEdgeProfiles(const ImageQualityOptions& o, const std::vector<ImageQualityRow>& rows, const fs::path& out,
                       std::vector<Chart>* charts) {
    const double densest = *std::max_element(o.densities.begin(), o.densities.end());
    for (double depth : o.depths) {
        PlotSpec es = plotSpec(fmt::format("ESF, target {:g} m deep, {:g} photons/m^3", depth, densest),
                               "distance from the edge (m)", "radiance (W m^-2 sr^-1 um^-1)");
        PlotSpec ls = plotSpec(fmt::format("LSF, target {:g} m deep, {:g} photons/m^3", depth, densest),
                               "distance from the edge (m)", "per m (unit area)");
        std::string ecsv = "distance_m";
        std::vector<const ImageQualityRow*> sel;
        for (const auto& r : rows)
            if (r.depth == depth && r.density == densest) {
                sel.push_back(&r);
                ecsv += fmt::format(",esf_r{:g},lsf_r{:g}", r.radius, r.radius);
                PlotSeries e = plotSeries(fmt::format("SR {:g} m", r.radius)), l = e;
                e.x = r.m.esfX, e.y = r.m.esf, l.x = r.m.lsfX, l.y = r.m.lsf;
                e.markers = l.markers = false;
                es.series.push_back(std::move(e)), ls.series.push_back(std::move(l));
            }
        ecsv += "\n";
        for (size_t i = 0; !sel.empty() && i < sel[0]->m.esfX.size(); ++i) {
            ecsv += fmt::format("{:.4f}", sel[0]->m.esfX[i]);
            for (const auto* r : sel) {
                const bool ok = i < r->m.esfX.size();
                const auto it = std::find(r->m.lsfX.begin(), r->m.lsfX.end(), ok ? r->m.esfX[i] : NAN);
                ecsv += fmt::format(",{:.6g},{}", ok ? r->m.esf[i] : NAN,
                                    it != r->m.lsfX.end() ? fmt::format("{:.6g}", r->m.lsf[it - r->m.lsfX.begin()]) : "");
            }
            ecsv += "\n";
        }
        writeTextFileAtomic(out / fmt::format("esf_d{:g}.csv", depth), ecsv);
        charts->push_back({fmt::format("esf_d{:g}.png", depth), es});
        charts->push_back({fmt::format("lsf_d{:g}.png", depth), ls});
    }
}

std::string summaryText(const std::vector<ImageQualityRow>& rows, const fs::path& out) {
    std::string s = fmt::format("image-quality study: {} runs -> {}\n", rows.size(), out.string());
    s += "  depth  density  radius   SNR bright  SNR dark   FWHM m  10-90 m  tails\n";
    for (const auto& r : rows)
        s += fmt::format("  {:5g}  {:7g}  {:6g}   {:10.1f}  {:8.1f}   {:>6}  {:>7}  {:>5}\n", r.depth, r.density,
                         r.radius, r.m.bright.snr, r.m.dark.snr, defined(r.m.fwhm, "-"), defined(r.m.width1090, "-"),
                         defined(r.m.tailFraction, "-"));
    return s;
}

}  // namespace

EdgeMeasures analyseEdge(const std::vector<float>& plane, const PixelGrid& g, const EdgeGeometry& e,
                         const EdgeAnalysisOptions& o) {
    LITTORAL_CHECK(plane.size() == static_cast<size_t>(g.width) * static_cast<size_t>(g.height));
    EdgeMeasures m;
    const int nb = static_cast<int>(std::round(2 * o.esfHalfRange / o.binWidth));
    const EdgeSamples s = sampleEdge(plane, g, e, o, nb);
    m.bright = stats(s.bright);
    m.dark = stats(s.dark);
    if (m.bright.pixels < 2 || m.dark.pixels < 2)
        throw InputError(fmt::format("the image holds too few pixels on the sides of the edge ({} bright, {} dark): "
                                     "the target must fill the image beyond {} m from the edge",
                                     m.bright.pixels, m.dark.pixels, o.margin + o.regionWidth));
    oversampledEsf(s, o, &m);
    const std::vector<double> sm = boxcar(m.esf, o.smoothBins);
    const int peak = lineSpread(sm, o, &m);
    // The pixels in one tails window (tailFrom wide, the edge's length long) and the spread of a
    // pixel about its side's mean give the window mean's standard error.
    const double windowPixels = std::max(1.0, o.tailFrom * 2 * e.halfLength / (g.pixel * g.pixel));
    const double pixelSpread = std::sqrt(0.5 * (m.bright.stddev * m.bright.stddev + m.dark.stddev * m.dark.stddev));
    edgeWidthAndTails(sm, peak, o, pixelSpread / std::sqrt(windowPixels), &m);
    // The edge measures need a step: bright minus dark at least kResolvedSigmas standard errors of
    // the two sides' means (the pixels are correlated by the search disc, so the standard errors
    // from their spread are optimistic: hence the margin).
    constexpr double kResolvedSigmas = 4;
    const double contrast = m.bright.mean - m.dark.mean;
    const double se = std::sqrt(m.bright.stddev * m.bright.stddev / m.bright.pixels +
                                m.dark.stddev * m.dark.stddev / m.dark.pixels);
    if (!(contrast > kResolvedSigmas * se)) {
        m.fwhm = m.width1090 = m.tailFraction = NAN;
        m.undefined = fmt::format("the step is not resolved: bright minus dark is {:.3g} +- {:.2g}, less than {:g} "
                                  "standard errors, so the FWHM, 10-90 % width and tails are undefined (raise the "
                                  "photon density or the samples per pixel)",
                                  contrast, se, kResolvedSigmas);
    } else if (std::isnan(m.fwhm)) {
        noteUndefined(&m, "the LSF does not fall to half its peak on both sides, so the FWHM is undefined");
    }
    return m;
}

std::vector<ImageQualityRow> runImageQualityStudy(const ImageQualityOptions& o, std::string* summary) {
    const WaterType& water = waterType(o.water);
    checkStudyOptions(o);
    const fs::path out(o.out);
    createOutputFolder(out, "--out");
    const StudySetup setup = studySetup(o, water);

    std::vector<ImageQualityRow> rows;
    const size_t total = o.depths.size() * o.radii.size() * o.densities.size();
    for (double depth : o.depths)
        for (double density : o.densities)
            for (double radius : o.radii) {
                ImageQualityRow row = runOne(o, setup, depth, density, radius, out);
                if (o.progress)
                    log::info("image quality {}/{}: depth {} m, {} photons/m^3, radius {} m: SNR bright {:.1f}, dark "
                              "{:.1f}; FWHM {} m ({:.1f} s)",
                              rows.size() + 1, total, depth, density, radius, row.m.bright.snr, row.m.dark.snr,
                              defined(row.m.fwhm, "undefined"), row.seconds);
                if (!row.m.undefined.empty())
                    log::warn("image quality: depth {} m, {} photons/m^3, radius {} m: {}", depth, density, radius,
                              row.m.undefined);
                rows.push_back(std::move(row));
            }

    writeTable(rows, out);
    std::vector<Chart> charts;
    addRadiusFigures(o, rows, &charts);
    addDensityFigure(o, rows, &charts);
    writeEdgeProfiles(o, rows, out, &charts);
    if (const std::string why = drawCharts(out, charts); !why.empty()) log::warn("image quality: {}", why);
    if (summary) *summary = summaryText(rows, out);
    return rows;
}

}  // namespace littoral::pipelines
