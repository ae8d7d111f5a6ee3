// Geometry queries: closest-hit and any-hit traversal (BVH, or brute force over every primitive),
// the surface data of a hit, and error-bounded spawn origins (pbrt-v4 OffsetRayOrigin). Ties in
// t resolve to the lowest canonical primitive id, so BVH and brute force agree bit for bit.
#include <algorithm>
#include <cmath>
#include <thread>

#include "render/geometry_impl.h"
#include "render/prim_test.h"
#include "render/traverse.h"

namespace wsd::render {

uint32_t Geometry::Impl::shape_of(uint32_t prim) const {
    auto it = std::upper_bound(shape_first.begin(), shape_first.end(), prim);
    return static_cast<uint32_t>(it - shape_first.begin()) - 1;
}

namespace {

using namespace detail;

// The primitives of order[first, first + count) that pass the filter, into the running closest hit.
// Called, not inlined, from the walk: with the primitive tests inlined into its loop, the loop
// spills registers and closest hits were measured slower.
template <int kFilter>
[[gnu::noinline]] void closest_in(const Impl& g, const RayPre& r, uint32_t first, uint32_t count, Best& best,
                                  Counters& c) {
    prefetch_leaf_vertices(g, first, count);
#if defined(__SSE2__)
    if (kFilter != 2 && g.tris_in_order) {
        test_leaf_triangles<EdgesPair>(
            g, r, first, count, c, [&] { return best.limit; },
            [&](uint32_t k, double t, double b1, double b2) {
                best.offer(t, g.tris[k].prim, k, b1, b2);
                return false;
            });
        return;
    }
#endif
    for (uint32_t k = first; k < first + count; ++k) {
        const uint32_t e = entry_at(g, k);
        if (!passes<kFilter>(e)) continue;
        const uint32_t slot = e & kSlotMask;
        // Triangles straight into the running hit, without a HitRecord to fill and compare.
        if (is_triangle(e)) [[likely]] {
            const TriPrim& tri = g.tris[slot];
            double t, b1, b2;
            if (test_stored_triangle(g, r, tri, best.limit, c, t, b1, b2))
                best.offer(t, tri.prim, slot, b1, b2);
            continue;
        }
        HitRecord h;
        if (test_entry(g, r, e, best.limit, c, h)) best.offer(h, slot);
    }
}

#if defined(WSD_AVX_DISPATCH)
// closest_in for the walk built for AVX, on a mesh's triangles (kFilter != 2, tris_in_order):
// four at a time. No prefetch of their vertices (prefetch_leaf_vertices): with the four tested
// at once, camera and shadow rays went faster without it.
[[gnu::noinline, gnu::target("avx"), gnu::flatten]] void closest_in_avx(const Impl& g, const RayPre& r,
                                                                        uint32_t first, uint32_t count,
                                                                        Best& best, Counters& c) {
    test_leaf_triangles<EdgesQuad>(
        g, r, first, count, c, [&] { return best.limit; },
        [&](uint32_t k, double t, double b1, double b2) {
            best.offer(t, g.tris[k].prim, k, b1, b2);
            return false;
        });
}
#endif

// True when one of the primitives of order[first, first + count) that pass the filter is hit.
template <int kFilter>
[[gnu::noinline]] bool any_in(const Impl& g, const RayPre& r, uint32_t first, uint32_t count, double tmax,
                              Counters& c) {
    prefetch_leaf_vertices(g, first, count);
#if defined(__SSE2__)
    if (kFilter != 2 && g.tris_in_order)
        return test_leaf_triangles<EdgesPair>(
            g, r, first, count, c, [tmax] { return tmax; },
            [](uint32_t, double, double, double) { return true; });
#endif
    for (uint32_t k = first; k < first + count; ++k) {
        const uint32_t e = entry_at(g, k);
        if (!passes<kFilter>(e)) continue;
        if (is_triangle(e)) [[likely]] {
            double t, b1, b2;
            if (test_stored_triangle(g, r, g.tris[e & kSlotMask], tmax, c, t, b1, b2)) return true;
            continue;
        }
        HitRecord h;
        if (test_entry(g, r, e, tmax, c, h)) return true;
    }
    return false;
}

#if defined(WSD_AVX_DISPATCH)
// any_in for the walk built for AVX, as closest_in_avx.
[[gnu::noinline, gnu::target("avx"), gnu::flatten]] bool any_in_avx(const Impl& g, const RayPre& r,
                                                                    uint32_t first, uint32_t count,
                                                                    double tmax, Counters& c) {
    return test_leaf_triangles<EdgesQuad>(
        g, r, first, count, c, [tmax] { return tmax; },
        [](uint32_t, double, double, double) { return true; });
}
#endif

// The BVH walk of a closest-hit query: nearest child first, waiting children pruned by the
// running hit's distance (in floats, rounded up).
template <int kFilter>
struct ClosestHit : OneRayTest {
    static constexpr WalkOrder kOrder = WalkOrder::NearestFirst;
    using Child = BvhChild;
    const Impl& g;
    const RayPre& r;
    Best& best;
    Counters& c;

    bool leaf(const Child& e) {
        const double before = best.limit;
        closest_in<kFilter>(g, r, e.first(), e.count(), best, c);
        if (best.limit != before) limit = to_float_up(best.limit);  // a hit: rarely
        return false;
    }
#if defined(WSD_AVX_DISPATCH)
    [[gnu::target("avx")]] bool leaf_avx(const Child& e) {
        if (kFilter == 2 || !g.tris_in_order) return leaf(e);
        const double before = best.limit;
        closest_in_avx(g, r, e.first(), e.count(), best, c);
        if (best.limit != before) limit = to_float_up(best.limit);
        return false;
    }
#endif
    bool open(float t) const {
        return t <= limit * RayBoxTest::kWiden;
    }
    void prefetch_leaf(uint32_t first) const {
        prefetch_leaf_data(g, first);
    }
};

// The walk of an any-hit query: depth first, ended by the first hit.
template <int kFilter>
struct AnyHit : OneRayTest {
    static constexpr WalkOrder kOrder = WalkOrder::DepthFirst;
    using Child = BvhChild;
    const Impl& g;
    const RayPre& r;
    double tmax;
    Counters& c;

    bool leaf(const Child& e) { return any_in<kFilter>(g, r, e.first(), e.count(), tmax, c); }
#if defined(WSD_AVX_DISPATCH)
    [[gnu::target("avx")]] bool leaf_avx(const Child& e) {
        if (kFilter == 2 || !g.tris_in_order) return leaf(e);
        return any_in_avx(g, r, e.first(), e.count(), tmax, c);
    }
#endif
    void prefetch_leaf(uint32_t first) const {
        prefetch_leaf_data(g, first);
    }
};

template <int kFilter>
void closest_hit(const Impl& g, const RayPre& r, Best& best, Counters& c) {
    if (g.nodes.empty()) {
        closest_in<kFilter>(g, r, 0, static_cast<uint32_t>(g.order.size()), best, c);
        return;
    }
    ClosestHit<kFilter> q{{&r.box, to_float_up(best.limit)}, g, r, best, c};
    uint64_t boxes = 0;  // counted in a register, added to c once
    walk_bvh_chosen(g.nodes.data(), q, boxes);
    c.boxes += boxes;
}

template <int kFilter>
bool any_hit(const Impl& g, const Ray& ray, const RayPre& r, double tmax, Counters& c) {
    for (const PlanePrim& p : g.planes) {
        if constexpr (kFilter != 0) {
            if ((p.transmissive != 0) != (kFilter == 2)) continue;
        }
        ++c.planes;
        double t;
        if (intersect_plane(ray.o, ray.d, p, tmax, t)) return true;
    }
    if (g.nodes.empty()) return any_in<kFilter>(g, r, 0, static_cast<uint32_t>(g.order.size()), tmax, c);
    AnyHit<kFilter> q{{&r.box, to_float_up(tmax)}, g, r, tmax, c};
    uint64_t boxes = 0;
    const bool hit = walk_bvh_chosen(g.nodes.data(), q, boxes);
    c.boxes += boxes;
    return hit;
}

}  // namespace

Geometry::Geometry(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Geometry::~Geometry() = default;

std::optional<HitRecord> Geometry::intersect(const Ray& ray, double tmax, RayStats& stats,
                                             RayFilter filter) const {
    if (!ray_is_valid(ray, tmax)) {
        ++stats.rejected_rays;
        return std::nullopt;
    }
    if (!(tmax > 0)) return std::nullopt;
    if (const int s = direction_scale(ray.d); s != 0) {
        auto hit = intersect(scaled(ray, s), std::ldexp(tmax, -s), stats, filter);
        if (hit) hit->t = std::ldexp(hit->t, s);
        return hit;
    }
    const Impl& g = *impl_;
    if (!g.has_transmissive) {
        if (filter == RayFilter::TransmissiveOnly) return std::nullopt;
        filter = RayFilter::All;
    }
    Best best{tmax};
    Counters c;
    RayPre r(ray);
    switch (filter) {
        case RayFilter::All:
            test_planes<0>(g, ray, best, c);
            closest_hit<0>(g, r, best, c);
            break;
        case RayFilter::OpaqueOnly:
            test_planes<1>(g, ray, best, c);
            closest_hit<1>(g, r, best, c);
            break;
        case RayFilter::TransmissiveOnly:
            test_planes<2>(g, ray, best, c);
            closest_hit<2>(g, r, best, c);
            break;
    }
    c.flush(stats);
    return best.record();
}

bool Geometry::occluded(const Ray& ray, double tmax, RayStats& stats, RayFilter filter) const {
    if (!ray_is_valid(ray, tmax)) {
        ++stats.rejected_rays;
        return false;
    }
    if (!(tmax > 0)) return false;
    if (const int s = direction_scale(ray.d); s != 0)
        return occluded(scaled(ray, s), std::ldexp(tmax, -s), stats, filter);
    const Impl& g = *impl_;
    if (!g.has_transmissive) {
        if (filter == RayFilter::TransmissiveOnly) return false;
        filter = RayFilter::All;
    }
    Counters c;
    c.any_hit = true;
    RayPre r(ray);
    bool hit = false;
    switch (filter) {
        case RayFilter::All:
            hit = any_hit<0>(g, ray, r, tmax, c);
            break;
        case RayFilter::OpaqueOnly:
            hit = any_hit<1>(g, ray, r, tmax, c);
            break;
        case RayFilter::TransmissiveOnly:
            hit = any_hit<2>(g, ray, r, tmax, c);
            break;
    }
    c.flush(stats);
    return hit;
}

Vec3 Geometry::offset_origin(const SurfaceHit& s, const Vec3& w) {
    double dist = glm::dot(abs3(s.ng), s.p_error);
    Vec3 offset = dist * s.ng;
    if (glm::dot(w, s.ng) < 0) offset = -offset;
    Vec3 po = s.p + offset;
    // Round away from the surface, so that the addition's own rounding cannot pull po back.
    for (int i = 0; i < 3; ++i) {
        if (offset[i] > 0)
            po[i] = next_float_up(po[i]);
        else if (offset[i] < 0)
            po[i] = next_float_down(po[i]);
    }
    return po;
}

size_t geometry_memory_bytes(const Geometry::Impl& g) {
    auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
    size_t n = bytes(g.verts) + bytes(g.tris) + bytes(g.spheres) + bytes(g.boxes) + bytes(g.planes) +
               bytes(g.xforms) + bytes(g.shapes) + bytes(g.shape_first) + bytes(g.tri_extra) +
               bytes(g.plane_extra) + bytes(g.nodes) + bytes(g.order);
    if (!g.others.empty())
        n += bytes(g.others) + bytes(g.quadrics) + bytes(g.csgs) + bytes(g.instances) + bytes(g.prototypes) +
             bytes(g.inherits);
    for (const auto& p : g.prototypes)
        if (p) n += p->memory_bytes();
    return n;
}

// Instances count once each in Impl::primitive_count; their prototypes' primitives are stored once.
size_t Geometry::primitive_count() const {
    const Impl& g = *impl_;
    size_t n = g.primitive_count;
    if (g.instances.empty()) return n;
    n -= instance_count();
    for (const auto& p : g.prototypes)
        if (p && p->geometry) n += p->geometry->primitive_count;
    return n;
}
size_t Geometry::triangle_count() const {
    const Impl& g = *impl_;
    size_t n = g.tris.size();
    for (const auto& p : g.prototypes)
        if (p) n += p->triangles;
    return n;
}
size_t Geometry::instance_count() const {
    const Impl& g = *impl_;
    size_t n = 0;
    for (size_t i = 0; i < g.instances.size(); ++i)
        if (i == 0 || g.instances[i].prim != g.instances[i - 1].prim) ++n;
    return n;
}
size_t Geometry::instanced_primitive_count() const {
    const Impl& g = *impl_;
    size_t n = g.primitive_count - instance_count();
    for (size_t i = 0; i < g.instances.size(); ++i)
        if (i == 0 || g.instances[i].prim != g.instances[i - 1].prim)
            n += g.prototypes[g.instances[i].prototype]->geometry->primitive_count;
    return n;
}
size_t Geometry::instanced_triangle_count() const {
    const Impl& g = *impl_;
    size_t n = g.tris.size();
    for (size_t i = 0; i < g.instances.size(); ++i)
        if (i == 0 || g.instances[i].prim != g.instances[i - 1].prim)
            n += g.prototypes[g.instances[i].prototype]->triangles;
    return n;
}
bool Geometry::has_transmissive() const {
    return impl_->has_transmissive;
}

size_t Geometry::memory_bytes() const {
    return geometry_memory_bytes(*impl_);
}

}  // namespace wsd::render
