// Storage of instances: the prototypes' geometry, built once each, and per instance a transform
// and a reference (the two-level BVH), tested through render/other_prims.h.
//
// Exactness: an instance of triangles, meshes, spheres and boxes hits, and shades, bit for bit
// like the same shapes written out flat with object_to_world = instance · member. The prototype's
// BVH is walked with the ray taken into the prototype's frame, its boxes widened by a bound on
// that ray's error (so no hit is missed), but those primitives are tested against the world ray
// as the flat build would store them: triangle vertices transformed by the composed matrix and
// rounded to float as Geometry::build does, spheres and boxes with the composed Transform. Other
// kinds (cylinders, cones, tori, discs, CSG) are tested with the ray in the prototype's frame.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "render/aabb.h"
#include "render/geometry.h"

namespace wsd::render {

// SceneSpec::prototypes[i], built: its own primitives and BVH in the prototype's frame.
struct Prototype {
    std::unique_ptr<Geometry::Impl> geometry;
    // The spec's shapes (meshes shared, not copied): each member's own matrix and source data,
    // from which an instance composes the flat scene's transforms. Index = ShapeInfo index.
    std::vector<ShapeSpec> shapes;
    // Per lone triangle (by ShapeInfo::extra): its vertices in its own frame, in double.
    std::vector<std::array<Vec3, 3>> tri_src;
    Bounds3f bounds;  // every member, in the prototype's frame
    bool built = false, failed = false;
    // Which members have an explicit transmissive or opaque material, and which inherit theirs.
    bool has_transmissive = false, has_opaque = false, has_inherit = false;
    size_t triangles = 0;  // stored triangles
    size_t memory_bytes() const;
};

struct InstancePrim {
    uint32_t prototype = 0;  // index into Impl::prototypes
    uint32_t prim = 0;       // canonical id (an instance's entries share it)
    uint32_t xform = 0;      // index into Impl::xforms
    uint32_t material = 0;   // the instance's material, for members with kInheritMaterial
    // Which members this entry covers: 0 all, 1 the opaque ones, 2 the transmissive ones (an
    // instance with both kinds has one entry for each, so that ray filters see members).
    uint8_t filter = 0;
    bool transmissive = false;          // the entry's transmissive bit
    bool inherit_transmissive = false;  // the instance's material is transmissive
    // Per axis of the prototype's frame: how far the prototype's stored primitives may lie from
    // the world primitives mapped back (float roundings), by which node boxes are widened.
    Vec3 pad{0, 0, 0};
};

}  // namespace wsd::render
