// The one dispatch of PrimKind::Other entries to their kind's code.
#include "render/other_prims.h"

namespace wsd::render {

namespace detail {

bool test_other(const Impl& g, const RayPre& r, uint32_t slot, double limit, Counters& c, HitRecord& h) {
    const OtherPrim& o = g.others[slot];
    switch (o.kind) {
        case OtherKind::Quadric:
            return test_quadric(g, g.quadrics[o.index], r, limit, c, h);
        case OtherKind::Csg:
            return test_csg(g, g.csgs[o.index], r, limit, c, h);
        case OtherKind::Instance:
            return test_instance(g, g.instances[o.index], r, limit, c, h);
    }
    return false;
}

}  // namespace detail

void other_surface(const Geometry::Impl& g, const ShapeInfo& info, const Ray& ray, const HitRecord& hit,
                   SurfaceHit& s) {
    const OtherPrim& o = g.others[hit.slot];
    switch (o.kind) {
        case OtherKind::Quadric:
            return quadric_surface(g, g.quadrics[o.index], info, ray, hit, s);
        case OtherKind::Csg:
            return csg_surface(g, g.csgs[o.index], info, ray, hit, s);
        case OtherKind::Instance:
            return instance_surface(g, g.instances[o.index], info, ray, hit, s);
    }
}

}  // namespace wsd::render
