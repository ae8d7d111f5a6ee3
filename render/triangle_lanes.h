// The watertight triangle test (render/shapes.h: triangle_edges, finish_edges, triangle_hit) for
// several (ray, triangle) pairs at once, one per SIMD lane: two with SSE2 (EdgesPair), four with
// AVX (EdgesQuad) and eight with AVX-512 (EdgesOct, for packets), chosen at run time. Each lane
// does the scalar code's operations with its roundings: a lane rules out exactly the pairs the
// scalar test would, finishes (t, its error bound, the hit) as the scalar test does, and hands on
// a lane whose edge function is zero, to be recomputed, as the scalar test has it then. One
// struct per register width: they differ in their intrinsics only. Internal to render/.
#pragma once

#include <cstdint>

#include "render/shapes.h"
#if defined(WSD_AVX_DISPATCH)
#include <immintrin.h>
#elif defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace wsd::render {

#if defined(__SSE2__)
// What finish() leaves per lane: t, the determinant and the edge functions that give b1 and b2
// (triangle_hit divides them only for a hit that is taken).
struct LaneHits {
    alignas(64) double t[8], det[8], e1[8], e2[8];
};

// triangle_edges' translation, shear and edge functions for two (ray, triangle) pairs at once,
// one per lane, with the same operations and roundings as the scalar code lane by lane: two rays
// against one triangle (packets) or one ray against two triangles (a leaf). Vertex i of lane l
// is (vx[i], vy[i], vz[i]) lane l, already permuted to the ray's axes (kx, ky, kz).
struct EdgesPair {
    static constexpr uint32_t kWidth = 2;
    __m128d pz[3], x[3], y[3], e0, e1, e2;

    // Ray r against two triangles: vertex i of lane l's has the float components v[i][l].
    void compute(const float* const (&v)[3][2], const RayPre& r) {
        __m128d vx[3], vy[3], vz[3];
        for (int i = 0; i < 3; ++i) {
            vx[i] = _mm_set_pd(static_cast<double>(v[i][1][r.kx]), static_cast<double>(v[i][0][r.kx]));
            vy[i] = _mm_set_pd(static_cast<double>(v[i][1][r.ky]), static_cast<double>(v[i][0][r.ky]));
            vz[i] = _mm_set_pd(static_cast<double>(v[i][1][r.kz]), static_cast<double>(v[i][0][r.kz]));
        }
        compute(vx, vy, vz, _mm_set1_pd(r.ox), _mm_set1_pd(r.oy), _mm_set1_pd(r.oz), _mm_set1_pd(r.sx),
                _mm_set1_pd(r.sy));
    }
    // One triangle in every lane: vertex i's float components v[i], taken on axes k (kx, ky, kz).
    struct Triangle {
        __m128d vx[3], vy[3], vz[3];
        void set(const float* const (&v)[3], const int (&k)[3]) {
            for (int i = 0; i < 3; ++i) {
                vx[i] = _mm_set1_pd(static_cast<double>(v[i][k[0]]));
                vy[i] = _mm_set1_pd(static_cast<double>(v[i][k[1]]));
                vz[i] = _mm_set1_pd(static_cast<double>(v[i][k[2]]));
            }
        }
    };
    // Two rays (lane l: RayPre's ox, oy, oz, sx, sy at index l of each array, 16-byte aligned; all
    // with the triangle's axes) against the triangle.
    void compute(const Triangle& t, const double* ox, const double* oy, const double* oz, const double* sx,
                 const double* sy) {
        compute(t.vx, t.vy, t.vz, _mm_load_pd(ox), _mm_load_pd(oy), _mm_load_pd(oz), _mm_load_pd(sx),
                _mm_load_pd(sy));
    }

    void compute(const __m128d (&vx)[3], const __m128d (&vy)[3], const __m128d (&vz)[3], __m128d ox,
                 __m128d oy, __m128d oz, __m128d sx, __m128d sy) {
        for (int i = 0; i < 3; ++i) {
            pz[i] = _mm_sub_pd(vz[i], oz);
            x[i] = _mm_add_pd(_mm_sub_pd(vx[i], ox), opaque(_mm_mul_pd(sx, pz[i])));
            y[i] = _mm_add_pd(_mm_sub_pd(vy[i], oy), opaque(_mm_mul_pd(sy, pz[i])));
        }
        e0 = _mm_sub_pd(opaque(_mm_mul_pd(x[1], y[2])), opaque(_mm_mul_pd(y[1], x[2])));
        e1 = _mm_sub_pd(opaque(_mm_mul_pd(x[2], y[0])), opaque(_mm_mul_pd(y[2], x[0])));
        e2 = _mm_sub_pd(opaque(_mm_mul_pd(x[0], y[1])), opaque(_mm_mul_pd(y[0], x[1])));
    }
    // Bit l set when lane l's line misses as finish_edges decides: no edge function is zero (it
    // would be recomputed) and two of them have opposite signs.
    uint32_t ruled_out() const {
        const __m128d zero = _mm_setzero_pd();
        const __m128d zeros =
            _mm_or_pd(_mm_or_pd(_mm_cmpeq_pd(e0, zero), _mm_cmpeq_pd(e1, zero)), _mm_cmpeq_pd(e2, zero));
        const __m128d neg =
            _mm_or_pd(_mm_or_pd(_mm_cmplt_pd(e0, zero), _mm_cmplt_pd(e1, zero)), _mm_cmplt_pd(e2, zero));
        const __m128d pos =
            _mm_or_pd(_mm_or_pd(_mm_cmpgt_pd(e0, zero), _mm_cmpgt_pd(e1, zero)), _mm_cmpgt_pd(e2, zero));
        return static_cast<uint32_t>(_mm_movemask_pd(_mm_andnot_pd(zeros, _mm_and_pd(neg, pos))));
    }
    // Bit l set when one of lane l's edge functions is zero (finish_edges recomputes it).
    uint32_t zero_lanes() const {
        const __m128d zero = _mm_setzero_pd();
        return static_cast<uint32_t>(_mm_movemask_pd(
            _mm_or_pd(_mm_or_pd(_mm_cmpeq_pd(e0, zero), _mm_cmpeq_pd(e1, zero)), _mm_cmpeq_pd(e2, zero))));
    }
    // The rest of finish_edges and triangle_hit for both lanes at once, the same operations lane
    // by lane (sz: each lane's RayPre::sz), for lanes whose edge functions finish_edges takes as
    // they are (no zero among them, signs not ruled out): bit l is set when lane l hits at
    // out.t[l] > δt, before its limit is compared.
    uint32_t finish(const double* sz, LaneHits& out) const {
        const __m128d s = _mm_loadu_pd(sz), zero = _mm_setzero_pd(), sign = _mm_set1_pd(-0.0);
        const __m128d det = _mm_add_pd(_mm_add_pd(e0, e1), e2);
        const __m128d z0 = _mm_mul_pd(s, pz[0]), z1 = _mm_mul_pd(s, pz[1]), z2 = _mm_mul_pd(s, pz[2]);
        const __m128d t =
            _mm_div_pd(_mm_add_pd(_mm_add_pd(opaque(_mm_mul_pd(e0, z0)), opaque(_mm_mul_pd(e1, z1))),
                                  opaque(_mm_mul_pd(e2, z2))),
                       det);
        // TriangleEdges::t_error: std::max({a, b, c}) keeps a until a later value is greater.
        const auto abs_max = [sign](__m128d a, __m128d b, __m128d c) {
            const __m128d m = _mm_max_pd(_mm_andnot_pd(sign, b), _mm_andnot_pd(sign, a));
            return _mm_max_pd(_mm_andnot_pd(sign, c), m);
        };
        const __m128d max_zt = abs_max(z0, z1, z2), max_pz = abs_max(pz[0], pz[1], pz[2]);
        const __m128d max_xt = abs_max(x[0], x[1], x[2]), max_yt = abs_max(y[0], y[1], y[2]);
        const __m128d max_e = abs_max(e0, e1, e2);
        const __m128d delta_z = _mm_mul_pd(_mm_set1_pd(gamma(3)), max_zt);
        const __m128d delta_x = _mm_mul_pd(_mm_set1_pd(gamma(5)), _mm_add_pd(max_xt, max_pz));
        const __m128d delta_y = _mm_mul_pd(_mm_set1_pd(gamma(5)), _mm_add_pd(max_yt, max_pz));
        const __m128d delta_e = _mm_mul_pd(
            _mm_set1_pd(2.0),
            _mm_add_pd(_mm_add_pd(opaque(_mm_mul_pd(_mm_mul_pd(_mm_set1_pd(gamma(2)), max_xt), max_yt)),
                                  opaque(_mm_mul_pd(delta_y, max_xt))),
                       opaque(_mm_mul_pd(delta_x, max_yt))));
        const __m128d bound = _mm_mul_pd(
            _mm_set1_pd(3.0),
            _mm_add_pd(_mm_add_pd(opaque(_mm_mul_pd(_mm_mul_pd(_mm_set1_pd(gamma(3)), max_e), max_zt)),
                                  opaque(_mm_mul_pd(delta_e, max_zt))),
                       opaque(_mm_mul_pd(delta_z, max_e))));
        const __m128d t_error = _mm_div_pd(bound, _mm_andnot_pd(sign, det));
        _mm_store_pd(out.t, t);
        _mm_store_pd(out.det, det);
        _mm_store_pd(out.e1, e1);
        _mm_store_pd(out.e2, e2);
        // det != 0, t > 0 and not t <= δt, each as the scalar code compares (NaN included).
        const __m128d hit = _mm_and_pd(_mm_and_pd(_mm_cmpneq_pd(det, zero), _mm_cmpgt_pd(t, zero)),
                                       _mm_cmpnle_pd(t, t_error));
        return static_cast<uint32_t>(_mm_movemask_pd(hit));
    }
    // Lane l as triangle_edges leaves it before finish_edges.
    void lane(int l, TriangleEdges& q) const {
        const auto at = [l](__m128d v) { return _mm_cvtsd_f64(l == 0 ? v : _mm_unpackhi_pd(v, v)); };
        q.p0z = at(pz[0]), q.p1z = at(pz[1]), q.p2z = at(pz[2]);
        q.x0 = at(x[0]), q.y0 = at(y[0]), q.x1 = at(x[1]), q.y1 = at(y[1]), q.x2 = at(x[2]), q.y2 = at(y[2]);
        q.e0 = at(e0), q.e1 = at(e1), q.e2 = at(e2);
    }
};
#endif

#if defined(WSD_AVX_DISPATCH)
// EdgesPair for four pairs at once, for CPUs with AVX: only functions built for AVX call it
// (render/cpu_features.h), and inline it (gnu::flatten: these are not always_inline, so that
// templates built for every x86-64, such as test_leaf_triangles, may name them). The same
// operations and roundings lane by lane, no contraction, so each lane's results are those of
// the scalar code bit for bit.
struct EdgesQuad {
    static constexpr uint32_t kWidth = 4;
    __m256d pz[3], x[3], y[3], e0, e1, e2;

    // opaque() for four lanes: a product stays a rounded product whatever the build's FMA.
    [[gnu::target("avx"), gnu::always_inline]] static __m256d kept(__m256d v) {
        asm("" : "+x"(v));
        return v;
    }
    [[gnu::target("avx")]] void compute(const __m256d (&vx)[3], const __m256d (&vy)[3],
                                        const __m256d (&vz)[3], __m256d ox, __m256d oy, __m256d oz,
                                        __m256d sx, __m256d sy) {
        for (int i = 0; i < 3; ++i) {
            pz[i] = _mm256_sub_pd(vz[i], oz);
            x[i] = _mm256_add_pd(_mm256_sub_pd(vx[i], ox), kept(_mm256_mul_pd(sx, pz[i])));
            y[i] = _mm256_add_pd(_mm256_sub_pd(vy[i], oy), kept(_mm256_mul_pd(sy, pz[i])));
        }
        e0 = _mm256_sub_pd(kept(_mm256_mul_pd(x[1], y[2])), kept(_mm256_mul_pd(y[1], x[2])));
        e1 = _mm256_sub_pd(kept(_mm256_mul_pd(x[2], y[0])), kept(_mm256_mul_pd(y[2], x[0])));
        e2 = _mm256_sub_pd(kept(_mm256_mul_pd(x[0], y[1])), kept(_mm256_mul_pd(y[0], x[1])));
    }
    // Ray r against four triangles, as EdgesPair's. Each vertex is loaded whole (its three
    // floats; a masked load reads nothing past them) and permuted to the ray's axes, and the
    // four vertices of a corner are transposed into lanes. Float to double is exact, so the lanes
    // hold what converting component by component gives.
    [[gnu::target("avx")]] void compute(const float* const (&v)[3][4], const RayPre& r) {
        const __m128i axes = _mm_setr_epi32(r.kx, r.ky, r.kz, 3);
        const __m128i xyz = _mm_setr_epi32(-1, -1, -1, 0);
        __m256d vx[3], vy[3], vz[3];
        for (int i = 0; i < 3; ++i) {
            __m128 p[4];
            for (int l = 0; l < 4; ++l) p[l] = _mm_permutevar_ps(_mm_maskload_ps(v[i][l], xyz), axes);
            const __m128 xy01 = _mm_unpacklo_ps(p[0], p[1]), xy23 = _mm_unpacklo_ps(p[2], p[3]);
            const __m128 z01 = _mm_unpackhi_ps(p[0], p[1]), z23 = _mm_unpackhi_ps(p[2], p[3]);
            vx[i] = _mm256_cvtps_pd(_mm_movelh_ps(xy01, xy23));
            vy[i] = _mm256_cvtps_pd(_mm_movehl_ps(xy23, xy01));
            vz[i] = _mm256_cvtps_pd(_mm_movelh_ps(z01, z23));
        }
        compute(vx, vy, vz, _mm256_set1_pd(r.ox), _mm256_set1_pd(r.oy), _mm256_set1_pd(r.oz),
                _mm256_set1_pd(r.sx), _mm256_set1_pd(r.sy));
    }
    // Four rays against one triangle, as EdgesPair's (the arrays 32-byte aligned).
    struct Triangle {
        __m256d vx[3], vy[3], vz[3];
        [[gnu::target("avx")]] void set(const float* const (&v)[3], const int (&k)[3]) {
            for (int i = 0; i < 3; ++i) {
                vx[i] = _mm256_set1_pd(static_cast<double>(v[i][k[0]]));
                vy[i] = _mm256_set1_pd(static_cast<double>(v[i][k[1]]));
                vz[i] = _mm256_set1_pd(static_cast<double>(v[i][k[2]]));
            }
        }
    };
    [[gnu::target("avx")]] void compute(const Triangle& t, const double* ox, const double* oy,
                                        const double* oz, const double* sx, const double* sy) {
        compute(t.vx, t.vy, t.vz, _mm256_load_pd(ox), _mm256_load_pd(oy), _mm256_load_pd(oz),
                _mm256_load_pd(sx), _mm256_load_pd(sy));
    }
    // EdgesPair::ruled_out, bit l for lane l.
    [[gnu::target("avx")]] uint32_t ruled_out() const {
        const __m256d zero = _mm256_setzero_pd();
        const __m256d zeros = _mm256_or_pd(
            _mm256_or_pd(_mm256_cmp_pd(e0, zero, _CMP_EQ_OQ), _mm256_cmp_pd(e1, zero, _CMP_EQ_OQ)),
            _mm256_cmp_pd(e2, zero, _CMP_EQ_OQ));
        const __m256d neg = _mm256_or_pd(
            _mm256_or_pd(_mm256_cmp_pd(e0, zero, _CMP_LT_OQ), _mm256_cmp_pd(e1, zero, _CMP_LT_OQ)),
            _mm256_cmp_pd(e2, zero, _CMP_LT_OQ));
        const __m256d pos = _mm256_or_pd(
            _mm256_or_pd(_mm256_cmp_pd(e0, zero, _CMP_GT_OQ), _mm256_cmp_pd(e1, zero, _CMP_GT_OQ)),
            _mm256_cmp_pd(e2, zero, _CMP_GT_OQ));
        return static_cast<uint32_t>(_mm256_movemask_pd(_mm256_andnot_pd(zeros, _mm256_and_pd(neg, pos))));
    }
    // EdgesPair::zero_lanes, bit l for lane l.
    [[gnu::target("avx")]] uint32_t zero_lanes() const {
        const __m256d zero = _mm256_setzero_pd();
        return static_cast<uint32_t>(_mm256_movemask_pd(_mm256_or_pd(
            _mm256_or_pd(_mm256_cmp_pd(e0, zero, _CMP_EQ_OQ), _mm256_cmp_pd(e1, zero, _CMP_EQ_OQ)),
            _mm256_cmp_pd(e2, zero, _CMP_EQ_OQ))));
    }
    // |a|, |b|, |c| as std::max({a, b, c}) orders them (EdgesPair::finish).
    [[gnu::target("avx"), gnu::always_inline]] static __m256d abs_max(__m256d a, __m256d b, __m256d c) {
        const __m256d sign = _mm256_set1_pd(-0.0);
        const __m256d m = _mm256_max_pd(_mm256_andnot_pd(sign, b), _mm256_andnot_pd(sign, a));
        return _mm256_max_pd(_mm256_andnot_pd(sign, c), m);
    }
    // EdgesPair::finish for four lanes.
    [[gnu::target("avx")]] uint32_t finish(const double* sz, LaneHits& out) const {
        const __m256d s = _mm256_loadu_pd(sz), zero = _mm256_setzero_pd();
        const __m256d det = _mm256_add_pd(_mm256_add_pd(e0, e1), e2);
        const __m256d z0 = _mm256_mul_pd(s, pz[0]), z1 = _mm256_mul_pd(s, pz[1]),
                      z2 = _mm256_mul_pd(s, pz[2]);
        const __m256d t = _mm256_div_pd(
            _mm256_add_pd(_mm256_add_pd(kept(_mm256_mul_pd(e0, z0)), kept(_mm256_mul_pd(e1, z1))),
                          kept(_mm256_mul_pd(e2, z2))),
            det);
        const __m256d max_zt = abs_max(z0, z1, z2), max_pz = abs_max(pz[0], pz[1], pz[2]);
        const __m256d max_xt = abs_max(x[0], x[1], x[2]), max_yt = abs_max(y[0], y[1], y[2]);
        const __m256d max_e = abs_max(e0, e1, e2);
        const __m256d delta_z = _mm256_mul_pd(_mm256_set1_pd(gamma(3)), max_zt);
        const __m256d delta_x = _mm256_mul_pd(_mm256_set1_pd(gamma(5)), _mm256_add_pd(max_xt, max_pz));
        const __m256d delta_y = _mm256_mul_pd(_mm256_set1_pd(gamma(5)), _mm256_add_pd(max_yt, max_pz));
        const __m256d delta_e = _mm256_mul_pd(
            _mm256_set1_pd(2.0),
            _mm256_add_pd(
                _mm256_add_pd(kept(_mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(gamma(2)), max_xt), max_yt)),
                              kept(_mm256_mul_pd(delta_y, max_xt))),
                kept(_mm256_mul_pd(delta_x, max_yt))));
        const __m256d bound = _mm256_mul_pd(
            _mm256_set1_pd(3.0),
            _mm256_add_pd(
                _mm256_add_pd(kept(_mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(gamma(3)), max_e), max_zt)),
                              kept(_mm256_mul_pd(delta_e, max_zt))),
                kept(_mm256_mul_pd(delta_z, max_e))));
        const __m256d t_error = _mm256_div_pd(bound, _mm256_andnot_pd(_mm256_set1_pd(-0.0), det));
        _mm256_store_pd(out.t, t);
        _mm256_store_pd(out.det, det);
        _mm256_store_pd(out.e1, e1);
        _mm256_store_pd(out.e2, e2);
        const __m256d hit = _mm256_and_pd(
            _mm256_and_pd(_mm256_cmp_pd(det, zero, _CMP_NEQ_UQ), _mm256_cmp_pd(t, zero, _CMP_GT_OQ)),
            _mm256_cmp_pd(t, t_error, _CMP_NLE_UQ));
        return static_cast<uint32_t>(_mm256_movemask_pd(hit));
    }
    // Lane l as triangle_edges leaves it before finish_edges.
    [[gnu::target("avx")]] void lane(int l, TriangleEdges& q) const {
        alignas(32) double v[12][4];
        const __m256d all[12] = {pz[0], pz[1], pz[2], x[0], y[0], x[1], y[1], x[2], y[2], e0, e1, e2};
        for (int i = 0; i < 12; ++i) _mm256_store_pd(v[i], all[i]);
        q.p0z = v[0][l], q.p1z = v[1][l], q.p2z = v[2][l];
        q.x0 = v[3][l], q.y0 = v[4][l], q.x1 = v[5][l], q.y1 = v[6][l], q.x2 = v[7][l], q.y2 = v[8][l];
        q.e0 = v[9][l], q.e1 = v[10][l], q.e2 = v[11][l];
    }
};

// EdgesQuad for eight pairs at once, for CPUs with AVX-512 (avx512_packets() in
// render/cpu_features.h): four rays against one triangle become eight, for packets. The same
// operations and roundings lane by lane, no contraction: each lane's results are the scalar
// code's bit for bit. Comparisons give masks directly.
struct EdgesOct {
    static constexpr uint32_t kWidth = 8;
    __m512d pz[3], x[3], y[3], e0, e1, e2;

    [[gnu::target("avx512f"), gnu::always_inline]] static __m512d kept(__m512d v) {
        asm("" : "+v"(v));
        return v;
    }
    [[gnu::target("avx512f")]] void compute(const __m512d (&vx)[3], const __m512d (&vy)[3],
                                            const __m512d (&vz)[3], __m512d ox, __m512d oy, __m512d oz,
                                            __m512d sx, __m512d sy) {
        for (int i = 0; i < 3; ++i) {
            pz[i] = _mm512_sub_pd(vz[i], oz);
            x[i] = _mm512_add_pd(_mm512_sub_pd(vx[i], ox), kept(_mm512_mul_pd(sx, pz[i])));
            y[i] = _mm512_add_pd(_mm512_sub_pd(vy[i], oy), kept(_mm512_mul_pd(sy, pz[i])));
        }
        e0 = _mm512_sub_pd(kept(_mm512_mul_pd(x[1], y[2])), kept(_mm512_mul_pd(y[1], x[2])));
        e1 = _mm512_sub_pd(kept(_mm512_mul_pd(x[2], y[0])), kept(_mm512_mul_pd(y[2], x[0])));
        e2 = _mm512_sub_pd(kept(_mm512_mul_pd(x[0], y[1])), kept(_mm512_mul_pd(y[0], x[1])));
    }
    // Eight rays against one triangle, as EdgesPair's (the arrays need no alignment).
    struct Triangle {
        __m512d vx[3], vy[3], vz[3];
        [[gnu::target("avx512f")]] void set(const float* const (&v)[3], const int (&k)[3]) {
            for (int i = 0; i < 3; ++i) {
                vx[i] = _mm512_set1_pd(static_cast<double>(v[i][k[0]]));
                vy[i] = _mm512_set1_pd(static_cast<double>(v[i][k[1]]));
                vz[i] = _mm512_set1_pd(static_cast<double>(v[i][k[2]]));
            }
        }
    };
    [[gnu::target("avx512f")]] void compute(const Triangle& t, const double* ox, const double* oy,
                                            const double* oz, const double* sx, const double* sy) {
        compute(t.vx, t.vy, t.vz, _mm512_loadu_pd(ox), _mm512_loadu_pd(oy), _mm512_loadu_pd(oz),
                _mm512_loadu_pd(sx), _mm512_loadu_pd(sy));
    }
    // EdgesPair::ruled_out, bit l for lane l.
    [[gnu::target("avx512f")]] uint32_t ruled_out() const {
        const __m512d zero = _mm512_setzero_pd();
        const __mmask8 zeros = _mm512_cmp_pd_mask(e0, zero, _CMP_EQ_OQ) |
                               _mm512_cmp_pd_mask(e1, zero, _CMP_EQ_OQ) |
                               _mm512_cmp_pd_mask(e2, zero, _CMP_EQ_OQ);
        const __mmask8 neg = _mm512_cmp_pd_mask(e0, zero, _CMP_LT_OQ) |
                             _mm512_cmp_pd_mask(e1, zero, _CMP_LT_OQ) |
                             _mm512_cmp_pd_mask(e2, zero, _CMP_LT_OQ);
        const __mmask8 pos = _mm512_cmp_pd_mask(e0, zero, _CMP_GT_OQ) |
                             _mm512_cmp_pd_mask(e1, zero, _CMP_GT_OQ) |
                             _mm512_cmp_pd_mask(e2, zero, _CMP_GT_OQ);
        return static_cast<uint32_t>(~zeros & neg & pos & 0xffu);
    }
    // EdgesPair::zero_lanes, bit l for lane l.
    [[gnu::target("avx512f")]] uint32_t zero_lanes() const {
        const __m512d zero = _mm512_setzero_pd();
        return static_cast<uint32_t>(_mm512_cmp_pd_mask(e0, zero, _CMP_EQ_OQ) |
                                     _mm512_cmp_pd_mask(e1, zero, _CMP_EQ_OQ) |
                                     _mm512_cmp_pd_mask(e2, zero, _CMP_EQ_OQ));
    }
    // _mm512_max_pd(a, b), the same instruction: GCC 12's header fills an unused operand with an
    // uninitialized value and warns about it, so every lane is taken through the mask instead.
    [[gnu::target("avx512f"), gnu::always_inline]] static __m512d max(__m512d a, __m512d b) {
        return _mm512_mask_max_pd(a, 0xff, a, b);
    }
    // |a|, |b|, |c| as std::max({a, b, c}) orders them (EdgesPair::finish).
    [[gnu::target("avx512f"), gnu::always_inline]] static __m512d abs_max(__m512d a, __m512d b, __m512d c) {
        const __m512d m = max(_mm512_abs_pd(b), _mm512_abs_pd(a));
        return max(_mm512_abs_pd(c), m);
    }
    // EdgesPair::finish for eight lanes.
    [[gnu::target("avx512f")]] uint32_t finish(const double* sz, LaneHits& out) const {
        const __m512d s = _mm512_loadu_pd(sz), zero = _mm512_setzero_pd();
        const __m512d det = _mm512_add_pd(_mm512_add_pd(e0, e1), e2);
        const __m512d z0 = _mm512_mul_pd(s, pz[0]), z1 = _mm512_mul_pd(s, pz[1]),
                      z2 = _mm512_mul_pd(s, pz[2]);
        const __m512d t = _mm512_div_pd(
            _mm512_add_pd(_mm512_add_pd(kept(_mm512_mul_pd(e0, z0)), kept(_mm512_mul_pd(e1, z1))),
                          kept(_mm512_mul_pd(e2, z2))),
            det);
        const __m512d max_zt = abs_max(z0, z1, z2), max_pz = abs_max(pz[0], pz[1], pz[2]);
        const __m512d max_xt = abs_max(x[0], x[1], x[2]), max_yt = abs_max(y[0], y[1], y[2]);
        const __m512d max_e = abs_max(e0, e1, e2);
        const __m512d delta_z = _mm512_mul_pd(_mm512_set1_pd(gamma(3)), max_zt);
        const __m512d delta_x = _mm512_mul_pd(_mm512_set1_pd(gamma(5)), _mm512_add_pd(max_xt, max_pz));
        const __m512d delta_y = _mm512_mul_pd(_mm512_set1_pd(gamma(5)), _mm512_add_pd(max_yt, max_pz));
        const __m512d delta_e = _mm512_mul_pd(
            _mm512_set1_pd(2.0),
            _mm512_add_pd(
                _mm512_add_pd(kept(_mm512_mul_pd(_mm512_mul_pd(_mm512_set1_pd(gamma(2)), max_xt), max_yt)),
                              kept(_mm512_mul_pd(delta_y, max_xt))),
                kept(_mm512_mul_pd(delta_x, max_yt))));
        const __m512d bound = _mm512_mul_pd(
            _mm512_set1_pd(3.0),
            _mm512_add_pd(
                _mm512_add_pd(kept(_mm512_mul_pd(_mm512_mul_pd(_mm512_set1_pd(gamma(3)), max_e), max_zt)),
                              kept(_mm512_mul_pd(delta_e, max_zt))),
                kept(_mm512_mul_pd(delta_z, max_e))));
        const __m512d t_error = _mm512_div_pd(bound, _mm512_abs_pd(det));
        _mm512_store_pd(out.t, t);
        _mm512_store_pd(out.det, det);
        _mm512_store_pd(out.e1, e1);
        _mm512_store_pd(out.e2, e2);
        const __mmask8 hit = _mm512_cmp_pd_mask(det, zero, _CMP_NEQ_UQ) &
                             _mm512_cmp_pd_mask(t, zero, _CMP_GT_OQ) &
                             _mm512_cmp_pd_mask(t, t_error, _CMP_NLE_UQ);
        return static_cast<uint32_t>(hit);
    }
    // Lane l as triangle_edges leaves it before finish_edges.
    [[gnu::target("avx512f")]] void lane(int l, TriangleEdges& q) const {
        alignas(64) double v[12][8];
        const __m512d all[12] = {pz[0], pz[1], pz[2], x[0], y[0], x[1], y[1], x[2], y[2], e0, e1, e2};
        for (int i = 0; i < 12; ++i) _mm512_store_pd(v[i], all[i]);
        q.p0z = v[0][l], q.p1z = v[1][l], q.p2z = v[2][l];
        q.x0 = v[3][l], q.y0 = v[4][l], q.x1 = v[5][l], q.y1 = v[6][l], q.x2 = v[7][l], q.y2 = v[8][l];
        q.e0 = v[9][l], q.e1 = v[10][l], q.e2 = v[11][l];
    }
};
#endif

}  // namespace wsd::render
