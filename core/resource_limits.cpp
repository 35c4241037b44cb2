#include "core/resource_limits.h"

#include <unistd.h>

#include <atomic>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <string>

#include <fmt/format.h>

namespace littoral {

namespace {

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;

// cgroup v2 (memory.max) or v1 (memory.limit_in_bytes) limit of this process's container; 0 if
// none is set ("max", or the v1 "unlimited" value near 2^63).
uint64_t cgroupLimit() {
    for (const char* path : {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
        std::ifstream f(path);
        std::string s;
        if (!(f >> s) || s == "max") continue;
        uint64_t v = 0;
        const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
        if (r.ec == std::errc() && v > 0 && v < (uint64_t{1} << 60)) return v;
    }
    return 0;
}

std::atomic<uint64_t>& budgetCell() {
    static std::atomic<uint64_t> b{defaultMemoryBudget()};
    return b;
}

}  // namespace

uint64_t physicalMemoryBytes() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), pageSize = ::sysconf(_SC_PAGESIZE);
    uint64_t phys = pages > 0 && pageSize > 0 ? static_cast<uint64_t>(pages) * static_cast<uint64_t>(pageSize) : 0;
    const uint64_t cg = cgroupLimit();
    if (cg > 0 && (phys == 0 || cg < phys)) phys = cg;
    return phys;
}

uint64_t defaultMemoryBudget() {
    const uint64_t phys = physicalMemoryBytes();
    if (phys == 0) return static_cast<uint64_t>(4 * kGiB);
    return std::max<uint64_t>(phys / 4 * 3, static_cast<uint64_t>(kGiB));
}

uint64_t memoryBudget() { return budgetCell().load(std::memory_order_relaxed); }

void setMemoryBudget(uint64_t bytes) { budgetCell().store(bytes, std::memory_order_relaxed); }

std::string formatBytes(double bytes) {
    static const char* kUnits[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    int u = 0;
    while (bytes >= 1024.0 && u < 6) {
        bytes /= 1024.0;
        ++u;
    }
    if (u == 0) return fmt::format("{:.0f} B", bytes);
    return fmt::format("{:.3g} {}", bytes, kUnits[u]);
}

uint64_t parseByteSize(std::string_view text, std::string_view option) {
    std::string s(text);
    auto bad = [&]() -> InputError {
        return InputError(fmt::format("{}: '{}' is not a memory size; give a positive number with an optional unit "
                                      "K, M, G or T (binary; a bare number is GiB), e.g. 512M or 8G",
                                      option, s));
    };
    size_t end = 0;
    while (end < s.size() && (std::isdigit(static_cast<unsigned char>(s[end])) || s[end] == '.')) ++end;
    double v = 0;
    const auto r = std::from_chars(s.data(), s.data() + end, v);
    if (end == 0 || r.ec != std::errc() || r.ptr != s.data() + end || !(v > 0) || !std::isfinite(v)) throw bad();
    std::string unit = s.substr(end);
    for (char& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    double scale = kGiB;
    if (unit == "K" || unit == "KIB") scale = 1024.0;
    else if (unit == "M" || unit == "MIB") scale = 1024.0 * 1024.0;
    else if (unit.empty() || unit == "G" || unit == "GIB") scale = kGiB;
    else if (unit == "T" || unit == "TIB") scale = 1024.0 * kGiB;
    else throw bad();
    const double bytes = v * scale;
    if (bytes < 1.0 || bytes > 1.0e18) throw bad();
    return static_cast<uint64_t>(bytes);
}

void requireMemory(double bytes, const std::string& what, const SourceLoc& where) {
    const double budget = static_cast<double>(memoryBudget());
    if (!(bytes <= budget))
        throw InputError(where, fmt::format("{} need {} of memory, more than the memory budget of {} (--max-memory)",
                                            what, formatBytes(bytes), formatBytes(budget)));
}

void requireCountFitsFile(double count, double minBytesEach, double payloadBytes, const std::string& what,
                          const SourceLoc& where) {
    if (!(count * minBytesEach <= payloadBytes))
        throw InputError(where, fmt::format("the header declares {:.0f} {} (at least {:.0f} bytes each, {} in all) but "
                                            "the file holds only {:.0f} bytes after the header: truncated or corrupt",
                                            count, what, minBytesEach, formatBytes(count * minBytesEach),
                                            payloadBytes));
}

}  // namespace littoral
