// Writes the synthetic coastal site (scene.yaml, classification map, class textures, object meshes)
// into a folder. Usage: gen_coastal_site [OUT_DIR] [--seed N] [--triangles N]
// Default OUT_DIR is data_synthetic/coastal_site beside this file's source folder when run from
// the repository root. The same seed writes byte-identical files.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "core/error.h"
#include "scenegen/synthetic_site.h"

int main(int argc, char** argv) {
    using namespace littoral::scenegen;
    std::string out = "data_synthetic/coastal_site";
    SiteOptions opt;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--seed" && i + 1 < argc) opt.seed = std::strtoull(argv[++i], nullptr, 10);
        else if (a == "--triangles" && i + 1 < argc) opt.surfaceTriangles = std::strtoull(argv[++i], nullptr, 10);
        else if (a == "-h" || a == "--help") {
            std::printf("usage: gen_coastal_site [OUT_DIR] [--seed N] [--triangles N]\n");
            return 0;
        } else if (!a.empty() && a[0] != '-') out = a;
        else {
            std::fprintf(stderr, "gen_coastal_site: unknown argument '%s'\n", a.c_str());
            return 1;
        }
    }
    try {
        const SiteSummary s = writeSyntheticSite(out, opt);
        std::printf("wrote %zu files (%.1f kB) to %s; scene %s; step targets at", s.files.size(),
                    static_cast<double>(s.totalBytes) / 1024.0, out.c_str(), s.sceneFile.string().c_str());
        for (double d : s.targetTopDepths) std::printf(" %.2f", d);
        std::printf(" m\n");
    } catch (const littoral::InputError& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "internal error: %s\n", e.what());
        return 2;
    }
    return 0;
}
