// Object values: what an object block evaluates to before anything is added to the scene. A leaf
// is a lowered primitive (sphere, box, triangle, plane, mesh, cylinder, cone, torus, disc); a group
// or CSG holds its members; an instance (`object EXPR { ... }`) refers to another value. Each
// carries its own transforms and, optionally, its own material. Values are immutable and shared:
// adding the same value twice adds the same geometry, which is how instances share it
// (lang/lower_instances.cpp keys prototypes on the value's identity).
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "lang/lower.h"
#include "lang/value.h"

namespace wsd::lang {

enum class ObjectKind : uint8_t { Leaf, Group, Csg, Instance };

// Values nest through names and calls beyond what one file's syntax can nest; lowering walks them
// recursively, so their depth is bounded where they are made.
inline constexpr int kMaxObjectDepth = 1000;

// The `default_material` binding in scope where a leaf's block was evaluated: its material when
// neither it nor anything enclosing it gives one.
struct FallbackMaterial {
    MaterialPtr material;              // null: none usable
    bool failed = false;               // bound, but its definition failed (already reported)
    const char* wrong_type = nullptr;  // bound to a value of this type, not a material
    Span defined_at;
};

struct ObjectValue {
    ObjectKind kind = ObjectKind::Leaf;
    Span keyword;  // sphere, group, union, object, ...
    IncludeChain chain;
    MaterialPtr material;  // its own material, or null (leaf: its `material`; others: the item)
    // Leaf: the lowered primitive (its shape's object_to_world holds its transforms; its material
    // index is not set yet) and its fallback.
    std::optional<LoweredObject> leaf;
    FallbackMaterial fallback;
    // Group and CSG: the members, in the order added. Instance: the value it adds.
    render::CsgOp op = render::CsgOp::Union;
    std::vector<ObjectPtr> members;
    ObjectPtr target;
    render::Mat4 transform{1.0};  // group, CSG, instance: their own transforms, composed
    // Counted as `wsd check` counts (as instanced): leaf objects and triangles.
    size_t objects = 0, triangles = 0;
    // The primitives a CSG made of this value stores (nested CSG and instances expanded), saturating.
    size_t solid_primitives = 0;
    int depth = 1;  // levels of groups, CSG and instances down to its deepest leaf

    bool is_mesh() const { return kind == ObjectKind::Leaf && leaf->shape.kind == render::ShapeKind::Mesh; }
};

// The keyword a leaf is written with ("sphere", "mesh", ...): render::shape_word.
using render::shape_word;

}  // namespace wsd::lang
