#pragma once
// Shared by the fuzz targets: what counts as a finding, and the limits every target runs under.
//
// A reader given arbitrary bytes may only return a value or throw InputError (the user's input
// is wrong: exit 1). Anything else -- a crash, a sanitizer report, a leak, an InternalError or any
// other exception escaping (exit 2 in `littoral`), a timeout, running out of memory -- is a
// finding, so other exceptions are left to escape and abort the run.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/error.h"
#include "core/resource_limits.h"

namespace littoral::fuzz {

// The memory budget the readers check against: far below libFuzzer's default RSS limit (2 GB),
// so an input that asks for too much must be refused by the budget check, not by the OOM killer.
inline void init() { setMemoryBudget(256u << 20); }

template <class F> void run(const uint8_t* data, size_t size, F&& parse) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    try {
        parse(bytes);
    } catch (const InputError&) {
        // Expected for most inputs.
    }
}

}  // namespace littoral::fuzz
