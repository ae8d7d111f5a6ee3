// The scenes and rays of the side-by-side benchmark (bench_embree.cpp), made once and traced by
// both sides: the scenes as SceneSpecs (every primitive opaque), the rays as float values held in
// doubles, secondary rays from wsd's own primary hits. Nothing here uses Embree.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "bench/cornell_geometry.h"
#include "bench/uv_sphere.h"
#include "render/geometry.h"
#include "render/math.h"
#include "render/texture.h"

namespace wsd::bench {

using namespace wsd::render;

inline constexpr double kInf = std::numeric_limits<double>::infinity();

struct SceneDef {
    std::string name;
    SceneSpec spec;
    Vec3 eye, target;
    double fov_deg = 45;
    int size = 512;  // size×size primary rays
    Vec3 light_corner, light_u, light_v;
    double scale = 1;  // the scene's size, for the origin class
};

// A closed axis-aligned room of 12 triangles.
inline ShapeSpec room(Vec3 lo, Vec3 hi) {
    auto m = std::make_shared<MeshData>();
    for (int k = 0; k < 8; ++k)
        m->vertices.push_back({static_cast<float>(k & 1 ? hi.x : lo.x),
                               static_cast<float>(k & 2 ? hi.y : lo.y),
                               static_cast<float>(k & 4 ? hi.z : lo.z)});
    const unsigned quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                                  {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    for (const auto& q : quads) {
        m->faces.push_back({q[0], q[1], q[2]});
        m->faces.push_back({q[0], q[2], q[3]});
    }
    ShapeSpec s;
    s.kind = ShapeKind::Mesh;
    s.mesh = m;
    return s;
}

inline SceneDef displaced_mesh_scene(const std::string& name, int slices, int stacks) {
    SceneDef d;
    d.name = name;
    d.spec.materials.resize(1);
    ShapeSpec mesh;
    mesh.kind = ShapeKind::Mesh;
    auto m = uv_sphere(slices, stacks, 1.0f);
    for (auto& v : m->vertices) {
        const Vec3 p(v);
        const double r = 1 + 0.1 * perlin_noise(4 * p.x, 4 * p.y, 4 * p.z);
        v = Vec3f(static_cast<float>(p.x * r), static_cast<float>(p.y * r), static_cast<float>(p.z * r));
    }
    mesh.mesh = m;
    d.spec.shapes.push_back(mesh);
    d.spec.shapes.push_back(room({-4, -1.2, -4}, {4, 3, 4}));
    d.eye = {0.3, 0.4, -3};
    d.target = {0, 0, 0};
    d.fov_deg = 45;
    d.size = 1024;
    d.light_corner = {-0.5, 2.95, -0.5};
    d.light_u = {1, 0, 0};
    d.light_v = {0, 0, 1};
    d.scale = 4;
    return d;
}

inline SceneDef cornell_scene() {
    SceneDef d;
    d.name = "cornell";
    d.spec = cornell_geometry();
    for (auto& m : d.spec.materials) m.transmission = 0;
    d.eye = {0, 0, -550};
    d.target = {0, 0, 500};
    d.fov_deg = 60;
    d.size = 512;
    d.light_corner = {0, 500, 600};
    d.light_u = {50, 0, 0};
    d.light_v = {0, 0, 50};
    d.scale = 600;
    return d;
}

struct RaySet {
    std::string name;
    std::vector<Ray> rays;  // float values held in doubles
    double tmax = kInf;
};

inline Vec3 to_float_vec(const Vec3& v) {
    return Vec3(static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z));
}

// o rounded to float componentwise away from p (the surface point it was offset from).
inline Vec3 round_away(const Vec3& o, const Vec3& p) {
    Vec3 r;
    for (int a = 0; a < 3; ++a) r[a] = o[a] >= p[a] ? to_float_up(o[a]) : to_float_down(o[a]);
    return r;
}

struct Rng {
    uint64_t s;
    double next() {  // splitmix64, in [0, 1)
        uint64_t z = (s += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        z ^= z >> 31;
        return static_cast<double>(z >> 11) * 0x1.0p-53;
    }
};

inline RaySet primary_rays(const SceneDef& d) {
    RaySet out{"primary", {}, kInf};
    const Vec3 fwd = glm::normalize(d.target - d.eye);
    const Vec3 right = glm::normalize(glm::cross(Vec3(0, 1, 0), fwd));
    const Vec3 up = glm::cross(fwd, right);
    const double h = std::tan(d.fov_deg * kPi / 360);
    const int n = d.size;
    const Vec3 eye = to_float_vec(d.eye);
    for (int ty = 0; ty < n; ty += 16)
        for (int tx = 0; tx < n; tx += 16)
            for (int by = ty; by < ty + 16; by += 4)
                for (int bx = tx; bx < tx + 16; bx += 4)
                    for (int k = 0; k < 16; ++k) {
                        const int x = bx + k % 4, y = by + k / 4;
                        const double sx = (2 * (x + 0.5) / n - 1) * h, sy = (1 - 2 * (y + 0.5) / n) * h;
                        out.rays.push_back({eye, to_float_vec(fwd + sx * right + sy * up)});
                    }
    return out;
}

// Shadow and diffuse rays from wsd's primary hits.
inline void secondary_rays(const SceneDef& d, const Geometry& g, const RaySet& primary, RaySet& shadow,
                           RaySet& diffuse) {
    shadow = {"shadow", {}, 1.0};
    diffuse = {"diffuse", {}, kInf};
    Rng rng{12345};
    RayStats stats;
    for (const Ray& r : primary.rays) {
        auto hit = g.intersect(r, kInf, stats);
        if (!hit) continue;
        const SurfaceHit s = g.surface(r, *hit);
        const Vec3 light = d.light_corner + rng.next() * d.light_u + rng.next() * d.light_v;
        const Vec3 os = round_away(Geometry::offset_origin(s, light - s.p), s.p);
        shadow.rays.push_back({os, to_float_vec(light - os)});
        const Vec3 n = glm::dot(s.ng, r.d) < 0 ? s.ng : -s.ng;
        const Vec3 t =
            glm::normalize(std::abs(n.x) > 0.9 ? glm::cross(n, Vec3(0, 1, 0)) : glm::cross(n, Vec3(1, 0, 0)));
        const Vec3 b = glm::cross(n, t);
        const double u1 = rng.next(), u2 = rng.next();
        const double rad = std::sqrt(u1), phi = 2 * kPi * u2;
        const Vec3 w =
            rad * std::cos(phi) * t + rad * std::sin(phi) * b + std::sqrt(std::max(0.0, 1 - u1)) * n;
        const Vec3 od = round_away(Geometry::offset_origin(s, w), s.p);
        diffuse.rays.push_back({od, to_float_vec(w)});
    }
}

}  // namespace wsd::bench
