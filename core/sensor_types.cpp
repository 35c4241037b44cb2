#include "core/sensor_types.h"

#include <fmt/format.h>

#include "core/error.h"
#include "core/suggest.h"

namespace littoral {

namespace {

// Pinhole: rays from one point through the pixel centres of an image plane at the focal length
// (render/camera.h gives the mapping). The field of view follows from the two: 2 atan(W pitch / 2f).
SensorKind pinholeKind() {
    SensorKind k;
    k.type = ir::Sensor::Type::Pinhole;
    k.info.family = "sensor type";
    k.info.name = "pinhole";
    k.info.doc = "a frame camera: rays from one point (position) through the pixels of an image plane at the focal "
                 "length";
    k.info.params = {
        {"focal_length_m", "focal_length_mm", ParamType::Real, std::nullopt, 1e-3, 1e5, "mm",
         "distance from the pinhole to the image plane"},
        {"pixel_pitch_m", "pixel_pitch_um", ParamType::Real, std::nullopt, 1e-2, 1e5, "um",
         "centre-to-centre spacing of the pixels on the image plane"},
    };
    k.fields = {{1e-3, &ir::Sensor::focalLength}, {1e-6, &ir::Sensor::pixelPitch}};
    return k;
}

// Orthographic: parallel rays along the view direction from the pixels of an image plane through
// the position.
SensorKind orthographicKind() {
    SensorKind k;
    k.type = ir::Sensor::Type::Orthographic;
    k.info.family = "sensor type";
    k.info.name = "orthographic";
    k.info.doc = "parallel rays along the view direction, one from each pixel of an image plane centred on position";
    k.info.params = {
        {"pixel_size_m", "", ParamType::Real, std::nullopt, 1e-6, 1e4, "m", "side of a pixel on the image plane"},
    };
    k.fields = {{1.0, &ir::Sensor::pixelSize}};
    return k;
}

// Every ir::Sensor::Type has exactly one kind, in the enum table's order, each binding every
// parameter to a field.
void checkComplete(const KindRegistry<SensorKind>& r) {
    if (r.names() != allNames<ir::Sensor::Type>())
        throw InternalError(fmt::format("sensor types registered ({}) differ from ir::Sensor::Type ({})",
                                        joinList(r.names()), joinList(allNames<ir::Sensor::Type>())));
    for (const SensorKind& k : r.kinds()) {
        if (nameOf(k.type) != k.info.name || k.fields.size() != k.info.params.size())
            throw InternalError(fmt::format("sensor type '{}': its type or fields do not match its descriptor", k.info.name));
        for (const SensorField& f : k.fields)
            if (!f.field || !(f.irScale > 0)) throw InternalError(fmt::format("sensor type '{}': bad field", k.info.name));
    }
}

}  // namespace

const KindRegistry<SensorKind>& sensorTypeKinds() {
    static const KindRegistry<SensorKind> registry = [] {
        KindRegistry<SensorKind> r("sensor type");
        r.add(pinholeKind());
        r.add(orthographicKind());
        checkComplete(r);
        return r;
    }();
    return registry;
}

const SensorKind& sensorKind(ir::Sensor::Type type) {
    for (const SensorKind& k : sensorTypeKinds().kinds())
        if (k.type == type) return k;
    throw InternalError(fmt::format("sensor type {} has no descriptor", static_cast<int>(type)));
}

}  // namespace littoral
