#pragma once
// Checks of a scene that need its geometry but no rendering, run by `littoral build` (and so by
// `run`, `demo` and `check-scene`, which builds the geometry in memory). Each failure is an
// InputError located at the scene-file entry that causes it:
//   * an object outside the scene domain, or crossing its edge (the water volume is cut at the
//     domain walls, so part of the object would be lost);
//   * two objects that intersect or contain one another;
//   * a sea surface that does not cover the domain;
//   * a sensor inside an object or under the ground, or one whose field of view misses the whole
//     scene (it would render nothing but sky);
//   * a probe inside an object or under the seabed (it would measure nothing);
//   * a render (images, photon maps) that needs more memory than the budget.
#include <functional>
#include <vector>

#include "bathymetry/terrain.h"
#include "core/mesh.h"
#include "core/scene_ir.h"
#include "scenegen/assembly_spec.h"
#include "scenegen/scene_file.h"
#include "surfaces/wave_surface.h"

namespace littoral::scenegen {

// The render that `ir` asks for fits the memory budget (core/render_budget.h); otherwise an
// InputError at the scene-file entry of the largest part (a sensor, render.photons.surface or
// render.photons.volume), naming the memory it needs.
void checkRenderMemory(const SceneSpec& spec, const ir::SceneIR& ir);

// Inside a closed, consistently oriented triangle mesh (majority of three ray-parity tests along
// fixed, irrational directions, so a ray that grazes an edge cannot decide the answer alone).
bool insideClosedMesh(const TriMesh& mesh, const Point3& p);

// Does the view of `sensor` (its frustum, or the orthographic prism) meet the box? Exact for a
// box: some corner ray hits it, or some box edge has a part inside the view volume.
bool viewSeesBox(const ir::Sensor& sensor, const BBox3& box);

// Objects (world meshes, in scene-file order) inside `domain` and pairwise disjoint.
void checkObjectPlacement(const std::vector<ObjectSpec>& specs, const std::vector<const TriMesh*>& meshes,
                          const bathymetry::Extent& domain);

// The surface rectangle (centre +- size / 2) covers `domain`; `where` locates water.surface.
void checkSurfaceCoverage(const surfaces::WaveParams& surface, const bathymetry::Extent& domain, const SourceLoc& where);

// Sensors and probes of `spec` (placed as in `ir`) against the ground, the objects and the scene.
// `ground` is the terrain elevation inside `domain`.
// `objects` are the placed meshes of `objectSpecs`, in the same order.
void checkSensorsAndProbes(const SceneSpec& spec, const ir::SceneIR& ir, const std::vector<ObjectSpec>& objectSpecs,
                           const std::vector<const TriMesh*>& objects,
                           const std::function<double(double, double)>& ground, const bathymetry::Extent& domain);

}  // namespace littoral::scenegen
