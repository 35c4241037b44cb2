#pragma once
// Sensors: pinhole frame cameras and nadir/orthographic cameras, placed by the Scene IR.
//
// Image convention (shared with film.h): pixel (i, j), i = column from the left, j = row from the
// top. With right = normalize(cross(forward, up)) and upOrtho = cross(right, forward), a film
// position (x, y) in pixel units (x in [0, W], y in [0, H]; the pixel centre is (i + 0.5, j + 0.5))
// maps to
//   pinhole:       d = normalize(f forward + (x - W/2) pitch right - (y - H/2) pitch upOrtho)
//   orthographic:  o = position + (x - W/2) size right - (y - H/2) size upOrtho, d = forward.
// With one sample per pixel the ray goes through the pixel centre (as the thesis' comparators
// do); with more, samples are stratified and jittered over the pixel.
//
// Each sensor type (core/sensor_types.h: its parameters, as the scene file and the IR read them)
// makes its projection here, through a table of factories keyed by ir::Sensor::Type (camera.cpp);
// a static_assert there checks that every type has exactly one.
#include <variant>

#include "core/ray.h"
#include "core/scene_ir.h"

namespace littoral::render {

// A frame camera placed the dissertation's way (Table 10.1): looking at `target` from the
// direction given by the view zenith angle (0 = nadir view from straight above) and azimuth
// (radians, counter-clockwise from +x east, the direction from the target toward the camera),
// at slant `range` (m), with ground sample distance `gsd` (m per pixel, measured on a plane
// normal to the optical axis at the target) and pixel pitch `pitch` (m): the focal length is
// f = pitch * range / gsd. Image "up" is the projection of +z (north, +y, for a nadir view).
// InputError on non-positive range, gsd, pitch or image size, or a zenith outside [0, pi/2).
ir::Sensor frameCamera(const std::string& name, const Point3& target, double viewZenith, double viewAzimuth,
                       double range, double gsd, int width, int height, double pitch);

// The per-type part of a camera, chosen once per sensor and evaluated per sample (a variant, not
// virtual dispatch: generateRay is on the hot path). Lengths in metres.
struct PinholeProjection {
    double focal = 0, pitch = 0;
};
struct OrthographicProjection {
    double size = 0;
};
using Projection = std::variant<PinholeProjection, OrthographicProjection>;

class Camera {
public:
    // InputError on zero or negative image size, non-positive focal length, pitch or pixel size
    // (the type's factory), a zero forward vector or an up vector parallel to forward.
    explicit Camera(const ir::Sensor& sensor);

    Ray generateRay(double x, double y) const;
    int width() const { return width_; }
    int height() const { return height_; }
    int samplesPerPixel() const { return spp_; }
    const std::string& name() const { return name_; }
    const Vec3& forward() const { return forward_; }
    const Vec3& right() const { return right_; }
    const Vec3& upOrtho() const { return upOrtho_; }
    const Point3& position() const { return position_; }

private:
    std::string name_;
    Projection projection_;
    Point3 position_;
    Vec3 forward_, right_, upOrtho_;
    int width_, height_, spp_;
};

}  // namespace littoral::render
