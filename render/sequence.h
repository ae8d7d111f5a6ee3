// Stratified sample sequences for progressive rendering: the first two dimensions of Sobol'
// (a (0,2)-sequence), Owen-scrambled by hashing (Burley, "Practical hash-based Owen scrambling",
// JCGT 2020). Point i of a sequence is a function of i and the sequence's key alone, so a pixel's
// n-th sample is the same whatever happened before it. Every prefix of 2^k points is a
// (0,k,2)-net: each of the 2^k elementary rectangles of any shape 2^-a × 2^-(k−a) holds exactly one
// point. Different keys give independent randomisations; the index is shuffled too (within
// aligned blocks of every power of two, which keeps prefixes stratified), so that two sequences
// read at the same index are not correlated.
#pragma once

#include <cstdint>

#include "render/sampling.h"

namespace wsd::render {

inline constexpr uint64_t kSequenceSalt = 0x2545f4914f6cdd1dULL;

inline uint32_t reverse_bits32(uint32_t x) {
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
    x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
    return (x >> 16) | (x << 16);
}

// A random permutation of 32-bit values in which output bit b depends on input bits ≤ b only
// (Laine and Karras), seeded.
inline uint32_t laine_karras_permutation(uint32_t x, uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

// Owen scrambling of a 32-bit fixed-point value in [0, 1): output bit b (from the top) depends on
// the bits above it only, so the value's dyadic intervals are permuted as a nested whole.
inline uint32_t nested_uniform_scramble(uint32_t x, uint32_t seed) {
    return reverse_bits32(laine_karras_permutation(reverse_bits32(x), seed));
}

// Sobol's second dimension: direction numbers v_0 = 2^31, v_b = v_(b−1) ^ (v_(b−1) >> 1).
inline uint32_t sobol_second(uint32_t index) {
    uint32_t x = 0, v = 0x80000000u;
    for (; index != 0; index >>= 1, v ^= v >> 1)
        if (index & 1u) x ^= v;
    return x;
}

// Point `index` of the scrambled two-dimensional sequence `key`, in [0, 1)².
inline Uniform2 sobol2(uint32_t index, uint64_t key) {
    const uint64_t h = mix64(key);
    const uint32_t shuffle = uint32_t(mix64(key ^ kSequenceSalt));
    const uint32_t i = nested_uniform_scramble(index, shuffle);
    const uint32_t x = nested_uniform_scramble(reverse_bits32(i), uint32_t(h));
    const uint32_t y = nested_uniform_scramble(sobol_second(i), uint32_t(h >> 32));
    return {double(x) * 0x1p-32, double(y) * 0x1p-32};
}

}  // namespace wsd::render
