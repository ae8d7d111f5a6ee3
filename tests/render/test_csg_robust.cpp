// CSG hard cases (docs/robustness.md R72–R76): coincident and touching surfaces, spawned rays,
// glass as one solid, lines through a member's rim.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "tests/render/csg_test_util.h"

using namespace wsd::test;
using namespace wsd::test::csg_util;

TEST_CASE("R72: CSG coincident faces: a box minus a box sharing faces leaves no sliver", "[csg][robust]") {
    auto spec = basic_scene(8, 8);
    const uint32_t red = add_material(spec, matte({1, 0, 0})),
                   steel = add_material(spec, matte({0.5, 0.5, 0.5}));
    // The removed half written differently (centred, moved, turned a quarter about x), so that
    // its faces' crossings differ from the first box's by rounding.
    ShapeSpec half = box({-0.5, -1, -1}, {0.5, 1, 1}, steel);
    half.object_to_world = glm::translate(Mat4(1.0), Vec3(0.5, 0, 0)) *
                           glm::rotate(Mat4(1.0), glm::radians(90.0), Vec3(1, 0, 0));
    ShapeSpec solid = csg(CsgOp::Difference, {box({-1, -1, -1}, {1, 1, 1}, red), half}, red);
    // Rotated and far from the origin, so that the faces' crossings differ by rounding.
    const Mat4 m = placed({1, 1, 1}, 30, {1000, -500, 300});
    solid.object_to_world = m;
    spec.shapes.push_back(solid);
    auto scene = build(spec);
    const Mat4 inv = glm::inverse(m);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.2, 1.2);
    int sliver = 0, cut = 0, wrong_material = 0;
    for (int k = 0; k < 20000; ++k) {
        // Aimed at the shared faces y = ±1 and z = ±1 over the removed half x ∈ (0, 1).
        const Vec3 target_local(std::abs(u(rng)), k % 2 ? 1.0 : -1.0, u(rng));
        const Vec3 dir_local =
            glm::normalize(Vec3(u(rng), k % 2 ? -1.0 : 1.0, u(rng)) + Vec3(0, k % 2 ? -0.2 : 0.2, 0));
        const Vec3 o_local = target_local - 6.0 * dir_local;
        const Ray ray{Vec3(m * glm::dvec4(o_local, 1.0)), Vec3(m * glm::dvec4(dir_local, 0.0))};
        const auto hit = first_hit(*scene, ray);
        if (!hit) continue;
        const auto s = scene->geometry().surface(ray, *hit);
        const Vec3 p = Vec3(inv * glm::dvec4(s.p, 1.0));
        if (p.x > 1e-9) ++sliver;
        if (std::abs(p.x) < 1e-9) {
            ++cut;
            if (s.material != steel) ++wrong_material;  // the cut surface is the subtracting member's
        }
    }
    CHECK(sliver == 0);
    CHECK(cut > 100);
    CHECK(wrong_material == 0);
}

TEST_CASE("R73: CSG coincident faces: two boxes touching face to face make one solid", "[csg][robust]") {
    auto spec = basic_scene(8, 8);
    const uint32_t red = add_material(spec, matte({1, 0, 0}));
    ShapeSpec left = box({-0.5, -0.5, -0.5}, {0, 0.5, 0.5}, red),
              right = box({-0.5, -1, -1}, {0.5, 1, 1}, red);
    left.object_to_world =
        glm::scale(Mat4(1.0), Vec3(2.0)) * glm::rotate(Mat4(1.0), glm::radians(180.0), Vec3(1, 0, 0));
    right.object_to_world = glm::translate(Mat4(1.0), Vec3(0.5, 0, 0));
    ShapeSpec solid = csg(CsgOp::Union, {left, right}, red);
    const Mat4 m = placed({2, -1, 3}, 40, {-300, 700, 1000});
    solid.object_to_world = m;
    spec.shapes.push_back(solid);
    auto scene = build(spec);
    const Mat4 inv = glm::inverse(m);
    auto world = [&](Vec3 p, double w) { return Vec3(m * glm::dvec4(p, w)); };
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-0.9, 0.9);
    int inner = 0, misses = 0;
    for (int k = 0; k < 20000; ++k) {
        // From inside the first box across the shared face x = 0.
        const Vec3 o(-std::abs(u(rng)) * 0.5, u(rng), u(rng));
        const Vec3 d = glm::normalize(Vec3(1, u(rng) * 0.3, u(rng) * 0.3));
        const Ray ray{world(o, 1), world(d, 0)};
        const auto hit = first_hit(*scene, ray);
        if (!hit) {
            ++misses;
            continue;
        }
        const Vec3 p = Vec3(inv * glm::dvec4(scene->geometry().surface(ray, *hit).p, 1.0));
        const double outer = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
        if (std::abs(outer - 1) > 1e-9) ++inner;
    }
    CHECK(misses == 0);
    CHECK(inner == 0);
    // Rays exactly along the shared face: from outside they meet the front face, from inside the back.
    for (double y : {-0.5, 0.0, 0.7}) {
        const Ray outside{world({0, y, -5}, 1), world({0, 0, 1}, 0)};
        const auto h1 = first_hit(*scene, outside);
        REQUIRE(h1);
        CHECK(h1->t == Approx(4.0).epsilon(1e-12));
        const Ray within{world({0, y, 0}, 1), world({0, 0, 1}, 0)};
        const auto h2 = first_hit(*scene, within);
        REQUIRE(h2);
        CHECK(h2->t == Approx(1.0).epsilon(1e-12));
    }
}

TEST_CASE("R73: CSG: a member exactly touching another changes nothing", "[csg][robust]") {
    auto spec = basic_scene(8, 8);
    const uint32_t red = add_material(spec, matte({1, 0, 0}));
    // The sphere touches the box's top face at one point from outside: the difference is the box.
    spec.shapes.push_back(
        csg(CsgOp::Difference, {box({-1, -1, -1}, {1, 1, 1}, red), sphere({0, 2, 0}, 1, red)}, red));
    auto scene = build(spec);
    int bad = 0;
    for (int j = -20; j <= 20; ++j)
        for (int i = -20; i <= 20; ++i) {
            const Ray ray{{i * 0.01, 5, j * 0.01}, {0, -1, 0}};
            const auto hit = first_hit(*scene, ray);
            if (!hit || hit->t != 4.0) {
                ++bad;
                continue;
            }
            const auto s = scene->geometry().surface(ray, *hit);
            if (s.ng.y != 1.0 && !(s.ng.y > 0.999999)) ++bad;
        }
    CHECK(bad == 0);
}

TEST_CASE("R75: CSG: a glass union of two spheres refracts at its outer surface only (the analytic lens)",
          "[csg]") {
    auto spec = basic_scene(8, 8);
    const uint32_t g = add_material(spec, glass(1.5));
    const Vec3 c1(-0.5, 0, 0), c2(0.5, 0, 0);
    spec.shapes.push_back(csg(CsgOp::Union, {sphere(c1, 1, g), sphere(c2, 1, g)}, g));
    auto scene = build(spec);
    auto interval = [](const Ray& r, Vec3 c, double& t0, double& t1) {
        const Vec3 f = r.o - c;
        const double b = glm::dot(f, r.d), disc = b * b - (glm::dot(f, f) - 1);
        if (disc < 0) return false;
        t0 = -b - std::sqrt(disc);
        t1 = -b + std::sqrt(disc);
        return true;
    };
    int checked = 0;
    for (int j = -6; j <= 6; ++j)
        for (int i = -8; i <= 8; ++i) {
            const Ray ray{{i * 0.1, j * 0.1, -5}, glm::normalize(Vec3(0.03, -0.02, 1))};
            const auto h1 = first_hit(*scene, ray);
            double a0, a1, b0, b1;
            const bool in1 = interval(ray, c1, a0, a1), in2 = interval(ray, c2, b0, b1);
            if (!in1 && !in2) {
                CHECK(!h1);
                continue;
            }
            REQUIRE(h1);
            const double t_entry = std::min(in1 ? a0 : 1e30, in2 ? b0 : 1e30);
            CHECK(h1->t == Approx(t_entry).epsilon(1e-12));
            const auto s1 = scene->geometry().surface(ray, *h1);
            const auto fr = wsd::render::fresnel_refract(ray.d, s1.ng, 1 / 1.5);
            REQUIRE(!fr.total_internal);
            const Ray inner{wsd::render::Geometry::offset_origin(s1, fr.refracted), fr.refracted};
            // Exact exit from the union: the end of the run of overlapping intervals holding t = 0.
            double e0 = 0, e1 = 0, f0 = 0, f1 = 0;
            const bool r1 = interval(inner, c1, e0, e1), r2 = interval(inner, c2, f0, f1);
            double exit = 0;
            if (r1 && e0 <= 1e-9 && e1 > 0) exit = e1;
            if (r2 && f0 <= 1e-9 && f1 > 0) exit = std::max(exit, f1);
            if (r1 && e0 <= exit && e1 > exit) exit = e1;
            if (r2 && f0 <= exit && f1 > exit) exit = f1;
            const auto h2 = first_hit(*scene, inner);
            REQUIRE(h2);
            CHECK(h2->t == Approx(exit).epsilon(1e-9));
            const auto s2 = scene->geometry().surface(inner, *h2);
            CHECK(glm::dot(s2.ng, inner.d) > 0);  // leaving: the outward normal faces along the ray
            ++checked;
        }
    CHECK(checked > 100);
}

TEST_CASE("R75: CSG: light through a glass union is absorbed along its whole chord", "[csg]") {
    auto spec = basic_scene(8, 8);
    spec.settings.background = Color(1);
    // η = 1: no bending, so the colour is exp(−α·L) with L the chord through both spheres.
    auto m = glass(1.0, Color(1), Color(0.7, 0.7, 0.7));
    m.ambient = 0;
    const uint32_t g = add_material(spec, m);
    spec.shapes.push_back(csg(CsgOp::Union, {sphere({-0.5, 0, 0}, 1, g), sphere({0.5, 0, 0}, 1, g)}, g));
    RayProbe probe(spec);
    for (double y : {0.0, 0.3, 0.6}) {
        const double h = std::sqrt(1 - y * y);  // half-chord of each sphere along x at height y
        const double chord = 2 * h + 1.0;       // from x = −0.5 − h to 0.5 + h
        const Color c = probe.trace({-5, y, 0}, {1, 0, 0});
        CHECK(c.x == Approx(std::exp(-0.7 * chord)).epsilon(1e-6));
    }
}

TEST_CASE("R74: rays spawned from a convex CSG never re-hit it, 2^-10 to 2^10 and 10^5 away",
          "[csg][robust]") {
    // A lens (the intersection of two spheres), a rotated box minus a half-space, a cylinder cut
    // by a box and a capped cone cut by a sphere are convex: a ray leaving the surface outward
    // cannot meet them again, and one entering must leave.
    int rehits = 0, escapes = 0, rays = 0;
    for (double scale : {0x1p-10, 1.0, 0x1p10})
        for (Vec3 shift : {Vec3(0), Vec3(1e5, -1e5, 1e5)}) {
            auto spec = basic_scene(8, 8);
            const uint32_t red = add_material(spec, matte({1, 0, 0}));
            ShapeSpec lens = csg(CsgOp::Intersection,
                                 {sphere({0, 0, -0.6}, 1.2, red), sphere({0, 0, 0.6}, 1.2, red)}, red);
            ShapeSpec cut = box({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}, red);
            cut.object_to_world = glm::rotate(Mat4(1.0), 0.7, Vec3(1, 2, 0));
            ShapeSpec wedge = csg(CsgOp::Difference, {cut, plane({1, 1, 1}, -0.2, red)}, red);
            const Mat4 place = glm::translate(Mat4(1.0), shift) * glm::scale(Mat4(1.0), Vec3(scale));
            lens.object_to_world = place;
            wedge.object_to_world = place * glm::translate(Mat4(1.0), Vec3(4, 0, 0));
            ShapeSpec can;
            can.kind = ShapeKind::Cylinder;
            can.base = {0, -0.6, 0};
            can.cap = {0.2, 0.6, 0.1};
            can.radius = 0.4;
            can.material = red;
            ShapeSpec tip = can;
            tip.kind = ShapeKind::Cone;
            tip.cap_radius = 0.1;
            ShapeSpec pill =
                csg(CsgOp::Intersection, {can, box({-0.5, -0.3, -0.5}, {0.5, 0.5, 0.3}, red)}, red);
            ShapeSpec nib = csg(CsgOp::Intersection, {tip, sphere({0, 0, 0}, 0.55, red)}, red);
            pill.object_to_world = place * glm::translate(Mat4(1.0), Vec3(0, 4, 0));
            nib.object_to_world = place * glm::translate(Mat4(1.0), Vec3(4, 4, 0));
            spec.shapes = {lens, wedge, pill, nib};
            auto scene = build(spec);
            std::mt19937 rng(17);
            for (int k = 0; k < 4000; ++k) {
                const Vec3 aim = Vec3(k % 2 ? 4 : 0, (k / 2) % 2 ? 4 : 0, 0) + unit(rng) * 0.3;
                const Vec3 from = aim + unit(rng) * 6.0;
                const Ray ray{Vec3(place * glm::dvec4(from, 1)), Vec3(place * glm::dvec4(aim - from, 0))};
                const auto hit = first_hit(*scene, ray);
                if (!hit) continue;
                ++rays;
                const auto s = scene->geometry().surface(ray, *hit);
                const Vec3 out = glm::normalize(s.ng + 0.9 * unit(rng));
                const Vec3 w = glm::dot(out, s.ng) > 0 ? out : -out;
                const auto again = first_hit(*scene, Ray{wsd::render::Geometry::offset_origin(s, w), w});
                if (again && again->prim == hit->prim) ++rehits;
                const Vec3 in = -w;
                const auto through = first_hit(*scene, Ray{wsd::render::Geometry::offset_origin(s, in), in});
                if (!through || through->prim != hit->prim) ++escapes;
            }
        }
    CHECK(rays > 10000);
    CHECK(rehits == 0);
    CHECK(escapes == 0);
}

TEST_CASE("R76: CSG: a line through a cylinder's rim keeps the inside count right", "[csg][robust]") {
    auto spec = basic_scene(8, 8);
    const uint32_t red = add_material(spec, matte({1, 0, 0}));
    ShapeSpec can;
    can.kind = ShapeKind::Cylinder;
    can.base = {0, 0, 0};
    can.cap = {0, 1, 0};
    can.radius = 1;
    can.material = red;
    spec.shapes.push_back(csg(CsgOp::Union, {can}, red));
    auto scene = build(spec);
    int wrong = 0;
    for (int k = 0; k < 64; ++k) {
        const double a = 2 * 3.14159265358979323846 * k / 64;
        const Vec3 rim(std::cos(a), 1, std::sin(a));
        // Down and inward through the rim, seen from outside and from inside the solid.
        const Vec3 d = glm::normalize(Vec3(-0.5 * rim.x, -1, -0.5 * rim.z));
        for (double back : {-2.0, 0.3}) {
            const Ray ray{rim + back * d, d};
            const auto h = first_hit(*scene, ray);
            if (!h) {
                ++wrong;
                continue;
            }
            const auto s = scene->geometry().surface(ray, *h);
            const bool leaving = glm::dot(s.ng, d) > 0;
            if (leaving != (back > 0)) ++wrong;
        }
    }
    CHECK(wrong == 0);
}

TEST_CASE("R73: CSG: two closed meshes touching face to face make one solid", "[csg][robust]") {
    // Mesh vertices are stored as floats in world space: 10³ from the origin they are rounded to
    // about 6e-5, so distances are compared to that.
    auto spec = basic_scene(8, 8);
    const uint32_t red = add_material(spec, matte({1, 0, 0}));
    ShapeSpec left = mesh_shape(cube_mesh(false), red), right = mesh_shape(cube_mesh(true), red);
    left.object_to_world = glm::translate(Mat4(1.0), Vec3(-1, -0.5, -0.5));
    right.object_to_world = glm::translate(Mat4(1.0), Vec3(0, -0.5, -0.5));
    ShapeSpec solid = csg(CsgOp::Union, {left, right}, red);
    const Mat4 m = placed({2, -1, 3}, 40, {-300, 700, 1000});
    solid.object_to_world = m;
    spec.shapes.push_back(solid);
    auto scene = build(spec);
    auto world = [&](Vec3 p, double w) { return Vec3(m * glm::dvec4(p, w)); };
    int bad = 0, total = 0;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-0.45, 0.45);
    for (int k = 0; k < 2000; ++k) {
        const double y = u(rng);
        // Along the shared face from outside and from inside, and across it.
        const Ray outside{world({0, y, -5}, 1), world({0, 0, 1}, 0)};
        const auto h1 = first_hit(*scene, outside);
        ++total;
        if (!h1 || std::abs(h1->t - 4.5) > 1e-4) ++bad;
        const Ray within{world({0, y, 0}, 1), world({0, 0, 1}, 0)};
        const auto h2 = first_hit(*scene, within);
        if (!h2 || std::abs(h2->t - 0.5) > 1e-4) ++bad;
        const Ray across{world({-0.7, y, u(rng)}, 1), world({1, 0.01, 0}, 0)};
        const auto h3 = first_hit(*scene, across);
        if (!h3 || std::abs(h3->t - 1.7) > 1e-4) ++bad;
    }
    CHECK(total == 2000);
    CHECK(bad == 0);
}

TEST_CASE("R75: CSG: a hollow glass sphere absorbs only in its shell", "[csg][robust]") {
    auto spec = basic_scene(8, 8);
    spec.settings.background = Color(1);
    auto m = glass(1.0, Color(1), Color(0.9, 0.9, 0.9));
    m.ambient = 0;
    const uint32_t g = add_material(spec, m);
    // The cavity's surface is the subtracted sphere's, facing into the cavity: leaving the glass.
    spec.shapes.push_back(csg(CsgOp::Difference, {sphere({0, 0, 0}, 1, g), sphere({0, 0, 0}, 0.6, g)}, g));
    RayProbe probe(spec);
    for (double y : {0.0, 0.3, 0.59, 0.8}) {
        const double outer = 2 * std::sqrt(1 - y * y);
        const double cavity = y < 0.6 ? 2 * std::sqrt(0.36 - y * y) : 0.0;
        const Color c = probe.trace({-5, y, 0}, {1, 0, 0});
        CHECK(c.x == Approx(std::exp(-0.9 * (outer - cavity))).epsilon(1e-6));
    }
}

TEST_CASE("R74: rays spawned from a half torus never re-hit it at their origin", "[csg][robust]") {
    // Not convex: a ray may meet the solid again, but never within 10^-7 of its size of where it
    // left (the true next surface is far farther: the tube's radius is 0.3).
    int self = 0, rays = 0;
    for (double scale : {0x1p-10, 1.0, 0x1p10})
        for (Vec3 shift : {Vec3(0), Vec3(1e5, -1e5, 1e5)}) {
            auto spec = basic_scene(8, 8);
            const uint32_t red = add_material(spec, matte({1, 0, 0}));
            ShapeSpec ring;
            ring.kind = ShapeKind::Torus;
            ring.major = 0.8;
            ring.minor = 0.3;
            ring.material = red;
            ShapeSpec solid = csg(CsgOp::Difference, {ring, box({-2, 0.1, -2}, {2, 2, 2}, red)}, red);
            const Mat4 place = glm::translate(Mat4(1.0), shift) * glm::scale(Mat4(1.0), Vec3(scale)) *
                               glm::rotate(Mat4(1.0), 0.3, Vec3(1, 0, 1));
            solid.object_to_world = place;
            spec.shapes = {solid};
            auto scene = build(spec);
            std::mt19937 rng(19);
            for (int k = 0; k < 4000; ++k) {
                const Vec3 aim = unit(rng) * 0.9;
                const Vec3 from = aim + unit(rng) * 6.0;
                const Ray ray{Vec3(place * glm::dvec4(from, 1)), Vec3(place * glm::dvec4(aim - from, 0))};
                const auto hit = first_hit(*scene, ray);
                if (!hit) continue;
                ++rays;
                const auto s = scene->geometry().surface(ray, *hit);
                for (int side : {1, -1}) {
                    const Vec3 out = glm::normalize(s.ng + 0.9 * unit(rng));
                    const Vec3 w = (glm::dot(out, s.ng) > 0 ? out : -out) * double(side);
                    const auto again = first_hit(*scene, Ray{wsd::render::Geometry::offset_origin(s, w), w});
                    if (again && again->t < 1e-7 * scale) ++self;
                }
            }
        }
    CHECK(rays > 10000);
    CHECK(self == 0);
}
