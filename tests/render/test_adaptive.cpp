// Adaptive area lights (probe corners and centre, refine where they disagree) and adaptive
// supersampling (centre-ray prepass, full grid only at edges).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "tests/render/scene_builders.h"

using namespace wsd::test;
using wsd::render::LightSampling;
using wsd::render::RenderOptions;
using wsd::render::SceneSpec;
using wsd::render::TracerOptions;

namespace {

// A floor under an 8×8 area light, with an opaque half-plane (x < 0; large enough that every
// visible floor point sees its edge as a straight line) or a box at height 1.
SceneSpec shadow_scene(LightSampling sampling, bool box_blocker) {
    auto spec = basic_scene(40, 30, {0, 0.5, -3}, 60);
    spec.camera.look_at = {0, 0, 1};
    spec.shapes.push_back(plane({0, 1, 0}, 0, add_material(spec, matte({0.7, 0.7, 0.7}, 0.1))));
    const uint32_t dark = add_material(spec, matte({0.5, 0.2, 0.2}, 0.3));
    if (box_blocker)
        spec.shapes.push_back(box({-0.5, 1, 0.5}, {0.3, 1.2, 1.5}, dark));
    else
        spec.shapes.push_back(quad({-1000, 1, -1000}, {1000, 0, 0}, {0, 0, 2000}, dark));
    spec.lights.push_back(area_light({0, 3, 1}, {2, 0, 0}, {0, 0, 2}, 8, 8, sampling));
    return spec;
}

RenderOptions adaptive_options() {
    RenderOptions o;
    o.adaptive_lights = true;
    return o;
}

}  // namespace

TEST_CASE("adaptive lights: lit and shadowed points take 5 shadow rays and equal the full grid",
          "[adaptive]") {
    const auto spec = shadow_scene(LightSampling::Jittered, false);
    TracerOptions adaptive;
    adaptive.adaptive_lights = true;
    // Floor points seen from the side: far from the edge (lit), deep under the blocker (dark),
    // and below the shadow's edge (penumbra).
    for (double x : {3.0, -3.0, 0.0}) {
        RayProbe full(spec), fast(spec, adaptive);
        const Vec3 target{x, 0, 1};
        const Vec3 eye{x, 0.5, -2};
        const Color a = full.trace(eye, target - eye);
        const Color b = fast.trace(eye, target - eye);
        INFO("x = " << x);
        CHECK(full.stats.shadow_rays == 64);
        if (x != 0.0) {
            CHECK(fast.stats.shadow_rays == 5);
            CHECK(a == b);
        } else {
            CHECK(fast.stats.shadow_rays > 5);
            CHECK(fast.stats.shadow_rays <= 64);
            CHECK(std::abs(a.x - b.x) < 0.05);
        }
    }
}

TEST_CASE("adaptive lights: a straight shadow edge on a uniform grid is exact", "[adaptive]") {
    const auto spec = shadow_scene(LightSampling::Uniform, false);
    const auto full = render_spec(spec);
    const auto fast = render_spec(spec, adaptive_options());
    CHECK(fast.stats.nonfinite_samples == 0);
    CHECK(std::equal(fast.film.rgb.begin(), fast.film.rgb.end(), full.film.rgb.begin(), full.film.rgb.end()));
    CHECK(fast.stats.shadow_rays * 2 < full.stats.shadow_rays);
}

TEST_CASE("adaptive lights: error against the full jittered grid is bounded", "[adaptive]") {
    const auto spec = shadow_scene(LightSampling::Jittered, true);
    const auto full = render_spec(spec);
    const auto fast = render_spec(spec, adaptive_options());
    CHECK(fast.stats.nonfinite_samples == 0);
    double max_error = 0, sum_error = 0;
    size_t exact = 0;
    for (size_t i = 0; i < full.film.rgb.size(); ++i) {
        const double e = std::abs(double(full.film.rgb[i]) - double(fast.film.rgb[i]));
        max_error = std::max(max_error, e);
        sum_error += e;
        exact += e == 0;
    }
    const double mean_error = sum_error / double(full.film.rgb.size());
    INFO("max " << max_error << " mean " << mean_error << " exact " << exact);
    // Bounds: one 8×8 cell's full contribution (1/64 of the light) times a few cells.
    CHECK(max_error < 0.1);
    CHECK(mean_error < 0.002);
    CHECK(exact > full.film.rgb.size() * 8 / 10);
    CHECK(fast.stats.shadow_rays * 2 < full.stats.shadow_rays);
}

TEST_CASE("adaptive supersampling refines only where neighbours differ", "[adaptive]") {
    auto spec = basic_scene(32, 32);
    spec.settings.supersamples = 9;
    spec.settings.adaptive_supersampling = true;
    spec.settings.background = {0.2, 0.2, 0.2};
    spec.shapes.push_back(sphere({0, 0, 0}, 1, add_material(spec, matte({1, 0.5, 0.2}))));
    spec.lights.push_back(point_light({3, 3, -3}));
    auto single = spec;
    single.settings.supersamples = 1;
    const auto reference = render_spec(single);

    // Nothing differs by more than 1 in display values: the image is the centre rays'.
    spec.settings.aa_threshold = 1;
    const auto none = render_spec(spec);
    CHECK(none.stats.adaptive_pixels == 0);
    CHECK(std::equal(none.film.rgb.begin(), none.film.rgb.end(), reference.film.rgb.begin(),
                     reference.film.rgb.end()));

    spec.settings.aa_threshold = 0.02;
    const auto some = render_spec(spec);
    CHECK(some.stats.nonfinite_samples == 0);
    CHECK(some.stats.adaptive_pixels > 0);
    CHECK(some.stats.adaptive_pixels < 32 * 32 / 2);
    // A corner pixel sees only background, as do its neighbours: not refined, exactly the centre.
    CHECK(pixel(some.film, 0, 0) == Color(0.2f));
    int changed = 0;
    for (size_t i = 0; i < some.film.rgb.size(); ++i) changed += some.film.rgb[i] != reference.film.rgb[i];
    CHECK(changed > 0);
}
