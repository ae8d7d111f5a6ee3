// The primitive tests that every traversal shares (closest-hit, any-hit and the shaft-culled
// shadow queries): one encoded entry of Impl::order against a ray, with per-query counters.
// Internal to render/ like geometry_impl.h.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <optional>

#include "render/geometry_impl.h"
#include "render/triangle_lanes.h"

namespace wsd::render::detail {

using Impl = Geometry::Impl;

struct Counters {
    uint64_t boxes = 0, tri_tests = 0, tri_hits = 0, sph_tests = 0, sph_hits = 0, shape_boxes = 0, planes = 0;
    // An any-hit query: primitives made of others (instances) may stop at their first hit.
    bool any_hit = false;
    void flush(RayStats& s) const {
        s.box_tests += boxes;
        s.triangle_tests += tri_tests;
        s.triangle_hits += tri_hits;
        s.sphere_tests += sph_tests;
        s.sphere_hits += sph_hits;
        s.shape_box_tests += shape_boxes;
        s.plane_tests += planes;
    }
};

// The running closest hit. Primitive tests accept t < limit; after a hit the limit becomes the
// next double above it, so that an exact tie can still be resolved by primitive id.
struct Best {
    double limit;
    HitRecord h{std::numeric_limits<double>::infinity(), 0xffffffffu};  // valid when `hit`
    bool hit = false;

    void offer(double t_new, uint32_t prim_new, uint32_t slot_new, double b1_new, double b2_new) {
        if (t_new < h.t || prim_new < h.prim) {
            h = HitRecord{t_new, prim_new, slot_new, b1_new, b2_new};
            hit = true;
            limit = next_float_up(h.t);
        }
    }
    // A hit from test_entry, at entry slot `slot_new`.
    // An instance's entries share its id: a tie between them goes to the lower inner id.
    void offer(const HitRecord& x, uint32_t slot_new) {
        if (x.t < h.t || x.prim < h.prim || (x.prim == h.prim && x.inner_prim < h.inner_prim)) {
            h = x;
            h.slot = slot_new;
            hit = true;
            limit = next_float_up(h.t);
        }
    }

    // The hit as a query returns it, or nullopt.
    std::optional<HitRecord> record() const {
        if (!hit) return std::nullopt;
        return h;
    }
};

inline bool ray_is_valid(const Ray& r, double tmax) {
    return is_finite(r.o) && is_finite(r.d) && (r.d.x != 0 || r.d.y != 0 || r.d.z != 0) && !std::isnan(tmax);
}

// The power of two that brings a direction's largest component into [2^-64, 2^64], or 0 when
// it is there already. Traversal keeps 1/d in floats, which vanish past about 1e38 (every box,
// even an empty one, would then be entered) and overflow below about 1e-38; scaling by a power
// of two is exact, and every test is covariant with it, so the answers do not change.
inline int direction_scale(const Vec3& d) {
    const double m = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
    if (m >= 0x1p-64 && m <= 0x1p64) return 0;
    int e = 0;
    (void)std::frexp(m, &e);
    return -e;
}
inline Ray scaled(const Ray& r, int s) {
    return {r.o, {std::ldexp(r.d.x, s), std::ldexp(r.d.y, s), std::ldexp(r.d.z, s)}};
}

inline Vec3 sphere_origin_error(const Transform& x, const SpherePrim& s, const Vec3& o) {
    Vec3 c = abs3(s.center);
    double m = std::max({c.x, c.y, c.z}) + s.radius;
    return x.inv_point_error(o) + x.resid_lin * m + x.resid_t;
}

// True for an entry of Impl::order that is a triangle.
inline bool is_triangle(uint32_t e) {
    return ((e >> kKindShift) & 3u) == uint32_t(PrimKind::Triangle);
}

// Entry k of Impl::order. With tris_in_order that is tris[k], an opaque triangle (encoded as
// k), and the leaves' triangles are read without a load of order.
[[gnu::always_inline]] inline uint32_t entry_at(const Impl& g, uint32_t k) {
    return g.tris_in_order ? k : g.order[k];
}

// A triangle whose vertices are at hand, counted.
[[gnu::always_inline]] inline bool test_triangle(const RayPre& r, const Vec3f& v0, const Vec3f& v1,
                                                 const Vec3f& v2, double limit, Counters& c, double& t,
                                                 double& b1, double& b2) {
    ++c.tri_tests;
    if (!intersect_triangle(r, v0, v1, v2, limit, t, b1, b2)) return false;
    ++c.tri_hits;
    return true;
}

// Triangle `tri` of g.tris, counted.
[[gnu::always_inline]] inline bool test_stored_triangle(const Impl& g, const RayPre& r, const TriPrim& tri,
                                                        double limit, Counters& c, double& t, double& b1,
                                                        double& b2) {
    return test_triangle(r, g.verts[tri.v[0]], g.verts[tri.v[1]], g.verts[tri.v[2]], limit, c, t, b1, b2);
}

// A sphere; x is its transform (SpherePrim::xform), null for kNoTransform. Counted.
[[gnu::always_inline]] inline bool test_sphere(const SpherePrim& s, const Transform* x, const RayPre& r,
                                               double limit, Counters& c, double& t) {
    ++c.sph_tests;
    bool hit;
    if (x == nullptr) {
        hit = intersect_sphere(r.o, r.d, r.a, r.inv_a, s.center, s.radius, Vec3(0), limit, t);
    } else {
        Vec3 o = x->inv_point(r.o), d = x->inv_vector(r.d);
        double a = glm::dot(d, d);
        hit =
            intersect_sphere(o, d, a, 1.0 / a, s.center, s.radius, sphere_origin_error(*x, s, r.o), limit, t);
    }
    if (!hit) return false;
    ++c.sph_hits;
    return true;
}

// A box; x is its transform (BoxPrim::xform), null for the identity. Counted.
[[gnu::always_inline]] inline bool test_box(const BoxPrim& bx, const Transform* x, const RayPre& r,
                                            double limit, Counters& c, double& t, int& face) {
    ++c.shape_boxes;
    if (x == nullptr) {
        // The identity's own error bound (γ₃|o|, as a transform would give), so that a
        // scene scaled by 2^k decides edge cases exactly as the unscaled one.
        return intersect_box_local(r.o, r.d, bx.lo, bx.hi, gamma(3) * abs3(r.o) + bx.band, limit, t, face);
    }
    return intersect_box_local(x->inv_point(r.o), x->inv_vector(r.d), bx.lo, bx.hi,
                               x->inv_point_error(r.o) + bx.band, limit, t, face);
}

// Defined in render/other_prims.cpp: the one dispatch of PrimKind::Other entries.
bool test_other(const Impl& g, const RayPre& r, uint32_t slot, double limit, Counters& c, HitRecord& h);

// One primitive test; fills h.t, slot-specific parameters, the canonical id and (Other kinds)
// the inner hit on a hit. h.slot is left to the caller.
[[gnu::always_inline]] inline bool test_entry(const Impl& g, const RayPre& r, uint32_t e, double limit,
                                              Counters& c, HitRecord& h) {
    const uint32_t slot = e & kSlotMask;
    switch ((e >> kKindShift) & 3u) {
        case 0: {
            const TriPrim& tri = g.tris[slot];
            if (!test_stored_triangle(g, r, tri, limit, c, h.t, h.b1, h.b2)) return false;
            h.prim = tri.prim;
            return true;
        }
        case 1: {
            const SpherePrim& s = g.spheres[slot];
            if (!test_sphere(s, s.xform == kNoTransform ? nullptr : &g.xforms[s.xform], r, limit, c, h.t))
                return false;
            h.prim = s.prim;
            h.b1 = h.b2 = 0;
            return true;
        }
        case 2: {
            const BoxPrim& bx = g.boxes[slot];
            int face = 0;
            if (!test_box(bx, bx.xform == kNoTransform ? nullptr : &g.xforms[bx.xform], r, limit, c, h.t,
                          face))
                return false;
            h.prim = bx.prim;
            h.b1 = face;
            h.b2 = 0;
            return true;
        }
        default:
            return test_other(g, r, slot, limit, c, h);
    }
}

#if defined(__SSE2__)
// The lanes of e in `lanes` (those its edge functions do not rule out), in lane order, as
// finish_edges and triangle_hit go on for each against limit(l) as it is then: a lane with a zero
// edge function (recomputed) on its own with ray_of(l), the others together (Group::finish,
// sz[l]: lane l's RayPre::sz). hit(l, t, b1, b2) takes lane l's hit and returns true to stop;
// so does this function then.
template <class Group, class RayOf, class Limit, class Hit>
[[gnu::always_inline]] inline bool finish_lanes(const Group& e, uint32_t lanes, const double* sz,
                                                RayOf ray_of, Limit limit, Counters& c, Hit hit) {
    const uint32_t zero = e.zero_lanes();
    LaneHits f;
    const uint32_t hits = (lanes & ~zero) != 0 ? e.finish(sz, f) : 0;
    for (uint32_t l = lanes; l != 0; l &= l - 1) {
        const int lane = std::countr_zero(l);
        double t, b1, b2;
        if (zero >> lane & 1) [[unlikely]] {
            TriangleEdges q;
            e.lane(lane, q);
            if (!finish_edges(ray_of(lane), q) || !triangle_hit(q, limit(lane), t, b1, b2)) continue;
        } else {
            if (!(hits >> lane & 1) || !(f.t[lane] < limit(lane))) continue;
            t = f.t[lane];
            b1 = f.e1[lane] / f.det[lane];
            b2 = f.e2[lane] / f.det[lane];
        }
        ++c.tri_hits;
        if (hit(lane, t, b1, b2)) return true;
    }
    return false;
}

// The triangles tris[first, first + count) of a tree whose leaves hold triangles in order
// (Impl::tris_in_order) against one ray, Group::kWidth at a time (EdgesPair, or EdgesQuad in
// functions built for AVX: the scalar test's operations lane by lane): their edge functions,
// then finish_lanes for those whose line meets the ray, in order, against limit() as it is then.
// hit(k, t, b1, b2) takes a hit of tris[k] and returns true to stop; so does this function then.
// Counted as test_triangle: the triangles of each group.
template <class Group, class Limit, class Hit>
[[gnu::always_inline]] inline bool test_leaf_triangles(const Impl& g, const RayPre& r, uint32_t first,
                                                       uint32_t count, Counters& c, Limit limit, Hit hit) {
    constexpr uint32_t kWidth = Group::kWidth;
    const uint32_t end = first + count;
    const double sz[4] = {r.sz, r.sz, r.sz, r.sz};
    for (uint32_t k = first; k < end; k += kWidth) {
        // Past the last triangle, lanes repeat it; only the first n count.
        const uint32_t n = std::min(end - k, kWidth);
        c.tri_tests += n;
        const float* v[3][kWidth];
        for (uint32_t l = 0; l < kWidth; ++l) {
            const TriPrim& tri = g.tris[k + std::min(l, n - 1)];
            for (int i = 0; i < 3; ++i) v[i][l] = glm::value_ptr(g.verts[tri.v[i]]);
        }
        Group e;
        e.compute(v, r);
        const uint32_t lanes = ((1u << n) - 1) & ~e.ruled_out();
        if (lanes != 0 &&
            finish_lanes(
                e, lanes, sz, [&r](int) -> const RayPre& { return r; }, [&limit](int) { return limit(); }, c,
                [&hit, k](int lane, double t, double b1, double b2) {
                    return hit(k + static_cast<uint32_t>(lane), t, b1, b2);
                }))
            return true;
    }
    return false;
}
#endif

// A hint for the leaf over order[first, ...]: its entries, and the triangles they most likely
// name. Triangles are stored in leaf order (geometry_build.cpp), so the leaf's first triangle is
// tris[first] exactly when every entry before it is a triangle (a mesh) and a few entries off
// otherwise; a wrong guess costs a wasted fetch, never a different answer.
[[gnu::always_inline]] inline void prefetch_leaf_data(const Impl& g, uint32_t first) {
    if (g.tris_in_order) {  // a mesh: the leaf's first triangle is tris[first]
        __builtin_prefetch(g.tris.data() + first);
        return;
    }
    __builtin_prefetch(g.order.data() + first);
    if (!g.tris.empty()) __builtin_prefetch(g.tris.data() + std::min<size_t>(first, g.tris.size() - 1));
}

// The vertices of the triangles of order[first, first + count), fetched all at once before the
// first test: their cache misses then overlap instead of following one another.
[[gnu::always_inline]] inline void prefetch_leaf_vertices(const Impl& g, uint32_t first, uint32_t count) {
    if (count < 2) return;
    for (uint32_t k = first; k < first + count; ++k) {
        const uint32_t e = entry_at(g, k);
        if (!is_triangle(e)) continue;
        const TriPrim& tri = g.tris[e & kSlotMask];
        for (int j = 0; j < 3; ++j) __builtin_prefetch(g.verts.data() + tri.v[j]);
    }
}

// kFilter: 0 every primitive, 1 opaque only, 2 transmissive only.
template <int kFilter>
inline bool passes(uint32_t e) {
    if constexpr (kFilter == 0) {
        return true;
    } else {
        bool trans = (e & kTransmissiveBit) != 0;
        return trans == (kFilter == 2);
    }
}

// Every plane (kept outside the BVH) against the ray, into the running closest hit.
template <int kFilter>
void test_planes(const Impl& g, const Ray& ray, Best& best, Counters& c) {
    for (size_t i = 0; i < g.planes.size(); ++i) {
        const PlanePrim& p = g.planes[i];
        if constexpr (kFilter != 0) {
            if ((p.transmissive != 0) != (kFilter == 2)) continue;
        }
        ++c.planes;
        double t;
        if (intersect_plane(ray.o, ray.d, p, best.limit, t))
            best.offer(t, p.prim, static_cast<uint32_t>(i), 0, 0);
    }
}

}  // namespace wsd::render::detail
