#include "core/stats.h"

#include <algorithm>
#include <deque>
#include <mutex>

#include <fmt/format.h>

namespace littoral {

namespace {
std::mutex gMutex;
std::deque<StatCounter>& counters() {
    static std::deque<StatCounter> c;  // deque: references survive growth
    return c;
}
}  // namespace

StatCounter& statCounter(const std::string& name) {
    std::lock_guard<std::mutex> lock(gMutex);
    for (auto& c : counters())
        if (c.name == name) return c;
    auto& c = counters().emplace_back();
    c.name = name;
    return c;
}

std::vector<std::pair<std::string, int64_t>> statSnapshot() {
    std::lock_guard<std::mutex> lock(gMutex);
    std::vector<std::pair<std::string, int64_t>> out;
    for (auto& c : counters()) out.emplace_back(c.name, c.value.load());
    std::sort(out.begin(), out.end());
    return out;
}

void statsReset() {
    std::lock_guard<std::mutex> lock(gMutex);
    for (auto& c : counters()) c.value = 0;
}

void statsPrint(std::ostream& os) {
    const auto snap = statSnapshot();
    size_t w = 0;
    for (auto& [n, v] : snap) w = std::max(w, n.size());
    os << "statistics:\n";
    for (auto& [n, v] : snap) os << fmt::format("  {:<{}}  {:>14}\n", n, w, v);
}

}  // namespace littoral
