// The Whitted integrator of wsd-language.md §4 "material": local Phong shading with shadow rays
// to every light sample, mirror reflection, Fresnel-split refraction with Beer–Lambert absorption,
// depth and weight limits. Tracer is one thread's integrator; make_tracer picks a version
// specialised on the scene's effects (or the general one) so unused effects cost nothing.
#pragma once

#include <cstdint>
#include <memory>

#include "render/geometry.h"
#include "render/stats.h"

namespace wsd::render {

class Scene;

// The mirror direction of d about the unit normal n.
inline Vec3 reflect(const Vec3& d, const Vec3& n) {
    return d - (2.0 * glm::dot(d, n)) * n;
}

struct FresnelResult {
    double reflectance = 1;  // unpolarised dielectric Fresnel F; 1 under total internal reflection
    Vec3 refracted{0};       // unit transmitted direction (meaningless under TIR)
    bool total_internal = true;
};

// d: unit incident direction; n: unit normal on the incident side (dot(d, n) ≤ 0);
// eta = n_incident / n_transmitted. Exact s and p polarisation averaged; eta = 1 gives F = 0 and
// the undeflected ray exactly; sin²θt ≥ 1 is total internal reflection.
FresnelResult fresnel_refract(const Vec3& d, const Vec3& n, double eta);

class Tracer {
public:
    virtual ~Tracer() = default;
    // The colour seen by the camera ray through image position (px, py). `key` is the sample's
    // random key (sampling.h); the sample is not checked for NaN here (the film does that).
    virtual Color camera_sample(double px, double py, uint64_t key) = 0;
    // camera_sample for n ≤ Geometry::kMaxPacket samples at once (out[k] for positions px[k],
    // py[k], keys key[k]), with the same colours: the camera rays are intersected as a packet.
    virtual void camera_samples(const double* px, const double* py, const uint64_t* key, int n,
                                Color* out) = 0;
    // camera_samples for progressive rendering (TracerOptions::sampled_lights): sample k is
    // point index[k] of its pixel's sequence seq[k] (render/sequence.h), from which each area light
    // it meets, at any depth, takes one stratified point instead of every cell.
    virtual void sequence_samples(const double* px, const double* py, const uint64_t* key,
                                  const uint64_t* seq, const uint32_t* index, int n, Color* out) = 0;
    // The colour seen along any ray (unit direction) at recursion depth 0.
    virtual Color trace_ray(const Ray& ray, uint64_t key) = 0;
};

struct TracerOptions {
    bool specialise = true;        // false: the general path with every effect enabled
    bool adaptive_lights = false;  // every area light adaptive (RenderOptions::adaptive_lights)
    // sequence_samples: one point of each area light a sample (see direct() in integrator.cpp)
    bool sampled_lights = false;
};

// One tracer a thread; it counts into `stats`, which must outlive it.
std::unique_ptr<Tracer> make_tracer(const Scene& scene, const TracerOptions& options, RayStats& stats);

}  // namespace wsd::render
