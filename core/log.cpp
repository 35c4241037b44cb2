#include "core/log.h"

#include <atomic>
#include <cstdio>
#include <mutex>
#include <set>
#include <string>

namespace littoral::log {

namespace {
std::atomic<Level> gLevel{Level::Info};
std::mutex gMutex;
}  // namespace

void setLevel(Level l) { gLevel = l; }

bool firstTime(std::string_view msg) {
    static std::set<std::string> seen;
    std::lock_guard<std::mutex> lock(gMutex);
    return seen.emplace(msg).second;
}
Level level() { return gLevel; }

void write(Level l, std::string_view msg) {
    static const char* names[] = {"debug", "info", "warning", "error"};
    std::lock_guard<std::mutex> lock(gMutex);
    if (l == Level::Info)
        std::fprintf(stderr, "%.*s\n", static_cast<int>(msg.size()), msg.data());
    else
        std::fprintf(stderr, "%s: %.*s\n", names[static_cast<int>(l)], static_cast<int>(msg.size()), msg.data());
    std::fflush(stderr);
}

}  // namespace littoral::log
