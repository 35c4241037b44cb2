#include "render/progressive_checkpoint.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"

namespace littoral::render {

namespace {

// InputError (an unreadable checkpoint) unless the probe sums read fit this run (the passes and the
// image sums are checked against the run as they are read).
void checkShape(const ProgressiveState& st, const CheckpointShape& shape) {
    if (st.probeSums.size() != shape.probeValues || st.probeSquares.size() != shape.probeValues)
        throw InputError(fmt::format("it holds {} probe values, this run computes {}", st.probeSums.size(), shape.probeValues));
    for (size_t i = 0; i < st.probeSums.size(); ++i)
        if (st.probeSums[i].size() != shape.bands || st.probeSquares[i].size() != shape.bands)
            throw InputError(fmt::format("probe value {} has {} bands, the scene {}", i, st.probeSums[i].size(), shape.bands));
}

}  // namespace

int64_t checkpointWholeNumber(const nlohmann::json& j, const std::string& what) {
    if (j.is_number_unsigned() && j.get<uint64_t>() > static_cast<uint64_t>(std::numeric_limits<int64_t>::max()))
        throw InputError(fmt::format("{} is {}, out of range", what, j.dump()));
    if (!j.is_number_integer()) throw InputError(fmt::format("{} is {}, not a whole number", what, j.dump()));
    return j.get<int64_t>();
}

// The sums of image i after `passes` passes: image<i>-<passes>.f64.
std::string imageFileName(size_t i, int passes) { return fmt::format("image{}-{}.f64", i, passes); }

void saveCheckpoint(const std::filesystem::path& dir, const ProgressiveState& st, const CheckpointShape& shape) {
    createOutputFolder(dir);
    nlohmann::json j;
    j["format"] = "littoral-progressive-checkpoint";
    j["ir_hash"] = std::to_string(st.irHash);
    j["sensor"] = shape.sensor;
    j["passes"] = shape.passes;
    j["passes_done"] = st.passesDone;
    j["probe_sums"] = st.probeSums;
    j["probe_squares"] = st.probeSquares;
    std::vector<size_t> sizes;
    for (const auto& v : st.imageSums) sizes.push_back(v.size());
    j["image_sizes"] = sizes;
    for (size_t i = 0; i < st.imageSums.size(); ++i) {
        const auto& v = st.imageSums[i];
        writeTextFileAtomic(dir / imageFileName(i, st.passesDone),
                            std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double)));
    }
    writeTextFileAtomic(dir / "state.json", j.dump(1) + "\n");
    // A checkpoint exists to survive an interrupted or failed run: it is published at once
    // instead of waiting for the command's output set (core/atomic_file.h). The image sums carry
    // their pass count in their names and state.json is renamed last, so a run killed while saving
    // leaves the previous pass's state with the previous pass's sums; those go once the new state
    // is in place.
    publishStagedOutputs();
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
        const std::string name = e.path().filename().string();
        bool current = false;
        for (size_t i = 0; i < st.imageSums.size(); ++i) current = current || name == imageFileName(i, st.passesDone);
        if (!current && name.rfind("image", 0) == 0 && e.path().extension() == ".f64") std::filesystem::remove(e.path(), ec);
    }
}

ProgressiveState loadCheckpoint(const std::filesystem::path& dir, size_t irHash, const CheckpointShape& shape) {
    const auto file = dir / "state.json";
    if (!std::filesystem::exists(file))
        throw InputError(SourceLoc{file.string()}, "--resume: no progressive checkpoint here (a run saves one after "
                                                   "every pass but the last)");
    ProgressiveState st;
    try {
        // The checkpoint is this run's own state, which it replaces after every pass: not an input
        // that outputs must leave alone (core/atomic_file.h).
        const auto j = nlohmann::json::parse(readTextFile(file));
        forgetInput(file);
        if (j.at("format") != "littoral-progressive-checkpoint") throw InputError("not a checkpoint");
        if (j.at("ir_hash").get<std::string>() != std::to_string(irHash))
            throw InputError(SourceLoc{file.string()}, "--resume: the checkpoint was made by a different scene (the IR "
                                                       "changed since); start the render again without --resume");
        const std::string sensor = j.at("sensor").get<std::string>();
        if (sensor != shape.sensor)
            throw InputError(SourceLoc{file.string()},
                             fmt::format("--resume: the checkpoint was made {}, this run renders {}; resume with the "
                                         "same --sensor selection",
                                         sensor.empty() ? "for every sensor" : "with --sensor " + sensor,
                                         shape.sensor.empty() ? "every sensor" : "only --sensor " + shape.sensor));
        st.irHash = irHash;
        const int64_t done = checkpointWholeNumber(j.at("passes_done"), "passes_done");
        if (!(done >= 1 && done < shape.passes))
            throw InputError(fmt::format("passes_done is {}; a checkpoint of this {}-pass run holds 1 to {} passes", done,
                                         shape.passes, shape.passes - 1));
        st.passesDone = static_cast<int>(done);
        st.probeSums = j.at("probe_sums").get<std::vector<std::vector<double>>>();
        st.probeSquares = j.at("probe_squares").get<std::vector<std::vector<double>>>();
        const auto& sizes = j.at("image_sizes");
        if (!sizes.is_array()) throw InputError("image_sizes is not a list");
        if (sizes.size() != shape.imageSizes.size())
            throw InputError(fmt::format("it holds {} images, this run renders {}", sizes.size(), shape.imageSizes.size()));
        for (size_t i = 0; i < sizes.size(); ++i) {
            const int64_t n = checkpointWholeNumber(sizes[i], fmt::format("image_sizes[{}]", i));
            if (n < 0 || static_cast<uint64_t>(n) != shape.imageSizes[i])
                throw InputError(fmt::format("image {} holds {} values, the sensor renders {}", i, n, shape.imageSizes[i]));
            const std::filesystem::path imageFile = dir / imageFileName(i, st.passesDone);
            const std::string raw = readTextFile(imageFile);
            forgetInput(imageFile);
            if (raw.size() != shape.imageSizes[i] * sizeof(double)) throw InputError("image sums truncated");
            std::vector<double> v(shape.imageSizes[i]);
            std::memcpy(v.data(), raw.data(), raw.size());
            for (size_t k = 0; k < v.size(); ++k)
                if (!std::isfinite(v[k]))
                    throw InputError(fmt::format("{} holds {} at value {}; a render's sums are finite",
                                                 imageFileName(i, st.passesDone), v[k], k));
            st.imageSums.push_back(std::move(v));
        }
        checkShape(st, shape);
    } catch (const InputError& e) {
        if (!e.where().file.empty()) throw;
        throw InputError(SourceLoc{file.string()}, "--resume: unreadable checkpoint: " + e.message());
    } catch (const std::exception& e) {
        throw InputError(SourceLoc{file.string()}, std::string("--resume: unreadable checkpoint: ") + e.what());
    }
    return st;
}

}  // namespace littoral::render
