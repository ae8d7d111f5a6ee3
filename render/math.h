// Numeric helpers for geometry (robustness.md: error bounds, safe functions): GLM aliases, gamma(n) error
// bounds for double and float, next-float stepping, Kahan's difference of products, an opaque
// barrier that stops the compiler fusing a product into an FMA, and safe elementary functions.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <limits>

#include "render/scene_spec.h"

namespace wsd::render {

using Vec3f = glm::vec3;
using Vec2f = glm::vec2;
using Mat3 = glm::dmat3;

inline constexpr double kPi = 3.14159265358979323846;

inline bool finite3(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Unit roundoff (half an ULP of 1) of double and float.
inline constexpr double kEpsD = 0x1p-53;
inline constexpr double kEpsF = 0x1p-24;

// pbrt's gamma: a chain of n roundings multiplies the exact value by at most (1 ± gamma(n)).
constexpr double gamma(int n) {
    return n * kEpsD / (1 - n * kEpsD);
}
// The same bound for float arithmetic, evaluated in double.
constexpr double gamma_f(int n) {
    return n * kEpsF / (1 - n * kEpsF);
}

inline double next_float_up(double v) {
    if (std::isinf(v) && v > 0) return v;
    if (v == -0.0) v = 0.0;
    uint64_t bits = std::bit_cast<uint64_t>(v);
    bits = v >= 0 ? bits + 1 : bits - 1;
    return std::bit_cast<double>(bits);
}
inline double next_float_down(double v) {
    if (std::isinf(v) && v < 0) return v;
    if (v == 0.0) v = -0.0;
    uint64_t bits = std::bit_cast<uint64_t>(v);
    bits = v > 0 ? bits - 1 : bits + 1;
    return std::bit_cast<double>(bits);
}
inline float next_float_up(float v) {
    if (std::isinf(v) && v > 0) return v;
    if (v == -0.0f) v = 0.0f;
    uint32_t bits = std::bit_cast<uint32_t>(v);
    bits = v >= 0 ? bits + 1 : bits - 1;
    return std::bit_cast<float>(bits);
}
inline float next_float_down(float v) {
    if (std::isinf(v) && v < 0) return v;
    if (v == 0.0f) v = -0.0f;
    uint32_t bits = std::bit_cast<uint32_t>(v);
    bits = v > 0 ? bits - 1 : bits + 1;
    return std::bit_cast<float>(bits);
}

// A double rounded to the float at or below (above) it: bounds that stay conservative. Written
// without a branch, since every ray's slab constants round this way and the direction is a coin
// toss: the nearest float steps one unit away from zero or towards it, which adds ±1 to its
// bits. The cases next_float_* treats apart cannot need a step here (+inf rounded down is
// stepped as FLT_MAX + 1 ulp, its bits less one; -0 stepped down gains a sign bit already set).
inline float to_float_down(double v) {
    const float f = static_cast<float>(v);
    const uint32_t bits = std::bit_cast<uint32_t>(f);
    const uint32_t sign = static_cast<uint32_t>(static_cast<int32_t>(bits) >> 31);  // 0 or ~0
    const uint32_t step = (~sign | 1u) & (0u - static_cast<uint32_t>(static_cast<double>(f) > v));
    return std::bit_cast<float>(bits + step);
}
inline float to_float_up(double v) {
    const float f = static_cast<float>(v);
    const uint32_t bits = std::bit_cast<uint32_t>(f);
    const uint32_t sign = static_cast<uint32_t>(static_cast<int32_t>(bits) >> 31);
    const uint32_t step = (sign | 1u) & (0u - static_cast<uint32_t>(static_cast<double>(f) < v));
    return std::bit_cast<float>(bits + step);
}

// Hides a value's origin from the optimiser, so that `opaque(a*b) - opaque(c*d)` is evaluated
// as two rounded products and a subtraction whatever -ffp-contract says: the watertight triangle
// test needs e(p, q) == -e(q, p) exactly (robustness.md, watertight triangles).
template <class T>
inline T opaque(T v) {
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
    asm("" : "+x"(v));
#elif defined(__GNUC__) && defined(__aarch64__)
    asm("" : "+w"(v));
#else
    volatile T tmp = v;
    v = tmp;
#endif
    return v;
}

// a·b − c·d to about 1.5 ULP (Kahan; pbrt-v4 DifferenceOfProducts): exactly 0 when the exact
// difference is 0, and always of the right sign. Uses std::fma explicitly, so contraction
// settings cannot change it.
inline double difference_of_products(double a, double b, double c, double d) {
    double cd = c * d;
    double err = std::fma(-c, d, cd);
    double dop = std::fma(a, b, -cd);
    return dop + err;
}

inline double safe_sqrt(double x) {
    return std::sqrt(x > 0 ? x : 0.0);
}
inline double safe_asin(double x) {
    return std::asin(x < -1 ? -1.0 : (x > 1 ? 1.0 : x));
}
inline double safe_acos(double x) {
    return std::acos(x < -1 ? -1.0 : (x > 1 ? 1.0 : x));
}

// normalize(v), or `fallback` when v has no usable length (zero, denormal-small or non-finite).
inline Vec3 safe_normalize(const Vec3& v, const Vec3& fallback) {
    double len2 = glm::dot(v, v);
    if (!(len2 > 0) || !std::isfinite(len2)) {
        // Rescale before giving up: tiny or huge but finite vectors still have a direction.
        double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
        if (!(m > 0) || !std::isfinite(m)) return fallback;
        Vec3 w = v / m;
        return w / std::sqrt(glm::dot(w, w));
    }
    return v / std::sqrt(len2);
}

inline bool is_finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
inline bool is_finite(const Vec3f& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

inline Vec3 abs3(const Vec3& v) {
    return {std::abs(v.x), std::abs(v.y), std::abs(v.z)};
}

}  // namespace wsd::render
