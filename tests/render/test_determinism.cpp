// Determinism (robustness.md R52): the image depends only on the scene and the seed — not on the
// thread count, the tiling or the region rendered — and the specialised integrator gives exactly
// the general one's image. Also cancellation and progress reporting.
#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <cstring>
#include <random>

#include "tests/render/scene_builders.h"

using namespace wsd::test;
using wsd::render::Film;
using wsd::render::LightSampling;
using wsd::render::Region;
using wsd::render::RenderOptions;
using wsd::render::SceneSpec;

namespace {

// Jittered soft shadows, supersampling, a mirror, glass with absorption and a checker floor, in
// an image whose size is not a multiple of the tile size.
SceneSpec busy_scene() {
    auto spec = basic_scene(45, 37, {0, 1.5, -5});
    spec.settings.supersamples = 4;
    spec.settings.background = {0.1, 0.2, 0.3};
    auto floor = matte({1, 1, 1});
    wsd::render::TextureSpec checker;
    checker.kind = wsd::render::TextureKind::Checker;
    checker.checker_scale = 0.5;
    checker.color1 = {0.9, 0.9, 0.9};
    checker.color2 = {0.2, 0.3, 0.2};
    floor.texture = checker;
    spec.shapes.push_back(plane({0, 1, 0}, -1, add_material(spec, floor)));
    auto mirror = matte({0.8, 0.8, 0.8});
    mirror.reflection = 0.5;
    mirror.specular = 0.4;
    spec.shapes.push_back(sphere({-1.1, 0, 0.5}, 1, add_material(spec, mirror)));
    spec.shapes.push_back(
        sphere({1.1, 0, 0}, 0.9, add_material(spec, glass(1.5, {1, 0.9, 0.8}, {0.2, 0.1, 0}))));
    spec.lights.push_back(area_light({0, 4, -1}, {2, 0, 0}, {0, 0, 2}, 4, 4, LightSampling::Jittered));
    spec.lights.push_back(point_light({-3, 3, -3}, 0.3));
    return spec;
}

bool same_pixels(const Film& a, const Film& b) {
    return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
           std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

RenderOptions with_threads(int n) {
    RenderOptions o;
    o.threads = n;
    return o;
}

}  // namespace

TEST_CASE("R52: 1, 2 and 3 threads give bit-identical images", "[determinism]") {
    const auto spec = busy_scene();
    const auto one = render_spec(spec, with_threads(1));
    const auto two = render_spec(spec, with_threads(2));
    const auto three = render_spec(spec, with_threads(3));
    CHECK(one.stats.nonfinite_samples == 0);
    CHECK(same_pixels(one.film, two.film));
    CHECK(same_pixels(one.film, three.film));
    CHECK(one.stats.ray_queries() == two.stats.ray_queries());
}

TEST_CASE("the seed decides the jitter", "[determinism]") {
    auto spec = busy_scene();
    const auto a = render_spec(spec);
    const auto b = render_spec(spec);
    CHECK(same_pixels(a.film, b.film));
    spec.settings.seed = 12345;
    const auto c = render_spec(spec);
    CHECK(c.stats.nonfinite_samples == 0);
    CHECK_FALSE(same_pixels(a.film, c.film));
}

TEST_CASE("a region render equals the same pixels of the full render, bit for bit", "[determinism]") {
    for (bool adaptive : {false, true}) {
        auto spec = busy_scene();
        spec.settings.adaptive_supersampling = adaptive;
        spec.settings.aa_threshold = 0.02;
        const auto full = render_spec(spec);
        CHECK(full.stats.nonfinite_samples == 0);
        for (const Region r :
             {Region{0, 0, 45, 37}, Region{3, 5, 29, 22}, Region{17, 0, 18, 37}, Region{40, 30, 45, 37}}) {
            RenderOptions o;
            o.region = r;
            const auto part = render_spec(spec, o);
            REQUIRE(part.film.width == r.x1 - r.x0);
            REQUIRE(part.film.height == r.y1 - r.y0);
            bool same = true;
            for (int y = r.y0; y < r.y1; ++y)
                for (int x = r.x0; x < r.x1; ++x)
                    same = same && pixel(part.film, x - r.x0, y - r.y0) == pixel(full.film, x, y);
            INFO("adaptive " << adaptive << " region " << r.x0 << "," << r.y0 << "," << r.x1 << "," << r.y1);
            CHECK(same);
        }
    }
}

TEST_CASE("the specialised integrator gives the general one's image", "[determinism]") {
    auto glassy = busy_scene();
    auto diffuse = busy_scene();
    diffuse.materials[1].reflection = 0;
    diffuse.materials[2] = matte({0.3, 0.6, 0.3});
    auto adaptive = busy_scene();
    adaptive.lights[0].adaptive = true;
    for (const SceneSpec* spec : {&glassy, &diffuse, &adaptive}) {
        RenderOptions general;
        general.specialise = false;
        const auto a = render_spec(*spec);
        const auto b = render_spec(*spec, general);
        CHECK(a.stats.nonfinite_samples == 0);
        CHECK(same_pixels(a.film, b.film));
    }
    RenderOptions forced;
    forced.adaptive_lights = true;
    const auto a = render_spec(diffuse, forced);
    forced.specialise = false;
    const auto b = render_spec(diffuse, forced);
    CHECK(same_pixels(a.film, b.film));
}

TEST_CASE("cancellation stops the render; progress ends at 1", "[determinism]") {
    const auto spec = busy_scene();
    std::atomic<bool> cancel{true};
    RenderOptions o;
    o.cancel = &cancel;
    const auto stopped = render_spec(spec, o);
    CHECK(stopped.cancelled);

    double last = -1;
    int calls = 0;
    RenderOptions p;
    p.progress = [&](double fraction, const wsd::render::RayStats&) {
        CHECK(fraction >= last);
        last = fraction;
        ++calls;
    };
    const auto done = render_spec(spec, p);
    CHECK_FALSE(done.cancelled);
    CHECK(calls >= 1);
    CHECK(last == 1.0);
}

TEST_CASE("camera samples traced as a packet give exactly the colours traced one by one", "[determinism]") {
    // The renderer traces camera rays four at a time (a pixel's grid, or a 2×2 block of pixels);
    // every effect downstream of the first hit must see the same hit, so the colours must match
    // bit for bit: sub-pixel neighbours, whole-pixel neighbours, far-apart positions, and
    // partial packets.
    const auto spec = busy_scene();
    auto scene = build(spec);
    for (bool specialise : {true, false}) {
        wsd::render::RayStats stats;
        wsd::render::TracerOptions options;
        options.specialise = specialise;
        auto tracer = wsd::render::make_tracer(*scene, options, stats);
        std::mt19937_64 gen(17);
        auto uniform = [&](double lo, double hi) {
            return std::uniform_real_distribution<double>(lo, hi)(gen);
        };
        int lit = 0;
        for (int i = 0; i < 3000; ++i) {
            const double spread = i % 3 == 0 ? 0.5 : i % 3 == 1 ? 2.0 : 40.0;
            const double x0 = uniform(0, 45), y0 = uniform(0, 37);
            constexpr int kMax = wsd::render::Geometry::kMaxPacket;
            double px[kMax], py[kMax];
            uint64_t key[kMax];
            for (int k = 0; k < kMax; ++k) {
                px[k] = std::clamp(x0 + uniform(0, spread), 0.0, 45.0);
                py[k] = std::clamp(y0 + uniform(0, spread), 0.0, 37.0);
                key[k] = uint64_t(i) * kMax + uint64_t(k);
            }
            const int n = 1 + i % kMax;
            Color out[kMax];
            tracer->camera_samples(px, py, key, n, out);
            for (int k = 0; k < n; ++k) {
                const Color one = tracer->camera_sample(px[k], py[k], key[k]);
                INFO("sample " << i << " lane " << k << " specialised " << specialise);
                REQUIRE(std::memcmp(&one, &out[k], sizeof(Color)) == 0);
                lit += one != spec.settings.background ? 1 : 0;
            }
        }
        CHECK(lit > 3000 * 4);  // most samples see the scene, not the background
    }
}
