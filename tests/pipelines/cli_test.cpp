// End-to-end tests of the `littoral` command: exit codes and messages as a user sees them.
#include <gtest/gtest.h>

#include "tests/support/test_support.h"

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

namespace {

const fs::path kBinary = fs::path(LITTORAL_BINARY_DIR) / "bin" / "littoral";

using Result = littoral::testing_support::CommandResult;
Result run(const std::string& args) { return littoral::testing_support::runLittoral(args); }

fs::path tempDir() {
    const fs::path d = fs::temp_directory_path() / "littoral_cli_test";
    fs::create_directories(d);
    return d;
}

}  // namespace

class Cli : public testing::Test {
protected:
    void SetUp() override {
        if (!fs::exists(kBinary)) GTEST_SKIP() << "littoral binary not built: " << kBinary;
    }
};

TEST_F(Cli, VersionAndHelp) {
    const auto v = run("--version");
    EXPECT_EQ(v.status, 0);
    EXPECT_NE(v.output.find("littoral "), std::string::npos);
    const auto h = run("check-scene --help");
    EXPECT_EQ(h.status, 0);
    EXPECT_NE(h.output.find("SCENE"), std::string::npos);
}

TEST_F(Cli, CheckSceneExitCodes) {
    const fs::path good = tempDir() / "good.yaml";
    std::ofstream(good) << "scene: {name: cli}\nsky: {radiance: 1}\n";
    const auto ok = run("check-scene " + good.string());
    EXPECT_EQ(ok.status, 0) << ok.output;
    EXPECT_NE(ok.output.find("valid"), std::string::npos);

    const fs::path bad = tempDir() / "bad.yaml";
    std::ofstream(bad) << "scene: {name: cli}\nsky: {radiance: 1, modle: uniform}\n";
    const auto r = run("check-scene " + bad.string());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("bad.yaml:2:20: error: sky.modle: unknown key 'modle'"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("did you mean 'model'?"), std::string::npos) << r.output;

    const auto missing = run("check-scene " + (tempDir() / "nope.yaml").string());
    EXPECT_EQ(missing.status, 1);
    EXPECT_NE(missing.output.find("nope.yaml: error: cannot open the scene file"), std::string::npos) << missing.output;
}

TEST_F(Cli, UnknownSubcommandIsAUsageError) {
    const auto r = run("frobnicate");
    EXPECT_EQ(r.status, 1);
}
