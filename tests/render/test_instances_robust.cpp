// Robustness through instances (docs/robustness.md R81, R82: R1 and R12 through a two-level BVH):
// a closed mesh stays watertight when instanced under rotations, scales 2^±10 and translations of
// 10^5, and rays spawned from instanced surfaces never re-hit the member they leave.
#include <catch2/catch.hpp>
#include <limits>

#include "render/geometry.h"
#include "tests/render/geometry_test_util.h"

using namespace wsd::render;
using namespace wsd::render::test;

namespace {

std::optional<HitRecord> hit_of(const Geometry& g, const Ray& r) {
    RayStats stats;
    return g.intersect(r, std::numeric_limits<double>::infinity(), stats);
}

// Any unit vector in the hemisphere around n; some near grazing (test_robust_geometry.cpp's).
Vec3 outgoing(Rng& rng, const Vec3& n, bool grazing) {
    Vec3 w = rng.unit_vector();
    if (grazing) {
        w = w - glm::dot(w, n) * n;
        w = safe_normalize(w, Vec3(1, 0, 0)) + 1e-3 * n;
    }
    if (glm::dot(w, n) < 0) w = w - 2 * glm::dot(w, n) * n;
    return glm::normalize(w);
}

ShapeSpec instance_of(uint32_t prototype, const Mat4& x) {
    ShapeSpec s;
    s.kind = ShapeKind::Instance;
    s.prototype = prototype;
    s.object_to_world = x;
    return s;
}

}  // namespace

TEST_CASE("R81 an instanced closed mesh is watertight at scales 2^-10 .. 2^10 and 1e5 away") {
    Rng rng(168);
    auto m = perturbed_uv_sphere(16, 16, rng);
    for (int e = -10; e <= 10; e += 5)
        for (Vec3 at : {Vec3(0), Vec3(1e5, -1e5, 1e5)}) {
            if (at != Vec3(0) && e < 0) continue;  // float vertices 1e5 away sit on a 0.008 grid
            const double s = std::ldexp(1.0, e);
            const Mat4 x = translate(at) * scale(Vec3(s)) * rotate_xyz({10, 20, 30});
            SceneSpec spec = scene_of({instance_of(0, x)});
            spec.prototypes.push_back(PrototypeSpec{{mesh(m)}, 0});
            auto g = build_ok(spec);
            REQUIRE(g);
            int escapes = 0;
            for (int i = 0; i < ray_budget(20000); ++i) {
                const Vec3 o = Vec3(x * glm::dvec4(0.5 * rng.uniform() * rng.unit_vector(), 1.0));
                const glm::uvec3& f = m->faces[size_t(rng.integer(0, int(m->faces.size()) - 1))];
                const Vec3 a(x * glm::dvec4(Vec3(m->vertices[f[0]]), 1.0)),
                    b(x * glm::dvec4(Vec3(m->vertices[f[1]]), 1.0));
                const Vec3 target = i % 2 == 0 ? a : a + rng.uniform() * (b - a);  // a vertex, or on an edge
                if (!hit_of(*g, {o, target - o})) ++escapes;
            }
            INFO("scale 2^" << e << ", at " << at.x);
            CHECK(escapes == 0);
        }
}

TEST_CASE(
    "R82 rays spawned from instanced surfaces never re-hit their member, at 2^-10 .. 2^10 and 1e5 away") {
    Rng rng(1268);
    int rehits = 0, tested = 0;
    for (int e = -10; e <= 10; e += 4)
        for (Vec3 at : {Vec3(0), Vec3(1e5, -1e5, 1e5)}) {
            if (at != Vec3(0) && e < 0) continue;
            const double s = std::ldexp(1.0, e);
            ShapeSpec b = box({-1, -1, -1}, {1, 2, 1});
            b.object_to_world = rotate_xyz({10, 20, 30});
            ShapeSpec ell = sphere({0, 0, 0}, 1);
            ell.object_to_world = translate({0, 5, 0}) * scale({1, 0.3, 2});
            PrototypeSpec p{{sphere({5, 0, 0}, 1), b, ell, mesh(icosphere(2, 1.0f, {-5, 0, 0})),
                             triangle({-2, -5, -2}, {2, -5, -2}, {0, -5, 2})},
                            0};
            const Mat4 x = translate(at) * scale(Vec3(s)) * rotate_xyz({-15, 40, 5});
            SceneSpec spec = scene_of({instance_of(0, x)});
            spec.prototypes.push_back(p);
            auto g = build_ok(spec);
            REQUIRE(g);
            for (int i = 0; i < ray_budget(3000); ++i) {
                const Vec3 aims[] = {{5, 0, 0}, {0, 0.5, 0}, {0, 5, 0}, {-5, 0, 0}, {0, -5, 0}};
                const Vec3 aim = Vec3(x * glm::dvec4(aims[i % 5] + 0.5 * rng.unit_vector(), 1.0));
                const Vec3 from = aim + s * 20.0 * rng.unit_vector();
                const Ray probe{from, aim - from};
                auto h = hit_of(*g, probe);
                if (!h) continue;
                const SurfaceHit sh = g->surface(probe, *h);
                Vec3 w = outgoing(rng, sh.ng, i % 3 == 0);
                if (glm::dot(w, probe.d) > 0 && glm::dot(sh.ng, probe.d) > 0) w = -w;  // hit from behind
                const Ray spawned{Geometry::offset_origin(sh, w), w};
                ++tested;
                auto again = hit_of(*g, spawned);
                // Convex members: nothing of the same member may be hit again.
                if (again && g->surface(spawned, *again).member == sh.member) ++rehits;
            }
        }
    CHECK(tested > 10000 / (kSanitized ? 10 : 1));
    CHECK(rehits == 0);
}
