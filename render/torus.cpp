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
//    (ρ − R)² + y² − r², one of the quartic's two factors: the other, (ρ + R)² + y² − r², vanishes
//    only on a spindle torus's inner "lemon", which is not part of the surface.
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

// A root of g in [lo, hi] where g(lo) and g(hi) differ in sign: regula falsi (Illinois) with a
// bisection every third step, until the bracket cannot shrink.
template <class G>
double refine(G g, double lo, double hi, double glo, double ghi) {
    int side = 0;
    for (int i = 0; i < 200; ++i) {
        double m;
        if (i % 3 == 2 || glo == ghi) {
            m = 0.5 * (lo + hi);
        } else {
            m = (lo * ghi - hi * glo) / (ghi - glo);
            if (!(m > lo && m < hi)) m = 0.5 * (lo + hi);
        }
        if (!(m > lo && m < hi)) break;  // adjacent doubles
        const double gm = g(m);
        if (gm == 0) return m;
        if ((gm < 0) == (glo < 0)) {
            lo = m, glo = gm;
            if (side == -1) ghi *= 0.5;
            side = -1;
        } else {
            hi = m, ghi = gm;
            if (side == 1) glo *= 0.5;
            side = 1;
        }
    }
    return 0.5 * (lo + hi);
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
    auto g = [&](double x) { return horner(c, degree, x); };
    int n = 0;
    for (int i = 0; i + 1 < np; ++i) {
        const double a = pts[i], b = pts[i + 1];
        const double ga = g(a), gb = g(b);
        if (ga == 0) {
            if (i > 0) out[n++] = a;
            continue;
        }
        if ((ga < 0) != (gb < 0) && gb != 0) out[n++] = refine(g, a, b, ga, gb);
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

}  // namespace

int torus_crossings(const QuadricPrim& q, const Vec3& o, const Vec3& d, const Vec3& oe, Crossing* out) {
    const double major = q.r0, minor = q.r1;
    const double len = std::sqrt(glm::dot(d, d));
    if (!(len > 0) || !std::isfinite(len)) return 0;
    const Vec3 u = d / len;
    // The point of the line closest to the centre: s measures from it in unit steps.
    const double t0 = -glm::dot(o, u);
    const Vec3 c = o + t0 * u;
    const double reach = major + minor;  // the bounding sphere's radius
    const double cc = glm::dot(c, c);
    if (cc > reach * reach * (1 + gamma(8))) return 0;

    // f(s) = (|p|² + R² − r²)² − 4R²(px² + pz²) for p = c + s·u, expanded.
    const double e = glm::dot(u, u);
    const double b = glm::dot(c, u);
    const double g = cc + (major * major - minor * minor);
    const double uxz = u.x * u.x + u.z * u.z;
    const double cuxz = c.x * u.x + c.z * u.z;
    const double cxz = c.x * c.x + c.z * c.z;
    const double r4 = 4 * major * major;
    double f[5];
    f[4] = e * e;
    f[3] = 4 * e * b;
    f[2] = 4 * b * b + 2 * e * g - r4 * uxz;
    f[1] = 4 * b * g - 2 * r4 * cuxz;
    f[0] = g * g - r4 * cxz;
    const double d3[4] = {f[1], 2 * f[2], 3 * f[3], 4 * f[4]};

    // Every root has |p| ≤ R + r, so |s| ≤ R + r; the bracket is a little wider than that.
    const double span = reach * 1.0625 + std::abs(b);
    double crit2[2], crit3[3];
    const int n2 = quadratic_roots(12 * f[4], 6 * f[3], 2 * f[2], crit2);
    const int n3 = roots_between(d3, 3, crit2, n2, -span, span, crit3);

    auto implicit = [&](double s) { return torus_f(major, minor, c + s * u); };
    double pts[5];
    int np = 0;
    pts[np++] = -span;
    for (int i = 0; i < n3; ++i) pts[np++] = crit3[i];
    pts[np++] = span;

    // The origin's own surface: the implicit function at o vanishes within its error bound.
    const double rho_o = std::sqrt(o.x * o.x + o.z * o.z);
    const double a_o = rho_o - major;
    const double f_o = (a_o * a_o + o.y * o.y) - minor * minor;
    const double err_f = gamma(6) * (2 * std::abs(a_o) * (rho_o + major) + o.y * o.y + minor * minor) +
                         2 * (std::abs(a_o) * (oe.x + oe.z) + std::abs(o.y) * oe.y);
    const bool on_surface = std::abs(f_o) <= err_f;
    const double oe_max = std::max({oe.x, oe.y, oe.z});
    const double o_max = std::max({std::abs(o.x), std::abs(o.y), std::abs(o.z)});
    // How far from t = 0 the root of the origin's own surface may land, in distance.
    const double self_reach = 16 * (gamma(4) * (o_max + reach) + oe_max) + 2 * err_f / minor;

    int n = 0;
    double gprev = implicit(pts[0]);
    for (int i = 0; i + 1 < np && n < kMaxCrossings; ++i) {
        const double gnext = implicit(pts[i + 1]);
        double s;
        if (gnext == 0 && i + 2 < np) {
            s = pts[i + 1];
        } else if ((gprev < 0) != (gnext < 0) && gprev != 0) {
            s = refine(implicit, pts[i], pts[i + 1], gprev, gnext);
        } else {
            gprev = gnext;
            continue;
        }
        gprev = gnext;
        const double t = (t0 + s) / len;
        out[n++] = {t, kQuadricBody, on_surface && std::abs(t0 + s) <= self_reach};
    }
    return n;
}

}  // namespace wsd::render::detail
