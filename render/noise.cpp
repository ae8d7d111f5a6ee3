// Ken Perlin's improved noise (2002): reference permutation, quintic fade, 12-direction grad.
// Robustness (robustness.md, robust noise; R37): the lattice cell comes from floor() in double and is
// wrapped modulo 256 while still a double, so no float-to-int cast can overflow; non-finite
// input gives 0. Also the noise/turbulence/marble/wood patterns of wsd-language.md §4.
#include "render/noise.h"

#include <cmath>

#include "render/texture.h"

namespace wsd::render {

namespace {

constexpr std::array<uint8_t, 256> kPermutation = {
    151, 160, 137, 91,  90,  15,  131, 13,  201, 95,  96,  53,  194, 233, 7,   225, 140, 36,  103, 30,
    69,  142, 8,   99,  37,  240, 21,  10,  23,  190, 6,   148, 247, 120, 234, 75,  0,   26,  197, 62,
    94,  252, 219, 203, 117, 35,  11,  32,  57,  177, 33,  88,  237, 149, 56,  87,  174, 20,  125, 136,
    171, 168, 68,  175, 74,  165, 71,  134, 139, 48,  27,  166, 77,  146, 158, 231, 83,  111, 229, 122,
    60,  211, 133, 230, 220, 105, 92,  41,  55,  46,  245, 40,  244, 102, 143, 54,  65,  25,  63,  161,
    1,   216, 80,  73,  209, 76,  132, 187, 208, 89,  18,  169, 200, 196, 135, 130, 116, 188, 159, 86,
    164, 100, 109, 198, 173, 186, 3,   64,  52,  217, 226, 250, 124, 123, 5,   202, 38,  147, 118, 126,
    255, 82,  85,  212, 207, 206, 59,  227, 47,  16,  58,  17,  182, 189, 28,  42,  223, 183, 170, 213,
    119, 248, 152, 2,   44,  154, 163, 70,  221, 153, 101, 155, 167, 43,  172, 9,   129, 22,  39,  253,
    19,  98,  108, 110, 79,  113, 224, 232, 178, 185, 112, 104, 218, 246, 97,  228, 251, 34,  242, 193,
    238, 210, 144, 12,  191, 179, 162, 241, 81,  51,  145, 235, 249, 14,  239, 107, 49,  192, 214, 31,
    181, 199, 106, 157, 184, 84,  204, 176, 115, 121, 50,  45,  127, 4,   150, 254, 138, 236, 205, 93,
    222, 114, 67,  29,  24,  72,  243, 141, 128, 195, 78,  66,  215, 61,  156, 180};

// The permutation repeated twice, so p[i + 1] never needs a wrap (the reference's p[512]).
struct DoubledPermutation {
    std::array<int, 512> p{};
    constexpr DoubledPermutation() {
        for (int i = 0; i < 512; ++i) p[static_cast<size_t>(i)] = kPermutation[static_cast<size_t>(i & 255)];
    }
};
constexpr DoubledPermutation kP{};

inline double fade(double t) {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}
inline double lerp(double t, double a, double b) {
    return a + t * (b - a);
}

// The low 4 bits of the hash pick one of 12 gradient directions (4 of them repeated).
inline double grad(int hash, double x, double y, double z) {
    const int h = hash & 15;
    const double u = h < 8 ? x : y;
    const double v = h < 4 ? y : (h == 12 || h == 14 ? x : z);
    return ((h & 1) == 0 ? u : -u) + ((h & 2) == 0 ? v : -v);
}

// floor(c) modulo 256 as an int, computed entirely in double: fmod of an integer-valued double
// by 256 is exact, so this is correct (and free of undefined behaviour) for any finite c.
inline int lattice(double floored) {
    double m = std::fmod(floored, 256.0);
    if (m < 0) m += 256.0;
    return static_cast<int>(m) & 255;
}

inline int perm(int i) {
    return kP.p[static_cast<size_t>(i)];
}

}  // namespace

const std::array<uint8_t, 256>& perlin_permutation() {
    return kPermutation;
}

double perlin_noise(double x, double y, double z) {
    if (!(std::isfinite(x) && std::isfinite(y) && std::isfinite(z))) return 0.0;
    const double fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
    const int xi = lattice(fx), yi = lattice(fy), zi = lattice(fz);
    x -= fx;
    y -= fy;
    z -= fz;
    const double u = fade(x), v = fade(y), w = fade(z);
    const int a = perm(xi) + yi, aa = perm(a) + zi, ab = perm(a + 1) + zi;
    const int b = perm(xi + 1) + yi, ba = perm(b) + zi, bb = perm(b + 1) + zi;
    return lerp(w,
                lerp(v, lerp(u, grad(perm(aa), x, y, z), grad(perm(ba), x - 1, y, z)),
                     lerp(u, grad(perm(ab), x, y - 1, z), grad(perm(bb), x - 1, y - 1, z))),
                lerp(v, lerp(u, grad(perm(aa + 1), x, y, z - 1), grad(perm(ba + 1), x - 1, y, z - 1)),
                     lerp(u, grad(perm(ab + 1), x, y - 1, z - 1), grad(perm(bb + 1), x - 1, y - 1, z - 1))));
}

namespace {

double turbulence_sum(const Vec3& s, int octaves, uint64_t& noise_calls) {
    double t = 0.0;
    for (int l = 1; l <= octaves; ++l) {
        const double f = static_cast<double>(l);
        t += std::fabs(perlin_noise(f * s.x, f * s.y, f * s.z)) / f;
    }
    if (octaves > 0) noise_calls += static_cast<uint64_t>(octaves);
    return t;
}

}  // namespace

double perlin_pattern(PerlinKind kind, const Vec3& scale, int octaves, const Vec3& p, uint64_t& noise_calls) {
    const Vec3 s = scale * p;  // (a·x, b·y, c·z)
    double coef = 0.0;
    switch (kind) {
        case PerlinKind::Noise:
            ++noise_calls;
            coef = 0.5 * (1.0 + perlin_noise(s.x, s.y, s.z));
            break;
        case PerlinKind::Turbulence:
            coef = turbulence_sum(s, octaves, noise_calls);
            break;
        case PerlinKind::Marble:
            coef = 0.5 + 0.5 * std::sin(s.x + s.y + turbulence_sum(s, octaves, noise_calls));
            break;
        case PerlinKind::Wood: {
            // floor, not truncation: g − trunc(g) is negative wherever the noise is, which the clamp
            // turned into a flat band along every sign change (the DH2323 report's seam).
            ++noise_calls;
            const double g = 5.0 * perlin_noise(s.x, s.y, s.z);
            coef = g - std::floor(g);
            break;
        }
    }
    return clamp_unit(coef);
}

}  // namespace wsd::render
