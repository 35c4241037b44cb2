#include "core/large_buffer.h"

#include <sys/mman.h>

#include <cstdlib>

namespace littoral {

namespace {
constexpr std::size_t kHugePage = std::size_t{2} << 20;
}

void* allocateLarge(std::size_t bytes) {
    if (bytes < kHugePage) return ::operator new(bytes);
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    void* p = std::aligned_alloc(kHugePage, rounded);
    if (!p) throw std::bad_alloc();
    madvise(p, rounded, MADV_HUGEPAGE);  // advice only: a refusal leaves ordinary pages
    return p;
}

void deallocateLarge(void* p, std::size_t bytes) noexcept {
    if (!p) return;
    if (bytes < kHugePage) ::operator delete(p);
    else std::free(p);
}

}  // namespace littoral
