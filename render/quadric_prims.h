// Storage of the quadric primitives and the torus (cylinder, cone, torus, disc): one record each,
// in its own canonical frame, tested through render/other_prims.h.
//
// The canonical frame of every kind has its axis along +y:
// - cylinder and cone: the base centre at the origin, the cap centre at (0, h, 0); the radius is
//   r0 at y = 0 and r1 at y = h (a cylinder has r0 = r1); `open` leaves out the two end caps;
// - torus: the shape's own frame (centred at the origin, the major circle in the xz-plane), with
//   r0 the major and r1 the minor radius; its surface is the set of points at distance r1 from
//   the major circle, so a spindle torus (r1 ≥ r0) is the outer "apple" only;
// - disc: the centre at the origin, the normal +y, radius r0 and a hole of radius r1.
// Its x axis is the object's +x projected onto the plane normal to the axis (+z where that
// vanishes), so that a shape whose axis is the object's y axis has the object's own axes.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "render/math.h"
#include "render/scene_spec.h"

namespace wsd::render {

struct QuadricPrim {
    ShapeKind kind = ShapeKind::Cylinder;
    uint32_t prim = 0;   // canonical id
    uint32_t xform = 0;  // index into Impl::xforms: the canonical frame → world
    double r0 = 1, r1 = 1, h = 1;
    bool open = false;
    // The canonical frame → the shape's object frame, a rigid motion: p_obj = origin + R·p with
    // the columns of R the frame's axes (for textures, which work in the object frame).
    Vec3 origin{0};
    Vec3 axis_x{1, 0, 0}, axis_y{0, 1, 0}, axis_z{0, 0, 1};
    // The per-axis uncertainty of a world point mapped into the canonical frame that does not
    // depend on the point (the composed transform's residual at the shape's extent).
    Vec3 band{0};
};

// Validates `s` (a cylinder, cone, torus or disc in its object frame) and fills q's shape fields
// and object frame (kind, r0, r1, h, open, origin, axes), leaving prim, xform and band. Returns
// the problem, phrased for a message, or nullopt. `frame` receives the canonical frame → object
// frame as a matrix, to be composed with the object's transform.
std::optional<std::string> make_quadric(const ShapeSpec& s, QuadricPrim& q, Mat4& frame);

// The parts of a cylinder or cone (body, base cap at y = 0, top cap at y = h); a torus and a
// disc have one part, the body.
enum QuadricPart : int { kQuadricBody = 0, kQuadricBaseCap = 1, kQuadricTopCap = 2 };

// Every crossing of the whole line o + t·d (t over all reals; o and d in q's canonical frame,
// d non-zero) with the surface of q: up to `max` parameters t in ascending order into t[], each
// with its part into part[]; returns how many. A closed cylinder or cone and a torus are solids:
// along the line the crossings alternate between entering and leaving (a line tangent to the
// surface, or through a rim or an apex, may give a crossing twice or not at all). At most 4
// crossings exist for every kind (a line meets a closed cylinder or cone at most twice), so
// max = 4 never truncates.
int quadric_crossings(const QuadricPrim& q, const Vec3& o, const Vec3& d, double* t, int* part, int max);

// The surface at a crossing: the point o + t·d moved onto part `part` of q (canonical frame),
// a bound on its remaining error per component, the outward unit normal there (for a disc +y)
// and its texture coordinates (docs/wsd-language.md: cylinder, cone, torus, disc).
struct QuadricPoint {
    Vec3 p, p_error, n;
    Vec2 uv;
};
QuadricPoint quadric_part_surface(const QuadricPrim& q, int part, const Vec3& o, const Vec3& d, double t);

// The point p (canonical frame) in the shape's object frame.
inline Vec3 quadric_to_object(const QuadricPrim& q, const Vec3& p) {
    return q.origin + p.x * q.axis_x + p.y * q.axis_y + p.z * q.axis_z;
}

}  // namespace wsd::render
