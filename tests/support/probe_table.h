#pragma once
// The probe values a run wrote (OUT/probes.json, docs/outputs.md) as the tests read them: per probe
// and quantity, band 0's value, standard error, method and sample count.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

namespace littoral::testing_support {

struct ProbeCell {
    double value = NAN, se = NAN;
    std::string method;
    long long samples = 0;
};
using ProbeTable = std::map<std::string, std::map<std::string, ProbeCell>>;  // probe -> quantity -> cell

// The table of DIR/probes.json (a test failure, and an empty table, if there is none).
inline ProbeTable readProbeTable(const std::filesystem::path& dir) {
    ProbeTable t;
    std::ifstream in(dir / "probes.json");
    if (!in) {
        ADD_FAILURE() << "no probes.json in " << dir;
        return t;
    }
    const auto j = nlohmann::json::parse(in);
    for (const auto& v : j["probes"])
        t[v["probe"].get<std::string>()][v["quantity"].get<std::string>()] =
            ProbeCell{v["value"][0].get<double>(), v["stderr"][0].get<double>(), v["method"].get<std::string>(),
                      v["samples"].get<long long>()};
    return t;
}

}  // namespace littoral::testing_support
