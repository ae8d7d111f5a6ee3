#include "render/huge_pages.h"

#include <sys/mman.h>

#include <cstdint>

namespace wsd::render {

namespace {

constexpr std::size_t kHugePage = std::size_t{2} << 20;
constexpr std::size_t kPage = 4096;

std::size_t round_up(std::size_t x, std::size_t to) {
    return (x + to - 1) / to * to;
}

}  // namespace

void* huge_allocate(std::size_t bytes, std::size_t align) {
    if (!kMapsHugePages || bytes < kHugePageMin) return ::operator new (bytes, std::align_val_t{align});
    if (bytes > static_cast<std::size_t>(-1) - 2 * kHugePage) throw std::bad_alloc();
    // Mapped with a huge page of slack, then trimmed to start on a 2 MiB boundary: a block that
    // started mid huge page could not use one there. Its tail, past its last whole huge page,
    // stays in 4 KiB pages, so no more memory is mapped than asked for.
    const std::size_t size = round_up(bytes, kPage);
    const std::size_t mapped = size + kHugePage;
    void* m = mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (m == MAP_FAILED) throw std::bad_alloc();
    const auto base = reinterpret_cast<std::uintptr_t>(m);
    const std::uintptr_t start = round_up(base, kHugePage);
    if (start > base) munmap(m, start - base);
    munmap(reinterpret_cast<void*>(start + size), base + mapped - (start + size));
    void* p = reinterpret_cast<void*>(start);
#if defined(MADV_HUGEPAGE)
    madvise(p, size, MADV_HUGEPAGE);  // advice only: where it is refused, the block stays as mapped
#endif
    return p;
}

void huge_deallocate(void* p, std::size_t bytes, std::size_t align) noexcept {
    if (!p) return;
    if (!kMapsHugePages || bytes < kHugePageMin) return ::operator delete (p, std::align_val_t{align});
    munmap(p, round_up(bytes, kPage));
}

}  // namespace wsd::render
