// HugePageAllocator: large blocks start on a 2 MiB boundary, are advised for huge pages and are
// unmapped when freed; small blocks and vectors that grow across the threshold behave as usual.
#include <sys/mman.h>

#include <catch2/catch.hpp>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>

#include "render/huge_pages.h"

using namespace wsd::render;

namespace {

constexpr std::uintptr_t kTwoMiB = std::uintptr_t{2} << 20;

// The VmFlags line of the mapping that holds p, from /proc/self/smaps ("" when not found).
std::string vm_flags_at(const void* p) {
    std::ifstream smaps("/proc/self/smaps");
    const auto addr = reinterpret_cast<std::uintptr_t>(p);
    std::string line;
    bool inside = false;
    while (std::getline(smaps, line)) {
        unsigned long lo = 0, hi = 0;
        if (std::sscanf(line.c_str(), "%lx-%lx ", &lo, &hi) == 2 && line.find(':') > line.find(' ')) {
            inside = addr >= lo && addr < hi;
            continue;
        }
        if (inside && line.rfind("VmFlags:", 0) == 0) return line;
    }
    return "";
}

// Whether the page holding p is mapped (mincore fails with ENOMEM on unmapped pages).
bool mapped(const void* p) {
    const auto page = reinterpret_cast<std::uintptr_t>(p) & ~std::uintptr_t{4095};
    unsigned char v = 0;
    return mincore(reinterpret_cast<void*>(page), 4096, &v) == 0 || errno != ENOMEM;
}

bool kernel_has_thp() {
    return std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled").good();
}

}  // namespace

TEST_CASE("large blocks start on a huge page, are advised for huge pages, and are unmapped when freed") {
    const size_t bytes = 5 * (size_t{1} << 20) + 100;  // not a whole number of pages
    void* p = huge_allocate(bytes, 16);
    auto* b = static_cast<unsigned char*>(p);
    for (size_t i = 0; i < bytes; i += 4096) b[i] = static_cast<unsigned char>(i >> 12);
    b[bytes - 1] = 7;
    CHECK(b[4096 * 300] == static_cast<unsigned char>(300));
    CHECK(b[bytes - 1] == 7);
    if (!kMapsHugePages) {  // AddressSanitizer's build: from operator new, like any other block
        huge_deallocate(p, bytes, 16);
        return;
    }
    CHECK(reinterpret_cast<std::uintptr_t>(p) % kTwoMiB == 0);
    if (kernel_has_thp()) {
        const std::string flags = vm_flags_at(p);
        INFO(flags);
        CHECK(flags.find(" hg") != std::string::npos);
    }
    // The tail past the last whole huge page stays mapped (4 KiB pages), nothing past the block.
    CHECK(mapped(b + bytes - 1));
    huge_deallocate(p, bytes, 16);
    // Both looked at before anything else can map memory into the freed range.
    const bool head = mapped(p), tail = mapped(b + bytes - 1);
    CHECK_FALSE(head);
    CHECK_FALSE(tail);
}

TEST_CASE("small blocks come from operator new with their alignment") {
    void* p = huge_allocate(1000, 64);
    REQUIRE(p != nullptr);
    CHECK(reinterpret_cast<std::uintptr_t>(p) % 64 == 0);
    static_cast<char*>(p)[999] = 1;
    huge_deallocate(p, 1000, 64);
    huge_deallocate(nullptr, 0, 8);  // a vector that never allocated
}

TEST_CASE("a HugePageVector keeps its elements as it grows past the threshold and is copied") {
    HugePageVector<uint32_t> v;
    for (uint32_t i = 0; i < 3'000'000; ++i) v.push_back(i * 7u);  // 12 MB: several moves, small to large
    if (kMapsHugePages) CHECK(reinterpret_cast<std::uintptr_t>(v.data()) % kTwoMiB == 0);
    bool same = true;
    for (uint32_t i = 0; i < v.size(); ++i) same = same && v[i] == i * 7u;
    CHECK(same);
    HugePageVector<uint32_t> w = v;
    CHECK(w == v);
    w.resize(10);
    w.shrink_to_fit();  // back to a small block
    CHECK(w.size() == 10);
    CHECK(w[9] == 63u);
    HugePageVector<uint32_t>().swap(v);
    CHECK(v.capacity() == 0);
}

TEST_CASE("a block too large to map is std::bad_alloc") {
    // (AddressSanitizer's operator new stops the process on such a size instead.)
    if (kMapsHugePages) CHECK_THROWS_AS(huge_allocate(static_cast<size_t>(-1) - 4096, 16), std::bad_alloc);
    HugePageAllocator<double> a;
    CHECK_THROWS_AS(a.allocate(static_cast<size_t>(-1) / 4), std::bad_array_new_length);
}
