// The crossings of a line with a quadric primitive or torus in its canonical frame
// (render/quadric_prims.h), with the rounding-error bookkeeping that lets a ray reject the
// surface its origin lies on (docs/robustness.md: offset origins, the torus quartic).
// Internal to render/.
#pragma once

#include "render/quadric_prims.h"

namespace wsd::render::detail {

struct Crossing {
    double t;
    int part;
    // The crossing is the surface the line's origin lies on (within the origin's error `o_err`
    // and the crossing's own rounding): a ray from there must not hit it again.
    bool self;
};
inline constexpr int kMaxCrossings = 4;

// Every crossing of the line o + t·d, ascending in t (at most kMaxCrossings). o_err bounds the
// error already in o, per canonical axis.
int line_crossings(const QuadricPrim& q, const Vec3& o, const Vec3& d, const Vec3& o_err, Crossing* out);

// The torus's part of it (render/torus.cpp): appends to out[n...], returns the new count.
int torus_crossings(const QuadricPrim& q, const Vec3& o, const Vec3& d, const Vec3& o_err, Crossing* out);

// The torus's implicit function in the factored form that stays accurate near the surface:
// (ρ − R)² + y² − r² with ρ the distance from the axis (negative inside the tube).
inline double torus_f(double major, double minor, const Vec3& p) {
    const double rho = std::sqrt(p.x * p.x + p.z * p.z);
    const double a = rho - major;
    return (a * a + p.y * p.y) - minor * minor;
}

}  // namespace wsd::render::detail
