#pragma once
// The checkpoint of a progressive photon-mapping render (render_job.h): after every pass but the
// last, the running sums are saved to DIR/progressive.checkpoint/ as state.json (format, IR hash,
// sensor selection, passes, passes done, probe sums and squares, image sizes) and
// image<i>-<passes done>.f64 (the image sums, native doubles; state.json is renamed last).
// `--resume` reads them back, checked against the resuming run.
// Its own file so that the reader can be fuzzed without a renderer (fuzz/targets/fuzz_checkpoint.cpp).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace littoral::render {

// Running sums over progressive passes: images pixel by pixel, probes value by value (and the
// squares of the pass values, for the spread).
struct ProgressiveState {
    size_t irHash = 0;
    int passesDone = 0;
    std::vector<std::vector<double>> imageSums;
    std::vector<std::vector<double>> probeSums, probeSquares;
};

// What a checkpoint of this run must hold: the sensor selection it was made with, the passes of
// the run, and the sizes of its sums (pixels x bands per image, bands per probe value).
struct CheckpointShape {
    std::string sensor;  // --sensor ("" = every sensor and the probes)
    int passes = 1;
    std::vector<size_t> imageSizes;
    size_t probeValues = 0, bands = 0;
};

// Writes the checkpoint into `dir` and publishes it at once (outside the command's output set).
void saveCheckpoint(const std::filesystem::path& dir, const ProgressiveState& st, const CheckpointShape& shape);
// Reads the checkpoint in `dir`: InputError located at dir/state.json ("--resume: ...") if there is
// none, if it was made by another IR (`irHash`) or another sensor selection, or if it is unreadable
// or its passes and sums do not fit `shape`.
ProgressiveState loadCheckpoint(const std::filesystem::path& dir, size_t irHash, const CheckpointShape& shape);
// The file of image i's sums after `passes` passes.
std::string imageFileName(size_t i, int passes);

// A whole number of a checkpoint (progressive or tile): InputError naming `what` for a value that is
// not one or lies beyond int64 (nlohmann's get<int64_t> of 1e300, 2.5 or 2^64 - 1 would be undefined
// behaviour or silently truncate; a checkpoint can be edited by hand).
int64_t checkpointWholeNumber(const nlohmann::json& j, const std::string& what);

}  // namespace littoral::render
