#include "core/progress.h"

#include <unistd.h>

#include <cstdio>

#include <fmt/format.h>

namespace littoral {

namespace {
std::atomic<bool> gEnabled{true};

std::string formatSeconds(double s) {
    if (s < 60) return fmt::format("{:.1f}s", s);
    if (s < 3600) return fmt::format("{}m{:02d}s", static_cast<int>(s / 60), static_cast<int>(s) % 60);
    return fmt::format("{}h{:02d}m", static_cast<int>(s / 3600), (static_cast<int>(s) / 60) % 60);
}
}  // namespace

void Progress::setEnabled(bool on) { gEnabled = on; }

Progress::Progress(std::string label, uint64_t total, std::string unit)
    : label_(std::move(label)), unit_(std::move(unit)), total_(total),
      start_(std::chrono::steady_clock::now()), lastDraw_(start_) {
    tty_ = isatty(STDERR_FILENO) != 0 && std::getenv("CI") == nullptr;
}

Progress::~Progress() { finish(); }

void Progress::advance(uint64_t n) {
    const uint64_t d = done_.fetch_add(n) + n;
    if (!gEnabled || total_ == 0) return;
    if (tty_) {
        const auto now = std::chrono::steady_clock::now();
        if (now - lastDraw_ < std::chrono::milliseconds(100) && d < total_) return;
        std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
        if (!lock.owns_lock()) return;
        lastDraw_ = now;
        draw(false);
    } else {
        const int decile = static_cast<int>(10 * d / total_);
        int prev = lastDecile_.load();
        while (decile > prev) {
            if (lastDecile_.compare_exchange_weak(prev, decile)) {
                if (decile < 10) {
                    std::lock_guard<std::mutex> lock(mutex_);
                    draw(false);
                }
                break;
            }
        }
    }
}

void Progress::draw(bool final) {
    const uint64_t d = std::min(done_.load(), total_);
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double rate = elapsed > 0 ? d / elapsed : 0.0;
    const double frac = total_ ? static_cast<double>(d) / total_ : 1.0;
    if (tty_) {
        const int width = 30;
        const int filled = static_cast<int>(frac * width);
        std::string bar(filled, '#');
        bar.resize(width, '.');
        std::string tail = final ? fmt::format("done in {}", formatSeconds(elapsed))
                                 : fmt::format("ETA {}", rate > 0 ? formatSeconds((total_ - d) / rate) : "?");
        std::fprintf(stderr, "\r%s [%s] %3.0f%% %.3g %s/s %s   %s", label_.c_str(), bar.c_str(), 100 * frac,
                     rate, unit_.c_str(), tail.c_str(), final ? "\n" : "");
    } else if (final) {
        std::fprintf(stderr, "%s: %llu %s in %s (%.3g %s/s)\n", label_.c_str(),
                     static_cast<unsigned long long>(d), unit_.c_str(), formatSeconds(elapsed).c_str(), rate,
                     unit_.c_str());
    } else {
        std::fprintf(stderr, "%s: %3.0f%% (%llu/%llu %s)\n", label_.c_str(), 100 * frac,
                     static_cast<unsigned long long>(d), static_cast<unsigned long long>(total_), unit_.c_str());
    }
    std::fflush(stderr);
}

void Progress::finish() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished_) return;
    finished_ = true;
    if (gEnabled && total_ > 0) draw(true);
}

}  // namespace littoral
