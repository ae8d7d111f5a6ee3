// CSG solids: building, ray tests and surfaces.
#include "render/csg_prims.h"
#include "render/other_prims.h"

namespace wsd::render {

namespace detail {

bool test_csg(const Impl&, const CsgPrim&, const RayPre&, double, Counters&, HitRecord&) {
    return false;
}

}  // namespace detail

void csg_surface(const Geometry::Impl&, const CsgPrim&, const ShapeInfo&, const Ray&, const HitRecord&,
                 SurfaceHit&) {}

std::optional<Bounds3f> build_csg(const OtherBuild& b, const ShapeSpec&, const Transform&) {
    b.error("CSG is not built yet");
    return std::nullopt;
}

}  // namespace wsd::render
