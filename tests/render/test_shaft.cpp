// Shaft culling of area-light shadow rays: the primitives gathered for a shaft answer every ray
// inside it exactly as a full BVH traversal does, the culling really removes primitives, and a
// degenerate shaft is refused rather than trusted.
#include <catch2/catch.hpp>
#include <limits>

#include "geometry_test_util.h"
#include "render/shaft.h"

using namespace wsd::render;
using namespace wsd::render::test;

namespace {

struct Quad {
    Vec3 corner, u, v;
};

Quad random_quad(Rng& rng, double size) {
    const Vec3 centre = rng.in_box(Vec3(-size), Vec3(size));
    const double s = size * rng.log_uniform(-2, -0.3);
    const Vec3 u = s * rng.unit_vector();
    Vec3 v = glm::cross(u, rng.unit_vector());
    v *= s * rng.uniform(0.2, 1.5) / glm::length(v);
    return {centre - 0.5 * (u + v), u, v};
}

}  // namespace

TEST_CASE(
    "shadow rays inside a shaft: the gathered primitives give the full traversal's answer, through glass "
    "too") {
    Rng rng(20261124);
    int compared = 0, blocked = 0, used = 0, glass_hits = 0;
    for (int scene = 0; scene < 40; ++scene) {
        // Scales from 2^-10 to 2^10 and far from the origin, so margins are tested relative.
        const double size = std::ldexp(1.0, rng.integer(-10, 10));
        SceneSpec spec = random_scene(rng, rng.integer(1, 200), size);
        // Every fifth scene sits far from the origin (float vertices may then make a tiny
        // triangle degenerate: such a scene is refused by the build and skipped).
        const Vec3 shift = scene % 5 == 4 ? Vec3(1000 * size) : Vec3(0);
        for (ShapeSpec& s : spec.shapes) s.object_to_world = translate(shift) * s.object_to_world;
        auto geom = build_ok(spec);
        if (!geom) continue;
        for (int point = 0; point < 60; ++point) {
            const Quad q = random_quad(rng, size);
            const Vec3 apex = shift + rng.in_box(Vec3(-size), Vec3(size));
            const double radius = size * rng.log_uniform(-12, -4);
            Shaft shaft;
            if (!shaft.init(apex, radius, q.corner + shift, q.u, q.v)) continue;
            ShaftCandidates cand;
            RayStats stats;
            if (!cand.gather(*geom, shaft, ShaftSelf{}, stats)) continue;
            ++used;
            for (int s = 0; s < 50; ++s) {
                const Vec3 o = apex + radius * rng.uniform() * rng.unit_vector();
                const Vec3 P = q.corner + shift + rng.uniform() * q.u + rng.uniform() * q.v;
                const Ray ray{o, P - o};
                const bool full = geom->occluded(ray, 1.0, stats, RayFilter::OpaqueOnly);
                const bool among = cand.occluded(*geom, ray, 1.0, stats);
                REQUIRE(full == among);
                ++compared;
                blocked += full ? 1 : 0;
                // The walk through glass: the listed transmissive primitives give the same hit,
                // and none at all when the shaft says no transmissive primitive meets it.
                const auto glass = geom->intersect(ray, 1.0, stats, RayFilter::TransmissiveOnly);
                if (!cand.transmissive) REQUIRE(!glass);
                if (cand.transmissive_listed) {
                    const auto listed = cand.intersect_transmissive(*geom, ray, 1.0, stats);
                    REQUIRE(bool(glass) == bool(listed));
                    if (glass) {
                        REQUIRE(glass->t == listed->t);
                        REQUIRE(glass->prim == listed->prim);
                        REQUIRE(glass->b1 == listed->b1);
                        ++glass_hits;
                        // The walk's next segment starts just past that surface, on the ray.
                        const Vec3 next = Geometry::offset_origin(geom->surface(ray, *glass), ray.d);
                        const Ray on{next, P - next};
                        const auto a = geom->intersect(on, 1.0, stats, RayFilter::TransmissiveOnly);
                        const auto b = cand.intersect_transmissive(*geom, on, 1.0, stats);
                        REQUIRE(bool(a) == bool(b));
                        if (a) REQUIRE(a->prim == b->prim);
                    }
                }
            }
        }
    }
    // The comparison must have seen both answers many times to mean anything.
    CHECK(used > 500);
    CHECK(blocked > 1000);
    CHECK(compared - blocked > 1000);
    CHECK(glass_hits > 1000);
}

TEST_CASE("a shaft gathers only the primitives between the point and the light") {
    // A row of 20 unit spheres along x; the light is straight above sphere 10, the point below.
    std::vector<ShapeSpec> shapes;
    for (int i = 0; i < 20; ++i) shapes.push_back(sphere({3.0 * i, 0, 0}, 1, 0));
    auto geom = build_ok(scene_of(std::move(shapes)));
    REQUIRE(geom);
    Shaft shaft;
    REQUIRE(shaft.init({30, -5, 0}, 1e-9, {29.5, 10, -0.5}, {1, 0, 0}, {0, 0, 1}));
    ShaftCandidates cand;
    RayStats stats;
    REQUIRE(cand.gather(*geom, shaft, ShaftSelf{}, stats));
    CHECK(cand.count >= 1);
    CHECK(cand.count <= 4);  // one leaf at most around sphere 10
    // The light straight above sphere 10 is blocked for every sample; one far to the side is not.
    CHECK(cand.occluded(*geom, Ray{{30, -5, 0}, Vec3(0, 15, 0)}, 1.0, stats));
    Shaft side;
    REQUIRE(side.init({30, -5, 0}, 1e-9, {29.5, -5.5, 10}, {1, 0, 0}, {0, 1, 0}));
    REQUIRE(cand.gather(*geom, side, ShaftSelf{}, stats));
    CHECK(!cand.occluded(*geom, Ray{{30, -5, 0}, Vec3(0, 0, 10)}, 1.0, stats));
}

namespace {

// What the integrator does for one shading point and area light: the shaft from the point (a
// ball holding both spawn origins) to the light, and, when the light lies on one side of the
// surface, that side's origin and the surface's own primitive for the plane-side tests.
struct SurfaceShaft {
    Shaft shaft;
    ShaftSelf self;
    Vec3 o_front, o_back;
    bool ok = false;
};

SurfaceShaft surface_shaft(const SurfaceHit& s, const Quad& q, bool side_tests) {
    SurfaceShaft out;
    out.o_front = Geometry::offset_origin(s, s.ng);
    out.o_back = Geometry::offset_origin(s, -s.ng);
    const double radius = std::max(glm::length(out.o_front - s.p), glm::length(out.o_back - s.p));
    if (!out.shaft.init(s.p, radius, q.corner, q.u, q.v)) return out;
    out.ok = true;
    out.self.prim = s.prim;
    out.self.ng = s.ng;
    const int side = side_tests ? surface_side(s.p, s.ng, q.corner, q.u, q.v) : 0;
    if (side != 0) {
        out.shaft.set_origin(side > 0 ? out.o_front : out.o_back);
        out.self.ng_side = side;
    }
    return out;
}

// Flat quads (two triangles of a mesh) along the axes and turned, a ground plane and a
// tessellated sphere, among the random shapes: surfaces whose own primitives and coplanar
// neighbours the side tests must clear without changing any answer.
SceneSpec surfaces_scene(Rng& rng, double size) {
    SceneSpec spec = random_scene(rng, rng.integer(5, 60), size);
    for (int k = 0; k < 4; ++k) {
        auto m = std::make_shared<MeshData>();
        const float h = float(size);
        m->vertices = {{-h, 0, -h}, {h, 0, -h}, {h, 0, h}, {-h, 0, h}};
        m->faces = {{0, 1, 2}, {0, 2, 3}};
        ShapeSpec quad = mesh(m, 0);
        const Vec3 shift = rng.in_box(Vec3(-size), Vec3(size));
        quad.object_to_world =
            k < 2 ? translate(shift) * rotate_xyz({90.0 * k, 0, 0})
                  : translate(shift) * rotate_xyz({rng.uniform(0, 360), rng.uniform(0, 360), 0});
        spec.shapes.push_back(quad);
    }
    spec.shapes.push_back(plane(rng.unit_vector(), size * rng.uniform(-1, 1), 0));
    spec.shapes.push_back(mesh(icosphere(2, float(0.3 * size), rng.in_box(Vec3(-size), Vec3(size))), 0));
    return spec;
}

}  // namespace

TEST_CASE("shadow rays leaving a surface: primitives cleared by side give the full traversal's answer") {
    Rng rng(20261125);
    int compared = 0, blocked = 0, used = 0, with_side = 0, blocked_shafts = 0;
    long gathered_plain = 0, gathered_sides = 0;
    for (int scene = 0; scene < 30; ++scene) {
        const double size = std::ldexp(1.0, rng.integer(-10, 10));
        auto geom = build_ok(surfaces_scene(rng, size));
        if (!geom) continue;
        RayStats stats;
        for (int point = 0; point < 200; ++point) {
            const Ray view = random_ray(rng, size);
            const auto hit = geom->intersect(view, std::numeric_limits<double>::infinity(), stats);
            if (!hit) continue;
            const SurfaceHit s = geom->surface(view, *hit);
            const Quad q = random_quad(rng, size);
            const SurfaceShaft plain = surface_shaft(s, q, false);
            const SurfaceShaft sides = surface_shaft(s, q, true);
            if (!sides.ok) continue;
            ShaftCandidates cand_plain, cand;
            const bool fits_plain = cand_plain.gather(*geom, plain.shaft, plain.self, stats);
            if (!cand.gather(*geom, sides.shaft, sides.self, stats)) continue;
            ++used;
            with_side += sides.self.ng_side != 0 ? 1 : 0;
            blocked_shafts += cand.blocked ? 1 : 0;
            if (fits_plain) {
                gathered_plain += cand_plain.count;
                gathered_sides += cand.count;
            }
            for (int k = 0; k < 30; ++k) {
                const Vec3 P = q.corner + rng.uniform() * q.u + rng.uniform() * q.v;
                // As the integrator picks it: the origin on the side of the sample.
                const Vec3 o = glm::dot(P - s.p, s.ng) < 0 ? sides.o_back : sides.o_front;
                const Ray ray{o, P - o};
                const bool full = geom->occluded(ray, 1.0, stats, RayFilter::OpaqueOnly);
                REQUIRE(full == cand.occluded(*geom, ray, 1.0, stats));
                ++compared;
                blocked += full ? 1 : 0;
            }
        }
    }
    CHECK(used > 1000);
    CHECK(with_side > 500);
    CHECK(blocked_shafts > 5);  // shafts a sphere blocks entirely: every ray must agree
    CHECK(blocked > 1000);
    CHECK(compared - blocked > 1000);
    // The side tests must really clear primitives (the surface's own, at least).
    CHECK(gathered_sides < gathered_plain);
}

TEST_CASE("a point on a flat floor gathers neither floor triangle, axis-aligned or turned") {
    for (const bool turned : {false, true}) {
        auto m = std::make_shared<MeshData>();
        m->vertices = {{-600, -600, 0}, {600, -600, 0}, {600, -600, 1200}, {-600, -600, 1200}};
        m->faces = {{0, 1, 2}, {0, 2, 3}};
        ShapeSpec floor = mesh(m, 0);
        if (turned) floor.object_to_world = rotate_xyz({3, 0, 5});
        auto geom = build_ok(scene_of({floor, sphere({0, -300, 600}, 100, 0)}));
        REQUIRE(geom);
        RayStats stats;
        const Ray view{{-200, 0, -500}, Vec3(0, -600, 1000) - Vec3(-200, 0, -500)};
        const auto hit = geom->intersect(view, 1e9, stats);
        REQUIRE(hit);
        const SurfaceHit s = geom->surface(view, *hit);
        const SurfaceShaft ss = surface_shaft(s, Quad{{25, 500, 625}, {50, 0, 0}, {0, 0, 50}}, true);
        REQUIRE(ss.ok);
        CHECK(ss.self.ng_side != 0);
        ShaftCandidates cand;
        REQUIRE(cand.gather(*geom, ss.shaft, ss.self, stats));
        // Axis-aligned, both triangles are cleared exactly; turned, the point's own triangle is
        // (its side is known by construction) and the other one's side cannot be certain.
        CHECK(cand.count == (turned ? 1 : 0));
    }
}

TEST_CASE("a sphere blocks a whole shaft only when every ray from the origin to the light meets it") {
    // Lights behind a sphere as seen from a point, from well inside its silhouette to across its
    // edge, at scales 2^-10 to 2^10: each shaft blocks_all() accepts must block every ray.
    Rng rng(20261126);
    int accepted = 0, refused_all_blocked = 0, refused = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const double size = std::ldexp(1.0, rng.integer(-10, 10));
        const Vec3 centre = rng.in_box(Vec3(-size), Vec3(size));
        const double radius = size * rng.uniform(0.05, 1);
        const Vec3 axis = rng.unit_vector();
        const Vec3 origin = centre - axis * radius * rng.log_uniform(0.001, 1.3);
        // The light's centre on a line through the sphere, up to about the silhouette's edge.
        const double dist = glm::length(centre - origin);
        const double spread = std::asin(radius / dist) * rng.uniform(0, 1.3);
        Vec3 side = glm::normalize(glm::cross(axis, rng.unit_vector()));
        const Vec3 dir = std::cos(spread) * axis + std::sin(spread) * side;
        const double beyond = dist + radius * rng.uniform(-1.5, 4);  // some cut the sphere
        const Vec3 light_centre = origin + dir * beyond;
        const double extent = radius * rng.log_uniform(-4, 0.3);
        const Vec3 u = extent * glm::normalize(glm::cross(dir, rng.unit_vector()));
        const Vec3 v = extent * glm::normalize(glm::cross(dir, u));
        const Vec3 corner = light_centre - 0.5 * (u + v);
        Shaft shaft;
        if (!shaft.init(origin, 0, corner, u, v)) continue;
        shaft.set_origin(origin);
        auto geom = build_ok(scene_of({sphere(centre, radius, 0)}));
        REQUIRE(geom);
        RayStats stats;
        bool all = true;
        for (int k = 0; k < 200; ++k) {
            const Vec3 P = corner + rng.uniform() * u + rng.uniform() * v;
            all = all && geom->occluded(Ray{origin, P - origin}, 1.0, stats, RayFilter::OpaqueOnly);
        }
        if (shaft.blocks_all(centre, radius)) {
            ++accepted;
            REQUIRE(all);
        } else {
            ++refused;
            refused_all_blocked += all ? 1 : 0;
        }
    }
    // Both answers occur often, and many fully blocked lights are recognised as such.
    CHECK(accepted > 300);
    CHECK(refused > 300);
    CHECK(accepted > refused_all_blocked);
}

TEST_CASE("a shaft whose apex touches the light's plane is refused") {
    Shaft shaft;
    CHECK_FALSE(shaft.init({0, 0, 0}, 1e-9, {-1, 0, -1}, {2, 0, 0}, {0, 0, 2}));     // in the plane
    CHECK_FALSE(shaft.init({0, 1e-3, 0}, 0.01, {-1, 0, -1}, {2, 0, 0}, {0, 0, 2}));  // ball crosses it
    CHECK_FALSE(shaft.init({0, 1, 0}, 0, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}));          // parallel edges
    CHECK(shaft.init({0, 1, 0}, 1e-9, {-1, 0, -1}, {2, 0, 0}, {0, 0, 2}));
}
