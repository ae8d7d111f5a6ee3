// Scale and translation of a whole scene (robustness.md section D): examples/cornell.wsd, loaded
// through the language front end and rendered at 64×64, moved by a top-level transform (every
// shape's object_to_world, the lights and the camera): scaled by 2^±10 it is bit-identical (R27),
// by 10^±3 close (R28), translated by 10^5 within a stated tolerance (R29).
#include <algorithm>
#include <catch2/catch.hpp>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <sstream>

#include "lang/load.h"
#include "render/image_io.h"
#include "tests/render/scene_builders.h"

using namespace wsd::test;
using wsd::render::Film;
using wsd::render::Mat4;
using wsd::render::SceneSpec;

namespace {

SceneSpec load_cornell() {
    const std::string path = std::string(WSD_SOURCE_DIR) + "/examples/cornell.wsd";
    std::ifstream in(path);
    REQUIRE(in);
    std::stringstream text;
    text << in.rdbuf();
    wsd::lang::SourceManager sources;
    wsd::lang::Diagnostics diags;
    wsd::lang::LoadOptions options;
    options.build = false;
    auto loaded = wsd::lang::load_scene(path, text.str(), sources, diags, options);
    REQUIRE(loaded);
    REQUIRE_FALSE(diags.has_errors());
    loaded->spec.settings.width = loaded->spec.settings.height = 64;
    return loaded->spec;
}

// The scene under x ↦ s·x + t, with absorption per unit length rescaled by 1/s.
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

struct Difference {
    double max_linear = 0;     // largest difference of a channel, linear
    int max_display = 0;       // largest difference of a channel in 8-bit sRGB steps
    double mean_relative = 0;  // mean absolute difference over the mean value
    int over_5_percent = 0;    // pixels with a channel more than 5 % of the brightest channel off
};

Difference compare(const Film& a, const Film& b) {
    Difference d;
    double sum = 0, sum_abs = 0, brightest = 0;
    for (float v : a.rgb) brightest = std::max(brightest, double(v));
    auto to8 = [](float v) {
        return int(std::lround(255 * wsd::render::srgb_encode(std::clamp(double(v), 0.0, 1.0))));
    };
    for (size_t i = 0; i < a.rgb.size(); ++i) {
        const double diff = std::abs(double(a.rgb[i]) - double(b.rgb[i]));
        d.max_linear = std::max(d.max_linear, diff);
        d.max_display = std::max(d.max_display, std::abs(to8(a.rgb[i]) - to8(b.rgb[i])));
        sum += a.rgb[i];
        sum_abs += diff;
    }
    for (size_t i = 0; i < a.rgb.size(); i += 3) {
        bool off = false;
        for (size_t k = 0; k < 3; ++k) off = off || std::abs(a.rgb[i + k] - b.rgb[i + k]) > 0.05 * brightest;
        if (off) ++d.over_5_percent;
    }
    d.mean_relative = sum_abs / sum;
    return d;
}

}  // namespace

TEST_CASE("R27: the Cornell box scaled by 2^10 and 2^-10 renders bit-identical to the original") {
    const SceneSpec cornell = load_cornell();
    const auto base = render_spec(cornell);
    CHECK(base.stats.refraction_rays > 0);
    for (const double s : {1024.0, 1.0 / 1024}) {
        const auto scaled = render_spec(moved(cornell, s, Vec3(0)));
        const Difference d = compare(base.film, scaled.film);
        INFO("scale " << s << ": max difference " << d.max_linear);
        CHECK(d.max_linear == 0);
        CHECK(base.film.rgb == scaled.film.rgb);
        CHECK(base.stats.ray_queries() == scaled.stats.ray_queries());
    }
}

TEST_CASE("R28: the Cornell box scaled by 10^3 and 10^-3 stays close to the original") {
    const SceneSpec cornell = load_cornell();
    const auto base = render_spec(cornell);
    for (const double s : {1e3, 1e-3}) {
        const auto scaled = render_spec(moved(cornell, s, Vec3(0)));
        const Difference d = compare(base.film, scaled.film);
        INFO("scale " << s << ": max " << d.max_linear << " linear, " << d.max_display
                      << "/255 display, mean " << d.mean_relative << " of the mean, " << d.over_5_percent
                      << " pixels off by > 5 %");
        CHECK(d.mean_relative <= 1e-3);
        CHECK(d.over_5_percent <= 4);  // silhouette pixels of 4096 (robustness.md allows a mask)
    }
}

TEST_CASE("R29: the Cornell box translated by 10^5 stays within 1/255 of the original") {
    const SceneSpec cornell = load_cornell();
    const auto base = render_spec(cornell);
    for (const Vec3 t : {Vec3(1e5, 1e5, 1e5), Vec3(131072, 0, 0)}) {
        const auto far = render_spec(moved(cornell, 1, t));
        const Difference d = compare(base.film, far.film);
        INFO("translation " << t.x << "," << t.y << "," << t.z << ": max " << d.max_linear << " linear, "
                            << d.max_display << "/255 display, mean " << d.mean_relative << " of the mean, "
                            << d.over_5_percent << " pixels off by > 5 %");
        CHECK(d.mean_relative <= 1e-2);
        CHECK(d.max_display <= 1);
        CHECK(d.over_5_percent == 0);
    }
    // The move is real: translating everything but the camera changes the picture.
    SceneSpec shifted = moved(cornell, 1, {1e5, 1e5, 1e5});
    shifted.camera = cornell.camera;
    CHECK(compare(base.film, render_spec(shifted).film).max_linear > 0.1);
}
