// Mobley et al. (1993) canonical problems 1 (albedo 0.9 and 0.2) and 6, as the scene files in
// data_synthetic/mobley1993/, run end to end with `littoral run` (the path estimator) and compared
// cell by cell with the published model means (pipelines/reference/mobley1993.h, reference-data.md).
//
// A cell passes when its relative difference from the table mean is within
//   max(3 s/mean, 3 se/mean) + half a unit of the table's third significant digit,
// s/mean the published inter-model spread, se the run's standard error from independent batches
// (render/probes.h), and the rounding term because the table prints 3 digits (at problem 6,
// tau = 1, Ed its s/mean is printed as 0.000). So that this cannot pass by being noisy, every
// cell must also have se/mean <= max(s/mean, 1 %): the comparison is at least as strict as the
// models' own agreement, or 3 % where they agree better than 1 %.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "pipelines/reference/mobley1993.h"
#include "tests/support/probe_table.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral::testing_support;
namespace mobley1993 = littoral::reference::mobley1993;

namespace {

// Runs one scene file and returns {probe name -> {quantity -> (value, stderr)}} of band 0. With
// `backward`, render.probe_photons: 0 turns the forward irradiance tallies off, so that every
// quantity comes from backward paths (these columns are horizontally invariant, where Ed and Eou
// are otherwise tallied forward; render/forward_tally.h).
ProbeTable runProblem(const std::string& file, bool backward = false) {
    fs::path scene = fs::path(LITTORAL_SOURCE_DIR) / "data_synthetic" / "mobley1993" / file;
    const fs::path out = scratchDir("mobley1993", fs::path(file).stem().string() + (backward ? "_backward" : ""));
    if (backward) {
        std::ifstream in(scene);
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        scene = writeTextFile(out.parent_path(), fs::path(file).stem().string() + "_backward.yaml",
                              replacedOnce(text, "  estimator: path\n", "  estimator: path\n  probe_photons: 0\n"));
    }
    const CommandResult r = runLittoral("--quiet run " + scene.string() + " --out " + out.string());
    EXPECT_EQ(r.status, 0) << r.output;
    return readProbeTable(out);
}

using Cells = ProbeTable;

Cells checkProblem(const std::string& file, int problem, double w0, const std::map<double, std::string>& probeAtTau,
                   double noiseFloor = 0.01, bool backward = false) {
    const auto cells = runProblem(file, backward);
    for (const auto& [tau, probe] : probeAtTau) {
        const mobley1993::Row* row = mobley1993::find(problem, w0, tau);
        EXPECT_NE(row, nullptr) << problem << " " << w0 << " " << tau;
        if (!row) continue;
        const std::pair<const char*, const mobley1993::Cell*> quantities[] = {
            {"Ed", &row->Ed}, {"Eou", &row->Eou}, {"Lu", &row->Lu}};
        for (const auto& [q, cell] : quantities) {
            if (!cells.count(probe) || !cells.at(probe).count(q)) {
                ADD_FAILURE() << file << ": no " << q << " for probe " << probe;
                continue;
            }
            const ProbeCell& c = cells.at(probe).at(q);
            const double rel = c.value / cell->mean - 1.0;
            const double tol = mobley1993::toleranceWithRounding(*cell, c.se);
            EXPECT_LE(std::abs(rel), tol) << file << " tau " << tau << " " << q << ": " << c.value << " +- " << c.se
                                          << " vs " << cell->mean << " (s/mean " << cell->sOverMean << ")";
            EXPECT_LE(c.se / c.value, std::max(cell->sOverMean, noiseFloor))
                << file << " tau " << tau << " " << q << ": the run is too noisy to test this cell";
            std::printf("[ mobley ] %-22s tau %4.1f %-3s %.4e +- %.2e  table %.3e  diff %+6.2f %%  tol %5.2f %%\n",
                        file.c_str(), tau, q, c.value, c.se, cell->mean, 100 * rel, 100 * tol);
        }
    }
    return cells;
}

}  // namespace

// The column is horizontally invariant, so a pilot chooses forward or backward per cell
// (docs/rendering.md); Lu at tau 1 and 5 goes forward (the collision estimator: the pilot predicts
// 0.07 % and 0.3 % against 0.6 % and 0.9 % backward), so the published Lu checks it.
TEST(Mobley1993, Problem1Albedo09) {
    const Cells cells = checkProblem("problem1_albedo09.yaml", 1, 0.9, {{1.0, "tau1"}, {5.0, "tau5"}, {10.0, "tau10"}});
    EXPECT_EQ(cells.at("tau1").at("Lu").method, "forward");
    EXPECT_EQ(cells.at("tau5").at("Lu").method, "forward");
}

// Backward paths for every quantity (the forward tallies off): the estimator every scene that is
// not a column uses for its irradiance probes.
TEST(Mobley1993, Problem1Albedo02BackwardPaths) {
    checkProblem("problem1_albedo02.yaml", 1, 0.2, {{1.0, "tau1"}, {5.0, "tau5"}, {10.0, "tau10"}}, 0.01, true);
}

// Problem 6 also has the bottom identities Eou = 2 Eu = Ed and Lu = Eu / pi for a Lambertian
// bottom (reference-data.md); Eou and Lu at the bottom are compared with Ed through them, within
// 3 combined standard errors. In this low-albedo water the upwelling light is mostly singly
// scattered sunlight, which backward paths find through their sun connection: the pilot predicts
// smaller errors for them (Eou at tau 1: 0.38 % against 0.5 % forward at 10^6 photons; Ed at tau 5:
// 0.31 % against 0.49 %; Eou at tau 5: 0.53 % against 1.5 %), so they answer, the choice the
// forward tallies' default must leave alone.
TEST(Mobley1993, Problem6ShallowBottom) {
    const Cells cells = checkProblem("problem6.yaml", 6, 0.2, {{1.0, "tau1"}, {5.0, "tau5"}});
    EXPECT_EQ(cells.at("tau1").at("Eou").method, "backward");
    EXPECT_EQ(cells.at("tau5").at("Ed").method, "backward");
    EXPECT_EQ(cells.at("tau5").at("Eou").method, "backward");
    ASSERT_TRUE(cells.count("tau5"));
    const auto& b = cells.at("tau5");
    const ProbeCell ed = b.at("Ed"), eou = b.at("Eou"), lu = b.at("Lu");
    EXPECT_NEAR(eou.value, ed.value, 3 * std::hypot(eou.se, ed.se));
    EXPECT_NEAR(2 * M_PI * lu.value, ed.value, 3 * std::hypot(2 * M_PI * lu.se, ed.se));
}

// The same problems with the dirsig estimator's photon maps (MediumPM in the water, SurfacePM on
// problem 6's bottom) instead of the path tracer, under the same tolerance, max(3 s/mean,
// 3 se/mean) + rounding. The standard errors are the spread of independent progressive passes,
// each with its own maps, so they include the maps' noise. At a CI budget (about 30-50 s each on
// 2 cores) the photon-map runs reach 0.1-1 % near the surface and 1-4 % at depth, so the noise
// floor (the cap on se/mean that keeps a noisy run from passing) is 5 % here instead of 1 %.
// Problem 1 with albedo 0.2 is not run with photon maps: at tau = 10 the light is 10^-6 of the
// surface's, and a photon pass would need ~10^4 times the photons of tau = 1 to reach it.
TEST(Mobley1993, Problem1Albedo09PhotonMaps) {
    checkProblem("problem1_albedo09_photon_maps.yaml", 1, 0.9, {{1.0, "tau1"}, {5.0, "tau5"}, {10.0, "tau10"}}, 0.05);
}

TEST(Mobley1993, Problem6PhotonMaps) {
    // Ed just above the bottom is the tightest cell: about +1.3 % (se 0.5 %, tolerance 1.7 %). Part
    // of it is the effective-scattering model itself (forward scattering within 0.01 sr counted as
    // unscattered): an independent 1-D Monte Carlo of Petzold water gives Ed(tau 5) 0.24 +- 0.17 %
    // higher with the model than without; the path tracer gives +0.4 +- 0.3 % against the table.
    // Without effective scattering the cell is -1.6 % and Lu(tau 1) -17 % (Petzold's forward peak
    // makes the beam estimates heavy-tailed).
    const Cells cells = checkProblem("problem6_photon_maps.yaml", 6, 0.2, {{1.0, "tau1"}, {5.0, "tau5"}}, 0.05);
    ASSERT_TRUE(cells.count("tau5"));
    const auto& b = cells.at("tau5");
    // The bottom identities of the path test (Eou = Ed, 2 pi Lu = Ed): here Eou and Lu come from the
    // surface map, Ed from the volume map and the direct beam, so they check the two maps
    // against each other.
    const ProbeCell ed = b.at("Ed"), eou = b.at("Eou"), lu = b.at("Lu");
    EXPECT_NEAR(eou.value, ed.value, 3 * std::hypot(eou.se, ed.se));
    EXPECT_NEAR(2 * M_PI * lu.value, ed.value, 3 * std::hypot(2 * M_PI * lu.se, ed.se));
}
