// Intersection and surface data of every shape kind: hit distances, normals, the UV layouts of
// wsd-language.md §4 at known points, transforms, ray filters, counters and build-time validation.
#include <bit>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "geometry_test_util.h"
#include "render/shapes.h"

using namespace wsd::render;
using namespace wsd::render::test;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Traced {
    HitRecord hit;
    SurfaceHit s;
};

std::optional<Traced> trace(const Geometry& g, Vec3 o, Vec3 d, double tmax = kInf,
                            RayFilter filter = RayFilter::All) {
    RayStats stats;
    Ray r{o, d};
    auto h = g.intersect(r, tmax, stats, filter);
    if (!h) return std::nullopt;
    return Traced{*h, g.surface(r, *h)};
}

void check_vec(const Vec3& a, const Vec3& b, double tol = 1e-12) {
    CHECK(a.x == Approx(b.x).margin(tol));
    CHECK(a.y == Approx(b.y).margin(tol));
    CHECK(a.z == Approx(b.z).margin(tol));
}

void check_uv(const Vec2& a, const Vec2& b, double tol = 1e-12) {
    CHECK(a.x == Approx(b.x).margin(tol));
    CHECK(a.y == Approx(b.y).margin(tol));
}

}  // namespace

TEST_CASE("sphere: hit distance, normal, inside hit and miss") {
    auto g = build_ok(scene_of({sphere({0, 0, 5}, 2)}));
    REQUIRE(g);
    auto h = trace(*g, {0, 0, 0}, {0, 0, 1});
    REQUIRE(h);
    CHECK(h->hit.t == Approx(3));
    check_vec(h->s.p, {0, 0, 3});
    check_vec(h->s.ng, {0, 0, -1});
    check_vec(h->s.ns, h->s.ng);
    check_vec(h->s.p_object, {0, 0, -2});
    CHECK(h->s.shape == 0);
    // Unnormalised direction: t is in units of d.
    auto h2 = trace(*g, {0, 0, 0}, {0, 0, 4});
    REQUIRE(h2);
    CHECK(h2->hit.t == Approx(0.75));
    // From inside: the exit.
    auto h3 = trace(*g, {0, 0, 5}, {1, 0, 0});
    REQUIRE(h3);
    CHECK(h3->hit.t == Approx(2));
    check_vec(h3->s.ng, {1, 0, 0});
    CHECK_FALSE(trace(*g, {0, 0, 0}, {0, 1, 0}));
    CHECK_FALSE(trace(*g, {0, 0, 0}, {0, 0, -1}));
    CHECK_FALSE(trace(*g, {0, 0, 0}, {0, 0, 1}, 2.9));
}

TEST_CASE("sphere: similarity and non-uniform transforms") {
    ShapeSpec s = sphere({1, 0, 0}, 1);
    s.object_to_world = translate({0, 0, 10}) * rotate_xyz({0, 90, 0}) * scale(Vec3(2));
    // Object centre (1,0,0) → scaled (2,0,0) → rotated about y by 90° → (0,0,-2) → (0,0,8).
    auto g = build_ok(scene_of({s}));
    REQUIRE(g);
    auto h = trace(*g, {0, 0, 0}, {0, 0, 1});
    REQUIRE(h);
    CHECK(h->hit.t == Approx(6));
    check_vec(h->s.ng, {0, 0, -1}, 1e-12);
    // p_object is in the sphere's own frame, relative to its centre, at the object radius 1:
    // the world offset (0,0,−2) maps back through R_y(90)ᵀ and the scale to (1,0,0).
    CHECK(glm::length(h->s.p_object) == Approx(1));
    check_vec(h->s.p_object, {1, 0, 0}, 1e-12);

    ShapeSpec e = sphere({0, 0, 0}, 1);
    e.object_to_world = translate({0, 0, 10}) * scale({3, 1, 0.5});  // an ellipsoid
    auto ge = build_ok(scene_of({e}));
    REQUIRE(ge);
    auto a = trace(*ge, {0, 0, 0}, {0, 0, 1});
    REQUIRE(a);
    CHECK(a->hit.t == Approx(9.5));
    check_vec(a->s.ng, {0, 0, -1}, 1e-12);
    auto b = trace(*ge, {-10, 0, 10}, {1, 0, 0});
    REQUIRE(b);
    CHECK(b->hit.t == Approx(7));
    check_vec(b->s.ng, {-1, 0, 0}, 1e-12);
    // An oblique hit: the normal is the inverse transpose of the object normal.
    Vec3 p_obj = glm::normalize(Vec3(1, 1, 1));
    Vec3 target = Vec3(10 * 0 + 3 * p_obj.x, p_obj.y, 10 + 0.5 * p_obj.z);
    auto c = trace(*ge, target + Vec3(0, 5, 0), {0, -1, 0});
    REQUIRE(c);
    Vec3 n_expected = glm::normalize(Vec3(p_obj.x / 3, p_obj.y, p_obj.z / 0.5));
    check_vec(c->s.ng, n_expected, 1e-9);
    check_vec(c->s.p, target, 1e-9);
}

TEST_CASE("sphere UV at the texture centre, the sides, the poles and the seam") {
    auto g = build_ok(scene_of({sphere({0, 0, 0}, 1)}));
    REQUIRE(g);
    auto uv_from = [&](Vec3 from) {
        auto h = trace(*g, from, -from);
        REQUIRE(h);
        return h->s.uv;
    };
    check_uv(uv_from({0, 0, -5}), {0.5, 0.5});  // centre faces −z
    check_uv(uv_from({5, 0, 0}), {0.75, 0.5});  // +x is to the right of the centre seen from −z
    check_uv(uv_from({-5, 0, 0}), {0.25, 0.5});
    Vec2 north = uv_from({0, 5, 0}), south = uv_from({0, -5, 0});
    CHECK(north.y == 0);  // north pole: top row; u is any column there, but a finite one
    CHECK(south.y == 1);
    CHECK((north.x >= 0 && north.x < 1 && south.x >= 0 && south.x < 1));
    Vec2 seam = uv_from({0, 0, 5});  // seam at +z: u wraps to 0, never 1
    CHECK(seam.x == 0);
    CHECK(seam.y == Approx(0.5));
    // Directly on the sphere map: ±0 on the seam, and a pole component rounded above 1.
    CHECK(sphere_uv({0.0, 0, 1}).x == 0);
    CHECK(sphere_uv({-0.0, 0, 1}).x == 0);
    Vec2 pole = sphere_uv({0, 1.0000001, 0});
    CHECK(std::isfinite(pole.x));
    CHECK(pole.y == 0);
    // Rotating the sphere rotates its texture: after rotate <0, 90, 0> the centre (object −z)
    // faces world −x (R_y(90)·(0,0,−1) = (−1,0,0)).
    ShapeSpec s = sphere({0, 0, 0}, 1);
    s.object_to_world = rotate_xyz({0, 90, 0});
    auto gr = build_ok(scene_of({s}));
    REQUIRE(gr);
    auto h = trace(*gr, {-5, 0, 0}, {1, 0, 0});
    REQUIRE(h);
    check_uv(h->s.uv, {0.5, 0.5}, 1e-12);
}

TEST_CASE("triangle: barycentrics, geometric normal, uvs and both sides") {
    ShapeSpec t = triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    auto g = build_ok(scene_of({t}));
    REQUIRE(g);
    auto h = trace(*g, {0.25, 0.5, -1}, {0, 0, 1});
    REQUIRE(h);
    CHECK(h->hit.t == Approx(1));
    CHECK(h->hit.b1 == Approx(0.25));
    CHECK(h->hit.b2 == Approx(0.5));
    check_vec(h->s.p, {0.25, 0.5, 0});
    check_vec(h->s.ng, {0, 0, 1});   // normalize(cross(v1 − v0, v2 − v0))
    check_uv(h->s.uv, {0.25, 0.5});  // no uvs: (b1, b2)
    auto back = trace(*g, {0.25, 0.25, 1}, {0, 0, -1});
    REQUIRE(back);
    check_vec(back->s.ng, {0, 0, 1});  // ng does not turn toward the ray
    CHECK_FALSE(trace(*g, {0.75, 0.75, -1}, {0, 0, 1}));

    t.tri_uv = std::array<Vec2, 3>{Vec2(0.5, 0.5), Vec2(1, 0.5), Vec2(0.5, 1)};
    auto gu = build_ok(scene_of({t}));
    REQUIRE(gu);
    auto hu = trace(*gu, {0.25, 0.5, -1}, {0, 0, 1});
    REQUIRE(hu);
    check_uv(hu->s.uv, {0.5 + 0.25 * 0.5, 0.5 + 0.5 * 0.5});

    // A mirroring transform keeps the normal outward (it follows the object's normal).
    ShapeSpec m = triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    m.object_to_world = scale({-1, 1, 1});
    auto gm = build_ok(scene_of({m}));
    REQUIRE(gm);
    auto hm = trace(*gm, {-0.25, 0.25, -1}, {0, 0, 1});
    REQUIRE(hm);
    check_vec(hm->s.ng, {0, 0, 1});
    check_vec(hm->s.p_object, {0.25, 0.25, 0});
}

TEST_CASE("mesh: face ids, smooth normals kept on the geometric side, per-vertex uvs") {
    auto m = std::make_shared<MeshData>();
    m->vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    m->faces = {{0, 1, 2}, {0, 2, 3}};
    m->uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    m->normals = {{0, 0, 1}, {1, 0, 1}, {0, 0, 1}, {0, 0, -1}};  // the last one flipped
    auto g = build_ok(scene_of({sphere({5, 5, 5}, 1), mesh(m)}));
    REQUIRE(g);
    CHECK(g->triangle_count() == 2);
    CHECK(g->primitive_count() == 3);
    auto h = trace(*g, {0.75, 0.25, -1}, {0, 0, 1});
    REQUIRE(h);
    CHECK(h->s.shape == 1);
    CHECK(h->hit.prim == 1);  // canonical ids: the sphere is 0, face 0 is 1
    check_uv(h->s.uv, {0.75, 0.25});
    check_vec(h->s.ng, {0, 0, 1});
    // Interpolated: b0 = 0.25 at v0, b1 = 0.5 at v1, b2 = 0.25 at v2.
    Vec3 n = glm::normalize(0.25 * Vec3(0, 0, 1) + 0.5 * Vec3(1, 0, 1) + 0.25 * Vec3(0, 0, 1));
    check_vec(h->s.ns, n, 1e-7);
    // Near the vertex with the flipped normal the interpolation points below: turned back.
    auto f = trace(*g, {0.02, 0.95, -1}, {0, 0, 1});
    REQUIRE(f);
    CHECK(f->hit.prim == 2);
    CHECK(glm::dot(f->s.ns, f->s.ng) > 0);
    CHECK(glm::length(f->s.ns) == Approx(1));
}

TEST_CASE("mesh: vertex normals all on the other side of the winding are turned, not mirrored") {
    // Faces wound so that the geometric normal is +z, every vertex normal leaning towards -z: the
    // same smooth surface seen from -z. The shading normal is the interpolated one negated (turned
    // to the geometric side), not its mirror image about the facet, which would swap the tilt.
    auto m = std::make_shared<MeshData>();
    m->vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m->faces = {{0, 1, 2}};
    m->normals = {{-0.5, -0.5, -1}, {0.5, -0.5, -1}, {0, 0.5, -1}};
    auto g = build_ok(scene_of({mesh(m)}));
    REQUIRE(g);
    auto h = trace(*g, {0.25, 0.25, -1}, {0, 0, 1});
    REQUIRE(h);
    check_vec(h->s.ng, {0, 0, 1});
    // b0 = 0.5, b1 = 0.25, b2 = 0.25.
    const Vec3 n =
        glm::normalize(0.5 * Vec3(-0.5, -0.5, -1) + 0.25 * Vec3(0.5, -0.5, -1) + 0.25 * Vec3(0, 0.5, -1));
    check_vec(h->s.ns, -n, 1e-7);
}

TEST_CASE("box: faces, normals and the unfolded-cube UV at face centres and corners") {
    auto g = build_ok(scene_of({box({-1, -2, -3}, {1, 2, 3})}));
    REQUIRE(g);
    struct Case {
        Vec3 from, n;
        Vec2 centre_uv;
    };
    const Case cases[] = {
        {{0, 0, -10}, {0, 0, -1}, {1.5 / 4, 1.5 / 3}}, {{10, 0, 0}, {1, 0, 0}, {2.5 / 4, 1.5 / 3}},
        {{0, 0, 10}, {0, 0, 1}, {3.5 / 4, 1.5 / 3}},   {{-10, 0, 0}, {-1, 0, 0}, {0.5 / 4, 1.5 / 3}},
        {{0, 10, 0}, {0, 1, 0}, {1.5 / 4, 0.5 / 3}},   {{0, -10, 0}, {0, -1, 0}, {1.5 / 4, 2.5 / 3}},
    };
    for (const Case& c : cases) {
        auto h = trace(*g, c.from, -c.from);
        REQUIRE(h);
        check_vec(h->s.ng, c.n);
        check_uv(h->s.uv, c.centre_uv);
    }
    // Upright seen from outside: the top-left corner of −z is (lo.x, hi.y); of +x it is
    // (hi.x, ·, lo.z); of +y (above −z) it is (lo.x, ·, hi.z).
    auto near_corner = [&](Vec3 p, Vec3 d) {
        auto h = trace(*g, p - d, d);
        REQUIRE(h);
        return h->s.uv;
    };
    check_uv(near_corner({-0.98, 1.98, -3}, {0, 0, 1}), {0.25, 1.0 / 3}, 0.01);
    check_uv(near_corner({1, 1.98, -2.98}, {-1, 0, 0}), {0.5, 1.0 / 3}, 0.01);
    check_uv(near_corner({-0.98, 2, 2.98}, {0, -1, 0}), {0.25, 0.0}, 0.01);
    check_uv(near_corner({-0.98, -2, -2.98}, {0, 1, 0}), {0.25, 2.0 / 3}, 0.01);
    check_uv(near_corner({-1, 1.98, 2.98}, {1, 0, 0}), {0.0, 1.0 / 3}, 0.01);
    check_uv(near_corner({0.98, 1.98, 3}, {0, 0, -1}), {0.75, 1.0 / 3}, 0.01);
    // From inside: the exit face, normal still outward.
    auto in = trace(*g, {0, 0, 0}, {0, 0, 1});
    REQUIRE(in);
    CHECK(in->hit.t == Approx(3));
    check_vec(in->s.ng, {0, 0, 1});
}

TEST_CASE("box under rotation: the dice on its corner") {
    ShapeSpec b = box(Vec3(-125), Vec3(125));
    b.object_to_world = translate({-400, -350, 990}) * rotate_xyz({35.264, 0, 0}) * rotate_xyz({0, 0, 45});
    auto g = build_ok(scene_of({b}));
    REQUIRE(g);
    // The lowest corner is at (−400, −566.51, 990): a ray straight up just beside it hits.
    auto h = trace(*g, {-400, -700, 990}, {0, 1, 0});
    REQUIRE(h);
    CHECK(h->s.p.y == Approx(-566.51).margin(0.05));
    CHECK(glm::length(h->s.ng) == Approx(1));
    CHECK(h->s.uv.x >= 0);
    CHECK(h->s.uv.x <= 1);
    CHECK(h->s.uv.y >= 0);
    CHECK(h->s.uv.y <= 1);
    CHECK_FALSE(trace(*g, {-200, -700, 990}, {0, 1, 0}));  // x beyond the cube's −223.2
}

TEST_CASE("plane: hits from both sides, parallel rays, plane axes and wrapping uv") {
    ShapeSpec p = plane({0, 2, 0}, 1);  // normal normalised by the builder: y = 1
    p.uv_scale = 4;
    auto g = build_ok(scene_of({p}));
    REQUIRE(g);
    auto h = trace(*g, {3, 5, -6}, {0, -1, 0});
    REQUIRE(h);
    CHECK(h->hit.t == Approx(4));
    check_vec(h->s.ng, {0, 1, 0});
    CHECK(h->s.planar);
    // u = +x, v = cross(n, u) = −z.
    check_uv(h->s.plane_xy, {3, 6});
    check_uv(h->s.uv, {0.75, 1.5});
    auto below = trace(*g, {0, -5, 0}, {0, 1, 0});
    REQUIRE(below);
    check_vec(below->s.ng, {0, 1, 0});
    CHECK_FALSE(trace(*g, {0, 5, 0}, {1, 0, 0}));
    CHECK_FALSE(trace(*g, {0, 1, 0}, {1, 0, 0}));  // in the plane and parallel to it
    // Normal along x: the projection of +x vanishes, so u = +z and v = cross(x, z) = −y.
    auto gx = build_ok(scene_of({plane({1, 0, 0}, 0)}));
    REQUIRE(gx);
    auto hx = trace(*gx, {5, 2, 3}, {-1, 0, 0});
    REQUIRE(hx);
    check_uv(hx->s.plane_xy, {3, -2});
    // Transformed: translated up by 5, its object frame moves with it.
    ShapeSpec t = plane({0, 1, 0}, 0);
    t.object_to_world = translate({0, 5, 0});
    auto gt = build_ok(scene_of({t}));
    REQUIRE(gt);
    auto ht = trace(*gt, {1, 10, 2}, {0, -1, 0});
    REQUIRE(ht);
    CHECK(ht->hit.t == Approx(5));
    check_vec(ht->s.p_object, {1, 0, 2});
    CHECK(plane_u_axis(glm::normalize(Vec3(1, 1e-30, 0))).x >= 0);
}

TEST_CASE("valid hits are 0 < t < tmax") {
    auto g = build_ok(scene_of({plane({0, 1, 0}, 0)}));
    REQUIRE(g);
    CHECK_FALSE(trace(*g, {0, 1, 0}, {0, -1, 0}, 1.0));
    CHECK(trace(*g, {0, 1, 0}, {0, -1, 0}, next_float_up(1.0)));
    RayStats stats;
    CHECK_FALSE(g->occluded({{0, 1, 0}, {0, -1, 0}}, 1.0, stats));
    CHECK(g->occluded({{0, 1, 0}, {0, -1, 0}}, next_float_up(1.0), stats));
    CHECK_FALSE(trace(*g, {0, 1, 0}, {0, -1, 0}, 0.0));
    CHECK_FALSE(trace(*g, {0, 1, 0}, {0, -1, 0}, -1.0));
}

TEST_CASE("ray filters: transmissive primitives for shadow rays") {
    // A glass sphere (material 1) in front of an opaque one, and a glass plane behind both.
    auto g =
        build_ok(scene_of({sphere({0, 0, 5}, 1, 1), sphere({0, 0, 10}, 1, 0), plane({0, 0, -1}, -20, 1)}));
    REQUIRE(g);
    CHECK(g->has_transmissive());
    auto all = trace(*g, {0, 0, 0}, {0, 0, 1});
    REQUIRE(all);
    CHECK(all->s.shape == 0);
    auto opaque = trace(*g, {0, 0, 0}, {0, 0, 1}, kInf, RayFilter::OpaqueOnly);
    REQUIRE(opaque);
    CHECK(opaque->s.shape == 1);
    auto glass = trace(*g, {0, 0, 12}, {0, 0, 1}, kInf, RayFilter::TransmissiveOnly);
    REQUIRE(glass);
    CHECK(glass->s.shape == 2);
    RayStats stats;
    CHECK(g->occluded({{0, 0, 0}, {0, 0, 1}}, 7, stats, RayFilter::TransmissiveOnly));
    CHECK_FALSE(g->occluded({{0, 0, 0}, {0, 0, 1}}, 7, stats, RayFilter::OpaqueOnly));
    CHECK(g->occluded({{0, 0, 0}, {0, 0, 1}}, 7, stats, RayFilter::All));
    // Without transmissive materials, TransmissiveOnly sees nothing and OpaqueOnly everything.
    auto o = build_ok(scene_of({sphere({0, 0, 5}, 1)}));
    REQUIRE(o);
    CHECK_FALSE(o->has_transmissive());
    CHECK_FALSE(trace(*o, {0, 0, 0}, {0, 0, 1}, kInf, RayFilter::TransmissiveOnly));
    CHECK(trace(*o, {0, 0, 0}, {0, 0, 1}, kInf, RayFilter::OpaqueOnly));
}

TEST_CASE("counters count tests per kind") {
    auto g = build_ok(scene_of({sphere({0, 0, 5}, 1), triangle({-1, -1, 8}, {1, -1, 8}, {0, 1, 8}),
                                box({-1, -1, 11}, {1, 1, 12}), plane({0, 0, -1}, -20)}));
    REQUIRE(g);
    RayStats stats;
    CHECK(g->intersect({{0, 0, 0}, {0, 0, 1}}, kInf, stats));
    CHECK(stats.plane_tests == 1);
    CHECK(stats.sphere_tests >= 1);
    CHECK(stats.sphere_hits == 1);
    CHECK(stats.box_tests > 0);
    RayStats s2;
    CHECK_FALSE(g->occluded({{0, 0, 0}, {0, 1, 0}}, kInf, s2));
    CHECK(s2.plane_tests == 1);
    RayStats s3;
    auto bf = build_ok(scene_of({sphere({0, 0, 5}, 1), triangle({-1, -1, 8}, {1, -1, 8}, {0, 1, 8}),
                                 box({-1, -1, 11}, {1, 1, 12})}),
                       false);
    REQUIRE(bf);
    CHECK(bf->intersect({{0, 0, 0}, {0, 0, 1}}, kInf, s3));
    // Brute force tests everything once; the triangle lies beyond the sphere's hit, so it is
    // tested but not counted as a hit.
    CHECK(s3.sphere_tests == 1);
    CHECK(s3.triangle_tests == 1);
    CHECK(s3.triangle_hits == 0);
    CHECK(s3.shape_box_tests == 1);
    CHECK(s3.box_tests == 0);
}

TEST_CASE("invalid input gives errors naming the element, never a geometry") {
    auto errors_of = [](std::vector<ShapeSpec> shapes) {
        std::vector<SpecError> errors;
        auto g = Geometry::build(scene_of(std::move(shapes)), errors);
        CHECK_FALSE(g);
        return errors;
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    CHECK(errors_of({sphere({0, 0, 0}, 0)}).size() == 1);
    CHECK(errors_of({sphere({0, 0, 0}, -1)}).size() == 1);
    CHECK(errors_of({sphere({0, 0, 0}, nan)}).size() == 1);
    CHECK(errors_of({sphere({nan, 0, 0}, 1)}).size() == 1);
    CHECK(errors_of({box({0, 0, 0}, {1, -1, 1})}).size() == 1);
    CHECK(errors_of({box({0, 0, 0}, {1, 0, 1})}).size() == 1);  // flat
    CHECK(errors_of({plane({0, 0, 0}, 1)}).size() == 1);
    CHECK(errors_of({triangle({0, 0, 0}, {1, 1, 1}, {2, 2, 2})}).size() == 1);
    CHECK(errors_of({triangle({0, 0, 0}, {0, 0, 0}, {0, 1, 0})}).size() == 1);
    ShapeSpec singular = sphere({0, 0, 0}, 1);
    singular.object_to_world = scale({1, 0, 1});
    CHECK(errors_of({singular}).size() == 1);
    ShapeSpec nan_matrix = sphere({0, 0, 0}, 1);
    nan_matrix.object_to_world[3][0] = nan;
    CHECK(errors_of({nan_matrix}).size() == 1);
    ShapeSpec bad_material = sphere({0, 0, 0}, 1, 7);
    CHECK(errors_of({bad_material}).size() == 1);

    // Errors carry the shape's index and tag; mesh errors also the face and its source line.
    auto m = std::make_shared<MeshData>();
    m->vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}};
    m->faces = {{0, 1, 2}, {0, 1, 3}, {0, 1, 9}};
    m->face_lines = {10, 11, 12};
    m->source_name = "m.obj";
    ShapeSpec ms = mesh(m);
    ms.tag = 42;
    auto errors = errors_of({sphere({0, 0, 0}, 1), ms});
    REQUIRE(errors.size() == 2);
    CHECK(errors[0].index == 1);
    CHECK(errors[0].tag == 42);
    CHECK(errors[0].face == 1);
    CHECK(errors[0].message.find("m.obj line 11") != std::string::npos);
    CHECK(errors[1].face == 2);
    CHECK(errors[1].message.find("out of range") != std::string::npos);
    // Per-vertex attributes must match the vertex count.
    auto w = std::make_shared<MeshData>(*m);
    w->faces = {{0, 1, 2}};
    w->normals = {{0, 0, 1}};
    CHECK(errors_of({mesh(w)}).size() == 1);
}

TEST_CASE("doubles round to the float at or below and at or above them") {
    // The float nearest below (above) v, or v itself, by the definition: what nextafter gives.
    auto down = [](double v) {
        float f = static_cast<float>(v);
        return static_cast<double>(f) > v ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
    };
    auto up = [](double v) {
        float f = static_cast<float>(v);
        return static_cast<double>(f) < v ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
    };
    const double big = std::numeric_limits<float>::max(), tiny = std::numeric_limits<float>::denorm_min();
    std::vector<double> vs = {
        0.0,   -0.0,   1.0,        -1.0,        0.1,       -0.1,      1e-50,           -1e-50,
        tiny,  -tiny,  tiny * 0.5, -tiny * 0.5, big,       -big,      big * 1.0000001, -big * 1.0000001,
        1e300, -1e300, kInf,       -kInf,       3.0000001, -3.0000001};
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 20000; ++i) vs.push_back(std::ldexp(u(rng), static_cast<int>(rng() % 300) - 150));
    for (double v : vs) {
        INFO(v);
        CHECK(std::bit_cast<uint32_t>(to_float_down(v)) == std::bit_cast<uint32_t>(down(v)));
        CHECK(std::bit_cast<uint32_t>(to_float_up(v)) == std::bit_cast<uint32_t>(up(v)));
    }
    CHECK(std::isnan(to_float_down(std::nan(""))));
    CHECK(std::isnan(to_float_up(std::nan(""))));
}
