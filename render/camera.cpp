#include "render/camera.h"

#include <algorithm>
#include <cmath>
#include <iterator>

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

namespace {

// The factories: one per ir::Sensor::Type, each checking the parameters its descriptor
// (core/sensor_types.h) declares.
Projection makePinhole(const ir::Sensor& s, const std::string& who) {
    if (!(s.focalLength > 0) || !(s.pixelPitch > 0))
        throw InputError(fmt::format("{}: pinhole focalLength ({} m) and pixelPitch ({} m) must be positive", who,
                                     s.focalLength, s.pixelPitch));
    return PinholeProjection{s.focalLength, s.pixelPitch};
}

Projection makeOrthographic(const ir::Sensor& s, const std::string& who) {
    if (!(s.pixelSize > 0))
        throw InputError(fmt::format("{}: orthographic pixelSize ({} m) must be positive", who, s.pixelSize));
    return OrthographicProjection{s.pixelSize};
}

struct SensorFactory {
    ir::Sensor::Type type;
    Projection (*make)(const ir::Sensor&, const std::string& who);
};
constexpr SensorFactory kSensorFactories[] = {
    {ir::Sensor::Type::Pinhole, makePinhole},
    {ir::Sensor::Type::Orthographic, makeOrthographic},
};

// One factory per type, in the order of the type's name table (core/scene_ir.h), which the sensor
// descriptors follow too (checked when core/sensor_types.cpp builds them).
constexpr bool everyTypeHasAFactory() {
    const auto& types = EnumNames<ir::Sensor::Type>::table;
    if (std::size(kSensorFactories) != std::size(types)) return false;
    for (size_t i = 0; i < std::size(types); ++i)
        if (kSensorFactories[i].type != types[i].value) return false;
    return true;
}
static_assert(everyTypeHasAFactory(), "every ir::Sensor::Type needs exactly one entry in kSensorFactories");

template <class... F> struct Overloaded : F... {
    using F::operator()...;
};
// Needed by clang before 17, which does not deduce an aggregate's template arguments (P1816).
template <class... F> Overloaded(F...) -> Overloaded<F...>;

Projection makeProjection(const ir::Sensor& s, const std::string& who) {
    for (const SensorFactory& f : kSensorFactories)
        if (f.type == s.type) return f.make(s, who);
    throw InternalError(fmt::format("{}: sensor type {} has no factory", who, static_cast<int>(s.type)));
}

}  // namespace

namespace {
// The direction of v as a unit vector, scaled by its largest component first so that a vector like
// (0, 1e200, 0), whose length overflows, keeps its direction. InputError when v is not finite or
// is zero.
Vec3 unitDirection(const Vec3& v, const std::string& who, const char* what) {
    const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
    if (!isFinite(v) || !(m > 0))
        throw InputError(fmt::format("{}: {} vector {} must be finite and non-zero", who, what, fmt::streamed(v)));
    return normalize(Vec3{v.x / m, v.y / m, v.z / m});
}
}  // namespace

Camera::Camera(const ir::Sensor& s)
    : name_(s.name), position_(s.position), width_(s.width), height_(s.height), spp_(s.samplesPerPixel) {
    const std::string who = fmt::format("sensor '{}'", s.name);
    if (s.width <= 0 || s.height <= 0)
        throw InputError(fmt::format("{}: image size {} x {} px: width and height must be positive", who, s.width,
                                     s.height));
    if (s.samplesPerPixel < 1)
        throw InputError(fmt::format("{}: samplesPerPixel {} must be at least 1", who, s.samplesPerPixel));
    if (!isFinite(s.position)) throw InputError(fmt::format("{}: position is not finite", who));
    forward_ = unitDirection(s.forward, who, "forward");
    const Vec3 up = unitDirection(s.up, who, "up");
    const Vec3 r = cross(forward_, up);
    if (!(length(r) > 1e-9))
        throw InputError(fmt::format("{}: up vector {} is parallel to forward {}", who, fmt::streamed(s.up),
                                     fmt::streamed(s.forward)));
    right_ = normalize(r);
    upOrtho_ = cross(right_, forward_);
    projection_ = makeProjection(s, who);
}

Ray Camera::generateRay(double x, double y) const {
    const double dx = x - 0.5 * width_, dy = y - 0.5 * height_;
    // A visit, so that a projection without a case here does not compile.
    return std::visit(Overloaded{[&](const PinholeProjection& p) {
                                     return Ray{position_, normalize(forward_ * p.focal + right_ * (dx * p.pitch) -
                                                                     upOrtho_ * (dy * p.pitch))};
                                 },
                                 [&](const OrthographicProjection& o) {
                                     return Ray{position_ + right_ * (dx * o.size) - upOrtho_ * (dy * o.size), forward_};
                                 }},
                      projection_);
}

}  // namespace littoral::render
