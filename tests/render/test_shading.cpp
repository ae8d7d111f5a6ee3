// Shading rules: Fresnel and Snell (robustness.md R38, R39), Phong specular without NaN (R58),
// ambient-only materials (R64), two-sided lighting, glass shadows, depth and bailout limits,
// ray counters, effect analysis and build_scene validation.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "render/effects.h"
#include "render/integrator.h"
#include "tests/render/scene_builders.h"

using namespace wsd::test;
using wsd::render::fresnel_refract;
using wsd::render::SpecItem;

TEST_CASE("R38: Fresnel boundary values", "[shading][fresnel]") {
    const Vec3 n{0, 0, 1};
    CHECK(fresnel_refract({0, 0, -1}, n, 1 / 1.5).reflectance == Approx(0.04).margin(1e-12));
    CHECK(fresnel_refract({0, 0, -1}, n, 1.5).reflectance == Approx(0.04).margin(1e-12));
    // Grazing incidence reflects everything.
    CHECK(fresnel_refract({1, 0, 0}, n, 1 / 1.5).reflectance == Approx(1.0).margin(1e-12));
    // eta = 1: no reflection and the ray goes straight on, exactly.
    const Vec3 d = glm::normalize(Vec3(0.3, -0.2, -0.9));
    const auto same = fresnel_refract(d, n, 1.0);
    CHECK(same.reflectance == 0.0);
    CHECK(same.refracted == d);
    // Inside glass: F rises monotonically to 1 at the critical angle, and is 1 beyond it.
    const double critical = std::asin(1 / 1.5);
    double last = 0;
    for (int i = 0; i <= 100; ++i) {
        const double a = critical * i / 100.0 * 0.999999;
        const auto r = fresnel_refract({std::sin(a), 0, -std::cos(a)}, n, 1.5);
        REQUIRE(!r.total_internal);
        CHECK(r.reflectance >= last);
        last = r.reflectance;
    }
    CHECK(last > 0.9);
    for (double a : {critical + 1e-9, 0.8, 1.2, 1.5}) {
        const auto r = fresnel_refract({std::sin(a), 0, -std::cos(a)}, n, 1.5);
        CHECK(r.total_internal);
        CHECK(r.reflectance == 1.0);
    }
    // Slightly non-unit cosines stay finite.
    for (double z : {-1 - 1e-7, 1 + 1e-7}) {
        const auto r = fresnel_refract({0, 0, z}, n, 1 / 1.5);
        CHECK(std::isfinite(r.reflectance));
    }
}

TEST_CASE("R39: Snell's law, unit length and reversibility", "[shading][fresnel]") {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    const Vec3 n{0, 0, 1};
    for (double eta : {1 / 2.4, 1 / 1.5, 1.0, 1.33, 1.5, 2.4}) {
        for (int k = 0; k < 2000; ++k) {
            Vec3 d{u(rng), u(rng), -std::abs(u(rng)) - 1e-3};
            d = glm::normalize(d);
            const double sin_i = std::sqrt(std::max(0.0, 1 - d.z * d.z));
            const auto r = fresnel_refract(d, n, eta);
            CHECK(r.total_internal == (eta * sin_i >= 1));
            if (r.total_internal) continue;
            const double sin_t = std::sqrt(std::max(0.0, 1 - r.refracted.z * r.refracted.z));
            CHECK(eta * sin_i == Approx(sin_t).margin(1e-9));
            CHECK(glm::length(r.refracted) == Approx(1).margin(1e-12));
            CHECK(r.refracted.z < 0);
            const auto back = fresnel_refract(-r.refracted, n * -1.0, 1 / eta);
            REQUIRE(!back.total_internal);
            CHECK(glm::length(-back.refracted - d) < 1e-9);
        }
    }
}

TEST_CASE("R64: an ambient-only material renders exactly color × ambient", "[shading]") {
    auto spec = basic_scene(16, 16);
    auto m = matte({0.4, 0.6, 0.8}, 0.25);
    m.diffuse = 0;
    spec.shapes.push_back(sphere({0, 0, 0}, 1, add_material(spec, m)));
    spec.lights.push_back(point_light({2, 2, -3}));
    const auto result = render_spec(spec);
    CHECK(result.stats.shadow_rays == 0);  // nothing a shadow ray could change
    const Color expected = 0.25 * Color(0.4, 0.6, 0.8);
    CHECK(close_to(pixel(result.film, 8, 8), expected, 1e-7));
}

TEST_CASE("R58: Phong specular is finite for every shininess and 0 behind the mirror direction",
          "[shading]") {
    for (double shininess : {0.5, 1.7, 50.0, 1e6}) {
        auto spec = basic_scene(25, 25);  // odd: the centre pixel's ray is the optical axis
        auto m = matte({0.5, 0.5, 0.5}, 0.1);
        m.specular = 1;
        m.shininess = shininess;
        spec.shapes.push_back(sphere({0, 0, 0}, 1, add_material(spec, m)));
        spec.lights.push_back(point_light({0, 0, -10}));
        const auto result = render_spec(spec);
        CHECK(result.stats.nonfinite_samples == 0);
        for (float v : result.film.rgb) REQUIRE(std::isfinite(v));
        // The highlight at the centre: R = V, so the full specular weight is added.
        const Color centre = pixel(result.film, 12, 12);
        CHECK(centre.x > 0.05 + 0.5 * 0.9 + 0.9);
    }
    // A light whose mirror direction points away from the viewer (R·V < 0) adds no specular.
    auto spec = basic_scene(8, 8);
    auto m = matte({0.5, 0.5, 0.5}, 0.0);
    m.diffuse = 0;
    m.specular = 1;
    spec.shapes.push_back(plane({0, 0, -1}, 0, add_material(spec, m)));
    spec.lights.push_back(point_light({5, 0, -1}));
    RayProbe probe(spec);
    CHECK(probe.trace({3, 0, -3}, {-1, 0, 1}) == Color(0));
}

TEST_CASE("lights light both sides of an opaque surface; the normal faces the viewer", "[shading]") {
    // A triangle whose geometric normal (by its winding) is −z, towards the first camera.
    auto spec = basic_scene(8, 8);
    const Color c{0.5, 0.7, 0.9};
    spec.shapes.push_back(triangle({-5, -5, 0}, {-5, 5, 0}, {5, -5, 0}, add_material(spec, matte(c, 0.1))));
    const Vec3 lp{1, 2, -4};
    spec.lights.push_back(point_light(lp));
    RayProbe probe(spec);
    const Vec3 p{-1, -1, 0};
    const double nl = glm::dot(Vec3(0, 0, -1), glm::normalize(lp - p));
    CHECK(close_to(probe.trace({-1, -1, -5}, {0, 0, 1}), 0.1 * c + c * nl, 1e-12));
    // Seen from behind with the light on the camera's side: lit the same way.
    spec.lights[0].position = {1, 2, 4};
    RayProbe behind(spec);
    CHECK(close_to(behind.trace({-1, -1, 5}, {0, 0, -1}), 0.1 * c + c * nl, 1e-12));
    // Light on the other side from the viewer: ambient only.
    spec.lights[0].position = {1, 2, -4};
    RayProbe other(spec);
    CHECK(close_to(other.trace({-1, -1, 5}, {0, 0, -1}), 0.1 * c, 1e-12));
}

TEST_CASE("glass casts a light, tinted shadow", "[shading]") {
    auto spec = basic_scene(8, 8);
    const Color cf{0.8, 0.8, 0.8}, tint{1, 0.5, 0.25}, sigma{0.1, 0.2, 0.0};
    spec.shapes.push_back(plane({0, 1, 0}, 0, add_material(spec, matte(cf, 0.1))));
    // A glass slab 0.5 thick between the light and the floor point (0, 0, 0).
    spec.shapes.push_back(box({-1, 2, -1}, {1, 2.5, 1}, add_material(spec, glass(1.5, tint, sigma))));
    spec.lights.push_back(point_light({0, 5, 0}));
    RayProbe probe(spec);
    // Look at (0, 0, 0) from the side, below the slab.
    const Color got = probe.trace({-3, 1, 0}, Vec3(3, -1, 0));
    const Color transmittance = tint * tint * glm::exp(-sigma * 0.5);  // two surfaces, 0.5 inside
    CHECK(close_to(got, 0.1 * cf + cf * transmittance, 1e-9));
    // An opaque slab blocks it completely.
    spec.materials[1] = matte(tint);
    RayProbe opaque(spec);
    CHECK(close_to(opaque.trace({-3, 1, 0}, Vec3(3, -1, 0)), 0.1 * cf, 1e-12));
}

TEST_CASE("max_depth 0 is local shading only; bailout skips faint rays", "[shading]") {
    auto spec = basic_scene(16, 16);
    spec.settings.background = {1, 1, 1};
    auto m = matte({0.5, 0.5, 0.5}, 0.2);
    m.reflection = 0.001;
    spec.shapes.push_back(sphere({0, 0, 0}, 1, add_material(spec, m)));
    spec.settings.max_depth = 0;
    CHECK(render_spec(spec).stats.reflection_rays == 0);
    spec.settings.max_depth = 3;
    CHECK(render_spec(spec).stats.reflection_rays == 0);  // 0.001 < 1/512
    spec.settings.bailout = 0;
    const auto traced = render_spec(spec);
    CHECK(traced.stats.reflection_rays > 0);
    CHECK(traced.stats.nonfinite_samples == 0);
}

TEST_CASE("effect analysis names the effects and the shapes that call for them", "[shading][effects]") {
    auto spec = basic_scene(8, 8);
    spec.shapes.push_back(sphere({0, 0, 0}, 1, add_material(spec, matte({1, 1, 1}))));
    auto mirror = matte({1, 1, 1});
    mirror.reflection = 0.5;
    spec.shapes.push_back(sphere({2, 0, 0}, 1, add_material(spec, mirror)));
    spec.shapes.push_back(sphere({-2, 0, 0}, 1, add_material(spec, glass(1.5, Color(1), {0.1, 0, 0}))));
    spec.lights.push_back(area_light({0, 5, 0}, {1, 0, 0}, {0, 0, 1}, 2, 2));
    const auto fx = wsd::render::analyse_effects(spec);
    using wsd::render::Effect;
    CHECK(fx.has(Effect::AreaShadows));
    CHECK_FALSE(fx.has(Effect::PointShadows));
    CHECK(fx.shapes[size_t(Effect::Reflection)] == std::vector<uint32_t>{1});
    CHECK(fx.shapes[size_t(Effect::Refraction)] == std::vector<uint32_t>{2});
    CHECK(fx.shapes[size_t(Effect::Absorption)] == std::vector<uint32_t>{2});
    CHECK_FALSE(fx.has(Effect::AdaptiveLights));
    CHECK(wsd::render::analyse_effects(spec, true).has(Effect::AdaptiveLights));
    const auto result = render_spec(spec);
    CHECK(std::find(result.effects.begin(), result.effects.end(), "refraction") != result.effects.end());
}

TEST_CASE("R45 R46 R47 R63: build_scene rejects cameras and lights without a frame",
          "[shading][validation]") {
    auto base = basic_scene(8, 8);
    base.shapes.push_back(sphere({0, 0, 0}, 1, add_material(base, matte({1, 1, 1}))));
    auto expect_error = [](const wsd::render::SceneSpec& spec, SpecItem item) {
        std::vector<wsd::render::SpecError> errors;
        CHECK_FALSE(wsd::render::build_scene(spec, errors));
        REQUIRE(!errors.empty());
        CHECK(errors.front().item == item);
        CHECK(!errors.front().message.empty());
    };
    auto s = base;
    s.camera.up = {0, 0, 1};  // parallel to the view direction
    expect_error(s, SpecItem::Camera);
    s = base;
    s.camera.up = {0, 0, -1};
    expect_error(s, SpecItem::Camera);
    s = base;
    s.camera.up = {0, 0, 0};
    expect_error(s, SpecItem::Camera);
    s = base;
    s.camera.look_at = s.camera.position;
    expect_error(s, SpecItem::Camera);
    for (double fov : {0.0, 180.0, std::nan("")}) {
        s = base;
        s.camera.fov_degrees = fov;
        expect_error(s, SpecItem::Camera);
    }
    s = base;
    s.lights.push_back(area_light({0, 5, 0}, {1, 0, 0}, {2, 0, 0}, 2, 2));  // parallel edges
    expect_error(s, SpecItem::Light);
    s = base;
    s.lights.push_back(area_light({0, 5, 0}, {1, 0, 0}, {0, 0, 0}, 2, 2));  // zero edge
    expect_error(s, SpecItem::Light);
    s = base;
    s.lights.push_back(area_light({0, 5, 0}, {1, 0, 0}, {0, 0, 1}, 1024, 1024));  // > 65536 cells
    expect_error(s, SpecItem::Light);
    s = base;
    wsd::render::TextureSpec tex;
    tex.kind = wsd::render::TextureKind::Image;
    tex.image_path = "/nonexistent/texture.png";
    tex.tag = 42;
    s.materials[0].texture = tex;
    std::vector<wsd::render::SpecError> errors;
    CHECK_FALSE(wsd::render::build_scene(s, errors));
    REQUIRE(errors.size() == 1);
    CHECK(errors[0].item == SpecItem::Texture);
    CHECK(errors[0].index == 0);
    CHECK(errors[0].tag == 42);
    CHECK(errors[0].message.find("/nonexistent/texture.png") != std::string::npos);
}

TEST_CASE("R42: two facing mirrors: depth 256 terminates with linear work", "[shading]") {
    auto spec = basic_scene(4, 4, {0, 0, -0.5}, 10);
    spec.camera.look_at = {0, 0, 1};
    spec.settings.max_depth = 256;
    spec.settings.bailout = 0;
    auto mirror = matte({1, 1, 1}, 0.01);
    mirror.reflection = 1;
    mirror.diffuse = 0;
    const uint32_t m = add_material(spec, mirror);
    spec.shapes.push_back(plane({0, 0, 1}, -1e-3 - 1, m));
    spec.shapes.push_back(plane({0, 0, -1}, -1, m));
    const auto result = render_spec(spec);
    CHECK(result.stats.nonfinite_samples == 0);
    CHECK(result.stats.reflection_rays == 16 * 256);
    // Each bounce adds the ambient term 0.01 (weights stay 1): 257 terms.
    CHECK(pixel(result.film, 1, 1).x == Approx(257 * 0.01).epsilon(1e-6));
}

TEST_CASE("R59: a ray refracted into an absorbing half-space never comes back", "[shading]") {
    const Color bg{0.5, 0.6, 0.7};
    auto spec = basic_scene(4, 4);
    spec.settings.background = bg;
    spec.shapes.push_back(plane({0, 1, 0}, 0, add_material(spec, glass(1.5, Color(1), {1, 0, 0}))));
    RayProbe probe(spec);
    const Color got = probe.trace({0, 5, 0}, {0, -1, 0});
    const double F = 0.04;
    CHECK(close_to(got, F * bg + (1 - F) * Color(0, 1, 1) * bg, 1e-12));
    CHECK(probe.stats.nonfinite_samples == 0);
}
