#include "core/error.h"

#include <algorithm>
#include <vector>

namespace littoral {

std::string SourceLoc::str() const {
    std::string s = file;
    if (line > 0) {
        s += ':' + std::to_string(line);
        if (column > 0) s += ':' + std::to_string(column);
    }
    return s;
}

static std::string withLoc(const SourceLoc& w, const std::string& what) {
    const std::string loc = w.str();
    return loc.empty() ? what : loc + ": " + what;
}

InputError::InputError(std::string what) : std::runtime_error(what), message_(std::move(what)) {}

InputError::InputError(SourceLoc where, std::string what)
    : std::runtime_error(withLoc(where, what)), where_(std::move(where)), message_(std::move(what)) {}

namespace detail {
void checkFailed(const char* file, int line, const std::string& what) {
    throw InternalError(std::string("internal check failed at ") + file + ":" + std::to_string(line) + ": " + what);
}
}  // namespace detail

std::string libraryMessage(const std::string& text) {
    std::string out, line;
    std::vector<std::string> seen;
    auto flush = [&] {
        const size_t a = line.find_first_not_of(" \t\r"), b = line.find_last_not_of(" \t\r");
        const std::string t = a == std::string::npos ? "" : line.substr(a, b - a + 1);
        line.clear();
        if (t.empty() || std::find(seen.begin(), seen.end(), t) != seen.end()) return;
        seen.push_back(t);
        out += (out.empty() ? "" : "; ") + t;
    };
    for (char c : text) {
        if (c == '\n') flush();
        else line += c;
    }
    flush();
    return out;
}

}  // namespace littoral
