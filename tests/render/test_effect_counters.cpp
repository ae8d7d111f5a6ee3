// "Simulate only the effects a scene calls for", proved with counters: a plain diffuse
// scene under a point light does no work of any optional kind; switching on one effect at a time
// (mirror, glass, area light, checker texture, Perlin texture, bump) makes exactly that
// kind of work non-zero, and a material with a zero weight spawns nothing.
#include <catch2/catch.hpp>

#include "scene_builders.h"

using namespace wsd::test;
namespace render = wsd::render;

namespace {

// A matte sphere on a matte plane under one point light, 16×16 pixels, one ray per pixel.
render::SceneSpec plain_scene() {
    auto spec = basic_scene(16, 16);
    spec.shapes.push_back(sphere({0, 0, 0}, 1, add_material(spec, matte({0.5, 0.5, 0.5}))));
    spec.shapes.push_back(plane({0, 1, 0}, -1, add_material(spec, matte({0.8, 0.8, 0.8}))));
    spec.lights.push_back(point_light({2, 3, -3}));
    return spec;
}

render::TextureSpec perlin_texture(render::PerlinKind kind) {
    render::TextureSpec t;
    t.kind = render::TextureKind::Perlin;
    t.perlin = kind;
    t.perlin_scale = Vec3(4.0);
    return t;
}

}  // namespace

TEST_CASE("counters: a plain diffuse scene does no optional work at all", "[effects][stats]") {
    const auto r = render_spec(plain_scene());
    CHECK(r.stats.camera_rays == 256);
    CHECK(r.stats.shadow_rays > 0);
    // A point light takes one shadow ray per lit-side shading point: never more than the camera rays.
    CHECK(r.stats.shadow_rays <= r.stats.camera_rays);
    CHECK(r.stats.reflection_rays == 0);
    CHECK(r.stats.refraction_rays == 0);
    CHECK(r.stats.fresnel_evals == 0);
    CHECK(r.stats.texture_evals == 0);
    CHECK(r.stats.noise_evals == 0);
    CHECK(r.stats.adaptive_pixels == 0);
}

TEST_CASE("counters: each effect switched on alone costs only its own kind of work", "[effects][stats]") {
    SECTION("an area light: many shadow rays per point, nothing else") {
        auto spec = plain_scene();
        spec.lights[0] = area_light({2, 3, -3}, {1, 0, 0}, {0, 0, 1}, 4, 4);
        const auto r = render_spec(spec);
        CHECK(r.stats.shadow_rays > 8 * r.stats.camera_rays);
        CHECK(r.stats.reflection_rays + r.stats.refraction_rays + r.stats.fresnel_evals == 0);
        CHECK(r.stats.texture_evals + r.stats.noise_evals == 0);
    }
    SECTION("a checker texture: texture lookups, no noise, no secondary rays") {
        auto spec = plain_scene();
        render::TextureSpec checker;
        checker.kind = render::TextureKind::Checker;
        checker.checker_scale = 0.5;
        spec.materials[1].texture = checker;
        const auto r = render_spec(spec);
        CHECK(r.stats.texture_evals > 0);
        CHECK(r.stats.noise_evals == 0);
        CHECK(r.stats.reflection_rays + r.stats.refraction_rays == 0);
    }
    SECTION("a Perlin texture: noise evaluations, no secondary rays") {
        auto spec = plain_scene();
        spec.materials[0].texture = perlin_texture(render::PerlinKind::Marble);
        const auto r = render_spec(spec);
        CHECK(r.stats.noise_evals > 0);
        CHECK(r.stats.reflection_rays + r.stats.refraction_rays + r.stats.fresnel_evals == 0);
    }
    SECTION("a bump: noise evaluations only") {
        auto spec = plain_scene();
        spec.materials[0].bump = perlin_texture(render::PerlinKind::Noise);
        spec.materials[0].bump_strength = 0.5;
        const auto r = render_spec(spec);
        CHECK(r.stats.noise_evals > 0);
        CHECK(r.stats.texture_evals == 0);
        CHECK(r.stats.reflection_rays + r.stats.refraction_rays == 0);
    }
    SECTION("a mirror: reflection rays but no Fresnel term and no refraction") {
        auto spec = plain_scene();
        spec.materials[0].reflection = 0.5;
        const auto r = render_spec(spec);
        CHECK(r.stats.reflection_rays > 0);
        CHECK(r.stats.refraction_rays == 0);
        CHECK(r.stats.fresnel_evals == 0);
        CHECK(r.stats.texture_evals + r.stats.noise_evals == 0);
    }
    SECTION("glass: refraction rays and Fresnel terms") {
        auto spec = plain_scene();
        spec.materials[0] = glass();
        const auto r = render_spec(spec);
        CHECK(r.stats.refraction_rays > 0);
        CHECK(r.stats.fresnel_evals > 0);
    }
}

TEST_CASE("counters: zero weights spawn no rays even where the material kind allows them",
          "[effects][stats]") {
    auto spec = plain_scene();
    spec.materials[0].reflection = 0.0;
    spec.materials[0].specular = 1.0;  // a shiny but non-mirroring surface
    const auto shiny = render_spec(spec);
    CHECK(shiny.stats.reflection_rays == 0);
    CHECK(shiny.stats.fresnel_evals == 0);

    // Only the surfaces whose material mirrors spawn reflected rays: with the floor mirroring and
    // the sphere at reflection 0 there are strictly fewer than with both mirroring.
    auto floor_mirror = plain_scene();
    floor_mirror.materials[1].reflection = 0.3;
    auto both_mirror = floor_mirror;
    both_mirror.materials[0].reflection = 0.3;
    const auto floor_only = render_spec(floor_mirror);
    const auto both = render_spec(both_mirror);
    CHECK(floor_only.stats.reflection_rays > 0);
    CHECK(floor_only.stats.reflection_rays < both.stats.reflection_rays);
}
