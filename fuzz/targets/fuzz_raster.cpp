// The elevation-raster readers: ESRI ASCII grids and the GeoTIFF tag walker (pixel decoding of
// TIFFs is OpenImageIO's and is guarded by the memory budget, see docs/reliability.md).
#include "bathymetry/geotiff_tags.h"
#include "bathymetry/terrain.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    littoral::fuzz::init();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    littoral::fuzz::run(data, size, [](std::string_view bytes) {
        const auto t = littoral::bathymetry::parseAsciiGridTerrain(bytes, "fuzz/grid.asc");
        const auto e = t->extent();
        (void)t->elevation(0.5 * (e.x0 + e.x1), 0.5 * (e.y0 + e.y1));
    });
    littoral::fuzz::run(data, size, [](std::string_view bytes) {
        (void)littoral::bathymetry::parseGeoTiffInfo(bytes, "fuzz/dem.tif");
    });
    return 0;
}
