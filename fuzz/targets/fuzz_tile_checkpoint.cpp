// The one-pass render checkpoint reader (`run`/`render --resume` after a path-traced or one-pass
// dirsig render was killed): the folder render.checkpoint/ (state.json and sensor<k>-<generation>.f32),
// packed as in fuzz_folder.h, read by render::TileCheckpoint::load with the checks a resuming run
// makes (format, IR hash, sensor selection, generation, per sensor the film values and the tile
// flags, the size of every values file), against one fixed shape: two sensors of 24 and 4 film
// values in 6 and 2 tiles, IR hash kIrHash, every sensor selected. The seeds (fuzz/corpus/
// tile_checkpoint, made by fuzz/make_tile_checkpoint_seeds.py) are checkpoints of that shape.
//
// What a resuming run relies on after load() returns: one value per film value and a readable flag
// per tile of each sensor, restored into films of the right size. As in every target, only
// InputError is an expected outcome (fuzz_common.h). With LITTORAL_FUZZ_VERBOSE set, each input's
// outcome is printed.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "fuzz_common.h"
#include "fuzz_folder.h"
#include "render/film.h"
#include "render/tile_checkpoint.h"

namespace {

constexpr size_t kIrHash = 1234567890123456789u;
const std::vector<size_t> kFilmValues{24, 4}, kSlots{6, 2};

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    littoral::fuzz::init();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::filesystem::path dir = littoral::fuzz::scratchFolder("tile_checkpoint") / "render.checkpoint";
    std::filesystem::create_directories(dir);
    littoral::fuzz::unpackFolder(std::string_view(reinterpret_cast<const char*>(data), size), dir, "state.json");
    static const bool verbose = std::getenv("LITTORAL_FUZZ_VERBOSE") != nullptr;
    try {
        littoral::render::TileCheckpoint ck(dir, kIrHash, "", kFilmValues, kSlots);
        ck.load();
        int done = 0;
        for (size_t k = 0; k < kFilmValues.size(); ++k) {
            if (ck.values(k).size() != kFilmValues[k]) __builtin_trap();
            for (size_t s = 0; s < kSlots[k]; ++s) done += ck.done(k, s);
            // Two films per sensor, as a radiance film and its standard error would be.
            littoral::render::Film a, b;
            a.pixels.assign(kFilmValues[k] / 2, -1.0f);
            b.pixels.assign(kFilmValues[k] - kFilmValues[k] / 2, -1.0f);
            ck.restore(k, {&a, &b});
            if (std::memcmp(a.pixels.data(), ck.values(k).data(), a.pixels.size() * sizeof(float)) != 0 ||
                std::memcmp(b.pixels.data(), ck.values(k).data() + a.pixels.size(), b.pixels.size() * sizeof(float)) != 0)
                __builtin_trap();
        }
        if (verbose) std::fprintf(stderr, "read: %d tiles done\n", done);
    } catch (const littoral::InputError& e) {
        // Expected for most inputs.
        if (verbose) std::fprintf(stderr, "input error: %s\n", e.what());
    }
    littoral::clearNotedInputs();  // one process, many runs: this run's inputs are gone
    return 0;
}
