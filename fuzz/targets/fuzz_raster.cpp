// The elevation-raster readers: ESRI ASCII grids (own parser) and GDAL's (GeoTIFF, BAG, NetCDF,
// ... ; GDAL itself is not instrumented, but everything Littoral does with what it returns is).
#include <cpl_vsi.h>

#include "bathymetry/raster_source.h"
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
        // The bytes as an in-memory file (not copied, not freed by GDAL).
        const char* name = "/vsimem/fuzz_dem.tif";
        VSIFCloseL(VSIFileFromMemBuffer(name, reinterpret_cast<GByte*>(const_cast<char*>(bytes.data())),
                                        vsi_l_offset(bytes.size()), FALSE));
        try {
            (void)littoral::bathymetry::detail::readGdalRaster(name, "fuzz/dem.tif", {});
        } catch (...) {
            VSIUnlink(name);
            throw;
        }
        VSIUnlink(name);
    });
    return 0;
}
