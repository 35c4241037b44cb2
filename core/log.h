#pragma once
// Minimal leveled logging to stderr, formatted with fmt. Thread-safe (one line per call).
#include <fmt/format.h>

#include <string_view>

namespace littoral::log {

enum class Level { Debug = 0, Info = 1, Warn = 2, Error = 3, Quiet = 4 };

void setLevel(Level l);
Level level();
void write(Level l, std::string_view msg);

template <class... Args> void debug(fmt::format_string<Args...> f, Args&&... a) {
    if (level() <= Level::Debug) write(Level::Debug, fmt::format(f, std::forward<Args>(a)...));
}
template <class... Args> void info(fmt::format_string<Args...> f, Args&&... a) {
    if (level() <= Level::Info) write(Level::Info, fmt::format(f, std::forward<Args>(a)...));
}
template <class... Args> void warn(fmt::format_string<Args...> f, Args&&... a) {
    if (level() <= Level::Warn) write(Level::Warn, fmt::format(f, std::forward<Args>(a)...));
}
// A warning printed at most once per process for the same text (a check that runs at parse time
// and again at generation time must not say the same thing twice).
bool firstTime(std::string_view msg);
template <class... Args> void warnOnce(fmt::format_string<Args...> f, Args&&... a) {
    if (level() > Level::Warn) return;
    const std::string m = fmt::format(f, std::forward<Args>(a)...);
    if (firstTime(m)) write(Level::Warn, m);
}
template <class... Args> void error(fmt::format_string<Args...> f, Args&&... a) {
    if (level() <= Level::Error) write(Level::Error, fmt::format(f, std::forward<Args>(a)...));
}

}  // namespace littoral::log
