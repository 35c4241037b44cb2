// The progressive-render checkpoint reader (`render --resume`): the folder progressive.checkpoint/
// (state.json and image<i>-<passes>.f64), packed as in fuzz_folder.h, read by render::loadCheckpoint with
// the checks a resuming run makes (format, IR hash, sensor selection, passes, the sizes of every
// sum), against one fixed small run in both of its sensor selections.
//
// The fixed run is fuzz/seeds/checkpoint_run.yaml, whose interrupted renders made the seeds
// (fuzz/make_seeds.sh): 3 progressive passes on 2 bands, a 4 x 3 px sensor `nadir`, a 2 x 2 px
// sensor `side` and a probe with Ed and Eu. kIrHash is the hash of its IR (std::hash of
// ir::toJsonText, as render_job.cpp computes it), the seeds' ir_hash; make_seeds.sh prints it.
//
// As in every target, only InputError is an expected outcome (fuzz_common.h). With
// LITTORAL_FUZZ_VERBOSE set, each input's outcome is printed.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/atomic_file.h"
#include "fuzz_common.h"
#include "fuzz_folder.h"
#include "render/progressive_checkpoint.h"

namespace {

constexpr size_t kIrHash = 5175176643253610547u;

littoral::render::CheckpointShape everySensor() {
    littoral::render::CheckpointShape s;
    s.passes = 3;
    s.bands = 2;
    s.imageSizes = {4 * 3 * 2, 2 * 2 * 2};
    s.probeValues = 2;
    return s;
}

littoral::render::CheckpointShape onlySide() {
    littoral::render::CheckpointShape s;
    s.sensor = "side";
    s.passes = 3;
    s.bands = 2;
    s.imageSizes = {2 * 2 * 2};
    return s;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    littoral::fuzz::init();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::filesystem::path dir = littoral::fuzz::scratchFolder("checkpoint") / "progressive.checkpoint";
    std::filesystem::create_directories(dir);
    littoral::fuzz::unpackFolder(std::string_view(reinterpret_cast<const char*>(data), size), dir, "state.json");
    static const bool verbose = std::getenv("LITTORAL_FUZZ_VERBOSE") != nullptr;
    for (const auto& shape : {everySensor(), onlySide()}) {
        try {
            const littoral::render::ProgressiveState st = littoral::render::loadCheckpoint(dir, kIrHash, shape);
            // What a resuming run relies on: the passes left and one sum per pixel value and band.
            if (st.passesDone < 1 || st.passesDone >= shape.passes || st.imageSums.size() != shape.imageSizes.size() ||
                st.probeSums.size() != shape.probeValues)
                __builtin_trap();
            for (size_t i = 0; i < st.imageSums.size(); ++i)
                if (st.imageSums[i].size() != shape.imageSizes[i]) __builtin_trap();
            if (verbose) std::fprintf(stderr, "read: %d passes done\n", st.passesDone);
        } catch (const littoral::InputError& e) {
            // Expected for most inputs.
            if (verbose) std::fprintf(stderr, "input error: %s\n", e.what());
        }
    }
    littoral::clearNotedInputs();  // one process, many runs: this run's inputs are gone
    return 0;
}
