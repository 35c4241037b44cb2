// `littoral validate --quick` (pipelines/lib_validate.h) as CI runs it: every case passes, the
// report lists every case with its plots, summary.json holds each check's numbers, and the
// self-shading case covers three sun zeniths. Each check's tolerance is derived beside its case in
// pipelines/lib_validate.cpp; a noisy run cannot pass, since every Monte Carlo case also checks its
// standard errors against a cap.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "pipelines/lib_validate.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral::testing_support;

TEST(Validate, QuickSuitePassesAndItsReportShowsEveryCaseWithAPlot) {
    const fs::path out = scratchDir("validate", "quick");
    const CommandResult r = runLittoral("validate --quick --out " + out.string());
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("about"), std::string::npos) << "no ETA in the progress lines:\n" << r.output;
    const auto j = nlohmann::json::parse(littoral::readTextFile(out / "summary.json"));
    EXPECT_TRUE(j["pass"].get<bool>());
    EXPECT_TRUE(j["quick"].get<bool>());
    const std::string report = littoral::readTextFile(out / "report.html");

    std::set<std::string> expected, seen, categories;
    for (const auto& c : littoral::pipelines::validationCases())
        if (c.quick) expected.insert(c.name);
    for (const auto& c : j["cases"]) {
        const std::string name = c["name"].get<std::string>();
        seen.insert(name);
        categories.insert(c["category"].get<std::string>());
        EXPECT_TRUE(c["pass"].get<bool>()) << name << ": " << c.dump(1);
        EXPECT_GE(c["checks"].size(), 6u) << name;
        for (const auto& k : c["checks"]) {
            EXPECT_TRUE(k["pass"].get<bool>()) << name << ": " << k.dump();
            EXPECT_GT(k["tolerance"].get<double>(), 0) << name << ": " << k.dump();
        }
        EXPECT_NE(report.find("id=\"" + name + "\""), std::string::npos) << name << " is not in the report";
        ASSERT_GE(c["plots"].size(), 1u) << name;
        for (const auto& p : c["plots"]) {
            const std::string file = p.get<std::string>();
            EXPECT_GT(pngSize(out / file).first, 300u) << file << " is not a drawn PNG";
            EXPECT_NE(report.find("<img src=\"" + file + "\""), std::string::npos) << file << " is not shown in the report";
        }
    }
    EXPECT_EQ(seen, expected);
    for (const char* cat : {"analytic", "published", "solver against solver", "3-D against 1-D"})
        EXPECT_TRUE(categories.count(cat)) << "no " << cat << " case";

    // Self-shading: eps against a R at three sun zeniths, each within Gordon and Ding's accuracy.
    std::set<std::string> zeniths;
    for (const auto& c : j["cases"])
        if (c["name"] == "self-shading")
            for (const auto& k : c["checks"]) {
                const std::string label = k["label"].get<std::string>();
                if (label.find("3 standard errors") == std::string::npos) zeniths.insert(label.substr(0, label.find(", a R")));
            }
    EXPECT_EQ(zeniths, (std::set<std::string>{"eps(Lu), sun 20 deg", "eps(Lu), sun 40 deg", "eps(Lu), sun 60 deg"}));
}

// An unknown case is one error naming the known ones, before anything runs; nothing is left.
TEST(Validate, UnknownCaseIsRefusedAndLeavesNothing) {
    const fs::path out = scratchDir("validate", "unknown") / "out";
    const CommandResult r = runLittoral("validate --out " + out.string() + " --case direct-sun --case nope");
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("unknown validation case 'nope'"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("self-shading"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
}

// One named case runs alone, with the full setting's samples (here the cheapest: direct sun). A
// second validation into the same folder replaces the first: the folder never holds two runs' cases.
TEST(Validate, OneCaseRunsAloneAndALaterRunReplacesIt) {
    const fs::path out = scratchDir("validate", "one");
    const CommandResult r = runLittoral("--quiet validate --out " + out.string() + " --case direct-sun");
    EXPECT_EQ(r.status, 0) << r.output;
    auto j = nlohmann::json::parse(littoral::readTextFile(out / "summary.json"));
    ASSERT_EQ(j["cases"].size(), 1u);
    EXPECT_EQ(j["cases"][0]["name"], "direct-sun");
    EXPECT_FALSE(j["quick"].get<bool>());
    EXPECT_TRUE(fs::is_directory(out / "runs" / "direct-sun"));

    const CommandResult again = runLittoral("--quiet validate --out " + out.string() + " --case mobley-column");
    EXPECT_EQ(again.status, 0) << again.output;
    j = nlohmann::json::parse(littoral::readTextFile(out / "summary.json"));
    ASSERT_EQ(j["cases"].size(), 1u);
    EXPECT_EQ(j["cases"][0]["name"], "mobley-column");
    EXPECT_FALSE(fs::exists(out / "cases" / "direct-sun"));
    EXPECT_FALSE(fs::exists(out / "runs" / "direct-sun"));
    EXPECT_TRUE(fs::is_directory(out / "cases" / "mobley-column"));
}
