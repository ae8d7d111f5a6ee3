// Closest hits for a packet of up to 16 rays that start close together and point the same way
// (camera rays through one pixel or a block of pixels): one walk of the BVH for all of them.
// At each node one SIMD test bounds, by interval arithmetic over the rays, which of the
// children any ray may enter; at a leaf each ray's own slab test (RayBoxTest::hit's
// arithmetic, lane by lane) picks the rays whose primitives are tested, with the single-ray
// triangle test's operations (two rays at a time when the rays share their axes; on CPUs with
// AVX four, and eight rays' leaf boxes and a node's eight children at once; with AVX-512 eight
// rays a triangle and sixteen a leaf box). Each ray gets
// exactly the hit intersect() returns: it enters every box intersect() would enter for it (the
// bounds are conservative, its own test is the same, its limit never below its own), and the
// closest hit with ties to the lowest id does not depend on the order primitives are tested in.
// Rays whose directions differ in sign on some axis, or that the single-ray path rejects or
// rescales, are traced one by one instead.
#include <algorithm>
#include <bit>

#include "render/geometry_impl.h"
#include "render/prim_test.h"
#include "render/traverse.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace wsd::render {

#if defined(__SSE2__)
namespace {

using namespace detail;

// Fewer nodes than primitives, so a node index and its lane fit in 32 bits (BvhChildAt::box).
static_assert(kMaxPrimitives <= (size_t{1} << (32 - kLaneBits)));

// test_entry for one ray of a packet, compiled once for both walks (flatten does not inline
// it): a build that contracts products into FMAs might contract the primitive's arithmetic
// differently in each, and the two must find the same hits. (Triangles keep their products
// rounded themselves: render/shapes.h.)
[[gnu::noinline]] bool test_entry_once(const Impl& g, const RayPre& r, uint32_t entry, double limit,
                                       Counters& c, HitRecord& h) {
    return test_entry(g, r, entry, limit, c, h);
}

// Q groups of four rays (lanes = rays; ray 4q + k is lane k of group q).
template <int Q>
struct Packet {
    static constexpr int kRays = 4 * Q;
    const RayPre* pre[kRays];
    // Per ray: RayBoxTest's constants, axis by axis (the groups of an axis side by side).
    alignas(32) __m128 o_near[3][Q], o_far[3][Q], inv[3][Q];
    // For the whole packet (broadcast): origins and inverse directions that bound every ray's
    // slab distances (see bound).
    __m128 po_near[3], po_far[3], inv_lo[3], inv_hi[3];
    int near_off[3], far_off[3];

    // Ray by ray: hit's operations for child i of the node at `base`, so that bit r is set
    // exactly when RayBoxTest::hit of ray r would set bit i.
    uint32_t rays_in(const float* base, int i, const __m128* t_limit) const {
        __m128 lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            lo[a] = _mm_set1_ps(base[near_off[a] + i]);
            hi[a] = _mm_set1_ps(base[far_off[a] + i]);
        }
        uint32_t in = 0;
        for (int q = 0; q < Q; ++q) {
            __m128 tn = _mm_setzero_ps(), tf = t_limit[q];
            for (int a = 0; a < 3; ++a) {
                __m128 t0 = _mm_mul_ps(_mm_sub_ps(lo[a], o_near[a][q]), inv[a][q]);
                __m128 t1 = _mm_mul_ps(_mm_sub_ps(hi[a], o_far[a][q]), inv[a][q]);
                tn = _mm_max_ps(t0, tn);
                tf = _mm_min_ps(t1, tf);
            }
            const int m = _mm_movemask_ps(_mm_cmple_ps(tn, _mm_mul_ps(tf, _mm_set1_ps(RayBoxTest::kWiden))));
            in |= static_cast<uint32_t>(m) << (4 * q);
        }
        return in;
    }

    // Child by child (lanes = children): bit i is set when some ray may enter child i within
    // its limit (t_limit is the largest). Interval arithmetic over the rays: the plane offset
    // is taken from the origin that makes it smallest (near) or largest (far), and rounded
    // products are monotone in each factor, so t_entry[i] is at most, and the exit bound at
    // least, what any ray's own test computes. Finite non-zero inverses only (no NaN here).
    int bound(const BvhWideNode& node, float t_limit, float* t_entry) const {
        const float* base = &node.lo[0][0];
        int mask = 0;
        for (int g = 0; g < kBvhGroups; ++g) {
            __m128 tn = _mm_setzero_ps(), tf = _mm_set1_ps(t_limit);
            for (int a = 0; a < 3; ++a) {
                const __m128 dn = _mm_sub_ps(_mm_load_ps(base + near_off[a] + 4 * g), po_near[a]);
                const __m128 df = _mm_sub_ps(_mm_load_ps(base + far_off[a] + 4 * g), po_far[a]);
                const __m128 t0 = _mm_min_ps(_mm_mul_ps(dn, inv_lo[a]), _mm_mul_ps(dn, inv_hi[a]));
                const __m128 t1 = _mm_max_ps(_mm_mul_ps(df, inv_lo[a]), _mm_mul_ps(df, inv_hi[a]));
                tn = _mm_max_ps(t0, tn);
                tf = _mm_min_ps(t1, tf);
            }
            _mm_storeu_ps(t_entry + 4 * g, tn);
            mask |= _mm_movemask_ps(_mm_cmple_ps(tn, _mm_mul_ps(tf, _mm_set1_ps(RayBoxTest::kWiden))))
                    << (4 * g);
        }
        return mask;
    }

#if defined(WSD_AVX_DISPATCH)
    // rays_in eight rays at a time (the same operations lane by lane). Not always_inline: leaf
    // calls it, which is built for every x86-64 and inlined into the AVX walk (flatten).
    [[gnu::target("avx")]] uint32_t rays_in_avx(const float* base, int i, const float* t_limit) const {
        static_assert(Q % 2 == 0);
        __m256 lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            lo[a] = _mm256_broadcast_ss(base + near_off[a] + i);
            hi[a] = _mm256_broadcast_ss(base + far_off[a] + i);
        }
        uint32_t in = 0;
        for (int h = 0; h < Q / 2; ++h) {
            __m256 tn = _mm256_setzero_ps(), tf = _mm256_load_ps(t_limit + 8 * h);
            for (int a = 0; a < 3; ++a) {
                const __m256 iv = _mm256_load_ps(reinterpret_cast<const float*>(&inv[a][2 * h]));
                __m256 t0 = _mm256_mul_ps(
                    _mm256_sub_ps(lo[a], _mm256_load_ps(reinterpret_cast<const float*>(&o_near[a][2 * h]))),
                    iv);
                __m256 t1 = _mm256_mul_ps(
                    _mm256_sub_ps(hi[a], _mm256_load_ps(reinterpret_cast<const float*>(&o_far[a][2 * h]))),
                    iv);
                tn = _mm256_max_ps(t0, tn);
                tf = _mm256_min_ps(t1, tf);
            }
            const int m = _mm256_movemask_ps(
                _mm256_cmp_ps(tn, _mm256_mul_ps(tf, _mm256_set1_ps(RayBoxTest::kWiden)), _CMP_LE_OQ));
            in |= static_cast<uint32_t>(m) << (8 * h);
        }
        return in;
    }

    // rays_in for all sixteen rays at once, for CPUs with AVX-512 (the same operations lane by
    // lane; comparisons give the mask directly).
    [[gnu::target("avx512f")]] uint32_t rays_in_avx512(const float* base, int i, const float* t_limit) const {
        static_assert(Q == 4);
        __m512 tn = _mm512_setzero_ps(), tf = _mm512_loadu_ps(t_limit);
        for (int a = 0; a < 3; ++a) {
            const __m512 lo = _mm512_set1_ps(base[near_off[a] + i]),
                         hi = _mm512_set1_ps(base[far_off[a] + i]);
            const __m512 iv = _mm512_loadu_ps(reinterpret_cast<const float*>(&inv[a][0]));
            const __m512 t0 = _mm512_mul_ps(
                _mm512_sub_ps(lo, _mm512_loadu_ps(reinterpret_cast<const float*>(&o_near[a][0]))), iv);
            const __m512 t1 = _mm512_mul_ps(
                _mm512_sub_ps(hi, _mm512_loadu_ps(reinterpret_cast<const float*>(&o_far[a][0]))), iv);
            // _mm512_max_ps and _mm512_min_ps through an all-lanes mask: GCC 12's header warns
            // about an uninitialized operand in the unmasked forms. The same instructions.
            tn = _mm512_mask_max_ps(t0, 0xffff, t0, tn);
            tf = _mm512_mask_min_ps(t1, 0xffff, t1, tf);
        }
        return _mm512_cmp_ps_mask(tn, _mm512_mul_ps(tf, _mm512_set1_ps(RayBoxTest::kWiden)), _CMP_LE_OQ);
    }

    // bound for all eight children at once (the same operations lane by lane).
    [[gnu::target("avx"), gnu::always_inline]] int bound_avx(const BvhWideNode& node, float t_limit,
                                                             float* t_entry) const {
        static_assert(kBvhWidth == 8);
        const float* base = &node.lo[0][0];
        __m256 tn = _mm256_setzero_ps(), tf = _mm256_set1_ps(t_limit);
        for (int a = 0; a < 3; ++a) {
            // The packet-wide constants are broadcast: every lane of them holds the same value.
            const __m256 lo = _mm256_broadcast_ss(reinterpret_cast<const float*>(&inv_lo[a]));
            const __m256 hi = _mm256_broadcast_ss(reinterpret_cast<const float*>(&inv_hi[a]));
            const __m256 dn = _mm256_sub_ps(_mm256_load_ps(base + near_off[a]),
                                            _mm256_broadcast_ss(reinterpret_cast<const float*>(&po_near[a])));
            const __m256 df = _mm256_sub_ps(_mm256_load_ps(base + far_off[a]),
                                            _mm256_broadcast_ss(reinterpret_cast<const float*>(&po_far[a])));
            const __m256 t0 = _mm256_min_ps(_mm256_mul_ps(dn, lo), _mm256_mul_ps(dn, hi));
            const __m256 t1 = _mm256_max_ps(_mm256_mul_ps(df, lo), _mm256_mul_ps(df, hi));
            tn = _mm256_max_ps(t0, tn);
            tf = _mm256_min_ps(t1, tf);
        }
        _mm256_storeu_ps(t_entry, tn);
        return _mm256_movemask_ps(
            _mm256_cmp_ps(tn, _mm256_mul_ps(tf, _mm256_set1_ps(RayBoxTest::kWiden)), _CMP_LE_OQ));
    }
#endif
};

// The packet's BVH walk: nearest child first by the packet's interval test (bound); at a leaf,
// each ray's own slab test picks the rays whose primitives are tested. Rays whose lane in `live`
// is clear have limit −1 and enter nothing. kLevel 1: the walk built for AVX (walk_bvh_avx, only
// where avx_walk() is true), whose triangle tests take four rays at a time; 2: that walk with
// AVX-512 leaves (avx512_packets()), eight rays a triangle test and sixteen a leaf's box.
template <int Q, int kLevel>
struct PacketClosestHit {
    static constexpr WalkOrder kOrder = WalkOrder::NearestFirst;
    static constexpr int kRays = 4 * Q;
    using Child = BvhChildAt;
    const Impl& g;
    const Packet<Q>& p;
    Best* best;
    Counters& c;
    alignas(32) float lim[kRays];
    __m128 limit[Q];
    float limit_max = -1;
    uint64_t leaf_boxes = 0;

    // Triangle edge functions two or four rays at a time when every ray of the packet has the
    // same axes (RayPre::kx, ky, kz): per ray the operations of triangle_edges, so the rays they
    // reject are those it would reject, and the others take the full test.
    bool paired = true;
    int axes[3] = {0, 1, 2};
    alignas(32) double ox[kRays], oy[kRays], oz[kRays], sx[kRays], sy[kRays], sz[kRays];

    PacketClosestHit(const Impl& g_, const Packet<Q>& p_, Best* best_, uint32_t live, Counters& c_)
        : g(g_), p(p_), best(best_), c(c_) {
        for (int k = 0; k < kRays; ++k) lim[k] = (live >> k & 1) ? to_float_up(best[k].limit) : -1.0f;
        load_limits();
        axes[0] = p.pre[0]->kx, axes[1] = p.pre[0]->ky, axes[2] = p.pre[0]->kz;
        for (int k = 0; k < kRays; ++k) {
            const RayPre& r = *p.pre[k];
            paired = paired && r.kx == axes[0] && r.ky == axes[1] && r.kz == axes[2];
            ox[k] = r.ox, oy[k] = r.oy, oz[k] = r.oz, sx[k] = r.sx, sy[k] = r.sy, sz[k] = r.sz;
        }
    }

    // The triangle (vertices v0, v1, v2; canonical id prim, stored at slot) against the rays
    // of `lanes`, Group::kWidth at a time (EdgesPair, or EdgesQuad in the walk built for AVX):
    // their edge functions, then finish_lanes for the rays whose line meets the triangle.
    template <class Group>
    void test_triangle_rays(const Vec3f& v0, const Vec3f& v1, const Vec3f& v2, uint32_t lanes, uint32_t prim,
                            uint32_t slot) {
        constexpr int kWidth = Group::kWidth;
        const float* v[3] = {glm::value_ptr(v0), glm::value_ptr(v1), glm::value_ptr(v2)};
        typename Group::Triangle tri;
        tri.set(v, axes);
        for (int j = 0; j < kRays; j += kWidth) {
            const uint32_t group = lanes >> j & ((1u << kWidth) - 1);
            if (group == 0) continue;
            c.tri_tests += kChildCount[group];  // std::popcount is a library call on baseline x86-64
            Group e;
            e.compute(tri, ox + j, oy + j, oz + j, sx + j, sy + j);
            const uint32_t live = group & ~e.ruled_out();
            if (live == 0) continue;
            finish_lanes(
                e, live, sz + j, [&](int lane) -> const RayPre& { return *p.pre[j + lane]; },
                [&](int lane) { return best[j + lane].limit; }, c,
                [&](int lane, double t, double b1, double b2) {
                    best[j + lane].offer(t, prim, slot, b1, b2);
                    return false;
                });
        }
    }

#if defined(WSD_AVX_DISPATCH)
    [[gnu::target("avx"), gnu::always_inline]] int enter_avx(const BvhWideNode& node, uint32_t,
                                                             float* tn) const {
        return p.bound_avx(node, limit_max, tn);
    }
#endif

    void load_limits() {
        __m128 m = _mm_set1_ps(-1.0f);
        for (int q = 0; q < Q; ++q) {
            limit[q] = _mm_load_ps(lim + 4 * q);
            m = _mm_max_ps(m, limit[q]);
        }
        m = _mm_max_ps(m, _mm_shuffle_ps(m, m, _MM_SHUFFLE(1, 0, 3, 2)));
        limit_max = _mm_cvtss_f32(_mm_max_ps(m, _mm_shuffle_ps(m, m, _MM_SHUFFLE(2, 3, 0, 1))));
    }

    int enter(const BvhWideNode& node, uint32_t, float* tn) const {
        return p.bound(node, limit_max, tn);
    }
    bool open(float t) const {
        return t <= limit_max * RayBoxTest::kWiden;
    }
    void prefetch_leaf(uint32_t first) const {
        prefetch_leaf_data(g, first);
    }

    bool leaf(const Child& e) {
        const BvhWideNode* nodes = g.nodes.data();
        const float* base = &nodes[e.box >> kLaneBits].lo[0][0];
        const int i = static_cast<int>(e.box & kLaneMask);
        uint32_t lanes;
#if defined(WSD_AVX_DISPATCH)
        if constexpr (kLevel == 2)
            lanes = p.rays_in_avx512(base, i, lim);
        else if constexpr (kLevel == 1 && Q % 2 == 0)
            lanes = p.rays_in_avx(base, i, lim);
        else
#endif
            lanes = p.rays_in(base, i, limit);
        leaf_boxes += Q;
        if (lanes == 0) return false;
        // Primitive by primitive, each for every ray in the leaf: a triangle's vertices are
        // fetched once. Each ray still meets the primitives in order (not that it matters: the
        // closest hit with ties to the lowest id does not depend on the order).
        for (uint32_t j = e.first(); j < e.first() + e.count(); ++j) {
            const uint32_t entry = entry_at(g, j);
            const uint32_t slot = entry & kSlotMask;
            double t, b1, b2;
            if (is_triangle(entry)) {
                const TriPrim& tri = g.tris[slot];
                const Vec3f &v0 = g.verts[tri.v[0]], &v1 = g.verts[tri.v[1]], &v2 = g.verts[tri.v[2]];
                if (paired) {
#if defined(WSD_AVX_DISPATCH)
                    if constexpr (kLevel == 2) {
                        test_triangle_rays<EdgesOct>(v0, v1, v2, lanes, tri.prim, slot);
                        continue;
                    } else if constexpr (kLevel == 1) {
                        test_triangle_rays<EdgesQuad>(v0, v1, v2, lanes, tri.prim, slot);
                        continue;
                    }
#endif
                    test_triangle_rays<EdgesPair>(v0, v1, v2, lanes, tri.prim, slot);
                    continue;
                }
                for (uint32_t l = lanes; l != 0; l &= l - 1) {
                    const int k = std::countr_zero(l);
                    if (test_triangle(*p.pre[k], v0, v1, v2, best[k].limit, c, t, b1, b2))
                        best[k].offer(t, tri.prim, slot, b1, b2);
                }
            } else {
                for (uint32_t l = lanes; l != 0; l &= l - 1) {
                    const int k = std::countr_zero(l);
                    HitRecord h;
                    if (test_entry_once(g, *p.pre[k], entry, best[k].limit, c, h)) best[k].offer(h, slot);
                }
            }
        }
        for (uint32_t l = lanes; l != 0; l &= l - 1) {
            const int k = std::countr_zero(l);
            lim[k] = to_float_up(best[k].limit);
        }
        load_limits();
        return false;
    }
};

#if defined(WSD_AVX_DISPATCH)
// The walk built for AVX, everything it calls inlined into it (the AVX tests included).
template <int Q>
[[gnu::target("avx"), gnu::flatten]] void closest_hit_packet_avx(const Impl& g, const Packet<Q>& p,
                                                                 Best* best, uint32_t live, Counters& c) {
    PacketClosestHit<Q, 1> q(g, p, best, live, c);
    uint64_t boxes = 0;
    walk_bvh_avx(g.nodes.data(), q, boxes);
    c.boxes += boxes + 4 * q.leaf_boxes;
}

// The same with AVX-512 leaves, for packets of sixteen rays (Q = 4).
[[gnu::target("avx512f"), gnu::flatten]] void closest_hit_packet_avx512(const Impl& g, const Packet<4>& p,
                                                                        Best* best, uint32_t live,
                                                                        Counters& c) {
    PacketClosestHit<4, 2> q(g, p, best, live, c);
    uint64_t boxes = 0;
    walk_bvh_avx(g.nodes.data(), q, boxes);
    c.boxes += boxes + 4 * q.leaf_boxes;
}
#endif

template <int Q>
void closest_hit_packet(const Impl& g, const Packet<Q>& p, Best* best, uint32_t live, Counters& c) {
#if defined(WSD_AVX_DISPATCH)
    if constexpr (Q == 4)
        if (avx512_packets()) return closest_hit_packet_avx512(g, p, best, live, c);
    if (avx_walk()) return closest_hit_packet_avx(g, p, best, live, c);
#endif
    PacketClosestHit<Q, 0> q(g, p, best, live, c);
    uint64_t boxes = 0;
    walk_bvh(g.nodes.data(), q, boxes);
    c.boxes += boxes + 4 * q.leaf_boxes;
}

// All four lanes set to the least (most) of x's lanes.
inline __m128 all_min(__m128 x) {
    x = _mm_min_ps(x, _mm_shuffle_ps(x, x, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm_min_ps(x, _mm_shuffle_ps(x, x, _MM_SHUFFLE(2, 3, 0, 1)));
}
inline __m128 all_max(__m128 x) {
    x = _mm_max_ps(x, _mm_shuffle_ps(x, x, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm_max_ps(x, _mm_shuffle_ps(x, x, _MM_SHUFFLE(2, 3, 0, 1)));
}

// The packet's constants from its rays (rays past n repeat the last one). False unless on
// every axis all directions have one sign and every inverse direction is a finite, non-zero
// float: then no slab distance is NaN and one plane is near for all.
template <int Q>
bool make_packet(const Ray* rays, int n, const RayPre* pre, Packet<Q>& p) {
    Vec3 o[Q][4], d[Q][4];
    for (int k = 0; k < 4 * Q; ++k) {
        p.pre[k] = &pre[k];
        o[k / 4][k % 4] = rays[std::min(k, n - 1)].o;
        d[k / 4][k % 4] = rays[std::min(k, n - 1)].d;
    }
    bool neg[3];
    for (int a = 0; a < 3; ++a) {
        neg[a] = std::signbit(d[0][0][a]);
        for (int k = 1; k < 4 * Q; ++k)
            if (std::signbit(d[k / 4][k % 4][a]) != neg[a]) return false;
    }
    const __m128 sign_bit = _mm_set1_ps(-0.0f);
    const __m128 inf = _mm_set1_ps(std::numeric_limits<float>::infinity());
    __m128 on_lo[3], on_hi[3], of_lo[3], of_hi[3], iv_lo[3], iv_hi[3];
    for (int q = 0; q < Q; ++q) {
        __m128 on[3], of[3], iv[3];
        slab_constants4(o[q], d[q], neg, on, of, iv);
        for (int a = 0; a < 3; ++a) {
            p.o_near[a][q] = on[a], p.o_far[a][q] = of[a], p.inv[a][q] = iv[a];
            const __m128 mag = _mm_andnot_ps(sign_bit, iv[a]);
            if (_mm_movemask_ps(_mm_and_ps(_mm_cmplt_ps(mag, inf), _mm_cmpgt_ps(mag, _mm_setzero_ps()))) !=
                15)
                return false;
            const bool first = q == 0;
            on_lo[a] = first ? on[a] : _mm_min_ps(on_lo[a], on[a]);
            on_hi[a] = first ? on[a] : _mm_max_ps(on_hi[a], on[a]);
            of_lo[a] = first ? of[a] : _mm_min_ps(of_lo[a], of[a]);
            of_hi[a] = first ? of[a] : _mm_max_ps(of_hi[a], of[a]);
            iv_lo[a] = first ? iv[a] : _mm_min_ps(iv_lo[a], iv[a]);
            iv_hi[a] = first ? iv[a] : _mm_max_ps(iv_hi[a], iv[a]);
        }
    }
    for (int a = 0; a < 3; ++a) {
        p.near_off[a] = (neg[a] ? 3 * kBvhWidth : 0) + kBvhWidth * a;
        p.far_off[a] = (neg[a] ? 0 : 3 * kBvhWidth) + kBvhWidth * a;
        // The near plane's offset (plane − origin) is least with the largest origin when the
        // rays go up this axis, and a negative inverse turns the greatest offset into the least
        // distance; the far plane's the other way round.
        p.po_near[a] = neg[a] ? all_min(on_lo[a]) : all_max(on_hi[a]);
        p.po_far[a] = neg[a] ? all_max(of_hi[a]) : all_min(of_lo[a]);
        p.inv_lo[a] = all_min(iv_lo[a]);
        p.inv_hi[a] = all_max(iv_hi[a]);
    }
    return true;
}

// The packet walk for n ≤ 4Q rays; false (nothing traced) when make_packet declines them.
template <int Q>
bool trace_packet(const Impl& g, const Ray* rays, int n, double tmax, RayStats& stats,
                  std::optional<HitRecord>* out) {
    // Rays past n repeat the last ray and stay dead (limit −1: no box is entered). The slab
    // constants are made for all the rays at once (make_packet), not by RayPre.
    RayPre pre[4 * Q];
    for (int k = 0; k < 4 * Q; ++k) pre[k].init(rays[std::min(k, n - 1)], false);
    Packet<Q> p;
    if (!make_packet(rays, n, pre, p)) return false;
    Best best[4 * Q];
    for (Best& b : best) b = Best{tmax};
    Counters c;
    if (!g.planes.empty())
        for (int k = 0; k < n; ++k) test_planes<0>(g, rays[k], best[k], c);
    closest_hit_packet(g, p, best, (1u << n) - 1, c);
    c.flush(stats);
    // Assigned in place: a whole optional built on the stack and copied (record()) reloaded its
    // flag byte as part of a wider word, which waits for the byte's store to complete.
    for (int k = 0; k < n; ++k)
        if (best[k].hit)
            out[k] = best[k].h;
        else
            out[k].reset();
    return true;
}

}  // namespace
#endif

void Geometry::intersect_packet(const Ray* rays, int n, double tmax, RayStats& stats,
                                std::optional<HitRecord>* out) const {
    const Impl& g = *impl_;
    bool packet = n >= 2 && n <= kMaxPacket && !g.nodes.empty() && tmax > 0;
#if !defined(__SSE2__)
    packet = false;
#endif
    // Directions far from unit length are traced one by one (intersect() rescales them).
    for (int k = 0; k < n && packet; ++k)
        packet = ray_is_valid(rays[k], tmax) && direction_scale(rays[k].d) == 0;
#if defined(__SSE2__)
    if (packet && (n <= 4 ? trace_packet<1>(g, rays, n, tmax, stats, out)
                          : trace_packet<4>(g, rays, n, tmax, stats, out)))
        return;
#endif
    for (int k = 0; k < n; ++k) out[k] = intersect(rays[k], tmax, stats);
}

}  // namespace wsd::render
