#include "pipelines/lib_embedded.h"

#include <fmt/format.h>

#include "core/error.h"
#include "pipelines/embedded_scenes.h"

namespace littoral::pipelines {

std::string embeddedSceneText(const std::string& name) {
    for (const auto& [n, text] : kEmbeddedScenes)
        if (name == n) return text;
    throw InternalError("no built-in scene data_synthetic/" + name + ".yaml");
}

std::string replacedOnce(std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    if (at == std::string::npos || text.find(from, at + 1) != std::string::npos)
        throw InternalError("built-in scene: expected exactly one '" + from + "'");
    return text.replace(at, from.size(), to);
}

std::string boxObj(double sx, double sy, double h) {
    std::string s = "# a closed box written by Littoral\n";
    for (int i = 0; i < 8; ++i)
        s += fmt::format("v {:g} {:g} {:g}\n", (i & 1 ? 0.5 : -0.5) * sx, (i & 2 ? 0.5 : -0.5) * sy, i & 4 ? h : 0.0);
    // Faces by vertex bits (x = 1, y = 2, z = 4), 1-based, counter-clockwise seen from outside.
    for (const char* f : {"1 3 4", "1 4 2", "5 6 8", "5 8 7", "1 2 6", "1 6 5", "3 7 8", "3 8 4", "1 5 7", "1 7 3", "2 4 8", "2 8 6"})
        s += fmt::format("f {}\n", f);
    return s;
}

}  // namespace littoral::pipelines
