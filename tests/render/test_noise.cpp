// Perlin noise and its patterns: the reference permutation, agreement with an independent
// transcription of the published algorithm, lattice zeros, range, continuity across lattice
// planes (robustness.md R37), huge and non-finite input, and the four pattern formulas.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <set>

#include "render/noise.h"
#include "render/texture.h"

using namespace wsd::render;

namespace {

// The published algorithm written another way: the gradient as a table of 16 vectors (the 12
// cube-edge directions, then the padding (1,1,0), (0,-1,1), (-1,1,0), (0,-1,-1) in the order the
// reference grad() bit tests yield for hashes 12..15), and the interpolation as a sum over the 8
// cell corners of weight × dot(gradient, offset).
double reference_noise(double x, double y, double z) {
    static const int g[16][3] = {{1, 1, 0},  {-1, 1, 0},  {1, -1, 0}, {-1, -1, 0}, {1, 0, 1},  {-1, 0, 1},
                                 {1, 0, -1}, {-1, 0, -1}, {0, 1, 1},  {0, -1, 1},  {0, 1, -1}, {0, -1, -1},
                                 {1, 1, 0},  {0, -1, 1},  {-1, 1, 0}, {0, -1, -1}};
    const auto& perm = perlin_permutation();
    const auto p = [&](int i) { return static_cast<int>(perm[static_cast<size_t>(i & 255)]); };
    const double cell[3] = {std::floor(x), std::floor(y), std::floor(z)};
    const double f[3] = {x - cell[0], y - cell[1], z - cell[2]};
    const int c[3] = {static_cast<int>(cell[0]) & 255, static_cast<int>(cell[1]) & 255,
                      static_cast<int>(cell[2]) & 255};
    const auto s = [](double t) { return t * t * t * (t * (t * 6 - 15) + 10); };
    double sum = 0;
    for (int corner = 0; corner < 8; ++corner) {
        const int d[3] = {corner & 1, (corner >> 1) & 1, (corner >> 2) & 1};
        const int h = p(p(p(c[0] + d[0]) + c[1] + d[1]) + c[2] + d[2]) & 15;
        double weight = 1, dot = 0;
        for (int a = 0; a < 3; ++a) {
            weight *= d[a] ? s(f[a]) : 1 - s(f[a]);
            dot += g[h][a] * (f[a] - d[a]);
        }
        sum += weight * dot;
    }
    return sum;
}

}  // namespace

TEST_CASE("the permutation is Perlin's reference table", "[noise]") {
    const auto& p = perlin_permutation();
    std::set<int> values(p.begin(), p.end());
    CHECK(values.size() == 256);  // a permutation of 0..255
    CHECK(p[0] == 151);
    CHECK(p[1] == 160);
    CHECK(p[2] == 137);
    CHECK(p[36] == 0);
    CHECK(p[254] == 156);
    CHECK(p[255] == 180);
}

TEST_CASE("noise matches the published algorithm", "[noise]") {
    // The value Perlin's Java reference prints for noise(3.14, 42, 7), quoted by many ports.
    CHECK(perlin_noise(3.14, 42, 7) == Approx(0.13691995878400012).margin(1e-15));
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> coord(-300.0, 300.0);
    for (int i = 0; i < 2000; ++i) {
        const double x = coord(rng), y = coord(rng), z = coord(rng);
        INFO(x << ", " << y << ", " << z);
        REQUIRE(perlin_noise(x, y, z) == Approx(reference_noise(x, y, z)).margin(1e-12));
    }
}

TEST_CASE("noise is zero on the integer lattice", "[noise]") {
    for (double x : {-3.0, -1.0, -0.0, 0.0, 1.0, 2.0, 255.0, 256.0, 1e6, -1e6, 0x1p40})
        for (double y : {-2.0, 0.0, 7.0})
            for (double z : {-5.0, 0.0, 300.0}) CHECK(perlin_noise(x, y, z) == 0.0);
}

TEST_CASE("R37: noise range, determinism and periodicity", "[noise]") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> coord(-1000.0, 1000.0);
    double lo = 0, hi = 0;
    for (int i = 0; i < 200000; ++i) {
        const double x = coord(rng), y = coord(rng), z = coord(rng);
        const double n = perlin_noise(x, y, z);
        lo = std::min(lo, n);
        hi = std::max(hi, n);
        if (i % 1000 == 0) {
            REQUIRE(perlin_noise(x, y, z) == n);
            // The lattice repeats every 256 cells; only the fractional part's rounding differs.
            REQUIRE(perlin_noise(x + 256.0, y, z - 512.0) == Approx(n).margin(1e-9));
        }
    }
    CHECK(lo >= -1.04);
    CHECK(hi <= 1.04);
    CHECK(lo < -0.7);  // the samples do spread over the range
    CHECK(hi > 0.7);
}

TEST_CASE("R37: noise is continuous across every lattice plane", "[noise]") {
    // Lines along each axis crossing x = -10 .. 10, including the integers and -0.0 exactly.
    // |n(x+h) − n(x)| ≤ K·h, K a generous bound on the gradient (truncating instead of flooring
    // would jump by O(1) at every negative integer).
    const double h = 1e-4, k = 10.0;
    const double others[][2] = {{0.3, 0.7}, {-2.6, 4.1}, {-0.0, 0.5}};
    for (int axis = 0; axis < 3; ++axis) {
        for (const auto& o : others) {
            for (int i = -100000; i < 100000; ++i) {
                const double t = i * h;
                double a[3], b[3];
                a[axis] = t, b[axis] = t + h;
                a[(axis + 1) % 3] = b[(axis + 1) % 3] = o[0];
                a[(axis + 2) % 3] = b[(axis + 2) % 3] = o[1];
                const double na = perlin_noise(a[0], a[1], a[2]), nb = perlin_noise(b[0], b[1], b[2]);
                if (std::fabs(nb - na) > k * h) {
                    INFO("axis " << axis << " at " << t);
                    REQUIRE(std::fabs(nb - na) <= k * h);
                }
            }
        }
    }
    for (double y : {0.25, -3.5}) {
        CHECK(perlin_noise(-0.0, y, 0.5) == perlin_noise(0.0, y, 0.5));
        const double below = perlin_noise(-std::numeric_limits<double>::denorm_min(), y, 0.5);
        CHECK(below == Approx(perlin_noise(0.0, y, 0.5)).margin(1e-12));
        CHECK(perlin_noise(std::nextafter(-3.0, 0.0), y, 0.5) ==
              Approx(perlin_noise(-3.0, y, 0.5)).margin(1e-12));
    }
}

TEST_CASE("R37: noise at huge and non-finite coordinates is defined", "[noise]") {
    const double inf = std::numeric_limits<double>::infinity();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (double big : {1e6 + 0.37, -1e6 - 0.37, 1e9 + 0.25, -1e9 - 0.75, 3e9 + 0.5}) {
        const double n = perlin_noise(big, 0.3, -0.6);
        CHECK(std::isfinite(n));
        CHECK(std::fabs(n) <= 1.04);
    }
    // Beyond 2^52 every double is an integer: a lattice point.
    CHECK(perlin_noise(1e20, 0.5, 0.5) == 0.0);
    CHECK(perlin_noise(-1e300, 0.5, 0.5) == 0.0);
    CHECK(perlin_noise(inf, 0.5, 0.5) == 0.0);
    CHECK(perlin_noise(0.5, -inf, 0.5) == 0.0);
    CHECK(perlin_noise(0.5, 0.5, nan) == 0.0);
}

TEST_CASE("pattern formulas and their noise counts", "[noise]") {
    const Vec3 scale(0.7, 1.3, 2.1);
    const int octaves = 5;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> coord(-20.0, 20.0);
    for (int i = 0; i < 500; ++i) {
        const Vec3 p(coord(rng), coord(rng), coord(rng));
        const Vec3 s = scale * p;
        const double n = perlin_noise(s.x, s.y, s.z);
        double t = 0;
        for (int l = 1; l <= octaves; ++l) t += std::fabs(perlin_noise(l * s.x, l * s.y, l * s.z)) / l;

        uint64_t calls = 0;
        CHECK(perlin_pattern(PerlinKind::Noise, scale, octaves, p, calls) ==
              Approx(std::clamp(0.5 * (1 + n), 0.0, 1.0)).margin(1e-15));
        CHECK(calls == 1);
        calls = 0;
        CHECK(perlin_pattern(PerlinKind::Turbulence, scale, octaves, p, calls) ==
              Approx(std::min(t, 1.0)).margin(1e-15));
        CHECK(calls == octaves);
        calls = 0;
        CHECK(perlin_pattern(PerlinKind::Marble, scale, octaves, p, calls) ==
              Approx(0.5 + 0.5 * std::sin(s.x + s.y + t)).margin(1e-15));
        CHECK(calls == octaves);
        calls = 0;
        const double g = 5 * n;
        CHECK(perlin_pattern(PerlinKind::Wood, scale, octaves, p, calls) ==
              Approx(std::clamp(g - std::floor(g), 0.0, 1.0)).margin(1e-15));
        CHECK(calls == 1);
    }
}

TEST_CASE("every pattern stays in [0, 1], even for non-finite points", "[noise]") {
    const double inf = std::numeric_limits<double>::infinity();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> coord(-50.0, 50.0);
    std::vector<Vec3> points = {{nan, 0, 0}, {inf, -inf, 0}, {1e300, 1e300, 1e300}, {0, 0, 0}};
    for (int i = 0; i < 5000; ++i) points.emplace_back(coord(rng), coord(rng), coord(rng));
    for (PerlinKind kind :
         {PerlinKind::Noise, PerlinKind::Turbulence, PerlinKind::Marble, PerlinKind::Wood}) {
        for (const Vec3& p : points) {
            uint64_t calls = 0;
            const double c = perlin_pattern(kind, Vec3(3.0, 3.0, 3.0), 9, p, calls);
            REQUIRE(c >= 0.0);
            REQUIRE(c <= 1.0);
        }
    }
}

TEST_CASE("wood has no seam where the noise changes sign", "[noise]") {
    // Walk a line, find sign changes of N, and check that the wood coefficient moves by a small
    // amount modulo 1 there (rings are a sawtooth in g = 5·N, so the distance is circular), and
    // that negative noise is not flattened to 0 (what g − trunc(g) and the clamp did).
    const Vec3 scale(1.0, 1.0, 1.0);
    const double h = 1e-5;
    int sign_changes = 0, negative_nonzero = 0;
    for (int i = 0; i < 400000; ++i) {
        const Vec3 a(i * h - 2.0, 0.37, -1.21), b((i + 1) * h - 2.0, 0.37, -1.21);
        const double na = perlin_noise(a.x, a.y, a.z), nb = perlin_noise(b.x, b.y, b.z);
        uint64_t calls = 0;
        const double wa = perlin_pattern(PerlinKind::Wood, scale, 1, a, calls);
        const double wb = perlin_pattern(PerlinKind::Wood, scale, 1, b, calls);
        const double d = std::fabs(wa - wb);
        REQUIRE(std::min(d, 1.0 - d) <= 5.0 * 10.0 * h);
        if ((na < 0) != (nb < 0)) ++sign_changes;
        if (na < -0.01 && wa > 0.01) ++negative_nonzero;
    }
    CHECK(sign_changes >= 2);
    CHECK(negative_nonzero > 1000);
}
