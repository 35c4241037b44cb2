// `littoral column` end to end: Mobley et al. (1993) problems 1 and 6 from their scene files in
// data_synthetic/mobley1993/, every cell of reference-data.md; the files it writes; a refused scene.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "pipelines/reference/mobley1993.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral::testing_support;
namespace mobley1993 = littoral::reference::mobley1993;

namespace {

// {depth -> {quantity -> value}} of band 0 of `littoral column SCENE --depths ... --streams n`.
std::map<double, std::map<std::string, double>> runColumn(const std::string& file, const std::string& depths, int streams) {
    const fs::path scene = fs::path(LITTORAL_SOURCE_DIR) / "data_synthetic" / "mobley1993" / file;
    const fs::path out = scratchDir("column", fs::path(file).stem().string() + "_" + std::to_string(streams));
    const CommandResult r = runLittoral("--quiet column " + scene.string() + " --out " + out.string() + " --depths " + depths +
                                        " --streams " + std::to_string(streams));
    EXPECT_EQ(r.status, 0) << r.output;
    std::map<double, std::map<std::string, double>> cells;
    std::ifstream in(out / "profiles.json");
    if (!in) {
        ADD_FAILURE() << "no profiles.json in " << out;
        return cells;
    }
    const auto j = nlohmann::json::parse(in);
    for (const auto& d : j["bands"][0]["depths"])
        for (const char* q : {"Ed", "Eou", "Lu", "Eu"}) cells[d["depth_m"].get<double>()][q] = d[q].get<double>();
    return cells;
}

// A deterministic solver has no standard error; its error is the discretisation's. So a cell passes
// when |solver/mean - 1| <= 3 s/mean + rounding of the table's 3 digits (as for the Monte Carlo
// estimators, pipelines/reference/mobley1993.h) + the change from the default 8 to 16 Gauss directions per
// side of the Snell-window edge (a bound on the default's quadrature error, since the 16-direction
// result has converged further).
void checkProblem(const std::string& file, int problem, double w0, const std::vector<double>& taus, const std::string& depths) {
    const auto base = runColumn(file, depths, 8), fine = runColumn(file, depths, 16);
    for (double tau : taus) {
        const mobley1993::Row* row = mobley1993::find(problem, w0, tau);
        ASSERT_NE(row, nullptr);
        const std::pair<const char*, const mobley1993::Cell*> quantities[] = {{"Ed", &row->Ed}, {"Eou", &row->Eou}, {"Lu", &row->Lu}};
        for (const auto& [q, cell] : quantities) {
            ASSERT_TRUE(base.count(tau) && fine.count(tau)) << file << " tau " << tau;
            const double v = base.at(tau).at(q), v2 = fine.at(tau).at(q);
            const double conv = std::abs(v2 - v) / cell->mean;
            const double tol = 3 * cell->sOverMean + mobley1993::roundingHalfUnit(*cell) + conv;
            const double rel = v / cell->mean - 1;
            EXPECT_LE(std::abs(rel), tol) << file << " tau " << tau << " " << q << ": " << v << " vs " << cell->mean;
            std::printf("[ column ] %-22s tau %4.1f %-3s %.4e (16: %.4e)  table %.3e  diff %+6.2f %%  tol %5.2f %%\n",
                        file.c_str(), tau, q, v, v2, cell->mean, 100 * rel, 100 * tol);
        }
    }
}

}  // namespace

TEST(ColumnMobley1993, Problem1Albedo09) { checkProblem("problem1_albedo09.yaml", 1, 0.9, {1, 5, 10}, "1,5,10"); }
TEST(ColumnMobley1993, Problem1Albedo02) { checkProblem("problem1_albedo02.yaml", 1, 0.2, {1, 5, 10}, "1,5,10"); }

// Problem 6's tau = 5 cells are at the bottom; there the identities Eou = 2 Eu = Ed (R = 0.5) and
// Lu = Eu / pi hold to rounding in the solver (tests/column/column_analytic_test.cpp): 1e-9.
TEST(ColumnMobley1993, Problem6ShallowBottom) {
    checkProblem("problem6.yaml", 6, 0.2, {1, 5}, "1,5");
    const auto b = runColumn("problem6.yaml", "1,5", 8).at(5.0);
    EXPECT_NEAR(b.at("Eou") / b.at("Ed"), 1.0, 1e-9);
    EXPECT_NEAR(b.at("Eou") / (2 * b.at("Eu")), 1.0, 1e-9);
    EXPECT_NEAR(M_PI * b.at("Lu") / b.at("Eu"), 1.0, 1e-9);
}

// The command writes its four files and prints the profile (a header and one row per depth).
TEST(ColumnCli, WritesProfilesAndPrintsThem) {
    const fs::path scene = fs::path(LITTORAL_SOURCE_DIR) / "data_synthetic" / "mobley1993" / "problem6.yaml";
    const fs::path out = scratchDir("column", "cli") / "out";
    const CommandResult r = runLittoral("column " + scene.string() + " --out " + out.string());
    ASSERT_EQ(r.status, 0) << r.output;
    for (const char* f : {"profiles.csv", "profiles.json", "radiance.csv", "profiles.png", "charts.json", "littoral_plots.py"}) EXPECT_TRUE(fs::is_regular_file(out / f)) << f;
    EXPECT_NE(r.output.find("depth_m"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("Rrs"), std::string::npos) << r.output;
    // Default grid: 0 to the bottom (5 m) every metre, plus the probes' depths (1 and 4.999 m).
    std::ifstream csv(out / "profiles.csv");
    int rows = 0;
    for (std::string line; std::getline(csv, line);) ++rows;
    EXPECT_EQ(rows, 1 + 7);
}

// A scene the column cannot honour is refused with its location, and leaves no output folder.
TEST(ColumnCli, RefusesWhatAColumnCannotHonour) {
    const fs::path dir = scratchDir("column", "refused");
    const std::string base = R"(scene: {name: refused, domain: {x: [-5, 5], y: [-5, 5]}}
sun: {zenith_deg: 30, irradiance: 1000}
water:
  horizontal: periodic
  optics: {preset: coastal}
)";
    const std::pair<std::string, std::string> cases[] = {
        {base + "  surface: {model: flat, roughness: {wind_speed_m_s: 5}}\n", "refused.yaml:6:"},
        // The anisotropic (default) Cox-Munk form, and shadowing other than the default smith-light
        // (the column's one-facet normalisation), are refused at their keys.
        {base + "  surface: {model: flat, roughness: {wind_speed: 5}}\n", "refused.yaml:6:"},
        {base + "  surface: {model: flat, roughness: {wind_speed: 5, slopes: isotropic, shadowing: none}}\n",
         "refused.yaml:6:"},
        {base + "  surface: {model: flat, roughness: {wind_speed: 5, slopes: isotropic, shadowing: smith-separable}}\n",
         "refused.yaml:6:"},
        {base + "bathymetry: {type: planar_slope, z0_m: -5, slope_x: 0.1, material: sand}\nmaterials: [{name: sand, reflectance: 0.2}]\n",
         "refused.yaml:6:"},
        {base + "  surface: {model: sinusoid, amplitude: 0.2, wavelength: 4}\n", "refused.yaml:6:"},
    };
    for (const auto& [text, where] : cases) {
        const fs::path scene = writeTextFile(dir, "refused.yaml", text), out = dir / "out";
        const CommandResult r = runLittoral("column " + scene.string() + " --out " + out.string());
        EXPECT_EQ(r.status, 1) << r.output;
        EXPECT_NE(r.output.find(where), std::string::npos) << r.output;
        EXPECT_NE(r.output.find("error:"), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(out)) << r.output;
    }
}
