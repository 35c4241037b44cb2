// Chi-square goodness-of-fit tests (issue 17) of three samplers of the transport, through the
// shared harness (tests/support/chi_square.h):
//
//  1. Medium::sampleFreeFlight: the distances it draws against the density of its contract
//     (render/medium.h): the hero band is floor(uBand n) of the group's n bands, the distance is
//     drawn from that band's c(t) T(t), so over uniform uBand the density is the band average
//     pdf(t) = (1/n) sum_b c_b(t) T_b(t) and P(no event before tMax) = (1/n) sum_b T_b(tMax). The
//     optical depths T_b = exp(-tau_b) are computed here from the layer boundaries by intersecting
//     the ray's interval with each slab (not by walking the layers as the medium does), and the
//     cell probabilities are differences of exp(-tau) (closed form, no quadrature). The remainder
//     cell is "reached tMax unscattered". Each sample's weight is also checked against the
//     contract's one-sample-MIS weight T_b b_b / pdf (scattered) or T_b / P(no event) (passed).
//  2. Medium::sampleAround / pdfAround: directions around a tilted axis against pdfAround, via
//     testSphere (theta, phi) about a frame built independently of the sampler's, and pdfAround's
//     normalisation over the sphere. The single-constituent layers overlap with
//     tests/core/phase_functions_test.cpp, which already tests every PhaseFunction sampler in
//     theta and four of them in directions; what is new here is the layer path (IR phase
//     description -> makePhaseFunction -> sampleAround, pdfAround through the chord |w - dir|),
//     and above all the layer that mixes constituents with band-dependent weights, which
//     sampleAround draws from with the band-averaged weights (averageWeights) and which nothing
//     else tests. The single-constituent cases therefore use fewer samples.
//  3. SunSource::sampleDirection: uniform over the disc's cone, with cell probabilities in closed
//     form (equal-solid-angle rings times azimuth sectors), and inDisc against the cone. The
//     existing Sampling.LambertianTripleAndCone (render_core_test.cpp) checks only one binomial
//     fraction of sampleUniformCone, in the cone's own frame and not through SunSource.
//
// Every sampler also gets a test that the harness rejects a deliberately wrong pdf, so these
// tests have power.
//
// Seeds are fixed; LITTORAL_TEST_SEED (as in skyfraction_test.cpp) shifts all of them, to check
// that the acceptance tests pass for other seeds too.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "core/frame.h"
#include "core/rng.h"
#include "core/scene_ir.h"
#include "core/spectrum.h"
#include "core/units.h"
#include "render/medium.h"
#include "core/phase_functions.h"
#include "render/sources.h"
#include "tests/support/chi_square.h"

using namespace littoral;
using namespace littoral::render;
namespace chi2 = littoral::testing_support::chi2;

namespace {

// Family-wise false-alarm probability 1 % over the acceptance tests of this file (each is one
// chi-square test of a correct sampler, independent streams): free flight 5 (homogeneous single
// band, homogeneous band mixture in a sub-group, one band of a group, layered mixture downward,
// layered upward to an infinite tMax), directions around an axis 6 (isotropic, HG 0.9, Petzold,
// Fournier-Forand, Rayleigh-like, two-constituent layer), sun disc 4 (0.53 and 10 deg at zenith
// and 85 deg). Sidak's level per test: 1 - 0.99^(1/15) = 6.7e-4.
constexpr double kFamilyAlpha = 0.01;
constexpr int kAcceptanceTests = 15;
const double kSamplingAlpha = chi2::sidakLevel(kFamilyAlpha, kAcceptanceTests);

uint64_t seed(uint64_t s) {
    if (const char* e = std::getenv("LITTORAL_TEST_SEED")) return s + 1000 * std::stoull(e);
    return s;
}

void report(const char* what, const chi2::ChiSquareResult& r) {
    std::printf("[ info ] chi2 %-58.58s p = %.3g (dof %d, %lld samples, level %.2g)\n", what, r.pValue, r.dof, r.samples,
                kSamplingAlpha);
}

const std::vector<Band> kBands3 = {Band{0.40, 0.45}, Band{0.45, 0.50}, Band{0.50, 0.55}};
const double kCentres3[3] = {0.425, 0.475, 0.525};

// A spectrum linear in wavelength over [0.40, 0.55] um, given by its values at the two ends; its
// band average is its value at the band centre.
Spectrum linear(double at400, double at550) { return Spectrum::tabulated({0.40, 0.55}, {at400, at550}, "test spectrum"); }
double linearAt(double at400, double at550, double wl) { return at400 + (at550 - at400) * (wl - 0.40) / 0.15; }

// =============================================================================================
// 1. Free-flight sampling

// The test's own model of a layered medium along one ray: per layer its slab and, for each band
// of the group, c and b.
struct SlabModel {
    double zTop, zBottom;
    std::vector<double> c, b;  // per band of the group
};

struct FlightModel {
    Point3 o;
    Vec3 d;
    std::vector<SlabModel> slabs;

    // [tEnter, tExit) of the ray's parameter inside slab i (empty if the ray misses it).
    std::pair<double, double> interval(size_t i) const {
        const SlabModel& s = slabs[i];
        if (d.z == 0) return (o.z >= s.zBottom && o.z < s.zTop) ? std::pair{0.0, ir::kInfinity} : std::pair{0.0, 0.0};
        double t0 = (s.zBottom - o.z) / d.z, t1 = (s.zTop - o.z) / d.z;  // +-inf for unbounded slabs
        if (t0 > t1) std::swap(t0, t1);
        return {std::max(t0, 0.0), std::max(t1, 0.0)};
    }
    // Optical depth of band k over [0, t] (t may be infinite; a c = 0 slab adds nothing).
    double tau(int k, double t) const {
        double s = 0;
        for (size_t i = 0; i < slabs.size(); ++i) {
            const auto [a, b] = interval(i);
            const double len = std::min(b, t) - a;
            if (len > 0 && slabs[i].c[k] > 0) s += slabs[i].c[k] * len;
        }
        return s;
    }
    double survival(int k, double t) const { return std::exp(-tau(k, t)); }
    // Slab holding the point at distance t, or -1 within 1e-9 m of a boundary (ambiguous).
    int slabAt(double t) const {
        const double z = o.z + t * d.z;
        for (size_t i = 0; i < slabs.size(); ++i)
            if (z >= slabs[i].zBottom + 1e-9 && z < slabs[i].zTop - 1e-9) return static_cast<int>(i);
        return -1;
    }
};

struct FlightCase {
    const Medium* medium;
    FlightModel model;       // the correct density (and the weights the contract gives)
    double tMax;
    BandGroup g;
    int fixedBand = -1;      // >= 0: uBand is drawn inside this band's slot [k/n, (k+1)/n)
    std::vector<double> edges;  // distance bins, from 0; a tail cell [edges.back(), tMax) follows
    long long samples;
    uint64_t seed;
};

struct FlightResult {
    chi2::ChiSquareResult chi;
    double worstWeightError = 0;  // relative, against the contract's weight
    long long layerMismatches = 0, scattered = 0;
};

// Runs the sampler and tests its distances against `judge` (the model of case `fc`, or a wrong
// one for the power tests). Cells: the distance bins, the tail [edges.back(), tMax), "reached
// tMax unscattered", and "impossible" (a scattering distance outside [0, tMax), or an
// unscattered result with t != tMax): expected 0, so one sample there rejects.
FlightResult runFreeFlight(const FlightCase& fc, const FlightModel& judge) {
    const int n = fc.g.count;
    const size_t nb = fc.edges.size() - 1;
    std::vector<int> bands;
    for (int k = 0; k < n; ++k)
        if (fc.fixedBand < 0 || fc.fixedBand == k) bands.push_back(k);
    // Probability that the drawn band's flight ends (scatters) before t.
    auto cdf = [&](double t) {
        double s = 0;
        for (int k : bands) s += 1.0 - judge.survival(k, t);
        return s / static_cast<double>(bands.size());
    };
    const double N = static_cast<double>(fc.samples);
    std::vector<double> expected(nb + 3, 0.0), observed(nb + 3, 0.0);
    std::vector<std::string> labels(nb + 3);
    for (size_t i = 0; i < nb; ++i) {
        expected[i] = N * (cdf(fc.edges[i + 1]) - cdf(fc.edges[i]));
        labels[i] = "t [" + std::to_string(fc.edges[i]) + ", " + std::to_string(fc.edges[i + 1]) + ")";
    }
    const size_t tail = nb, pass = nb + 1, impossible = nb + 2;
    expected[tail] = N * (cdf(fc.tMax) - cdf(fc.edges.back()));
    labels[tail] = "t [" + std::to_string(fc.edges.back()) + ", tMax)";
    expected[pass] = N * (1.0 - cdf(fc.tMax));
    labels[pass] = "reached tMax unscattered";
    labels[impossible] = "impossible result";

    FlightResult res;
    Ray ray;
    ray.o = fc.model.o;
    ray.d = fc.model.d;
    for (long long s = 0; s < fc.samples; ++s) {
        RandomStream rs(fc.seed, 0, static_cast<uint64_t>(s));
        const double uBand = fc.fixedBand < 0 ? rs.uniform() : (fc.fixedBand + rs.uniform()) / n;
        const double u = rs.uniform();
        const FreeFlight ff = fc.medium->sampleFreeFlight(ray, fc.tMax, fc.g, uBand, u);
        // The contract's weights, from the case's own (correct) model.
        const FlightModel& m = fc.model;
        double pdf = 0;
        std::vector<double> want(static_cast<size_t>(n));
        if (ff.scattered) {
            ++res.scattered;
            if (!(ff.t >= 0 && ff.t < fc.tMax)) {
                observed[impossible] += 1;
                continue;
            }
            const size_t bin = static_cast<size_t>(std::upper_bound(fc.edges.begin(), fc.edges.end(), ff.t) - fc.edges.begin());
            observed[bin == 0 ? impossible : bin - 1] += 1;  // bin - 1 == nb is the tail
            const int slab = m.slabAt(ff.t);
            if (slab >= 0 && slab != ff.layer) ++res.layerMismatches;
            const int L = slab >= 0 ? slab : ff.layer;
            for (int k = 0; k < n; ++k) pdf += m.slabs[L].c[k] * m.survival(k, ff.t) / n;
            for (int k = 0; k < n; ++k) want[k] = m.survival(k, ff.t) * m.slabs[L].b[k] / pdf;
        } else {
            if (ff.t != fc.tMax) {
                observed[impossible] += 1;
                continue;
            }
            observed[pass] += 1;
            for (int k = 0; k < n; ++k) pdf += m.survival(k, fc.tMax) / n;
            for (int k = 0; k < n; ++k) want[k] = m.survival(k, fc.tMax) / pdf;
        }
        for (int k = 0; k < n; ++k)
            res.worstWeightError =
                std::max(res.worstWeightError, std::abs(ff.weight[k] - want[k]) / (std::abs(want[k]) + 1e-12));
    }
    chi2::Options o;
    o.samples = fc.samples;
    res.chi = chi2::testCells(observed, expected, labels, o);
    res.chi.samples = fc.samples;
    return res;
}

// The medium's per-band coefficients must be the ones the model was written for (they come from
// band averages of linear spectra, i.e. values at band centres), else the test would judge the
// sampler against the wrong density.
void expectModelMatchesMedium(const Medium& m, const FlightModel& model, BandGroup g) {
    ASSERT_EQ(m.layers().size(), model.slabs.size());
    for (size_t i = 0; i < model.slabs.size(); ++i) {
        EXPECT_EQ(m.layers()[i].zTop, model.slabs[i].zTop);
        EXPECT_EQ(m.layers()[i].zBottom, model.slabs[i].zBottom);
        const Spec c = m.c(static_cast<int>(i), g), b = m.b(static_cast<int>(i), g);
        for (int k = 0; k < g.count; ++k) {
            EXPECT_NEAR(c[k], model.slabs[i].c[k], 1e-13) << "layer " << i << " band " << k;
            EXPECT_NEAR(b[k], model.slabs[i].b[k], 1e-13) << "layer " << i << " band " << k;
        }
    }
}

void expectAccepted(const char* what, const FlightResult& r) {
    report(what, r.chi);
    EXPECT_FALSE(r.chi.rejectedAt(kSamplingAlpha)) << what << ": " << r.chi.summary();
    // Weights: T b / pdf and T / P(pass) evaluated here from closed forms; the sampler sums the
    // same optical depths layer by layer, so they agree to rounding (a few 1e-16 per term).
    EXPECT_LT(r.worstWeightError, 1e-11) << what;
    EXPECT_EQ(r.layerMismatches, 0) << what;
}

// --- The cases ---

// Homogeneous water, one band: a = 0.3, b = 0.5 m^-1 (c = 0.8), tMax = 3.125 m (optical depth
// 2.5, P(pass) = e^-2.5 = 8.2 %). Exponential in 40 bins of 0.078 m.
Medium homogeneousOneBand() {
    return Medium(ir::Medium::homogeneous("w", 1.34, Spectrum::constant(0.3), Spectrum::constant(0.5)), {Band{0.4, 0.6}},
                  "test water");
}
FlightCase homogeneousOneBandCase(const Medium& m) {
    FlightCase fc{&m, {{0.2, -0.1, -1.0}, normalize(Vec3{0.3, -0.4, -0.8}), {{ir::kInfinity, -ir::kInfinity, {0.8}, {0.5}}}},
                  3.125, BandGroup{0, 1}, -1, chi2::uniformEdges(0, 3.125, 40), 200000, seed(101)};
    return fc;
}

// Homogeneous water over three bands, a linear in wavelength (0.10 .. 1.00 m^-1 over 400..550 nm:
// band means 0.25, 0.55, 0.85), b = 0.2: c = 0.45, 0.75, 1.05.
Medium homogeneousThreeBands() {
    return Medium(ir::Medium::homogeneous("w", 1.34, linear(0.10, 1.00), Spectrum::constant(0.2)), kBands3, "test water");
}
FlightModel homogeneousThreeBandModel(BandGroup g) {
    SlabModel s{ir::kInfinity, -ir::kInfinity, {}, {}};
    for (int k = 0; k < g.count; ++k) {
        s.c.push_back(linearAt(0.10, 1.00, kCentres3[g.begin + k]) + 0.2);
        s.b.push_back(0.2);
    }
    return {{0, 0, -0.5}, normalize(Vec3{-0.2, 0.5, -0.6}), {s}};
}

// Three layers over three bands; coefficients chosen so the bands differ strongly and each layer
// matters: top (z >= -2 m) a 0.10 .. 0.55 (band means 0.15, 0.25, 0.35) + b 0.3; middle
// (-5 <= z < -2) a 1.20 .. 0.60 (1.10, 0.90, 0.70) + b 0.5; bottom (z < -5) a 0.05, no scatterer
// (c = 0.05, b = 0: its events are absorptions, weight 0).
Medium layeredThreeBands() {
    ir::Medium w = ir::Medium::homogeneous("w", 1.34, Spectrum::constant(0), Spectrum::constant(0));
    w.layers.resize(3);
    w.layers[0].zBottom = -2.0;
    w.layers[1].zTop = -2.0;
    w.layers[1].zBottom = -5.0;
    w.layers[2].zTop = -5.0;
    w.layers[0].absorption = linear(0.10, 0.55);
    w.layers[0].scatterers.push_back({"particles", Spectrum::constant(0.3), {}});
    w.layers[1].absorption = linear(1.20, 0.60);
    w.layers[1].scatterers.push_back({"particles", Spectrum::constant(0.5), {}});
    w.layers[2].absorption = Spectrum::constant(0.05);
    return Medium(w, kBands3, "layered test water");
}
std::vector<SlabModel> layeredThreeBandSlabs() {
    std::vector<SlabModel> s = {{ir::kInfinity, -2.0, {}, {}}, {-2.0, -5.0, {}, {}}, {-5.0, -ir::kInfinity, {}, {}}};
    for (int k = 0; k < 3; ++k) {
        s[0].c.push_back(linearAt(0.10, 0.55, kCentres3[k]) + 0.3);
        s[0].b.push_back(0.3);
        s[1].c.push_back(linearAt(1.20, 0.60, kCentres3[k]) + 0.5);
        s[1].b.push_back(0.5);
        s[2].c.push_back(0.05);
        s[2].b.push_back(0.0);
    }
    return s;
}

// One band, three layers: a clear top layer (z >= -1 m, c = 0: no events there at all),
// a turbid middle one (-3 <= z < -1, c = 0.9) and a bottom one (c = 0.3). The ray rises from
// z = -6 toward the surface with tMax infinite, so P(pass) = exp(-(0.3 * 3 + 0.9 * 2) / mu).
Medium layeredClearTop() {
    ir::Medium w = ir::Medium::homogeneous("w", 1.34, Spectrum::constant(0), Spectrum::constant(0));
    w.layers.resize(3);
    w.layers[0].zBottom = -1.0;
    w.layers[1].zTop = -1.0;
    w.layers[1].zBottom = -3.0;
    w.layers[2].zTop = -3.0;
    w.layers[1].absorption = Spectrum::constant(0.4);
    w.layers[1].scatterers.push_back({"particles", Spectrum::constant(0.5), {}});
    w.layers[2].absorption = Spectrum::constant(0.1);
    w.layers[2].scatterers.push_back({"particles", Spectrum::constant(0.2), {}});
    return Medium(w, {Band{0.4, 0.6}}, "clear-top test water");
}

}  // namespace

// Sample counts: 200000 per case (300000 for the three-band layered case, whose density has
// nine pieces). Bins are 40 (60) equal distance intervals: expected counts of 100 .. 10000 per
// bin, except in the weakly attenuating bottom layer of the layered case (~9 per bin; the
// harness pools those below 5) and in the clear layer (0: dropped, and any event there rejects). At these counts an
// extinction error of 1 % already moves the statistic by ~ N (0.01)^2 ~ 20 (see the power
// test below, which uses 5 %).
TEST(FreeFlightChiSquare, HomogeneousOneBandIsExponential) {
    const Medium m = homogeneousOneBand();
    const FlightCase fc = homogeneousOneBandCase(m);
    expectModelMatchesMedium(m, fc.model, fc.g);
    const FlightResult r = runFreeFlight(fc, fc.model);
    expectAccepted("free flight: homogeneous, 1 band, tMax at tau 2.5", r);
    // P(pass) = e^-2.5: 8.2 % of the samples, binomial sd 0.06 %.
    EXPECT_NEAR(1.0 - double(r.scattered) / fc.samples, std::exp(-2.5), 5 * std::sqrt(0.082 * 0.918 / fc.samples));
}

// A sub-group (bands 1 and 2 of three: g.begin = 1 must select c = 0.75 and 1.05), uBand uniform:
// the distance is the equal mixture of the two exponentials; tMax infinite, so every flight
// scatters and the remainder cells expect 0. 40 bins up to 6 m, tail beyond (mass ~0.6 %).
TEST(FreeFlightChiSquare, HomogeneousBandMixtureInSubGroup) {
    const Medium m = homogeneousThreeBands();
    const BandGroup g{1, 2};
    FlightCase fc{&m, homogeneousThreeBandModel(g), ir::kInfinity, g, -1, chi2::uniformEdges(0, 6.0, 40), 200000, seed(102)};
    expectModelMatchesMedium(m, fc.model, g);
    const FlightResult r = runFreeFlight(fc, fc.model);
    expectAccepted("free flight: homogeneous, mixture of bands 1-2, tMax inf", r);
    EXPECT_EQ(r.scattered, fc.samples);
}

// One band of a three-band group: uBand inside band 0's slot [0, 1/3) gives band 0's exponential
// (c = 0.45) alone, whatever the other bands' c; the weights still use the group's mixture pdf.
// tMax = 4 m (optical depth 1.8, P(pass) = 16.5 %).
TEST(FreeFlightChiSquare, OneBandOfAGroupIsThatBandsExponential) {
    const Medium m = homogeneousThreeBands();
    const BandGroup g{0, 3};
    FlightCase fc{&m, homogeneousThreeBandModel(g), 4.0, g, 0, chi2::uniformEdges(0, 4.0, 40), 200000, seed(103)};
    expectModelMatchesMedium(m, fc.model, g);
    const FlightResult r = runFreeFlight(fc, fc.model);
    expectAccepted("free flight: homogeneous, band 0 of 3, tMax at tau 1.8", r);
}

// Layered, three bands mixed, a ray sinking at 28 deg from nadir from z = -0.5 m through both
// boundaries (z = -2 at t = 1.71 m, z = -5 at t = 5.12 m) to tMax = 12 m in the bottom layer.
// The density is piecewise exponential with a jump at each boundary, per band, mixed over the
// bands; P(pass) = 0.22 %. 60 bins of 0.2 m.
TEST(FreeFlightChiSquare, LayeredBandMixtureSinking) {
    const Medium m = layeredThreeBands();
    const BandGroup g{0, 3};
    const Vec3 d = normalize(Vec3{0.45, -0.3, -1.0});
    FlightCase fc{&m, {{1.0, 2.0, -0.5}, d, layeredThreeBandSlabs()}, 12.0, g, -1, chi2::uniformEdges(0, 12.0, 60), 300000,
                  seed(104)};
    expectModelMatchesMedium(m, fc.model, g);
    const FlightResult r = runFreeFlight(fc, fc.model);
    expectAccepted("free flight: 3 layers, mixture of 3 bands, sinking", r);
}

// Layered, one band, a ray rising at 30 deg from the zenith from z = -6 m with tMax infinite:
// events in the bottom and middle layers only; the clear top layer (c = 0) must receive none
// (its bins expect 0, so one event there rejects); P(pass) = exp(-2.7 / cos 30) = 4.4 %.
// 40 bins of 0.2 m cover the bottom and middle legs (up to t = 5.77 m) and part of the top one.
TEST(FreeFlightChiSquare, LayeredRisingIntoClearLayer) {
    const Medium m = layeredClearTop();
    const Vec3 d{0.5 * std::cos(0.3), 0.5 * std::sin(0.3), std::cos(deg2rad(30))};
    FlightModel model{{0, 0, -6.0},
                      d,
                      {{ir::kInfinity, -1.0, {0.0}, {0.0}}, {-1.0, -3.0, {0.9}, {0.5}}, {-3.0, -ir::kInfinity, {0.3}, {0.2}}}};
    FlightCase fc{&m, model, ir::kInfinity, BandGroup{0, 1}, -1, chi2::uniformEdges(0, 8.0, 40), 200000, seed(105)};
    expectModelMatchesMedium(m, fc.model, fc.g);
    const FlightResult r = runFreeFlight(fc, fc.model);
    expectAccepted("free flight: 3 layers, clear top, rising, tMax inf", r);
    const double pPass = std::exp(-(0.3 * 3 + 0.9 * 2) / std::cos(deg2rad(30)));
    EXPECT_NEAR(1.0 - double(r.scattered) / fc.samples, pPass, 5 * std::sqrt(pPass * (1 - pPass) / fc.samples));
}

// Power: the same samples judged against a wrong density must be rejected. (a) the homogeneous
// case with c 5 % too high (expected shift of the statistic ~ N (0.05)^2 ~ 500 against dof 40);
// (b) the layered case with only the middle layer's c 5 % too high; (c) the layered mixture
// judged as if the hero were always band 0 (a band-selection error).
TEST(FreeFlightChiSquare, RejectsWrongDensities) {
    {
        const Medium m = homogeneousOneBand();
        const FlightCase fc = homogeneousOneBandCase(m);
        FlightModel wrong = fc.model;
        wrong.slabs[0].c[0] *= 1.05;
        const FlightResult r = runFreeFlight(fc, wrong);
        report("free flight, wrong: homogeneous c + 5 %", r.chi);
        EXPECT_TRUE(r.chi.rejectedAt(kSamplingAlpha)) << r.chi.summary();
    }
    const Medium m = layeredThreeBands();
    const BandGroup g{0, 3};
    const Vec3 d = normalize(Vec3{0.45, -0.3, -1.0});
    FlightCase fc{&m, {{1.0, 2.0, -0.5}, d, layeredThreeBandSlabs()}, 12.0, g, -1, chi2::uniformEdges(0, 12.0, 60), 300000,
                  seed(104)};
    {
        FlightModel wrong = fc.model;
        for (double& c : wrong.slabs[1].c) c *= 1.05;
        const FlightResult r = runFreeFlight(fc, wrong);
        report("free flight, wrong: layered, middle layer c + 5 %", r.chi);
        EXPECT_TRUE(r.chi.rejectedAt(kSamplingAlpha)) << r.chi.summary();
    }
    {
        // A sampler that ignored uBand and always flew band 0 would produce band 0's density; the
        // real (mixed) samples judged against it: every band given band 0's coefficients.
        FlightModel wrong = fc.model;
        for (SlabModel& s : wrong.slabs) s.c.assign(3, s.c[0]);
        const FlightResult r = runFreeFlight(fc, wrong);
        report("free flight, wrong: layered, band 0's density for the mixture", r.chi);
        EXPECT_TRUE(r.chi.rejectedAt(kSamplingAlpha)) << r.chi.summary();
    }
}

// =============================================================================================
// 2. Directions around an axis: sampleAround against pdfAround

namespace {

// The IR's description of a phase function, by its registered name, with the parameter its
// kind takes (core/phase_functions.cpp's descriptors).
namespace T {
constexpr const char* Isotropic = "isotropic";
constexpr const char* HenyeyGreenstein = "henyey-greenstein";
constexpr const char* Petzold = "petzold";
constexpr const char* FournierForand = "fournier-forand";
constexpr const char* RayleighLike = "rayleigh";
}  // namespace T
ir::PhaseFunction irPhase(const std::string& t, double g = 0, double B = 0, double k = 1) {
    ir::PhaseFunction p;
    p.type = t;
    if (t == T::HenyeyGreenstein) p.params.set("g", g);
    if (t == T::FournierForand) p.params.set("backscatter_fraction", B);
    if (t == T::RayleighLike) p.params.set("k", k);
    return p;
}

// One homogeneous layer, one band, one scatterer with phase function `p`.
Medium singleScattererMedium(const ir::PhaseFunction& p) {
    return Medium(ir::Medium::homogeneous("w", 1.34, Spectrum::constant(0.1), Spectrum::constant(0.4), p),
                  {Band{0.4, 0.6}}, "test water");
}

// One layer, three bands, two constituents whose share of b changes with the band: molecular
// water (1 + 0.835 cos^2) with b 0.35 .. 0.05 m^-1 over 400..550 nm (band means 0.30, 0.20,
// 0.10) and Petzold particles with b 0.0 .. 0.9 (0.15, 0.45, 0.75). Per band the water's share
// is 2/3, 4/13, 2/17; sampleAround's contract is their band average 0.3640, which differs from
// the share of the band-averaged b (0.6 / 1.95 = 0.3077), so mixing up the two shows.
Medium twoConstituentMedium() {
    ir::Medium w = ir::Medium::homogeneous("w", 1.34, Spectrum::constant(0.05), Spectrum::constant(0));
    w.layers[0].scatterers.push_back({"water", linear(0.35, 0.05), irPhase(T::RayleighLike, 0, 0, 0.835)});
    w.layers[0].scatterers.push_back({"particles", linear(0.0, 0.9), irPhase(T::Petzold)});
    return Medium(w, kBands3, "two-constituent test water");
}
double waterShare(int band) {
    const double bw = linearAt(0.35, 0.05, kCentres3[band]), bp = linearAt(0.0, 0.9, kCentres3[band]);
    return bw / (bw + bp);
}
double averageWaterShare() { return (waterShare(0) + waterShare(1) + waterShare(2)) / 3.0; }

// The sampled axis, tilted, and the test's frame about it: its azimuth origin is set by a
// tangent hint, not by Frame::fromNormal as in the sampler, so the binning is independent of the
// sampler's construction.
const Vec3 kAxis = normalize(Vec3{-0.55, 0.25, -0.8});
const Frame kTestFrame = Frame::fromNormalAndTangent(kAxis, Vec3{0.2, 1.0, 0.4});

Vec3 directionAt(double theta, double phi) {
    const double s = std::sin(theta);
    return kTestFrame.toWorld({s * std::cos(phi), s * std::sin(phi), std::cos(theta)});
}

chi2::ChiSquareResult aroundChiSquare(const Medium& m, BandGroup g, const std::vector<double>& edges, int phiBins,
                                      long long samples, uint64_t sd, const std::function<double(double, double)>& pdf) {
    chi2::Options o;
    o.samples = samples;
    o.seed = sd;
    // Each cell's probability to 1e-8 relative: its error moves the statistic by ~E (1e-8)^2 / 1
    // per cell, nothing against the Poisson spread sqrt(E); the default 1e-10 costs 4 s more for
    // Petzold's piecewise-linear table (a kink at every node) in 2-D.
    o.relTol = 1e-8;
    return chi2::testSphere(
        edges, phiBins, kTestFrame,
        [&](RandomStream& rs) -> std::optional<Vec3> {
            const double u0 = rs.uniform(), u1 = rs.uniform(), u2 = rs.uniform(), u3 = rs.uniform();
            return m.sampleAround(0, g, kAxis, u0, u1, u2, u3);
        },
        pdf, o);
}

// pdfAround as a function of (theta, phi) for the harness's quadrature. pdfAround depends on the
// two directions only through the chord |w - dir| (1 - cos = |w - dir|^2 / 2), and a chord
// between two rounded unit vectors carries ~1e-16 absolute rounding: about the tilted axis that
// is ~1e-16/theta relative noise, which the adaptive quadrature (relative tolerance 1e-10 .. 1e-11)
// would chase forever near theta = 0 for the forward power laws of Petzold and Fournier-Forand.
// About +z the chord of (sin th cos ph, sin th sin ph, cos th) is exact to rounding at every
// angle, so the quadrature evaluates pdfAround there; expectSameAboutTiltedAxis checks that this
// is the density about the tilted axis the samples are drawn around.
std::function<double(double, double)> pdfAroundOf(const Medium& m, BandGroup g) {
    return [&m, g](double th, double ph) {
        const double s = std::sin(th);
        return m.pdfAround(0, g, Vec3{0, 0, 1}, Vec3{s * std::cos(ph), s * std::sin(ph), std::cos(th)});
    };
}

// pdfAround about the tilted axis equals pdfAround about +z at the same (theta, phi), to the
// chord's rounding (2e-12 relative in 1 - cos at theta = 1e-4; the steepest density, Petzold's,
// has slope -0.67 in log t; bound 1e-9).
void expectSameAboutTiltedAxis(const Medium& m, BandGroup g, const std::string& what) {
    const auto aboutZ = pdfAroundOf(m, g);
    for (double th : {1e-4, 3e-3, 0.1, 0.8, 1.6, 2.5, 3.1})
        for (double ph : {0.1, 2.0, 4.5})
            EXPECT_NEAR(m.pdfAround(0, g, kAxis, directionAt(th, ph)) / aboutZ(th, ph), 1.0, 1e-9) << what << " " << th;
}

// FINDING (reported to the lead, not fixed here: render/ is being rewritten). pdfAround (like
// Medium::phase) evaluates the phase function at max(1 - cos, 1e-18), i.e. it is flat inside the
// cone theta < 1.41e-9 rad, while sampleAround draws from the unfloored function, whose forward
// power law (Petzold t^-0.673, Fournier-Forand) puts mass there: 5.4e-6 of Petzold's samples and
// 1.9e-5 of Fournier-Forand's (B = 0.0183) by quadrature of the unfloored p; 201 and 762 of 4e7
// drawn by their samplers), where the true density exceeds the floored one up to ~3e3 (Petzold)
// and ~2e5 (Fournier-Forand) times. So pdfAround is the sampling density only outside that cone,
// and it integrates to 1 minus
//   deficit = Int_{t < 1e-18} (p(t) - p(1e-18)) dOmega
// (3.6e-6 for Petzold, 1.4e-5 for Fournier-Forand B = 0.0183; ~1e-19 for the bounded functions).
// The chi-square tests cannot see it (their first cell, theta < 1e-5 or 1e-6, holds both). The
// practical effect is nil as far as we can see: the path estimator divides Medium::phase, floored
// the same way, by pdfAround, so f/pdf stays exact; only a direction inside the cone sampled from
// one axis and weighed against a phase function about another would be off, by a share of the
// estimate ~1e-17. The tests pin the normalisation to 1 - deficit, with the deficit computed
// here from the unfloored phase function (exact 1 - cos), so a change of the floor shows.
constexpr double kPdfFloor = 1e-18;
double floorDeficit(const PhaseFunction& pf) {
    const double thetaFloor = chi2::thetaFromOneMinusCos(kPdfFloor), pFloor = pf.evalOneMinusCos(kPdfFloor);
    auto excess = [&](double th) { return (pf.evalOneMinusCos(chi2::oneMinusCosFromTheta(th)) - pFloor) * std::sin(th); };
    return 2.0 * kPi * chi2::integrate(excess, 0.0, thetaFloor, 1e-10, chi2::Singular::Lower);
}

}  // namespace

// Single-constituent layers. pdfAround must integrate to 1 - deficit over the sphere (see the
// FINDING above; the quadrature of the chord-based evaluation at relative tolerance 1e-11 agrees
// with itself at 1e-10 to 1.5e-10 for Petzold, the worst case: bound 1e-9, as kQuadTol in
// phase_functions_test.cpp) and the samples must follow it in (theta, phi): 8 azimuth sectors;
// uniform theta bins for the broad functions, geometric ones inside the forward peak for the
// others. 100000 samples each (these phase functions' own samplers are tested with more in
// phase_functions_test.cpp); the smallest cells (back hemisphere of Petzold) are pooled.
TEST(SampleAroundChiSquare, SingleConstituentLayersFollowPdfAround) {
    struct Case {
        const char* what;
        ir::PhaseFunction p;
        std::vector<double> edges;
    };
    const std::vector<Case> cases = {
        {"around: isotropic", irPhase(T::Isotropic), chi2::uniformEdges(0, kPi, 16)},
        {"around: Henyey-Greenstein g 0.9", irPhase(T::HenyeyGreenstein, 0.9), chi2::forwardPeakedThetaEdges(1e-3, 15, 0.5, 12)},
        {"around: Petzold", irPhase(T::Petzold), chi2::forwardPeakedThetaEdges(1e-5, 18, 0.5, 12)},
        {"around: Fournier-Forand B 0.0183", irPhase(T::FournierForand, 0, 0.0183),
         chi2::forwardPeakedThetaEdges(1e-6, 18, 0.5, 12)},
        {"around: Rayleigh-like (k 1)", irPhase(T::RayleighLike, 0, 0, 1.0), chi2::uniformEdges(0, kPi, 16)},
    };
    uint64_t sd = 201;
    for (const Case& c : cases) {
        const Medium m = singleScattererMedium(c.p);
        const BandGroup g{0, 1};
        const auto pdf = pdfAroundOf(m, g);
        expectSameAboutTiltedAxis(m, g, c.what);
        const double deficit = floorDeficit(m.layers()[0].phases[0]);
        const double norm = chi2::sphereIntegral(pdf, kPi, 1e-11);
        std::printf("[ info ] %s: pdfAround integrates to 1 %+.3g (floor deficit %.3g)\n", c.what, norm - 1, deficit);
        EXPECT_NEAR(norm, 1.0 - deficit, 1e-9) << c.what;
        const auto r = aroundChiSquare(m, g, c.edges, 8, 100000, seed(sd++), pdf);
        report(c.what, r);
        EXPECT_FALSE(r.rejectedAt(kSamplingAlpha)) << c.what << ": " << r.summary();
    }
}

// The two-constituent layer over its three bands. pdfAround must be the band-averaged mixture
// (checked against the two phase functions built here and the shares computed here), integrate
// to 1 - deficit, and the samples must follow it: 300000 samples (this is the case nothing else covers),
// Petzold's binning.
TEST(SampleAroundChiSquare, MixedLayerFollowsBandAveragedMixture) {
    const Medium m = twoConstituentMedium();
    const BandGroup g{0, 3};
    const double w = averageWaterShare();
    EXPECT_NEAR(w, (2.0 / 3 + 4.0 / 13 + 2.0 / 17) / 3, 1e-12);
    const PhaseFunction water = PhaseFunction::molecularWater(0.835), particles = PhaseFunction::petzold();
    for (double th : {1e-4, 0.01, 0.3, 1.0, 2.0, 3.1}) {
        const Vec3 v = directionAt(th, 0.7);
        const double t = chi2::oneMinusCosFromTheta(th);
        const double want = w * water.evalOneMinusCos(t) + (1 - w) * particles.evalOneMinusCos(t);
        // The chord |v - axis| carries ~1e-16 absolute rounding: 2e-12 relative in 1 - cos at
        // theta = 1e-4, where Petzold's slope is -0.67 in log t.
        EXPECT_NEAR(m.pdfAround(0, g, kAxis, v) / want, 1.0, 1e-10) << th;
    }
    const auto pdf = pdfAroundOf(m, g);
    expectSameAboutTiltedAxis(m, g, "mixed layer");
    const double deficit = w * floorDeficit(water) + (1 - w) * floorDeficit(particles);
    const double norm = chi2::sphereIntegral(pdf, kPi, 1e-11);
    std::printf("[ info ] mixed layer: pdfAround integrates to 1 %+.3g (floor deficit %.3g)\n", norm - 1, deficit);
    EXPECT_NEAR(norm, 1.0 - deficit, 1e-9);
    const auto r = aroundChiSquare(m, g, chi2::forwardPeakedThetaEdges(1e-5, 18, 0.5, 12), 8, 300000, seed(211), pdf);
    report("around: molecular water + Petzold, 3 bands", r);
    EXPECT_FALSE(r.rejectedAt(kSamplingAlpha)) << r.summary();
}

// Power: (a) HG sampled with g = 0.9 judged against g = 0.92; (b) the mixed layer's samples
// judged against the mixture weighted by the share of the band-averaged b (0.3077 instead of
// 0.3640: the plausible mistake of averaging b before dividing).
TEST(SampleAroundChiSquare, RejectsWrongPdfs) {
    {
        const Medium m = singleScattererMedium(irPhase(T::HenyeyGreenstein, 0.9));
        const PhaseFunction wrong = PhaseFunction::henyeyGreenstein(0.92);
        const auto r = aroundChiSquare(m, BandGroup{0, 1}, chi2::forwardPeakedThetaEdges(1e-3, 15, 0.5, 12), 8, 100000,
                                       seed(202), [&](double th, double) {
                                           return wrong.evalOneMinusCos(chi2::oneMinusCosFromTheta(th));
                                       });
        report("around, wrong: HG 0.9 judged as HG 0.92", r);
        EXPECT_TRUE(r.rejectedAt(kSamplingAlpha)) << r.summary();
    }
    {
        const Medium m = twoConstituentMedium();
        const double bw = 0.30 + 0.20 + 0.10, bp = 0.15 + 0.45 + 0.75, wWrong = bw / (bw + bp);
        const PhaseFunction water = PhaseFunction::molecularWater(0.835), particles = PhaseFunction::petzold();
        const auto r = aroundChiSquare(m, BandGroup{0, 3}, chi2::forwardPeakedThetaEdges(1e-5, 18, 0.5, 12), 8, 300000,
                                       seed(211), [&](double th, double) {
                                           const double t = chi2::oneMinusCosFromTheta(th);
                                           return wWrong * water.evalOneMinusCos(t) + (1 - wWrong) * particles.evalOneMinusCos(t);
                                       });
        report("around, wrong: mixture weighted by the averaged b", r);
        EXPECT_TRUE(r.rejectedAt(kSamplingAlpha)) << r.summary();
    }
}

// =============================================================================================
// 3. The sun disc

namespace {

SunSource sunAt(double zenithDeg, double azimuthDeg, double diameterDeg) {
    ir::Sun s;
    s.zenith = deg2rad(zenithDeg);
    s.azimuth = deg2rad(azimuthDeg);
    s.halfAngle = 0.5 * deg2rad(diameterDeg);
    s.irradiance = Spectrum::constant(1.0);
    return makeSun(s, {Band{0.4, 0.6}});
}

// Uniform over the cone of half-angle alpha about the sun: with t = 1 - cos(theta) from the
// disc's centre, P(t < t1) = t1 / (1 - cos alpha), and the azimuth about the centre is uniform.
// Cells: nRings rings of equal solid angle (equal steps in t up to tCone = 1 - cos(alphaJudge))
// times nSectors azimuth sectors, each expecting N / (nRings nSectors); then "outside the
// cone" (expected 0). Samples are binned in a frame about the sun built from a tangent hint (not
// the sampler's Frame::fromNormal). A sample counts as inside the true cone when its t exceeds
// tCone by less than 1e-9 relative (the sampler's and this binning's rounding near the rim is
// ~1e-11 relative for the 0.53 deg disc): it then goes to the outermost ring.
// `alphaJudge` is the disc the samples are judged against (the sun's, or a wrong one).
chi2::ChiSquareResult discChiSquare(const SunSource& sun, double alphaJudge, int nRings, int nSectors, long long samples,
                                    uint64_t sd, long long* notInDisc) {
    const Frame f = Frame::fromNormalAndTangent(sun.direction, Vec3{0.3, -0.8, 0.5});
    const double tCone = 2.0 * sqr(std::sin(0.5 * alphaJudge));  // 1 - cos, exact for small angles
    const size_t cells = static_cast<size_t>(nRings * nSectors);
    const double N = static_cast<double>(samples);
    std::vector<double> observed(cells + 1, 0.0), expected(cells + 1, N / (nRings * nSectors));
    expected[cells] = 0.0;
    std::vector<std::string> labels(cells + 1);
    for (int i = 0; i < nRings; ++i)
        for (int j = 0; j < nSectors; ++j)
            labels[static_cast<size_t>(i * nSectors + j)] = "ring " + std::to_string(i) + " sector " + std::to_string(j);
    labels[cells] = "outside the disc";
    *notInDisc = 0;
    for (long long k = 0; k < samples; ++k) {
        RandomStream rs(sd, 0, static_cast<uint64_t>(k));
        const double u1 = rs.uniform(), u2 = rs.uniform();
        const Vec3 w = sun.sampleDirection(u1, u2);
        *notInDisc += !sun.inDisc(w);
        const Vec3 l = f.toLocal(w);
        const double theta = std::atan2(std::hypot(l.x, l.y), l.z);
        const double t = chi2::oneMinusCosFromTheta(theta);
        double phi = std::atan2(l.y, l.x);
        if (phi < 0) phi += 2.0 * kPi;
        if (!(t <= tCone * (1 + 1e-9)) || !std::isfinite(phi)) {
            observed[cells] += 1;
            continue;
        }
        const int i = std::min(nRings - 1, static_cast<int>(t / tCone * nRings));
        const int j = std::min(nSectors - 1, static_cast<int>(phi / (2.0 * kPi) * nSectors));
        observed[static_cast<size_t>(i * nSectors + j)] += 1;
    }
    chi2::Options o;
    o.samples = samples;
    chi2::ChiSquareResult r = chi2::testCells(observed, expected, labels, o);
    r.samples = samples;
    return r;
}

}  // namespace

// The 0.53 deg sun and a 10 deg disc, at the zenith and at 85 deg (azimuth 140 deg; the large
// disc then reaches 5 deg below the horizon, which the sampler does not care about: its
// contract is the whole cone). 10 rings x 12 sectors, 120000 samples: 1000 expected per cell,
// 119 dof. Also: solidAngle is the cone's 2 pi (1 - cos alpha) (1e-9 relative: cos alpha rounds
// to 1e-16, i.e. 1e-11 of 1 - cos alpha for the small disc), and every sample lies inDisc.
TEST(SunDiscChiSquare, SamplesAreUniformOverTheCone) {
    struct Case {
        double zenith, azimuth, diameter;
    };
    uint64_t sd = 301;
    for (const Case c : {Case{0, 0, 0.53}, Case{0, 0, 10}, Case{85, 140, 0.53}, Case{85, 140, 10}}) {
        const SunSource sun = sunAt(c.zenith, c.azimuth, c.diameter);
        const double alpha = 0.5 * deg2rad(c.diameter);
        ASSERT_TRUE(sun.enabled);
        EXPECT_NEAR(sun.solidAngle / (4.0 * kPi * sqr(std::sin(0.5 * alpha))), 1.0, 1e-9);
        long long outside = 0;
        const auto r = discChiSquare(sun, alpha, 10, 12, 120000, seed(sd++), &outside);
        const std::string what = "sun disc " + std::to_string(c.diameter).substr(0, 4) + " deg at zenith " +
                                 std::to_string(static_cast<int>(c.zenith)) + " deg";
        report(what.c_str(), r);
        EXPECT_FALSE(r.rejectedAt(kSamplingAlpha)) << what << ": " << r.summary();
        EXPECT_EQ(outside, 0) << what << ": samples that inDisc rejects";
    }
}

// inDisc is the cone: directions at 1 - 1e-6 and 1 + 1e-6 times the angular radius from the
// centre, at 16 azimuths, are in and out (for the 0.53 deg disc the two differ by 2e-11 in
// cos, 2e5 times the rounding of the test direction); the anti-solar direction and a direction
// 90 deg off are out; a disabled sun has no disc.
TEST(SunDiscChiSquare, InDiscIsTheCone) {
    for (const auto& [zen, az, dia] : {std::tuple{0.0, 0.0, 0.53}, std::tuple{0.0, 0.0, 10.0}, std::tuple{85.0, 140.0, 0.53},
                                       std::tuple{85.0, 140.0, 10.0}, std::tuple{30.0, -60.0, 0.53}}) {
        SunSource sun = sunAt(zen, az, dia);
        const double alpha = 0.5 * deg2rad(dia);
        const Frame f = Frame::fromNormalAndTangent(sun.direction, Vec3{0.3, -0.8, 0.5});
        for (int j = 0; j < 16; ++j) {
            const double phi = 2.0 * kPi * (j + 0.37) / 16;
            auto at = [&](double th) {
                return f.toWorld({std::sin(th) * std::cos(phi), std::sin(th) * std::sin(phi), std::cos(th)});
            };
            EXPECT_TRUE(sun.inDisc(at(alpha * (1 - 1e-6)))) << zen << " " << dia << " " << j;
            EXPECT_FALSE(sun.inDisc(at(alpha * (1 + 1e-6)))) << zen << " " << dia << " " << j;
            EXPECT_TRUE(sun.inDisc(at(0.0)));
            EXPECT_FALSE(sun.inDisc(at(0.5 * kPi)));
        }
        EXPECT_FALSE(sun.inDisc(-sun.direction));
        sun.enabled = false;
        EXPECT_FALSE(sun.inDisc(sun.direction));
    }
}

// Power: the samples of the 0.53 deg sun judged against a disc 1 % larger in angular radius (2 %
// more solid angle: its outermost ring expects 20 % of its count beyond the true rim, ~200 per
// sector, and sees none), and those of the 10 deg disc judged against a 1 % smaller one (~2 % of
// the samples land outside it, in a cell that expects none).
TEST(SunDiscChiSquare, RejectsWrongDiscs) {
    long long outside = 0;
    {
        const SunSource sun = sunAt(0, 0, 0.53);
        const auto r = discChiSquare(sun, 1.01 * sun.halfAngle, 10, 12, 120000, seed(301), &outside);
        report("sun disc, wrong: 0.53 deg judged as 1 % wider", r);
        EXPECT_TRUE(r.rejectedAt(kSamplingAlpha)) << r.summary();
    }
    {
        const SunSource sun = sunAt(85, 140, 10);
        const auto r = discChiSquare(sun, 0.99 * sun.halfAngle, 10, 12, 120000, seed(304), &outside);
        report("sun disc, wrong: 10 deg judged as 1 % narrower", r);
        EXPECT_TRUE(r.rejectedAt(kSamplingAlpha)) << r.summary();
    }
}
