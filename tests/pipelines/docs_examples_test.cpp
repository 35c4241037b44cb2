// The documentation's scene-file examples are checked by the scene reader, so docs and code agree:
// every ```yaml block of docs/scene-format.md that is a whole scene (it has a top-level `scene:`)
// must pass `littoral check-scene`, and every block that is a `water:` section must pass inside a
// minimal scene.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral::testing_support;

TEST(DocsExamples, SceneFormatExamplesAreValid) {
    const fs::path md = fs::path(LITTORAL_SOURCE_DIR) / "docs" / "scene-format.md";
    const auto blocks = markdownBlocks(md, "yaml");
    ASSERT_FALSE(blocks.empty());
    int scenes = 0, waters = 0, probeArrays = 0;
    const fs::path dir = scratchDir("docs_examples", "scene_format");
    for (size_t i = 0; i < blocks.size(); ++i) {
        std::string text;
        if (blocks[i].find("\nscene:") != std::string::npos || blocks[i].rfind("scene:", 0) == 0 ||
            blocks[i].find("\nscene:\n") != std::string::npos) {
            text = blocks[i];
            ++scenes;
        } else if (blocks[i].rfind("water:", 0) == 0) {
            // check-scene assembles the whole scene, so the fragment gets a small domain, a seabed
            // below its deepest layer (10 m in the docs) and the seabed's material.
            text = "scene: {name: doc-example, domain: {x: [-5, 5], y: [-5, 5]}}\nsky: {radiance: 1}\n"
                   "bathymetry: {type: planar_slope, z0_m: -12, spacing_m: 1, material: bottom}\n"
                   "materials:\n  - {name: bottom, type: lambertian, reflectance: 0.2}\n" +
                   blocks[i];
            ++waters;
        } else if (blocks[i].rfind("probes:", 0) == 0) {
            // The probe-array example: under flat water over the same seabed.
            text = "scene: {name: doc-example, domain: {x: [-5, 5], y: [-5, 5]}}\nsky: {radiance: 1}\n"
                   "water: {surface: {model: flat, size: [10, 10]}, optics: {preset: coastal}}\n"
                   "bathymetry: {type: planar_slope, z0_m: -12, spacing_m: 1, material: bottom}\n"
                   "materials:\n  - {name: bottom, type: lambertian, reflectance: 0.2}\n" +
                   blocks[i];
            ++probeArrays;
        } else {
            continue;
        }
        const fs::path f = writeTextFile(dir, "example" + std::to_string(i) + ".yaml", text);
        const CommandResult r = runLittoral("--quiet check-scene " + f.string());
        EXPECT_EQ(r.status, 0) << "docs/scene-format.md yaml block " << i << ":\n" << text << "\n" << r.output;
    }
    EXPECT_GE(scenes, 1);  // the complete annotated example
    EXPECT_GE(waters, 1);  // the layered water example
    EXPECT_GE(probeArrays, 1);  // the probe-array example
}
