// The primitives beyond triangles, spheres and boxes (PrimKind::Other entries): quadrics and the
// torus (render/quadric_prims.*), CSG solids (render/csg.*) and instances (render/instances.*).
// Traversal, shadow queries and Geometry::surface reach each through the one switch here, so a
// scene without them runs exactly the code it ran before. Internal to render/.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "render/geometry_impl.h"
#include "render/prim_test.h"

namespace wsd::render {

namespace detail {

// The primitive in Impl::others[slot] against the ray: on a hit with δt < t < limit, fills
// h.t, h.prim, h.b1, h.b2 and the inner fields, and returns true.
bool test_other(const Impl& g, const RayPre& r, uint32_t slot, double limit, Counters& c, HitRecord& h);
bool test_quadric(const Impl& g, const QuadricPrim& q, const RayPre& r, double limit, Counters& c,
                  HitRecord& h);
bool test_csg(const Impl& g, const CsgPrim& q, const RayPre& r, double limit, Counters& c, HitRecord& h);
bool test_instance(const Impl& g, const InstancePrim& q, const RayPre& r, double limit, Counters& c,
                   HitRecord& h);

}  // namespace detail

// The surface of a hit on an Other primitive (hit.slot indexes Impl::others); s.shape, s.prim and
// s.material are set by the caller (the material may be overridden here: an instance's member).
void other_surface(const Geometry::Impl& g, const ShapeInfo& info, const Ray& ray, const HitRecord& hit,
                   SurfaceHit& s);
void quadric_surface(const Geometry::Impl& g, const QuadricPrim& q, const ShapeInfo& info, const Ray& ray,
                     const HitRecord& hit, SurfaceHit& s);
void csg_surface(const Geometry::Impl& g, const CsgPrim& q, const ShapeInfo& info, const Ray& ray,
                 const HitRecord& hit, SurfaceHit& s);
void instance_surface(const Geometry::Impl& g, const InstancePrim& q, const ShapeInfo& info, const Ray& ray,
                      const HitRecord& hit, SurfaceHit& s);

// The surfaces of the kinds traversal tests inline, from the primitive and its shape's transform
// (render/geometry_surface.cpp): Geometry::surface and instances share them. Triangle: world
// vertices v, their indices in the mesh (local), extra for a lone triangle (null for a mesh).
void triangle_surface_of(const Vec3 (&v)[3], const uint32_t (&local)[3], const ShapeInfo& info,
                         const TriExtra* extra, const Transform& x, const HitRecord& hit, SurfaceHit& s);
void sphere_surface_of(const SpherePrim& sp, const Transform& x, const Ray& ray, const HitRecord& hit,
                       SurfaceHit& s);
void box_surface_of(const BoxPrim& bx, const Transform& x, const Ray& ray, const HitRecord& hit,
                    SurfaceHit& s);

// Building (Geometry::build): validates shape `s` (every problem through `error`), appends its
// record to the kind's store with canonical id `prim` and returns its world bounds, or nullopt
// after an error. `x` is s.object_to_world made a Transform, stored as Impl::xforms[xform].
// `transmissive` (when set) starts as whether s.material is transmissive; a shape with surfaces
// of other materials (a CSG's members) sets it when any of them is, so that shadow rays walk it.
struct OtherBuild {
    Geometry::Impl& g;
    const SceneSpec& spec;
    const std::function<void(std::string)>& error;
    uint32_t prim;
    uint32_t xform;
    bool* transmissive = nullptr;
    int threads = 0;  // for building nested BVHs (0: all cores)
};
std::optional<Bounds3f> build_quadric(const OtherBuild& b, const ShapeSpec& s, const Transform& x);
std::optional<Bounds3f> build_csg(const OtherBuild& b, const ShapeSpec& s, const Transform& x);
std::optional<Bounds3f> build_instance(const OtherBuild& b, const ShapeSpec& s, const Transform& x);

}  // namespace wsd::render
