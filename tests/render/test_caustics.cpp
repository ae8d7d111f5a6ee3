// Caustic photons (docs/wsd-language.md "caustics"): the photon power rule against energies
// computed another way, a ball lens's paraxial focus, a mirror's patch, total internal
// reflection, a light inside glass, scenes that shoot nothing, and determinism.
#include <catch2/catch.hpp>
#include <cmath>

#include "render/integrator.h"
#include "render/math.h"
#include "render/photon_map.h"
#include "scene_builders.h"

using namespace wsd;
using namespace wsd::test;
using render::kPi;

namespace {

// A floor (matte plane y = −h), a unit-radius ball of `ball` at the origin, and caustic photons.
render::SceneSpec ball_scene(const render::MaterialSpec& ball, double h, int photons) {
    render::SceneSpec spec = basic_scene(32, 32, {0, 3, -6});
    const uint32_t floor = add_material(spec, matte(Color(0.8)));
    spec.shapes.push_back(plane({0, 1, 0}, -h, floor));
    spec.shapes.push_back(sphere({0, 0, 0}, 1, add_material(spec, ball)));
    spec.settings.caustic_photons = photons;
    return spec;
}

Color stored_power(const render::Scene& scene, double below_y = 1e300) {
    Color sum(0);
    if (!scene.caustics()) return sum;
    for (const render::Photon& p : scene.caustics()->photons())
        if (p.p.y < below_y) sum += Color(p.power);
    return sum;
}

// The power-weighted RMS distance of the stored photons from the y axis.
double spot_radius(const render::Scene& scene) {
    double w = 0, r2 = 0;
    for (const render::Photon& p : scene.caustics()->photons()) {
        const double pw = double(p.power.x);
        w += pw;
        r2 += pw * (p.p.x * p.p.x + p.p.z * p.p.z);
    }
    return std::sqrt(r2 / w);
}

double fresnel(double cos_i, double eta) {
    const double s = std::sqrt(1 - cos_i * cos_i);
    return render::fresnel_refract({s, -cos_i, 0}, {0, 1, 0}, eta).reflectance;
}

// A ball (radius 1, index n, clear glass) under parallel light from above, traced in its
// meridional plane with every Fresnel branch followed to `depth` bounces: the fraction of the
// power entering at impact parameter b that leaves downwards (towards a floor below).
double downward_fraction(double b, double n, int depth) {
    struct Ray2 {
        double px, py, dx, dy, w;
        bool inside;
        int depth;
    };
    double out = 0;
    std::vector<Ray2> stack{{b, 10, 0, -1, 1, false, 0}};
    while (!stack.empty()) {
        const Ray2 r = stack.back();
        stack.pop_back();
        // The far (inside) or near (outside) intersection with the unit circle.
        const double bq = r.px * r.dx + r.py * r.dy, c = r.px * r.px + r.py * r.py - 1;
        const double disc = bq * bq - c;
        if (disc <= 0 || r.depth > depth) {
            if (r.depth > 0 && !r.inside && r.dy < 0) out += r.w;
            continue;
        }
        const double t = r.inside ? -bq + std::sqrt(disc) : -bq - std::sqrt(disc);
        if (t <= 1e-9) {
            if (r.depth > 0 && !r.inside && r.dy < 0) out += r.w;
            continue;
        }
        const double hx = r.px + t * r.dx, hy = r.py + t * r.dy;
        const render::Vec3 nrm = r.inside ? render::Vec3(-hx, -hy, 0) : render::Vec3(hx, hy, 0);
        const render::Vec3 d(r.dx, r.dy, 0);
        const auto fr = render::fresnel_refract(d, nrm, r.inside ? n : 1 / n);
        const render::Vec3 refl = render::reflect(d, nrm);
        if (r.depth == depth) continue;  // the photon's bounces are used up
        const double f = fr.total_internal ? 1.0 : fr.reflectance;
        stack.push_back(
            {hx + 1e-9 * refl.x, hy + 1e-9 * refl.y, refl.x, refl.y, r.w * f, r.inside, r.depth + 1});
        if (!fr.total_internal)
            stack.push_back({hx + 1e-9 * fr.refracted.x, hy + 1e-9 * fr.refracted.y, fr.refracted.x,
                             fr.refracted.y, r.w * (1 - f), !r.inside, r.depth + 1});
    }
    return out;
}

}  // namespace

TEST_CASE("caustics: a clear ball of index 1 passes light through its cross-section exactly", "[caustics]") {
    const Color c(1, 0.5, 0.25);
    render::SceneSpec spec = ball_scene(glass(1.0, c), 3, 40000);
    spec.lights.push_back(point_light({0, 1000, 0}, 2));
    const auto scene = build(spec);
    REQUIRE(scene->caustic_build().shot == 40000);
    // Each interface passes t·c: c² after two; the power entering is light × πR².
    const Color expected = 2.0 * kPi * c * c;
    const Color got = stored_power(*scene);
    CHECK(got.x == Approx(expected.x).epsilon(0.03));
    CHECK(got.y == Approx(expected.y).epsilon(0.03));
    CHECK(got.z == Approx(expected.z).epsilon(0.03));
}

TEST_CASE("caustics: a glass ball's stored power matches a meridional Fresnel trace", "[caustics]") {
    render::SceneSpec spec = ball_scene(glass(1.5), 3, 60000);
    spec.lights.push_back(point_light({0, 1000, 0}, 1));
    const auto scene = build(spec);
    // ∫ 2πb·fraction(b) db over the unit disc (midpoint rule).
    double expected = 0;
    constexpr int kSteps = 4000;
    for (int i = 0; i < kSteps; ++i) {
        const double b = (i + 0.5) / kSteps;
        expected += 2 * kPi * b * downward_fraction(b, 1.5, spec.settings.max_depth) / kSteps;
    }
    CHECK(stored_power(*scene).x == Approx(expected).epsilon(0.02));
}

TEST_CASE("caustics: a ball lens focuses near-axis light at its paraxial focus", "[caustics]") {
    // A spot light far above lights only the ball's central 15 % (paraxial rays); the floor is
    // moved along the axis, and the spot on it is smallest at f = nR / (2(n − 1)) from the centre.
    const double n = 1.5, f = n / (2 * (n - 1));
    auto radius_at = [&](double h) {
        render::SceneSpec spec = ball_scene(glass(n), h, 30000);
        render::LightSpec l = point_light({0, 100, 0}, 1);
        l.kind = render::LightKind::Spot;
        l.look_at = {0, 0, 0};
        l.angle = l.falloff = std::atan(0.15 / 100) * 180 / kPi;
        spec.lights.push_back(l);
        const auto scene = build(spec);
        REQUIRE(scene->caustics());
        return spot_radius(*scene);
    };
    // A parabola through the spot radius at three heights around f: its minimum.
    const double step = 0.1 * f;
    const double a = radius_at(f - step), b = radius_at(f), c = radius_at(f + step);
    CHECK(b < 0.5 * a);
    CHECK(b < 0.5 * c);
    const double vertex = f + step * (a - c) / (2 * (a - 2 * b + c));
    CHECK(vertex == Approx(f).epsilon(0.03));
}

TEST_CASE("caustics: the gathered energy in a lens's focus matches ten times the photons counted",
          "[caustics]") {
    // The estimate the renderer uses (k nearest, cone filter) integrated over a disc around the
    // focus, against the photons of a map ten times larger that land in the disc.
    const double f = 1.5, disc = 0.2;
    auto spec_with = [&](int photons) {
        render::SceneSpec spec = ball_scene(glass(1.5), f, photons);
        spec.lights.push_back(point_light({0, 1000, 0}, 1));
        return spec;
    };
    const auto coarse = build(spec_with(30000));
    const auto fine = build(spec_with(300000));
    render::RayStats stats;
    double gathered = 0;
    // Rings around the axis, finely spaced: the focus is a sharp peak that a coarse grid misses.
    constexpr int kRings = 400, kAngles = 24;
    const double dr = disc / kRings;
    for (int j = 0; j < kRings; ++j) {
        const double r = (j + 0.5) * dr;
        for (int i = 0; i < kAngles; ++i) {
            const double phi = 2 * kPi * (i + 0.5) / kAngles;
            gathered += coarse->caustics()
                            ->irradiance({r * std::cos(phi), -f, r * std::sin(phi)}, {0, 1, 0}, stats)
                            .x *
                        (2 * kPi * r * dr / kAngles);
        }
    }
    double counted = 0;
    for (const render::Photon& p : fine->caustics()->photons())
        if (p.p.x * p.p.x + p.p.z * p.p.z <= disc * disc && p.p.y < -f + 1e-6) counted += double(p.power.x);
    CHECK(stats.photon_lookups > 0);
    CHECK(stats.photons_visited >= stats.photon_lookups);
    CHECK(gathered == Approx(counted).epsilon(0.03));
    // Most of the light through the ball lands in the disc: it is a focus.
    CHECK(counted > 0.5 * stored_power(*fine).x);
}

TEST_CASE("caustics: a mirror throws a patch of light of its projected area", "[caustics]") {
    render::SceneSpec spec = basic_scene(32, 32, {-4, 0, -6});
    render::MaterialSpec mirror = matte(Color(1));
    mirror.reflection = 0.8;
    mirror.diffuse = 0;
    const double L = 1;
    const Vec3 u = Vec3(1, -1, 0) * (L / std::sqrt(2.0)), v(0, 0, L);
    spec.shapes.push_back(quad(-0.5 * u - 0.5 * v, u, v, add_material(spec, mirror)));
    spec.shapes.push_back(quad({3, -5, -5}, {0, 10, 0}, {0, 0, 10}, add_material(spec, matte(Color(0.8)))));
    spec.lights.push_back(point_light({0, 1000, 0}, 1));
    spec.settings.caustic_photons = 100000;
    const auto scene = build(spec);
    REQUIRE(scene->caustics());
    const double half_y = L / (2 * std::sqrt(2.0)) + 0.01, half_z = L / 2 + 0.01;
    for (const render::Photon& p : scene->caustics()->photons()) {
        REQUIRE(p.p.x == Approx(3).margin(1e-6));
        REQUIRE(std::abs(p.p.y) <= half_y);
        REQUIRE(std::abs(p.p.z) <= half_z);
    }
    CHECK(stored_power(*scene).x == Approx(0.8 * L * L / std::sqrt(2.0)).epsilon(0.015));
    // And the render shows it: the wall is brighter inside the patch than beside it.
    render::SceneSpec view = spec;
    view.camera.position = {0, 0, 0.2};
    view.camera.look_at = {3, 0, 0.2};
    auto lit = render_spec(view);
    CHECK(lit.stats.photon_lookups > 0);
    CHECK(pixel(lit.film, 16, 16).x > pixel(lit.film, 16, 2).x + 0.3);
}

TEST_CASE("caustics: photons pass a light pipe by total internal reflection", "[caustics]") {
    // Light enters the top of a tall glass block at 30°, meets the sides beyond the critical
    // angle (TIR: nothing leaks) and leaves at the bottom: (1 − F)/(1 + F) of it reaches the floor.
    render::SceneSpec spec = basic_scene(32, 32, {0, 2, -8});
    spec.shapes.push_back(box({-0.5, 0, -0.5}, {0.5, 4, 0.5}, add_material(spec, glass(1.5))));
    spec.shapes.push_back(plane({0, 1, 0}, -1, add_material(spec, matte(Color(0.8)))));
    const double theta = 30 * kPi / 180, D = 100, a = 0.3;
    render::LightSpec l = point_light(Vec3(0, 4, 0) + D * Vec3(std::sin(theta), std::cos(theta), 0), 1);
    l.kind = render::LightKind::Spot;
    l.look_at = {0, 4, 0};
    l.angle = l.falloff = std::atan(a / D) * 180 / kPi;
    spec.lights.push_back(l);
    spec.settings.caustic_photons = 1000000;
    const auto scene = build(spec);
    REQUIRE(scene->caustics());
    const double F = fresnel(std::cos(theta), 1 / 1.5);
    const double entering = kPi * a * a;  // the beam's cross-section: light × area
    CHECK(stored_power(*scene).x == Approx(entering * (1 - F) / (1 + F)).epsilon(0.02));
    // Every photon left through the bottom at 30° (either way, after an even or odd number of
    // reflections off the sides): none leaked through a side to land farther out.
    int left = 0, right = 0;
    for (const render::Photon& p : scene->caustics()->photons()) {
        REQUIRE(std::abs(p.p.x) <= 0.5 + std::tan(theta) + 1e-3);
        REQUIRE(std::abs(p.p.z) <= 1.1 * a);  // the beam widens by 5 % from the top to the floor
        (p.p.x < 0 ? left : right) += 1;
    }
    CHECK(left > 100);
    CHECK(right > 100);
}

TEST_CASE("caustics: a point light inside glass lights the floor through the ball", "[caustics]") {
    render::SceneSpec spec = ball_scene(glass(1.5), 2, 40000);
    spec.lights.push_back(point_light({0, 0, 0}, 1));
    const auto scene = build(spec);
    REQUIRE(scene->caustics());
    // Radial rays: F(0) reflected back through the centre, the rest out; half goes down.
    const double F0 = 0.04;
    const double expected = 2 * kPi * (1 - std::pow(F0, spec.settings.max_depth));
    CHECK(stored_power(*scene).x == Approx(expected).epsilon(0.02));
    const auto result = render_spec(spec);
    CHECK(result.stats.nonfinite_samples == 0);
    CHECK(result.stats.photons_stored == scene->caustic_build().stored);
}

TEST_CASE("caustics: nothing is shot where no object can focus light", "[caustics]") {
    render::SceneSpec spec = ball_scene(matte(Color(0.5)), 2, 50000);
    spec.lights.push_back(point_light({0, 10, 0}, 1));
    const auto scene = build(spec);
    CHECK(scene->caustic_build().shot == 0);
    CHECK(scene->caustic_build().skipped == "no object can focus light");
    CHECK(!scene->caustics());
    const auto with = render_spec(spec);
    CHECK(with.stats.photons_shot == 0);
    CHECK(with.stats.photon_lookups == 0);
    spec.settings.caustic_photons = 0;
    CHECK(render_spec(spec).film.rgb == with.film.rgb);

    // Glass but nothing diffuse to receive it.
    render::SceneSpec bare = basic_scene(16, 16);
    bare.shapes.push_back(sphere({0, 0, 0}, 1, add_material(bare, glass(1.5))));
    bare.lights.push_back(point_light({0, 10, 0}, 1));
    bare.settings.caustic_photons = 1000;
    CHECK(build(bare)->caustic_build().skipped == "no diffuse surface can receive light");
    CHECK(build(bare)->caustic_build().shot == 0);
}

TEST_CASE("caustics: the map and the image do not depend on threads or tiles", "[caustics]") {
    render::SceneSpec spec = ball_scene(glass(1.5), 1.5, 20000);
    spec.lights.push_back(area_light({0, 6, 0}, {1, 0, 0}, {0, 0, 1}, 2, 2));
    std::vector<render::SpecError> errors;
    const auto one = render::build_scene(spec, errors, true, 1);
    const auto three = render::build_scene(spec, errors, true, 3);
    REQUIRE(one);
    REQUIRE(three);
    const auto& a = one->caustics()->photons();
    const auto& b = three->caustics()->photons();
    REQUIRE(a.size() == b.size());
    for (size_t i = 0; i < a.size(); ++i) {
        REQUIRE(a[i].p == b[i].p);
        REQUIRE(a[i].power == b[i].power);
    }
    render::RenderOptions o1, o3;
    o1.threads = 1;
    o3.threads = 3;
    const auto full = render::render(*one, o1);
    CHECK(full.film.rgb == render::render(*three, o3).film.rgb);
    render::RenderOptions tile;
    tile.region = render::Region{8, 8, 24, 20};
    const auto part = render::render(*one, tile);
    for (int y = 8; y < 20; ++y)
        for (int x = 8; x < 24; ++x) REQUIRE(pixel(part.film, x - 8, y - 8) == pixel(full.film, x, y));
    CHECK(full.stats.nonfinite_samples == 0);
    CHECK(full.stats.photon_lookups > 0);
}

TEST_CASE("caustics: the photon estimate integrates to the power it was given", "[caustics]") {
    // Photons of total power 1 spread evenly over a small disc (a sharp spot) and a wider one. The
    // k-nearest estimate has tails (around a spot, r grows with the distance until r_max), so a
    // sharp spot's integral exceeds its power by a few per cent; never more than 8 %.
    for (const auto& [spot, tolerance] : {std::pair{0.02, 0.08}, std::pair{0.1, 0.03}}) {
        std::vector<render::Photon> photons;
        constexpr int kN = 20000;
        uint64_t h = 12345;
        for (int i = 0; i < kN; ++i) {
            const render::Uniform2 u = render::uniform2(h = render::mix64(h + 1));
            const double r = spot * std::sqrt(u.u), phi = 2 * kPi * u.v;
            photons.push_back(
                {{r * std::cos(phi), 0, r * std::sin(phi)}, render::Vec3f(1.0f / kN), {0, 1, 0}});
        }
        const render::PhotonMap map(photons, 35, 0.25);
        render::RayStats stats;
        double sum = 0;
        constexpr int kGrid = 200;
        const double half = 0.5, cell = 2 * half / kGrid;
        for (int j = 0; j < kGrid; ++j)
            for (int i = 0; i < kGrid; ++i)
                sum +=
                    map.irradiance({-half + (i + 0.5) * cell, 0, -half + (j + 0.5) * cell}, {0, 1, 0}, stats)
                        .x *
                    cell * cell;
        INFO("spot radius " << spot);
        CHECK(sum == Approx(1).epsilon(tolerance));
        CHECK(sum >= 1 - tolerance / 4);
    }
}
