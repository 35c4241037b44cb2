#include "render/camera.h"

#include <cmath>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "core/error.h"

namespace littoral::render {

ir::Sensor frameCamera(const std::string& name, const Point3& target, double viewZenith, double viewAzimuth,
                       double range, double gsd, int width, int height, double pitch) {
    if (!(range > 0) || !(gsd > 0) || !(pitch > 0))
        throw InputError(fmt::format("frame camera '{}': range ({} m), gsd ({} m) and pitch ({} m) must be positive",
                                     name, range, gsd, pitch));
    if (!(viewZenith >= 0 && viewZenith < 0.5 * 3.14159265358979323846))
        throw InputError(fmt::format("frame camera '{}': view zenith {} rad must lie in [0, pi/2)", name, viewZenith));
    if (width <= 0 || height <= 0)
        throw InputError(fmt::format("frame camera '{}': image size {} x {} px must be positive", name, width,
                                     height));
    const double sz = std::sin(viewZenith);
    const Vec3 toCamera{sz * std::cos(viewAzimuth), sz * std::sin(viewAzimuth), std::cos(viewZenith)};
    ir::Sensor s;
    s.name = name;
    s.type = ir::Sensor::Type::Pinhole;
    s.position = target + toCamera * range;
    s.forward = -toCamera;
    // Up = +z projected on the image plane; for a nadir view (+z along the axis) use north.
    s.up = viewZenith < 1e-9 ? Vec3{0, 1, 0} : Vec3{0, 0, 1};
    s.width = width;
    s.height = height;
    s.pixelPitch = pitch;
    s.focalLength = pitch * range / gsd;  // GSD = pitch * range / f on the axis
    return s;
}

Camera::Camera(const ir::Sensor& s)
    : name_(s.name), type_(s.type), position_(s.position), width_(s.width), height_(s.height),
      spp_(s.samplesPerPixel), focal_(s.focalLength), pitch_(s.pixelPitch), size_(s.pixelSize) {
    const std::string who = fmt::format("sensor '{}'", s.name);
    if (s.width <= 0 || s.height <= 0)
        throw InputError(fmt::format("{}: image size {} x {} px: width and height must be positive", who, s.width,
                                     s.height));
    if (s.samplesPerPixel < 1)
        throw InputError(fmt::format("{}: samplesPerPixel {} must be at least 1", who, s.samplesPerPixel));
    if (!isFinite(s.position)) throw InputError(fmt::format("{}: position is not finite", who));
    if (!(length(s.forward) > 0) || !isFinite(s.forward))
        throw InputError(fmt::format("{}: forward vector must be non-zero", who));
    forward_ = normalize(s.forward);
    const Vec3 r = cross(forward_, s.up);
    if (!(length(r) > 1e-9 * length(s.up)))
        throw InputError(fmt::format("{}: up vector {} is parallel to forward {}", who, fmt::streamed(s.up),
                                     fmt::streamed(s.forward)));
    right_ = normalize(r);
    upOrtho_ = cross(right_, forward_);
    if (type_ == ir::Sensor::Type::Pinhole) {
        if (!(focal_ > 0) || !(pitch_ > 0))
            throw InputError(fmt::format("{}: pinhole focalLength ({} m) and pixelPitch ({} m) must be positive", who,
                                         focal_, pitch_));
    } else if (!(size_ > 0)) {
        throw InputError(fmt::format("{}: orthographic pixelSize ({} m) must be positive", who, size_));
    }
}

Ray Camera::generateRay(double x, double y) const {
    const double dx = x - 0.5 * width_, dy = y - 0.5 * height_;
    Ray r;
    if (type_ == ir::Sensor::Type::Pinhole) {
        r.o = position_;
        r.d = normalize(forward_ * focal_ + right_ * (dx * pitch_) - upOrtho_ * (dy * pitch_));
    } else {
        r.o = position_ + right_ * (dx * size_) - upOrtho_ * (dy * size_);
        r.d = forward_;
    }
    return r;
}

}  // namespace littoral::render
