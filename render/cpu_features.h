// The instruction sets the BVH walks choose at run time.
#pragma once

// Where the AVX node test (RayBoxTest::hit_avx in render/aabb.h) is compiled into every build,
// to be chosen at run time: x86-64 with GCC or clang.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define WSD_AVX_DISPATCH 1
#endif

namespace wsd::render {

// True when the walks for one ray (Geometry::intersect and occluded, and within instances) test
// a node's children with RayBoxTest::hit_avx (render/traverse.h, walk_bvh_chosen) and a mesh's
// leaves four triangles at a time (render/prim_test.h), and packets walk with AVX too
// (render/geometry_packet.cpp): on CPUs with AVX, detected at start-up, unless
// set_avx_walk(false) said otherwise (render/cpu_features.cpp). Shadow shafts keep the baseline
// tests.
#if defined(WSD_AVX_DISPATCH)
extern bool g_avx_walk;
extern bool g_avx512_packets;
inline bool avx_walk() {
    return g_avx_walk;
}
// True when, on top of avx_walk(), packets test a triangle against eight rays at once and a
// leaf's box against sixteen (render/geometry_packet.cpp): on CPUs with AVX-512 (AVX512F),
// unless set_avx512_packets(false) said otherwise.
inline bool avx512_packets() {
    return g_avx_walk && g_avx512_packets;
}
#else
inline bool avx_walk() {
    return false;
}
inline bool avx512_packets() {
    return false;
}
#endif
// Chooses the baseline (false) or the AVX tests (true, only where the CPU has AVX); returns
// whether AVX is used now. For comparisons (tests, benchmarks); the results are the same.
bool set_avx_walk(bool on);
// Chooses whether packets use AVX-512 where the CPU has it (and avx_walk() holds); returns
// whether they do now. For comparisons too; the results are the same.
bool set_avx512_packets(bool on);

}  // namespace wsd::render
