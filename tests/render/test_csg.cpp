// CSG solids (union, intersection, difference) against closed forms and brute-force point
// classification; the coincident-surface rule (docs/robustness.md's hard-case catalogue); glass
// CSG as one solid; closed-mesh validation.
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <random>

#include "render/effects.h"
#include "render/mesh_topology.h"
#include "tests/render/scene_builders.h"

using namespace wsd::test;
using wsd::render::CsgOp;
using wsd::render::CsgSpec;
using wsd::render::kInheritMaterial;
using wsd::render::Mat4;
using wsd::render::MeshData;
using wsd::render::Ray;
using wsd::render::RayStats;
using wsd::render::ShapeKind;
using wsd::render::ShapeSpec;

namespace {

ShapeSpec csg(CsgOp op, std::vector<ShapeSpec> members, uint32_t material = kInheritMaterial) {
    auto c = std::make_shared<CsgSpec>();
    c->op = op;
    c->members = std::move(members);
    ShapeSpec s;
    s.kind = ShapeKind::Csg;
    s.csg = c;
    s.material = material;
    return s;
}

ShapeSpec inherit(ShapeSpec s) {
    s.material = kInheritMaterial;
    return s;
}

// A regular octahedron |x| + |y| + |z| ≤ size, faces wound outward.
std::shared_ptr<MeshData> octahedron(double size) {
    auto m = std::make_shared<MeshData>();
    const float f = static_cast<float>(size);
    m->vertices = {{f, 0, 0}, {-f, 0, 0}, {0, f, 0}, {0, -f, 0}, {0, 0, f}, {0, 0, -f}};
    for (int sx : {1, -1})
        for (int sy : {1, -1})
            for (int sz : {1, -1}) {
                glm::uvec3 face(sx > 0 ? 0 : 1, sy > 0 ? 2 : 3, sz > 0 ? 4 : 5);
                if (sx * sy * sz < 0) std::swap(face.y, face.z);
                m->faces.push_back(face);
            }
    return m;
}

ShapeSpec mesh_shape(std::shared_ptr<MeshData> m, uint32_t material) {
    ShapeSpec s;
    s.kind = ShapeKind::Mesh;
    s.mesh = std::move(m);
    s.material = material;
    return s;
}

// A closed unit cube [0,1]³ as 12 triangles; `split` gives each face its own four vertices.
std::shared_ptr<MeshData> cube_mesh(bool split) {
    auto m = std::make_shared<MeshData>();
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    auto corner = [](int i) { return glm::vec3(float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)); };
    if (!split)
        for (int i = 0; i < 8; ++i) m->vertices.push_back(corner(i));
    for (const auto& q : quads) {
        uint32_t v[4];
        for (int k = 0; k < 4; ++k) {
            if (split) {
                v[k] = uint32_t(m->vertices.size());
                m->vertices.push_back(corner(q[k]));
            } else {
                v[k] = uint32_t(q[k]);
            }
        }
        m->faces.push_back({v[0], v[1], v[2]});
        m->faces.push_back({v[0], v[2], v[3]});
    }
    return m;
}

// Point classification straight from the spec: each member's implicit inside test in its frame.
bool inside(const ShapeSpec& s, const Mat4& parent, const Vec3& p) {
    const Mat4 m = parent * s.object_to_world;
    const Vec3 q = Vec3(glm::inverse(m) * glm::dvec4(p, 1.0));
    switch (s.kind) {
        case ShapeKind::Sphere:
            return glm::dot(q - s.center, q - s.center) < s.radius * s.radius;
        case ShapeKind::Box:
            return glm::all(glm::greaterThan(q, s.box_min)) && glm::all(glm::lessThan(q, s.box_max));
        case ShapeKind::Plane:
            return glm::dot(glm::normalize(s.normal), q) < s.distance;
        case ShapeKind::Mesh:  // the octahedra of these tests
            return std::abs(q.x) + std::abs(q.y) + std::abs(q.z) < s.mesh->vertices[0].x;
        case ShapeKind::Csg: {
            const auto& ms = s.csg->members;
            switch (s.csg->op) {
                case CsgOp::Union:
                    for (const auto& c : ms)
                        if (inside(c, m, p)) return true;
                    return false;
                case CsgOp::Intersection:
                    for (const auto& c : ms)
                        if (!inside(c, m, p)) return false;
                    return true;
                case CsgOp::Difference:
                    if (!inside(ms[0], m, p)) return false;
                    for (size_t i = 1; i < ms.size(); ++i)
                        if (inside(ms[i], m, p)) return false;
                    return true;
            }
            return false;
        }
        default:
            return false;
    }
}

std::optional<wsd::render::HitRecord> first_hit(const wsd::render::Scene& scene, const Ray& ray) {
    RayStats stats;
    return scene.geometry().intersect(ray, std::numeric_limits<double>::infinity(), stats);
}

Vec3 unit(std::mt19937& rng) {
    std::normal_distribution<double> n;
    return glm::normalize(Vec3(n(rng), n(rng), n(rng)));
}

Mat4 placed(Vec3 axis, double degrees, Vec3 translate) {
    return glm::translate(Mat4(1.0), translate) *
           glm::rotate(Mat4(1.0), glm::radians(degrees), glm::normalize(axis));
}

}  // namespace

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

TEST_CASE("R74: rays spawned from a convex CSG never re-hit it, 2^-10 to 2^10 and 10^5 away",
          "[csg][robust]") {
    // A lens (the intersection of two spheres) and a rotated box minus a half-space are convex:
    // a ray leaving the surface outward cannot meet them again, and one entering must leave.
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
            spec.shapes = {lens, wedge};
            auto scene = build(spec);
            std::mt19937 rng(17);
            for (int k = 0; k < 4000; ++k) {
                const Vec3 aim = Vec3(k % 2 ? 4 : 0, 0, 0) + unit(rng) * 0.3;
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
