// The demonstration scenes of the README (data_synthetic/demos/) stay valid scene files: each
// passes `littoral check-scene`, which builds its geometry.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral::testing_support;

TEST(DemoScenes, AllPassCheckScene) {
    const fs::path dir = fs::path(LITTORAL_SOURCE_DIR) / "data_synthetic" / "demos";
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
        if (e.path().extension() != ".yaml") continue;
        const CommandResult r = runLittoral("--quiet check-scene " + e.path().string());
        EXPECT_EQ(r.status, 0) << e.path() << ":\n" << r.output;
        ++n;
    }
    EXPECT_EQ(n, 6);  // glint x3, pool caustics, floating cube, box shadows
}
