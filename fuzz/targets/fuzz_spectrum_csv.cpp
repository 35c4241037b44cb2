// The spectrum CSV reader of scene files ({file: name.csv}).
#include "fuzz_common.h"
#include "scenegen/scene_file.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    littoral::fuzz::init();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    littoral::fuzz::run(data, size, [](std::string_view bytes) {
        const littoral::Spectrum s = littoral::scenegen::parseSpectrumCsv(bytes, "fuzz/spectrum.csv", 0.0, 1.0, "");
        if (s.maxWavelength() > s.minWavelength())
            (void)s.bandAverage(littoral::Band{s.minWavelength(), s.maxWavelength()});
    });
    return 0;
}
