// Scattering water (issue 8): energy conservation, Beer–Lambert per band through layers, the
// two-stream model, instrument self-shading and the honesty of the probes' standard errors, all
// with the path estimator (and the dirsig estimator where it applies).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/units.h"
#include "render/estimator.h"
#include "render/probes.h"
#include "render/renderer.h"
#include "tests/render/render_test_scenes.h"
#include "pipelines/reference/gordon_ding.h"
#include "tests/support/two_stream.h"

namespace littoral::render {
namespace {

using namespace testing;
using M = ir::Material;

ir::Material white(const std::string& name, double r) {
    ir::Material m;
    m.name = name;
    m.reflectance = Spectrum::constant(r);
    return m;
}

ir::Material blackMaterial(const std::string& name) {
    ir::Material m;
    m.name = name;
    m.type = M::Type::Black;
    return m;
}

ir::Probe probeAt(const std::string& name, Point3 p, std::vector<std::string> q, int samples) {
    ir::Probe pr;
    pr.name = name;
    pr.position = p;
    pr.quantities = std::move(q);
    pr.medium = "water";
    pr.samples = samples;
    return pr;
}

const ProbeValue& find(const std::vector<ProbeValue>& v, const std::string& q) {
    for (const auto& x : v)
        if (x.quantity == q) return x;
    throw std::runtime_error("no quantity " + q);
}

// ---------------------------------------------------------------------------------------------
// White furnace. A non-absorbing, scattering water slab (n = 1.34, HG g = 0.8, b = 0.6 m^-1,
// 3 m deep, horizontally periodic) over a white Lambertian floor (r = 1) under a uniform sky of
// radiance L. Nothing absorbs, so the field is in equilibrium everywhere: radiance L in air in
// every direction, n^2 L in the water (Fresnel reflection and transmission conserve energy, the
// n^2 law scales radiance across the surface, scattering only redirects, the floor returns
// r E / pi = n^2 L). A camera above sees L in every pixel; in the water Ed = Eu = pi n^2 L,
// Eod = Eou = 2 pi n^2 L, Lu = n^2 L. Every factor of the transport (cosines, pdfs, Fresnel
// weights, phase normalisation, free-flight weights, the n^2 law) enters, so an error in any of
// them shows. Every path ends at the sky carrying weight exactly 1 when all of them are right, so
// the estimate is exact to rounding (before the periodic-wall fix, paths grazing a wall were lost
// and this test measured a 0.02 % deficit at 2–3 standard errors). Tolerance: 4 standard errors
// (pixels: their spread over sqrt(pixels); probes: batch standard errors) plus rounding, and each
// standard error must be below 1 %.
TEST(PathEstimator, WhiteFurnaceConservesRadiance) {
    const double L = 1.0 / kPi, n = 1.34;
    ir::SceneIR s = uniformSkyScene();
    s.render.estimator = ir::Estimator::Path;
    s.render.settings.set("probe_batches", 16);
    s.materials.push_back(white("white-floor", 1.0));
    addPeriodicSlab(s, water(0.0, 0.6, n, {"henyey-greenstein", {{"g", 0.8}}}), 5.0, 3.0, "white-floor");
    ir::Sensor cam = ortho("above", {0.3, 0.2, 10}, {0, 0, -1}, {0, 1, 0}, 8, 8, 0.7);
    cam.samplesPerPixel = 256;
    s.sensors.push_back(cam);
    s.probes.push_back(probeAt("mid", {0.1, -0.2, -1.5}, {"Ed", "Eu", "Eod", "Eou", "Lu"}, 16000));
    const Scene scene(s, ".");
    const SensorImage img = renderSensor(scene, s.sensors[0], quiet());
    double sum = 0, sum2 = 0;
    const size_t np = img.film.pixels.size();
    for (float v : img.film.pixels) {
        sum += v;
        sum2 += double(v) * v;
    }
    const double mean = sum / np, se = std::sqrt((sum2 / np - mean * mean) / (np - 1));
    // (A path that ends at the sky carries weight exactly 1 here, so the estimate is exact up to
    // rounding: the film stores floats, 6e-8 relative; 1e-7 allows for that.)
    EXPECT_NEAR(mean, L, 4 * se + 1e-7 * L) << "camera";
    EXPECT_LT(se / L, 0.01);
    const auto pv = evaluateProbe(scene, s.probes[0], 0, quiet());
    const double n2L = n * n * L;
    const std::pair<const char*, double> expect[] = {
        {"Ed", kPi * n2L}, {"Eu", kPi * n2L}, {"Eod", 2 * kPi * n2L}, {"Eou", 2 * kPi * n2L}, {"Lu", n2L}};
    for (const auto& [q, e] : expect) {
        const ProbeValue& v = find(pv, q);
        EXPECT_NEAR(v.mean[0], e, 4 * v.stderr_[0] + 1e-9 * e) << q;
        EXPECT_LT(v.stderr_[0] / e, 0.01) << q;
        std::printf("[ furnace ] %-3s %.6f +- %.6f (expected %.6f)\n", q, v.mean[0], v.stderr_[0], e);
    }
    std::printf("[ furnace ] camera %.6f +- %.6f (expected %.6f)\n", mean, se, L);
}

// ---------------------------------------------------------------------------------------------
// A layer's combined phase function (LayerPhase, what Medium::phase and the volume photon-map
// queries evaluate) equals the b-weighted sum of its scatterers' own phase functions, evaluated one
// by one, in every band: Petzold's table (twice: two scatterers share it), a mixture holding the
// same table and an isotropic part, molecular water, Henyey-Greenstein and Fournier-Forand, over t
// = 1 - cos from the table's forward power law (below its first node) to straight back, node
// values included. The combination only regroups the same linear pieces: 1e-12 relative.
TEST(Media, CombinedLayerPhaseEqualsTheWeightedSumOfItsScatterers) {
    const std::vector<PhaseFunction> phases = {
        PhaseFunction::petzold(), PhaseFunction::molecularWater(), PhaseFunction::henyeyGreenstein(0.9),
        PhaseFunction::mixture({{0.7, PhaseFunction::petzold()}, {0.3, PhaseFunction::isotropic()}}),
        PhaseFunction::fournierForand(0.012), PhaseFunction::petzold()};
    // [band][scatterer]: each band's weights sum to 1; the bands differ.
    const std::vector<std::vector<double>> w = {{0.3, 0.1, 0.2, 0.15, 0.15, 0.1},
                                                {0.05, 0.5, 0.1, 0.05, 0.25, 0.05},
                                                {0.6, 0.0, 0.1, 0.1, 0.0, 0.2}};
    const LayerPhase combined(phases, w);
    std::vector<double> ts;
    for (double e = -12; e <= 0.30103; e += 0.01) ts.push_back(std::min(2.0, std::pow(10.0, e)));
    ts.push_back(2.0);
    std::shared_ptr<const TabulatedPhase> table = *std::get_if<std::shared_ptr<const TabulatedPhase>>(&phases[0].part(0));
    for (size_t j = 0; j < table->nodesOneMinusCos().size(); j += 7) ts.push_back(table->nodesOneMinusCos()[j]);
    int checked = 0;
    for (double t : ts)
        for (int begin = 0; begin < 3; ++begin)
            for (int count = 1; begin + count <= 3; ++count) {
                double out[3];
                combined.eval(t, begin, count, out);
                for (int k = 0; k < count; ++k) {
                    double expected = 0;
                    for (size_t i = 0; i < phases.size(); ++i) expected += w[begin + k][i] * phases[i].evalOneMinusCos(t);
                    ASSERT_NEAR(out[k], expected, 1e-12 * expected) << "t " << t << " band " << begin + k;
                    ++checked;
                }
            }
    EXPECT_GT(checked, 5000);
}

// Beer–Lambert per band, through two layers. Purely absorbing water with a(lambda) linear in
// lambda, so each band's mean is a at its centre (0.05, 0.25, 0.45 m^-1 in the top 2 m, twice that
// below), a sun at 40 deg zenith with a tiny disc and a black sky: the probe at 3 m depth sees
// only the refracted direct beam, Ed = E cos(40) T_f(40) exp(-(2 a1 + 1 a2) / mu_w) per band,
// mu_w = cos of the refracted angle. Exact up to the disc (half-angle 1e-5 rad: cosines vary by
// 1e-5 relative), under both estimators.
TEST(Media, BeerLambertPerBandThroughLayers) {
    for (ir::Estimator est : {ir::Estimator::Dirsig, ir::Estimator::Path}) {
        ir::SceneIR s;
        s.name = "beer";
        s.render.estimator = est;
        s.render.bands = {Band{0.40, 0.45}, Band{0.45, 0.50}, Band{0.50, 0.55}};
        s.render.settings.set("probe_samples", 64);
        s.render.settings.set("probe_batches", 4);
        s.sun.enabled = true;
        s.sun.zenith = deg2rad(40);
        s.sun.azimuth = deg2rad(30);
        s.sun.halfAngle = 1e-5;
        s.sun.irradiance = Spectrum::constant(2.0);
        s.sky.radiance = Spectrum::constant(0.0);
        ir::Medium w = water(0, 0);
        w.layers.resize(2);
        w.layers[0].zBottom = -2.0;
        w.layers[1].zTop = -2.0;
        w.layers[0].absorption = Spectrum::tabulated({0.4, 0.6}, {0.0, 0.8}, "a top");
        w.layers[1].absorption = Spectrum::tabulated({0.4, 0.6}, {0.0, 1.6}, "a bottom");
        s.materials.push_back(blackMaterial("floor"));
        addPeriodicSlab(s, w, 20.0, 10.0, "floor");
        s.probes.push_back(probeAt("p", {0.5, 0.5, -3.0}, {"Ed"}, 64));
        const Scene scene(s, ".");
        const auto pv = evaluateProbe(scene, s.probes[0], 0, quiet());
        const double n = 1.34, th = deg2rad(40);
        const double muW = std::sqrt(1 - sqr(std::sin(th) / n));
        for (int b = 0; b < 3; ++b) {
            const double a1 = 4.0 * (0.425 + 0.05 * b - 0.4), a2 = 2 * a1;
            const double pred = 2.0 * std::cos(th) * (1 - fresnelEq42(th, 1.0, n)) * std::exp(-(2 * a1 + a2) / muW);
            EXPECT_NEAR(pv[0].mean[b], pred, 1e-5 * pred) << nameOf(est) << " band " << b;
        }
    }
}

// The Snell window (Eq. 4.7) per band under the path estimator: splitting at the interface makes
// it noise free, so it holds pixel by pixel as under the dirsig estimator (test C, §4.3).
TEST(Media, SnellWindowPathEstimator) {
    const double n = 1.34, z = 4.0;
    const int W = 60;
    const double f = 5000e-6, pitch = 200e-6;
    ir::SceneIR s = uniformSkyScene();
    s.render.estimator = ir::Estimator::Path;
    s.render.bands = {Band{0.40, 0.45}, Band{0.45, 0.50}};
    ir::Medium w = water(0, 0, n);
    w.layers[0].absorption = Spectrum::tabulated({0.4, 0.5}, {0.05, 0.25}, "a");
    s.materials.push_back(blackMaterial("floor"));
    addPeriodicSlab(s, w, 50.0, 20.0, "floor");
    s.sensors.push_back(pinhole("up", {0, 0, -z}, {0, 0, 1}, {0, 1, 0}, W, W, f, pitch, "water"));
    const Scene scene(s, ".");
    const SensorImage img = renderSensor(scene, s.sensors[0], quiet());
    int inside = 0;
    for (int j = 0; j < W; ++j)
        for (int i = 0; i < W; ++i) {
            const double th = std::atan(std::hypot(i + 0.5 - W / 2.0, j + 0.5 - W / 2.0) * pitch / f);
            for (int b = 0; b < 2; ++b) {
                const double a = b == 0 ? 0.1 : 0.2;  // band means of the linear a(lambda)
                const double pred =
                    th < std::asin(1 / n) ? (1 / kPi) * (1 - fresnelEq42(th, n, 1.0)) * n * n * std::exp(-a * z / std::cos(th))
                                          : 0.0;
                EXPECT_NEAR(img.film.at(i, j, b), pred, 1e-6 * pred + 1e-12) << i << "," << j << " band " << b;
            }
            inside += th < std::asin(1 / n);
        }
    EXPECT_GT(inside, 1000);
}

// ---------------------------------------------------------------------------------------------
// Two-stream model (Appendix A.2 / A.2.1, digest §3.8–3.9, corrected bottom coupling 2 r mubar):
// uniform illumination L_n filling the whole downward hemisphere just below the surface
// (index-matched water, n = 1, under a uniform sky), isotropic scattering (p = 1, b = 1/2),
// albedo 0.5, a Lambertian bottom r = 0.5 at tau* = 2 (c = 1 m^-1). The prediction is the
// appendix's own: the two-stream source S(tau) (A.30) integrated formally along every direction
// (A.31/A.42 for the downwelling field, A.43/A.44 plus the bottom for the upwelling one) and then
// over the hemisphere, with mubar = 1/2 (the A.2 isotropic case).
//
// Its accuracy bound. The formal integration attenuates each direction exactly; only the source
// is approximate, through its one free parameter mubar, which the model holds constant while the
// true field's mean cosine (Eq. 7.16 per stream: E / E_o) varies with depth and stream. We measure
// that variation (mubar_d = Ed/Eod, mubar_u = Eu/Eou at every probe), and bound the error of each
// prediction by how much it changes when mubar moves over the measured range. For Ed this touches
// only the scattered part: the unscattered part 2 pi L_n E3(tau) is exact. Allowed difference:
// that spread plus 3 standard errors. (Measured: 0.6–20 % for Ed, 25–60 % for Eu, whose
// bottom-reflected part inherits the spread of Ed(tau*): the two-stream model is coarse.) The test
// can still fail: each Ed bound is checked to be smaller than the scattered light itself, so a
// renderer that lost the in-scattered light fails, and each Eu bound smaller than Eu, so one that
// lost the upwelling light fails.
TEST(PathEstimator, TwoStreamSlabOverLambertianBottom) {
    const double w0 = 0.5, tauStar = 2.0, r = 0.5, Ln = 1.0;
    ir::SceneIR s = uniformSkyScene();
    s.sky.radiance = Spectrum::constant(Ln);
    s.render.estimator = ir::Estimator::Path;
    s.render.settings.set("probe_batches", 16);
    s.materials.push_back(white("bottom", r));
    addPeriodicSlab(s, water(1 - w0, w0, 1.0, {"isotropic", {}}), 10.0, tauStar, "bottom");
    const std::vector<double> taus = {0.25, 1.0, 1.75};
    for (size_t i = 0; i < taus.size(); ++i)
        s.probes.push_back(probeAt("t" + std::to_string(i), {0.1, 0.2, -taus[i]}, {"Ed", "Eu", "Eod", "Eou"}, 16000));
    const Scene scene(s, ".");
    const EstimatorSet est(scene);
    std::vector<double> Ed, Eu, seD, seU, mubars;
    for (size_t i = 0; i < taus.size(); ++i) {
        const auto v = evaluateProbe(scene, est, s.probes[i], static_cast<int>(i), quiet());
        Ed.push_back(find(v, "Ed").mean[0]);
        Eu.push_back(find(v, "Eu").mean[0]);
        seD.push_back(find(v, "Ed").stderr_[0]);
        seU.push_back(find(v, "Eu").stderr_[0]);
        mubars.push_back(Ed.back() / find(v, "Eod").mean[0]);
        mubars.push_back(Eu.back() / find(v, "Eou").mean[0]);
    }
    const double muLo = *std::min_element(mubars.begin(), mubars.end());
    const double muHi = *std::max_element(mubars.begin(), mubars.end());
    // Hemispheric integrals by the midpoint rule in mu (2000 panels: the integrands are smooth).
    auto hemi = [](auto&& L) {
        const int n = 2000;
        double sum = 0;
        for (int k = 0; k < n; ++k) {
            const double mu = (k + 0.5) / n;
            sum += L(mu) * mu;
        }
        return 2 * kPi * sum / n;
    };
    auto solution = [&](double mubar) {
        testing_support::two_stream::Params p;
        p.w0 = w0;
        p.tauStar = tauStar;
        p.bottomReflectance = r;
        p.Ln = Ln;
        p.mubar = mubar;
        return testing_support::two_stream::Solution(p);
    };
    for (size_t i = 0; i < taus.size(); ++i) {
        const double t = taus[i];
        // The unscattered part, exact in the model and in the field (reported for context).
        const double direct = hemi([&](double mu) { return Ln * std::exp(-t / mu); });  // 2 pi L_n E3(tau)
        double dLo = 1e300, dHi = 0, uLo = 1e300, uHi = 0;
        for (int k = 0; k <= 20; ++k) {
            const auto sol = solution(muLo + (muHi - muLo) * k / 20.0);
            const double d = sol.Ed(t), u = hemi([&](double mu) { return sol.LplusAngular(t, mu); });
            dLo = std::min(dLo, d), dHi = std::max(dHi, d), uLo = std::min(uLo, u), uHi = std::max(uHi, u);
        }
        const auto half = solution(0.5);
        const double predD = half.Ed(t), predU = hemi([&](double mu) { return half.LplusAngular(t, mu); });
        const double boundD = std::max(dHi - predD, predD - dLo), boundU = std::max(uHi - predU, predU - uLo);
        EXPECT_NEAR(Ed[i], predD, boundD + 3 * seD[i]) << "tau " << t;
        EXPECT_NEAR(Eu[i], predU, boundU + 3 * seU[i]) << "tau " << t;
        EXPECT_LT(boundD + 3 * seD[i], predD - direct) << "tau " << t;
        EXPECT_LT(boundU + 3 * seU[i], predU) << "tau " << t;
        std::printf("[ two-stream ] tau %.2f  Ed %.5f (+-%.5f) vs %.5f +- %.5f (unscattered %.5f)  Eu %.5f (+-%.5f) vs "
                    "%.5f +- %.5f\n",
                    t, Ed[i], seD[i], predD, boundD, direct, Eu[i], seU[i], predU, boundU);
    }
    std::printf("[ two-stream ] measured mubar %.4f .. %.4f\n", muLo, muHi);
}

// ---------------------------------------------------------------------------------------------
// Instrument self-shading (Gordon and Ding 1992): an opaque cylinder of radius R floating at the
// surface shades the water below it, so a radiometer at the centre of its bottom face reads
// Lu low by eps = 1 - exp(-k' a R), with k' = k''/tan(theta_w) for the sun (k''(Lu) = 2.23 at
// theta_0 = 30 deg, pipelines/reference/gordon_ding.h). Sun only (black sky), theta_0 = 30 deg, a = 0.5,
// b = 1 m^-1 (Petzold), R = 0.1 m: a R = 0.05, predicted eps = 0.24. eps is measured as
// 1 - Lu(with the cylinder) / Lu(without), each from the path estimator with its standard error.
// Gordon and Ding fitted their k'' to Monte Carlo results with an accuracy they put at about
// 10-15 %; the issue asks for agreement within 20 %. Tolerance: 20 % of eps plus 3 standard
// errors of the measured eps (from the two probes' errors).
TriMesh cylinder(double R, double z0, double z1, int n) {
    TriMesh m;
    m.positions.push_back({0, 0, z0});
    m.positions.push_back({0, 0, z1});
    for (int i = 0; i < n; ++i) {
        const double p = 2 * kPi * i / n;
        m.positions.push_back({R * std::cos(p), R * std::sin(p), z0});
        m.positions.push_back({R * std::cos(p), R * std::sin(p), z1});
    }
    auto lo = [&](int i) { return static_cast<uint32_t>(2 + 2 * (i % n)); };
    auto hi = [&](int i) { return static_cast<uint32_t>(3 + 2 * (i % n)); };
    for (int i = 0; i < n; ++i) {
        m.triangles.push_back({0, lo(i + 1), lo(i)});
        m.triangles.push_back({1, hi(i), hi(i + 1)});
        m.triangles.push_back({lo(i), lo(i + 1), hi(i + 1)});
        m.triangles.push_back({lo(i), hi(i + 1), hi(i)});
    }
    orientAway(m, {0, 0, 0.5 * (z0 + z1)});
    return m;
}

TEST(PathEstimator, InstrumentSelfShadingGordonDing) {
    const double a = 0.5, b = 1.0, R = 0.1, theta0 = 30.0;
    auto lu = [&](bool shaded) {
        ir::SceneIR s;
        s.name = "self-shading";
        s.render.estimator = ir::Estimator::Path;
        s.render.settings.set("probe_batches", 16);
        s.sun.enabled = true;
        s.sun.zenith = deg2rad(theta0);
        s.sun.irradiance = Spectrum::constant(1.0);
        s.sky.radiance = Spectrum::constant(0.0);
        s.materials.push_back(blackMaterial("floor"));
        addPeriodicSlab(s, water(a, b, littoral::reference::gordon_ding::kWaterIndex, {"petzold", {}}), 10.0, 30.0, "floor");
        if (shaded) {
            s.materials.push_back(blackMaterial("instrument"));
            s.meshes.push_back(meshOf("instrument", cylinder(R, -0.001, 0.3, 96), {"instrument"}, "", "", true));
        }
        s.probes.push_back(probeAt("lu", {0, 0, -0.002}, {"Lu"}, 96000));
        const Scene scene(s, ".");
        return evaluateProbe(scene, s.probes[0], 0, quiet())[0];
    };
    const ProbeValue open = lu(false), shaded = lu(true);
    const double ratio = shaded.mean[0] / open.mean[0];
    const double eps = 1 - ratio;
    const double seEps = ratio * std::hypot(shaded.stderr_[0] / shaded.mean[0], open.stderr_[0] / open.mean[0]);
    const double pred = littoral::reference::gordon_ding::epsilonSun(littoral::reference::gordon_ding::Quantity::Lu, theta0, a, R);
    EXPECT_NEAR(eps, pred, 0.2 * pred + 3 * seEps);
    EXPECT_LT(seEps, 0.05 * pred);
    std::printf("[ self-shading ] Lu open %.5e +- %.1e, shaded %.5e +- %.1e: eps %.4f +- %.4f (Gordon & Ding %.4f)\n",
                open.mean[0], open.stderr_[0], shaded.mean[0], shaded.stderr_[0], eps, seEps, pred);
}

// ---------------------------------------------------------------------------------------------
// Honest standard errors: over 20 independent seeds, the spread of each probe value matches the
// standard error the run reports. For each quantity q and seed k, z = (x_k - mean_q) / se_k; with
// honest errors the z are standard-normal-like, so sqrt(sum z^2 / (n - 1)) over the n = 20 seeds
// and 4 quantities (76 degrees of freedom) is 1 with a relative sampling error of
// 1/sqrt(2 x 76) = 8 %; the 30 % is then 3.7 of those. (The batch standard errors are
// themselves estimates from 16 batches; their scatter enters the same statistic.)
TEST(PathEstimator, StandardErrorsMatchTheSpreadOverSeeds) {
    const int seeds = 20;
    const std::vector<std::string> quantities = {"Ed", "Eu", "Eou", "Lu"};
    std::vector<std::vector<double>> x(quantities.size()), se(quantities.size());
    for (int k = 0; k < seeds; ++k) {
        ir::SceneIR s;
        s.name = "seeds";
        s.render.estimator = ir::Estimator::Path;
        s.render.seed = 1000 + k;
        s.render.settings.set("probe_batches", 16);
        s.sun.enabled = true;
        s.sun.zenith = deg2rad(35);
        s.sun.irradiance = Spectrum::constant(1.0);
        s.sky.radiance = Spectrum::constant(0.05);
        s.materials.push_back(white("sand", 0.3));
        addPeriodicSlab(s, water(0.2, 0.5, 1.34, {"henyey-greenstein", {{"g", 0.9}}}), 10.0, 4.0, "sand");
        s.probes.push_back(probeAt("p", {0.3, 0.1, -2.0}, quantities, 1600));
        const Scene scene(s, ".");
        const auto v = evaluateProbe(scene, s.probes[0], 0, quiet());
        for (size_t q = 0; q < quantities.size(); ++q) {
            x[q].push_back(find(v, quantities[q]).mean[0]);
            se[q].push_back(find(v, quantities[q]).stderr_[0]);
        }
    }
    double sumZ2 = 0;
    int dof = 0;
    for (size_t q = 0; q < quantities.size(); ++q) {
        double m = 0;
        for (double v : x[q]) m += v / seeds;
        double zq = 0;
        for (int k = 0; k < seeds; ++k) zq += sqr((x[q][k] - m) / se[q][k]);
        sumZ2 += zq;
        dof += seeds - 1;
        std::printf("[ seeds ] %-3s mean %.5f, rms z %.3f\n", quantities[q].c_str(), m, std::sqrt(zq / (seeds - 1)));
    }
    const double ratio = std::sqrt(sumZ2 / dof);
    EXPECT_NEAR(ratio, 1.0, 0.3);
    std::printf("[ seeds ] spread / reported standard error = %.3f over %d degrees of freedom\n", ratio, dof);
}

}  // namespace
}  // namespace littoral::render
