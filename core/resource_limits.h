#pragma once
// Resource limits checked before anything large is allocated.
//
// One process-wide memory budget (`littoral --max-memory`, default derived from the machine's
// memory) bounds every allocation whose size comes from input: image size x bands, photon
// counts, grid sizes, element counts in file headers. A refusal is an InputError naming the
// setting that asked for the memory, how much it needs and the budget, e.g.
//     coast.yaml:31:14: error: render.photons.surface: 2000000000 photons need 59.6 GiB
//       (32 B each), more than the memory budget of 17.3 GiB (--max-memory)
// so a hostile or mistyped input fails in microseconds instead of after minutes of swapping or
// with std::bad_alloc.
//
// Element counts that a file header declares are also checked against the file's size
// (requireCountFitsFile): a 60-byte PLY cannot hold a billion vertices, whatever the budget.
#include <cstdint>
#include <string>
#include <string_view>

#include "core/error.h"

namespace littoral {

// Physical memory of the machine, bytes (sysconf), lowered to the cgroup limit when the process
// runs in a container with a smaller one. 0 if unknown.
uint64_t physicalMemoryBytes();

// Default budget: 3/4 of physicalMemoryBytes() (the rest is for the system and other programs),
// at least 1 GiB; 4 GiB when the machine's memory is unknown.
uint64_t defaultMemoryBudget();

// The current budget (defaultMemoryBudget() until set).
uint64_t memoryBudget();
void setMemoryBudget(uint64_t bytes);

// "512 MiB", "17.3 GiB": binary units, three significant digits.
std::string formatBytes(double bytes);

// Parses a memory size as given on the command line: a number with an optional binary unit
// suffix K, M, G, T (also KiB, MiB, GiB, TiB, case-insensitive); a bare number is GiB (what
// `littoral waves --max-memory` always accepted). Throws InputError naming `option` if the
// text is not a positive size.
uint64_t parseByteSize(std::string_view text, std::string_view option = "--max-memory");

// Refuses (InputError at `where`) an allocation of `bytes` that exceeds the budget. `what`
// names the setting and the amount, e.g. "render.photons.surface: 2000000000 photons (32 B each)".
// `bytes` is a double so products of hostile counts cannot overflow before the comparison.
void requireMemory(double bytes, const std::string& what, const SourceLoc& where = {});

// A header that declares `count` elements of at least `minBytesEach` bytes each cannot belong to
// a file whose remaining payload is `payloadBytes`: InputError at `where` ("the header declares
// 4000000000 vertices (at least 12 bytes each, 48.0 GB) but the file holds only 60 bytes").
// Returns normally when the count fits.
void requireCountFitsFile(double count, double minBytesEach, double payloadBytes, const std::string& what,
                          const SourceLoc& where);

}  // namespace littoral
