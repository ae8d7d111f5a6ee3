// Storage of instances: the prototypes' geometry, built once each, and per instance a transform
// and a reference (the two-level BVH), tested through render/other_prims.h.
#pragma once

#include <cstdint>
#include <memory>

#include "render/geometry.h"

namespace wsd::render {

// SceneSpec::prototypes[i], built: its own primitives and BVH in the prototype's frame.
struct Prototype {
    std::unique_ptr<Geometry::Impl> geometry;
};

struct InstancePrim {
    uint32_t prototype = 0;  // index into Impl::prototypes
    uint32_t prim = 0;       // canonical id
    uint32_t xform = 0;      // index into Impl::xforms
};

}  // namespace wsd::render
