// Shaft culling of area-light shadow rays: the primitives gathered for a shaft answer every ray
// inside it exactly as a full BVH traversal does, the culling really removes primitives, and a
// degenerate shaft is refused rather than trusted.
#include <catch2/catch.hpp>

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

TEST_CASE("shadow rays inside a shaft: the gathered primitives give the full traversal's answer") {
    Rng rng(20261124);
    int compared = 0, blocked = 0, used = 0;
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
            if (!geom->gather_shaft(shaft, cand, stats)) continue;
            ++used;
            for (int s = 0; s < 50; ++s) {
                const Vec3 o = apex + radius * rng.uniform() * rng.unit_vector();
                const Vec3 P = q.corner + shift + rng.uniform() * q.u + rng.uniform() * q.v;
                const Ray ray{o, P - o};
                const bool full = geom->occluded(ray, 1.0, stats, RayFilter::OpaqueOnly);
                const bool among = geom->occluded_among(cand, ray, 1.0, stats);
                REQUIRE(full == among);
                ++compared;
                blocked += full ? 1 : 0;
            }
        }
    }
    // The comparison must have seen both answers many times to mean anything.
    CHECK(used > 500);
    CHECK(blocked > 1000);
    CHECK(compared - blocked > 1000);
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
    REQUIRE(geom->gather_shaft(shaft, cand, stats));
    CHECK(cand.count >= 1);
    CHECK(cand.count <= 4);  // one leaf at most around sphere 10
    // The light straight above sphere 10 is blocked for every sample; one far to the side is not.
    CHECK(geom->occluded_among(cand, Ray{{30, -5, 0}, Vec3(0, 15, 0)}, 1.0, stats));
    Shaft side;
    REQUIRE(side.init({30, -5, 0}, 1e-9, {29.5, -5.5, 10}, {1, 0, 0}, {0, 1, 0}));
    REQUIRE(geom->gather_shaft(side, cand, stats));
    CHECK(!geom->occluded_among(cand, Ray{{30, -5, 0}, Vec3(0, 0, 10)}, 1.0, stats));
}

TEST_CASE("a shaft whose apex touches the light's plane is refused") {
    Shaft shaft;
    CHECK_FALSE(shaft.init({0, 0, 0}, 1e-9, {-1, 0, -1}, {2, 0, 0}, {0, 0, 2}));    // in the plane
    CHECK_FALSE(shaft.init({0, 1e-3, 0}, 0.01, {-1, 0, -1}, {2, 0, 0}, {0, 0, 2}));  // ball crosses it
    CHECK_FALSE(shaft.init({0, 1, 0}, 0, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}));           // parallel edges
    CHECK(shaft.init({0, 1, 0}, 1e-9, {-1, 0, -1}, {2, 0, 0}, {0, 0, 2}));
}
