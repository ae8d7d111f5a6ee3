// Cylinders, cones, tori and discs through the whole tracer: every texture kind and bumps on each
// (no NaN, the texture visible), a glass torus and an open tube seen from inside.
#include <catch2/catch.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <string>

#include "tests/render/scene_builders.h"

using namespace wsd::test;

namespace {

std::vector<wsd::render::ShapeSpec> primitives(uint32_t material) {
    std::vector<wsd::render::ShapeSpec> out;
    wsd::render::ShapeSpec s;
    s.material = material;
    s.kind = wsd::render::ShapeKind::Cylinder;
    s.base = {0, -1, 0};
    s.cap = {0.3, 1, 0.2};
    s.radius = 0.7;
    out.push_back(s);
    s.kind = wsd::render::ShapeKind::Cone;
    s.cap_radius = 0.1;
    out.push_back(s);
    s.open = true;
    out.push_back(s);
    s.kind = wsd::render::ShapeKind::Torus;
    s.major = 0.9;
    s.minor = 0.35;
    s.object_to_world = glm::rotate(wsd::render::Mat4(1.0), 1.1, Vec3(1, 0, 0));
    out.push_back(s);
    s.minor = 1.2;  // a spindle torus
    out.push_back(s);
    s.kind = wsd::render::ShapeKind::Disc;
    s.object_to_world = wsd::render::Mat4(1.0);
    s.center = {0, 0, 0};
    s.normal = {0.2, 0.3, -1};
    s.radius = 1.2;
    s.hole = 0.4;
    out.push_back(s);
    return out;
}

wsd::render::TextureSpec texture(wsd::render::TextureKind kind) {
    wsd::render::TextureSpec t;
    t.kind = kind;
    t.checker_scale = 0.25;
    t.perlin_scale = Vec3(4);
    t.image_path = std::string(WSD_SOURCE_DIR) + "/examples/textures/marble-tiles.png";
    return t;
}

}  // namespace

TEST_CASE("every texture and bumps work on cylinders, cones, tori and discs", "[quadric][texture][render]") {
    using wsd::render::TextureKind;
    for (TextureKind kind : {TextureKind::Checker, TextureKind::Perlin, TextureKind::Image}) {
        for (bool bumpy : {false, true}) {
            auto spec = basic_scene(40, 40, {0.5, 1, -5}, 45);
            spec.lights.push_back(point_light({-3, 4, -5}));
            auto m = matte(Color(1), 0.2);
            m.texture = texture(kind);
            m.specular = 0.4;
            if (bumpy) m.bump = texture(TextureKind::Perlin);
            const uint32_t id = add_material(spec, m);
            for (const auto& shape : primitives(id)) {
                auto one = spec;
                one.shapes.push_back(shape);
                const auto r = render_spec(one);
                // The texture is visible: the object's pixels are not all one colour.
                double lo = 1e300, hi = -1e300;
                int covered = 0;
                for (int y = 0; y < 40; ++y) {
                    for (int x = 0; x < 40; ++x) {
                        const double v = pixel(r.film, x, y).x + pixel(r.film, x, y).y;
                        if (v == 0) continue;
                        ++covered;
                        lo = std::min(lo, v);
                        hi = std::max(hi, v);
                    }
                }
                INFO("texture " << int(kind) << " bump " << bumpy << " shape " << int(shape.kind));
                CHECK(covered > 100);
                CHECK(hi > lo + 0.05);
            }
        }
    }
}

TEST_CASE("a glass torus and an open tube seen from inside render without NaN", "[quadric][render]") {
    auto spec = basic_scene(48, 48, {0, 0.3, -4}, 50);
    spec.settings.background = Color(0.3, 0.5, 0.7);
    spec.settings.max_depth = 10;
    spec.lights.push_back(point_light({2, 5, -4}));
    const uint32_t g = add_material(spec, glass(1.5));
    auto shapes = primitives(g);
    for (size_t i : {size_t(3), size_t(4)}) {
        auto one = spec;
        one.shapes.push_back(shapes[i]);
        const auto r = render_spec(one);
        CHECK(r.stats.nonfinite_samples == 0);
    }
    // Inside an open tube looking along it: the inside wall everywhere around the far opening.
    auto tube = basic_scene(32, 32, {0, 0, 0}, 60);
    tube.camera.look_at = {0, 0, 1};
    tube.settings.background = Color(1, 0, 0);
    wsd::render::ShapeSpec s;
    s.kind = wsd::render::ShapeKind::Cylinder;
    s.base = {0, 0, -1};
    s.cap = {0, 0, 3};
    s.radius = 1;
    s.open = true;
    s.material = add_material(tube, matte(Color(0, 1, 0), 1.0));
    tube.shapes.push_back(s);
    const auto r = render_spec(tube);
    CHECK(close_to(pixel(r.film, 0, 0), Color(0, 1, 0), 1e-6));    // the wall
    CHECK(close_to(pixel(r.film, 16, 16), Color(1, 0, 0), 1e-6));  // out through the far end
}
