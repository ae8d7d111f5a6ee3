// Geometry's private state, shared by geometry_build.cpp (validation and construction) and the
// queries (geometry.cpp, geometry_packet.cpp, geometry_shadow.cpp, geometry_surface.cpp), which
// walk its BVH with walk_bvh (traverse.h). Not part of the public interface.
#pragma once

#include <memory>
#include <vector>

#include "render/bvh.h"
#include "render/csg_prims.h"
#include "render/geometry.h"
#include "render/instance_prims.h"
#include "render/limits.h"
#include "render/quadric_prims.h"
#include "render/shapes.h"
#include "render/transform.h"

namespace wsd::render {

// Entries of Impl::order: bit 31 transmissive, bits 29–30 the kind, bits 0–28 the slot.
// Other: every primitive beyond the three that traversal tests inline (render/other_prims.h).
enum class PrimKind : uint32_t { Triangle = 0, Sphere = 1, Box = 2, Other = 3 };
inline constexpr uint32_t kTransmissiveBit = 1u << 31;
inline constexpr uint32_t kKindShift = 29;
inline constexpr uint32_t kSlotMask = (1u << 29) - 1;

inline uint32_t encode_entry(PrimKind kind, uint32_t slot, bool transmissive) {
    return (transmissive ? kTransmissiveBit : 0u) | (static_cast<uint32_t>(kind) << kKindShift) | slot;
}

// A PrimKind::Other entry's record (render/other_prims.h).
enum class OtherKind : uint8_t { Quadric, Csg, Instance };
struct OtherPrim {
    OtherKind kind = OtherKind::Quadric;
    uint32_t index = 0;  // into Impl::quadrics, Impl::csgs or Impl::instances
};

struct ShapeInfo {
    ShapeKind kind = ShapeKind::Sphere;
    uint32_t material = 0;
    uint32_t xform = 0;                    // index into Impl::xforms (0 is the identity)
    uint32_t first_prim = 0;               // canonical id of its first primitive
    uint32_t extra = 0;                    // triangle: index into tri_extra; plane: into plane_extra
    uint32_t vertex_offset = 0;            // triangle, mesh: first vertex in Impl::verts
    bool mirrored = false;                 // det < 0: world winding is the reverse of the object's
    std::shared_ptr<const MeshData> mesh;  // kept only when it has normals or uvs
};

struct TriExtra {
    bool has_uv = false;
    Vec2 uv[3];
};

struct PlaneExtra {
    Vec3 u, v;  // object-frame plane axes
    double uv_scale = 1;
};

struct Geometry::Impl {
    HugePageVector<Vec3f> verts;  // world-space triangle vertices, shared within a mesh
    HugePageVector<TriPrim> tris;
    std::vector<SpherePrim> spheres;
    std::vector<BoxPrim> boxes;
    std::vector<PlanePrim> planes;
    std::vector<Transform> xforms;
    std::vector<ShapeInfo> shapes;
    std::vector<uint32_t> shape_first;  // shapes[i].first_prim, for lookups by canonical id
    HugePageVector<TriExtra> tri_extra;
    std::vector<PlaneExtra> plane_extra;
    std::vector<OtherPrim> others;                       // PrimKind::Other entries' slots
    std::vector<QuadricPrim> quadrics;                   // cylinders, cones, tori, discs
    std::vector<CsgPrim> csgs;                           // CSG solids
    std::vector<InstancePrim> instances;                 // instances of prototypes
    std::vector<std::unique_ptr<Prototype>> prototypes;  // SceneSpec::prototypes, built when used
    HugePageVector<BvhWideNode> nodes;  // the BVH in its wide traversal form; empty without BVH
    HugePageVector<uint32_t> order;     // encoded entries; leaf ranges (BVH) or canonical order; empty
                                        // with tris_in_order
    std::vector<uint8_t> inherits;      // a prototype's: per order entry, 1 when its material is inherited
    bool use_bvh = true;
    bool has_transmissive = false;
    // Every entry is an opaque triangle and entry k names tris[k]: a BVH over triangles alone,
    // whose leaves then read tris directly; order is not stored (entry_at, geometry_build.cpp).
    bool tris_in_order = false;
    size_t primitive_count = 0;
    int bvh_depth = 0;

    uint32_t shape_of(uint32_t prim) const;
};

// A triangle vertex in world space as the build stores it: the double transform, then rounded
// to float. Instances compute their vertices with it too (render/instances.cpp), so that an
// instance's triangles are exactly those of the same geometry written out flat.
inline Vec3f world_vertex_of(const Transform& x, const Vec3& p) {
    const Vec3 w = x.point(p);
    return Vec3f(static_cast<float>(w.x), static_cast<float>(w.y), static_cast<float>(w.z));
}

// Everything `g` stores (primitives, BVHs, instanced objects' geometry once each), in bytes.
size_t geometry_memory_bytes(const Geometry::Impl& g);

// Geometry::build's work: validates and builds `shapes` (spec.shapes, or a prototype's shapes
// with `prototype` set: members may inherit their material, planes and instances are refused)
// into the empty `g`. Returns false after appending errors (their index is into `shapes`).
bool build_geometry_into(Geometry::Impl& g, const SceneSpec& spec, const std::vector<ShapeSpec>& shapes,
                         std::vector<SpecError>& errors, bool use_bvh, int threads, bool prototype);

}  // namespace wsd::render
