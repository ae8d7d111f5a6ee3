// settings.exact_area_lights: where a point sees a whole area light above its tangent plane, the
// diffuse term is the closed-form average of N·L, the limit the jittered cell sum converges to.
#include <catch2/catch.hpp>
#include <cmath>

#include "render/rect_light_integral.h"
#include "tests/render/scene_builders.h"

using namespace wsd::test;
using wsd::render::LightSampling;
using wsd::render::Ray;

namespace {

const Color kFloor{0.7, 0.6, 0.5};
const Vec3 kCentre{0, 3, 1}, kU{2, 0, 0}, kV{0, 0, 2};

// A floor under an n×n area light that every floor point sees whole.
wsd::render::SceneSpec floor_scene(int n, bool exact) {
    auto spec = basic_scene(40, 30, {0, 2, -3}, 60);
    spec.camera.look_at = {0, 0, 1};
    spec.settings.exact_area_lights = exact;
    spec.shapes.push_back(plane({0, 1, 0}, 0, add_material(spec, matte(kFloor, 0.1))));
    // A sphere under the floor, out of every shadow ray's way: the scene has a BVH, which the
    // shaft that proves a point sees the light whole needs.
    spec.shapes.push_back(sphere({0, -5, 0}, 1, 0));
    spec.lights.push_back(area_light(kCentre, kU, kV, n, n, LightSampling::Jittered));
    return spec;
}

// The closed-form value of the floor pixel (x, y), or −1 where the pixel's ray misses the floor.
double closed_form_pixel(const wsd::render::SceneSpec& spec, int x, int y) {
    const Ray ray = camera_ray(spec, x + 0.5, y + 0.5);
    if (!(ray.d.y < 0)) return -1;
    const Vec3 p = ray.o + (-ray.o.y / ray.d.y) * ray.d;
    return wsd::render::rect_light_average_cosine(p, {0, 1, 0}, kCentre - 0.5 * kU - 0.5 * kV, kU, kV);
}

}  // namespace

TEST_CASE("exact_area_lights: a fully lit floor is ambient + colour × the closed form",
          "[light][closedform]") {
    const auto spec = floor_scene(4, true);
    const auto result = render_spec(spec);
    int checked = 0;
    for (int y = 0; y < 30; ++y) {
        for (int x = 0; x < 40; ++x) {
            const double a = closed_form_pixel(spec, x, y);
            if (a < 0) continue;
            ++checked;
            const Color got = pixel(result.film, x, y), want = 0.1 * kFloor + kFloor * a;
            INFO("pixel " << x << "," << y << ": " << got.r << " against " << want.r);
            CHECK(close_to(got, want, 1e-5));
        }
    }
    CHECK(checked > 800);
}

TEST_CASE("exact_area_lights: the jittered n×n cell sum converges to the closed form",
          "[light][closedform]") {
    const auto exact = render_spec(floor_scene(2, true));
    double previous = 1e300;
    for (int n : {2, 6, 18, 54}) {
        const auto cells = render_spec(floor_scene(n, false));
        double se = 0;
        int count = 0;
        for (size_t i = 0; i < exact.film.rgb.size(); ++i) {
            const double d = double(cells.film.rgb[i]) - double(exact.film.rgb[i]);
            se += d * d;
            ++count;
        }
        const double rmse = std::sqrt(se / count);
        INFO("n " << n << " rmse " << rmse);
        // Stratified jitter of a smooth integrand: the error falls at least like 1/n per side.
        CHECK(rmse < 0.5 * previous);
        previous = rmse;
    }
    CHECK(previous < 2e-4);
}

TEST_CASE("exact_area_lights off leaves the cell sum unchanged", "[light][closedform]") {
    auto spec = floor_scene(5, false);
    const auto a = render_spec(spec);
    spec.settings.exact_area_lights = true;
    const auto b = render_spec(spec);
    spec.settings.exact_area_lights = false;
    const auto c = render_spec(spec);
    CHECK(a.film.rgb == c.film.rgb);
    CHECK(a.film.rgb != b.film.rgb);
}

TEST_CASE("exact_area_lights: the specular term is still the cells' sum", "[light][closedform]") {
    // specular(on) − specular(off) is the same highlight whichever way the diffuse term is found.
    auto render_with = [](bool exact, double specular) {
        auto spec = floor_scene(4, exact);
        spec.materials[0].specular = specular;
        spec.materials[0].shininess = 20;
        return render_spec(spec).film.rgb;
    };
    const auto exact_s = render_with(true, 0.5), exact_d = render_with(true, 0);
    const auto cells_s = render_with(false, 0.5), cells_d = render_with(false, 0);
    double highlight = 0;
    for (size_t i = 0; i < exact_s.size(); ++i) {
        const double a = double(exact_s[i]) - double(exact_d[i]), b = double(cells_s[i]) - double(cells_d[i]);
        highlight = std::max(highlight, b);
        CHECK(std::abs(a - b) < 1e-6);
    }
    CHECK(highlight > 0.05);
}
