// Memory for a scene's large arrays (the BVH, its build's references, triangles and vertices) in
// transparent huge pages: blocks of kHugePageMin bytes or more are mapped on their own, aligned to
// 2 MiB and advised MADV_HUGEPAGE, so that the kernel backs them with 2 MiB pages where it can
// (Linux's "madvise" setting, the usual default, gives huge pages only to memory advised so).
// Touching fresh memory then takes one page fault per 2 MiB instead of one per 4 KiB: on a VM where
// a fault is expensive (2 cores, AMD EPYC) the 10⁷-triangle mesh's build went from about 5.5 s to
// 3.4-4.0 s on 2 threads, the 10⁶-triangle one from 0.50 to 0.27 s; tracing rays on it was as fast
// as before. (On another VM, whose free memory the host had not backed yet, huge pages were once
// slower to fault in than 4 KiB pages recycled from freed memory.) Where the kernel has no huge
// pages the advice is ignored and the memory is ordinary; smaller blocks come from operator new.
// Nothing stored depends on where memory comes from, so neither does any image.
#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace wsd::render {

inline constexpr std::size_t kHugePageMin = std::size_t{2} << 20;

// AddressSanitizer checks accesses to memory from operator new, not to memory mapped here: its
// builds take every block from operator new, so that the tree's arrays stay checked.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kMapsHugePages = false;
#else
inline constexpr bool kMapsHugePages = true;
#endif

// Raw blocks: huge_allocate(bytes, align) for align at most 4096; throws std::bad_alloc.
// huge_deallocate takes the same byte count and alignment as the huge_allocate that returned p.
void* huge_allocate(std::size_t bytes, std::size_t align);
void huge_deallocate(void* p, std::size_t bytes, std::size_t align) noexcept;

template <class T>
struct HugePageAllocator {
    using value_type = T;
    HugePageAllocator() = default;
    template <class U>
    HugePageAllocator(const HugePageAllocator<U>&) noexcept {}
    T* allocate(std::size_t n) {
        if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
        return static_cast<T*>(huge_allocate(n * sizeof(T), alignof(T)));
    }
    void deallocate(T* p, std::size_t n) noexcept { huge_deallocate(p, n * sizeof(T), alignof(T)); }
    template <class U>
    bool operator==(const HugePageAllocator<U>&) const noexcept {
        return true;
    }
};

template <class T>
using HugePageVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace wsd::render
