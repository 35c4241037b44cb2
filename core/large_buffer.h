#pragma once
// Storage for large numeric arrays (photon records and their grid, up to gigabytes):
//
//  * Allocations of 2 MiB or more are aligned to 2 MiB and advised for transparent huge pages
//    (madvise MADV_HUGEPAGE; Debian's default THP mode, "madvise", backs only advised ranges). One
//    page-table entry then covers 2 MiB instead of 4 KiB: a photon map of 100 M records takes
//    ~1200 page faults to fill instead of ~600 000, and random queries into it miss the TLB far
//    less. Where the kernel declines, the memory is ordinary pages: nothing depends on it.
//  * Elements are default-initialised: resizing a buffer of integers that is about to be
//    overwritten does not first write zeros to all of it. (Value-initialise explicitly, e.g.
//    assign(n, 0), where zeros are wanted.)
#include <cstddef>
#include <new>
#include <utility>
#include <vector>

namespace littoral {

void* allocateLarge(std::size_t bytes);                    // std::bad_alloc on failure
void deallocateLarge(void* p, std::size_t bytes) noexcept;  // bytes as allocated

template <class T> struct LargeBufferAllocator {
    using value_type = T;
    LargeBufferAllocator() = default;
    template <class U> LargeBufferAllocator(const LargeBufferAllocator<U>&) noexcept {}
    T* allocate(std::size_t n) { return static_cast<T*>(allocateLarge(n * sizeof(T))); }
    void deallocate(T* p, std::size_t n) noexcept { deallocateLarge(p, n * sizeof(T)); }
    template <class U> void construct(U* p) noexcept { ::new (static_cast<void*>(p)) U; }
    template <class U, class... A> void construct(U* p, A&&... a) {
        ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
    }
    template <class U> bool operator==(const LargeBufferAllocator<U>&) const noexcept { return true; }
};

template <class T> using LargeVector = std::vector<T, LargeBufferAllocator<T>>;

}  // namespace littoral
