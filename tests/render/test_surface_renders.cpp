// Whole renders of surface features: an image-textured sphere seen head-on shows the texture's
// centre at the image centre, upright and not mirrored; a bumpy mirror stays finite and has no
// black speckles (no bent normal sends a reflected ray into its own surface).
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>

#include "render/image_io.h"
#include "scene_builders.h"

using namespace wsd::test;
using wsd::render::Film;

namespace {

// A 64×32 texture: blue, a red block around the centre (u, v) = (0.5, 0.5), a green block to
// its right (u ≈ 0.62) and a white block above it (v ≈ 0.35).
std::string write_marked_texture() {
    Film f{64, 32, std::vector<float>(64 * 32 * 3)};
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 64; ++x) {
            Color c(0, 0, 1);
            if (x >= 30 && x < 34 && y >= 14 && y < 18) c = Color(1, 0, 0);
            if (x >= 38 && x < 42 && y >= 14 && y < 18) c = Color(0, 1, 0);
            if (x >= 30 && x < 34 && y >= 9 && y < 13) c = Color(1, 1, 1);
            float* p = &f.rgb[3 * (size_t(y) * 64 + size_t(x))];
            p[0] = float(c.x), p[1] = float(c.y), p[2] = float(c.z);
        }
    const std::string path =
        (std::filesystem::temp_directory_path() / ("wsd-marked-" + std::to_string(::getpid()) + ".png"))
            .string();
    std::string error;
    REQUIRE(wsd::render::write_image(path, f, error));
    return path;
}

bool near(const Color& a, const Color& b) {
    return close_to(a, b, 0.02);
}

}  // namespace

TEST_CASE("a textured sphere seen head-on shows the texture's centre, upright and unmirrored",
          "[texture][render]") {
    const std::string path = write_marked_texture();
    auto spec = basic_scene(65, 65, {0, 0, -5}, 30);
    auto m = matte(Color(1), 1.0);  // ambient 1, no lights: the pixel is the texel
    wsd::render::TextureSpec t;
    t.kind = wsd::render::TextureKind::Image;
    t.image_path = path;
    m.texture = t;
    spec.shapes.push_back(sphere({0, 0, 0}, 1.5, add_material(spec, m)));
    const auto r = render_spec(spec);
    std::filesystem::remove(path);
    CHECK(r.stats.nonfinite_samples == 0);
    CHECK(near(pixel(r.film, 32, 32), Color(1, 0, 0)));  // the texture's centre
    // Right of the centre in the image is larger u (green), above it is smaller v (white).
    bool green_right = false, green_left = false, white_above = false, white_below = false;
    for (int d = 2; d <= 32; ++d) {
        green_right = green_right || near(pixel(r.film, 32 + d, 32), Color(0, 1, 0));
        green_left = green_left || near(pixel(r.film, 32 - d, 32), Color(0, 1, 0));
        white_above = white_above || near(pixel(r.film, 32, 32 - d), Color(1, 1, 1));
        white_below = white_below || near(pixel(r.film, 32, 32 + d), Color(1, 1, 1));
    }
    CHECK(green_right);
    CHECK_FALSE(green_left);
    CHECK(white_above);
    CHECK_FALSE(white_below);
}

TEST_CASE("R31 R34: a bumpy mirror has no NaN and no black speckles", "[texture][bump][render]") {
    for (const double strength : {0.3, 1.0, 3.0, 20.0}) {
        auto spec = basic_scene(48, 48, {0, 0.5, -5}, 35);
        spec.settings.background = Color(0.6, 0.7, 0.8);
        spec.settings.max_depth = 8;
        auto mirror = matte(Color(0.1), 0.2);
        mirror.reflection = 0.9;
        wsd::render::TextureSpec bump;
        bump.kind = wsd::render::TextureKind::Perlin;
        bump.perlin_scale = Vec3(8);
        mirror.bump = bump;
        mirror.bump_strength = strength;
        spec.shapes.push_back(sphere({0, 0, 0}, 1.2, add_material(spec, mirror)));
        // A bright floor: whatever a reflected ray meets is at least 0.5 in every channel.
        auto floor = matte(Color(1), 1.0);
        wsd::render::TextureSpec checker;
        checker.color2 = Color(0.5);
        floor.texture = checker;
        spec.shapes.push_back(plane({0, 1, 0}, -1.2, add_material(spec, floor)));
        spec.lights.push_back(point_light({-3, 5, -4}, 0.5));
        const auto r = render_spec(spec);
        INFO("bump_strength " << strength);
        CHECK(r.stats.nonfinite_samples == 0);
        int sphere_pixels = 0, dark = 0;
        for (int y = 0; y < 48; ++y)
            for (int x = 0; x < 48; ++x) {
                if (hit_sphere(camera_ray(spec, x + 0.5, y + 0.5), {0, 0, 0}, 1.2) < 0) continue;
                ++sphere_pixels;
                const Color c = pixel(r.film, x, y);
                // local ≥ 0.02, reflected ≥ 0.9 · 0.5: anything darker is a ray lost inside.
                if (std::min({c.x, c.y, c.z}) < 0.4) ++dark;
            }
        CHECK(sphere_pixels > 300);
        CHECK(dark == 0);
    }
}
