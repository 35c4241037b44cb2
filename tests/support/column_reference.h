#pragma once
// The column solver (`littoral column`, column/: no transport code shared with render/) as the
// reference of the 3-D estimators' probes on horizontally invariant columns (issue 19): its cells
// at the probes' depths, and the check of a run's probe table against them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/probe_table.h"
#include "tests/support/test_support.h"

namespace littoral::testing_support {

using ColumnCells = std::map<double, std::map<std::string, double>>;  // depth -> quantity -> value

// {depth -> {quantity -> value}} of `littoral column SCENE --depths DEPTHS` with n streams per half
// (Ed, Eou and Lu of band 0), solved in a scratch folder named after `tag` (tests that run at the
// same time use different tags).
inline ColumnCells runColumnSolver(const std::filesystem::path& scene, const std::string& depths, int streams,
                                   const std::string& tag) {
    const std::filesystem::path out =
        scratchDir("pipelines", "column_" + tag + "_" + scene.stem().string() + std::to_string(streams));
    const CommandResult r = runLittoral("--quiet column " + scene.string() + " --out " + out.string() + " --depths " +
                                        depths + " --streams " + std::to_string(streams));
    EXPECT_EQ(r.status, 0) << r.output;
    ColumnCells cells;
    std::ifstream in(out / "profiles.json");
    if (!in) return cells;
    const auto j = nlohmann::json::parse(in);
    for (const auto& d : j["bands"][0]["depths"])
        for (const char* q : {"Ed", "Eou", "Lu"}) cells[d["depth_m"].get<double>()][q] = d[q].get<double>();
    return cells;
}

// How a run's probes are held to the column.
struct ColumnCheck {
    double k = 3;          // standard errors allowed (plus the solver's discretisation error)
    double maxRelSe = 0;   // a standard error above this share of the value fails (the check must bite)
    std::vector<std::string> quantities = {"Ed", "Eou"};
    std::string label = "forward";  // printed with each cell
};

// Every cell of `probes` (probe name -> depth) against the column solver: within k of its standard
// errors plus the solver's discretisation error, bounded by the change from 8 to 16 streams per half,
// and with a standard error of at most maxRelSe of the value.
inline void expectColumnAgreement(const ProbeTable& p, const std::filesystem::path& scene,
                                  const std::map<std::string, double>& depthOf, const std::string& depths,
                                  const ColumnCheck& check) {
    const ColumnCells base = runColumnSolver(scene, depths, 8, check.label),
                      fine = runColumnSolver(scene, depths, 16, check.label);
    for (const auto& [probe, z] : depthOf)
        for (const std::string& qs : check.quantities) {
            const char* q = qs.c_str();
            ASSERT_TRUE(p.count(probe) && p.at(probe).count(q)) << probe << " " << q;
            const ProbeCell& c = p.at(probe).at(q);
            ASSERT_TRUE(base.count(z) && fine.count(z)) << scene << " depth " << z;
            const double v = base.at(z).at(q), conv = std::abs(fine.at(z).at(q) - v);
            EXPECT_NEAR(c.value, v, check.k * c.se + conv) << scene.filename() << " " << probe << " " << q;
            EXPECT_LE(c.se, check.maxRelSe * c.value) << scene.filename() << " " << probe << " " << q;
            std::printf("[ %s ] %-22s %-6s %-3s %.5e +- %.2e (%.2f %%)  column %.5e  diff %+.2f %% = %+.1f se\n",
                        check.label.c_str(), scene.filename().c_str(), probe.c_str(), q, c.value, c.se,
                        100 * c.se / c.value, v, 100 * (c.value / v - 1), (c.value - v) / c.se);
        }
}

}  // namespace littoral::testing_support
