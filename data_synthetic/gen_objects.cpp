// Writes the object library: barge, small boat (hull slot 0, deck slot 1), buoy, pier with pilings
// (deck slot 0, pilings slot 1, one fused closed solid), a bright/dark step target and a 1 m cube (the
// dissertation's transparent epoxy cube, Sec. 10.4, with a dielectric material), as binary PLY
// with per-face material slots. Usage: gen_objects [OUT_DIR] (default data_synthetic/objects).
#include <cstdio>
#include <exception>
#include <string>

#include "scenegen/mesh_validity.h"
#include "scenegen/mesh_io.h"
#include "scenegen/synthetic_site.h"

int main(int argc, char** argv) {
    using namespace littoral::scenegen;
    const std::string out = argc > 1 ? argv[1] : "data_synthetic/objects";
    try {
        for (const auto& p : writeObjectLibrary(out)) {
            const ValidityReport r = checkMesh(readMeshFile(p));
            std::printf("%-40s %6zu faces  volume %10.4f m^3  %s\n", p.string().c_str(), r.faces, r.volume,
                        r.valid() ? "valid closed volume" : "INVALID");
            if (!r.valid()) return 1;
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
    return 0;
}
