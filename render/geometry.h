// The scene's geometry: every shape of a SceneSpec in world space, a BVH over the bounded ones
// (planes are kept outside it), closest-hit and any-hit queries, and the surface data of a hit.
// Robust by construction (docs/robustness.md): watertight triangles, stable sphere roots,
// widened NaN-safe slab tests, error-bounded spawn origins; no fixed epsilon anywhere.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "render/scene_spec.h"
#include "render/stats.h"

namespace wsd::render {

// d need not be unit length; t is measured in units of d. Valid hits have 0 < t < tmax.
struct Ray {
    Vec3 o;
    Vec3 d;
};

// What traversal records: enough to compute the surface later, nothing more.
struct HitRecord {
    double t = 0;
    uint32_t prim = 0;      // geometry-global primitive index
    uint32_t slot = 0;      // internal: where the primitive is stored (set by intersect)
    double b1 = 0, b2 = 0;  // barycentrics (triangles), or shape-specific parameters
    // Primitives made of others keep the inner hit here (render/other_prims.h): a CSG the member
    // hit and that member's own slot; an instance the hit inside its prototype's geometry.
    uint32_t member = 0, member_slot = 0;
    uint32_t inner_prim = 0, inner_slot = 0;
};

struct SurfaceHit {
    Vec3 p;                 // world-space hit point
    Vec3 p_error;           // absolute error bound on p, per component (for spawn offsets)
    Vec3 ng;                // unit geometric normal, outward as the shape defines it
    Vec3 ns;                // unit shading normal (interpolated), same side as ng, not yet bumped
    Vec2 uv{0, 0};          // texture coordinates (plane: plane coordinates / uv_scale)
    Vec2 plane_xy{0, 0};    // plane only: the plane's own 2-D coordinates in object units
    bool planar = false;    // true for planes
    Vec3 p_object;          // the point in the object's own frame (sphere: relative to its centre)
    uint32_t shape = 0;     // index into SceneSpec::shapes
    uint32_t prim = 0;      // the geometry-global primitive hit
    uint32_t material = 0;  // index into SceneSpec::materials
    // A hit on a member of an instance: the member's index in its object (PrototypeSpec::shapes).
    static constexpr uint32_t kNoMember = 0xffffffffu;
    uint32_t member = kNoMember;
};

// Which primitives a query sees; shadow rays skip transmissive ones and then walk them in order.
enum class RayFilter : uint8_t { All, OpaqueOnly, TransmissiveOnly };

class Geometry {
public:
    // Builds world-space primitives and the BVH. Appends an error for every degenerate input
    // (zero-area triangle, index out of range, non-finite coordinate, singular transform, zero
    // radius...) and returns nullptr if there was any. threads: 0 = all cores.
    static std::unique_ptr<Geometry> build(const SceneSpec& spec, std::vector<SpecError>& errors,
                                           bool use_bvh = true, int threads = 0);
    ~Geometry();

    std::optional<HitRecord> intersect(const Ray& ray, double tmax, RayStats& stats,
                                       RayFilter filter = RayFilter::All) const;
    bool occluded(const Ray& ray, double tmax, RayStats& stats,
                  RayFilter filter = RayFilter::OpaqueOnly) const;
    // intersect(rays[k], tmax, stats) for k < n ≤ kMaxPacket, walking the BVH once for all of
    // them when they point the same way (every direction component of one sign): camera rays
    // through a pixel or through neighbouring pixels. The same hits, bit for bit, as n single
    // queries.
    static constexpr int kMaxPacket = 16;
    void intersect_packet(const Ray* rays, int n, double tmax, RayStats& stats,
                          std::optional<HitRecord>* out) const;
    SurfaceHit surface(const Ray& ray, const HitRecord& hit) const;

    // The object-to-world matrix of a hit on a member of an instance (s.member is set): the
    // instance's times the member's, as the same shape written out flat would have.
    Mat4 member_to_world(const SurfaceHit& s) const;

    // A ray origin just off the surface on the side of w, by the hit's error bound (pbrt-v4).
    static Vec3 offset_origin(const SurfaceHit& s, const Vec3& w);

    // Primitives stored: every primitive outside instances, and each instanced object's
    // primitives once (however many instances it has). Instances themselves are not counted.
    size_t primitive_count() const;
    size_t triangle_count() const;  // stored, as primitive_count
    size_t instance_count() const;
    // Primitives and triangles as rendered: each instance counts its object's.
    size_t instanced_primitive_count() const;
    size_t instanced_triangle_count() const;
    bool has_transmissive() const;
    size_t memory_bytes() const;  // primitives and BVHs, each instanced object's once

    // The primitives and the BVH (geometry_impl.h), for render's own queries beyond these
    // (shadow shafts: shaft.h).
    struct Impl;
    const Impl& impl() const { return *impl_; }

private:
    explicit Geometry(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace wsd::render
