// The progressive-render checkpoint reader (render/progressive_checkpoint.h) on hand-edited
// checkpoints: every field that is not what this run would have saved is a located InputError, never
// undefined behaviour or silently wrong sums (the inputs fuzz_checkpoint found or was seeded with).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "render/progressive_checkpoint.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using littoral::render::CheckpointShape;
using littoral::render::ProgressiveState;
using littoral::testing_support::inputErrorOf;
using littoral::testing_support::scratchDir;
using littoral::testing_support::writeTextFile;

namespace {

constexpr size_t kHash = 1234;

// A 3-pass run of one 2 x 2 px sensor on one band, one probe value.
CheckpointShape shape() {
    CheckpointShape s;
    s.passes = 3;
    s.bands = 1;
    s.imageSizes = {4};
    s.probeValues = 1;
    return s;
}

// The checkpoint saveCheckpoint writes after pass 1, with `field`'s value in state.json replaced
// by `value` (nothing replaced when `field` is empty).
fs::path checkpoint(const std::string& name, const std::string& field = "", const std::string& value = "",
                    double pixel = 1.0) {
    const fs::path dir = scratchDir("progressive_checkpoint", name) / "progressive.checkpoint";
    ProgressiveState st;
    st.irHash = kHash;
    st.passesDone = 1;
    st.imageSums = {{pixel, 2, 3, 4}};
    st.probeSums = {{5}};
    st.probeSquares = {{25}};
    littoral::render::saveCheckpoint(dir, st, shape());
    littoral::clearNotedInputs();
    if (!field.empty()) {
        nlohmann::json j = nlohmann::json::parse(littoral::readTextFile(dir / "state.json"));
        littoral::clearNotedInputs();
        EXPECT_TRUE(j.contains(field)) << field;
        j[field] = nlohmann::json::parse(value);
        writeTextFile(dir, "state.json", j.dump(1));
    }
    return dir;
}

std::string errorOf(const fs::path& dir) {
    return inputErrorOf([&] { (void)littoral::render::loadCheckpoint(dir, kHash, shape()); });
}

}  // namespace

TEST(ProgressiveCheckpoint, ASavedCheckpointReadsBack) {
    const ProgressiveState st = littoral::render::loadCheckpoint(checkpoint("roundtrip"), kHash, shape());
    EXPECT_EQ(st.passesDone, 1);
    ASSERT_EQ(st.imageSums.size(), 1u);
    EXPECT_EQ(st.imageSums[0], (std::vector<double>{1, 2, 3, 4}));
    EXPECT_EQ(st.probeSums, (std::vector<std::vector<double>>{{5}}));
}

// passes_done 1e300 and image_sizes [2.4e30] went through nlohmann's get<int> and get<size_t>:
// undefined behaviour (UBSan: "outside the range of representable values"), found by fuzz_checkpoint.
TEST(ProgressiveCheckpoint, CountsMustBeWholeNumbersInRange) {
    std::string e = errorOf(checkpoint("passes_1e300", "passes_done", "1e300"));
    EXPECT_NE(e.find("state.json: --resume: unreadable checkpoint: passes_done is 1e+300, not a whole number"),
              std::string::npos)
        << e;
    e = errorOf(checkpoint("passes_fraction", "passes_done", "1.5"));
    EXPECT_NE(e.find("passes_done is 1.5, not a whole number"), std::string::npos) << e;
    e = errorOf(checkpoint("passes_huge", "passes_done", "18446744073709551615"));
    EXPECT_NE(e.find("passes_done is 18446744073709551615, out of range"), std::string::npos) << e;
    e = errorOf(checkpoint("passes_int_overflow", "passes_done", "4294967297"));
    EXPECT_NE(e.find("passes_done is 4294967297; a checkpoint of this 3-pass run holds 1 to 2 passes"), std::string::npos)
        << e;
    e = errorOf(checkpoint("passes_negative", "passes_done", "-2000000000"));
    EXPECT_NE(e.find("passes_done is -2000000000; a checkpoint of this 3-pass run holds 1 to 2 passes"), std::string::npos)
        << e;
    e = errorOf(checkpoint("sizes_huge", "image_sizes", "[2.4e30]"));
    EXPECT_NE(e.find("image_sizes[0] is 2.4e+30, not a whole number"), std::string::npos) << e;
    e = errorOf(checkpoint("sizes_negative", "image_sizes", "[-4]"));
    EXPECT_NE(e.find("image 0 holds -4 values, the sensor renders 4"), std::string::npos) << e;
    e = errorOf(checkpoint("sizes_not_a_list", "image_sizes", "4"));
    EXPECT_NE(e.find("image_sizes is not a list"), std::string::npos) << e;
}

TEST(ProgressiveCheckpoint, ImageSumsMustBeFinite) {
    for (const double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
        const std::string e = errorOf(checkpoint("nonfinite", "", "", bad));
        EXPECT_NE(e.find("unreadable checkpoint: image0-1.f64 holds "), std::string::npos) << e;
        EXPECT_NE(e.find(" at value 0; a render's sums are finite"), std::string::npos) << e;
    }
}

// A run killed while it saves pass 2's checkpoint has renamed some of the new files but not the new
// state.json (renamed last). The sums carry their pass in their names, so the old state still reads
// the old sums, never pass 2's; once pass 2's state is in place, pass 1's sums are removed.
TEST(ProgressiveCheckpoint, AKillWhileSavingLeavesTheLastCompleteState) {
    const fs::path dir = checkpoint("kill_while_saving");
    const std::string pass1State = littoral::readTextFile(dir / "state.json");
    const std::string pass1Sums = littoral::readTextFile(dir / "image0-1.f64");
    littoral::clearNotedInputs();
    ProgressiveState st;
    st.irHash = kHash;
    st.passesDone = 2;
    st.imageSums = {{10, 20, 30, 40}};
    st.probeSums = {{11}};
    st.probeSquares = {{61}};
    littoral::render::saveCheckpoint(dir, st, shape());
    EXPECT_FALSE(fs::exists(dir / "image0-1.f64"));
    EXPECT_EQ(littoral::render::loadCheckpoint(dir, kHash, shape()).imageSums[0], (std::vector<double>{10, 20, 30, 40}));
    littoral::clearNotedInputs();
    // What the kill leaves: pass 2's sums renamed, pass 1's state and sums still there.
    writeTextFile(dir, "state.json", pass1State);
    writeTextFile(dir, "image0-1.f64", pass1Sums);
    const ProgressiveState back = littoral::render::loadCheckpoint(dir, kHash, shape());
    EXPECT_EQ(back.passesDone, 1);
    EXPECT_EQ(back.imageSums[0], (std::vector<double>{1, 2, 3, 4}));
    EXPECT_EQ(back.probeSums, (std::vector<std::vector<double>>{{5}}));
}
