// Instances (a two-level BVH): an instance renders bit-identically to the same shapes written out
// flat with object_to_world = instance · member, through every query (closest hit, shadows,
// shafts, packets, ray filters); material inheritance; counts; the hard cases of the catalogue
// (scale 2^±10, translation 10^5, 10^6 instances).
#include <catch2/catch.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "render/cpu_features.h"
#include "render/effects.h"
#include "render/geometry.h"
#include "tests/render/scene_builders.h"

using namespace wsd::test;
using wsd::render::Geometry;
using wsd::render::kInheritMaterial;
using wsd::render::Mat4;
using wsd::render::MeshData;
using wsd::render::PrototypeSpec;
using wsd::render::Ray;
using wsd::render::RayFilter;
using wsd::render::RayStats;
using wsd::render::SceneSpec;
using wsd::render::ShapeKind;
using wsd::render::ShapeSpec;
using wsd::render::SpecError;

namespace {

// A bumpy sheet: an n×n grid of quads with normals and uvs, curved so that its triangles are
// not coplanar.
std::shared_ptr<const MeshData> sheet(int n) {
    auto m = std::make_shared<MeshData>();
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const float u = float(i) / float(n), v = float(j) / float(n);
            const float x = u - 0.5f, z = v - 0.5f;
            m->vertices.push_back({x, 0.3f * std::sin(5.0f * x) * std::cos(4.0f * z), z});
            m->normals.push_back(glm::normalize(glm::vec3(-0.2f * x, 1.0f, 0.3f * z)));
            m->uvs.push_back({u, v});
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const unsigned a = unsigned(j * (n + 1) + i), b = a + 1, c = a + unsigned(n + 1), d = c + 1;
            m->faces.push_back({a, c, b});
            m->faces.push_back({b, c, d});
        }
    return m;
}

ShapeSpec mesh_shape(std::shared_ptr<const MeshData> m, uint32_t material, Mat4 x = Mat4(1.0)) {
    ShapeSpec s;
    s.kind = ShapeKind::Mesh;
    s.mesh = std::move(m);
    s.material = material;
    s.object_to_world = x;
    return s;
}

ShapeSpec instance(uint32_t prototype, const Mat4& x, uint32_t material) {
    ShapeSpec s;
    s.kind = ShapeKind::Instance;
    s.prototype = prototype;
    s.object_to_world = x;
    s.material = material;
    return s;
}

Mat4 rot_scale(double degrees, Vec3 axis, Vec3 scale, Vec3 t) {
    return glm::translate(Mat4(1.0), t) * glm::rotate(Mat4(1.0), glm::radians(degrees), axis) *
           glm::scale(Mat4(1.0), scale);
}

// The same scene with every instance written out flat: its members in place of it, in order.
SceneSpec flattened(const SceneSpec& spec) {
    SceneSpec flat = spec;
    flat.prototypes.clear();
    flat.shapes.clear();
    for (const ShapeSpec& s : spec.shapes) {
        if (s.kind != ShapeKind::Instance) {
            flat.shapes.push_back(s);
            continue;
        }
        for (ShapeSpec m : spec.prototypes[s.prototype].shapes) {
            m.object_to_world = s.object_to_world * m.object_to_world;
            if (m.material == kInheritMaterial) m.material = s.material;
            flat.shapes.push_back(m);
        }
    }
    return flat;
}

// Camera, lights (a point light and an area light: shafts), a mirror floor, and materials:
// 0 matte checker, 1 mirror, 2 glass, 3 red, 4 blue, 5 specular, 6 bumped.
SceneSpec stage(int w = 64, int h = 48) {
    SceneSpec spec = basic_scene(w, h, {0.5, 2.5, -6}, 45);
    spec.camera.look_at = {0, 0.3, 0};
    spec.lights.push_back(point_light({4, 6, -3}, 0.7));
    spec.lights.push_back(
        area_light({-3, 5, -2}, {1, 0, 0}, {0, 0, 1}, 3, 3, wsd::render::LightSampling::Jittered, 0.6));
    auto checker = matte(Color(1));
    checker.texture = wsd::render::TextureSpec{};
    checker.texture->checker_scale = 0.25;
    checker.texture->color1 = Color(0.9, 0.8, 0.2);
    checker.texture->color2 = Color(0.1, 0.3, 0.8);
    add_material(spec, checker);
    auto mirror = matte(Color(0.8));
    mirror.reflection = 0.5;
    add_material(spec, mirror);
    add_material(spec, glass(1.5, Color(1), Color(0.3, 0.1, 0.05)));
    add_material(spec, matte(Color(0.9, 0.2, 0.2)));
    add_material(spec, matte(Color(0.2, 0.3, 0.9)));
    auto shiny = matte(Color(0.7, 0.7, 0.6));
    shiny.specular = 0.6;
    shiny.shininess = 30;
    add_material(spec, shiny);
    auto bumpy = matte(Color(0.6, 0.8, 0.5));
    bumpy.bump = wsd::render::TextureSpec{};
    bumpy.bump->kind = wsd::render::TextureKind::Perlin;
    bumpy.bump->perlin_scale = Vec3(8);
    bumpy.bump_strength = 0.8;
    add_material(spec, bumpy);
    spec.shapes.push_back(plane({0, 1, 0}, -1, 1));
    return spec;
}

// Every kind the instances test exactly: a mesh with normals and uvs, a lone triangle with uvs,
// spheres (one stretched: the non-similarity path), a rotated, bumped box; some members inherit.
PrototypeSpec mixed_prototype() {
    PrototypeSpec p;
    p.shapes.push_back(mesh_shape(sheet(12), 0, rot_scale(10, {1, 0, 0}, Vec3(1.2), {0, 0.1, 0})));
    ShapeSpec tri = triangle({-0.6, 0, 0.4}, {0.1, 0.9, 0.5}, {0.6, 0.05, 0.3}, kInheritMaterial);
    tri.tri_uv = std::array<Vec2, 3>{Vec2(0, 0), Vec2(1, 0), Vec2(0.5, 1)};
    p.shapes.push_back(tri);
    p.shapes.push_back(sphere({0.3, 0.35, -0.2}, 0.25, 5));
    ShapeSpec egg = sphere({0, 0, 0}, 0.2, kInheritMaterial);
    egg.object_to_world = rot_scale(30, {0, 0, 1}, {1, 1.6, 0.8}, {-0.35, 0.3, -0.25});
    p.shapes.push_back(egg);
    ShapeSpec b = box({-0.15, -0.1, -0.15}, {0.15, 0.2, 0.15}, 6);
    b.object_to_world = rot_scale(25, {0, 1, 0}, Vec3(1), {0.35, 0.0, 0.35});
    p.shapes.push_back(b);
    return p;
}

void require_identical(const SceneSpec& a, const SceneSpec& b) {
    const auto ra = render_spec(a), rb = render_spec(b);
    REQUIRE(ra.film.rgb.size() == rb.film.rgb.size());
    size_t differ = 0;
    for (size_t i = 0; i < ra.film.rgb.size(); ++i) differ += ra.film.rgb[i] != rb.film.rgb[i] ? 1 : 0;
    INFO(differ << " of " << ra.film.rgb.size() << " channels differ");
    CHECK(differ == 0);
}

size_t lit_pixels(const wsd::render::Film& film) {
    size_t n = 0;
    for (int y = 0; y < film.height; ++y)
        for (int x = 0; x < film.width; ++x) n += pixel(film, x, y) != Color(0) ? 1 : 0;
    return n;
}

}  // namespace

TEST_CASE("instances render bit-identical to the same shapes written out flat") {
    SceneSpec spec = stage();
    spec.prototypes.push_back(mixed_prototype());
    spec.shapes.push_back(sphere({2.2, 0, 1}, 0.5, 4));
    SECTION("integer translations") {
        spec.shapes.push_back(instance(0, glm::translate(Mat4(1.0), Vec3(-1, 0, 0)), 3));
        spec.shapes.push_back(instance(0, glm::translate(Mat4(1.0), Vec3(1, 0, 1)), 4));
        spec.shapes.push_back(instance(0, glm::translate(Mat4(1.0), Vec3(0, -1, 2)), 3));
    }
    SECTION("rotations, scales, a stretch and a mirror") {
        spec.shapes.push_back(instance(0, rot_scale(37, {0.3, 1, 0.2}, Vec3(1.7), {-1.2, 0.1, 0.3}), 3));
        spec.shapes.push_back(instance(0, rot_scale(-70, {0, 1, 0}, {1.3, 0.7, 1.1}, {1.1, -0.2, 0.8}), 4));
        spec.shapes.push_back(instance(0, rot_scale(15, {1, 0, 0}, {-1, 1, 1}, {0.1, 0.2, 2.5}), 3));
    }
    spec.shapes.push_back(box({-3, -1, 3}, {-2, 0.5, 3.5}, 5));
    require_identical(spec, flattened(spec));
    // The walks' baseline tests where the default is AVX (render/cpu_features.h): the same image.
    const bool avx = wsd::render::avx_walk();
    wsd::render::set_avx_walk(!avx);
    const auto other = render_spec(spec);
    wsd::render::set_avx_walk(avx);
    CHECK(other.film.rgb == render_spec(spec).film.rgb);
    // Without the top-level BVH (every entry tested): the same image again.
    std::vector<SpecError> errors;
    const auto brute = wsd::render::build_scene(spec, errors, false, 1);
    REQUIRE(brute);
    wsd::render::RenderOptions options;
    options.threads = 2;
    CHECK(wsd::render::render(*brute, options).film.rgb == render_spec(flattened(spec)).film.rgb);
}

TEST_CASE("an instance's members take the instance's material where they inherit it") {
    SceneSpec spec = stage(32, 24);
    PrototypeSpec p;
    p.shapes.push_back(sphere({0, 0, 0}, 0.8, kInheritMaterial));
    spec.prototypes.push_back(p);
    spec.shapes.push_back(instance(0, glm::translate(Mat4(1.0), Vec3(-1, 0, 0)), 3));
    spec.shapes.push_back(instance(0, glm::translate(Mat4(1.0), Vec3(1, 0, 0)), 4));
    const auto r = render_spec(spec);
    const Color left = pixel(r.film, 10, 12), right = pixel(r.film, 22, 12);
    CHECK(left.r > 2 * left.b);    // red
    CHECK(right.b > 2 * right.r);  // blue
    require_identical(spec, flattened(spec));
}

TEST_CASE("an instance with a transmissive and an opaque member: filters apply to the members") {
    SceneSpec spec = stage(48, 36);
    PrototypeSpec p;
    p.shapes.push_back(sphere({0, 0, -1}, 0.5, 2));                  // glass, in front
    p.shapes.push_back(box({-0.5, -0.5, 0.5}, {0.5, 0.5, 1.0}, 3));  // opaque, behind
    p.shapes.push_back(sphere({1.2, 0, 0}, 0.3, kInheritMaterial));  // as the instance
    spec.prototypes.push_back(p);
    spec.shapes.push_back(instance(0, Mat4(1.0), 4));
    spec.shapes.push_back(instance(0, glm::translate(Mat4(1.0), Vec3(-1, 1, 1)), 2));
    require_identical(spec, flattened(spec));

    std::vector<SpecError> errors;
    auto g = Geometry::build(spec, errors);
    REQUIRE(g);
    RayStats stats;
    const Ray ray{{0, 0, -5}, {0, 0, 1}};
    auto all = g->intersect(ray, 100, stats);
    auto opaque = g->intersect(ray, 100, stats, RayFilter::OpaqueOnly);
    auto clear = g->intersect(ray, 100, stats, RayFilter::TransmissiveOnly);
    REQUIRE(all);
    REQUIRE(opaque);
    REQUIRE(clear);
    CHECK(all->t == Approx(3.5));
    CHECK(clear->t == all->t);
    CHECK(opaque->t == Approx(5.5));
    CHECK(g->surface(ray, *opaque).material == 3);
    CHECK(g->surface(ray, *clear).material == 2);
    CHECK(g->occluded(ray, 100, stats, RayFilter::OpaqueOnly));
    CHECK_FALSE(g->occluded(ray, 5, stats, RayFilter::OpaqueOnly));
    CHECK(g->occluded(ray, 5, stats, RayFilter::TransmissiveOnly));
    // The inheriting sphere: opaque in the first instance, glass in the second.
    const Ray side{{1.2, 0, -5}, {0, 0, 1}};
    CHECK(g->occluded(side, 100, stats, RayFilter::OpaqueOnly));
    const Ray side2{{0.2, 1, -5}, {0, 0, 1}};
    CHECK_FALSE(g->occluded(side2, 100, stats, RayFilter::OpaqueOnly));
    CHECK(g->occluded(side2, 100, stats, RayFilter::TransmissiveOnly));
}

TEST_CASE("a packet of rays through instances gets the single-ray hits") {
    SceneSpec spec = stage(16, 16);
    spec.prototypes.push_back(mixed_prototype());
    for (int k = 0; k < 4; ++k)
        spec.shapes.push_back(
            instance(0, rot_scale(20.0 * k, {0, 1, 0}, Vec3(0.8), {k - 1.5, 0, k * 0.3}), 3));
    std::vector<SpecError> errors;
    auto g = Geometry::build(spec, errors);
    REQUIRE(g);
    RayStats stats;
    for (int y = 0; y < 16; y += 4)
        for (int x = 0; x < 16; x += 4) {
            Ray rays[Geometry::kMaxPacket];
            for (int k = 0; k < Geometry::kMaxPacket; ++k)
                rays[k] = camera_ray(spec, x + k % 4 + 0.5, y + k / 4 + 0.5);
            std::optional<wsd::render::HitRecord> out[Geometry::kMaxPacket];
            g->intersect_packet(rays, Geometry::kMaxPacket, 100, stats, out);
            for (int k = 0; k < Geometry::kMaxPacket; ++k) {
                const auto one = g->intersect(rays[k], 100, stats);
                REQUIRE(one.has_value() == out[k].has_value());
                if (!one) continue;
                CHECK(one->t == out[k]->t);
                CHECK(one->prim == out[k]->prim);
                CHECK(one->inner_prim == out[k]->inner_prim);
            }
        }
}

TEST_CASE("instances store their object once: counts and memory") {
    SceneSpec spec = stage(8, 8);
    PrototypeSpec p;
    p.shapes.push_back(mesh_shape(sheet(40), 0));  // 3,200 triangles
    p.shapes.push_back(sphere({0, 1, 0}, 0.2, 3));
    spec.prototypes.push_back(p);
    for (int k = 0; k < 100; ++k)
        spec.shapes.push_back(instance(0, glm::translate(Mat4(1.0), Vec3(k, 0, 0)), 3));
    std::vector<SpecError> errors;
    auto g = Geometry::build(spec, errors);
    auto flat = Geometry::build(flattened(spec), errors);
    REQUIRE(g);
    REQUIRE(flat);
    CHECK(g->triangle_count() == 3200);
    CHECK(g->primitive_count() == 1 + 3201);  // the floor and the object once
    CHECK(g->instance_count() == 100);
    CHECK(g->instanced_primitive_count() == flat->primitive_count());
    CHECK(g->instanced_triangle_count() == flat->triangle_count());
    CHECK(flat->triangle_count() == 320000);
    CHECK(g->memory_bytes() * 20 < flat->memory_bytes());
}

TEST_CASE("instance errors: a missing object, a plane inside one, a bad member") {
    SceneSpec spec = stage(8, 8);
    PrototypeSpec p;
    p.shapes.push_back(sphere({0, 0, 0}, -1, 3));
    spec.prototypes.push_back(p);
    PrototypeSpec q;
    q.shapes.push_back(plane({0, 1, 0}, 0, 3));
    spec.prototypes.push_back(q);
    spec.shapes.push_back(instance(0, Mat4(1.0), 3));
    spec.shapes.push_back(instance(0, Mat4(1.0), 3));
    spec.shapes.push_back(instance(1, Mat4(1.0), 3));
    spec.shapes.push_back(instance(7, Mat4(1.0), 3));
    std::vector<SpecError> errors;
    CHECK_FALSE(Geometry::build(spec, errors));
    REQUIRE(errors.size() == 3);
    CHECK(errors[0].index == 1);
    CHECK(errors[0].message == "in its object's shape 1: sphere radius must be a positive number");
    CHECK(errors[1].index == 3);
    CHECK(errors[1].message ==
          "in its object's shape 1: a plane cannot be part of an instanced object (it has no bounds)");
    CHECK(errors[2].index == 4);
    CHECK(errors[2].message == "instance of object 7, but the scene has 2");
}

namespace {

// Every shape (instances by their own transform only), the lights and the camera moved by
// x ↦ s·x + t (test_robust_cornell.cpp's `moved`).
SceneSpec moved(SceneSpec spec, double s, Vec3 t) {
    const Mat4 m = glm::translate(Mat4(1.0), t) * glm::scale(Mat4(1.0), Vec3(s));
    for (auto& sh : spec.shapes) sh.object_to_world = m * sh.object_to_world;
    for (auto& l : spec.lights) {
        l.position = s * l.position + t;
        l.u *= s;
        l.v *= s;
    }
    spec.camera.position = s * spec.camera.position + t;
    spec.camera.look_at = s * spec.camera.look_at + t;
    for (auto& mat : spec.materials) mat.absorption /= s;
    return spec;
}

SceneSpec instanced_scene() {
    SceneSpec spec = stage(48, 36);
    spec.prototypes.push_back(mixed_prototype());
    spec.shapes.push_back(instance(0, glm::translate(Mat4(1.0), Vec3(-1, 0, 0)), 3));
    spec.shapes.push_back(instance(0, rot_scale(37, {0.3, 1, 0.2}, Vec3(1.7), {1.2, 0.1, 0.3}), 2));
    spec.shapes.push_back(instance(0, rot_scale(-70, {0, 1, 0}, {1.3, 0.7, 1.1}, {0.1, -0.2, 1.8}), 4));
    return spec;
}

}  // namespace

TEST_CASE("R78: instanced geometry scaled by 2^10 and 2^-10 renders bit-identical to the original") {
    const SceneSpec spec = instanced_scene();
    const auto base = render_spec(spec);
    CHECK(base.stats.refraction_rays > 0);
    for (const double s : {1024.0, 1.0 / 1024}) {
        INFO("scale " << s);
        const auto scaled = render_spec(moved(spec, s, Vec3(0)));
        CHECK(base.film.rgb == scaled.film.rgb);
        CHECK(base.stats.ray_queries() == scaled.stats.ray_queries());
    }
}

TEST_CASE("R79: instanced geometry translated by 10^5 renders as the same geometry written out flat") {
    for (const Vec3 t : {Vec3(1e5, 1e5, 1e5), Vec3(131072, 0, 0)}) {
        INFO("translation " << t.x << "," << t.y << "," << t.z);
        const SceneSpec far = moved(instanced_scene(), 1, t);
        require_identical(far, flattened(far));
    }
}

TEST_CASE("R80: 10^6 instances build and render") {
    SceneSpec spec = basic_scene(32, 24, {500, 300, -200}, 50);
    spec.camera.look_at = {500, 0, 500};
    spec.lights.push_back(point_light({500, 1000, 500}, 1));
    const uint32_t red = add_material(spec, matte(Color(0.9, 0.2, 0.2)));
    PrototypeSpec p;
    p.shapes.push_back(sphere({0, 0.3, 0}, 0.3, kInheritMaterial));
    spec.prototypes.push_back(p);
    constexpr int kSide = 1000;
    spec.shapes.reserve(kSide * kSide);
    for (int i = 0; i < kSide; ++i)
        for (int j = 0; j < kSide; ++j)
            spec.shapes.push_back(instance(0, glm::translate(Mat4(1.0), Vec3(i, 0, j)), red));
    const auto scene = build(spec);
    CHECK(scene->geometry().instance_count() == 1000000);
    CHECK(scene->geometry().instanced_primitive_count() == 1000000);
    CHECK(scene->geometry().primitive_count() == 1);
    // Per instance a transform, a record and its share of the top-level BVH: well under 1 KiB.
    INFO("geometry bytes per instance: " << scene->geometry().memory_bytes() / 1000000);
    CHECK(scene->geometry().memory_bytes() < 1000000 * size_t(1024));
    wsd::render::RenderOptions options;
    options.threads = 2;
    const auto r = wsd::render::render(*scene, options);
    CHECK(r.stats.nonfinite_samples == 0);
    CHECK(lit_pixels(r.film) > 32 * 24 / 4);
    CHECK(pixel(r.film, 16, 23) != Color(0));  // the nearest rows of spheres
}

TEST_CASE("an instance has its members' effects, attributed to it") {
    SceneSpec spec = stage(8, 8);
    PrototypeSpec p;
    p.shapes.push_back(sphere({0, 0, 0}, 0.5, 2));                 // glass
    p.shapes.push_back(sphere({1, 0, 0}, 0.5, kInheritMaterial));  // the instance's
    spec.prototypes.push_back(p);
    spec.shapes.push_back(instance(0, Mat4(1.0), 5));  // specular
    const auto set = wsd::render::analyse_effects(spec);
    using wsd::render::Effect;
    CHECK(set.has(Effect::Refraction));
    CHECK(set.has(Effect::Specular));
    CHECK(set.shapes[size_t(Effect::Refraction)] == std::vector<uint32_t>{1});
    CHECK(set.shapes[size_t(Effect::Absorption)] == std::vector<uint32_t>{1});
}

TEST_CASE("an instance whose transform and a member's together are singular is refused") {
    SceneSpec spec = stage(8, 8);
    Mat4 shear(1.0);
    shear[1] = glm::dvec4(1, 1e-7, 0, 0);  // columns nearly parallel, but not singular alone
    PrototypeSpec p;
    ShapeSpec b = box({0, 0, 0}, {1, 1, 1}, 3);
    b.object_to_world = shear;
    p.shapes.push_back(sphere({0, 0, 0}, 1, 3));
    p.shapes.push_back(b);
    spec.prototypes.push_back(p);
    spec.shapes.push_back(instance(0, glm::translate(Mat4(1.0), Vec3(5, 0, 0)), 3));
    std::vector<SpecError> errors;
    CHECK(Geometry::build(spec, errors));
    spec.shapes.push_back(instance(0, shear, 3));
    CHECK_FALSE(Geometry::build(spec, errors));
    REQUIRE(errors.size() == 1);
    CHECK(errors[0].index == 2);
    CHECK(errors[0].message ==
          "with its object's shape 2: transform is singular (a zero scale or collapsed axes)");
}
