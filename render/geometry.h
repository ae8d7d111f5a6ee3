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
};

// Which primitives a query sees; shadow rays skip transmissive ones and then walk them in order.
enum class RayFilter : uint8_t { All, OpaqueOnly, TransmissiveOnly };

class Shaft;

// The opaque primitives that the shadow rays of one shading point towards one area light may
// meet (Geometry::gather_shaft), so that each of those rays tests only them.
struct ShaftCandidates {
    static constexpr int kMax = 32;  // more than this: not worth it, trace each ray in full
    uint32_t entries[kMax];
    int count = 0;
    bool transmissive = false;  // some transmissive primitive may meet the shaft
    bool blocked = false;       // an opaque sphere meets every ray: all are blocked (Shaft::blocks_all)
    // The transmissive primitives that may meet it, when there are at most kMaxTransmissive
    // (transmissive_listed): the walk through glass then tests only them.
    static constexpr int kMaxTransmissive = 8;
    uint32_t transmissive_entries[kMaxTransmissive];
    int transmissive_count = 0;
    bool transmissive_listed = false;
};

// The surface the shadow rays of a shaft leave: its primitive and geometric normal, and which
// side of it the rays start on (+1 along ng, −1 against it, 0 when they do not share one origin).
struct ShaftSelf {
    uint32_t prim = 0xffffffffu;
    Vec3 ng{0};
    int ng_side = 0;
};

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

    // Collects the opaque primitives (planes included) that shadow rays inside `shaft` may meet:
    // those in BVH leaves that meet it, less those a finer test clears (Shaft::outside_*,
    // clear_of_*); `self` is the surface the rays leave. False when there is no BVH or more than
    // ShaftCandidates::kMax of them: then use occluded() for each ray.
    bool gather_shaft(const Shaft& shaft, const ShaftSelf& self, ShaftCandidates& out, RayStats& stats) const;
    // occluded(ray, tmax, stats, RayFilter::OpaqueOnly) for a ray that lies inside the shaft the
    // candidates were gathered for: the same answer, testing only those primitives (none when
    // the shaft is known to be blocked).
    bool occluded_among(const ShaftCandidates& candidates, const Ray& ray, double tmax,
                        RayStats& stats) const;
    // intersect(ray, tmax, stats, RayFilter::TransmissiveOnly) for a ray inside the shaft, when
    // candidates.transmissive_listed: the same hit, testing only the listed primitives.
    std::optional<HitRecord> intersect_among(const ShaftCandidates& candidates, const Ray& ray, double tmax,
                                             RayStats& stats) const;

    // A ray origin just off the surface on the side of w, by the hit's error bound (pbrt-v4).
    static Vec3 offset_origin(const SurfaceHit& s, const Vec3& w);

    size_t primitive_count() const;  // triangles + spheres + boxes + planes
    size_t triangle_count() const;
    bool has_transmissive() const;
    size_t memory_bytes() const;  // primitives and BVH

    struct Impl;

private:
    explicit Geometry(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace wsd::render
