// Line crossings of cylinders, cones and discs in their canonical frame (axis +y): the body's
// quadratic with stable roots, the end caps and the disc as planes, each crossing marked when it
// is the surface the origin lies on. The torus is in render/torus.cpp.
#include "render/quadric_solve.h"

#include <algorithm>
#include <cmath>

namespace wsd::render::detail {

namespace {

// The body's quadratic a·t² + 2b·t + c for the line o + t·d, with bounds on the errors of b and c
// (oe bounds the error already in o).
struct BodyQuadratic {
    double a, b, c, scale_c, err_a, err_b, err_c;
};

BodyQuadratic body_quadratic(double k, double r0, const Vec3& o, const Vec3& d, const Vec3& oe) {
    BodyQuadratic f;
    const double rho = r0 + k * o.y;  // the body's radius at the origin's height
    f.a = d.x * d.x + d.z * d.z - (k * d.y) * (k * d.y);
    f.b = o.x * d.x + o.z * d.z - (k * rho) * d.y;
    f.c = o.x * o.x + o.z * o.z - rho * rho;
    f.scale_c = o.x * o.x + o.z * o.z + rho * rho;
    f.err_a = gamma(4) * (d.x * d.x + d.z * d.z + (k * d.y) * (k * d.y));
    f.err_b = gamma(6) * (std::abs(o.x * d.x) + std::abs(o.z * d.z) + std::abs(k * rho * d.y)) +
              oe.x * std::abs(d.x) + oe.z * std::abs(d.z) + std::abs(k * k * d.y) * oe.y;
    f.err_c = gamma(8) * f.scale_c +
              2 * (std::abs(o.x) * oe.x + std::abs(o.z) * oe.z + std::abs(rho * k) * oe.y) +
              (oe.x * oe.x + oe.z * oe.z + k * k * oe.y * oe.y);
    return f;
}

// The body quadratic's discriminant b² − ac at origin os, or false when there is no real root.
bool body_discriminant(const BodyQuadratic& f, double k, double r0, const Vec3& os, const Vec3& d,
                       double& disc) {
    if (k == 0) {
        // Haines et al.: the discriminant from the axis-to-closest-point vector, no b² − ac.
        const double s = f.b / f.a;
        const double lx = os.x - s * d.x, lz = os.z - s * d.z;
        disc = f.a * (r0 * r0 - (lx * lx + lz * lz));
        return disc >= 0;
    }
    disc = difference_of_products(f.b, f.b, f.a, f.c);
    // A line through the apex meets the double cone in a double root: the discriminant is zero
    // up to the error of its terms, and so is taken to be (a square root of that error would
    // move the root by about √ε).
    const double err_disc = gamma(4) * (f.b * f.b + std::abs(f.a * f.c)) + 2 * std::abs(f.b) * f.err_b +
                            std::abs(f.a) * f.err_c + std::abs(f.c) * f.err_a;
    if (!(disc >= -err_disc)) return false;
    if (disc <= err_disc) disc = 0;
    return true;
}

// The body x² + z² = (r0 + k·y)², 0 ≤ y ≤ h, with k = (r1 − r0)/h (0 for a cylinder).
int body_crossings(const QuadricPrim& q, const Vec3& o, const Vec3& d, const Vec3& oe, Crossing* out) {
    const double k = q.kind == ShapeKind::Cylinder ? 0.0 : (q.r1 - q.r0) / q.h;
    // Whether the origin lies on the body, from the origin as given.
    const BodyQuadratic at_o = body_quadratic(k, q.r0, o, d, oe);
    const bool on_surface = std::abs(at_o.c) <= at_o.err_c;
    // The roots from the line's point closest to the body's middle, so that the coefficients are
    // those of a line through the body, in its own units, however far the origin is.
    const Vec3 mid(0, 0.5 * q.h, 0);
    const double t0 = -glm::dot(o - mid, d) / glm::dot(d, d);
    const Vec3 os = o + t0 * d;
    const Vec3 oes = oe + gamma(3) * (abs3(o) + abs3(t0 * d));
    const BodyQuadratic f = body_quadratic(k, q.r0, os, d, oes);
    const double a = f.a, b = f.b, c = f.c;
    if (a == 0 && b == 0) return 0;  // along the axis of a cylinder, or a line on a cone's nappe
    double disc;
    if (!body_discriminant(f, k, q.r0, os, d, disc)) return 0;
    const double qq = -(b + std::copysign(std::sqrt(disc), b));
    double roots[2];  // from os
    int n = 0;
    if (qq != 0) roots[n++] = c / qq;
    if (a != 0) roots[n++] = qq / a;
    // The origin's own surface is the root nearest t = 0; the other one only within its error.
    int self_root = -1;
    double delta = 0;
    if (on_surface && n > 0) {
        self_root = (n == 2 && std::abs(t0 + roots[1]) < std::abs(t0 + roots[0])) ? 1 : 0;
        delta = (2 * at_o.err_b + std::sqrt(std::abs(at_o.a) * (gamma(10) * at_o.scale_c + 2 * at_o.err_c))) /
                std::abs(at_o.a);
    }
    int m = 0;
    for (int i = 0; i < n; ++i) {
        const double s = roots[i];
        const double t = t0 + s;
        if (!std::isfinite(t)) continue;
        // The root's own error (first order in the coefficients' errors; a double root's is
        // the square root of that), carried to y so that a root at the apex or a rim stays in.
        const double shift = s * s * f.err_a + 2 * std::abs(s) * f.err_b + f.err_c;
        const double slope = 2 * std::abs(a * s + b);
        const double err_s = disc == 0 ? std::sqrt(shift / std::abs(a)) : shift / slope;
        const double y = os.y + s * d.y;
        const double ey = gamma(3) * (std::abs(os.y) + std::abs(s * d.y)) + oes.y +
                          (std::isfinite(err_s) ? err_s * std::abs(d.y) : 0.0);
        if (!(y >= -ey && y <= q.h + ey)) continue;
        const bool self = i == self_root || (on_surface && std::abs(t) <= delta);
        out[m++] = {t, kQuadricBody, self};
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
