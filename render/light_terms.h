// The unshadowed shading terms of light samples (wsd-language.md §4: max(0, N·L) and
// max(0, R·V)^shininess) and, for area lights, all cells of one light at once: their points and
// terms computed two at a time with SSE2, rounded exactly as the scalar code rounds them, so the
// image does not depend on which path computed a cell. Internal to the integrator.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "render/lights.h"
#include "render/math.h"
#include "render/sampling.h"

namespace wsd::render {

// Per-hit constants of the light loop, hoisted out of the sample loop.
struct Shading {
    Vec3 p, ng, N, V;
    uint32_t prim;  // the primitive the point lies on
    Vec3 ng_v;      // the geometric normal on the viewer's side
    bool opaque;    // no transmission: light from behind the surface cannot reach the viewer's side
    double nv;
    bool diffuse;     // (1 − t)·diffuse > 0
    double specular;  // the material's specular weight
    double shininess;
    Vec3 o_front, o_back;  // spawn origins on the ng side and the opposite side
};

struct Term {
    double nl;  // max(0, N·L)
    double sp;  // max(0, R·V)^shininess (0 without specular)
    bool needed;
};

// The direction-dependent part of a light sample's terms, for to_light = (dx, dy, dz): N·L,
// R·V with R = 2(N·L)N − L (the mirror of L about N), and whether the sample can contribute at
// all. No branch: a loop over many samples vectorises; invalid samples give garbage, not a trap.
struct RawTerm {
    double nl, rv;
    bool ok;
};

[[gnu::always_inline]] inline RawTerm raw_term(const Shading& sh, double dx, double dy, double dz) {
    const double d2 = (dx * dx + dy * dy) + dz * dz;
    // A sample behind an opaque surface is blocked by the surface itself, whatever a bent or
    // interpolated N says (robustness.md, consistent shading normals (b), R35: no light leaks through).
    const double facing = (dx * sh.ng_v.x + dy * sh.ng_v.y) + dz * sh.ng_v.z;
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const bool ok = (d2 > 0.0) & (d2 < kInf) & (!sh.opaque | (facing > 0));
    const double inv = 1.0 / std::sqrt(d2);
    const double lx = dx * inv, ly = dy * inv, lz = dz * inv;
    const double nl = (sh.N.x * lx + sh.N.y * ly) + sh.N.z * lz;
    const double rv = (2.0 * nl) * sh.nv - ((lx * sh.V.x + ly * sh.V.y) + lz * sh.V.z);
    return {nl, rv, ok};
}

// The rest: the specular power and which samples need a shadow ray (those with nothing to
// contribute do not).
inline Term finish_term(const Shading& sh, const RawTerm& r) {
    if (!r.ok) return {0, 0, false};
    double sp = 0;
    if (sh.specular > 0 && r.rv > 0) sp = std::pow(r.rv, sh.shininess);
    const double dl = r.nl > 0 ? r.nl : 0.0;
    return {dl, sp, (sh.diffuse && dl > 0) || sp > 0};
}

// The unshadowed terms for the light sample at sh.p + to_light.
inline Term sample_term(const Shading& sh, const Vec3& to_light) {
    return finish_term(sh, raw_term(sh, to_light.x, to_light.y, to_light.z));
}

// Whether a specular lobe can reach the parallelogram light c + [0, 1]·u + [0, 1]·v: false only
// where max(0, R·V)^shininess is provably 0 at every point of it, so that its cells' specular sum
// is exactly 0 and can be skipped. R·V, with R the mirror of L about N, equals L·M with
// M = 2(N·V)N − V, the mirror of V about N, and L ∝ p − x: the sign of M·(p − x), which is linear
// in p, so it is at most 0 over the parallelogram when it is at its four corners. The corners
// must clear it by δ·|M|·(|q − x| + |c| + |u| + |v|), δ = 10⁻⁹: that covers the rounding of the
// cells' points (within 10⁻¹⁵·(|c| + |u| + |v|) of the parallelogram) and of raw_term's R·V
// (within 10⁻¹⁴ of the exact value), so every cell's computed R·V is ≤ −δ·|M| < 0, not 0 by luck.
inline bool specular_lobe_reaches(const Shading& sh, const Vec3& c, const Vec3& u, const Vec3& v) {
    constexpr double kDelta = 1e-9;
    const Vec3 m = (2.0 * sh.nv) * sh.N - sh.V;
    const double mlen = glm::length(m);
    const double size = glm::length(c) + glm::length(u) + glm::length(v);
    for (const Vec3& q : {c, c + u, c + v, c + u + v}) {
        const Vec3 d = q - sh.p;
        if (!(glm::dot(m, d) <= -kDelta * mlen * (glm::length(d) + size))) return true;
    }
    return false;
}

// The offset of a sample within cell `cell` of an area light (in cell units): the centre on a
// uniform grid, else seeded jitter.
inline Uniform2 cell_offset(const Light& light, uint64_t lkey, uint32_t cell) {
    return light.uniform ? Uniform2{0.5, 0.5} : cell_jitter(lkey, cell);
}

// The cells of one area light seen from one shading point (no allocation after resize()).
class LightCells {
public:
    void resize(size_t most) {
        for (auto* v : {&cell_s_, &cell_t_, &cell_x_, &cell_y_, &cell_z_, &raw_nl_, &raw_rv_, &raw_ok_})
            v->resize(most);
    }

    // Every cell's jittered point and raw terms, in cell order; returns the cell count.
    int prepare(const Shading& sh, const Light& light, uint64_t lkey) {
        int n = 0;
        for (int j = 0; j < light.nv; ++j) {
            for (int i = 0; i < light.nu; ++i, ++n) {
                const Uniform2 xi = cell_offset(light, lkey, uint32_t(n));
                cell_s_[size_t(n)] = double(i) + xi.u;
                cell_t_[size_t(n)] = double(j) + xi.v;
            }
        }
        cell_terms(sh, light, n);
        return n;
    }

    // Cell k's unshadowed terms, after prepare() (sample_term's value for its point).
    Term term(const Shading& sh, int k) const {
        return finish_term(sh, RawTerm{raw_nl_[size_t(k)], raw_rv_[size_t(k)], raw_ok_[size_t(k)] != 0});
    }

    Vec3 point(int k) const { return {cell_x_[size_t(k)], cell_y_[size_t(k)], cell_z_[size_t(k)]}; }

private:
    // The points of n light cells, corner + s·du + t·dv for the cell coordinates (s, t) in
    // cell_s_, cell_t_ (as Light::cell_point computes them), into cell_x_, cell_y_, cell_z_, and
    // their raw_term()s into raw_nl_, raw_rv_, raw_ok_. Two cells at a time with SSE2, which
    // rounds each operation exactly as the scalar code does (the same image either way).
    void cell_terms(const Shading& sh, const Light& light, int n) {
        const double* const cs = cell_s_.data();
        const double* const ct = cell_t_.data();
        double* const px = cell_x_.data();
        double* const py = cell_y_.data();
        double* const pz = cell_z_.data();
        double* const nl = raw_nl_.data();
        double* const rv = raw_rv_.data();
        double* const ok = raw_ok_.data();
        int k = 0;
#if defined(__SSE2__)
        auto splat = [](double x) { return _mm_set1_pd(x); };
        const __m128d c_x = splat(light.corner.x), c_y = splat(light.corner.y), c_z = splat(light.corner.z);
        const __m128d u_x = splat(light.du.x), u_y = splat(light.du.y), u_z = splat(light.du.z);
        const __m128d v_x = splat(light.dv.x), v_y = splat(light.dv.y), v_z = splat(light.dv.z);
        const __m128d p_x = splat(sh.p.x), p_y = splat(sh.p.y), p_z = splat(sh.p.z);
        const __m128d g_x = splat(sh.ng_v.x), g_y = splat(sh.ng_v.y), g_z = splat(sh.ng_v.z);
        const __m128d n_x = splat(sh.N.x), n_y = splat(sh.N.y), n_z = splat(sh.N.z);
        const __m128d w_x = splat(sh.V.x), w_y = splat(sh.V.y), w_z = splat(sh.V.z);
        const __m128d nv = splat(sh.nv), zero = _mm_setzero_pd(), one = splat(1.0), two = splat(2.0),
                      inf = splat(std::numeric_limits<double>::infinity());
        const __m128d not_opaque = sh.opaque ? zero : _mm_castsi128_pd(_mm_set1_epi32(-1));
        auto mul = [](__m128d a, __m128d b) { return _mm_mul_pd(a, b); };
        auto add = [](__m128d a, __m128d b) { return _mm_add_pd(a, b); };
        auto sub = [](__m128d a, __m128d b) { return _mm_sub_pd(a, b); };
        for (; k + 2 <= n; k += 2) {
            const __m128d s = _mm_loadu_pd(cs + k), t = _mm_loadu_pd(ct + k);
            const __m128d x = add(add(c_x, mul(s, u_x)), mul(t, v_x));
            const __m128d y = add(add(c_y, mul(s, u_y)), mul(t, v_y));
            const __m128d z = add(add(c_z, mul(s, u_z)), mul(t, v_z));
            _mm_storeu_pd(px + k, x);
            _mm_storeu_pd(py + k, y);
            _mm_storeu_pd(pz + k, z);
            const __m128d dx = sub(x, p_x), dy = sub(y, p_y), dz = sub(z, p_z);
            const __m128d d2 = add(add(mul(dx, dx), mul(dy, dy)), mul(dz, dz));
            const __m128d facing = add(add(mul(dx, g_x), mul(dy, g_y)), mul(dz, g_z));
            const __m128d valid = _mm_and_pd(_mm_and_pd(_mm_cmpgt_pd(d2, zero), _mm_cmplt_pd(d2, inf)),
                                             _mm_or_pd(not_opaque, _mm_cmpgt_pd(facing, zero)));
            const __m128d inv = _mm_div_pd(one, _mm_sqrt_pd(d2));
            const __m128d lx = mul(dx, inv), ly = mul(dy, inv), lz = mul(dz, inv);
            const __m128d dn = add(add(mul(n_x, lx), mul(n_y, ly)), mul(n_z, lz));
            const __m128d lv = add(add(mul(lx, w_x), mul(ly, w_y)), mul(lz, w_z));
            _mm_storeu_pd(nl + k, dn);
            _mm_storeu_pd(rv + k, sub(mul(mul(two, dn), nv), lv));
            _mm_storeu_pd(ok + k, _mm_and_pd(valid, one));
        }
#endif
        for (; k < n; ++k) {
            const Vec3 P = light.corner + cs[k] * light.du + ct[k] * light.dv;
            px[k] = P.x, py[k] = P.y, pz[k] = P.z;
            const RawTerm r = raw_term(sh, P.x - sh.p.x, P.y - sh.p.y, P.z - sh.p.z);
            nl[k] = r.nl;
            rv[k] = r.rv;
            ok[k] = r.ok ? 1.0 : 0.0;
        }
    }

    // Every cell gets its own shadow ray (the hot loop: no allocation, no virtual call). First
    // every cell's point and unshadowed terms: independent of each other, so they vectorise and
    // their square roots and divisions overlap. Then the shadow rays, summed in cell order.

    std::vector<double> cell_s_, cell_t_;           // cell coordinates (s, t) in cell units
    std::vector<double> cell_x_, cell_y_, cell_z_;  // the cells' points
    std::vector<double> raw_nl_, raw_rv_, raw_ok_;  // their raw_term()s
};

}  // namespace wsd::render
