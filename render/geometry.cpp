// Geometry queries: closest-hit and any-hit traversal (BVH, or brute force over every primitive),
// the surface data of a hit, and error-bounded spawn origins (pbrt-v4 OffsetRayOrigin). Ties in
// t resolve to the lowest canonical primitive id, so BVH and brute force agree bit for bit.
#include <algorithm>
#include <bit>
#include <cmath>
#include <thread>

#include "render/geometry_impl.h"
#include "render/prim_test.h"

namespace wsd::render {

uint32_t Geometry::Impl::shape_of(uint32_t prim) const {
    auto it = std::upper_bound(shape_first.begin(), shape_first.end(), prim);
    return static_cast<uint32_t>(it - shape_first.begin()) - 1;
}

namespace {

using namespace detail;

struct StackEntry {
    uint32_t first, count;
    float t;
};
// Each level of the 4-wide tree pushes at most three entries.
constexpr int kStackSize = 3 * kMaxBvhDepth + 1;

// The children of `node` that the ray enters, nearest first in out[0]; returns their number.
inline int entered_children(const Bvh4Node& node, int mask, const float* tn, StackEntry* out) {
    int m = 0;
    while (mask != 0) {
        const int i = std::countr_zero(static_cast<unsigned>(mask));
        mask &= mask - 1;
        StackEntry e{node.first[i], node.count[i], tn[i]};
        int j = m++;
        while (j > 0 && out[j - 1].t > e.t) {
            out[j] = out[j - 1];
            --j;
        }
        out[j] = e;
    }
    return m;
}

template <int kFilter>
void closest_hit(const Impl& g, const RayPre& r, Best& best, Counters& c) {
    auto leaf = [&](uint32_t first, uint32_t count) [[gnu::always_inline]] {
        for (uint32_t k = first; k < first + count; ++k) {
            uint32_t e = g.order[k];
            if (!passes<kFilter>(e)) continue;
            double t, b1, b2;
            uint32_t prim;
            if (test_entry(g, r, e, best.limit, c, t, prim, b1, b2))
                best.offer(t, prim, e & kSlotMask, b1, b2);
        }
    };
    if (g.nodes.empty()) {
        leaf(0, static_cast<uint32_t>(g.order.size()));
        return;
    }
    const Bvh4Node* nodes = g.nodes.data();
    float limit_f = to_float_up(best.limit);
    StackEntry stack[kStackSize];
    int sp = 0;
    uint32_t ni = 0;
    uint64_t visits = 0;  // counted in a register, added to c once
    for (;;) {
        const Bvh4Node& node = nodes[ni];
        alignas(16) float tn[4];
        const int mask = r.box.hit4(node, limit_f, tn);
        ++visits;
        StackEntry next{};
        bool have = mask != 0;
        if (have) {
            // Nearest child next; the others wait, farthest deepest, with their entry distances
            // for pruning once a hit shortens the ray. One or two children (the common cases)
            // need no sorting loop.
            const int i = std::countr_zero(static_cast<unsigned>(mask));
            const int rest = mask & (mask - 1);
            if (rest == 0) {
                next = {node.first[i], node.count[i], tn[i]};
            } else if ((rest & (rest - 1)) == 0) {
                const int j = std::countr_zero(static_cast<unsigned>(rest));
                const bool swap = tn[j] < tn[i];
                const int near = swap ? j : i, far = swap ? i : j;
                stack[sp++] = {node.first[far], node.count[far], tn[far]};
                next = {node.first[near], node.count[near], tn[near]};
            } else {
                StackEntry e[4];
                const int m = entered_children(node, mask, tn, e);
                for (int k = m - 1; k > 0; --k) stack[sp++] = e[k];
                next = e[0];
            }
        }
        for (;;) {
            if (have) {
                if (next.count == 0) {
                    ni = next.first;
                    break;
                }
                leaf(next.first, next.count);
                limit_f = to_float_up(best.limit);
            }
            if (sp == 0) {
                c.boxes += 4 * visits;
                return;
            }
            next = stack[--sp];
            have = next.t <= limit_f * RayBoxTest::kWiden;
        }
    }
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
    auto leaf = [&](uint32_t first, uint32_t count) {
        for (uint32_t k = first; k < first + count; ++k) {
            uint32_t e = g.order[k];
            if (!passes<kFilter>(e)) continue;
            double t, b1, b2;
            uint32_t prim;
            if (test_entry(g, r, e, tmax, c, t, prim, b1, b2)) return true;
        }
        return false;
    };
    if (g.nodes.empty()) return leaf(0, static_cast<uint32_t>(g.order.size()));
    const Bvh4Node* nodes = g.nodes.data();
    const float limit_f = to_float_up(tmax);
    StackEntry stack[kStackSize];
    int sp = 0;
    uint32_t ni = 0;
    uint64_t visits = 0;
    for (;;) {
        const Bvh4Node& node = nodes[ni];
        alignas(16) float tn[4];
        int mask = r.box.hit4(node, limit_f, tn);
        ++visits;
        for (; mask != 0; mask &= mask - 1) {
            const int i = std::countr_zero(static_cast<unsigned>(mask));
            stack[sp++] = {node.first[i], node.count[i], 0};
        }
        for (;;) {
            if (sp == 0) {
                c.boxes += 4 * visits;
                return false;
            }
            const StackEntry next = stack[--sp];
            if (next.count == 0) {
                ni = next.first;
                break;
            }
            if (leaf(next.first, next.count)) {
                c.boxes += 4 * visits;
                return true;
            }
        }
    }
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

size_t Geometry::primitive_count() const {
    return impl_->primitive_count;
}
size_t Geometry::triangle_count() const {
    return impl_->tris.size();
}
bool Geometry::has_transmissive() const {
    return impl_->has_transmissive;
}

size_t Geometry::memory_bytes() const {
    const Impl& g = *impl_;
    auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
    return bytes(g.verts) + bytes(g.tris) + bytes(g.spheres) + bytes(g.boxes) + bytes(g.planes) +
           bytes(g.xforms) + bytes(g.shapes) + bytes(g.shape_first) + bytes(g.tri_extra) +
           bytes(g.plane_extra) + bytes(g.nodes) + bytes(g.order);
}

}  // namespace wsd::render
