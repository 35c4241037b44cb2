#pragma once
// What the `littoral` binary carries with it, so that its named runs need no data files: scene
// files of data_synthetic/ compiled in (pipelines/CMakeLists.txt) and simple meshes written as OBJ.
#include <string>

namespace littoral::pipelines {

// The text of data_synthetic/<name>.yaml as built into the binary (e.g. "mobley1993/problem6");
// InternalError for a name that is not built in.
std::string embeddedSceneText(const std::string& name);

// `text` with its one occurrence of `from` replaced by `to`; InternalError if `from` occurs zero or
// several times (an embedded scene changed under the code that edits it).
std::string replacedOnce(std::string text, const std::string& from, const std::string& to);

// A closed box sx x sy x h (m) as an OBJ, its origin at the centre of its bottom, faces outward.
std::string boxObj(double sx, double sy, double h);

}  // namespace littoral::pipelines
