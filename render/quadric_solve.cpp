// Line crossings of cylinders, cones and discs in their canonical frame (axis +y): the body's
// quadratic with stable roots, the end caps and the disc as planes, each crossing marked when it
// is the surface the origin lies on. The torus is in render/torus.cpp.
#include "render/quadric_solve.h"

#include <algorithm>
#include <cmath>

namespace wsd::render::detail {

namespace {

// The body x² + z² = (r0 + k·y)², 0 ≤ y ≤ h, with k = (r1 − r0)/h (0 for a cylinder).
int body_crossings(const QuadricPrim& q, const Vec3& o, const Vec3& d, const Vec3& oe, Crossing* out) {
    const double k = q.kind == ShapeKind::Cylinder ? 0.0 : (q.r1 - q.r0) / q.h;
    const double rho = q.r0 + k * o.y;  // the body's radius at the origin's height
    const double a = d.x * d.x + d.z * d.z - (k * d.y) * (k * d.y);
    const double b = o.x * d.x + o.z * d.z - (k * rho) * d.y;
    const double c = o.x * o.x + o.z * o.z - rho * rho;
    const double scale_c = o.x * o.x + o.z * o.z + rho * rho;
    const double err_b = gamma(6) * (std::abs(o.x * d.x) + std::abs(o.z * d.z) + std::abs(k * rho * d.y)) +
                         oe.x * std::abs(d.x) + oe.z * std::abs(d.z) + std::abs(k * k * d.y) * oe.y;
    const double err_c = gamma(8) * scale_c +
                         2 * (std::abs(o.x) * oe.x + std::abs(o.z) * oe.z + std::abs(rho * k) * oe.y) +
                         (oe.x * oe.x + oe.z * oe.z + k * k * oe.y * oe.y);
    const double err_a = gamma(4) * (d.x * d.x + d.z * d.z + (k * d.y) * (k * d.y));
    if (a == 0 && b == 0) return 0;  // along the axis of a cylinder, or a line on a cone's nappe
    double disc;
    if (k == 0) {
        // Haines et al.: the discriminant from the axis-to-closest-point vector, no b² − ac.
        const double s = b / a;
        const double lx = o.x - s * d.x, lz = o.z - s * d.z;
        disc = a * (q.r0 * q.r0 - (lx * lx + lz * lz));
        if (!(disc >= 0)) return 0;
    } else {
        disc = difference_of_products(b, b, a, c);
        // A line through the apex meets the double cone in a double root: the discriminant is
        // zero up to the error of its terms, and so is taken to be (a square root of that error
        // would move the root by about √ε).
        const double err_disc = gamma(4) * (b * b + std::abs(a * c)) + 2 * std::abs(b) * err_b +
                                std::abs(a) * err_c + std::abs(c) * err_a;
        if (!(disc >= -err_disc)) return 0;
        if (disc <= err_disc) disc = 0;
    }
    const double qq = -(b + std::copysign(std::sqrt(disc), b));
    const bool on_surface = std::abs(c) <= err_c;
    double roots[2];
    bool self[2] = {false, false};
    int n = 0;
    if (qq != 0) {
        roots[n] = c / qq;  // the root that tends to 0 as the origin nears the surface
        self[n++] = on_surface;
    }
    if (a != 0) {
        roots[n] = qq / a;
        if (on_surface) {
            const double delta =
                (2 * err_b + std::sqrt(std::abs(a) * (gamma(10) * scale_c + 2 * err_c))) / std::abs(a);
            self[n] = std::abs(roots[n]) <= delta;
        }
        ++n;
    }
    int m = 0;
    for (int i = 0; i < n; ++i) {
        const double t = roots[i];
        if (!std::isfinite(t)) continue;
        // The root's own error (first order in the coefficients' errors; a double root's is
        // the square root of that), carried to y so that a root at the apex or a rim stays in.
        const double shift = t * t * err_a + 2 * std::abs(t) * err_b + err_c;
        const double slope = 2 * std::abs(a * t + b);
        const double err_t = disc == 0 ? std::sqrt(shift / std::abs(a)) : shift / slope;
        const double y = o.y + t * d.y;
        const double ey = gamma(3) * (std::abs(o.y) + std::abs(t * d.y)) + oe.y +
                          (std::isfinite(err_t) ? err_t * std::abs(d.y) : 0.0);
        if (!(y >= -ey && y <= q.h + ey)) continue;
        out[m++] = {t, kQuadricBody, self[i]};
    }
    return m;
}

// The plane y = yc within radius `outer` and outside radius `inner` (an end cap or the disc).
// Caps (`widen`) are closed at their rim by the rim point's own error, so that a line through
// the rim meets the cap or the body.
int plane_crossing(double yc, double inner, double outer, bool widen, int part, const Vec3& o, const Vec3& d,
                   const Vec3& oe, Crossing* out) {
    if (d.y == 0) return 0;
    const double gap = yc - o.y;
    const double t = gap / d.y;
    if (!std::isfinite(t)) return 0;
    const double x = o.x + t * d.x, z = o.z + t * d.z;
    const double r2 = x * x + z * z;
    double tol = 0;
    if (widen) {
        const double e =
            gamma(4) * (std::abs(o.x) + std::abs(t * d.x) + std::abs(o.z) + std::abs(t * d.z)) + oe.x + oe.z;
        tol = 2 * outer * e + e * e;
    }
    if (!(r2 <= outer * outer + tol) || r2 < inner * inner) return 0;
    const bool self = std::abs(gap) <= oe.y + gamma(2) * std::abs(gap);
    out[0] = {t, part, self};
    return 1;
}

}  // namespace

int line_crossings(const QuadricPrim& q, const Vec3& o, const Vec3& d, const Vec3& o_err, Crossing* out) {
    int n = 0;
    switch (q.kind) {
        case ShapeKind::Torus:
            n = torus_crossings(q, o, d, o_err, out);
            break;
        case ShapeKind::Disc:
            return plane_crossing(0, q.r1, q.r0, false, kQuadricBody, o, d, o_err, out);
        default:
            n = body_crossings(q, o, d, o_err, out);
            if (!q.open) {
                if (q.r0 > 0) n += plane_crossing(0, 0, q.r0, true, kQuadricBaseCap, o, d, o_err, out + n);
                if (q.r1 > 0) n += plane_crossing(q.h, 0, q.r1, true, kQuadricTopCap, o, d, o_err, out + n);
            }
            break;
    }
    std::sort(out, out + n, [](const Crossing& a, const Crossing& b) { return a.t < b.t; });
    return n;
}

}  // namespace wsd::render::detail
