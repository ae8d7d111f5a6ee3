// CSG solids (union, intersection, difference) against closed forms and brute-force point
// classification; member materials and kinds, effects, errors, closed-mesh validation. The hard
// cases of docs/robustness.md are in test_csg_robust.cpp.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "render/effects.h"
#include "render/mesh_topology.h"
#include "tests/render/csg_test_util.h"

using namespace wsd::test;
using namespace wsd::test::csg_util;

TEST_CASE("CSG: a box minus a box shows a hole of exactly its pixel count, head-on", "[csg]") {
    auto spec = basic_scene(8, 8);
    const uint32_t red = add_material(spec, matte({1, 0, 0}));
    spec.shapes.push_back(csg(
        CsgOp::Difference,
        {box({-1, -1, -0.2}, {1, 1, 0.2}, red), inherit(box({-0.3, -0.45, -1}, {0.3, 0.45, 1}, 0))}, red));
    auto scene = build(spec);
    // An orthographic view: parallel rays through the centres of a 200 × 200 grid over [-1, 1]².
    const int n = 200;
    int holes = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const Vec3 o(-1 + (i + 0.5) * 2.0 / n, -1 + (j + 0.5) * 2.0 / n, -5);
            if (!first_hit(*scene, Ray{o, {0, 0, 1}})) ++holes;
        }
    // Centres with |x| < 0.3 and |y| < 0.45: 60 × 90 of them.
    CHECK(holes == 60 * 90);
}

TEST_CASE("CSG: a box minus a sphere has a round hole of the exact area", "[csg]") {
    auto spec = basic_scene(8, 8);
    const uint32_t red = add_material(spec, matte({1, 0, 0}));
    spec.shapes.push_back(
        csg(CsgOp::Difference, {box({-1, -1, -0.2}, {1, 1, 0.2}, red), sphere({0, 0, 0}, 0.5, red)}, red));
    auto scene = build(spec);
    const int n = 400;
    int holes = 0, wrong = 0;
    const double r_hole = std::sqrt(0.25 - 0.04);  // where the sphere spans the slab's whole depth
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const Vec3 o(-1 + (i + 0.5) * 2.0 / n, -1 + (j + 0.5) * 2.0 / n, -5);
            const bool hole = !first_hit(*scene, Ray{o, {0, 0, 1}});
            holes += hole ? 1 : 0;
            const double r = std::hypot(o.x, o.y);
            if (std::abs(r - r_hole) > 1e-9 && hole != (r < r_hole)) ++wrong;
        }
    CHECK(wrong == 0);
    const double area = holes * (2.0 / n) * (2.0 / n);
    CHECK(area == Approx(3.14159265358979323846 * r_hole * r_hole).epsilon(0.005));
}

TEST_CASE("CSG: first hits agree with brute-force point classification", "[csg]") {
    auto spec = basic_scene(8, 8);
    const uint32_t a = add_material(spec, matte({1, 0, 0})), b = add_material(spec, matte({0, 1, 0}));
    ShapeSpec oct = mesh_shape(octahedron(0.7), b);
    oct.object_to_world = glm::translate(Mat4(1.0), Vec3(-0.8, 0.3, 0));
    ShapeSpec sq = box({0.3, -0.5, -0.5}, {1.5, 0.5, 0.5}, a);
    sq.object_to_world = glm::rotate(Mat4(1.0), 0.4, Vec3(0, 0, 1));
    ShapeSpec nested = csg(CsgOp::Intersection,
                           {box({-2, -2, -0.3}, {2, 2, 2}, b), inherit(sphere({0.2, -0.2, 0.4}, 0.6, 0))});
    ShapeSpec floor = plane({0.1, 1, 0}, -0.6, b);  // subtracts y < −0.6 (roughly): a flat cut
    ShapeSpec solid = csg(CsgOp::Difference,
                          {csg(CsgOp::Union, {sphere({0, 0, 0}, 1, a), sq, oct}),
                           sphere({0.5, 0.6, 0.2}, 0.45, b), nested, floor},
                          a);
    solid.object_to_world = glm::scale(placed({1, 2, 3}, 25, {0.1, 0.2, 0.3}), Vec3(1.0, 1.3, 0.8));
    spec.shapes.push_back(solid);
    auto scene = build(spec);

    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    int hits = 0, failures = 0;
    auto classify = [&](const Vec3& p) { return inside(solid, Mat4(1.0), p); };
    for (int k = 0; k < 20000; ++k) {
        const bool from_inside = k % 3 == 0;
        const Vec3 o = from_inside ? Vec3(u(rng), u(rng), u(rng)) * 0.6 : unit(rng) * 4.0;
        const Vec3 target(u(rng), u(rng), u(rng));
        const Vec3 d = from_inside ? unit(rng) : glm::normalize(target - o);
        const auto hit = first_hit(*scene, Ray{o, d});
        const bool start = classify(o);
        const double end = hit ? hit->t : 12.0;
        // Nothing changes before the hit...
        for (int s = 1; s < 64; ++s)
            if (classify(o + (end * s / 64.0) * d) != start) ++failures;
        if (!hit) continue;
        ++hits;
        // ...and the hit is where the solid's inside changes.
        if (classify(o + (hit->t - 1e-6) * d) == classify(o + (hit->t + 1e-6) * d)) ++failures;
        if (classify(o + (hit->t - 1e-6) * d) != start) ++failures;
    }
    CHECK(hits > 8000);
    CHECK(failures == 0);
}

TEST_CASE("CSG: a plane member is a half-space; members inherit the CSG's material", "[csg]") {
    auto spec = basic_scene(8, 8);
    const uint32_t red = add_material(spec, matte({1, 0, 0})), blue = add_material(spec, matte({0, 0, 1}));
    spec.shapes.push_back(
        csg(CsgOp::Intersection, {sphere({0, 0, 0}, 1, red), inherit(plane({0, 1, 0}, 0, 0))}, blue));
    auto scene = build(spec);
    const Ray down{{0.2, 5, 0.1}, {0, -1, 0}};
    const auto h = first_hit(*scene, down);
    REQUIRE(h);
    CHECK(h->t == 5.0);
    const auto s = scene->geometry().surface(down, *h);
    CHECK(s.material == blue);
    CHECK(s.ng.y == Approx(1.0));
    const Ray up{{0.2, -5, 0.1}, {0, 1, 0}};
    const auto h2 = first_hit(*scene, up);
    REQUIRE(h2);
    CHECK(h2->t == Approx(5 - std::sqrt(1 - 0.05)).epsilon(1e-12));
    CHECK(scene->geometry().surface(up, *h2).material == red);
}

TEST_CASE("CSG: a difference's cut surface shows the subtracting member's material, facing out", "[csg]") {
    auto spec = basic_scene(8, 8);
    const uint32_t red = add_material(spec, matte({1, 0, 0})),
                   steel = add_material(spec, matte({0.5, 0.5, 0.5})),
                   blue = add_material(spec, matte({0, 0, 1}));
    // Nested: the inner union inherits blue from the outer CSG; its second member has steel.
    spec.shapes.push_back(
        csg(CsgOp::Difference,
            {box({-1, -1, -1}, {1, 1, 1}, red),
             csg(CsgOp::Union, {inherit(sphere({0, 0, -1}, 0.5, 0)), sphere({0, 0, 1}, 0.5, steel)})},
            blue));
    auto scene = build(spec);
    const Ray front{{0, 0, -5}, {0, 0, 1}};
    const auto h = first_hit(*scene, front);
    REQUIRE(h);
    CHECK(h->t == Approx(4.5).epsilon(1e-12));
    const auto s = scene->geometry().surface(front, *h);
    CHECK(s.material == blue);
    CHECK(s.ng.z == Approx(-1.0));  // the dent's floor faces the viewer
    const Ray back{{0, 0, 5}, {0, 0, -1}};
    const auto hb = first_hit(*scene, back);
    REQUIRE(hb);
    CHECK(scene->geometry().surface(back, *hb).material == steel);
}

TEST_CASE("CSG: shadows through a glass member of an opaque solid", "[csg]") {
    auto spec = basic_scene(8, 8);
    const uint32_t floor_m = add_material(spec, matte({1, 1, 1}, 0)),
                   red = add_material(spec, matte({1, 0, 0}));
    auto clear = glass(1.0);
    clear.ambient = 0;
    const uint32_t g = add_material(spec, clear);
    spec.shapes.push_back(plane({0, 1, 0}, 0, floor_m));
    // Opaque box on the left, glass box on the right, one solid.
    spec.shapes.push_back(
        csg(CsgOp::Union, {box({-3, 1, -1}, {-1, 2, 1}, red), box({1, 1, -1}, {3, 2, 1}, g)}, red));
    // A point light, then a small area light (its shadow rays go through shafts).
    for (bool area : {false, true}) {
        spec.lights = {area ? area_light({0, 50, 0}, {0.2, 0, 0}, {0, 0, 0.2}, 4, 4)
                            : point_light({0, 50, 0})};
        RayProbe probe(spec);
        const Color under_opaque = probe.trace({-2, 0.5, -10}, glm::normalize(Vec3(0, -0.5, 10)));
        const Color under_glass = probe.trace({2, 0.5, -10}, glm::normalize(Vec3(0, -0.5, 10)));
        const Color open = probe.trace({0, 0.5, -10}, glm::normalize(Vec3(0, -0.5, 10)));
        CHECK(under_opaque.x == Approx(0.0).margin(1e-12));
        CHECK(open.x > 0.9);
        CHECK(under_glass.x == Approx(open.x).epsilon(1e-3));
    }
}

TEST_CASE("CSG: a closed mesh member works; an open one is an error naming its edge", "[csg]") {
    auto spec = basic_scene(8, 8);
    const uint32_t red = add_material(spec, matte({1, 0, 0}));
    ShapeSpec cube = mesh_shape(cube_mesh(true), red);
    cube.object_to_world = glm::translate(Mat4(1.0), Vec3(-0.5, -0.5, -0.5));
    spec.shapes.push_back(csg(CsgOp::Difference, {cube, sphere({0, 0, -0.5}, 0.25, red)}, red));
    {
        auto scene = build(spec);
        const auto h = first_hit(*scene, Ray{{0.3, 0.3, -5}, {0, 0, 1}});
        REQUIRE(h);
        CHECK(h->t == Approx(4.5).epsilon(1e-12));
        const auto hole = first_hit(*scene, Ray{{0, 0, -5}, {0, 0, 1}});
        REQUIRE(hole);
        CHECK(hole->t == Approx(4.75).epsilon(1e-12));
        // Through an edge and a vertex shared by several faces: entered once.
        const auto edge = first_hit(*scene, Ray{{0.5, 0.5, 5}, {0, 0, -1}});
        REQUIRE(edge);
        CHECK(edge->t == Approx(4.5).epsilon(1e-12));
        const auto diag = first_hit(*scene, Ray{{-0.4, -0.4, -0.4}, glm::normalize(Vec3(1, 1, 1))});
        REQUIRE(diag);
        CHECK(diag->t == Approx(std::sqrt(3.0) * 0.9).epsilon(1e-9));
    }
    auto open = cube_mesh(false);
    open->faces.pop_back();
    spec.shapes.back().csg = csg(CsgOp::Union, {mesh_shape(open, red)}).csg;
    std::vector<wsd::render::SpecError> errors;
    CHECK(!wsd::render::build_scene(spec, errors, true, 1));
    REQUIRE(errors.size() == 1);
    CHECK_THAT(errors[0].message, Catch::Contains("CSG member 1") && Catch::Contains("not closed"));
}

TEST_CASE("closed_mesh_problem: closed, open, inconsistently oriented, split at seams", "[csg]") {
    using wsd::render::closed_mesh_problem;
    CHECK(!closed_mesh_problem(*cube_mesh(false)));
    CHECK(!closed_mesh_problem(*cube_mesh(true)));
    CHECK(!closed_mesh_problem(*octahedron(1)));
    auto open = cube_mesh(false);
    open->faces.erase(open->faces.begin() + 3);
    auto p = closed_mesh_problem(*open);
    REQUIRE(p);
    CHECK_THAT(*p, Catch::Contains("belongs to no other face"));
    auto flipped = octahedron(1);
    std::swap(flipped->faces[2].y, flipped->faces[2].z);
    flipped->face_lines = {10, 11, 12, 13, 14, 15, 16, 17};
    flipped->source_name = "oct.obj";
    p = closed_mesh_problem(*flipped);
    REQUIRE(p);
    CHECK_THAT(*p, Catch::Contains("not consistently oriented") && Catch::Contains("oct.obj line"));
    auto fan = octahedron(1);
    fan->faces.push_back(fan->faces[0]);
    p = closed_mesh_problem(*fan);
    REQUIRE(p);
    CHECK_THAT(*p, Catch::Contains("shared by 3 faces"));
    // A seam written once as 0 and once as -0 (as OBJ writers print sin(2π)) is one position.
    auto signed_zero = octahedron(1);
    for (size_t i = 0; i < 2; ++i)  // two of the four faces at vertex 0 use the copy
        for (int k = 0; k < 3; ++k)
            if (signed_zero->faces[i][k] == 0) signed_zero->faces[i][k] = 6;
    signed_zero->vertices.push_back(signed_zero->vertices[0] * glm::vec3(1, -1, -1));
    REQUIRE(std::signbit(signed_zero->vertices.back().y));
    CHECK(!closed_mesh_problem(*signed_zero));
}

TEST_CASE("CSG: members that are not solids, and unbounded solids, are errors", "[csg]") {
    auto spec = basic_scene(8, 8);
    const uint32_t red = add_material(spec, matte({1, 0, 0}));
    spec.shapes.push_back(
        csg(CsgOp::Union, {sphere({0, 0, 0}, 1, red), triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, red)}, red));
    std::vector<wsd::render::SpecError> errors;
    CHECK(!wsd::render::build_scene(spec, errors, true, 1));
    REQUIRE(errors.size() == 1);
    CHECK(errors[0].message == "CSG member 2: 'triangle' is not a solid; CSG needs closed shapes");
    ShapeSpec tube;
    tube.kind = ShapeKind::Cylinder;
    tube.open = true;
    tube.material = red;
    spec.shapes.back() = csg(CsgOp::Difference, {sphere({0, 0, 0}, 1, red), tube}, red);
    errors.clear();
    CHECK(!wsd::render::build_scene(spec, errors, true, 1));
    REQUIRE(errors.size() == 1);
    CHECK(errors[0].message == "CSG member 2: an open cylinder is not a solid; CSG needs closed shapes");
    spec.shapes.back() = csg(CsgOp::Union, {sphere({0, 0, 0}, 1, red), plane({0, 1, 0}, 0, red)}, red);
    errors.clear();
    CHECK(!wsd::render::build_scene(spec, errors, true, 1));
    REQUIRE(errors.size() == 1);
    CHECK_THAT(errors[0].message, Catch::Contains("unbounded"));
}

TEST_CASE("CSG is an effect naming its solid, with its members' materials' effects", "[csg]") {
    auto spec = basic_scene(8, 8);
    const uint32_t red = add_material(spec, matte({1, 0, 0}));
    auto mirror = matte({1, 1, 1});
    mirror.reflection = 0.5;
    const uint32_t shiny = add_material(spec, mirror), g = add_material(spec, glass());
    spec.shapes.push_back(sphere({3, 0, 0}, 1, red));
    CHECK(!wsd::render::analyse_effects(spec).has(wsd::render::Effect::Csg));
    spec.shapes.push_back(csg(CsgOp::Union,
                              {sphere({0, 0, 0}, 1, g), csg(CsgOp::Union, {box({0, 0, 0}, {1, 1, 1}, shiny)}),
                               sphere({0, 1, 0}, 1, g)},
                              red));
    const auto fx = wsd::render::analyse_effects(spec);
    using wsd::render::Effect;
    REQUIRE(fx.has(Effect::Csg));
    CHECK(fx.shapes[size_t(Effect::Csg)] == std::vector<uint32_t>{1});
    CHECK(fx.shapes[size_t(Effect::Refraction)] == std::vector<uint32_t>{1});  // once, for two members
    CHECK(fx.shapes[size_t(Effect::Reflection)] == std::vector<uint32_t>{1});
    // The solid is walked by shadow rays as transmissive although its own material is not.
    CHECK(build(spec)->geometry().has_transmissive());
}

TEST_CASE("CSG: a box minus a cylinder has a round hole of the exact area; tori and cones as members",
          "[csg]") {
    auto spec = basic_scene(8, 8);
    const uint32_t red = add_material(spec, matte({1, 0, 0}));
    ShapeSpec drill;
    drill.kind = ShapeKind::Cylinder;
    drill.base = {0.1, -0.05, -2};
    drill.cap = {0.1, -0.05, 2};
    drill.radius = 0.4;
    drill.material = red;
    spec.shapes.push_back(csg(CsgOp::Difference, {box({-1, -1, -0.2}, {1, 1, 0.2}, red), drill}, red));
    auto scene = build(spec);
    const int n = 400;
    int holes = 0, wrong = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const Vec3 o(-1 + (i + 0.5) * 2.0 / n, -1 + (j + 0.5) * 2.0 / n, -5);
            const bool hole = !first_hit(*scene, Ray{o, {0, 0, 1}});
            holes += hole ? 1 : 0;
            const double r = std::hypot(o.x - 0.1, o.y + 0.05);
            if (std::abs(r - 0.4) > 1e-9 && hole != (r < 0.4)) ++wrong;
        }
    CHECK(wrong == 0);
    CHECK(holes * (2.0 / n) * (2.0 / n) == Approx(3.14159265358979323846 * 0.16).epsilon(0.005));

    // A torus around a cone, intersected with a half-space: first hits against classification.
    ShapeSpec ring;
    ring.kind = ShapeKind::Torus;
    ring.major = 0.8;
    ring.minor = 0.3;
    ring.object_to_world = glm::rotate(Mat4(1.0), 0.5, Vec3(1, 0, 0));
    ShapeSpec spike;
    spike.kind = ShapeKind::Cone;
    spike.base = {0, -1, 0};
    spike.cap = {0, 1, 0};
    spike.radius = 0.6;
    spike.cap_radius = 0.1;
    ShapeSpec solid =
        csg(CsgOp::Intersection,
            {csg(CsgOp::Union, {inherit(ring), inherit(spike)}), inherit(plane({0.2, 1, 0.1}, 0.5, 0))}, red);
    auto spec2 = basic_scene(8, 8);
    add_material(spec2, matte({1, 0, 0}));
    spec2.shapes.push_back(solid);
    auto scene2 = build(spec2);
    // Classification of the torus and the cone in their own frames.
    auto inside_ring = [&](const Vec3& p) {
        const Vec3 q = Vec3(glm::inverse(ring.object_to_world) * glm::dvec4(p, 1.0));
        const double a = std::hypot(q.x, q.z) - 0.8;
        return a * a + q.y * q.y < 0.09;
    };
    auto inside_spike = [&](const Vec3& p) {
        if (p.y <= -1 || p.y >= 1) return false;
        return std::hypot(p.x, p.z) < 0.6 + (p.y + 1) / 2 * (0.1 - 0.6);
    };
    auto classify = [&](const Vec3& p) {
        return (inside_ring(p) || inside_spike(p)) && glm::dot(glm::normalize(Vec3(0.2, 1, 0.1)), p) < 0.5;
    };
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.2, 1.2);
    int hits = 0, failures = 0;
    for (int k = 0; k < 3000; ++k) {
        const Vec3 o = unit(rng) * 4.0;
        const Vec3 d = glm::normalize(Vec3(u(rng), u(rng), u(rng)) - o);
        const auto hit = first_hit(*scene2, Ray{o, d});
        const double end = hit ? hit->t : 8.0;
        for (int s = 1; s < 64; ++s)
            if (classify(o + (end * s / 64.0) * d)) ++failures;
        if (!hit) continue;
        ++hits;
        if (classify(o + (hit->t - 1e-6) * d) || !classify(o + (hit->t + 1e-6) * d)) ++failures;
    }
    CHECK(hits > 500);
    CHECK(failures == 0);
}

TEST_CASE("CSG: packets of rays give the same hits as single rays", "[csg]") {
    auto spec = basic_scene(8, 8);
    const uint32_t red = add_material(spec, matte({1, 0, 0}));
    spec.shapes.push_back(
        csg(CsgOp::Difference, {box({-1, -1, -1}, {1, 1, 1}, red), sphere({0.3, 0.2, -1}, 0.7, red)}, red));
    spec.shapes.push_back(sphere({2, 0, 0}, 0.5, red));
    auto scene = build(spec);
    const auto& g = scene->geometry();
    Ray rays[16];
    std::optional<wsd::render::HitRecord> out[16];
    int compared = 0;
    for (int py = 0; py < 32; ++py)
        for (int px = 0; px < 32; px += 4) {
            for (int k = 0; k < 16; ++k)
                rays[k] =
                    Ray{{-3 + (px + k % 4) * 0.19, -3 + py * 0.19 + (k / 4) * 0.01, -6}, {0.1, 0.05, 1}};
            RayStats stats;
            g.intersect_packet(rays, 16, std::numeric_limits<double>::infinity(), stats, out);
            for (int k = 0; k < 16; ++k) {
                const auto single = first_hit(*scene, rays[k]);
                REQUIRE(bool(single) == bool(out[k]));
                if (!single) continue;
                CHECK(single->t == out[k]->t);
                CHECK(single->prim == out[k]->prim);
                CHECK(single->member == out[k]->member);
                ++compared;
            }
        }
    CHECK(compared > 100);
}

TEST_CASE("CSG surfaces give p_object in the CSG's own frame (textures and bumps follow the solid)",
          "[csg]") {
    auto spec = basic_scene(8, 8);
    const uint32_t red = add_material(spec, matte({1, 0, 0}));
    ShapeSpec ball = sphere({0, 0, 0}, 1, red);
    ball.object_to_world = glm::translate(Mat4(1.0), Vec3(1, 0, 0)) * glm::scale(Mat4(1.0), Vec3(2, 1, 1));
    ShapeSpec solid = csg(CsgOp::Union, {ball}, red);
    solid.object_to_world =
        glm::translate(Mat4(1.0), Vec3(5, 0, 0)) * glm::rotate(Mat4(1.0), 1.0, Vec3(0, 1, 0));
    spec.shapes.push_back(solid);
    auto scene = build(spec);
    const Ray ray{{5, 10, 0.1}, {0, -1, 0}};
    const auto h = first_hit(*scene, ray);
    REQUIRE(h);
    const auto s = scene->geometry().surface(ray, *h);
    const Vec3 expect = Vec3(glm::inverse(solid.object_to_world) * glm::dvec4(s.p, 1.0));
    CHECK(glm::length(s.p_object - expect) < 1e-12);
    CHECK(s.ng.y > 0.5);
}

TEST_CASE("CSG: an object instance of a solid is a member, its material inherited from the instance",
          "[csg]") {
    auto spec = basic_scene(8, 8);
    const uint32_t red = add_material(spec, matte({1, 0, 0})),
                   steel = add_material(spec, matte({0.5, 0.5, 0.5}));
    wsd::render::PrototypeSpec proto;
    proto.shapes.push_back(inherit(sphere({0, 0, 0}, 0.5, 0)));
    spec.prototypes.push_back(proto);
    ShapeSpec hole;
    hole.kind = ShapeKind::Instance;
    hole.prototype = 0;
    hole.material = steel;
    hole.object_to_world = glm::translate(Mat4(1.0), Vec3(0, 0, -1));
    spec.shapes.push_back(csg(CsgOp::Difference, {box({-1, -1, -1}, {1, 1, 1}, red), hole}, red));
    auto scene = build(spec);
    const Ray ray{{0, 0, -5}, {0, 0, 1}};
    const auto h = first_hit(*scene, ray);
    REQUIRE(h);
    CHECK(h->t == Approx(4.5).epsilon(1e-12));
    CHECK(scene->geometry().surface(ray, *h).material == steel);
}
