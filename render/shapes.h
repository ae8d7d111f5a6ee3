// Primitive storage and ray/primitive intersection: watertight triangles (Woop–Benthin–Wald in
// double with antisymmetric edge functions), spheres (Haines discriminant, stable roots), boxes
// (object-space slabs) and planes. Each test rejects the root at the ray origin by an error bound
// instead of an epsilon, so spawned rays never re-hit their own surface (robustness.md: offset origins).
#pragma once

#include <cstdint>
#include <glm/gtc/type_ptr.hpp>
#include <utility>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "render/aabb.h"
#include "render/geometry.h"
#include "render/transform.h"

namespace wsd::render {

// A ray with everything the primitive tests precompute once.
struct RayPre {
    Vec3 o, d;
    // Woop: the axis of largest |d| becomes z; x and y are sheared onto the ray.
    int kx = 0, ky = 1, kz = 2;
    double ox = 0, oy = 0, oz = 0;  // o[kx], o[ky], o[kz]
    double sx = 0, sy = 0, sz = 1;
    double a = 1, inv_a = 1;  // d·d, for spheres
    RayBoxTest box;

    // with_box: also the slab-test constants (only BVH traversal needs them).
    explicit RayPre(const Ray& r, bool with_box = true) { init(r, with_box); }
    RayPre() = default;
    void init(const Ray& r, bool with_box);
};

inline void RayPre::init(const Ray& r, bool with_box) {
    o = r.o;
    d = r.d;
    // Components through a pointer: glm's operator[] is a switch on the index.
    const double* op = glm::value_ptr(o);
    const double* dp = glm::value_ptr(d);
    const double ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
    kz = ax >= ay ? (ax >= az ? 0 : 2) : (ay >= az ? 1 : 2);
    kx = kz == 2 ? 0 : kz + 1;
    ky = kx == 2 ? 0 : kx + 1;
    if (dp[kz] < 0) std::swap(kx, ky);  // keep the winding, so e > 0 means the same side
    ox = op[kx], oy = op[ky], oz = op[kz];
    a = glm::dot(d, d);
    const double dx = dp[kx], dy = dp[ky], dz = dp[kz];
#if defined(__SSE2__)
    // The same IEEE divisions, two at a time.
    const __m128d q = _mm_div_pd(_mm_set_pd(-dy, -dx), _mm_set1_pd(dz));
    const __m128d rcp = _mm_div_pd(_mm_set1_pd(1.0), _mm_set_pd(a, dz));
    sx = _mm_cvtsd_f64(q);
    sy = _mm_cvtsd_f64(_mm_unpackhi_pd(q, q));
    sz = _mm_cvtsd_f64(rcp);
    inv_a = _mm_cvtsd_f64(_mm_unpackhi_pd(rcp, rcp));
#else
    sx = -dx / dz;
    sy = -dy / dz;
    sz = 1.0 / dz;
    inv_a = 1.0 / a;
#endif
    if (with_box) box.init(o, d);
}

// Triangle: indices into the world vertex pool and the canonical primitive id.
struct TriPrim {
    uint32_t v[3];
    uint32_t prim;
};

inline constexpr uint32_t kNoTransform = 0xffffffffu;

// Sphere: world centre and radius when `xform` is kNoTransform, else in the object frame of
// transform `xform` (a non-similarity: the ray is taken to object space).
struct SpherePrim {
    Vec3 center;
    double radius;
    uint32_t prim;
    uint32_t xform;
};

// Box: an object-space AABB; `band` is the per-axis object-space uncertainty of a world point
// mapped into the box frame that does not depend on the ray (transform residual).
struct BoxPrim {
    Vec3 lo, hi;
    Vec3 band;
    uint32_t prim;
    uint32_t xform;  // kNoTransform: identity
};

// Plane in world space: n·p = c, n unit.
struct PlanePrim {
    Vec3 n;
    double c;
    uint32_t prim;
    uint32_t transmissive;
};

// The watertight test's common part (Woop–Benthin–Wald): the triangle in the ray's sheared
// frame, its edge functions with exact signs, and the determinant. False when the ray's line
// misses the triangle; t() and t_error() are its line parameter and that parameter's error bound.
struct TriangleEdges {
    double p0z, p1z, p2z;  // translated, before the shear of z
    double x0, y0, x1, y1, x2, y2;
    double e0, e1, e2, det;
    double z0, z1, z2;

    // Products are kept rounded (opaque) here too: a build that contracts them into FMAs then
    // still computes t and δt alike wherever the test is inlined (the walks for each instruction
    // set), so that they find the same hits.
    double t() const { return (opaque(e0 * z0) + opaque(e1 * z1) + opaque(e2 * z2)) / det; }
    // δt: conservative bound on the error of t (pbrt-v4 IntersectTriangle, with the shear error
    // taken from the unsheared z so that unnormalised directions stay covered).
    // EdgesPair::finish and EdgesQuad::finish (render/triangle_lanes.h) repeat t, δt and
    // triangle_hit's comparisons lane by lane, operation for operation: a change here is made
    // there too (the AVX-against-baseline and BVH-against-brute-force tests compare them).
    double t_error() const {
        const double max_zt = std::max({std::abs(z0), std::abs(z1), std::abs(z2)});
        const double max_pz = std::max({std::abs(p0z), std::abs(p1z), std::abs(p2z)});
        const double max_xt = std::max({std::abs(x0), std::abs(x1), std::abs(x2)});
        const double max_yt = std::max({std::abs(y0), std::abs(y1), std::abs(y2)});
        const double delta_z = gamma(3) * max_zt;
        const double delta_x = gamma(5) * (max_xt + max_pz);
        const double delta_y = gamma(5) * (max_yt + max_pz);
        const double delta_e =
            2 * (opaque(gamma(2) * max_xt * max_yt) + opaque(delta_y * max_xt) + opaque(delta_x * max_yt));
        const double max_e = std::max({std::abs(e0), std::abs(e1), std::abs(e2)});
        return 3 * (opaque(gamma(3) * max_e * max_zt) + opaque(delta_e * max_zt) + opaque(delta_z * max_e)) /
               std::abs(det);
    }
};

// The rest of triangle_edges once q's translated vertices and edge functions are in place.
[[gnu::always_inline]] inline bool finish_edges(const RayPre& r, TriangleEdges& q) {
    // An exactly zero value may hide a sign: it is recomputed to about 1 ULP (exact sign).
    // All three first, then one test of their signs: the line misses when they differ, and
    // which way that goes is what a branch cannot predict.
    if ((q.e0 == 0) | (q.e1 == 0) | (q.e2 == 0)) [[unlikely]] {
        if (q.e0 == 0) q.e0 = difference_of_products(q.x1, q.y2, q.y1, q.x2);
        if (q.e1 == 0) q.e1 = difference_of_products(q.x2, q.y0, q.y2, q.x0);
        if (q.e2 == 0) q.e2 = difference_of_products(q.x0, q.y1, q.y0, q.x1);
    }
    if (((q.e0 < 0) | (q.e1 < 0) | (q.e2 < 0)) & ((q.e0 > 0) | (q.e1 > 0) | (q.e2 > 0))) return false;
    q.det = q.e0 + q.e1 + q.e2;
    if (q.det == 0) return false;
    q.z0 = r.sz * q.p0z;
    q.z1 = r.sz * q.p1z;
    q.z2 = r.sz * q.p2z;
    return true;
}

[[gnu::always_inline]] inline bool triangle_edges(const RayPre& r, const Vec3f& v0, const Vec3f& v1,
                                                  const Vec3f& v2, TriangleEdges& q) {
    const int kx = r.kx, ky = r.ky, kz = r.kz;
    // Components through a pointer: glm's operator[] is a switch on the index.
    const float* a0 = glm::value_ptr(v0);
    const float* a1 = glm::value_ptr(v1);
    const float* a2 = glm::value_ptr(v2);
    // Translate (exact float vertices, one double rounding each), permute, shear. Each vertex
    // is transformed by the same expressions in every triangle that shares it.
    q.p0z = static_cast<double>(a0[kz]) - r.oz;
    q.p1z = static_cast<double>(a1[kz]) - r.oz;
    q.p2z = static_cast<double>(a2[kz]) - r.oz;
    q.x0 = (static_cast<double>(a0[kx]) - r.ox) + opaque(r.sx * q.p0z);
    q.y0 = (static_cast<double>(a0[ky]) - r.oy) + opaque(r.sy * q.p0z);
    q.x1 = (static_cast<double>(a1[kx]) - r.ox) + opaque(r.sx * q.p1z);
    q.y1 = (static_cast<double>(a1[ky]) - r.oy) + opaque(r.sy * q.p1z);
    q.x2 = (static_cast<double>(a2[kx]) - r.ox) + opaque(r.sx * q.p2z);
    q.y2 = (static_cast<double>(a2[ky]) - r.oy) + opaque(r.sy * q.p2z);

    // Edge functions; e(p, q) == -e(q, p) bit for bit, so a shared edge splits rays exactly.
    q.e0 = opaque(q.x1 * q.y2) - opaque(q.y1 * q.x2);
    q.e1 = opaque(q.x2 * q.y0) - opaque(q.y2 * q.x0);
    q.e2 = opaque(q.x0 * q.y1) - opaque(q.y0 * q.x1);
    return finish_edges(r, q);
}

// The hit of a ray whose line meets the triangle (triangle_edges true): δt < t < limit.
[[gnu::always_inline]] inline bool triangle_hit(const TriangleEdges& q, double limit, double& t_out,
                                                double& b1_out, double& b2_out) {
    const double t = q.t();
    if (!(t > 0 && t < limit)) return false;
    if (t <= q.t_error()) return false;
    t_out = t;
    b1_out = q.e1 / q.det;
    b2_out = q.e2 / q.det;
    return true;
}

// Watertight ray/triangle test. Returns true for a hit with δt < t < limit (δt bounds the
// rounding error of t, pbrt-v4), with barycentrics b1, b2 of v1 and v2.
[[gnu::always_inline]] inline bool intersect_triangle(const RayPre& r, const Vec3f& v0, const Vec3f& v1,
                                                      const Vec3f& v2, double limit, double& t_out,
                                                      double& b1_out, double& b2_out) {
    TriangleEdges q;
    return triangle_edges(r, v0, v1, v2, q) && triangle_hit(q, limit, t_out, b1_out, b2_out);
}

// Ray/sphere in the frame where the ray is (o, d) and the sphere (c, radius). `o_err` bounds the
// error already in o (zero for world-space spheres). Picks the nearest root in (0, limit) that is
// not the surface the origin lies on.
[[gnu::always_inline]] inline bool intersect_sphere(const Vec3& o, const Vec3& d, double a, double inv_a,
                                                    const Vec3& c, double radius, const Vec3& o_err,
                                                    double limit, double& t_out) {
    Vec3 f = o - c;
    double b = glm::dot(f, d);
    // Haines et al.: the discriminant from the centre-to-closest-point vector, no b² − ac.
    Vec3 l = f - (b * inv_a) * d;
    double r2 = radius * radius;
    double disc = r2 - glm::dot(l, l);
    if (!(disc >= 0)) return false;
    double ff = glm::dot(f, f);
    double cc = ff - r2;
    double q = -(b + std::copysign(std::sqrt(a * disc), b));
    if (q == 0) return false;  // tangent at the origin
    double t_small = cc / q;   // the root that tends to 0 as the origin nears the surface
    double t_big = q * inv_a;

    // |cc| within its rounding error means the origin is on the sphere: that root is the
    // surface the ray starts from, and the other one is valid only beyond its own error.
    double err_o = std::abs(f.x) * o_err.x + std::abs(f.y) * o_err.y + std::abs(f.z) * o_err.z;
    double err_c = gamma(8) * (ff + r2) + 2 * err_o + glm::dot(o_err, o_err);
    if (std::abs(cc) <= err_c) {
        double err_b = gamma(5) * (std::abs(f.x * d.x) + std::abs(f.y * d.y) + std::abs(f.z * d.z)) +
                       o_err.x * std::abs(d.x) + o_err.y * std::abs(d.y) + o_err.z * std::abs(d.z);
        double delta = (2 * err_b + std::sqrt(a * (gamma(10) * (ff + r2) + 2 * err_c))) * inv_a;
        if (t_big > delta && t_big < limit) {
            t_out = t_big;
            return true;
        }
        return false;
    }
    double t0 = std::min(t_small, t_big), t1 = std::max(t_small, t_big);
    if (t0 > 0) {
        if (!(t0 < limit)) return false;
        t_out = t0;
        return true;
    }
    if (t1 > 0 && t1 < limit) {
        t_out = t1;
        return true;
    }
    return false;
}

// Ray/box slabs in the box's frame; o_err bounds the error of o per axis. `face` is
// 2·axis + (1 for the + side). Edges and corners are closed: tFar is widened by 2γ₃ and by what
// the origin's error can move the slab distances.
inline bool intersect_box_local(const Vec3& o, const Vec3& d, const Vec3& lo, const Vec3& hi,
                                const Vec3& o_err, double limit, double& t_out, int& face_out) {
    double tn = -std::numeric_limits<double>::infinity();
    double tf = std::numeric_limits<double>::infinity();
    int fn = -1, ff = -1;
    double slack = 0;  // how far the slab distances may be off because o is
    for (int i = 0; i < 3; ++i) {
        if (d[i] == 0) {
            if (o[i] < lo[i] - o_err[i] || o[i] > hi[i] + o_err[i]) return false;
            continue;
        }
        bool pos = d[i] > 0;
        double t_near = ((pos ? lo[i] : hi[i]) - o[i]) / d[i];
        double t_far = ((pos ? hi[i] : lo[i]) - o[i]) / d[i];
        slack = std::max(slack, o_err[i] / std::abs(d[i]));
        if (t_near > tn) {
            tn = t_near;
            fn = 2 * i + (pos ? 0 : 1);
        }
        if (t_far < tf) {
            tf = t_far;
            ff = 2 * i + (pos ? 1 : 0);
        }
    }
    if (fn < 0 || ff < 0) return false;
    // Edges and corners are closed: a ray through one may see tn a few ULPs past tf.
    if (!(tn <= tf + 2 * gamma(3) * std::abs(tf) + 2 * slack)) return false;
    // A face plane the origin lies on (within its error) is the surface the ray starts from.
    auto on_plane = [&](int face) {
        int axis = face >> 1;
        double plane = (face & 1) ? hi[axis] : lo[axis];
        double gap = std::abs(plane - o[axis]);
        return gap <= o_err[axis] + gamma(2) * gap;
    };
    if (tn > 0 && !on_plane(fn)) {
        if (!(tn < limit)) return false;
        t_out = tn;
        face_out = fn;
        return true;
    }
    if (tf > 0 && tf < limit && !on_plane(ff)) {
        t_out = tf;
        face_out = ff;
        return true;
    }
    return false;
}

inline bool intersect_plane(const Vec3& o, const Vec3& d, const PlanePrim& p, double limit, double& t_out) {
    double no = p.n.x * o.x + p.n.y * o.y + p.n.z * o.z;
    double num = p.c - no;
    double err =
        gamma(4) * (std::abs(p.c) + std::abs(p.n.x * o.x) + std::abs(p.n.y * o.y) + std::abs(p.n.z * o.z));
    if (std::abs(num) <= err) return false;  // the origin lies on the plane
    double den = glm::dot(p.n, d);
    if (den == 0) return false;
    double t = num / den;
    if (!(t > 0 && t < limit)) return false;
    t_out = t;
    return true;
}

// The cube-cross UV of a point on face `face` of the box [lo, hi] (wsd-language.md §4).
Vec2 box_uv(const Vec3& p, const Vec3& lo, const Vec3& hi, int face);
// The sphere map of an outward unit normal in the sphere's own frame; u in [0, 1), v in [0, 1].
Vec2 sphere_uv(const Vec3& n);
// The plane's u axis in its own frame: +x projected onto the plane, +z where that vanishes.
Vec3 plane_u_axis(const Vec3& n);

}  // namespace wsd::render
