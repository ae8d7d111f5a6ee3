// Helpers for the CSG tests (test_csg.cpp, test_csg_robust.cpp): CSG shapes, closed meshes,
// brute-force point classification straight from a ShapeSpec, first hits and placements.
#pragma once

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <memory>
#include <optional>
#include <random>
#include <vector>

#include "tests/render/scene_builders.h"

namespace wsd::test::csg_util {

using render::CsgOp;
using render::CsgSpec;
using render::kInheritMaterial;
using render::Mat4;
using render::MeshData;
using render::Ray;
using render::RayStats;
using render::ShapeKind;
using render::ShapeSpec;

inline ShapeSpec csg(CsgOp op, std::vector<ShapeSpec> members, uint32_t material = kInheritMaterial) {
    auto c = std::make_shared<CsgSpec>();
    c->op = op;
    c->members = std::move(members);
    ShapeSpec s;
    s.kind = ShapeKind::Csg;
    s.csg = c;
    s.material = material;
    return s;
}

inline ShapeSpec inherit(ShapeSpec s) {
    s.material = kInheritMaterial;
    return s;
}

// A regular octahedron |x| + |y| + |z| ≤ size, faces wound outward.
inline std::shared_ptr<MeshData> octahedron(double size) {
    auto m = std::make_shared<MeshData>();
    const float f = static_cast<float>(size);
    m->vertices = {{f, 0, 0}, {-f, 0, 0}, {0, f, 0}, {0, -f, 0}, {0, 0, f}, {0, 0, -f}};
    for (int sx : {1, -1})
        for (int sy : {1, -1})
            for (int sz : {1, -1}) {
                glm::uvec3 face(sx > 0 ? 0 : 1, sy > 0 ? 2 : 3, sz > 0 ? 4 : 5);
                if (sx * sy * sz < 0) std::swap(face.y, face.z);
                m->faces.push_back(face);
            }
    return m;
}

inline ShapeSpec mesh_shape(std::shared_ptr<MeshData> m, uint32_t material) {
    ShapeSpec s;
    s.kind = ShapeKind::Mesh;
    s.mesh = std::move(m);
    s.material = material;
    return s;
}

// A closed unit cube [0,1]³ as 12 triangles; `split` gives each face its own four vertices.
inline std::shared_ptr<MeshData> cube_mesh(bool split) {
    auto m = std::make_shared<MeshData>();
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    auto corner = [](int i) { return glm::vec3(float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)); };
    if (!split)
        for (int i = 0; i < 8; ++i) m->vertices.push_back(corner(i));
    for (const auto& q : quads) {
        uint32_t v[4];
        for (int k = 0; k < 4; ++k) {
            if (split) {
                v[k] = uint32_t(m->vertices.size());
                m->vertices.push_back(corner(q[k]));
            } else {
                v[k] = uint32_t(q[k]);
            }
        }
        m->faces.push_back({v[0], v[1], v[2]});
        m->faces.push_back({v[0], v[2], v[3]});
    }
    return m;
}

// Point classification straight from the spec: each member's implicit inside test in its frame.
inline bool inside(const ShapeSpec& s, const Mat4& parent, const Vec3& p) {
    const Mat4 m = parent * s.object_to_world;
    const Vec3 q = Vec3(glm::inverse(m) * glm::dvec4(p, 1.0));
    switch (s.kind) {
        case ShapeKind::Sphere:
            return glm::dot(q - s.center, q - s.center) < s.radius * s.radius;
        case ShapeKind::Box:
            return glm::all(glm::greaterThan(q, s.box_min)) && glm::all(glm::lessThan(q, s.box_max));
        case ShapeKind::Plane:
            return glm::dot(glm::normalize(s.normal), q) < s.distance;
        case ShapeKind::Mesh:  // the octahedra of these tests
            return std::abs(q.x) + std::abs(q.y) + std::abs(q.z) < s.mesh->vertices[0].x;
        case ShapeKind::Csg: {
            const auto& ms = s.csg->members;
            switch (s.csg->op) {
                case CsgOp::Union:
                    for (const auto& c : ms)
                        if (inside(c, m, p)) return true;
                    return false;
                case CsgOp::Intersection:
                    for (const auto& c : ms)
                        if (!inside(c, m, p)) return false;
                    return true;
                case CsgOp::Difference:
                    if (!inside(ms[0], m, p)) return false;
                    for (size_t i = 1; i < ms.size(); ++i)
                        if (inside(ms[i], m, p)) return false;
                    return true;
            }
            return false;
        }
        default:
            return false;
    }
}

inline std::optional<wsd::render::HitRecord> first_hit(const wsd::render::Scene& scene, const Ray& ray) {
    RayStats stats;
    return scene.geometry().intersect(ray, std::numeric_limits<double>::infinity(), stats);
}

inline Vec3 unit(std::mt19937& rng) {
    std::normal_distribution<double> n;
    return glm::normalize(Vec3(n(rng), n(rng), n(rng)));
}

inline Mat4 placed(Vec3 axis, double degrees, Vec3 translate) {
    return glm::translate(Mat4(1.0), translate) *
           glm::rotate(Mat4(1.0), glm::radians(degrees), glm::normalize(axis));
}

}  // namespace wsd::test::csg_util
