// The image plugin (core/image_io.h): OpenImageIO is loaded on the first image a command reads or
// writes, not at start-up, and a plugin that cannot be loaded is one clear error with nothing left
// behind.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "tests/support/test_support.h"

using namespace littoral::testing_support;
namespace fs = std::filesystem;

namespace {
const std::string kMissingPlugin = "LITTORAL_IMAGEIO_PLUGIN=/nonexistent/liblittoral_imageio.so ";
}

// check-scene reads no image: with the plugin unloadable it still passes, so it never loaded it.
// `run` writes the sensor's EXR: it names the plugin it could not load, exits 2 (an installation
// fault, not the user's input) and leaves none of the render's outputs.
TEST(ImagePlugin, LoadedOnFirstUseAndAMissingOneIsOneErrorWithNothingLeft) {
    const fs::path dir = scratchDir("pipelines", "image_plugin");
    const fs::path scene = writeTextFile(dir, "small.yaml", kSmallScene);
    const CommandResult check = runShellCommand(kMissingPlugin + littoralBinary().string() + " -q check-scene " +
                                                scene.string());
    EXPECT_EQ(check.status, 0) << check.output;

    const fs::path out = dir / "out";
    const CommandResult run = runShellCommand(kMissingPlugin + littoralBinary().string() + " -q run " +
                                              scene.string() + " --out " + out.string());
    EXPECT_EQ(run.status, 2) << run.output;
    EXPECT_NE(run.output.find("cannot load the image plugin /nonexistent/liblittoral_imageio.so"), std::string::npos)
        << run.output;
    // `run` publishes the IR before it renders (docs/outputs.md): that, and nothing of the render.
    std::vector<std::string> left;
    if (fs::exists(out))
        for (const auto& e : fs::directory_iterator(out)) left.push_back(e.path().filename().string());
    EXPECT_EQ(left, std::vector<std::string>{"ir"});

    // The same run with the build's plugin writes the image.
    const CommandResult ok = runLittoral("-q run " + scene.string() + " --out " + out.string());
    ASSERT_EQ(ok.status, 0) << ok.output;
    EXPECT_TRUE(fs::exists(out / "nadir.exr"));
}
