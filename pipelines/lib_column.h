#pragma once
// `littoral column`: the deterministic 1-D solver (column/) run on a scene file. The scene must be
// a column: horizontally periodic water with a flat surface, no objects or texture classes, and
// no bottom or a flat (zero-slope planar_slope) Lambertian or black one. Everything else is
// refused with its location; settings the column does not use (sensors, estimator settings, the
// sun's disc size) are listed as notes. docs/column.md.
#include <filesystem>
#include <string>
#include <vector>

#include "column/column_problem.h"
#include "column/column_solver.h"
#include "scenegen/scene_file.h"

namespace littoral::pipelines {

struct ColumnOptions {
    std::string scene;
    std::string out;
    std::vector<double> depths;  // m; empty: the default grid
    double step = 1.0;           // m, default grid spacing
    double maxDepth = 60.0;      // m, default grid extent without a bottom (or above a deeper one)
    int streams = 8;             // Gauss nodes per side of the Snell-window edge, per hemisphere
    int azimuths = 13;
};

// The column described by a scene file (every band), its output depths and the notes on settings
// it ignores. InputError at the scene-file location of anything the column cannot honour.
struct ColumnScene {
    std::vector<column::ColumnBand> bands;
    std::vector<double> depths;
    std::vector<std::string> notes;
    std::string name;
};
ColumnScene columnScene(const scenegen::SceneSpec& spec, const ColumnOptions& options);

// Solves every band and writes OUT/profiles.csv, profiles.json, radiance.csv and profiles.svg.
// Returns the printed summary (the profiles and the files).
std::string runColumn(const ColumnOptions& options);

}  // namespace littoral::pipelines
