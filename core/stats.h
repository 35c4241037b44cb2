#pragma once
// Named statistics counters ("rays cast", "photons stored"), printed by `--stats`.
// Counters are process-wide, thread-safe, and cheap to bump from hot loops: look the
// counter up once (statCounter) and keep the reference.
#include <atomic>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace littoral {

struct StatCounter {
    std::string name;
    std::atomic<int64_t> value{0};
    void add(int64_t v = 1) { value.fetch_add(v, std::memory_order_relaxed); }
};

// Returns the counter with this name, creating it at zero. References stay valid for the process.
StatCounter& statCounter(const std::string& name);
// Snapshot of every counter, sorted by name.
std::vector<std::pair<std::string, int64_t>> statSnapshot();
void statsReset();
void statsPrint(std::ostream& os);

}  // namespace littoral
