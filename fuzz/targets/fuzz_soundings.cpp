// The soundings CSV reader (latitude, longitude, depth).
#include "bathymetry/terrain.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    littoral::fuzz::init();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    littoral::fuzz::run(data, size, [](std::string_view bytes) {
        (void)littoral::bathymetry::parseSoundingsCsv(bytes, "fuzz/soundings.csv");
    });
    return 0;
}
