// Storage of CSG solids: each a tree of member solids combined by union, intersection or
// difference, tested through render/other_prims.h.
#pragma once

#include <cstdint>

#include "render/scene_spec.h"

namespace wsd::render {

struct CsgPrim {
    CsgOp op = CsgOp::Union;
    uint32_t prim = 0;  // canonical id
};

}  // namespace wsd::render
