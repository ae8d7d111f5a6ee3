// The UV maps of the shapes (sphere map, unfolded-cube box map, plane axes), as
// wsd-language.md §4 defines them. The per-ray precomputation and the intersection tests are
// inline in shapes.h so that traversal loops can inline them.
#include "render/shapes.h"

#include <cmath>

namespace wsd::render {

Vec2 box_uv(const Vec3& p, const Vec3& lo, const Vec3& hi, int face) {
    // Each face as seen from outside, upright (screen right = cross(up, forward) as for the
    // camera): the middle row runs −x, −z, +x, +z; +y sits above −z and −y below it.
    Vec3 e = hi - lo;
    auto frac = [](double num, double den) {
        double f = num / den;
        return f < 0 ? 0.0 : (f > 1 ? 1.0 : f);
    };
    double s = 0, t = 0;
    int col = 1, row = 1;
    switch (face) {
        case 0:  // −x: right is −z
            col = 0;
            s = frac(hi.z - p.z, e.z);
            t = frac(hi.y - p.y, e.y);
            break;
        case 1:  // +x: right is +z
            col = 2;
            s = frac(p.z - lo.z, e.z);
            t = frac(hi.y - p.y, e.y);
            break;
        case 2:  // −y: top edge meets −z's bottom edge
            row = 2;
            s = frac(p.x - lo.x, e.x);
            t = frac(p.z - lo.z, e.z);
            break;
        case 3:  // +y: bottom edge meets −z's top edge
            row = 0;
            s = frac(p.x - lo.x, e.x);
            t = frac(hi.z - p.z, e.z);
            break;
        case 4:  // −z: right is +x
            s = frac(p.x - lo.x, e.x);
            t = frac(hi.y - p.y, e.y);
            break;
        default:  // +z: right is −x
            col = 3;
            s = frac(hi.x - p.x, e.x);
            t = frac(hi.y - p.y, e.y);
            break;
    }
    return {(col + s) / 4.0, (row + t) / 3.0};
}

Vec2 sphere_uv(const Vec3& n) {
    double u = 0.5 + std::atan2(n.x, -n.z) / (2 * kPi);
    // atan2(±0, negative) = ±π puts the seam at exactly 1 or 0; both are the same texel column.
    if (!(u < 1)) u = 0;
    if (u < 0) u = 0;
    double v = 0.5 - safe_asin(n.y) / kPi;
    v = v < 0 ? 0.0 : (v > 1 ? 1.0 : v);
    return {u, v};
}

Vec3 plane_u_axis(const Vec3& n) {
    // x − (x·n)n = (1 − nx², −nx·ny, −nx·nz), and 1 − nx² = ny² + nz² for a unit n: no
    // cancellation when n is close to ±x.
    double s = std::sqrt(n.y * n.y + n.z * n.z);
    if (s == 0) return {0, 0, 1};
    Vec3 u(s, -n.x * n.y / s, -n.x * n.z / s);
    return u / glm::length(u);
}

}  // namespace wsd::render
