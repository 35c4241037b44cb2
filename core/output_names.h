#pragma once
// Names that become file names: sensors (S.exr, S_truth.exr ...), objects (meshes/object_N.ply),
// texture classes (textures/N.tif), and names that end up in tables and metadata (probes, the
// scene). A name from a scene file or an IR is never trusted as a path:
//   * 1 to 64 characters from the portable set A-Z a-z 0-9 . _ - (POSIX portable file name
//     characters), so no separators, no NUL or control characters, no spaces or quotes that
//     would break a CSV row, and nothing a shell or another OS reads specially;
//   * not starting with '.' or '-' (hidden files, "..", options), not a reserved device name on
//     Windows (CON, NUL, COM1 ...), so an output folder can be copied anywhere;
//   * unique after every suffix the writers add, compared without regard to case (sensor "cam"
//     writes cam_truth.exr, so a sensor "cam_truth" would overwrite it; "Cam" and "cam" are one
//     file on a case-insensitive file system).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"

namespace littoral {

inline constexpr size_t kMaxOutputNameLength = 64;

// What is wrong with `name` as an output name, or "" if nothing.
std::string outputNameProblem(std::string_view name);

// InputError at `where`: "<what> name '<name, escaped>': <problem>".
void checkOutputName(std::string_view name, std::string_view what, const SourceLoc& where);

// The files `littoral render` writes for one sensor, in the order it writes them.
std::vector<std::string> sensorOutputFiles(std::string_view sensor);
// The files it writes once per render when the scene has probes.
std::vector<std::string> probeOutputFiles();

// Two sensors whose outputs would share a file name (case-insensitively): indices into the list
// and the file. Also reports a sensor file equal to a probe table when `withProbes`.
struct OutputClash {
    size_t first = 0, second = 0;  // second > first; second == first for a clash with a probe table
    std::string file;
};
std::optional<OutputClash> findOutputClash(const std::vector<std::string>& sensors, bool withProbes);

// A name as it may be printed in a message: non-printable bytes as \xNN, at most 80 characters.
std::string printableName(std::string_view name);

}  // namespace littoral
