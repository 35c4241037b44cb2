#pragma once
// The sensor types (family "sensor type"): pinhole and orthographic cameras, one descriptor each,
// read by the scene-file parser (scenegen/scene_file.cpp), the Scene IR writer and reader
// (core/scene_ir.cpp) and their messages. The camera each type makes is render/'s
// (render/camera.cpp): a table of factories keyed by ir::Sensor::Type, whose completeness is a
// compile-time check there; this registry's completeness (exactly the names of ir::Sensor::Type,
// in its order) is checked when it is first built. The schema lives in core/ because the IR
// reader, which needs no registration, and the parser, which may not use render/, both read it.
//
// Units. A camera's optics are written in a scene file in the units of a data sheet (focal length
// in mm, pixel pitch in um) and held in metres in the IR and everywhere inside. Each ParamSpec is
// the scene file's view of a parameter: `sceneKey`, `unit` and the range are what a user writes and
// reads in messages and in docs/scene-format.md; `name` is the IR key, whose value is the scene
// value times `SensorField::irScale` (1e-3 for mm, 1e-6 for um, 1 for m). The scale sits in this
// family's own binding rather than in ParamSpec, because no other family converts units and the
// generic readers (resolveParams, the render settings) would otherwise have to honour it.
//
// The "frame" sensor of scene files is not a type here: it is a placement (dissertation Table 10.1:
// elevation, azimuth, range, GSD) that scenegen turns into a pinhole sensor with a 10 um pitch.
//
// The IR reader does not apply the scene-file ranges: a frame sensor's focal length
// (pitch x range / GSD) may lie outside them. The camera factory refuses non-positive values.
#include <vector>

#include "core/kinds.h"
#include "core/scene_ir.h"

namespace littoral {

// Where the IR value of one parameter lives and how it follows from the scene file's.
struct SensorField {
    double irScale = 1.0;                 // IR value (m) = scene-file value x irScale
    double ir::Sensor::*field = nullptr;  // the ir::Sensor member holding the IR value
};

struct SensorKind {
    KindInfo info;  // family "sensor type"; params: name = IR key, sceneKey/unit/range = the scene file's
    ir::Sensor::Type type;
    std::vector<SensorField> fields;  // one per info.params, in the same order
};
inline const KindInfo& kindInfo(const SensorKind& k) { return k.info; }

const KindRegistry<SensorKind>& sensorTypeKinds();
const SensorKind& sensorKind(ir::Sensor::Type type);

}  // namespace littoral
