#include "pipelines/lib_geo_layers.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "bathymetry/geo_frame.h"
#include "core/atomic_file.h"
#include "core/units.h"
#include "render/camera.h"
#include "render/image_output.h"

namespace littoral::pipelines {
namespace {

double compassDeg(double dx, double dy, double northAzimuthDeg) {
    const double grid = std::atan2(dx, dy) * 180.0 / kPi;  // clockwise from the local +y (grid north)
    return std::fmod(grid - northAzimuthDeg + 720.0, 360.0);
}

}  // namespace

bathymetry::GeoFrame geoFrameOf(const ir::GeoReference& g) {
    return g.frame == "utm" ? bathymetry::GeoFrame::utm(g.latitudeDeg, g.longitudeDeg, g.altitudeM, g.utmZone)
                            : bathymetry::GeoFrame::localCartesian(g.latitudeDeg, g.longitudeDeg, g.altitudeM);
}

std::vector<std::string> geoLayerNames() {
    return {"latitude_deg", "longitude_deg", "view_zenith_deg", "view_azimuth_deg", "sun_zenith_deg", "sun_azimuth_deg"};
}

std::vector<std::filesystem::path> writeGeoLayers(const ir::SceneIR& ir, const render::RenderJobResult& res,
                                                  const std::filesystem::path& outDir) {
    std::vector<std::filesystem::path> written;
    for (const render::SensorImage& img : res.images) {
        const std::filesystem::path path = outDir / (img.sensor + "_geo.img"), tif = outDir / (img.sensor + ".tif");
        const ir::Sensor* sensor = ir.findSensor(img.sensor);
        const std::optional<ImageGeoreference> georef = imageGeoreference(ir, *sensor);
        if (georef) {
            writeGeoTiff(tif, img.film, *georef,
                         fmt::format("Littoral render of scene {} sensor {}: band-averaged spectral radiance, W m^-2 sr^-1 "
                                     "um^-1; CRS {}",
                                     ir.name, img.sensor, georef->crsName));
            written.push_back(tif);
        } else {
            removeStaleOutput(tif, "a GeoTIFF");
        }
        if (!ir.geo) {  // this scene has no scene.origin
            for (const std::filesystem::path& p : {path, render::enviHeaderPath(path)})
                removeStaleOutput(p, "georeferencing layers");
            continue;
        }
        const ir::GeoReference& g = *ir.geo;
        const bathymetry::GeoFrame frame = geoFrameOf(g);
        const render::Camera cam(*sensor);
        const int w = img.truth.width, h = img.truth.height;
        const size_t n = static_cast<size_t>(w) * static_cast<size_t>(h);
        std::vector<std::vector<double>> layers(6, std::vector<double>(n, std::numeric_limits<double>::quiet_NaN()));
        const Vec3 sun = ir.sun.direction();
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const size_t i = img.truth.index(x, y);
                const double range = img.truth.range[i];
                if (!std::isfinite(range)) continue;
                const Ray ray = cam.generateRay(x + 0.5, y + 0.5);
                const Point3 p = ray.at(range);
                const bathymetry::Geodetic geo = frame.toGeodetic(p);
                const double north = frame.northAzimuthDeg(geo.latDeg, geo.lonDeg);
                const Vec3 v = -ray.d;  // toward the sensor
                layers[0][i] = geo.latDeg;
                layers[1][i] = geo.lonDeg;
                layers[2][i] = std::acos(std::clamp(v.z, -1.0, 1.0)) * 180.0 / kPi;
                layers[3][i] = compassDeg(v.x, v.y, north);
                layers[4][i] = ir.sun.zenith * 180.0 / kPi;
                layers[5][i] = compassDeg(sun.x, sun.y, north);
            }
        render::writeEnviLayers(path, w, h, geoLayerNames(), layers,
                                fmt::format("Littoral georeferencing of scene {} sensor {} ({}): degrees; latitude and "
                                            "longitude WGS84 of the first surface each pixel's centre ray meets; "
                                            "azimuths clockwise from true north; NaN where the ray meets nothing",
                                            ir.name, img.sensor, frame.describe()),
                                // the radiance's georeferencing lines, so that GDAL places the layers too
                                georef ? enviGeoHeaderLines(*georef) : std::string());
        written.push_back(path);
        written.push_back(render::enviHeaderPath(path));
    }
    return written;
}

}  // namespace littoral::pipelines
