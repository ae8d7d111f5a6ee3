// Instances: prototypes built once, each instance a transform and a reference (two-level BVH).
#include "render/instance_prims.h"
#include "render/other_prims.h"

namespace wsd::render {

namespace detail {

bool test_instance(const Impl&, const InstancePrim&, const RayPre&, double, Counters&, HitRecord&) {
    return false;
}

}  // namespace detail

void instance_surface(const Geometry::Impl&, const InstancePrim&, const ShapeInfo&, const Ray&,
                      const HitRecord&, SurfaceHit&) {}

std::optional<Bounds3f> build_instance(const OtherBuild& b, const ShapeSpec&, const Transform&) {
    b.error("instances are not built yet");
    return std::nullopt;
}

}  // namespace wsd::render
