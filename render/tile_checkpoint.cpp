#include "render/tile_checkpoint.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/ranks.h"
#include "core/error.h"
#include "render/progressive_checkpoint.h"
#include "render/film.h"

namespace littoral::render {

namespace {

constexpr const char* kFormat = "littoral-tile-checkpoint";

std::string valuesFile(size_t sensor, int64_t generation) { return fmt::format("sensor{}-{}.f32", sensor, generation); }

}  // namespace

TileCheckpoint::TileCheckpoint(std::filesystem::path dir, size_t irHash, std::string sensorSelection,
                               std::vector<size_t> filmValues, std::vector<size_t> slots)
    : dir_(std::move(dir)), irHash_(irHash), sensor_(std::move(sensorSelection)), filmValues_(std::move(filmValues)),
      slots_(std::move(slots)) {
    for (size_t k = 0; k < filmValues_.size(); ++k) {
        values_.emplace_back(filmValues_[k], 0.0f);
        done_.emplace_back(slots_[k], 0);
    }
    if (const char* e = std::getenv("LITTORAL_CHECKPOINT_SECONDS")) {
        char* end = nullptr;
        interval_ = std::strtod(e, &end);
        if (!*e || *end || !(interval_ >= 0 && interval_ <= 1e7))
            throw InputError(fmt::format("LITTORAL_CHECKPOINT_SECONDS: '{}' is not a number of seconds in [0, 10000000]", e));
    }
    lastSave_ = std::chrono::steady_clock::now();
}

void TileCheckpoint::restore(size_t sensor, const std::vector<Film*>& films) const {
    size_t k = 0;
    for (Film* f : films)
        for (float& v : f->pixels) v = values_[sensor][k++];
}

void TileCheckpoint::finished(size_t sensor, size_t begin, size_t end, const std::vector<const Film*>& films) {
    bool fresh = false;
    for (size_t s = begin; s < end; ++s) fresh = fresh || !done_[sensor][s], done_[sensor][s] = 1;
    if (!fresh) return;  // restored tiles: nothing new to save
    const bool sensorDone = std::all_of(done_[sensor].begin(), done_[sensor].end(), [](uint8_t d) { return d != 0; });
    const auto now = std::chrono::steady_clock::now();
    const bool due = std::chrono::duration<double>(now - lastSave_).count() >= interval_;
    if (!sensorDone && !due) return;
    // A finished sensor's films are kept (later saves write them again); the current one's when saved.
    size_t k = 0;
    for (const Film* f : films)
        for (float v : f->pixels) values_[sensor][k++] = v;
    if (!due) return;
    save();
    lastSave_ = std::chrono::steady_clock::now();
}

void TileCheckpoint::save() {
    if (!isRootRank()) return;  // rank 0 receives every rank's tiles and saves them
    ++generation_;
    // Written at once, outside the command's output set (a checkpoint exists to survive the run),
    // without publishing what the set has staged so far.
    const OutputSetPause outsideTheSet;
    createOutputFolder(dir_);
    nlohmann::json j;
    j["format"] = kFormat;
    j["ir_hash"] = std::to_string(irHash_);
    j["sensor"] = sensor_;
    j["generation"] = generation_;
    j["sensors"] = nlohmann::json::array();
    for (size_t k = 0; k < values_.size(); ++k) {
        std::string done(done_[k].size(), '0');
        for (size_t s = 0; s < done.size(); ++s) done[s] = done_[k][s] ? '1' : '0';
        j["sensors"].push_back({{"values", values_[k].size()}, {"done", done}});
        writeFileAtomic(dir_ / valuesFile(k, generation_),
                        std::string_view(reinterpret_cast<const char*>(values_[k].data()), values_[k].size() * sizeof(float)));
    }
    writeTextFileAtomic(dir_ / "state.json", j.dump(1) + "\n");  // last; then the previous generation goes
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(dir_, ec)) {
        const std::string name = e.path().filename().string();
        if (name.rfind("sensor", 0) == 0 && e.path().extension() == ".f32" &&
            name.find(fmt::format("-{}.f32", generation_)) == std::string::npos)
            std::filesystem::remove(e.path(), ec);
    }
}

void TileCheckpoint::load() {
    const auto file = dir_ / "state.json";
    if (!std::filesystem::exists(file))
        throw InputError(SourceLoc{file.string()}, "--resume: no render checkpoint here (a render saves one as its "
                                                   "tiles finish)");
    try {
        const auto j = nlohmann::json::parse(readTextFile(file));
        forgetInput(file);  // this run's own state, which it replaces as it goes
        if (j.at("format") != kFormat) throw InputError("not a render checkpoint");
        if (j.at("ir_hash").get<std::string>() != std::to_string(irHash_))
            throw InputError(SourceLoc{file.string()}, "--resume: the checkpoint was made by a different scene (the IR "
                                                       "changed since); start the render again without --resume");
        if (j.at("sensor").get<std::string>() != sensor_)
            throw InputError(SourceLoc{file.string()}, "--resume: the checkpoint was made with another --sensor "
                                                       "selection; resume with the same one");
        generation_ = checkpointWholeNumber(j.at("generation"), "generation");
        if (generation_ < 1) throw InputError(fmt::format("generation is {}; it counts from 1", generation_));
        const auto& sensors = j.at("sensors");
        if (!sensors.is_array() || sensors.size() != values_.size())
            throw InputError(fmt::format("it holds {} sensors, this run renders {}", sensors.is_array() ? sensors.size() : 0,
                                         values_.size()));
        for (size_t k = 0; k < values_.size(); ++k) {
            const int64_t n = checkpointWholeNumber(sensors[k].at("values"), fmt::format("sensors[{}].values", k));
            const std::string done = sensors[k].at("done").get<std::string>();
            if (n < 0 || static_cast<uint64_t>(n) != filmValues_[k] || done.size() != slots_[k] ||
                done.find_first_not_of("01") != std::string::npos)
                throw InputError(fmt::format("sensor {} does not fit this run ({} values and {} tiles; it renders {} "
                                             "and {})", k, n, done.size(), filmValues_[k], slots_[k]));
            const std::filesystem::path f = dir_ / valuesFile(k, generation_);
            const std::string raw = readTextFile(f);
            forgetInput(f);
            if (raw.size() != filmValues_[k] * sizeof(float)) throw InputError(f.filename().string() + " is truncated");
            std::memcpy(values_[k].data(), raw.data(), raw.size());
            for (size_t s = 0; s < done.size(); ++s) done_[k][s] = done[s] == '1';
        }
    } catch (const InputError& e) {
        if (!e.where().file.empty()) throw;
        throw InputError(SourceLoc{file.string()}, "--resume: unreadable render checkpoint: " + e.message());
    } catch (const std::exception& e) {
        throw InputError(SourceLoc{file.string()}, std::string("--resume: unreadable render checkpoint: ") + e.what());
    }
}

}  // namespace littoral::render
