// specular_lobe_reaches: with exact_area_lights, the specular cells of a light are summed only
// where the lobe can reach it; where it cannot, every cell's specular term is exactly 0.
#include <catch2/catch.hpp>
#include <random>

#include "render/light_terms.h"
#include "tests/render/scene_builders.h"

using namespace wsd::test;
using wsd::render::Light;
using wsd::render::LightCells;
using wsd::render::LightSampling;
using wsd::render::Shading;

namespace {

Vec3 unit(std::mt19937_64& rng) {
    std::normal_distribution<double> g;
    for (;;) {
        const Vec3 v{g(rng), g(rng), g(rng)};
        if (glm::length(v) > 1e-3) return glm::normalize(v);
    }
}

Shading shading(Vec3 p, Vec3 n, Vec3 v, double shininess) {
    Shading sh{};
    sh.p = p;
    sh.ng = sh.ng_v = sh.N = n;
    sh.V = v;
    sh.nv = glm::dot(n, v);
    sh.opaque = false;  // every cell counts, also those behind the surface: the hardest case
    sh.diffuse = true;
    sh.specular = 1;
    sh.shininess = shininess;
    return sh;
}

// The largest specular term over the light's cells (what the cell sum would add).
double max_cell_specular(const Shading& sh, const Light& light, uint64_t key) {
    LightCells cells;
    cells.resize(size_t(light.count()));
    const int n = cells.prepare(sh, light, key);
    double most = 0;
    for (int k = 0; k < n; ++k) most = std::max(most, cells.term(sh, k).sp);
    return most;
}

bool reaches(const Shading& sh, const Light& light) {
    return wsd::render::specular_lobe_reaches(sh, light.corner, light.du * double(light.nu),
                                              light.dv * double(light.nv));
}

}  // namespace

TEST_CASE("R97: specular lobe: where it cannot reach the light, every cell's specular term is 0",
          "[light][closedform]") {
    std::mt19937_64 rng(20261127);
    std::uniform_real_distribution<double> U(0, 1);
    int skipped = 0, summed = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        const double scale = std::pow(10.0, 6 * U(rng) - 3);  // 10⁻³ … 10³
        const Vec3 p = scale * 100.0 * (unit(rng) * U(rng));
        const Vec3 n = unit(rng);
        Vec3 v = unit(rng);
        if (glm::dot(n, v) < 0) v = -v;
        const Vec3 centre = p + scale * (1 + 4 * U(rng)) * unit(rng);
        const int nu = 1 + int(U(rng) * 8), nv = 1 + int(U(rng) * 8);
        const Light light = wsd::render::prepare_light(
            area_light(centre, scale * U(rng) * unit(rng), scale * U(rng) * unit(rng), nu, nv,
                       trial % 3 ? LightSampling::Jittered : LightSampling::Uniform));
        const Shading sh = shading(p, n, v, 1 + 99 * U(rng));
        const double most = max_cell_specular(sh, light, uint64_t(trial) * 7919);
        INFO("trial " << trial << ": largest cell term " << most);
        if (!reaches(sh, light)) {
            ++skipped;
            CHECK(most == 0);
        } else {
            ++summed;
        }
    }
    CHECK(skipped > 1000);
    CHECK(summed > 1000);
}

TEST_CASE("R97: specular lobe: a light touching the plane where R·L = 0 is not skipped",
          "[light][closedform]") {
    // V and N in the x-y plane; the mirror of V about N is M = (1, 1, 0)/√2. A light with one edge
    // on M·(q − p) = 0 and the rest behind it is at the lobe's boundary, where rounding could give
    // a cell a tiny positive R·L: the test claims only what it can prove, and does not skip it.
    const Vec3 n{0, 1, 0}, v = glm::normalize(Vec3{-1, 1, 0});
    const Shading sh = shading({0, 0, 0}, n, v, 10);
    const Vec3 edge = glm::normalize(Vec3{1, -1, 0}), m = glm::normalize(Vec3{1, 1, 0});
    const Light touching =
        wsd::render::prepare_light(area_light(3.0 * edge - 0.0005 * m, {0, 0, 2}, 0.001 * m, 4, 4));
    CHECK(reaches(sh, touching));
    // Moved clearly behind the plane it is skipped, and every cell agrees.
    const Light behind =
        wsd::render::prepare_light(area_light(3.0 * edge - 0.01 * m, {0, 0, 2}, 0.001 * m, 4, 4));
    CHECK_FALSE(reaches(sh, behind));
    CHECK(max_cell_specular(sh, behind, 1) == 0);
}

TEST_CASE("R97: specular lobe: a light in the mirror direction is summed", "[light][closedform]") {
    const Vec3 n{0, 1, 0}, v = glm::normalize(Vec3{-1, 1, 0});
    const Shading sh = shading({0, 0, 0}, n, v, 50);
    // Centred on the mirror direction, and one only grazed by it at a corner.
    const Light centred = wsd::render::prepare_light(area_light({5, 5, 0}, {1, 0, 0}, {0, 0, 1}, 4, 4));
    CHECK(reaches(sh, centred));
    CHECK(max_cell_specular(sh, centred, 1) > 0.5);
    const Light corner = wsd::render::prepare_light(area_light({5.5, 5, 0.5}, {1, 0, 0}, {0, 0, 1}, 4, 4));
    CHECK(reaches(sh, corner));
    CHECK(max_cell_specular(sh, corner, 1) > 0);
}

TEST_CASE("exact_area_lights: a highlight that misses the light adds exactly nothing",
          "[light][closedform]") {
    // A shiny floor under a light low behind the camera: no floor point's lobe reaches it.
    auto render_with = [](double specular, Vec3 light_centre) {
        auto spec = basic_scene(40, 30, {0, 2, -3}, 60);
        spec.camera.look_at = {0, 0, 1};
        spec.settings.exact_area_lights = true;
        auto m = matte({0.7, 0.6, 0.5}, 0.1);
        m.specular = specular;
        m.shininess = 20;
        spec.shapes.push_back(plane({0, 1, 0}, 0, add_material(spec, m)));
        spec.shapes.push_back(sphere({0, -5, 0}, 1, 0));
        spec.lights.push_back(area_light(light_centre, {2, 0, 0}, {0, 0, 2}, 4, 4));
        return render_spec(spec).film.rgb;
    };
    const Vec3 behind{0, 1, -8}, above{0, 3, 1};
    CHECK(render_with(0.5, behind) == render_with(0, behind));
    CHECK(render_with(0.5, above) != render_with(0, above));
}
