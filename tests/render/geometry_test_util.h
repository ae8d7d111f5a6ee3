// Helpers for the geometry tests: shape builders, closed test meshes (perturbed UV sphere,
// icosphere), a seeded RNG with log-uniform magnitudes, and a ray-count knob that is smaller
// under AddressSanitizer.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/gtc/matrix_transform.hpp>
#include <map>
#include <memory>
#include <random>
#include <vector>

#include "render/geometry.h"
#include "render/math.h"

namespace wsd::render::test {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif
#else
inline constexpr bool kSanitized = false;
#endif

// The full count in optimised builds, a tenth under ASan (the suite also runs there).
inline int ray_budget(int full) {
    return kSanitized ? full / 10 : full;
}

struct Rng {
    std::mt19937_64 gen;
    explicit Rng(uint64_t seed) : gen(seed) {}
    double uniform(double lo = 0, double hi = 1) {
        return std::uniform_real_distribution<double>(lo, hi)(gen);
    }
    int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(gen); }
    // 10^U(lo, hi)
    double log_uniform(double lo_exp, double hi_exp) { return std::pow(10.0, uniform(lo_exp, hi_exp)); }
    Vec3 unit_vector() {
        for (;;) {
            Vec3 v(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
            double l = glm::length(v);
            if (l > 1e-3 && l <= 1) return v / l;
        }
    }
    Vec3 in_box(const Vec3& lo, const Vec3& hi) {
        return {uniform(lo.x, hi.x), uniform(lo.y, hi.y), uniform(lo.z, hi.z)};
    }
};

inline ShapeSpec sphere(Vec3 c, double r, uint32_t material = 0) {
    ShapeSpec s;
    s.kind = ShapeKind::Sphere;
    s.center = c;
    s.radius = r;
    s.material = material;
    return s;
}

inline ShapeSpec triangle(Vec3 a, Vec3 b, Vec3 c, uint32_t material = 0) {
    ShapeSpec s;
    s.kind = ShapeKind::Triangle;
    s.v[0] = a, s.v[1] = b, s.v[2] = c;
    s.material = material;
    return s;
}

inline ShapeSpec box(Vec3 lo, Vec3 hi, uint32_t material = 0) {
    ShapeSpec s;
    s.kind = ShapeKind::Box;
    s.box_min = lo;
    s.box_max = hi;
    s.material = material;
    return s;
}

inline ShapeSpec plane(Vec3 n, double distance, uint32_t material = 0) {
    ShapeSpec s;
    s.kind = ShapeKind::Plane;
    s.normal = n;
    s.distance = distance;
    s.material = material;
    return s;
}

inline ShapeSpec mesh(std::shared_ptr<MeshData> m, uint32_t material = 0) {
    ShapeSpec s;
    s.kind = ShapeKind::Mesh;
    s.mesh = std::move(m);
    s.material = material;
    return s;
}

// Rotation by degrees about x, then y, then z, as the language's `rotate` applies it.
inline Mat4 rotate_xyz(Vec3 deg) {
    Mat4 m(1.0);
    m = glm::rotate(Mat4(1.0), glm::radians(deg.x), Vec3(1, 0, 0)) * m;
    m = glm::rotate(Mat4(1.0), glm::radians(deg.y), Vec3(0, 1, 0)) * m;
    m = glm::rotate(Mat4(1.0), glm::radians(deg.z), Vec3(0, 0, 1)) * m;
    return m;
}
inline Mat4 translate(Vec3 t) {
    return glm::translate(Mat4(1.0), t);
}
inline Mat4 scale(Vec3 s) {
    return glm::scale(Mat4(1.0), s);
}

// A scene of the given shapes with `materials` plain materials (material 1 transmissive when
// there are at least two).
inline SceneSpec scene_of(std::vector<ShapeSpec> shapes, int materials = 2) {
    SceneSpec spec;
    spec.materials.resize(static_cast<size_t>(materials));
    if (materials > 1) spec.materials[1].transmission = 1;
    spec.shapes = std::move(shapes);
    return spec;
}

// n random spheres, ellipsoids, boxes (rotated or not) and triangles within [-size, size]³;
// about a fifth of them transmissive (material 1).
inline SceneSpec random_scene(Rng& rng, int n, double size) {
    std::vector<ShapeSpec> shapes;
    for (int i = 0; i < n; ++i) {
        Vec3 c = rng.in_box(Vec3(-size), Vec3(size));
        double r = size * rng.log_uniform(-3, -0.7);
        uint32_t mat = rng.uniform() < 0.2 ? 1u : 0u;
        switch (rng.integer(0, 5)) {
            case 0:
                shapes.push_back(sphere(c, r, mat));
                break;
            case 1: {
                ShapeSpec s = sphere({0, 0, 0}, 1, mat);
                s.object_to_world = translate(c) * rotate_xyz({rng.uniform(0, 360), rng.uniform(0, 360), 0}) *
                                    scale({r, r * rng.uniform(0.2, 2), r * rng.uniform(0.2, 2)});
                shapes.push_back(s);
                break;
            }
            case 2: {
                ShapeSpec b = box(Vec3(-r), Vec3(r) * rng.uniform(0.3, 2), mat);
                b.object_to_world = translate(c) * rotate_xyz({rng.uniform(0, 360), rng.uniform(0, 360), 0});
                shapes.push_back(b);
                break;
            }
            case 3:
                shapes.push_back(box(c - Vec3(r), c + Vec3(r), mat));
                break;
            default:
                shapes.push_back(triangle(c + 2 * r * rng.unit_vector(), c + 2 * r * rng.unit_vector(),
                                          c + 2 * r * rng.unit_vector(), mat));
                break;
        }
    }
    return scene_of(std::move(shapes));
}

// A ray from around the scene, mostly aimed into it.
inline Ray random_ray(Rng& rng, double size) {
    Vec3 o = rng.in_box(Vec3(-1.5 * size), Vec3(1.5 * size));
    // Mostly aimed into the scene so that many rays hit something.
    Vec3 target = rng.in_box(Vec3(-size), Vec3(size));
    Vec3 d = rng.uniform() < 0.8 ? target - o : rng.unit_vector() * size;
    return {o, d};
}

inline std::unique_ptr<Geometry> build_ok(const SceneSpec& spec, bool use_bvh = true, int threads = 1) {
    std::vector<SpecError> errors;
    auto g = Geometry::build(spec, errors, use_bvh, threads);
    return errors.empty() ? std::move(g) : nullptr;
}

// pbrt-v4's Triangle.Watertight mesh: a closed UV sphere whose vertices are
// pushed out radially by up to `bump` (5 in pbrt's test: spiky); poles and the seam share vertices.
// bump 0 gives the plain UV sphere of the given radius.
inline std::shared_ptr<MeshData> perturbed_uv_sphere(int n_theta, int n_phi, Rng& rng, Vec3 offset = Vec3(0),
                                                     double bump = 5, double radius = 1) {
    auto m = std::make_shared<MeshData>();
    auto push = [&](double theta, double phi) {
        double r = radius * (1 + rng.uniform(0, bump));
        Vec3 p = offset +
                 r * Vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
        m->vertices.emplace_back(static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z));
    };
    push(0, 0);
    for (int t = 1; t < n_theta; ++t)
        for (int p = 0; p < n_phi; ++p) push(kPi * t / n_theta, 2 * kPi * p / n_phi);
    push(kPi, 0);
    auto idx = [&](int t, int p) { return static_cast<unsigned>(1 + (t - 1) * n_phi + (p % n_phi)); };
    const unsigned south = static_cast<unsigned>(m->vertices.size() - 1);
    for (int p = 0; p < n_phi; ++p) m->faces.push_back({0u, idx(1, p + 1), idx(1, p)});
    for (int t = 1; t < n_theta - 1; ++t)
        for (int p = 0; p < n_phi; ++p) {
            m->faces.push_back({idx(t, p), idx(t, p + 1), idx(t + 1, p + 1)});
            m->faces.push_back({idx(t, p), idx(t + 1, p + 1), idx(t + 1, p)});
        }
    for (int p = 0; p < n_phi; ++p) m->faces.push_back({south, idx(n_theta - 1, p), idx(n_theta - 1, p + 1)});
    return m;
}

// Opaque triangles only, within about [-size, size]³: a few closed meshes of random resolution
// and loose triangles.
inline SceneSpec mesh_scene(Rng& rng, double size) {
    std::vector<ShapeSpec> shapes;
    for (int i = rng.integer(1, 3); i > 0; --i)
        shapes.push_back(mesh(perturbed_uv_sphere(rng.integer(2, 40), rng.integer(3, 60), rng,
                                                  rng.in_box(Vec3(-0.6 * size), Vec3(0.6 * size)),
                                                  rng.uniform(0, 0.5), 0.4 * size)));
    for (int i = rng.integer(0, 60); i > 0; --i) {
        const Vec3 c = rng.in_box(Vec3(-size), Vec3(size));
        const double r = size * rng.log_uniform(-3, -1);
        shapes.push_back(
            triangle(c + r * rng.unit_vector(), c + r * rng.unit_vector(), c + r * rng.unit_vector()));
    }
    return scene_of(std::move(shapes));
}

// An icosphere of `levels` subdivisions (20·4^levels faces, outward winding, shared vertices).
inline std::shared_ptr<MeshData> icosphere(int levels, float radius, Vec3 center = Vec3(0)) {
    const double t = (1 + std::sqrt(5.0)) / 2;
    std::vector<Vec3> v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                           {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    for (auto& p : v) p = glm::normalize(p);
    std::vector<glm::uvec3> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<unsigned, unsigned>, unsigned> mid;
        auto midpoint = [&](unsigned a, unsigned b) {
            auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            v.push_back(glm::normalize(v[a] + v[b]));
            unsigned i = static_cast<unsigned>(v.size() - 1);
            mid.emplace(key, i);
            return i;
        };
        std::vector<glm::uvec3> next;
        for (const auto& tri : f) {
            unsigned a = midpoint(tri.x, tri.y), b = midpoint(tri.y, tri.z), c = midpoint(tri.z, tri.x);
            next.push_back({tri.x, a, c});
            next.push_back({tri.y, b, a});
            next.push_back({tri.z, c, b});
            next.push_back({a, b, c});
        }
        f = std::move(next);
    }
    auto m = std::make_shared<MeshData>();
    for (const auto& p : v) {
        Vec3 q = center + static_cast<double>(radius) * p;
        m->vertices.emplace_back(static_cast<float>(q.x), static_cast<float>(q.y), static_cast<float>(q.z));
    }
    // Wind every face counter-clockwise seen from outside (normal away from the centre).
    for (auto& tri : f) {
        Vec3 a = v[tri.x], b = v[tri.y], c = v[tri.z];
        if (glm::dot(glm::cross(b - a, c - a), a + b + c) < 0) std::swap(tri.y, tri.z);
    }
    m->faces = std::move(f);
    return m;
}

}  // namespace wsd::render::test
