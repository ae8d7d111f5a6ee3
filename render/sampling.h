// Counter-based random numbers and sample grids. Every random value is a hash of a key built from
// (seed, pixel x, pixel y, sample index, path branch, light, cell): no generator state is shared or
// carried between pixels, so an image is bit-identical for any thread count, tile order or region.
#pragma once

#include <cmath>
#include <cstdint>

namespace wsd::render {

// splitmix64's finaliser (a bijection on 64 bits with full avalanche).
constexpr uint64_t mix64(uint64_t z) {
    z ^= z >> 30;
    z *= 0xbf58476d1ce4e5b9ULL;
    z ^= z >> 27;
    z *= 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return z;
}

// Distinct odd constants keep the key spaces of the different derivations apart.
inline constexpr uint64_t kPixelSalt = 0x9e3779b97f4a7c15ULL;
inline constexpr uint64_t kSampleSalt = 0xd1b54a32d192ed03ULL;
inline constexpr uint64_t kBranchSalt = 0xa0761d6478bd642fULL;
inline constexpr uint64_t kLightSalt = 0xe7037ed1a0b428dbULL;
inline constexpr uint64_t kCameraSalt = 0x8ebc6af09c88c6e3ULL;

inline uint64_t pixel_key(uint32_t seed, int x, int y) {
    const uint64_t xy = (uint64_t(uint32_t(x)) << 32) | uint32_t(y);
    return mix64(mix64(seed + kPixelSalt) ^ xy);
}

// The key of one camera sample of a pixel; it is also the path key of that camera ray.
inline uint64_t sample_key(uint64_t pixel, uint32_t sample) {
    return mix64(pixel ^ mix64((uint64_t(sample) + 1) * kSampleSalt));
}

// The path key of a secondary ray: 1 = reflected, 2 = refracted.
inline uint64_t branch_key(uint64_t path, uint32_t branch) {
    return mix64(path ^ (uint64_t(branch) * kBranchSalt));
}

// The key of light `light` seen from the hit of path `path`; cells are hashed from it.
inline uint64_t light_key(uint64_t path, uint32_t light) {
    return mix64(path + (uint64_t(light) + 1) * kLightSalt);
}

struct Uniform2 {
    double u, v;  // each in [0, 1)
};

// Two independent uniform numbers from one 64-bit hash (32 bits each, exact in a double).
inline Uniform2 uniform2(uint64_t h) {
    return {double(h >> 32) * 0x1p-32, double(h & 0xffffffffULL) * 0x1p-32};
}

inline Uniform2 cell_jitter(uint64_t light, uint32_t cell) {
    return uniform2(mix64(light ^ cell));
}
inline Uniform2 camera_jitter(uint64_t sample) {
    return uniform2(mix64(sample ^ kCameraSalt));
}

// The camera-sample grid for `n` rays a pixel: n = k² gives k×k; another count m rows × n/m
// columns, m the largest divisor of n that is ≤ √n.
struct SampleGrid {
    int rows = 1, cols = 1;
};

inline SampleGrid supersample_grid(int n) {
    if (n <= 1) return {1, 1};
    int m = int(std::sqrt(double(n)));
    while (m * m > n) --m;
    while ((m + 1) * (m + 1) <= n) ++m;
    while (n % m != 0) --m;
    return {m, n / m};
}

}  // namespace wsd::render
