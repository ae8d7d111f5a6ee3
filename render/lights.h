// Lights prepared for shading: point lights and parallelogram area lights with their per-light
// constants (corner, cell edges, 1/n, colour × intensity) hoisted out of the shadow-ray loop.
#pragma once

#include <optional>
#include <string>

#include "render/limits.h"
#include "render/scene_spec.h"

namespace wsd::render {

struct Light {
    bool area = false;
    Vec3 position{0};        // point light position; area light centre
    Vec3 corner{0};          // area: position − u/2 − v/2
    Vec3 du{0}, dv{0};       // area: one cell's edges, u / nu and v / nv
    int nu = 1, nv = 1;      // area: grid size along u and v
    bool uniform = false;    // area: cell centres instead of one jittered point a cell
    bool adaptive = false;   // area: probe a few cells first (see integrator.cpp)
    Color radiance{1};       // colour × intensity
    double inv_count = 1.0;  // 1 / (nu·nv)

    int count() const { return nu * nv; }
    // The sample point of cell (i, j) at jitter (a, b) ∈ [0, 1)².
    Vec3 cell_point(int i, int j, double a, double b) const {
        return corner + (double(i) + a) * du + (double(j) + b) * dv;
    }
};

// An error message for a light that cannot be rendered, or nullopt.
std::optional<std::string> validate_light(const LightSpec& spec);

Light prepare_light(const LightSpec& spec);

}  // namespace wsd::render
