// Auxiliary images on analytic scenes: the albedo of a flat wall is its colour, a sphere's centre
// normal faces the camera, depth is the distance to the first hit; pure mirrors and clear glass
// pass the walk on, other surfaces end it; misses give 0 and +∞; the images are averaged like
// the colour, the same for any thread count or region, and asking for them changes no colour.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "render/aov.h"
#include "scene_builders.h"

using namespace wsd::test;
using wsd::render::AovFilm;
using wsd::render::AovSample;
using wsd::render::AovSum;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Color albedo_at(const wsd::render::RenderResult& r, int x, int y) {
    const size_t i = 3 * (size_t(y) * size_t(r.film.width) + size_t(x));
    return {r.aovs.albedo[i], r.aovs.albedo[i + 1], r.aovs.albedo[i + 2]};
}

Vec3 normal_at(const wsd::render::RenderResult& r, int x, int y) {
    const size_t i = 3 * (size_t(y) * size_t(r.film.width) + size_t(x));
    return {r.aovs.normal[i], r.aovs.normal[i + 1], r.aovs.normal[i + 2]};
}

double depth_at(const wsd::render::RenderResult& r, int x, int y) {
    return r.aovs.depth[size_t(y) * size_t(r.film.width) + size_t(x)];
}

wsd::render::RenderResult render_aovs(const wsd::render::SceneSpec& spec, int threads = 2) {
    wsd::render::RenderOptions options;
    options.aovs = true;
    options.threads = threads;
    auto r = render_spec(spec, options);
    const size_t pixels = size_t(r.film.width) * size_t(r.film.height);
    REQUIRE(r.aovs.albedo.size() == 3 * pixels);
    REQUIRE(r.aovs.normal.size() == 3 * pixels);
    REQUIRE(r.aovs.depth.size() == pixels);
    return r;
}

// Colours whose sums of four are exact in binary, so that averages come out exact.
const Color kRed{0.75, 0.125, 0.0625};
const Color kGreen{0.125, 0.5, 0.25};

// A camera at −5 z looking at a wall z = 0 facing it (7×7, so pixel (3, 3) looks straight ahead).
wsd::render::SceneSpec wall_scene(const wsd::render::MaterialSpec& wall) {
    auto spec = basic_scene(7, 7, {0, 0, -5});
    spec.shapes.push_back(plane({0, 0, -1}, 0, add_material(spec, wall)));
    spec.lights.push_back(point_light({0, 0, -4}));
    return spec;
}

wsd::render::MaterialSpec pure_mirror() {
    auto m = matte(Color(0.5), 0);
    m.reflection = 1;
    m.diffuse = 0;
    return m;
}

}  // namespace

TEST_CASE("the albedo of a flat red wall is red, its normal faces the camera, depth is the distance",
          "[aov]") {
    auto spec = wall_scene(matte(kRed));
    spec.settings.supersamples = 4;
    const auto r = render_aovs(spec);
    for (int y = 0; y < 7; ++y) {
        for (int x = 0; x < 7; ++x) {
            CHECK(albedo_at(r, x, y) == kRed);
            CHECK(normal_at(r, x, y) == Vec3(0, 0, -1));
        }
    }
    // One sample a pixel: the depth is the distance along that pixel's ray to z = 0.
    spec.settings.supersamples = 1;
    const auto one = render_aovs(spec);
    for (int y = 0; y < 7; ++y) {
        for (int x = 0; x < 7; ++x) {
            const wsd::render::Ray ray = camera_ray(spec, x + 0.5, y + 0.5);
            CHECK(depth_at(one, x, y) == Approx(5.0 / ray.d.z).epsilon(1e-6));
        }
    }
    CHECK(depth_at(one, 3, 3) == 5.0f);
}

TEST_CASE("a sphere's centre pixel: normal towards the camera, depth |eye − centre| − r", "[aov]") {
    auto spec = basic_scene(9, 9, {0, 0, -5}, 20);
    spec.shapes.push_back(sphere({0, 0, 0}, 1, add_material(spec, matte(kGreen))));
    const auto r = render_aovs(spec);
    const Vec3 n = normal_at(r, 4, 4);
    CHECK(n.x == Approx(0).margin(1e-6));
    CHECK(n.y == Approx(0).margin(1e-6));
    CHECK(n.z == Approx(-1).epsilon(1e-6));
    CHECK(depth_at(r, 4, 4) == Approx(4.0).epsilon(1e-6));
    CHECK(albedo_at(r, 4, 4) == kGreen);
    // The corners miss: albedo and normal 0, depth +∞.
    CHECK(albedo_at(r, 0, 0) == Color(0));
    CHECK(normal_at(r, 0, 0) == Vec3(0));
    CHECK(depth_at(r, 0, 0) == kInf);
}

TEST_CASE("a pure mirror shows the albedo and normal of what it reflects, and its own depth", "[aov]") {
    // The mirror wall at z = 0 sends the camera's rays back to a green wall behind the camera.
    auto spec = wall_scene(pure_mirror());
    spec.shapes.push_back(plane({0, 0, 1}, -10, add_material(spec, matte(kGreen))));
    const auto r = render_aovs(spec);
    CHECK(albedo_at(r, 3, 3) == kGreen);
    CHECK(normal_at(r, 3, 3) == Vec3(0, 0, 1));  // the green wall's, turned to the reflected ray
    CHECK(depth_at(r, 3, 3) == 5.0f);            // the first hit: the mirror

    SECTION("a black mirror with the default diffuse is pure too: no light of its own colour") {
        auto black = pure_mirror();
        black.color = Color(0);
        black.diffuse = 1;
        black.ambient = 0.2;
        spec.materials[0] = black;
        CHECK(albedo_at(render_aovs(spec), 3, 3) == kGreen);
    }
    SECTION("a partly reflective surface ends the walk with its own colour") {
        auto partial = matte(kRed);
        partial.reflection = 0.5;
        spec.materials[0] = partial;
        const auto p = render_aovs(spec);
        CHECK(albedo_at(p, 3, 3) == kRed);
        CHECK(normal_at(p, 3, 3) == Vec3(0, 0, -1));
    }
    SECTION("a full mirror that still has a diffuse term ends the walk with its own colour") {
        auto diffuse_mirror = pure_mirror();
        diffuse_mirror.diffuse = 0.1;
        spec.materials[0] = diffuse_mirror;
        CHECK(albedo_at(render_aovs(spec), 3, 3) == Color(0.5));
    }
    SECTION("a mirror whose reflection leaves the scene gives 0, like a miss") {
        spec.shapes.pop_back();
        const auto m = render_aovs(spec);
        CHECK(albedo_at(m, 3, 3) == Color(0));
        CHECK(normal_at(m, 3, 3) == Vec3(0));
        CHECK(depth_at(m, 3, 3) == 5.0f);
    }
}

TEST_CASE("two facing pure mirrors give 0 once the walk passes max_depth, as the image is black", "[aov]") {
    auto spec = wall_scene(pure_mirror());
    spec.shapes.push_back(plane({0, 0, 1}, -10, add_material(spec, pure_mirror())));
    spec.settings.max_depth = 3;
    const auto r = render_aovs(spec);
    CHECK(albedo_at(r, 3, 3) == Color(0));
    CHECK(normal_at(r, 3, 3) == Vec3(0));
    CHECK(depth_at(r, 3, 3) == 5.0f);
}

TEST_CASE("clear glass shows what lies behind it; tinted glass its own colour", "[aov]") {
    // A glass slab between the camera and a red wall at z = 2.
    auto spec = basic_scene(7, 7, {0, 0, -5});
    const uint32_t slab = add_material(spec, glass());
    spec.shapes.push_back(box({-5, -5, -1}, {5, 5, 0}, slab));
    spec.shapes.push_back(plane({0, 0, -1}, -2, add_material(spec, matte(kRed))));
    auto r = render_aovs(spec);
    CHECK(albedo_at(r, 3, 3) == kRed);
    CHECK(normal_at(r, 3, 3) == Vec3(0, 0, -1));
    CHECK(depth_at(r, 3, 3) == 4.0f);  // the slab's front face

    spec.materials[slab] = glass(1.5, kGreen);
    r = render_aovs(spec);
    CHECK(albedo_at(r, 3, 3) == kGreen);
    CHECK(normal_at(r, 3, 3) == Vec3(0, 0, -1));

    spec.materials[slab] = glass(1.5, Color(1), Color(0.5));  // absorbing: not clear
    r = render_aovs(spec);
    CHECK(albedo_at(r, 3, 3) == Color(1));
}

TEST_CASE("pure mirror and clear glass are told apart exactly", "[aov]") {
    wsd::render::Material m;
    m.reflection = 1;
    m.diffuse = 0;
    m.ambient = 0;
    CHECK(wsd::render::aov_pure_mirror(m, Color(1)));
    m.ambient = 0.2;
    CHECK_FALSE(wsd::render::aov_pure_mirror(m, Color(1)));
    CHECK(wsd::render::aov_pure_mirror(m, Color(0)));
    m.reflection = 0.99;
    CHECK_FALSE(wsd::render::aov_pure_mirror(m, Color(0)));

    wsd::render::Material g;
    g.transmission = 1;
    CHECK(wsd::render::aov_clear_glass(g, Color(1)));
    CHECK_FALSE(wsd::render::aov_clear_glass(g, Color(1, 1, 0.99)));
    g.transmission = 0.9;
    CHECK_FALSE(wsd::render::aov_clear_glass(g, Color(1)));
}

TEST_CASE("a pixel's AOVs average its samples: depth over the samples that hit", "[aov]") {
    AovSum sum;
    AovSample hit;
    hit.albedo = Color(1, 0.5, 0);
    hit.normal = Vec3(0, 0, -1);
    hit.depth = 2;
    sum.add(hit);
    hit.depth = 4;
    sum.add(hit);
    sum.add(AovSample{});
    sum.add(AovSample{});
    const AovSample m = sum.mean();
    CHECK(m.albedo == Color(0.5, 0.25, 0));
    CHECK(m.normal == Vec3(0, 0, -0.5));
    CHECK(m.depth == 3);
    CHECK(AovSum{}.mean().depth == kInf);

    // A pixel on a sphere's silhouette: some samples hit, some miss.
    auto spec = basic_scene(9, 9, {0, 0, -5}, 20);
    spec.settings.supersamples = 16;
    spec.shapes.push_back(sphere({0, 0, 0}, 1, add_material(spec, matte(Color(1)))));
    const auto r = render_aovs(spec);
    bool found_edge = false;
    for (int y = 0; y < 9; ++y) {
        for (int x = 0; x < 9; ++x) {
            const double a = albedo_at(r, x, y).x;
            if (a > 0 && a < 1) {
                found_edge = true;
                CHECK(std::isfinite(depth_at(r, x, y)));
                CHECK(depth_at(r, x, y) >= 4.0f);
                CHECK(depth_at(r, x, y) < 5.0f);
            }
        }
    }
    CHECK(found_edge);
}

namespace {

// Glass, a mirror, supersampling and an area light: every path the colour and AOVs can take.
wsd::render::SceneSpec busy_scene(bool adaptive) {
    auto spec = basic_scene(37, 29, {0, 1, -6}, 45);
    spec.settings.supersamples = 4;
    spec.settings.adaptive_supersampling = adaptive;
    spec.shapes.push_back(plane({0, 1, 0}, -1, add_material(spec, matte(kRed))));
    spec.shapes.push_back(sphere({-1, 0, 0}, 1, add_material(spec, glass())));
    spec.shapes.push_back(sphere({1.2, 0, 0.5}, 1, add_material(spec, pure_mirror())));
    spec.shapes.push_back(box({-3, -1, 2}, {3, 2, 3}, add_material(spec, matte(kGreen))));
    spec.lights.push_back(area_light({0, 5, -2}, {1, 0, 0}, {0, 0, 1}, 2, 2));
    return spec;
}

}  // namespace

TEST_CASE("AOVs are the same for any thread count and region, and change no colour", "[aov]") {
    for (const bool adaptive : {false, true}) {
        INFO("adaptive supersampling " << adaptive);
        const auto spec = busy_scene(adaptive);
        const auto one = render_aovs(spec, 1);
        const auto two = render_aovs(spec, 2);
        CHECK(one.aovs.albedo == two.aovs.albedo);
        CHECK(one.aovs.normal == two.aovs.normal);
        CHECK(one.aovs.depth == two.aovs.depth);

        wsd::render::RenderOptions plain;
        plain.threads = 2;
        const auto colour_only = render_spec(spec, plain);
        CHECK(colour_only.aovs.empty());
        CHECK(colour_only.film.rgb == one.film.rgb);

        // A region's AOVs are the whole image's pixels there.
        wsd::render::RenderOptions part;
        part.aovs = true;
        part.region = wsd::render::Region{5, 3, 30, 20};
        const auto region = render_spec(spec, part);
        for (int y = 3; y < 20; ++y) {
            for (int x = 5; x < 30; ++x) {
                const size_t i = size_t(y - 3) * 25 + size_t(x - 5), j = size_t(y) * 37 + size_t(x);
                for (size_t k = 0; k < 3; ++k) {
                    CHECK(region.aovs.albedo[3 * i + k] == one.aovs.albedo[3 * j + k]);
                    CHECK(region.aovs.normal[3 * i + k] == one.aovs.normal[3 * j + k]);
                }
                CHECK(region.aovs.depth[i] == one.aovs.depth[j]);
            }
        }
    }
}
