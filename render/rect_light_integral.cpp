// Closed form of (1/A)∫ N·(p−x)/|p−x| dA over a parallelogram (see the header).
//
// With x0 the foot of x on the light's plane, unit plane normal m, d = m·(c − x) and
// ρ = p − x0, p − x = ρ + d·m and r = √(|ρ|² + d²). Then
//   ∫ N·(p−x)/r dA = (N·m)·d·∫ 1/r dA + N_t·∫ ρ/r dA,   N_t = N − (N·m)·m.
// ρ/r is the in-plane gradient of r, so ∫ ρ/r dA = Σ_edges n_e ∫_e r ds (n_e the outward edge
// normal). ρ·(r − |d|)/|ρ|² has divergence 1/r, so ∫ 1/r dA = Σ_e a_e ∫_e dt/(r + |d|), with a_e the
// signed distance of x0 from edge e's line; per edge that is a_e·asinh(t/b)|, b² = a_e² + d², and
// the atan parts sum to −|d|·Ω with Ω the solid angle of the light (Van Oosterom–Strackee).
// The edge sum for ∫ ρ/r dA cancels like R/size for a far point, so beyond four light diameters
// the integrand, analytic there, is integrated by Gauss–Legendre with an order that keeps the
// error below double rounding.
#include "render/rect_light_integral.h"

#include <array>
#include <cmath>
#include <glm/glm.hpp>

namespace wsd::render {
namespace {

// asinh(t1/b) − asinh(t0/b) for t0 ≤ t1, b ≥ 0, without cancellation.
double asinh_diff(double t0, double t1, double b, double r0, double r1) {
    const double len = t1 - t0;
    const double sum = (t1 + t0) / (r1 + r0);  // (r1 − r0)/len
    if (t0 >= 0) return std::log1p(len * (1 + sum) / (t0 + r0));
    if (t1 <= 0) return std::log1p(len * (1 - sum) / (r1 - t1));
    return std::asinh(t1 / b) + std::asinh(-t0 / b);
}

// Signed solid angle of triangle (a, b, c) seen from the origin.
double solid_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    const double num = glm::dot(a, glm::cross(b, c));
    const double den = la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
    return 2.0 * std::atan2(num, den);
}

// Gauss–Legendre nodes and weights on [0, 1].
template <int N>
struct GaussLegendre {
    std::array<double, N> x{}, w{};
    GaussLegendre() {
        for (int i = 0; i < N; ++i) {
            double z = std::cos(3.14159265358979323846 * (i + 0.75) / (N + 0.5));
            double dp = 1;
            for (int it = 0; it < 100; ++it) {
                double p0 = 1, p1 = z;
                for (int k = 2; k <= N; ++k) {
                    const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
                    p0 = p1;
                    p1 = p2;
                }
                dp = N * (z * p1 - p0) / (z * z - 1);
                const double dz = p1 / dp;
                z -= dz;
                if (std::abs(dz) < 1e-17) break;
            }
            x[i] = 0.5 * (1 - z);
            w[i] = 1.0 / ((1 - z * z) * dp * dp);
        }
    }
};

template <int N>
double gauss_average(const Vec3& x, const Vec3& n, const Vec3& c, const Vec3& u, const Vec3& v) {
    static const GaussLegendre<N> g;
    const Vec3 q = c - x;
    double sum = 0;
    for (int i = 0; i < N; ++i) {
        double row = 0;
        for (int j = 0; j < N; ++j) {
            const Vec3 p = q + g.x[i] * u + g.x[j] * v;
            row += g.w[j] * glm::dot(n, p) / glm::length(p);
        }
        sum += g.w[i] * row;
    }
    return sum;
}

}  // namespace

double rect_light_average_cosine(const Vec3& x, const Vec3& n, const Vec3& c, const Vec3& u, const Vec3& v) {
    const Vec3 uxv = glm::cross(u, v);
    const double area = glm::length(uxv);
    if (!(area > 0) || !std::isfinite(area)) return 0;
    // Far: the integrand is analytic over the light; Gauss–Legendre of an order for which the
    // error, ~(4R/D)^(−2n), is below double rounding.
    const double diam = glm::length(u) + glm::length(v);
    const double near_dist = glm::length(c + 0.5 * (u + v) - x) - 0.5 * diam;
    const double ratio = near_dist / diam;
    if (ratio > 256) return gauss_average<4>(x, n, c, u, v);
    if (ratio > 16) return gauss_average<6>(x, n, c, u, v);
    if (ratio > 4) return gauss_average<8>(x, n, c, u, v);

    const Vec3 m = uxv / area;
    const Vec3 q = c - x;  // corner 0 relative to x
    const double d = glm::dot(m, q);
    const double ad = std::abs(d);
    const std::array<Vec3, 4> P{q, q + u, q + u + v, q + v};  // counter-clockwise about m
    double j_sum = 0;                                         // Σ a_e·asinh diff
    Vec3 k_sum{0, 0, 0};                                      // Σ n_e ∫ r ds
    for (int e = 0; e < 4; ++e) {
        const Vec3& p0 = P[e];
        const Vec3& p1 = P[(e + 1) % 4];
        const Vec3 edge = p1 - p0;
        const double len = glm::length(edge);
        const Vec3 dir = edge / len;
        const Vec3 out = glm::cross(dir, m);  // outward in-plane normal
        const double a = glm::dot(p0, out);   // signed distance of the foot from the edge's line
        const double t0 = glm::dot(p0, dir);
        const double t1 = t0 + len;
        const double b = std::sqrt(a * a + d * d);
        const double r0 = glm::length(p0), r1 = glm::length(p1);
        const double ash = b > 0 ? asinh_diff(t0, t1, b, r0, r1) : 0.0;
        j_sum += a * ash;
        // ∫ r dt = ½ [t·r + b²·asinh(t/b)]
        const double ir = 0.5 * ((t1 * r1 - t0 * r0) + b * b * ash);
        k_sum += ir * out;
    }
    const double omega = std::abs(solid_angle(P[0], P[1], P[2]) + solid_angle(P[0], P[2], P[3]));
    const double j = j_sum - ad * omega;  // ∫ 1/r dA
    const double nm = glm::dot(n, m);
    const Vec3 nt = n - nm * m;
    // p − x = ρ + d·m: the normal part is (N·m)·d·∫ 1/r dA.
    return (nm * d * j + glm::dot(nt, k_sum)) / area;
}

}  // namespace wsd::render
