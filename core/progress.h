#pragma once
// Progress reporting for long stages. On a terminal: a redrawn bar with rate and ETA.
// Otherwise (CI, redirected stderr): a plain line at each 10% step. Thread-safe: advance()
// may be called from worker threads; only one of them redraws at a time.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace littoral {

class Progress {
public:
    // `unit` names what is counted ("rows", "photons"). total may be 0 (nothing drawn).
    Progress(std::string label, uint64_t total, std::string unit = "items");
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    void advance(uint64_t n = 1);
    void finish();  // idempotent; prints the final line with the elapsed time
    uint64_t done() const { return done_.load(); }

    // Globally silence all progress output (tests, --quiet).
    static void setEnabled(bool on);

private:
    void draw(bool final);
    std::string label_, unit_;
    uint64_t total_;
    std::atomic<uint64_t> done_{0};
    std::atomic<int> lastDecile_{0};
    std::chrono::steady_clock::time_point start_, lastDraw_;
    std::mutex mutex_;
    bool tty_ = false;
    bool finished_ = false;
};

}  // namespace littoral
