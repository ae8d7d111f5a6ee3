// The AOV walk: the camera ray's first hit gives the depth; pure mirrors and clear glass pass the
// walk on along the ray the integrator follows there, the first other surface gives the albedo
// and the shading normal (bumped and turned to the viewer as the integrator shades it).
#include "render/aov.h"

#include "render/integrator.h"
#include "render/math.h"
#include "render/scene.h"
#include "render/texture.h"

namespace wsd::render {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The direction the walk leaves a pure mirror in: the mirror ray about N, or about the
// geometric normal when a bent N would send it below the surface (as the integrator does).
Vec3 mirror_direction(const Vec3& d, const Vec3& N, const Vec3& ng_v) {
    const Vec3 r = reflect(d, N);
    return glm::dot(r, ng_v) <= 0 ? reflect(d, ng_v) : r;
}

// The direction the walk leaves clear glass in: the refracted ray, or the reflected one under
// total internal reflection, with the integrator's fallback to the geometric normal.
Vec3 glass_direction(const Vec3& d, const Vec3& N, const Vec3& ng_v, double eta) {
    const Vec3 n_use = glm::dot(N, -d) > 0 ? N : ng_v;
    Vec3 refl = reflect(d, n_use);
    FresnelResult fr = fresnel_refract(d, n_use, eta);
    if (n_use != ng_v &&
        (glm::dot(refl, ng_v) <= 0 || (!fr.total_internal && glm::dot(fr.refracted, ng_v) >= 0))) {
        refl = reflect(d, ng_v);
        fr = fresnel_refract(d, ng_v, eta);
    }
    return fr.total_internal ? refl : fr.refracted;
}

}  // namespace

bool aov_pure_mirror(const Material& m, const Color& c) {
    if (!(m.reflection >= 1)) return false;
    for (int k = 0; k < 3; ++k)
        if (m.diffuse * c[k] != 0 || m.ambient * c[k] != 0) return false;
    return true;
}

bool aov_clear_glass(const Material& m, const Color& c) {
    return m.transmission >= 1 && c == Color(1) && !m.absorbs;
}

AovTracer::AovTracer(const Scene& scene) : scene_(scene) {}

AovSample AovTracer::sample(double px, double py) {
    const Geometry& geom = scene_.geometry();
    const int max_depth = scene_.settings().max_depth;
    AovSample out;
    Ray ray = scene_.camera().ray(px, py);
    std::optional<HitRecord> hit = geom.intersect(ray, kInfinity, stats_, RayFilter::All);
    if (!hit) return out;
    out.depth = hit->t;  // camera rays have unit directions
    for (int depth = 0;; ++depth) {
        const SurfaceHit s = geom.surface(ray, *hit);
        const Material& m = scene_.materials()[s.material];
        const Vec3 ng_v = glm::dot(ray.d, s.ng) < 0 ? s.ng : -s.ng;
        Vec3 ns = s.ns;
        if (m.bump)
            ns = bump_normal(*m.bump, m.bump_strength, s, ns, scene_.object_to_world(s.shape), stats_);
        const Vec3 N = glm::dot(ns, ng_v) < 0 ? -ns : ns;
        const Color c = m.texture ? m.texture->eval(s, stats_) : m.color;
        const bool mirror = aov_pure_mirror(m, c);
        if (!mirror && !aov_clear_glass(m, c)) {
            if (finite3(c) && finite3(N)) {
                out.albedo = c;
                out.normal = N;
            }
            return out;
        }
        if (depth >= max_depth) return out;  // the image is black there too
        const bool front = glm::dot(ray.d, s.ng) < 0;
        const Vec3 dir = mirror ? mirror_direction(ray.d, N, ng_v)
                                : glass_direction(ray.d, N, ng_v, front ? 1.0 / m.ior : m.ior);
        ray = Ray{Geometry::offset_origin(s, dir), dir};
        hit = geom.intersect(ray, kInfinity, stats_, RayFilter::All);
        if (!hit) return out;
    }
}

}  // namespace wsd::render
