#pragma once
// Objects in a scene: meshes loaded from OBJ/PLY/OFF/STL (scenegen/mesh_io.h), validated as closed
// volumes, scaled, rotated to their heading and placed by position and draft.
//
// Pose: the object frame has x = starboard, y = bow, z = up. Heading h is measured clockwise from
// north (compass convention, as the user gives it); world x = east, y = north. The rotation about
// z that takes the bow (+y) to compass heading h is counter-clockwise by -h:
//   R = [[cos h,  sin h, 0], [-sin h, cos h, 0], [0, 0, 1]]
// (h = 90 deg takes the bow to +x, east). Then world = R (scale * local) + t, with t.xy the
// position and t.z from the draft: the lowest point of the rotated mesh sits at waterLevel - draft.
#include <optional>
#include <string>
#include <vector>

#include "bathymetry/geo_frame.h"
#include "scenegen/assembly_spec.h"
#include "scenegen/mesh_io.h"
#include "scenegen/mesh_validity.h"
#include "scenegen/water_volume.h"

namespace littoral::scenegen {

struct Pose {
    Vec2 position;        // m, local frame
    double heading = 0;   // radians clockwise from north
    std::optional<double> draft;  // m below waterLevel of the lowest point
    std::optional<double> z;      // m, absolute z of the local origin (if no draft)
    double scale = 1.0;
};

// Applies scale, heading and translation (see the header comment). Throws InputError if neither
// or both of draft and z are set.
TriMesh placeMesh(const TriMesh& local, const Pose& pose, double waterLevel = 0.0);

struct PlacedObject {
    PlacedSolid solid;            // world coordinates
    ValidityReport validity;      // of the placed mesh
    Pose pose;
};

// Loads, validates (InputError listing the reasons if the mesh is not a valid closed volume,
// naming the object and its scene-file location) and places an object. `frame` converts
// latitude/longitude positions (required if the object uses them).
// The face material slots of an object's mesh against its `materials`: every slot a face uses
// must have a material (an OBJ's error names the usemtl line of the first slot without one).
void checkMaterialSlots(const ObjectSpec& spec, const TriMesh& mesh, const std::vector<MaterialSlotName>& slotNames);

PlacedObject loadObject(const ObjectSpec& spec, const bathymetry::GeoFrame* frame, double waterLevel = 0.0);

}  // namespace littoral::scenegen
