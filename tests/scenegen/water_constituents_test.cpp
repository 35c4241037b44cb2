// Water constituents: each data source reproduces its published numbers, compositions sum their
// components, and the dissertation's presets reproduce the printed tables.
#include "scenegen/water_constituents.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "scenegen/scene_file.h"
#include "tests/support/test_support.h"

using namespace littoral;
using namespace littoral::scenegen;
using littoral::testing_support::inputErrorOf;

// Pope and Fry (1997): the table's own entries come back exactly; between entries the value is
// interpolated linearly.
TEST(WaterConstituents, PureWaterAbsorptionIsPopeAndFry) {
    EXPECT_DOUBLE_EQ(pureWaterAbsorption(0.380), 0.01137);
    EXPECT_DOUBLE_EQ(pureWaterAbsorption(0.440), 0.00635);
    EXPECT_DOUBLE_EQ(pureWaterAbsorption(0.550), 0.0565);
    EXPECT_DOUBLE_EQ(pureWaterAbsorption(0.680), 0.465);
    EXPECT_DOUBLE_EQ(pureWaterAbsorption(0.700), 0.624);
    EXPECT_NEAR(pureWaterAbsorption(0.44125), 0.5 * (0.00635 + 0.00696), 1e-15);
    const Spectrum t = pureWaterAbsorptionTable();
    EXPECT_EQ(t.wavelengths().size(), 129u);
    for (double w : {0.4, 0.4525, 0.6, 0.6975}) EXPECT_NEAR(t.at(w), pureWaterAbsorption(w), 1e-15);
    const std::string err = inputErrorOf([] { pureWaterAbsorption(0.75); });
    EXPECT_NE(err.find("Pope and Fry"), std::string::npos) << err;
    EXPECT_NE(err.find("0.380-0.700 um"), std::string::npos) << err;
    EXPECT_THROW(pureWaterAbsorption(0.379), InputError);
}

// Morel (1974): b_w(500 nm) = 0.00222 (fresh) and 0.00288 m^-1 (sea), lambda^-4.32. The
// sea/fresh ratio is the 1.30 Morel gives (to its 3 printed digits: +-0.005).
TEST(WaterConstituents, PureWaterScatteringIsMorel) {
    EXPECT_DOUBLE_EQ(pureWaterScattering(0.5, WaterKind::Sea), 0.00288);
    EXPECT_DOUBLE_EQ(pureWaterScattering(0.5, WaterKind::Fresh), 0.00222);
    EXPECT_NEAR(pureWaterScattering(0.4, WaterKind::Sea) / pureWaterScattering(0.5, WaterKind::Sea), std::pow(0.8, -4.32),
                1e-14);
    EXPECT_NEAR(pureWaterScattering(0.45, WaterKind::Sea) / pureWaterScattering(0.45, WaterKind::Fresh), 1.30, 0.005);
}

// Bricaud et al. (1998) at 440 nm: A = 0.037824, E = 0.626633; Gordon and Morel (1983):
// b_p(550) = 0.30 Chl^0.62.
TEST(WaterConstituents, PhytoplanktonIsBricaudAndGordonMorel) {
    EXPECT_NEAR(phytoplanktonAbsorption(0.440, 1.0), 0.037824, 1e-15);
    EXPECT_NEAR(phytoplanktonAbsorption(0.440, 10.0), 0.037824 * std::pow(10.0, 0.626633), 1e-14);
    EXPECT_NEAR(phytoplanktonAbsorption(0.675, 1.0), 0.5 * (0.018238 + 0.0179744), 1e-15);  // between 674 and 676 nm
    EXPECT_EQ(phytoplanktonAbsorption(0.5, 0.0), 0.0);
    EXPECT_NEAR(phytoplanktonScattering(0.550, 1.0), 0.30, 1e-15);
    EXPECT_NEAR(phytoplanktonScattering(0.550, 10.0), 0.30 * std::pow(10.0, 0.62), 1e-14);
    EXPECT_NEAR(phytoplanktonScattering(0.440, 2.0) / phytoplanktonScattering(0.550, 2.0), 550.0 / 440.0, 1e-14);
    EXPECT_NE(inputErrorOf([] { phytoplanktonAbsorption(0.39, 1.0); }).find("Bricaud"), std::string::npos);
    EXPECT_NE(inputErrorOf([] { phytoplanktonAbsorption(0.5, -1.0); }).find("chlorophyll"), std::string::npos);
}

// Babin et al. (2003): 0.5 m^2 g^-1 at 555 nm (flat), 0.041 m^2 g^-1 at 443 nm with slope
// 0.0123 nm^-1; CDOM: a_g(440) exp(-0.014 (lambda - 440)) (Bricaud et al. 1981).
TEST(WaterConstituents, MineralAndCdom) {
    EXPECT_NEAR(mineralScattering(0.555, 10.0), 5.0, 1e-14);
    EXPECT_NEAR(mineralScattering(0.400, 10.0), 5.0, 1e-14);
    EXPECT_NEAR(mineralAbsorption(0.443, 10.0), 0.41, 1e-15);
    EXPECT_NEAR(mineralAbsorption(0.543, 10.0) / mineralAbsorption(0.443, 10.0), std::exp(-1.23), 1e-14);
    EXPECT_NEAR(cdomAbsorption(0.440, 0.2), 0.2, 1e-16);
    EXPECT_NEAR(cdomAbsorption(0.540, 0.2), 0.2 * std::exp(-1.4), 1e-16);
    EXPECT_NE(inputErrorOf([] { mineralScattering(0.5, -2.0); }).find("sediment concentration"), std::string::npos);
    EXPECT_NE(inputErrorOf([] { cdomAbsorption(0.5, -0.1); }).find("CDOM"), std::string::npos);
}

// A composition's totals are the sums of its components, on its grid and band-averaged; the
// scatterers' b are the weights of the phase-function mixture.
TEST(WaterConstituents, CompositionSumsComponents) {
    WaterComposition c;
    c.chlorophyllMgM3 = 1.5;
    c.sedimentGM3 = 2.0;
    c.cdomA440PerM = 0.1;
    std::vector<double> grid;
    for (int i = 0; i <= 30; ++i) grid.push_back(0.40 + 0.01 * i);
    const WaterIops w = computeIops(c, grid, "test water");
    ASSERT_EQ(w.components.size(), 4u);
    EXPECT_TRUE(w.includesPureWater);
    const Spectrum a = w.absorption(), b = w.scattering();
    for (double wl : grid) {
        const double aSum = pureWaterAbsorption(wl) + phytoplanktonAbsorption(wl, 1.5) + mineralAbsorption(wl, 2.0) +
                            cdomAbsorption(wl, 0.1);
        const double bSum =
            pureWaterScattering(wl, WaterKind::Sea) + phytoplanktonScattering(wl, 1.5) + mineralScattering(wl, 2.0);
        EXPECT_NEAR(a.at(wl) / aSum, 1.0, 1e-14) << wl;
        EXPECT_NEAR(b.at(wl) / bSum, 1.0, 1e-14) << wl;
        EXPECT_NEAR(w.absorptionAt(wl) / aSum, 1.0, 1e-14);
    }
    const auto weights = w.phaseWeightsAt(0.5);
    ASSERT_EQ(weights.size(), 3u);  // CDOM does not scatter
    EXPECT_EQ(weights[0].second, (ir::PhaseFunction{"pure-water", {{"depolarization_ratio", kPureWaterDepolarization}}}));
    EXPECT_EQ(weights[1].second, (ir::PhaseFunction{"petzold", {}}));
    double sum = 0;
    for (const auto& [bi, p] : weights) sum += bi;
    EXPECT_NEAR(sum / w.scatteringAt(0.5), 1.0, 1e-14);
    const Band band{0.45, 0.55};
    double bandSum = 0;
    for (const auto& [bi, p] : w.phaseWeights(band)) bandSum += bi;
    EXPECT_NEAR(bandSum / b.bandAverage(band), 1.0, 1e-13);

    c.includePureWater = false;
    c.chlorophyllMgM3 = 0;
    EXPECT_EQ(computeIops(c, grid).components.size(), 2u);
}

TEST(WaterConstituents, BadInputIsAClearInputError) {
    WaterComposition c;
    c.chlorophyllMgM3 = 1.0;
    EXPECT_NE(inputErrorOf([&] { computeIops(c, {0.39, 0.5}); }).find("Bricaud et al. 1998"), std::string::npos);
    c.chlorophyllMgM3 = 0;
    EXPECT_NE(inputErrorOf([&] { computeIops(c, {0.5, 0.72}); }).find("Pope and Fry"), std::string::npos);
    c.sedimentGM3 = -1;
    const std::string e = inputErrorOf([&] { computeIops(c, {0.5}); });
    EXPECT_NE(e.find("sediment concentration = -1"), std::string::npos) << e;
    c.sedimentGM3 = 0;
    EXPECT_THROW(computeIops(c, {0.5, 0.45}), InputError);  // wavelengths must increase
}

// ---- the dissertation's presets -------------------------------------------------------------

namespace {
// Table 10.3 as printed (spec/seed-ch05-10.md section 3.4), m^-1 at 0.4, 0.5, 0.6 um: chlorophyll
// a, b; TSS a, b; CDOM a, for Low, Mod, High.
struct Printed103 {
    const char* preset;
    double chlA[3], chlB[3], tssA[3], tssB[3], cdomA[3];
};
const Printed103 kPrinted103[] = {
    {"low",
     {0.001862, 0.001469, 0.000401},
     {0.005185, 0.005652, 0.005412},
     {0.011478, 0.003963, 0.001528},
     {0.079333, 0.063466, 0.052888},
     {0.007222, 0.001472, 0.000184}},
    {"moderate",
     {0.009311, 0.007348, 0.002007},
     {0.025929, 0.028264, 0.027063},
     {0.057391, 0.019817, 0.007640},
     {0.396665, 0.317334, 0.264444},
     {0.036110, 0.007360, 0.000920}},
    {"high",
     {0.018623, 0.014696, 0.004015},
     {0.051859, 0.056527, 0.054127},
     {0.114783, 0.039635, 0.015281},
     {0.793330, 0.634667, 0.528889},
     {0.072220, 0.014720, 0.001840}},
};
}  // namespace

// Every entry of Table 10.3 is 0.01 / 0.05 / 0.10 x Table 9.6 printed to 6 decimals; the
// dissertation sometimes truncates instead of rounding (Low TSS b at 0.5 um: 0.0634667 printed
// 0.063466), so an entry may differ from the product by up to one unit of its last digit, 1e-6.
TEST(WaterPresets, Table103EntriesMatchPrintedTable) {
    const double wl[3] = {0.4, 0.5, 0.6};
    for (const auto& row : kPrinted103) {
        const WaterIops w = waterPreset(row.preset);
        EXPECT_FALSE(w.includesPureWater);
        const IopComponent* chl = w.component("chlorophyll");
        const IopComponent* tss = w.component("TSS");
        const IopComponent* cdom = w.component("CDOM");
        ASSERT_TRUE(chl && tss && cdom);
        for (int i = 0; i < 3; ++i) {
            EXPECT_NEAR(chl->absorption.at(wl[i]), row.chlA[i], 1e-6) << row.preset << " " << wl[i];
            EXPECT_NEAR(chl->scattering.at(wl[i]), row.chlB[i], 1e-6) << row.preset << " " << wl[i];
            EXPECT_NEAR(tss->absorption.at(wl[i]), row.tssA[i], 1e-6) << row.preset << " " << wl[i];
            EXPECT_NEAR(tss->scattering.at(wl[i]), row.tssB[i], 1e-6) << row.preset << " " << wl[i];
            EXPECT_NEAR(cdom->absorption.at(wl[i]), row.cdomA[i], 1e-6) << row.preset << " " << wl[i];
            EXPECT_EQ(cdom->scattering.at(wl[i]), 0.0);
        }
        EXPECT_EQ(chl->phase, (ir::PhaseFunction{"henyey-greenstein", {{"g", 0.88}}}));  // Chapter 10's phase function
    }
}

// The model's totals against the sums of the printed entries (spec/seed-ch05-10.md section 3.4:
// a_total, b_total) and the printed single-scattering albedos 0.804 / 0.909 / 0.965. Each total
// sums three (a) or two (b) entries that may each be off by 1e-6 (see above); albedos are printed
// to 3 decimals (+-5e-4).
TEST(WaterPresets, Table103TotalsMatchPrintedSums) {
    const double wl[3] = {0.4, 0.5, 0.6};
    const double albedo[3] = {0.804, 0.909, 0.965};
    const struct {
        const char* preset;
        double a[3], b[3];
    } totals[] = {{"low", {0.020562, 0.006904, 0.002113}, {0.084518, 0.069118, 0.058300}},
                  {"moderate", {0.102812, 0.034525, 0.010567}, {0.422594, 0.345598, 0.291507}},
                  {"high", {0.205626, 0.069051, 0.021136}, {0.845189, 0.691194, 0.583016}}};
    for (const auto& t : totals) {
        const WaterIops w = waterPreset(t.preset);
        const Spectrum a = w.absorption(), b = w.scattering();
        for (int i = 0; i < 3; ++i) {
            EXPECT_NEAR(a.at(wl[i]), t.a[i], 3e-6) << t.preset << " " << wl[i];
            EXPECT_NEAR(b.at(wl[i]), t.b[i], 2e-6) << t.preset << " " << wl[i];
            EXPECT_NEAR(b.at(wl[i]) / (a.at(wl[i]) + b.at(wl[i])), albedo[i], 5e-4) << t.preset << " " << wl[i];
        }
    }
}

// Table 9.3 (spec/seed-ch08-09.md section 3.2): absorption, scattering and the printed total
// extinction (3 decimals, +-5e-4); derived albedos 0.9021 / 0.5573 / 0.7173 (4 decimals).
TEST(WaterPresets, Table93GroupsMatchPrintedTable) {
    const struct {
        const char* preset;
        double a, b, c, albedo;
    } rows[] = {{"coastal", 0.038, 0.350, 0.388, 0.9021}, {"bay", 0.143, 0.180, 0.323, 0.5573}, {"turbid", 0.268, 0.680, 0.948, 0.7173}};
    for (const auto& r : rows) {
        const WaterIops w = waterPreset(r.preset);
        EXPECT_FALSE(w.includesPureWater);
        ASSERT_EQ(w.components.size(), 1u);
        const Spectrum a = w.absorption(), b = w.scattering();
        EXPECT_TRUE(a.isConstant());
        EXPECT_DOUBLE_EQ(a.at(0.55), r.a);
        EXPECT_DOUBLE_EQ(b.at(0.55), r.b);
        EXPECT_NEAR(a.at(0.45) + b.at(0.45), r.c, 5e-4);
        EXPECT_NEAR(b.at(0.45) / (a.at(0.45) + b.at(0.45)), r.albedo, 5e-5);
        EXPECT_EQ(w.phaseWeightsAt(0.5).size(), 1u);
    }
}

TEST(WaterPresets, NamesAndErrors) {
    EXPECT_EQ(waterPresetNames(), (std::vector<std::string>{"pure", "low", "moderate", "high", "coastal", "bay", "turbid"}));
    const WaterIops pure = waterPreset("pure");
    EXPECT_EQ(pure.absorption().at(0.5), 0.0);
    EXPECT_EQ(pure.scattering().at(0.5), 0.0);
    EXPECT_TRUE(pure.phaseWeightsAt(0.5).empty());
    const std::string e = inputErrorOf([] { waterPreset("turbidd"); });
    EXPECT_NE(e.find("did you mean 'turbid'"), std::string::npos) << e;
    EXPECT_NE(e.find("low, moderate, high"), std::string::npos) << e;
}
