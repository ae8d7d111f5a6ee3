// Spot lights: the lit circle on a floor against its radius H·tan(angle), the smoothstep between
// angle and falloff pixel by pixel, the edge exactly on a shading point, and the spec checks.
#include <catch2/catch.hpp>
#include <cmath>

#include "render/lights.h"
#include "render/math.h"
#include "tests/render/scene_builders.h"

using namespace wsd::test;
using wsd::render::Ray;

namespace {

wsd::render::LightSpec spot(Vec3 position, Vec3 look_at, double angle, double falloff, double intensity = 1) {
    wsd::render::LightSpec l;
    l.kind = wsd::render::LightKind::Spot;
    l.position = position;
    l.look_at = look_at;
    l.angle = angle;
    l.falloff = falloff;
    l.intensity = intensity;
    return l;
}

// A white floor y = 0 under a spot at height h aiming straight down, seen from above.
wsd::render::SceneSpec floor_scene(double h, double angle, double falloff) {
    auto spec = basic_scene(64, 64, {0, 10, 0}, 60);
    spec.camera.up = {0, 0, 1};
    spec.shapes.push_back(plane({0, 1, 0}, 0, add_material(spec, matte(Color(1), 0.1))));
    spec.lights.push_back(spot({0, h, 0}, {0, 0, 0}, angle, falloff));
    return spec;
}

double smoothstep01(double s) {
    s = std::clamp(s, 0.0, 1.0);
    return s * s * (3 - 2 * s);
}

}  // namespace

TEST_CASE("a hard-edged spot lights a circle of radius H·tan(angle) on the floor", "[spot][analytic]") {
    const double h = 4, angle = 35;
    auto spec = floor_scene(h, angle, angle);
    const auto result = render_spec(spec);
    const double radius = h * std::tan(angle * wsd::render::kPi / 180);
    int lit = 0, dark = 0;
    for (int y = 0; y < 64; ++y) {
        for (int x = 0; x < 64; ++x) {
            const Ray ray = camera_ray(spec, x + 0.5, y + 0.5);
            const Vec3 p = ray.o + (-ray.o.y / ray.d.y) * ray.d;
            const double rho = std::hypot(p.x, p.z);
            if (std::abs(rho - radius) < 1e-9) continue;  // the edge itself
            const Vec3 to_light = Vec3(0, h, 0) - p;
            const double nl = h / glm::length(to_light);
            const Color expected = rho < radius ? Color(0.1 + nl) : Color(0.1);
            (rho < radius ? lit : dark)++;
            INFO("pixel " << x << "," << y << " at distance " << rho);
            CHECK(close_to(pixel(result.film, x, y), expected, 1e-6));
        }
    }
    CHECK(lit > 500);
    CHECK(dark > 500);
}

TEST_CASE("between angle and falloff a spot fades by smoothstep of the cosines", "[spot][analytic]") {
    const double h = 3, angle = 20, falloff = 50;
    auto spec = floor_scene(h, angle, falloff);
    const auto result = render_spec(spec);
    const double ca = std::cos(angle * wsd::render::kPi / 180),
                 cf = std::cos(falloff * wsd::render::kPi / 180);
    int partial = 0;
    for (int y = 0; y < 64; ++y) {
        for (int x = 0; x < 64; ++x) {
            const Ray ray = camera_ray(spec, x + 0.5, y + 0.5);
            const Vec3 p = ray.o + (-ray.o.y / ray.d.y) * ray.d;
            const Vec3 to_light = Vec3(0, h, 0) - p;
            const double cos_theta = h / glm::length(to_light);  // the axis is straight down
            const double f = smoothstep01((cos_theta - cf) / (ca - cf));
            if (f > 0 && f < 1) ++partial;
            INFO("pixel " << x << "," << y);
            CHECK(close_to(pixel(result.film, x, y), Color(0.1 + f * cos_theta), 1e-6));
        }
    }
    CHECK(partial > 300);
}

TEST_CASE("R71 a spot's edge exactly on a shading point", "[spot][robust]") {
    wsd::render::Light l = wsd::render::prepare_light(spot({0, 0, 0}, {0, -1, 0}, 30, 60));
    // cos 60° is exactly 0.5: the direction (√3/2, −1/2)·r is exactly on the falloff edge in cos.
    CHECK(l.cos_falloff == 0.5);
    CHECK(wsd::render::spot_factor(l, -Vec3(0, -1, 0)) == 1);
    CHECK(wsd::render::spot_factor(l, -Vec3(0, -1, 0) * 1e-300) == 1);
    CHECK(wsd::render::spot_factor(l, Vec3(0)) == 0);  // the light's own position: no NaN
    CHECK(wsd::render::spot_factor(l, -Vec3(1, 0, 0)) == 0);
    // Between the two cosines the factor rises monotonically from 0 to 1.
    double last = 0;
    for (int i = 0; i <= 100; ++i) {
        const double c = l.cos_falloff + (l.cos_angle - l.cos_falloff) * i / 100.0;
        const double f = wsd::render::spot_factor(l, -Vec3(std::sqrt(1 - c * c), -c, 0));
        CHECK(f >= last);
        CHECK(f >= 0);
        CHECK(f <= 1);
        last = f;
    }
    CHECK(last == 1);
    // A hard edge (angle = falloff): 0 on the edge and beyond, 1 inside, never in between. At
    // 90° the edge is exact: cos θ = 0 for every direction normal to the axis.
    wsd::render::Light hard = wsd::render::prepare_light(spot({0, 0, 0}, {0, -1, 0}, 90, 90));
    CHECK(hard.cos_falloff == 0);
    CHECK(wsd::render::spot_factor(hard, -Vec3(1, 0, 0)) == 0);
    CHECK(wsd::render::spot_factor(hard, -Vec3(1, -1e-300, 0)) == 1);
    CHECK(wsd::render::spot_factor(hard, -Vec3(1, 1e-300, 0)) == 0);
    wsd::render::Light hard60 = wsd::render::prepare_light(spot({0, 0, 0}, {0, -1, 0}, 60, 60));
    CHECK(wsd::render::spot_factor(hard60, -Vec3(0.6, -0.8, 0)) == 1);
    CHECK(wsd::render::spot_factor(hard60, -Vec3(0.9, -0.1, 0)) == 0);
    // A render whose edge runs through pixel centres: every pixel fully lit or fully dark.
    auto spec = floor_scene(1, 45, 45);
    spec.camera.fov_degrees = 90;
    const auto result = render_spec(spec);
    for (int y = 0; y < 64; ++y) {
        for (int x = 0; x < 64; ++x) {
            const double v = pixel(result.film, x, y).x;
            const bool dark = std::abs(v - 0.1) < 1e-6;
            INFO("pixel " << x << "," << y << " value " << v);
            CHECK((dark || v > 0.1 + 0.5));
        }
    }
}

TEST_CASE("spot light specs out of range are build errors", "[spot]") {
    for (auto l : {spot({0, 1, 0}, {0, 1, 0}, 30, 45), spot({0, 1, 0}, {0, 0, 0}, 50, 45),
                   spot({0, 1, 0}, {0, 0, 0}, 0, 45), spot({0, 1, 0}, {0, 0, 0}, 30, 91)}) {
        auto spec = basic_scene(4, 4);
        spec.lights.push_back(l);
        std::vector<wsd::render::SpecError> errors;
        CHECK_FALSE(wsd::render::build_scene(spec, errors, true, 1));
        REQUIRE(errors.size() == 1);
        CHECK(errors[0].item == wsd::render::SpecItem::Light);
    }
}
