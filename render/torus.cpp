// The torus's line crossings: a quartic, solved so that its roots stay accurate for grazing
// lines, for lines from far away and for tori of any size (docs/robustness.md, the torus quartic).
//
// 1. The origin moves to the line's point closest to the centre (and the direction becomes a
//    unit vector), so the coefficients are those of a line passing within the torus's bounding
//    sphere, whatever the distance it came from, in the torus's own units.
// 2. The quartic's real roots are isolated by its derivatives: the roots of f'' (a quadratic)
//    split f' into monotone pieces, whose roots split f into monotone pieces, each holding at most
//    one root of f. No closed-form (Ferrari) solution, whose cancellations lose grazing roots.
// 3. Each piece whose ends differ in sign is solved on the accurate implicit function
//    (ρ − R)² + y² − r² by Newton's method kept in the bracket, one of the quartic's two
//    factors: the other, (ρ + R)² + y² − r², vanishes only on a spindle torus's inner "lemon",
//    which is not part of the surface.
#include <algorithm>
#include <cmath>

#include "render/quadric_solve.h"

namespace wsd::render::detail {

namespace {

double horner(const double* c, int degree, double x) {
    double v = c[degree];
    for (int i = degree - 1; i >= 0; --i) v = v * x + c[i];
    return v;
}

// A root of g in [lo, hi] where g(lo) and g(hi) differ in sign: Newton's method from the secant
// point, kept inside the shrinking bracket (a step that leaves it bisects instead), until a step
// moves by at most one ULP. `gd(x, g, dg)` gives the value and the derivative.
template <class GD>
double refine(GD gd, double lo, double hi, double glo, double ghi) {
    double x = (lo * ghi - hi * glo) / (ghi - glo);
    if (!(x > lo && x < hi)) x = 0.5 * (lo + hi);
    for (int i = 0; i < 100; ++i) {
        double g, dg;
        gd(x, g, dg);
        if (g == 0) return x;
        if ((g < 0) == (glo < 0))
            lo = x;
        else
            hi = x;
        double next = x - g / dg;
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) return x;  // the bracket is two adjacent doubles
        if (next == x || next == next_float_up(x) || next == next_float_down(x)) return next;
        x = next;
    }
    return x;
}

// The roots of the polynomial c (degree 2 or 3) in (lo, hi), ascending, given its derivative's
// roots there (`crit`, ascending): one per monotone piece whose ends differ in sign.
int roots_between(const double* c, int degree, const double* crit, int n_crit, double lo, double hi,
                  double* out) {
    double pts[4];
    int np = 0;
    pts[np++] = lo;
    for (int i = 0; i < n_crit; ++i)
        if (crit[i] > lo && crit[i] < hi) pts[np++] = crit[i];
    pts[np++] = hi;
    double dc[3];
    for (int i = 1; i <= degree; ++i) dc[i - 1] = i * c[i];
    auto g = [&](double x) { return horner(c, degree, x); };
    auto gd = [&](double x, double& v, double& dv) {
        v = horner(c, degree, x);
        dv = horner(dc, degree - 1, x);
    };
    int n = 0;
    for (int i = 0; i + 1 < np; ++i) {
        const double a = pts[i], b = pts[i + 1];
        const double ga = g(a), gb = g(b);
        if (ga == 0) {
            if (i > 0) out[n++] = a;
            continue;
        }
        if ((ga < 0) != (gb < 0) && gb != 0) out[n++] = refine(gd, a, b, ga, gb);
    }
    return n;
}

// The real roots of c2·x² + c1·x + c0 (c2 ≠ 0), ascending.
int quadratic_roots(double c2, double c1, double c0, double* out) {
    const double disc = difference_of_products(c1, c1, 4 * c2, c0);
    if (disc < 0) return 0;
    const double q = -0.5 * (c1 + std::copysign(std::sqrt(disc), c1));
    if (q == 0) {
        out[0] = 0;
        return 1;
    }
    double a = q / c2, b = c0 / q;
    if (a > b) std::swap(a, b);
    out[0] = a;
    out[1] = b;
    return 2;
}

// The quartic f(s) = (|p|² + R² − r²)² − 4R²(px² + pz²) for p = c + s·u, expanded: f[k] is the
// coefficient of s^k.
void torus_quartic(double major, double minor, const Vec3& c, const Vec3& u, double* f) {
    const double e = glm::dot(u, u);
    const double b = glm::dot(c, u);
    const double g = glm::dot(c, c) + (major * major - minor * minor);
    const double r4 = 4 * major * major;
    f[4] = e * e;
    f[3] = 4 * e * b;
    f[2] = 4 * b * b + 2 * e * g - r4 * (u.x * u.x + u.z * u.z);
    f[1] = 4 * b * g - 2 * r4 * (c.x * u.x + c.z * u.z);
    f[0] = g * g - r4 * (c.x * c.x + c.z * c.z);
}

// The interval of s that can hold a root: the bounding sphere's (|p| ≤ R + r) cut by the slab
// |y| ≤ r, widened by 2^-20 of the size (beyond either bound the implicit function is positive,
// so any widening keeps the ends outside the tube). False when it is empty.
bool torus_bracket(double major, double minor, const Vec3& c, const Vec3& u, double& lo, double& hi) {
    const double reach = major + minor;
    const double cc = glm::dot(c, c);
    if (cc > reach * reach * (1 + gamma(8))) return false;  // the line passes the bounding sphere
    const double pad = 0x1p-20 * reach;
    lo = -std::sqrt(std::max(0.0, reach * reach - cc)) - std::abs(glm::dot(c, u)) - pad;
    hi = -lo;
    if (u.y != 0) {
        double y0 = (-minor - c.y) / u.y, y1 = (minor - c.y) / u.y;
        if (y0 > y1) std::swap(y0, y1);
        lo = std::max(lo, y0 - pad);
        hi = std::min(hi, y1 + pad);
    } else if (std::abs(c.y) > minor) {
        return false;
    }
    return lo < hi;
}

// When the origin o (error oe) lies on the surface, within its error bound: how far from it, in
// distance, the root of that surface may land; otherwise −1.
double torus_self_reach(double major, double minor, const Vec3& o, const Vec3& oe) {
    const double rho = std::sqrt(o.x * o.x + o.z * o.z);
    const double a = rho - major;
    const double f = (a * a + o.y * o.y) - minor * minor;
    const double err_f = gamma(6) * (2 * std::abs(a) * (rho + major) + o.y * o.y + minor * minor) +
                         2 * (std::abs(a) * (oe.x + oe.z) + std::abs(o.y) * oe.y);
    if (!(std::abs(f) <= err_f)) return -1;
    const double oe_max = std::max({oe.x, oe.y, oe.z});
    const double o_max = std::max({std::abs(o.x), std::abs(o.y), std::abs(o.z)});
    return 16 * (gamma(4) * (o_max + major + minor) + oe_max) + 2 * err_f / minor;
}

}  // namespace

int torus_crossings(const QuadricPrim& q, const Vec3& o, const Vec3& d, const Vec3& oe, Crossing* out) {
    const double len = std::sqrt(glm::dot(d, d));
    if (!(len > 0) || !std::isfinite(len)) return 0;
    const Vec3 u = d / len;
    // The point of the line closest to the centre: s measures from it in unit steps.
    const double t0 = -glm::dot(o, u);
    // Lengths below are in units of about the torus's size (a power of two, so that the scaling
    // is exact): the quartic's coefficients go with the fourth power of its size, which would
    // underflow or overflow for a torus far from unit size.
    const double unit = std::ldexp(1.0, std::ilogb(q.r0 + q.r1));
    const double major = q.r0 / unit, minor = q.r1 / unit;
    const Vec3 c = (o + t0 * u) / unit;
    double lo, hi;
    if (!torus_bracket(major, minor, c, u, lo, hi)) return 0;

    // Breakpoints: the roots of f' between the roots of f''; f is monotone between them.
    double f[5];
    torus_quartic(major, minor, c, u, f);
    const double d3[4] = {f[1], 2 * f[2], 3 * f[3], 4 * f[4]};
    double crit2[2], pts[5];
    const int n2 = quadratic_roots(12 * f[4], 6 * f[3], 2 * f[2], crit2);
    int np = 1 + roots_between(d3, 3, crit2, n2, lo, hi, pts + 1);
    pts[0] = lo;
    pts[np++] = hi;

    auto implicit = [&](double s) { return torus_f(major, minor, c + s * u); };
    // (ρ − R)² + y² − r² and its derivative along u: 2(ρ − R)·(p_xz·u_xz)/ρ + 2·y·u_y (NaN on
    // the axis, where a step bisects).
    auto implicit_d = [&](double s, double& v, double& dv) {
        const Vec3 p = c + s * u;
        const double rho = std::sqrt(p.x * p.x + p.z * p.z);
        const double a = rho - major;
        v = (a * a + p.y * p.y) - minor * minor;
        dv = 2 * (a * (p.x * u.x + p.z * u.z) / rho + p.y * u.y);
    };
    const double self_reach = torus_self_reach(q.r0, q.r1, o, oe);  // in the frame's own lengths

    int n = 0;
    double gprev = implicit(pts[0]);
    for (int i = 0; i + 1 < np && n < kMaxCrossings; ++i) {
        const double gnext = implicit(pts[i + 1]);
        double s;
        if (gnext == 0 && i + 2 < np) {
            s = pts[i + 1];
        } else if ((gprev < 0) != (gnext < 0) && gprev != 0) {
            s = refine(implicit_d, pts[i], pts[i + 1], gprev, gnext);
        } else {
            gprev = gnext;
            continue;
        }
        gprev = gnext;
        s *= unit;
        out[n++] = {(t0 + s) / len, kQuadricBody, std::abs(t0 + s) <= self_reach};
    }
    return n;
}

}  // namespace wsd::render::detail
