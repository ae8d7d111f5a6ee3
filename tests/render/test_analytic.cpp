// Analytic renders: scenes whose every pixel has a closed-form value, checked pixel by pixel
// (robustness.md R40, R41; wsd-language.md §4 shading formula).
#include <catch2/catch.hpp>
#include <cmath>

#include "tests/render/scene_builders.h"

using namespace wsd::test;
using wsd::render::LightSampling;
using wsd::render::Ray;

namespace {

// Fresnel reflectance written with angles (the sine/tangent form), independent of the
// renderer's cosine form.
double fresnel_angles(double theta_i, double n1, double n2) {
    const double theta_t = std::asin(n1 / n2 * std::sin(theta_i));
    const double rs = -std::sin(theta_i - theta_t) / std::sin(theta_i + theta_t);
    const double rp = std::tan(theta_i - theta_t) / std::tan(theta_i + theta_t);
    return 0.5 * (rs * rs + rp * rp);
}

}  // namespace

TEST_CASE("lambertian sphere under a point light matches ambient + c·I·max(0, N·L)", "[analytic]") {
    auto spec = basic_scene(48, 48, {0, 0, -4});
    const Color c{0.8, 0.5, 0.3};
    const Color light{0.9, 0.81, 0.72};
    const Vec3 lp{3, 4, -5};
    spec.shapes.push_back(sphere({0, 0, 0}, 1, add_material(spec, matte(c, 0.2))));
    spec.lights.push_back(point_light(lp, 0.9, {1, 0.9, 0.8}));
    const auto result = render_spec(spec);
    REQUIRE(result.stats.nonfinite_samples == 0);
    int hits = 0, lit = 0;
    for (int y = 0; y < 48; ++y) {
        for (int x = 0; x < 48; ++x) {
            const Ray ray = camera_ray(spec, x + 0.5, y + 0.5);
            const double b = glm::dot(ray.o, ray.d);
            const double miss_distance = std::sqrt(std::max(0.0, glm::dot(ray.o, ray.o) - b * b));
            if (std::abs(miss_distance - 1.0) < 1e-6) continue;  // the silhouette itself
            Color expected(0);
            const double t = hit_sphere(ray, {0, 0, 0}, 1);
            if (t > 0) {
                ++hits;
                const Vec3 p = ray.o + t * ray.d;
                const double nl = glm::dot(glm::normalize(p), glm::normalize(lp - p));
                if (nl > 0) ++lit;
                expected = 0.2 * c + c * light * std::max(0.0, nl);
            }
            INFO("pixel " << x << "," << y);
            CHECK(close_to(pixel(result.film, x, y), expected, 1e-5));
        }
    }
    CHECK(hits > 500);
    CHECK(lit > 100);
    CHECK(lit < hits);
}

TEST_CASE("a mirror sphere reflects the constant background", "[analytic]") {
    auto spec = basic_scene(32, 32, {0, 0, -4});
    const Color bg{0.3, 0.6, 0.9};
    const Color c{1, 0.5, 0.25};
    spec.settings.background = bg;
    auto m = matte(c, 0.5);
    m.diffuse = 0;
    m.reflection = 0.6;
    spec.shapes.push_back(sphere({0, 0, 0}, 1, add_material(spec, m)));
    for (int depth : {0, 1, 4}) {
        spec.settings.max_depth = depth;
        const auto result = render_spec(spec);
        REQUIRE(result.stats.nonfinite_samples == 0);
        CHECK((depth == 0) == (result.stats.reflection_rays == 0));
        for (int y = 0; y < 32; ++y) {
            for (int x = 0; x < 32; ++x) {
                const Ray ray = camera_ray(spec, x + 0.5, y + 0.5);
                const double t = hit_sphere(ray, {0, 0, 0}, 1);
                // A convex mirror's reflected rays all escape to the background.
                const Color expected = t > 0 ? 0.5 * c + (depth > 0 ? 0.6 : 0.0) * bg : bg;
                INFO("depth " << depth << " pixel " << x << "," << y);
                CHECK(close_to(pixel(result.film, x, y), expected, 1e-5));
            }
        }
    }
}

TEST_CASE("a glass slab at normal incidence reflects ((n-1)/(n+1))^2", "[analytic]") {
    const double n = 1.5;
    const double F = std::pow((n - 1) / (n + 1), 2);
    const Color bg{0.2, 0.5, 1.0};
    const Color sigma{0.5, 1.0, 0.0};
    auto spec = basic_scene(8, 8);
    spec.settings.background = bg;
    spec.settings.bailout = 0;
    spec.shapes.push_back(box({-5, -5, 0}, {5, 5, 1}, add_material(spec, glass(n, Color(1), sigma))));

    spec.settings.max_depth = 1;  // the reflected ray only: the refracted one ends inside
    RayProbe one(spec);
    CHECK(close_to(one.trace({0, 0, -3}, {0, 0, 1}), F * bg, 1e-12));
    CHECK(one.stats.fresnel_evals >= 1);

    spec.settings.max_depth = 2;  // + the ray refracted in, across the slab (absorbed), and out
    RayProbe two(spec);
    const Color expected = F * bg + (1 - F) * (1 - F) * glm::exp(-sigma * 1.0) * bg;
    CHECK(close_to(two.trace({0, 0, -3}, {0, 0, 1}), expected, 1e-12));
    CHECK(two.stats.nonfinite_samples == 0);
}

TEST_CASE("R41: total internal reflection is a reflection with weight 1, not black", "[analytic]") {
    // Camera inside a glass cube: the first face is met at 60° (past the critical angle, 41.8°),
    // the mirrored ray meets the next face at 30° and leaves with weight 1 − F(30°).
    const Color bg{1.0, 0.5, 0.25};
    auto spec = basic_scene(8, 8);
    spec.settings.background = bg;
    spec.settings.bailout = 0;
    spec.settings.max_depth = 2;
    spec.shapes.push_back(box({-1, -1, -1}, {1, 1, 1}, add_material(spec, glass(1.5))));
    RayProbe probe(spec);
    const double pi = std::acos(-1.0);
    const Vec3 dir{std::cos(pi / 3), 0, std::sin(pi / 3)};
    const Color got = probe.trace({0, 0, -0.9}, dir);
    const double f30 = fresnel_angles(pi / 6, 1.5, 1.0);
    CHECK(f30 > 0.01);
    CHECK(close_to(got, (1 - f30) * bg, 1e-9));
    CHECK(probe.stats.refraction_rays == 1);  // none at the TIR face
}

TEST_CASE("an area light's penumbra equals the exactly visible fraction of a uniform grid", "[analytic]") {
    auto spec = basic_scene(48, 36, {0, 0.5, -3}, 60);
    spec.camera.look_at = {0, 0, 1};
    const Color cf{0.7, 0.6, 0.5}, cb{0.5, 0.2, 0.2};
    spec.shapes.push_back(plane({0, 1, 0}, 0, add_material(spec, matte(cf, 0.1))));
    // An opaque half-plane x < 0 at height 1, facing down.
    spec.shapes.push_back(quad({-20, 1, -20}, {20, 0, 0}, {0, 0, 40}, add_material(spec, matte(cb, 0.3))));
    const Vec3 lc{0, 3, 2};
    spec.lights.push_back(area_light(lc, {2, 0, 0}, {0, 0, 2}, 4, 4, LightSampling::Uniform));
    const auto result = render_spec(spec);
    REQUIRE(result.stats.nonfinite_samples == 0);

    int penumbra = 0, checked = 0;
    for (int y = 0; y < 36; ++y) {
        for (int x = 0; x < 48; ++x) {
            const Ray ray = camera_ray(spec, x + 0.5, y + 0.5);
            Color expected(0);
            bool skip = false;
            const double tb = ray.d.y > 0 ? (1 - ray.o.y) / ray.d.y : -1;
            const Vec3 pb = ray.o + tb * ray.d;
            if (tb > 0 && pb.x < 0 && pb.x > -20 && std::abs(pb.z) < 20) {
                expected = 0.3 * cb;  // the blocker's underside sees no light
            } else if (ray.d.y < 0) {
                const Vec3 p = ray.o + (-ray.o.y / ray.d.y) * ray.d;
                double sum = 0;
                int visible = 0;
                for (int j = 0; j < 4; ++j) {
                    for (int i = 0; i < 4; ++i) {
                        const Vec3 s = lc + Vec3(-1 + (i + 0.5) * 0.5, 0, -1 + (j + 0.5) * 0.5);
                        const double xc = p.x + (s.x - p.x) / 3, zc = p.z + (s.z - p.z) / 3;
                        if (std::abs(xc) < 1e-9) skip = true;
                        if (xc < 0 && std::abs(zc) < 20) continue;
                        ++visible;
                        sum += (s.y - p.y) / glm::length(s - p);
                    }
                }
                if (visible > 0 && visible < 16) ++penumbra;
                expected = 0.1 * cf + cf * (sum / 16);
            }
            if (skip) continue;
            ++checked;
            INFO("pixel " << x << "," << y);
            CHECK(close_to(pixel(result.film, x, y), expected, 1e-5));
        }
    }
    CHECK(checked > 1500);
    CHECK(penumbra > 50);
}

TEST_CASE("R40: a glass sphere in a white furnace conserves energy with no dark ring", "[analytic]") {
    auto spec = basic_scene(32, 32, {0, 0, -4});
    spec.settings.background = Color(1);
    spec.settings.bailout = 0;
    spec.shapes.push_back(sphere({0, 0, 0}, 1, add_material(spec, glass(1.5))));
    for (int depth : {32, 64}) {
        spec.settings.max_depth = depth;
        const auto result = render_spec(spec);
        REQUIRE(result.stats.nonfinite_samples == 0);
        CHECK(result.stats.refraction_rays > 0);
        const double lo = 1 - 1 / (std::exp(1.0) * (depth - 1));
        float min_value = 2;
        for (float v : result.film.rgb) {
            min_value = std::min(min_value, v);
            REQUIRE(v <= 1 + 1e-4);
        }
        INFO("depth " << depth << " darkest " << min_value);
        CHECK(min_value >= lo);
    }
}

TEST_CASE("R27: scaling a scene by a power of two gives the same image bit for bit", "[analytic]") {
    // robustness.md R27: no absolute epsilon anywhere, so ×2^k changes no rounding decision.
    auto make = [](double k) {
        auto spec = basic_scene(24, 20, Vec3(0, 1.5, -5) * k);
        spec.camera.look_at = Vec3(0, 0, 0);
        spec.settings.supersamples = 4;
        spec.settings.background = {0.1, 0.2, 0.3};
        auto floor = matte({0.8, 0.8, 0.8});
        wsd::render::TextureSpec checker;
        checker.kind = wsd::render::TextureKind::Checker;
        checker.checker_scale = 0.5 * k;
        checker.color2 = {0.2, 0.3, 0.2};
        floor.texture = checker;
        spec.shapes.push_back(plane({0, 1, 0}, -1 * k, add_material(spec, floor)));
        auto mirror = matte({0.8, 0.8, 0.8});
        mirror.reflection = 0.5;
        mirror.specular = 0.5;
        spec.shapes.push_back(sphere(Vec3(-1.1, 0, 0.5) * k, 1 * k, add_material(spec, mirror)));
        spec.shapes.push_back(sphere(Vec3(1.1, 0, 0) * k, 0.9 * k,
                                     add_material(spec, glass(1.5, {1, 0.9, 0.8}, Color(0.2, 0.1, 0) / k))));
        spec.shapes.push_back(box(Vec3(-0.4, -1, -1.5) * k, Vec3(0.2, -0.4, -0.9) * k,
                                  add_material(spec, matte({0.3, 0.3, 0.9}))));
        spec.lights.push_back(area_light(Vec3(0, 4, -1) * k, Vec3(2, 0, 0) * k, Vec3(0, 0, 2) * k, 3, 3));
        spec.lights.push_back(point_light(Vec3(-3, 3, -3) * k, 0.3));
        return spec;
    };
    const auto base = render_spec(make(1));
    CHECK(base.stats.nonfinite_samples == 0);
    for (double k : {1024.0, 1.0 / 1024}) {
        const auto scaled = render_spec(make(k));
        INFO("scale " << k);
        CHECK(std::equal(base.film.rgb.begin(), base.film.rgb.end(), scaled.film.rgb.begin(),
                         scaled.film.rgb.end()));
    }
}
