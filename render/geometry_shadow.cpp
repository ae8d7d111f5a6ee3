// Shadow queries against the primitives a shaft gathered (shaft.h): one BVH walk per shading
// point and area light collects the few opaque primitives its shadow rays can meet, and each of
// those rays then tests only them.
#include <cmath>
#include <cstdint>
#include <new>
#include <optional>
#include <type_traits>

#include "render/geometry_impl.h"
#include "render/prim_test.h"
#include "render/shaft.h"
#include "render/traverse.h"

namespace wsd::render {

using namespace detail;

namespace {

// The triangle test's per-ray setup (the shear, three divisions), made on first use only: the
// candidates are often all spheres. Raw storage: no zeroing of a struct most rays never use.
class LazyRayPre {
public:
    explicit LazyRayPre(const Ray& ray) : ray_(ray) {}
    const RayPre& get() {
        if (!pre_) pre_ = new (storage_) RayPre(ray_, false);
        return *pre_;
    }

private:
    static_assert(std::is_trivially_destructible_v<RayPre>);
    const Ray& ray_;
    RayPre* pre_ = nullptr;
    alignas(RayPre) unsigned char storage_[sizeof(RayPre)];
};

// Entries of ShaftCandidates that are planes: kind Other with this bit in the slot (the BVH's
// slots stay below kMaxPrimitives), the plane's index below it.
constexpr uint32_t kPlaneSlotBit = 1u << 28;
static_assert(kMaxPrimitives < kPlaneSlotBit);
uint32_t plane_entry(size_t i) {
    return encode_entry(PrimKind::Other, kPlaneSlotBit | static_cast<uint32_t>(i), false);
}
bool is_plane(uint32_t e) {
    return ((e >> kKindShift) & 3u) == uint32_t(PrimKind::Other) && (e & kPlaneSlotBit) != 0;
}

// The origin's side of the plane with normal n, when the shading point lies on it and the
// shadow rays start on the side of `self` (ng_side·ng); 0 when n is not clearly ±ng.
int self_side(const Vec3& n, const ShaftSelf& self) {
    const double d = glm::dot(n, self.ng);
    const double len = glm::length(n);
    if (!(std::abs(d) > 0.5 * len)) return 0;
    return d > 0 ? self.ng_side : -self.ng_side;
}

// True when the primitive lies outside one of the shaft's planes (finer than its leaf's box).
bool outside_shaft(const Geometry::Impl& g, const Shaft& shaft, uint32_t e) {
    const uint32_t slot = e & kSlotMask;
    switch ((e >> kKindShift) & 3u) {
        case 0: {
            const TriPrim& t = g.tris[slot];
            return shaft.outside_triangle(g.verts[t.v[0]], g.verts[t.v[1]], g.verts[t.v[2]]);
        }
        case 1: {
            const SpherePrim& sp = g.spheres[slot];
            return sp.xform == kNoTransform && shaft.outside_ball(sp.center, sp.radius);
        }
        default:
            return false;
    }
}

// True when no shadow ray of the shaft can meet this opaque primitive: it lies outside the
// shaft, or the rays' origin and the whole light lie strictly on one side of its plane.
bool culled(const Geometry::Impl& g, const Shaft& shaft, const ShaftSelf& self, uint32_t e) {
    if (outside_shaft(g, shaft, e)) return true;
    if (((e >> kKindShift) & 3u) != 0) return false;
    const TriPrim& t = g.tris[e & kSlotMask];
    const Vec3f &a = g.verts[t.v[0]], &b = g.verts[t.v[1]], &c = g.verts[t.v[2]];
    const int side = (t.prim == self.prim && self.ng_side != 0)
                         ? self_side(glm::cross(Vec3(b) - Vec3(a), Vec3(c) - Vec3(a)), self)
                         : 0;
    return shaft.clear_of_triangle(a, b, c, side);
}

// Adds an opaque candidate; false when there is no room left.
bool add(ShaftCandidates& out, uint32_t e) {
    if (out.count == ShaftCandidates::kMax) return false;
    out.entries[out.count++] = e;
    return true;
}

// Notes a transmissive primitive that may meet the shaft, listing it while there is room.
void add_transmissive(ShaftCandidates& out, uint32_t e) {
    out.transmissive = true;
    if (out.transmissive_count == ShaftCandidates::kMaxTransmissive)
        out.transmissive_listed = false;
    else
        out.transmissive_entries[out.transmissive_count++] = e;
}

// The shaft's BVH walk: a child is entered unless its box lies outside the shaft; a leaf's
// primitives go to the candidates, and the walk ends when a sphere blocks every ray or the
// candidates overflow. Leaves first, so that a node's primitives are gathered in lane order.
struct ShaftGather {
    enum class End { Walked, Blocked, Overflow };
    static constexpr WalkOrder kOrder = WalkOrder::LeavesFirst;
    using Child = BvhChild;
    const Impl& g;
    const Shaft& shaft;
    const ShaftSelf& self;
    ShaftCandidates& out;
    End end = End::Walked;

    int enter(const BvhWideNode& node, uint32_t, float* tn) {
        int mask = 0;
        for (int i = 0; i < kBvhWidth; ++i) {
            tn[i] = 0;
            const float lo[3] = {node.lo[0][i], node.lo[1][i], node.lo[2][i]};
            const float hi[3] = {node.hi[0][i], node.hi[1][i], node.hi[2][i]};
            if (!(lo[0] <= hi[0])) continue;  // an unused lane
            if (!shaft.outside(lo, hi)) mask |= 1 << i;
        }
        return mask;
    }

    bool leaf(const Child& c) {
        for (uint32_t k = c.first(); k < c.first() + c.count(); ++k) {
            const uint32_t e = entry_at(g, k);
            if (g.has_transmissive && !passes<1>(e)) {
                // Shadow rays walk the transmissive primitives separately, from points along
                // the ray: note whether one may lie in the shaft (side tests assume the rays'
                // own origin, so only the shaft's planes may clear it).
                if (!outside_shaft(g, shaft, e)) add_transmissive(out, e);
                continue;
            }
            if (culled(g, shaft, self, e)) continue;
            if (((e >> kKindShift) & 3u) == uint32_t(PrimKind::Sphere)) {
                const SpherePrim& ball = g.spheres[e & kSlotMask];
                if (ball.xform == kNoTransform && shaft.blocks_all(ball.center, ball.radius)) {
                    end = End::Blocked;
                    return true;
                }
            }
            if (!add(out, e)) {
                end = End::Overflow;
                return true;
            }
        }
        return false;
    }
};

}  // namespace

bool ShaftCandidates::gather(const Geometry& geom, const Shaft& shaft, const ShaftSelf& self,
                             RayStats& stats) {
    const Impl& g = geom.impl();
    ShaftCandidates& out = *this;
    out.count = 0;
    out.blocked = false;
    out.transmissive = false;
    out.transmissive_count = 0;
    out.transmissive_listed = true;
    if (g.nodes.empty()) return false;
    for (size_t i = 0; i < g.planes.size(); ++i) {
        const PlanePrim& p = g.planes[i];
        if (g.has_transmissive && p.transmissive != 0) {
            add_transmissive(out, plane_entry(i));
            continue;
        }
        const int side = (p.prim == self.prim && self.ng_side != 0) ? self_side(p.n, self) : 0;
        if (shaft.clear_of_plane(p.n, p.c, side)) continue;
        if (!add(out, plane_entry(i))) return false;
    }
    ShaftGather q{g, shaft, self, out};
    uint64_t boxes = 0;
    walk_bvh(g.nodes.data(), q, boxes);
    stats.box_tests += boxes;
    out.blocked = q.end == ShaftGather::End::Blocked;
    return q.end != ShaftGather::End::Overflow;
}

bool ShaftCandidates::occluded(const Geometry& geom, const Ray& ray, double tmax, RayStats& stats) const {
    if (!ray_is_valid(ray, tmax)) {
        ++stats.rejected_rays;
        return false;
    }
    if (!(tmax > 0)) return false;
    if (blocked) return true;
    if (const int s = direction_scale(ray.d); s != 0)
        return occluded(geom, scaled(ray, s), std::ldexp(tmax, -s), stats);
    const Impl& g = geom.impl();
    Counters c;
    c.any_hit = true;
    bool hit = false;
    // Spheres in world space need only d·d; the rest the lazily made RayPre.
    LazyRayPre pre(ray);
    const double a = glm::dot(ray.d, ray.d), inv_a = 1.0 / a;
    for (int k = 0; k < count && !hit; ++k) {
        const uint32_t e = entries[k];
        const uint32_t kind = e >> kKindShift;
        double t;
        if (is_plane(e)) {
            ++c.planes;
            hit = intersect_plane(ray.o, ray.d, g.planes[e & (kPlaneSlotBit - 1)], tmax, t);
        } else if ((kind & 3u) == uint32_t(PrimKind::Sphere) &&
                   g.spheres[e & kSlotMask].xform == kNoTransform) {
            const SpherePrim& sp = g.spheres[e & kSlotMask];
            ++c.sph_tests;
            hit = intersect_sphere(ray.o, ray.d, a, inv_a, sp.center, sp.radius, Vec3(0), tmax, t);
            c.sph_hits += hit ? 1 : 0;
        } else {
            HitRecord h;
            hit = test_entry(g, pre.get(), e, tmax, c, h);
        }
    }
    c.flush(stats);
    return hit;
}

std::optional<HitRecord> ShaftCandidates::intersect_transmissive(const Geometry& geom, const Ray& ray,
                                                                 double tmax, RayStats& stats) const {
    if (!ray_is_valid(ray, tmax)) {
        ++stats.rejected_rays;
        return std::nullopt;
    }
    if (!(tmax > 0)) return std::nullopt;
    if (const int s = direction_scale(ray.d); s != 0) {
        auto hit = intersect_transmissive(geom, scaled(ray, s), std::ldexp(tmax, -s), stats);
        if (hit) hit->t = std::ldexp(hit->t, s);
        return hit;
    }
    const Impl& g = geom.impl();
    Counters c;
    Best best{tmax};
    LazyRayPre pre(ray);
    for (int k = 0; k < transmissive_count; ++k) {
        const uint32_t e = transmissive_entries[k];
        double t;
        if (is_plane(e)) {
            ++c.planes;
            const PlanePrim& p = g.planes[e & (kPlaneSlotBit - 1)];
            if (intersect_plane(ray.o, ray.d, p, best.limit, t)) best.offer(t, p.prim, e & kSlotMask, 0, 0);
            continue;
        }
        HitRecord h;
        if (test_entry(g, pre.get(), e, best.limit, c, h)) best.offer(h, e & kSlotMask);
    }
    c.flush(stats);
    return best.record();
}

}  // namespace wsd::render
