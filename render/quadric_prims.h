// Storage of the quadric primitives and the torus (cylinder, cone, torus, disc): one record each,
// in the shape's own frame, tested through render/other_prims.h.
#pragma once

#include <cstdint>

#include "render/scene_spec.h"

namespace wsd::render {

struct QuadricPrim {
    ShapeKind kind = ShapeKind::Cylinder;
    uint32_t prim = 0;   // canonical id
    uint32_t xform = 0;  // index into Impl::xforms (0: identity)
};

}  // namespace wsd::render
