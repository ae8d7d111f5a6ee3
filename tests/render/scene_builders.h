// Helpers for building render::SceneSpecs by hand in tests (no .wsd involved): shapes, materials,
// lights, a one-call build+render that asserts no NaN/Inf sample, pixel access, and single-ray
// tracing through a Tracer.
#pragma once

#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "render/camera.h"
#include "render/integrator.h"
#include "render/renderer.h"
#include "render/sampling.h"
#include "render/scene.h"
#include "render/scene_spec.h"

namespace wsd::test {

using render::Color;
using render::Vec2;
using render::Vec3;

// A small scene: camera at `eye` looking at the origin, no lights, black background.
inline render::SceneSpec basic_scene(int width, int height, Vec3 eye = {0, 0, -5}, double fov = 40) {
    render::SceneSpec spec;
    spec.settings.width = width;
    spec.settings.height = height;
    spec.settings.supersamples = 1;
    spec.camera.position = eye;
    spec.camera.look_at = {0, 0, 0};
    spec.camera.fov_degrees = fov;
    return spec;
}

inline uint32_t add_material(render::SceneSpec& spec, const render::MaterialSpec& m) {
    spec.materials.push_back(m);
    return uint32_t(spec.materials.size() - 1);
}

inline render::MaterialSpec matte(Color c, double ambient = 0.2) {
    render::MaterialSpec m;
    m.color = c;
    m.ambient = ambient;
    return m;
}

inline render::MaterialSpec glass(double ior = 1.5, Color c = Color(1), Color absorption = Color(0)) {
    render::MaterialSpec m;
    m.color = c;
    m.transmission = 1;
    m.ior = ior;
    m.absorption = absorption;
    m.diffuse = 0;
    return m;
}

inline render::ShapeSpec sphere(Vec3 c, double r, uint32_t material) {
    render::ShapeSpec s;
    s.kind = render::ShapeKind::Sphere;
    s.center = c;
    s.radius = r;
    s.material = material;
    return s;
}

inline render::ShapeSpec box(Vec3 lo, Vec3 hi, uint32_t material) {
    render::ShapeSpec s;
    s.kind = render::ShapeKind::Box;
    s.box_min = lo;
    s.box_max = hi;
    s.material = material;
    return s;
}

inline render::ShapeSpec plane(Vec3 n, double d, uint32_t material) {
    render::ShapeSpec s;
    s.kind = render::ShapeKind::Plane;
    s.normal = n;
    s.distance = d;
    s.material = material;
    return s;
}

inline render::ShapeSpec triangle(Vec3 a, Vec3 b, Vec3 c, uint32_t material) {
    render::ShapeSpec s;
    s.kind = render::ShapeKind::Triangle;
    s.v[0] = a;
    s.v[1] = b;
    s.v[2] = c;
    s.material = material;
    return s;
}

// A parallelogram (corner, edges u and v) as a two-triangle mesh, normal cross(u, v).
inline render::ShapeSpec quad(Vec3 corner, Vec3 u, Vec3 v, uint32_t material) {
    auto mesh = std::make_shared<render::MeshData>();
    for (Vec3 p : {corner, corner + u, corner + u + v, corner + v}) mesh->vertices.emplace_back(p);
    mesh->faces = {{0, 1, 2}, {0, 2, 3}};
    render::ShapeSpec s;
    s.kind = render::ShapeKind::Mesh;
    s.mesh = mesh;
    s.material = material;
    return s;
}

inline render::LightSpec point_light(Vec3 p, double intensity = 1, Color c = Color(1)) {
    render::LightSpec l;
    l.kind = render::LightKind::Point;
    l.position = p;
    l.intensity = intensity;
    l.color = c;
    return l;
}

inline render::LightSpec area_light(Vec3 centre, Vec3 u, Vec3 v, int nu, int nv,
                                    render::LightSampling sampling = render::LightSampling::Jittered,
                                    double intensity = 1) {
    render::LightSpec l;
    l.kind = render::LightKind::Area;
    l.position = centre;
    l.u = u;
    l.v = v;
    l.samples_u = nu;
    l.samples_v = nv;
    l.sampling = sampling;
    l.intensity = intensity;
    return l;
}

inline std::shared_ptr<const render::Scene> build(const render::SceneSpec& spec) {
    std::vector<render::SpecError> errors;
    auto scene = render::build_scene(spec, errors, true, 1);
    for (const auto& e : errors) UNSCOPED_INFO("spec error: " << e.message);
    REQUIRE(scene);
    return scene;
}

// Every render made through this helper asserts that no sample was NaN or infinite (robustness.md
// R51: the film replaces such a sample by 0 and counts it in stats.nonfinite_samples).
inline render::RenderResult render_spec(const render::SceneSpec& spec, render::RenderOptions options = {}) {
    if (options.threads == 0) options.threads = 2;
    auto result = render::render(*build(spec), options);
    CHECK(result.stats.nonfinite_samples == 0);
    return result;
}

inline Color pixel(const render::Film& film, int x, int y) {
    const size_t i = 3 * (size_t(y) * size_t(film.width) + size_t(x));
    return {film.rgb[i], film.rgb[i + 1], film.rgb[i + 2]};
}

inline render::Ray camera_ray(const render::SceneSpec& spec, double px, double py) {
    std::string err;
    auto cam = render::Camera::create(spec.camera, spec.settings.width, spec.settings.height, err);
    REQUIRE(cam);
    return cam->ray(px, py);
}

// Traces single rays through a scene's integrator, counting into `stats`.
struct RayProbe {
    std::shared_ptr<const render::Scene> scene;
    render::RayStats stats;
    std::unique_ptr<render::Tracer> tracer;

    explicit RayProbe(const render::SceneSpec& spec, render::TracerOptions options = {})
        : scene(build(spec)), tracer(render::make_tracer(*scene, options, stats)) {}

    // Asserts that the colour is finite (the film's NaN/Inf check does not see single rays).
    Color trace(Vec3 origin, Vec3 dir, uint64_t key = 1) {
        const Color c = tracer->trace_ray(render::Ray{origin, glm::normalize(dir)}, key);
        if (!(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)))
            FAIL_CHECK("non-finite ray colour");
        return c;
    }
};

// The distance along a ray to the sphere (c, r), or a negative number for a miss.
inline double hit_sphere(const render::Ray& ray, Vec3 c, double r) {
    const Vec3 oc = ray.o - c;
    const double b = glm::dot(oc, ray.d);
    const double disc = b * b - (glm::dot(oc, oc) - r * r);
    if (disc < 0) return -1;
    return -b - std::sqrt(disc);
}

inline bool close_to(const Color& a, const Color& b, double tol) {
    return std::abs(a.x - b.x) <= tol && std::abs(a.y - b.y) <= tol && std::abs(a.z - b.z) <= tol;
}

}  // namespace wsd::test
