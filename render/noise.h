// Perlin noise and the scalar patterns built on it (noise, turbulence, marble, wood) exactly as
// wsd-language.md §4 "texture" defines them. perlin_noise itself is declared in texture.h; this
// header adds what textures, bumps and tests need on top of it.
#pragma once

#include <array>
#include <cstdint>

#include "render/scene_spec.h"

namespace wsd::render {

// Ken Perlin's reference permutation (the 256-entry p[] of his 2002 implementation), for tests.
const std::array<uint8_t, 256>& perlin_permutation();

// Maps NaN to 0 and everything else into [0, 1].
inline double clamp_unit(double v) {
    if (!(v > 0.0)) return 0.0;  // also catches NaN
    return v < 1.0 ? v : 1.0;
}

// The pattern coefficient in [0, 1] at object-frame point p (never NaN):
//   noise       ½·(1 + N(a·x, b·y, c·z))
//   turbulence  min(Σ_{l=1..L} |N(l·a·x, l·b·y, l·c·z)| / l, 1)
//   marble      ½ + ½·sin(a·x + b·y + T), T the turbulence sum
//   wood        g − floor(g), g = 5·N(a·x, b·y, c·z)
// `noise_calls` is increased by the number of perlin_noise evaluations made.
double perlin_pattern(PerlinKind kind, const Vec3& scale, int octaves, const Vec3& p, uint64_t& noise_calls);

}  // namespace wsd::render
