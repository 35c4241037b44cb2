#include "core/stderr_capture.h"

#include <stdio.h>
#include <unistd.h>

#include <cstdlib>
#include <mutex>

namespace littoral {

namespace {
std::recursive_mutex& captureMutex() {
    static std::recursive_mutex m;
    return m;
}

void writeAll(int fd, const std::string& s) {
    size_t at = 0;
    while (at < s.size()) {
        const ssize_t n = ::write(fd, s.data() + at, s.size() - at);
        if (n <= 0) return;  // stderr itself is gone: nothing better to do
        at += static_cast<size_t>(n);
    }
}
}  // namespace

StderrCapture::StderrCapture() {
    captureMutex().lock();
    std::fflush(stderr);
    char name[] = "/tmp/littoral-stderr-XXXXXX";
    file_ = ::mkstemp(name);
    if (file_ < 0) return;  // no capture: the noise stays, the error is still reported
    ::unlink(name);
    saved_ = ::dup(2);
    if (saved_ < 0 || ::dup2(file_, 2) < 0) {
        if (saved_ >= 0) ::close(saved_);
        ::close(file_);
        saved_ = file_ = -1;
    }
}

StderrCapture::~StderrCapture() { finish(true); }

void StderrCapture::finish(bool succeeded) {
    if (done_) return;
    done_ = true;
    if (file_ >= 0) {
        std::fflush(stderr);
        ::dup2(saved_, 2);
        ::close(saved_);
        std::string text;
        char buf[4096];
        ::lseek(file_, 0, SEEK_SET);
        for (ssize_t n; (n = ::read(file_, buf, sizeof buf)) > 0;) text.append(buf, static_cast<size_t>(n));
        ::close(file_);
        std::string kept;
        for (size_t at = 0; at < text.size();) {
            size_t end = text.find('\n', at);
            end = end == std::string::npos ? text.size() : end + 1;
            const std::string line = text.substr(at, end - at);
            if (succeeded || line.rfind("libpng", 0) != 0) kept += line;
            at = end;
        }
        writeAll(2, kept);
    }
    captureMutex().unlock();
}

}  // namespace littoral
