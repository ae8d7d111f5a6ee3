// Indirect light (wsd-language.md, "indirect light"): Monte Carlo paths that gather the diffuse
// interreflection arriving at a shading point. Internal to the integrator.
//
// The diffuse term of wsd is Lambertian with albedo ρ = (1 − t)·diffuse·c: a surface under a
// uniform incoming radiance L reflects ρ·L. A path from point x samples a direction by the cosine
// (density cos θ / π), so each step multiplies the path's weight by ρ of the surface it leaves.
// At every diffuse vertex of a path:
// - next-event estimation: one point chosen on the emitters (emitters.h), with a shadow ray that
//   any surface blocks (light through glass and mirrors arrives along the paths themselves);
// - the sampled direction's hit adds its emission, weighted against the emitter sample by the
//   power heuristic (multiple importance sampling) when that emitter is sampled, else in full;
// - the lights shade the hit exactly as the direct term shades a camera hit (no falloff), so the
//   indirect estimate is consistent with the direct term;
// - the background is a uniform environment: a path that leaves the scene adds it.
// Reflection and refraction at a hit continue the path too: one of the diffuse, mirror and
// refracted directions is chosen in proportion to its mean weight and divided by its
// probability (unbiased; no Russian roulette otherwise). Mirror and refraction steps count
// towards max_depth, diffuse ones towards indirect_bounces: a camera hit followed by B diffuse
// reflections is the longest path, so the inside of a closed sphere of albedo a and emission E
// shows E·(1 + a + … + a^B).
// Random numbers: each path's key is a hash of the shading point's key and the path index, each
// event's of the path key and the event count: the same image for any thread count and tiling.
#pragma once

#include <cmath>
#include <limits>

#include "render/emitters.h"
#include "render/integrator.h"
#include "render/math.h"
#include "render/media.h"
#include "render/sampling.h"
#include "render/scene.h"
#include "render/texture.h"

namespace wsd::render {

inline constexpr uint64_t kIndirectSalt = 0xc2b2ae3d27d4eb4fULL;
inline constexpr uint64_t kEventSalt = 0x165667b19e3779f9ULL;

// The key of indirect path `index` from the shading point of path `path`.
inline uint64_t indirect_key(uint64_t path, uint32_t index) {
    return mix64(path ^ ((uint64_t(index) + 1) * kIndirectSalt));
}

// A unit direction about the unit normal n with density cos θ / π (Malley's method).
inline Vec3 cosine_direction(const Vec3& n, const Uniform2& xi) {
    const double r = std::sqrt(xi.u), phi = 2.0 * kPi * xi.v;
    const double x = r * std::cos(phi), y = r * std::sin(phi), z = std::sqrt(std::max(0.0, 1.0 - xi.u));
    const Vec3 a = std::abs(n.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    const Vec3 u = glm::normalize(glm::cross(n, a));
    const Vec3 v = glm::cross(n, u);
    return glm::normalize(x * u + y * v + z * n);
}

// The power heuristic's weight for a sample of density a against another strategy's density b.
inline double power_heuristic(double a, double b) {
    const double a2 = a * a, b2 = b * b;
    if (a2 + b2 <= std::numeric_limits<double>::max()) return a2 + b2 > 0 ? a2 / (a2 + b2) : 0.0;
    // Squares past the largest double (the density of a very small emitter): the same weight
    // from the ratio of the two, which stays in range.
    if (std::isinf(a) && std::isinf(b)) return 0.5;
    if (a >= b) {
        const double r = b / a;
        return 1 / (1 + r * r);
    }
    if (a < b) {
        const double r = a / b;
        return r * r / (1 + r * r);
    }
    return 0.0;  // NaN
}

// Host: the tracer, for its direct term (`lights`) at a hit.
template <class Host>
class IndirectGather {
public:
    IndirectGather(const Scene& scene, RayStats& stats, Host& host)
        : scene_(scene),
          geom_(scene.geometry()),
          materials_(scene.materials()),
          emitters_(scene.emitters()),
          stats_(stats),
          host_(host),
          samples_(scene.settings().indirect_samples),
          bounces_(scene.settings().indirect_bounces),
          max_depth_(scene.settings().max_depth),
          background_(scene.settings().background) {}

    // The mean over indirect_samples paths of the radiance arriving at s (cosine-weighted, /π):
    // the diffuse term multiplies it by ρ. N: the shading normal on the viewer's side; medium:
    // the transmissive object the point lies in, or −1.
    Color gather(const SurfaceHit& s, const Vec3& N, uint64_t key, int medium) {
        Color sum(0);
        for (int i = 0; i < samples_; ++i) sum += path(s, N, indirect_key(key, uint32_t(i)), medium);
        return sum / double(samples_);
    }

private:
    struct Vertex {
        SurfaceHit s;
        Vec3 N, ng_v;  // shading normal and geometric normal, on the side the path arrived from
    };

    Color path(const SurfaceHit& s0, const Vec3& N0, uint64_t key, int medium) {
        ++stats_.indirect_paths;
        Color L(0), beta(1);
        Vertex v{s0, N0, glm::dot(N0, s0.ng) >= 0 ? s0.ng : -s0.ng};
        int diffuse = 1, specular = 0;
        uint64_t event = 0;
        for (;;) {
            // Diffuse reflection number `diffuse` at v.
            ++stats_.indirect_bounces;
            const uint64_t h = mix64(key ^ (++event * kEventSalt));
            if (!emitters_.empty()) L += beta * next_event(v, h);
            const Vec3 w = cosine_direction(v.N, uniform2(mix64(h ^ 1)));
            const double cos_x = glm::dot(v.N, w);
            if (!(cos_x > 0) || !(glm::dot(w, v.ng_v) > 0)) return L;  // below the surface: no light
            const double pdf_dir = cos_x / kPi;
            bool after_diffuse = true;
            Ray ray{Geometry::offset_origin(v.s, w), w};
            for (;;) {  // until the next diffuse vertex
                ++stats_.indirect_rays;
                const auto hit = geom_.intersect(ray, std::numeric_limits<double>::infinity(), stats_);
                if (!hit) {
                    L += beta * (medium >= 0 ? background_ * absorb_forever(materials_[size_t(medium)])
                                             : background_);
                    return L;
                }
                if (medium >= 0) beta *= absorb(materials_[size_t(medium)], hit->t);
                const SurfaceHit hs = geom_.surface(ray, *hit);
                const Material& m = materials_[hs.material];
                if (m.emits)
                    L += beta * (emission_weight(hs, ray, hit->t, pdf_dir, after_diffuse) * m.emission);
                if (diffuse >= bounces_) return L;

                const bool front = glm::dot(ray.d, hs.ng) < 0;
                const Vec3 ng_v = front ? hs.ng : -hs.ng;
                Vec3 ns = hs.ns;
                if (m.bump)
                    ns = bump_normal(*m.bump, m.bump_strength, hs, ns, scene_.object_to_world(hs), stats_);
                const Vec3 N = glm::dot(ns, ng_v) < 0 ? -ns : ns;
                const Color c = m.texture ? m.texture->eval(hs, stats_) : m.color;
                const double t = m.transmission;
                const uint64_t hk = mix64(key ^ (++event * kEventSalt));
                L += beta * host_.lights(hs, m, N, -ray.d, c, t, hk);

                // Choose the next step: diffuse, mirror or refracted.
                const Color rho = (1.0 - t) * m.diffuse * c;
                double fresnel = 0;
                Vec3 refl{0}, refr{0};
                bool refracts = false;
                if (m.reflection > 0 || t > 0) {
                    const Vec3 n_use = glm::dot(N, -ray.d) > 0 ? N : ng_v;
                    refl = reflect(ray.d, n_use);
                    if (glm::dot(refl, ng_v) <= 0) refl = reflect(ray.d, ng_v);
                    if (t > 0) {
                        const FresnelResult fr = fresnel_refract(ray.d, ng_v, front ? 1.0 / m.ior : m.ior);
                        fresnel = fr.reflectance;
                        refracts = !fr.total_internal;
                        refr = fr.refracted;
                    }
                }
                const double w_refl = m.reflection + t * fresnel;
                const Color w_refr = refracts ? t * (1.0 - fresnel) * c : Color(0);
                const double a_d = mean(rho), a_r = w_refl, a_t = mean(w_refr);
                const double total = a_d + a_r + a_t;
                if (!(total > 0)) return L;
                const double u = uniform2(mix64(hk ^ 1)).u * total;
                if (u < a_d) {
                    beta *= rho * (total / a_d);
                    ++diffuse;
                    v = Vertex{hs, N, ng_v};
                    break;
                }
                if (++specular > max_depth_) return L;
                after_diffuse = false;
                if (u < a_d + a_r || !(a_t > 0)) {
                    beta *= w_refl * (total / a_r);
                    ray = Ray{Geometry::offset_origin(hs, refl), refl};
                } else {
                    beta *= w_refr * (total / a_t);
                    ray = Ray{Geometry::offset_origin(hs, refr), refr};
                    medium = front ? int(hs.material) : -1;  // media do not nest (as the tracer)
                }
                if (!(max_component(beta) > 0)) return L;
            }
        }
    }

    static double mean(const Color& c) { return (c.x + c.y + c.z) / 3.0; }

    // The weight of an emitter that a path's direction found: against the emitter sample of the
    // diffuse vertex it left, when there was one and the emitter is sampled; else 1.
    double emission_weight(const SurfaceHit& hs, const Ray& ray, double t, double pdf_dir,
                           bool after_diffuse) const {
        if (!after_diffuse || hs.member != SurfaceHit::kNoMember) return 1.0;
        const double pdf_area = emitters_.pdf_area(hs.shape);
        if (!(pdf_area > 0)) return 1.0;
        const double cos_y = std::abs(glm::dot(hs.ng, ray.d));
        if (!(cos_y > 0)) return 1.0;
        const double pdf_light = pdf_area * t * t / cos_y;  // per unit solid angle (ray.d is unit)
        return power_heuristic(pdf_dir, pdf_light);
    }

    // One point on the emitters, seen from v: its radiance × cos θ / π ÷ its density per solid
    // angle, weighted against the cosine-sampled direction.
    Color next_event(const Vertex& v, uint64_t h) {
        ++stats_.emitter_samples;
        const Uniform2 a = uniform2(mix64(h ^ 2)), b = uniform2(mix64(h ^ 3));
        const EmitterPoint e = emitters_.sample(a.u, a.v, b.u, b.v);
        const Vec3 d = e.p - v.s.p;
        const double d2 = glm::dot(d, d);
        if (!(d2 > 0) || !std::isfinite(d2)) return Color(0);
        const Vec3 w = d / std::sqrt(d2);
        const double cos_x = glm::dot(v.N, w);
        if (!(cos_x > 0) || !(glm::dot(w, v.ng_v) > 0)) return Color(0);
        const double cos_y = std::abs(glm::dot(e.n, w));
        if (!(cos_y > 0)) return Color(0);
        const double pdf_light = e.pdf_area * d2 / cos_y;
        const double pdf_dir = cos_x / kPi;
        // The shadow ray ends just off the emitter, on the side facing v.
        SurfaceHit target;
        target.p = e.p;
        target.p_error = e.p_error;
        target.ng = e.n;
        const Vec3 to = Geometry::offset_origin(target, -w);
        const Vec3 from = Geometry::offset_origin(v.s, w);
        ++stats_.shadow_rays;
        if (geom_.occluded(Ray{from, to - from}, 1.0, stats_, RayFilter::All)) return Color(0);
        return e.emission * (pdf_dir / pdf_light * power_heuristic(pdf_light, pdf_dir));
    }

    const Scene& scene_;
    const Geometry& geom_;
    const std::vector<Material>& materials_;
    const Emitters& emitters_;
    RayStats& stats_;
    Host& host_;
    int samples_, bounces_, max_depth_;
    Color background_;
};

}  // namespace wsd::render
