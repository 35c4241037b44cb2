#pragma once
// `littoral sweep SCENE.yaml --vary KEY=V1,V2,... [--vary ...] --out DIR`: a study as a grid of
// runs (docs/sweeps.md). Every point of the grid (the Cartesian product of the --vary lists, the
// last one varying fastest) becomes DIR/runs/NNNN/: a self-contained scene.yaml (the scene with the
// point's values set and every file path made absolute) and the complete output of `littoral run`
// on it (images, truth layers, probes, the IR). DIR/index.csv and DIR/index.json list every run's
// parameters, status and outputs; DIR/sweep.json records the plan, so that a second sweep into DIR
// resumes this one (finished runs are kept, unfinished ones are run again from the start) and a
// different sweep into DIR is refused.
#include <string>
#include <vector>

#include "render/image_output.h"

namespace littoral::pipelines {

// One --vary: a dotted key path into the scene file ("water.surface.wind_speed",
// "sensors[0].gsd_m") and the values it takes, as YAML scalars.
struct SweepAxis {
    std::string option;  // as given, for error messages
    std::string key;
    std::vector<std::string> values;
};
// Parses "KEY=V1,V2,...". InputError naming the option on a malformed one.
SweepAxis parseSweepAxis(const std::string& option);

struct SweepOptions {
    std::string scene;
    std::string out;
    std::vector<std::string> vary;  // the --vary options as given
    int threads = 0;
    bool progress = true;
    bool slurm = false;  // write DIR/sweep.sbatch (a Slurm job array) instead of running
    long long task = -1; // run only this run (0-based), as a Slurm array task does
    render::PreviewOptions preview;
};

// One point of the grid: its values (one per axis) and its scene file's text.
struct SweepRun {
    std::vector<std::string> values;
    std::string sceneYaml;
};
// Expands the grid and checks every point's scene (every section parsed and checked, the render
// settings against the estimator) before anything is written. InputError naming the --vary value
// and the scene-file location on the first point that fails.
std::vector<SweepRun> expandSweep(const std::string& sceneFile, const std::vector<SweepAxis>& axes);

// Runs (or, with `slurm`, schedules) the sweep; returns a summary of what was done.
std::string runSweep(const SweepOptions& options);

}  // namespace littoral::pipelines
