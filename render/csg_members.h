// The members of a CSG solid one at a time: every crossing of a ray's whole line with a member's
// surface (entering or leaving it, with an error bound on t), the surface at a member hit, and
// the closed-mesh member's own BVH. Internal to render/csg.cpp.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "render/csg_prims.h"
#include "render/prim_test.h"

namespace wsd::render::detail {

// Appends the crossings of member `m` (index `index`) with the line of `r`, and returns the
// member's inside count before its first crossing (1 for a half-space the line starts in).
int member_crossings(const CsgMember& m, uint32_t index, const RayPre& r, std::vector<CsgCrossing>& out,
                     Counters& c);

// The surface of member `m` at t along `ray`, with the crossing's parameters (sub, b1, b2), as
// the member defines its outward side; s.material is left alone.
void member_surface(const CsgMember& m, const Ray& ray, double t, uint32_t sub, double b1, double b2,
                    SurfaceHit& s);

// The member form of a closed mesh placed by `x`; nullptr with `error` set when a vertex is not
// finite after the transform or a face is degenerate.
std::shared_ptr<const CsgMesh> make_csg_mesh(const std::shared_ptr<const MeshData>& data, const Transform& x,
                                             std::string& error);

}  // namespace wsd::render::detail
