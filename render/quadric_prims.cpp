// Cylinders, cones, tori and discs: building, ray tests and surfaces.
#include "render/quadric_prims.h"

#include "render/other_prims.h"

namespace wsd::render {

namespace detail {

bool test_quadric(const Impl&, const QuadricPrim&, const RayPre&, double, Counters&, HitRecord&) {
    return false;
}

}  // namespace detail

void quadric_surface(const Geometry::Impl&, const QuadricPrim&, const ShapeInfo&, const Ray&,
                     const HitRecord&, SurfaceHit&) {}

std::optional<Bounds3f> build_quadric(const OtherBuild& b, const ShapeSpec&, const Transform&) {
    b.error("this primitive is not built yet");
    return std::nullopt;
}

}  // namespace wsd::render
