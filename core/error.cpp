#include "core/error.h"

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

}  // namespace littoral
