// The closed-form parallelogram-light average against adaptive Gauss–Legendre cubature
// (robustness.md, closed-form light): random, near-plane, grazing, very near, very far and skewed.
#include <catch2/catch.hpp>
#include <cmath>
#include <glm/glm.hpp>
#include <random>
#include <vector>

#include "render/rect_light_integral.h"

using wsd::render::rect_light_average_cosine;
using wsd::render::Vec3;

namespace {

constexpr int kOrder = 10;

struct Rule {
    double x[kOrder], w[kOrder];
    Rule() {
        for (int i = 0; i < kOrder; ++i) {
            double z = std::cos(M_PI * (i + 0.75) / (kOrder + 0.5)), dp = 1;
            for (int it = 0; it < 100; ++it) {
                double p0 = 1, p1 = z;
                for (int k = 2; k <= kOrder; ++k) {
                    const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
                    p0 = p1;
                    p1 = p2;
                }
                dp = kOrder * (z * p1 - p0) / (z * z - 1);
                z -= p1 / dp;
            }
            x[i] = 0.5 * (1 - z);
            w[i] = 1.0 / ((1 - z * z) * dp * dp);
        }
    }
};

struct Problem {
    Vec3 x, n, c, u, v;
    double f(double s, double t) const {
        const Vec3 p = c + s * u + t * v - x;
        return glm::dot(n, p) / glm::length(p);
    }
    double rect(double s0, double s1, double t0, double t1) const {
        static const Rule g;
        double sum = 0;
        for (int i = 0; i < kOrder; ++i)
            for (int j = 0; j < kOrder; ++j)
                sum += g.w[i] * g.w[j] * f(s0 + (s1 - s0) * g.x[i], t0 + (t1 - t0) * g.x[j]);
        return sum * (s1 - s0) * (t1 - t0);
    }
    // Adaptive: accept a rectangle when its four children agree with it to tol.
    double adapt(double s0, double s1, double t0, double t1, double whole, double tol, int depth) const {
        const double sm = 0.5 * (s0 + s1), tm = 0.5 * (t0 + t1);
        const double a = rect(s0, sm, t0, tm), b = rect(sm, s1, t0, tm), c2 = rect(s0, sm, tm, t1),
                     d = rect(sm, s1, tm, t1);
        const double fine = a + b + c2 + d;
        if (std::abs(fine - whole) <= tol || depth > 40) return fine;
        return adapt(s0, sm, t0, tm, a, tol / 2, depth + 1) + adapt(sm, s1, t0, tm, b, tol / 2, depth + 1) +
               adapt(s0, sm, tm, t1, c2, tol / 2, depth + 1) + adapt(sm, s1, tm, t1, d, tol / 2, depth + 1);
    }
    double reference() const {
        const double whole = rect(0, 1, 0, 1);
        return adapt(0, 1, 0, 1, whole, 1e-13 * std::max(std::abs(whole), 1e-300), 0);
    }
    bool above() const {
        for (const Vec3& p : {c, c + u, c + v, c + u + v})
            if (glm::dot(n, p - x) < 0) return false;
        return true;
    }
};

Vec3 unit(std::mt19937_64& rng) {
    std::normal_distribution<double> g;
    for (;;) {
        const Vec3 v{g(rng), g(rng), g(rng)};
        if (glm::length(v) > 1e-3) return glm::normalize(v);
    }
}

}  // namespace

TEST_CASE("R89: closed-form parallelogram light average matches cubature to 1e-9", "[light][closedform]") {
    std::mt19937_64 rng(20261127);
    std::uniform_real_distribution<double> U(0, 1);
    const char* kinds[] = {"random", "near plane", "grazing", "very near", "very far", "skewed"};
    int counts[6] = {};
    double worst[6] = {};
    int done = 0;
    while (done < 2400) {
        const int kind = done % 6;
        Problem p;
        p.x = Vec3{0, 0, 0};
        p.c = Vec3{U(rng) * 4 - 2, U(rng) * 4 - 2, U(rng) * 4 - 2};
        p.u = unit(rng) * (0.1 + 2 * U(rng));
        p.v = unit(rng) * (0.1 + 2 * U(rng));
        if (kind == 5)
            p.v = glm::normalize(p.u + unit(rng) * std::pow(10.0, -3 * U(rng))) * (0.01 + 2 * U(rng));
        const Vec3 uxv = glm::cross(p.u, p.v);
        if (glm::length(uxv) < 1e-6 * glm::length(p.u) * glm::length(p.v)) continue;
        const Vec3 m = glm::normalize(uxv);
        const double size = glm::length(p.u) + glm::length(p.v);
        p.n = unit(rng);
        if (kind == 1 || kind == 3) {
            // x a tiny distance from the light's plane, its foot inside or outside the light.
            const double d = size * std::pow(10.0, kind == 1 ? -8 * U(rng) : -2 - 6 * U(rng));
            const Vec3 foot = p.c + (1.6 * U(rng) - 0.3) * p.u + (1.6 * U(rng) - 0.3) * p.v;
            p.x = foot - d * m;
            p.n = glm::normalize(m + unit(rng) * U(rng));
        } else if (kind == 4) {
            p.x = p.c - unit(rng) * size * std::pow(10.0, 1 + 5 * U(rng));
            p.n = glm::normalize(p.c - p.x + unit(rng) * glm::length(p.c - p.x) * U(rng));
        }
        if (kind == 2) {
            // Move x along N until the lowest corner sits just above (or on) the tangent plane.
            double lo = 1e300;
            for (const Vec3& q : {p.c, p.c + p.u, p.c + p.v, p.c + p.u + p.v})
                lo = std::min(lo, glm::dot(p.n, q - p.x));
            const double eps = U(rng) < 0.2 ? 0.0 : size * std::pow(10.0, -8 * U(rng));
            p.x += (lo - eps) * p.n;
        }
        if (!p.above()) continue;
        const double ref = p.reference();
        const double got = rect_light_average_cosine(p.x, p.n, p.c, p.u, p.v);
        const double rel = std::abs(got - ref) / std::abs(ref);
        if (!(rel <= 1e-9)) {
            INFO("kind " << kinds[kind] << " ref " << ref << " got " << got);
            CHECK(rel <= 1e-9);
        }
        worst[kind] = std::max(worst[kind], rel);
        ++counts[kind];
        ++done;
    }
    for (int k = 0; k < 6; ++k) {
        INFO(kinds[k] << ": " << counts[k] << " cases, worst relative error " << worst[k]);
        CHECK(counts[k] == 400);
        WARN(kinds[k] << ": worst relative error " << worst[k]);
    }
}

TEST_CASE("closed-form light average: degenerate light is 0, symmetric case is exact",
          "[light][closedform]") {
    CHECK(rect_light_average_cosine({0, 0, 0}, {0, 0, 1}, {0, 0, 1}, {1, 0, 0}, {2, 0, 0}) == 0);
    // A point on the axis of a square light facing it: by symmetry the in-plane part vanishes and
    // the value is d·∫ 1/r dA / A; over the square [−1,1]² at height 1, ∫ 1/r dA = 8·asinh(1/√2) − 2π/3
    // (four edges at distance 1, and the solid angle of a cube's face from its centre).
    const double a = rect_light_average_cosine({0, 0, 0}, {0, 0, 1}, {-1, -1, 1}, {2, 0, 0}, {0, 2, 0});
    const double b = rect_light_average_cosine({0, 0, 0}, {0, 0, 1}, {1, 1, 1}, {-2, 0, 0}, {0, -2, 0});
    CHECK(a == Approx(b).epsilon(1e-14));
    CHECK(a == Approx((8 * std::asinh(1 / std::sqrt(2.0)) - 2 * M_PI / 3) / 4).epsilon(1e-13));
}
