#pragma once
// The checkpoint of a render made in one pass (the path estimator, or dirsig without progressive
// photon passes): a sensor's tiles are rendered in chunks of about 1/16 of them, and after a chunk
// that ends at least LITTORAL_CHECKPOINT_SECONDS (default 30) after the last save, the finished
// tiles of every sensor are saved to DIR/render.checkpoint/ as state.json
// (format, IR hash, sensor selection, generation, per sensor its film values and which tile of
// which band group is done) and sensor<k>-<generation>.f32 (the films end to end, native floats;
// state.json is renamed last, and the older generation removed after it). `--resume` reads them
// back, checked against the resuming run, and renders only the tiles not done. Pixels are
// independent and deterministic, so the resumed run equals the uninterrupted one byte for byte.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace littoral::render {

struct Film;

class TileCheckpoint {
public:
    // One slot per (band group, tile) of each sensor; `filmValues` the values of each sensor's
    // films (SensorImage::films()) end to end.
    TileCheckpoint(std::filesystem::path dir, size_t irHash, std::string sensorSelection,
                   std::vector<size_t> filmValues, std::vector<size_t> slots);
    // --resume: reads the checkpoint in the folder. InputError located at its state.json if there is
    // none, if another IR or sensor selection made it, or if it does not fit this run.
    void load();
    // Copies the saved values of `sensor` into its films (SensorImage::films(), before rendering
    // its tiles).
    void restore(size_t sensor, const std::vector<Film*>& films) const;
    bool done(size_t sensor, size_t slot) const { return done_[sensor][slot] != 0; }
    // Marks slots [begin, end) of `sensor` done and saves every sensor (published at once); `films`
    // the sensor's films as they stand.
    void finished(size_t sensor, size_t begin, size_t end, const std::vector<const Film*>& films);
    // The values of sensor k's films, end to end, as loaded or last kept.
    const std::vector<float>& values(size_t k) const { return values_[k]; }
    const std::filesystem::path& dir() const { return dir_; }

private:
    void save();
    std::filesystem::path dir_;
    size_t irHash_;
    std::string sensor_;
    std::vector<size_t> filmValues_, slots_;
    std::vector<std::vector<float>> values_;
    std::vector<std::vector<uint8_t>> done_;
    int64_t generation_ = 0;
    double interval_ = 30;  // s between saves
    std::chrono::steady_clock::time_point lastSave_;
};

}  // namespace littoral::render
