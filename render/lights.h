// Lights prepared for shading: point lights, spot lights and parallelogram area lights with their
// per-light constants (corner, cell edges, 1/n, colour × intensity, the spot's cone) hoisted out of
// the shadow-ray loop.
#pragma once

#include <cmath>
#include <optional>
#include <string>

#include "render/limits.h"
#include "render/scene_spec.h"

namespace wsd::render {

struct Light {
    bool area = false;
    Vec3 position{0};                       // point light position; area light centre
    Vec3 corner{0};                         // area: position − u/2 − v/2
    Vec3 du{0}, dv{0};                      // area: one cell's edges, u / nu and v / nv
    int nu = 1, nv = 1;                     // area: grid size along u and v
    bool uniform = false;                   // area: cell centres instead of one jittered point a cell
    bool adaptive = false;                  // area: probe a few cells first (see integrator.cpp)
    Color radiance{1};                      // colour × intensity
    double inv_count = 1.0;                 // 1 / (nu·nv)
    bool spot = false;                      // a point light limited to a cone (spot_factor)
    Vec3 axis{0, -1, 0};                    // spot: unit vector position → look_at
    double cos_angle = 1, cos_falloff = 1;  // spot: cosines of its two angles

    int count() const { return nu * nv; }
    // The sample point of cell (i, j) at jitter (a, b) ∈ [0, 1)².
    Vec3 cell_point(int i, int j, double a, double b) const {
        return corner + (double(i) + a) * du + (double(j) + b) * dv;
    }
};

// A spot light's factor for the point at position − to_light: 1 within `angle` of the axis, 0
// from `falloff` on, smoothstep 3s² − 2s³ in between with s = (cos θ − cos falloff) / (cos angle −
// cos falloff). With angle = falloff the edge is hard, and a point exactly on it is dark.
inline double spot_factor(const Light& l, const Vec3& to_light) {
    const double len = std::sqrt(to_light.x * to_light.x + to_light.y * to_light.y + to_light.z * to_light.z);
    const double c = -(l.axis.x * to_light.x + l.axis.y * to_light.y + l.axis.z * to_light.z) / len;
    if (!(c > l.cos_falloff)) return 0;  // also a point at the light itself (c is NaN)
    if (c >= l.cos_angle) return 1;
    const double s = (c - l.cos_falloff) / (l.cos_angle - l.cos_falloff);
    return s * s * (3 - 2 * s);
}

// cos of an angle in degrees, exact at 0, 60 and 90.
double cos_degrees(double degrees);

// An error message for a light that cannot be rendered, or nullopt.
std::optional<std::string> validate_light(const LightSpec& spec);

Light prepare_light(const LightSpec& spec);

}  // namespace wsd::render
