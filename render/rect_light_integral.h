// Exact average of N·(p−x)/|p−x| over a parallelogram light, the limit of the jittered cell sum
// for a point that sees the whole light above its tangent plane (robustness.md, closed-form light).
#pragma once

#include "render/scene_spec.h"

namespace wsd::render {

// The average over p = c + s·u + t·v, s, t uniform in [0, 1], of N·(p − x)/|p − x|, for a unit
// normal N. Exact (in double) when every point of the parallelogram has N·(p − x) ≥ 0; otherwise
// it is the signed average, without the clamp. Returns 0 for a degenerate parallelogram.
double rect_light_average_cosine(const Vec3& x, const Vec3& n, const Vec3& c, const Vec3& u, const Vec3& v);

}  // namespace wsd::render
