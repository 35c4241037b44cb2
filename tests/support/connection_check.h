#pragma once
// The check that the path estimator's sun connections count every chain once: render a view with
// the in-water sun estimates and without any (render::setInWaterSunEstimates(false): every sampled
// ray then counts the solar disc when it reaches it) and compare the image means.
#include <cmath>
#include <filesystem>
#include <utility>

#include "core/scene_ir.h"
#include "render/renderer.h"
#include "render/scene.h"
#include "render/sun_connection.h"

namespace littoral::testing_support {

// Renders s's first sensor (the scene's files under `dir`) with spp samples per pixel, with or
// without the in-water sun estimates; returns the image's mean radiance and the standard error of
// that mean (the pixels' standard errors in quadrature over the pixel count).
inline std::pair<double, double> meanOfSensorRender(ir::SceneIR& s, const std::filesystem::path& dir, bool connection,
                                                    int spp) {
    s.sensors[0].samplesPerPixel = spp;
    render::setInWaterSunEstimates(connection);
    const render::Scene scene(s, dir);
    render::RenderOptions quiet;
    quiet.progress = false;
    const render::SensorImage img = render::renderSensor(scene, s.sensors[0], quiet);
    render::setInWaterSunEstimates(true);
    double m = 0, v = 0;
    for (size_t i = 0; i < img.film.pixels.size(); ++i) {
        m += img.film.pixels[i];
        v += img.standardError->pixels[i] * img.standardError->pixels[i];
    }
    const double n = static_cast<double>(img.film.pixels.size());
    return {m / n, std::sqrt(v) / n};
}

}  // namespace littoral::testing_support
