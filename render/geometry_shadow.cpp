// Shadow queries against the primitives a shaft gathered (shaft.h): one BVH walk per shading
// point and area light collects the few opaque primitives its shadow rays can meet, and each of
// those rays then tests only them.
#include <cstdint>

#include "render/geometry_impl.h"
#include "render/prim_test.h"
#include "render/shaft.h"

namespace wsd::render {

using namespace detail;

bool Geometry::gather_shaft(const Shaft& shaft, ShaftCandidates& out, RayStats& stats) const {
    const Impl& g = *impl_;
    out.count = 0;
    if (g.nodes.empty()) return false;
    uint32_t stack[4 * kMaxBvhDepth + 4];  // each level pushes at most four children
    int sp = 0;
    uint32_t ni = 0;
    uint64_t boxes = 0;
    bool fits = true;
    for (;;) {
        const Bvh4Node& node = g.nodes[ni];
        for (int i = 0; i < 4 && fits; ++i) {
            const float lo[3] = {node.lo[0][i], node.lo[1][i], node.lo[2][i]};
            const float hi[3] = {node.hi[0][i], node.hi[1][i], node.hi[2][i]};
            if (!(lo[0] <= hi[0])) continue;  // an unused lane
            ++boxes;
            if (shaft.outside(lo, hi)) continue;
            if (node.count[i] == 0) {
                stack[sp++] = node.first[i];
                continue;
            }
            for (uint32_t k = node.first[i]; k < node.first[i] + node.count[i]; ++k) {
                const uint32_t e = g.order[k];
                if (g.has_transmissive && !passes<1>(e)) continue;
                if (out.count == ShaftCandidates::kMax) {
                    fits = false;
                    break;
                }
                out.entries[out.count++] = e;
            }
        }
        if (!fits || sp == 0) break;
        ni = stack[--sp];
    }
    stats.box_tests += boxes;
    return fits;
}

bool Geometry::occluded_among(const ShaftCandidates& candidates, const Ray& ray, double tmax,
                              RayStats& stats) const {
    if (!ray_is_valid(ray, tmax)) {
        ++stats.rejected_rays;
        return false;
    }
    if (!(tmax > 0)) return false;
    const Impl& g = *impl_;
    Counters c;
    bool hit = false;
    for (const PlanePrim& p : g.planes) {
        if (g.has_transmissive && p.transmissive != 0) continue;
        ++c.planes;
        double t;
        if (intersect_plane(ray.o, ray.d, p, tmax, t)) {
            hit = true;
            break;
        }
    }
    if (!hit && candidates.count > 0) {
        const RayPre r(ray, false);
        for (int k = 0; k < candidates.count && !hit; ++k) {
            double t, b1, b2;
            uint32_t prim;
            hit = test_entry(g, r, candidates.entries[k], tmax, c, t, prim, b1, b2);
        }
    }
    c.flush(stats);
    return hit;
}

}  // namespace wsd::render
