// Storage of CSG solids: each a tree of member solids combined by union, intersection or
// difference, tested through render/other_prims.h.
//
// A ray meets a CSG solid where the result's inside/outside changes along the ray's whole line:
// every member lists its crossings (entering or leaving it, with a bound on the error of t), the
// crossings are swept in order with an inside count per member, and the tree's boolean is
// evaluated at each change. Crossings of different members closer than their error bounds are one
// event (the coincident-surface rule, docs/robustness.md): a sliver or gap thinner than the
// rounding error is no surface, and the surface shown at a coincident boundary is that of the
// member whose crossing alone changes the result; when several or none do, a subtracting member
// (one in a difference's subtracted position) is preferred, then the member written first.
//
// Shadow rays: a solid with any transmissive surface (a member's material) is a transmissive
// entry, so opaque-only queries pass it and the transmittance walk meets its boundary surfaces in
// order, each with its member's material: an opaque member's surface stops the light there.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "render/aabb.h"
#include "render/quadric_prims.h"
#include "render/scene_spec.h"
#include "render/transform.h"

namespace wsd::render {

enum class CsgMemberKind : uint8_t { Sphere, Box, Plane, Mesh, Quadric };

// A closed triangle mesh member: world-space float vertices (the watertight test of the
// one-level tree runs on them), a small BVH over its faces for whole-line queries.
struct CsgMesh {
    struct Node {
        Vec3 lo, hi;
        uint32_t first = 0;  // inner: index of the first child (the second follows); leaf: into tris
        uint32_t count = 0;  // 0: inner node
    };
    std::vector<Vec3f> verts;
    std::vector<glm::uvec3> tris;  // in BVH leaf order
    std::vector<uint32_t> face;    // tris[i] is face face[i] of the mesh
    std::vector<Node> nodes;
    bool flip = false;  // true when the faces wind inward as seen in world space
    std::shared_ptr<const MeshData> data;
};

struct CsgMember {
    CsgMemberKind kind = CsgMemberKind::Sphere;
    ShapeKind shape_kind = ShapeKind::Sphere;
    Transform x;  // the member's frame to world (the CSG's transform after the member's own)
    // Sphere: centre and radius in the member's frame. Box: lo, hi. Plane: unit n, n·p = c.
    Vec3 center{0}, lo{0}, hi{0}, n{0, 1, 0};
    double radius = 1, c = 0, uv_scale = 1;
    Vec3 band{0};  // per-axis uncertainty of a world point mapped into this frame (transform residual)
    std::shared_ptr<const CsgMesh> mesh;
    QuadricPrim quadric;  // closed cylinder or cone, torus: x maps its canonical frame to world
    // The member's own material, resolved through enclosing nested CSGs; kInheritMaterial: the
    // material the whole solid has where it is used (member_material).
    uint32_t material = kInheritMaterial;
    bool subtracted = false;  // in the subtracted position of a difference (an odd number of times)
    bool bounded = false;     // wlo, whi bound the member in world space (all but half-spaces)
    Vec3 wlo{0}, whi{0};
    uint32_t tag = 0;
};

// A node of the boolean tree: `op` over children; child ≥ 0 is a node index, child < 0 the
// member ~child. Node 0 is the root.
struct CsgNode {
    CsgOp op = CsgOp::Union;
    std::vector<int32_t> children;
};

struct CsgSolid {
    std::vector<CsgMember> members;
    std::vector<CsgNode> nodes;
    // The CSG shape's own frame to world: surface points for textures and bumps are given in it
    // (SurfaceHit::p_object), as every shape gives them in its own object frame.
    Transform frame;
};

// A hit on a CSG solid (HitRecord): prim is the solid's canonical id; member the index of the
// member whose surface it is, with kCsgFlipBit set where the member's inside is the solid's
// outside (a difference's cut surface: csg_surface turns the normal); member_slot and b1, b2 the
// member's own parameters (box face, mesh triangle and barycentrics, quadric part).
inline constexpr uint32_t kCsgFlipBit = 1u << 31;

struct CsgPrim {
    CsgOp op = CsgOp::Union;
    uint32_t prim = 0;  // canonical id
    std::shared_ptr<const CsgSolid> solid;
};

// The material a member's surface shows: its own, else `solid_material` (the CSG shape's, which
// may itself be kInheritMaterial inside a prototype: then the instance's).
inline uint32_t member_material(const CsgMember& m, uint32_t solid_material) {
    return m.material != kInheritMaterial ? m.material : solid_material;
}

// True when some surface of the CSG shape `s` is transmissive: a member's own material or, for
// members that inherit, `solid_material` (s.material, or what it inherits).
bool csg_transmissive(const SceneSpec& spec, const CsgSpec& csg, uint32_t solid_material);

// The CSG's bounds in its own frame (before s.object_to_world); false when unbounded (a plane
// not cut down by a bounded member) or invalid.
bool csg_local_bounds(const SceneSpec& spec, const CsgSpec& csg, Vec3& lo, Vec3& hi);

// A crossing of a ray's line with a member's surface (render/csg_members.cpp).
struct CsgCrossing {
    double t = 0;
    double err = 0;  // bound on the error of t
    uint32_t member = 0;
    uint32_t sub = 0;  // box: face; mesh: index into CsgMesh::tris; quadric: its part
    double b1 = 0, b2 = 0;
    int8_t delta = 0;        // +1 entering the member, −1 leaving it
    bool at_origin = false;  // the surface the ray's origin lies on
};

}  // namespace wsd::render
