// Ray and test counters. Each render thread owns one RayStats and increments plain integers;
// they are summed once at the end, so counting costs no atomics or locks in the hot loop.
#pragma once

#include <cstdint>

namespace wsd::render {

struct RayStats {
    uint64_t camera_rays = 0;
    uint64_t shadow_rays = 0;
    uint64_t shaft_answered_rays = 0;  // shadow rays whose shaft held nothing to test (no traversal)
    uint64_t reflection_rays = 0;
    uint64_t refraction_rays = 0;
    uint64_t triangle_tests = 0, triangle_hits = 0;
    uint64_t sphere_tests = 0, sphere_hits = 0;
    uint64_t box_tests = 0;        // BVH node bounding-box tests
    uint64_t shape_box_tests = 0;  // tests against `box` shapes
    uint64_t plane_tests = 0;
    uint64_t fresnel_evals = 0;
    uint64_t texture_evals = 0;  // image/checker lookups
    uint64_t noise_evals = 0;    // Perlin evaluations (textures and bumps)
    uint64_t nonfinite_samples = 0;
    uint64_t rejected_rays = 0;     // NaN/Inf rays refused before traversal
    uint64_t adaptive_pixels = 0;   // pixels that took the full supersampling grid
    uint64_t indirect_paths = 0;    // Monte Carlo paths of indirect light
    uint64_t indirect_bounces = 0;  // their diffuse reflections (each path makes at least one)
    uint64_t indirect_rays = 0;     // rays they traced (diffuse and specular bounces)
    uint64_t emitter_samples = 0;   // points chosen on emissive surfaces (next-event estimation)
    uint64_t photons_shot = 0;      // caustic photons shot, and stored on diffuse surfaces
    uint64_t photons_stored = 0;
    uint64_t photon_lookups = 0;   // caustic estimates at shading points
    uint64_t photons_visited = 0;  // photons those estimates looked at (the gather cost)

    RayStats& operator+=(const RayStats& o) {
        camera_rays += o.camera_rays;
        shadow_rays += o.shadow_rays;
        shaft_answered_rays += o.shaft_answered_rays;
        reflection_rays += o.reflection_rays;
        refraction_rays += o.refraction_rays;
        triangle_tests += o.triangle_tests;
        triangle_hits += o.triangle_hits;
        sphere_tests += o.sphere_tests;
        sphere_hits += o.sphere_hits;
        box_tests += o.box_tests;
        shape_box_tests += o.shape_box_tests;
        plane_tests += o.plane_tests;
        fresnel_evals += o.fresnel_evals;
        texture_evals += o.texture_evals;
        noise_evals += o.noise_evals;
        nonfinite_samples += o.nonfinite_samples;
        rejected_rays += o.rejected_rays;
        adaptive_pixels += o.adaptive_pixels;
        indirect_paths += o.indirect_paths;
        indirect_bounces += o.indirect_bounces;
        indirect_rays += o.indirect_rays;
        emitter_samples += o.emitter_samples;
        photons_shot += o.photons_shot;
        photons_stored += o.photons_stored;
        photon_lookups += o.photon_lookups;
        photons_visited += o.photons_visited;
        return *this;
    }
    uint64_t ray_queries() const {
        return camera_rays + shadow_rays + reflection_rays + refraction_rays + indirect_rays;
    }
};

}  // namespace wsd::render
