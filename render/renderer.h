#pragma once
// Rendering a sensor: the tile-parallel driver around the render's Estimator.
//
// Pixel sample s of pixel (i, j) draws all its random numbers from
// RandomStream(seed, pass = s, index = j * W + i), and each image tile is written by exactly
// one task, so an image is bit-for-bit identical for any thread count or schedule.
//
// Checks made before any radiance is computed (all InputError, nothing is written):
//  * zero or negative image size, bad optics (Camera);
//  * (pinhole sensors) the camera sits inside an opaque object: a probe ray along any of the six
//    axis directions first meets the back (inside) of an opaque face of a closed mesh whose
//    inside medium is air (a water volume with black floor faces is not an opaque object);
//  * an empty view: none of the pixel-centre rays meets any geometry (the image would show only
//    sky or black; an aim error, e.g. a flipped forward vector, or a scene with nothing in view);
//  * spectra outside a band's range, unknown names (Scene construction).
#include <optional>
#include <string>
#include <vector>

#include "core/scene_ir.h"
#include "render/camera.h"
#include "render/film.h"
#include "render/scene.h"

namespace littoral::render {

class TileCheckpoint;  // render/tile_checkpoint.h

struct RenderOptions {
    int threads = 0;       // 0 = all cores
    int tileSize = 16;     // pixels per tile side
    bool progress = true;  // show a progress bar over tiles
    // A one-pass render job's checkpoint: renderSensor restores the tiles it holds for sensor
    // `checkpointSensor` and saves its tiles as they finish.
    TileCheckpoint* checkpoint = nullptr;
    size_t checkpointSensor = 0;
};

// A sensor's water-leaving products (ir::Sensor::waterProducts): the parts of its radiance
// (RadianceParts, render/estimator.h), each a film in the radiance's units, whose sum is `film`;
// and Ed(0+) (W m^-2 um^-1), the mean over the pixel's samples that met the sea, NaN if none did.
struct WaterProductFilms {
    Film waterLeaving, skyReflected, glint, other, ed0;
};

struct SensorImage {
    std::string sensor;
    Film film;            // band-averaged radiance, W m^-2 sr^-1 um^-1
    TruthImages truth;    // first-hit material, range, depth below z = 0 of the pixel-centre ray
    std::optional<WaterProductFilms> products;
    // The standard error of each pixel's radiance (the spread of its samples over sqrt(n)), with two
    // samples per pixel or more. Progressive passes average it; the render job divides by sqrt(passes).
    std::optional<Film> standardError;
    // The radiance film, the product films and the standard-error film, in that order (for sums over
    // passes and bands).
    std::vector<Film*> films();
    std::vector<const Film*> films() const;
};
// How many films SensorImage::films() holds for a render of `s` (the radiance, five water products,
// the standard error with two samples per pixel or more), for sizing checkpoints before rendering.
size_t filmCount(const ir::Sensor& s);

class EstimatorSet;
// Renders one sensor of the scene with the render's estimators (one per band group).
SensorImage renderSensor(const Scene& scene, const EstimatorSet& estimators, const ir::Sensor& sensor,
                         const RenderOptions& opts = {});
// Convenience: builds the estimators of `scene` for this one sensor.
SensorImage renderSensor(const Scene& scene, const ir::Sensor& sensor, const RenderOptions& opts = {});

// Geometric truth only (pixel-centre rays; refracted rays followed, with the first band's
// refractive indices, TIR reflected, to the first opaque surface for hitDepth). Also performs the
// camera checks above.
TruthImages renderTruth(const Scene& scene, const ir::Sensor& sensor, const RenderOptions& opts = {});

// Throws InputError if a sensor's or probe's position is not finite or has a coordinate beyond
// kMaxPositionM: Embree traces in single precision and refuses (asserts on) ray origins beyond
// about 1.8e18, and far short of that a ray origin keeps no useful precision.
inline constexpr double kMaxPositionM = 1e9;  // m: far beyond a geostationary orbit (3.6e7 m)
void checkPositionInRange(const Point3& p, const std::string& who);
// Throws InputError if the point lies inside a closed mesh with an opaque material.
void checkNotInsideOpaque(const Scene& scene, const Point3& p, const std::string& who);
// Throws InputError if an opaque surface lies closer than kSurfaceClearance to the point along one
// of the six axis directions (a probe on the seabed would read 0 from below).
inline constexpr double kSurfaceClearance = 1e-4;  // m
void checkClearOfSurfaces(const Scene& scene, const Point3& p, const std::string& who);
// Throws InputError unless a sensor with water_products sits in the air (medium 0) of a scene
// with water.
void checkWaterProducts(const Scene& scene, const ir::Sensor& sensor, int medium);
// Throws InputError if `declared` (a medium index) disagrees with the media the interfaces around
// the point put it in; nothing when they are ambiguous or absent.
void checkDeclaredMedium(const Scene& scene, const Point3& p, int declared, const std::string& who);

}  // namespace littoral::render
