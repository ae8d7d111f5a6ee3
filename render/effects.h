// Which rendering effects a scene calls for, and which shapes call for each: reported to users
// (RenderResult::effects, `--stats`) and used to pick the specialised integrator.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "render/scene_spec.h"

namespace wsd::render {

enum class Effect : uint8_t {
    PointShadows,  // a point or spot light (hard shadows)
    AreaShadows,   // an area light (soft shadows)
    Reflection,    // a material with reflection > 0
    Refraction,    // a material with transmission > 0 (Fresnel, Snell, light shadows)
    Absorption,    // a transmissive material with non-zero absorption
    ImageTextures,
    ProceduralTextures,  // checker or Perlin colour textures
    Bumps,
    SmoothNormals,          // a mesh with per-vertex normals
    Specular,               // a material with specular > 0
    Supersampling,          // settings.supersamples > 1
    AdaptiveSupersampling,  // adaptive_supersampling with supersamples > 1
    AdaptiveLights,         // an area light with adaptive sampling
    Csg,                    // a CSG solid (union, intersection, difference)
    Emission,               // a material with emission (an emitter)
    IndirectLight,          // settings.indirect_samples > 0
    Caustics,               // caustic_photons > 0 with a light, an object to focus it and one to receive it
};
inline constexpr size_t kEffectCount = 17;

const char* effect_name(Effect e);

struct EffectSet {
    uint32_t mask = 0;
    // For each effect, the indices of the shapes that call for it; empty for the scene-wide ones
    // (lights and supersampling).
    std::array<std::vector<uint32_t>, kEffectCount> shapes;

    bool has(Effect e) const { return (mask >> unsigned(e)) & 1u; }
    void add(Effect e) { mask |= 1u << unsigned(e); }
    std::vector<std::string> names() const;
};

// force_adaptive_lights: RenderOptions::adaptive_lights (makes every area light adaptive).
EffectSet analyse_effects(const SceneSpec& spec, bool force_adaptive_lights = false);

}  // namespace wsd::render
