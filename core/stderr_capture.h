#pragma once
// Libraries that print their own diagnostics on stderr (libpng prints "libpng error: Not enough
// image data" before OpenImageIO reports the same failure) would put noise around Littoral's one
// located error. quietLibraryCall runs a reader with fd 2 sent to a temporary file; afterwards it
// writes back what was printed, except, when the reader failed, the lines of the named libraries
// (their failure is the one the reader's exception reports).
#include <exception>
#include <type_traits>
#include <string>
#include <utility>

namespace littoral {

class StderrCapture {
public:
    StderrCapture();   // flushes stderr and redirects fd 2 (one capture at a time in the process)
    ~StderrCapture();  // finish(true) unless finish was called
    StderrCapture(const StderrCapture&) = delete;
    StderrCapture& operator=(const StderrCapture&) = delete;
    // Restores fd 2 and writes the captured text back to it: all of it if `succeeded`, else the
    // lines that do not start with "libpng".
    void finish(bool succeeded);

private:
    int saved_ = -1, file_ = -1;
    bool done_ = false;
};

// Calls f() under a StderrCapture and returns its result (see above).
template <class F> auto quietLibraryCall(F&& f) -> decltype(f()) {
    StderrCapture capture;
    try {
        if constexpr (std::is_void_v<decltype(f())>) {
            f();
            capture.finish(true);
        } else {
            auto result = f();
            capture.finish(true);
            return result;
        }
    } catch (...) {
        capture.finish(false);
        throw;
    }
}

}  // namespace littoral
