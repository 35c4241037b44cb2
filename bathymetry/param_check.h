#pragma once
// Internal: parameter validation shared by the bathymetry factories. A failed check is an
// InputError of the form "<what>.<field> = <value>: must be <allowed>", so the scene parser's
// messages line up with the keys the user wrote.
#include <cmath>
#include <string_view>

#include <fmt/format.h>

#include "core/error.h"

namespace littoral::bathymetry::detail {

inline void require(bool ok, std::string_view what, std::string_view field, double value, std::string_view allowed) {
    if (!ok || std::isnan(value))
        throw InputError(fmt::format("{}.{} = {}: must be {}", what, field, value, allowed));
}
inline void requireFinite(std::string_view what, std::string_view field, double v) {
    require(std::isfinite(v), what, field, v, "a finite number");
}
inline void requirePositive(std::string_view what, std::string_view field, double v) {
    require(std::isfinite(v) && v > 0, what, field, v, "a finite number > 0");
}
inline void requireNonNegative(std::string_view what, std::string_view field, double v) {
    require(std::isfinite(v) && v >= 0, what, field, v, "a finite number >= 0");
}

}  // namespace littoral::bathymetry::detail
