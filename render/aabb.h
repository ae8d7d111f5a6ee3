// Float bounding boxes and the ray/box slab test of BVH traversal (robustness.md, robust slab test):
// the double ray origin is rounded to floats on both sides so that each slab distance is
// conservative, tFar is widened by 1 + 2γ₃, and NaN slabs (0·∞) lose every comparison.
#pragma once

#include <cstdint>
#include <limits>
#include <utility>

#include "render/cpu_features.h"  // WSD_AVX_DISPATCH
#if defined(WSD_AVX_DISPATCH)
#include <immintrin.h>
#elif defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "render/math.h"

namespace wsd::render {

struct Bounds3f {
    Vec3f lo{std::numeric_limits<float>::infinity()};
    Vec3f hi{-std::numeric_limits<float>::infinity()};

    void extend(const Vec3f& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void extend(const Bounds3f& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    bool empty() const { return lo.x > hi.x; }
    Vec3f centroid() const { return (lo + hi) * 0.5f; }
    Vec3f extent() const { return hi - lo; }
    float half_area() const {
        if (empty()) return 0;
        Vec3f e = extent();
        return e.x * e.y + e.y * e.z + e.z * e.x;
    }
    // Conservative float box around a double box.
    static Bounds3f around(const Vec3& lo, const Vec3& hi) {
        Bounds3f b;
        b.lo = {to_float_down(lo.x), to_float_down(lo.y), to_float_down(lo.z)};
        b.hi = {to_float_up(hi.x), to_float_up(hi.y), to_float_up(hi.z)};
        return b;
    }
};

// 32 bytes: b[0..2] = lower corner, b[3..5] = upper corner. Inner nodes have count == 0 and
// their two children at `first` and `first + 1` (one cache line); leaves cover
// order[first, first + count).
struct BvhNode {
    float b[6];
    uint32_t first;
    uint32_t count;
};
static_assert(sizeof(BvhNode) == 32);

// The width of the traversal tree: children per node. 8 halves the levels a ray walks through
// against 4 (measured faster on meshes, docs/performance.md); the node test runs in 4-lane
// groups, so any x86-64 (SSE2) runs it.
inline constexpr int kBvhWidth = 8;
inline constexpr int kBvhGroups = kBvhWidth / 4;

// A node of the wide traversal tree: up to kBvhWidth children, transposed so that SIMD slab
// tests cover four at a time. Per axis a: lo[a][i] and hi[a][i] bound child i. Children fill
// lanes 0, 1, ...; unused lanes hold the empty box (lo = +inf, hi = -inf), which no ray enters,
// and child 0. A child's word packs count (bits 24-31) and first (bits 0-23): count == 0 is an
// inner child and `first` its own BvhWideNode; otherwise a leaf over order[first, first +
// count). 224 bytes at 32-byte alignment: whatever its offset, a node spans 4 cache lines.
struct alignas(32) BvhWideNode {
    static constexpr int kWidth = kBvhWidth;
    static constexpr int kFirstBits = 24;
    static constexpr uint32_t kFirstMask = (1u << kFirstBits) - 1;
    static constexpr uint32_t kMaxCount = 0xffu;
    float lo[3][kWidth];
    float hi[3][kWidth];
    uint32_t child[kWidth];

    uint32_t first(int i) const { return child[i] & kFirstMask; }
    uint32_t count(int i) const { return child[i] >> kFirstBits; }
    void set_child(int i, uint32_t first_, uint32_t count_) { child[i] = count_ << kFirstBits | first_; }

    // Bit i set for each lane that holds a child (the root is nobody's child, and a leaf's count
    // is not 0, so only unused lanes hold 0).
    int child_mask() const {
#if defined(__SSE2__)
        int m = 0;
        for (int g = 0; g < kBvhGroups; ++g) {
            const __m128i c = _mm_load_si128(reinterpret_cast<const __m128i*>(child + 4 * g));
            m |= _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(c, _mm_setzero_si128()))) << (4 * g);
        }
        return ~m & ((1 << kWidth) - 1);
#else
        int m = 0;
        for (int i = 0; i < kWidth; ++i)
            if (child[i] != 0) m |= 1 << i;
        return m;
#endif
    }
};
static_assert(sizeof(BvhWideNode) == 28 * kBvhWidth);
static_assert(kBvhWidth % 4 == 0 && kBvhWidth <= 16);

// Per-ray constants of the slab test, and the test of a node's children at once.
struct RayBoxTest {
    // Per axis (the fourth lane pads the rows, so that init writes each with one store).
    alignas(16) float o_near[4], o_far[4], inv[4];
    alignas(16) int near_off[4],
        far_off[4];  // the near and far plane rows: offsets into BvhWideNode, in floats
#if defined(__SSE2__)
    __m128 o_near4[3], o_far4[3], inv4[3];
#endif

    // The near plane is the lower bound when d > 0: its distance is underestimated by taking the
    // origin rounded up, the far one's overestimated by rounding it down.
    void init(const Vec3& o, const Vec3& d) {
#if defined(__SSE2__)
        // The scalar code below, three axes at once, bit for bit: the reciprocals are the same
        // IEEE divisions, and to_float_down / to_float_up's steps are taken lane by lane.
        const __m128d o01 = _mm_set_pd(o.y, o.x), o2 = _mm_set_sd(o.z);
        const __m128d d01 = _mm_set_pd(d.y, d.x), d2 = _mm_set_sd(d.z);
        const __m128d one = _mm_set1_pd(1.0);
        const __m128 rec = _mm_movelh_ps(_mm_cvtpd_ps(_mm_div_pd(one, d01)),
                                         _mm_cvtpd_ps(_mm_div_pd(one, _mm_set_pd(1.0, d.z))));
        const __m128 f = _mm_movelh_ps(_mm_cvtpd_ps(o01), _mm_cvtpd_ps(o2));  // to nearest
        const __m128d b01 = _mm_cvtps_pd(f), b2 = _mm_cvtps_pd(_mm_movehl_ps(f, f));
        const __m128 below = _mm_shuffle_ps(_mm_castpd_ps(_mm_cmplt_pd(b01, o01)),
                                            _mm_castpd_ps(_mm_cmplt_pd(b2, o2)), _MM_SHUFFLE(2, 0, 2, 0));
        const __m128 above = _mm_shuffle_ps(_mm_castpd_ps(_mm_cmpgt_pd(b01, o01)),
                                            _mm_castpd_ps(_mm_cmpgt_pd(b2, o2)), _MM_SHUFFLE(2, 0, 2, 0));
        const __m128i bits = _mm_castps_si128(f), ones = _mm_set1_epi32(-1), one_i = _mm_set1_epi32(1);
        const __m128i sign = _mm_srai_epi32(bits, 31);
        const __m128i up =
            _mm_add_epi32(bits, _mm_and_si128(_mm_or_si128(sign, one_i), _mm_castps_si128(below)));
        const __m128i down = _mm_add_epi32(
            bits, _mm_and_si128(_mm_or_si128(_mm_xor_si128(sign, ones), one_i), _mm_castps_si128(above)));
        // Lanes whose direction has its sign bit set (std::signbit; float keeps it, -0 included).
        const __m128i neg =
            _mm_srai_epi32(_mm_castps_si128(_mm_movelh_ps(_mm_cvtpd_ps(d01), _mm_cvtpd_ps(d2))), 31);
        const __m128i near = _mm_or_si128(_mm_and_si128(neg, down), _mm_andnot_si128(neg, up));
        const __m128i far = _mm_or_si128(_mm_and_si128(neg, up), _mm_andnot_si128(neg, down));
        _mm_store_ps(o_near, _mm_castsi128_ps(near));
        _mm_store_ps(o_far, _mm_castsi128_ps(far));
        _mm_store_ps(inv, rec);
        const __m128i row = _mm_setr_epi32(0, kBvhWidth, 2 * kBvhWidth, 3 * kBvhWidth);
        const __m128i other = _mm_set1_epi32(3 * kBvhWidth);
        _mm_store_si128(reinterpret_cast<__m128i*>(near_off), _mm_add_epi32(row, _mm_and_si128(neg, other)));
        _mm_store_si128(reinterpret_cast<__m128i*>(far_off),
                        _mm_add_epi32(row, _mm_andnot_si128(neg, other)));
        const __m128 vn = _mm_castsi128_ps(near), vf = _mm_castsi128_ps(far);
        o_near4[0] = _mm_shuffle_ps(vn, vn, 0x00), o_near4[1] = _mm_shuffle_ps(vn, vn, 0x55);
        o_near4[2] = _mm_shuffle_ps(vn, vn, 0xaa);
        o_far4[0] = _mm_shuffle_ps(vf, vf, 0x00), o_far4[1] = _mm_shuffle_ps(vf, vf, 0x55);
        o_far4[2] = _mm_shuffle_ps(vf, vf, 0xaa);
        inv4[0] = _mm_shuffle_ps(rec, rec, 0x00), inv4[1] = _mm_shuffle_ps(rec, rec, 0x55);
        inv4[2] = _mm_shuffle_ps(rec, rec, 0xaa);
#else
        const double rec[3] = {1.0 / d.x, 1.0 / d.y, 1.0 / d.z};
        for (int a = 0; a < 3; ++a) {
            bool neg = std::signbit(d[a]);
            float lo = to_float_down(o[a]), hi = to_float_up(o[a]);
            o_near[a] = neg ? lo : hi;
            o_far[a] = neg ? hi : lo;
            inv[a] = static_cast<float>(rec[a]);
            near_off[a] = (neg ? 3 * kBvhWidth : 0) + kBvhWidth * a;
            far_off[a] = (neg ? 0 : 3 * kBvhWidth) + kBvhWidth * a;
        }
#endif
    }

    static constexpr float kWiden = static_cast<float>(1 + 2 * gamma_f(3));

    // Bit i of the result is set when the ray may meet child i within (0, t_limit]; t_entry[i]
    // gets its entry distance. NaN slabs (0·∞) never decide.
    int hit(const BvhWideNode& node, float t_limit, float* t_entry) const {
#if defined(__AVX__) && defined(WSD_AVX_DISPATCH)
        return hit_avx(node, t_limit, t_entry);  // built for AVX (WSD_ARCH)
#elif defined(__SSE2__)
        const float* base = &node.lo[0][0];
        int mask = 0;
        for (int g = 0; g < kBvhGroups; ++g) {
            __m128 tn = _mm_setzero_ps(), tf = _mm_set1_ps(t_limit);
            for (int a = 0; a < 3; ++a) {
                __m128 t0 =
                    _mm_mul_ps(_mm_sub_ps(_mm_load_ps(base + near_off[a] + 4 * g), o_near4[a]), inv4[a]);
                __m128 t1 =
                    _mm_mul_ps(_mm_sub_ps(_mm_load_ps(base + far_off[a] + 4 * g), o_far4[a]), inv4[a]);
                tn = _mm_max_ps(t0, tn);  // maxps returns its second operand when one is NaN
                tf = _mm_min_ps(t1, tf);
            }
            _mm_storeu_ps(t_entry + 4 * g, tn);
            mask |= _mm_movemask_ps(_mm_cmple_ps(tn, _mm_mul_ps(tf, _mm_set1_ps(kWiden)))) << (4 * g);
        }
        return mask;
#else
        const float* base = &node.lo[0][0];
        int mask = 0;
        for (int i = 0; i < kBvhWidth; ++i) {
            float tn = 0, tf = t_limit;
            for (int a = 0; a < 3; ++a) {
                float t0 = (base[near_off[a] + i] - o_near[a]) * inv[a];
                float t1 = (base[far_off[a] + i] - o_far[a]) * inv[a];
                tn = t0 > tn ? t0 : tn;  // a NaN t0 leaves tn unchanged
                tf = t1 < tf ? t1 : tf;
            }
            t_entry[i] = tn;
            if (tn <= tf * kWiden) mask |= 1 << i;
        }
        return mask;
#endif
    }

#if defined(WSD_AVX_DISPATCH)
    // hit's operations on all eight lanes at once, for CPUs with AVX (avx_walk() in
    // render/cpu_features.h): a function of its own, so that code for every x86-64 holds it;
    // only functions built for AVX call it.
    // Bit for bit the same results (the same IEEE operations lane by lane, no contraction).
    [[gnu::target("avx"), gnu::always_inline]] inline int hit_avx(const BvhWideNode& node, float t_limit,
                                                                  float* t_entry) const {
        static_assert(kBvhWidth == 8);
        const float* base = &node.lo[0][0];
        __m256 tn = _mm256_setzero_ps(), tf = _mm256_set1_ps(t_limit);
        for (int a = 0; a < 3; ++a) {
            const __m256 on = _mm256_set1_ps(o_near[a]), of = _mm256_set1_ps(o_far[a]);
            const __m256 iv = _mm256_set1_ps(inv[a]);
            __m256 t0 = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(base + near_off[a]), on), iv);
            __m256 t1 = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(base + far_off[a]), of), iv);
            tn = _mm256_max_ps(t0, tn);  // returns its second operand when one is NaN, as maxps
            tf = _mm256_min_ps(t1, tf);
        }
        _mm256_storeu_ps(t_entry, tn);
        return _mm256_movemask_ps(_mm256_cmp_ps(tn, _mm256_mul_ps(tf, _mm256_set1_ps(kWiden)), _CMP_LE_OQ));
    }
#endif
};

// Whether the segment a + t·d, t in [0, 1], meets the closed box [lo, hi]: the slab test in double
// precision, for the handful of boxes of a conservative cull (Scene::may_cross_transmissive),
// where setting up RayBoxTest's float constants for every segment costs more than the test.
inline bool segment_meets_box(const Vec3& lo, const Vec3& hi, const Vec3& a, const Vec3& d) {
    double t0 = 0, t1 = 1;
    for (int i = 0; i < 3; ++i) {
        if (d[i] == 0) {
            if (!(a[i] >= lo[i] && a[i] <= hi[i])) return false;
            continue;
        }
        const double inv = 1.0 / d[i];
        double n = (lo[i] - a[i]) * inv, f = (hi[i] - a[i]) * inv;
        if (n > f) std::swap(n, f);
        t0 = n > t0 ? n : t0;
        t1 = f < t1 ? f : t1;
        if (!(t0 <= t1)) return false;
    }
    return true;
}

#if defined(__SSE2__)
// RayBoxTest::init's o_near, o_far and inv for four rays at once (lane k: ray k), bit for bit,
// without a branch (the rounding of o goes either way about half the time). Every ray's
// direction must have the sign `neg[a]` on axis a (signbit), as in a packet.
inline void slab_constants4(const Vec3 (&o)[4], const Vec3 (&d)[4], const bool (&neg)[3], __m128* o_near,
                            __m128* o_far, __m128* inv) {
    const __m128i one = _mm_set1_epi32(1), ones = _mm_set1_epi32(-1);
    for (int a = 0; a < 3; ++a) {
        const __m128d o01 = _mm_set_pd(o[1][a], o[0][a]), o23 = _mm_set_pd(o[3][a], o[2][a]);
        const __m128 f = _mm_movelh_ps(_mm_cvtpd_ps(o01), _mm_cvtpd_ps(o23));  // to nearest
        const __m128d b01 = _mm_cvtps_pd(f), b23 = _mm_cvtps_pd(_mm_movehl_ps(f, f));
        // Lanes where f fell below (above) o and must step up (down) one float.
        const __m128 below = _mm_shuffle_ps(_mm_castpd_ps(_mm_cmplt_pd(b01, o01)),
                                            _mm_castpd_ps(_mm_cmplt_pd(b23, o23)), _MM_SHUFFLE(2, 0, 2, 0));
        const __m128 above = _mm_shuffle_ps(_mm_castpd_ps(_mm_cmpgt_pd(b01, o01)),
                                            _mm_castpd_ps(_mm_cmpgt_pd(b23, o23)), _MM_SHUFFLE(2, 0, 2, 0));
        // Stepping up adds 1 to the bits of a positive float (or +0) and −1 to a negative one;
        // down the reverse. The cases next_float_* treats apart (+inf up, −inf down, −0 up, +0
        // down) cannot need a step here.
        const __m128i bits = _mm_castps_si128(f);
        const __m128i sign = _mm_srai_epi32(bits, 31);
        const __m128i step_up = _mm_or_si128(sign, one);
        const __m128i step_down = _mm_or_si128(_mm_xor_si128(sign, ones), one);
        const __m128 up =
            _mm_castsi128_ps(_mm_add_epi32(bits, _mm_and_si128(step_up, _mm_castps_si128(below))));
        const __m128 down =
            _mm_castsi128_ps(_mm_add_epi32(bits, _mm_and_si128(step_down, _mm_castps_si128(above))));
        o_near[a] = neg[a] ? down : up;
        o_far[a] = neg[a] ? up : down;
        const __m128d r01 = _mm_div_pd(_mm_set1_pd(1.0), _mm_set_pd(d[1][a], d[0][a]));
        const __m128d r23 = _mm_div_pd(_mm_set1_pd(1.0), _mm_set_pd(d[3][a], d[2][a]));
        inv[a] = _mm_movelh_ps(_mm_cvtpd_ps(r01), _mm_cvtpd_ps(r23));
    }
}
#endif

}  // namespace wsd::render
