// Lowering tests: transforms (rotation matrices and order), the defaults of every property table,
// block validation (unknown, repeated, missing, type, range), materials (base, the
// reflection + transmission rule, default_material, deduplication), camera and light checks,
// meshes (packed and general lists, OBJ files, face errors at the face), and SpecError mapping.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "eval_helpers.h"
#include "lang/lower.h"

using namespace wsd::lang;
using namespace wsd::lang::test;

namespace {

const std::string kMat = " material { } ";

std::unique_ptr<Loaded> scene(const std::string& body) {
    return load_text(std::string(kCamera) + body);
}

// The errors of a scene whose first line is the camera (lines count from the body's first line).
std::vector<std::string> body_errors(const std::string& body) {
    auto l = scene(body);
    std::vector<std::string> out;
    for (const Diagnostic& d : l->diags.all()) {
        if (d.severity != Severity::Error) continue;
        const LineCol lc = l->sources.line_col(d.span.file, d.span.begin);
        out.push_back(std::to_string(lc.line - 1) + ":" + std::to_string(lc.column) + ": " + d.message);
    }
    return out;
}

glm::dvec3 apply(const wsd::render::Mat4& m, glm::dvec3 p) {
    return glm::dvec3(m * glm::dvec4(p, 1.0));
}

void check_close(glm::dvec3 a, glm::dvec3 b) {
    CHECK(a.x == Approx(b.x).margin(1e-12));
    CHECK(a.y == Approx(b.y).margin(1e-12));
    CHECK(a.z == Approx(b.z).margin(1e-12));
}

struct TempDir {
    std::filesystem::path path;
    TempDir() {
        static int n = 0;
        path = std::filesystem::temp_directory_path() /
               ("wsd-h2-lower-" + std::to_string(::getpid()) + "-" + std::to_string(n++));
        std::filesystem::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    std::string write(const std::string& name, const std::string& text) const {
        std::filesystem::path p = path / name;
        std::filesystem::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << text;
        return p.string();
    }
};

}  // namespace

TEST_CASE("rotations use the spec's matrices, applied x then y then z", "[lower][transform]") {
    const double ax = 0.3, ay = -1.1, az = 2.0;  // radians
    const double deg = 180.0 / std::numbers::pi;
    const wsd::render::Mat4 m = rotation_matrix({ax * deg, ay * deg, az * deg});
    const glm::dvec3 p(0.7, -0.2, 1.3);
    // Rx, Ry, Rz written out from the language reference, applied in that order.
    glm::dvec3 q = {p.x, std::cos(ax) * p.y - std::sin(ax) * p.z, std::sin(ax) * p.y + std::cos(ax) * p.z};
    q = {std::cos(ay) * q.x + std::sin(ay) * q.z, q.y, -std::sin(ay) * q.x + std::cos(ay) * q.z};
    q = {std::cos(az) * q.x - std::sin(az) * q.y, std::sin(az) * q.x + std::cos(az) * q.y, q.z};
    check_close(apply(m, p), q);
}

TEST_CASE("quarter turns are exact", "[lower][transform]") {
    CHECK(apply(rotation_matrix({90, 0, 0}), {0, 1, 0}) == glm::dvec3(0, 0, 1));
    CHECK(apply(rotation_matrix({0, 90, 0}), {1, 0, 0}) == glm::dvec3(0, 0, -1));
    CHECK(apply(rotation_matrix({0, 0, 90}), {1, 0, 0}) == glm::dvec3(0, 1, 0));
    CHECK(apply(rotation_matrix({0, 0, -270}), {1, 0, 0}) == glm::dvec3(0, 1, 0));
    // x first, then y: +y → +z (Rx) → +x (Ry).
    CHECK(apply(rotation_matrix({90, 90, 0}), {0, 1, 0}) == glm::dvec3(1, 0, 0));
}

TEST_CASE("transforms apply in the order written", "[lower][transform]") {
    auto l =
        scene("sphere { center <0, 0, 0> radius 1 scale 2 translate <1, 0, 0>" + kMat +
              "}\n"
              "sphere { center <0, 0, 0> radius 1 translate <1, 0, 0> scale 2" +
              kMat +
              "}\n"
              "sphere { center <0, 0, 0> radius 1 scale <1, 2, 3> rotate <0, 0, 90> translate <0, 0, 5>" +
              kMat +
              "}\n"
              "box { min <-1, -1, -1> max <1, 1, 1> rotate <0, 0, 45> rotate <35.264, 0, 0>" +
              kMat + "}\n");
    REQUIRE(l->errors().empty());
    const auto& shapes = l->scene->spec.shapes;
    CHECK(apply(shapes[0].object_to_world, {1, 0, 0}) == glm::dvec3(3, 0, 0));
    CHECK(apply(shapes[1].object_to_world, {1, 0, 0}) == glm::dvec3(4, 0, 0));
    check_close(apply(shapes[2].object_to_world, {1, 1, 1}), {-2, 1, 8});
    // The dice on its corner: a body diagonal ends up vertical.
    const glm::dvec3 top = apply(shapes[3].object_to_world, {1, 1, -1});
    CHECK(top.x == Approx(0).margin(1e-4));
    CHECK(top.z == Approx(0).margin(1e-4));
    CHECK(std::fabs(top.y) == Approx(std::sqrt(3.0)).epsilon(1e-4));
}

TEST_CASE("scale factors are checked", "[lower][transform]") {
    CHECK(body_errors("sphere { center <0, 0, 0> radius 1 scale 0" + kMat + "}") ==
          std::vector<std::string>{"1:42: 'scale' factors must have a magnitude in [1e-12, 1e12], found 0"});
    CHECK(body_errors("sphere { center <0, 0, 0> radius 1 scale <1, 1e13, 1>" + kMat + "}").size() == 1);
    CHECK(body_errors("sphere { center <0, 0, 0> radius 1 scale <-1, 1, 1>" + kMat + "}").empty());
    CHECK(body_errors("sphere { center <0, 0, 0> radius 1 rotate 5" + kMat + "}") ==
          std::vector<std::string>{"1:43: 'rotate' must be a vector3, found number"});
}

TEST_CASE("every table's defaults are the documented ones", "[lower][defaults]") {
    auto l = load_text(
        "settings { }\ncamera { position <0, 0, 0> look_at <0, 0, 1> }\n"
        "light point { position <0, 5, 0> }\n"
        "light area { position <0, 5, 0> u <1, 0, 0> v <0, 0, 1> }\n"
        "plane { normal <0, 1, 0>" +
        kMat +
        "}\n"
        "triangle { <0, 0, 0>, <1, 0, 0>, <0, 1, 0>" +
        kMat +
        "}\n"
        "sphere { center <0, 0, 0> radius 1 material { texture checker { } bump perlin { } } }\n");
    REQUIRE(l->errors().empty());
    const auto& spec = l->scene->spec;
    CHECK(spec.settings.width == 640);
    CHECK(spec.settings.height == 480);
    CHECK(spec.settings.supersamples == 1);
    CHECK_FALSE(spec.settings.adaptive_supersampling);
    CHECK(spec.settings.aa_threshold == 0.05);
    CHECK(spec.settings.bailout == 1.0 / 512.0);
    CHECK(spec.settings.max_depth == 8);
    CHECK(spec.settings.ambient == 0.2);
    CHECK(spec.settings.background == glm::dvec3(0, 0, 0));
    CHECK(spec.settings.seed == 0);
    CHECK(spec.camera.up == glm::dvec3(0, 1, 0));
    CHECK(spec.camera.fov_degrees == 60);
    const auto& point = spec.lights[0];
    CHECK(point.kind == wsd::render::LightKind::Point);
    CHECK(point.color == glm::dvec3(1, 1, 1));
    CHECK(point.intensity == 1);
    const auto& area = spec.lights[1];
    CHECK(area.kind == wsd::render::LightKind::Area);
    CHECK(area.samples_u == 4);
    CHECK(area.samples_v == 4);
    CHECK(area.sampling == wsd::render::LightSampling::Jittered);
    CHECK_FALSE(area.adaptive);
    CHECK(area.color == glm::dvec3(1, 1, 1));
    CHECK(area.intensity == 1);
    const auto& plane = spec.shapes[0];
    CHECK(plane.distance == 0);
    CHECK(plane.uv_scale == 1);
    CHECK_FALSE(spec.shapes[1].tri_uv);
    const auto& m = spec.materials[0];
    CHECK(m.color == glm::dvec3(1, 1, 1));
    CHECK_FALSE(m.texture);
    CHECK_FALSE(m.ambient);
    CHECK(m.diffuse == 1);
    CHECK(m.specular == 0);
    CHECK(m.shininess == 50);
    CHECK(m.reflection == 0);
    CHECK(m.transmission == 0);
    CHECK(m.ior == 1.5);
    CHECK(m.absorption == glm::dvec3(0, 0, 0));
    CHECK_FALSE(m.bump);
    CHECK(m.bump_strength == 0.3);
    const auto& textured = spec.materials[2];
    REQUIRE(textured.texture);
    CHECK(textured.texture->kind == wsd::render::TextureKind::Checker);
    CHECK(textured.texture->checker_scale == 1);
    CHECK(textured.texture->color1 == glm::dvec3(1, 1, 1));
    CHECK(textured.texture->color2 == glm::dvec3(0, 0, 0));
    REQUIRE(textured.bump);
    CHECK(textured.bump->kind == wsd::render::TextureKind::Perlin);
    CHECK(textured.bump->perlin == wsd::render::PerlinKind::Noise);
    CHECK(textured.bump->perlin_scale == glm::dvec3(1, 1, 1));
    CHECK(textured.bump->octaves == 9);
    CHECK(textured.bump->color1 == glm::dvec3(1, 1, 1));
    CHECK(textured.bump->color2 == glm::dvec3(0, 0, 0));
}

TEST_CASE("properties are read into the spec", "[lower]") {
    auto l = load_text(
        "settings { width 32 height 16 supersamples 9 adaptive_supersampling on aa_threshold 0.1 "
        "bailout 0 max_depth 3 ambient 0.5 background <0.1, 0.2, 0.3> seed 4294967295 }\n"
        "camera { position <1, 2, 3> look_at <1, 2, 4> up <1, 1, 0> fov 45 }\n"
        "light area { position <0, 5, 0> u <1, 0, 0> v <0, 0, 1> samples 8, 4 sampling uniform "
        "adaptive on color <1, 0.5, 0> intensity 2 }\n"
        "triangle { <0, 0, 0>, <1, 0, 0>, <0, 1, 0> uv <0, 0>, <1, 0>, <0, 1>" +
        kMat +
        "}\n"
        "sphere { center <0, 0, 0> radius 1 material { texture perlin { kind marble scale <1, 2, 0> "
        "octaves 3 colors <1, 0, 0>, <0, 0, 1> } ambient 0.1 reflection 0.25 transmission 0.75 } }\n");
    REQUIRE(l->errors().empty());
    const auto& spec = l->scene->spec;
    CHECK(spec.settings.width == 32);
    CHECK(spec.settings.supersamples == 9);
    CHECK(spec.settings.adaptive_supersampling);
    CHECK(spec.settings.seed == 4294967295u);
    CHECK(spec.settings.background == glm::dvec3(0.1, 0.2, 0.3));
    CHECK(spec.camera.fov_degrees == 45);
    CHECK(spec.lights[0].samples_u == 8);
    CHECK(spec.lights[0].samples_v == 4);
    CHECK(spec.lights[0].sampling == wsd::render::LightSampling::Uniform);
    CHECK(spec.lights[0].adaptive);
    CHECK(spec.lights[0].intensity == 2);
    REQUIRE(spec.shapes[0].tri_uv);
    CHECK((*spec.shapes[0].tri_uv)[2] == glm::dvec2(0, 1));
    const auto& m = spec.materials[1];
    CHECK(m.ambient == 0.1);
    CHECK(m.texture->perlin == wsd::render::PerlinKind::Marble);
    CHECK(m.texture->perlin_scale == glm::dvec3(1, 2, 0));
    CHECK(m.texture->octaves == 3);
    CHECK(m.texture->color2 == glm::dvec3(0, 0, 1));
}

TEST_CASE("blocks report unknown, repeated, missing, mistyped and out-of-range properties",
          "[lower][errors]") {
    // A misspelt name is one error: the property it meant is not also reported missing.
    auto l = scene("sphere { center <0, 0, 0> radus 1" + kMat + "}\n");
    REQUIRE(l->diags.all().size() == 1);
    CHECK(l->errors()[0] == "2:27: unknown property 'radus' in sphere");
    CHECK(l->diags.all()[0].help == std::vector<std::string>{"did you mean 'radius'?"});
    CHECK(body_errors("box { min <0, 0, 0> mx <1, 1, 1>" + kMat + "}") ==
          std::vector<std::string>{"1:21: unknown property 'mx' in box"});
    CHECK(body_errors("mesh { fil \"a.obj\"" + kMat + "}") ==
          std::vector<std::string>{"1:8: unknown property 'fil' in mesh"});
    CHECK(body_errors("sphere { center <0, 0, 0> radius 1 materal m }") ==
          std::vector<std::string>{"1:36: unknown property 'materal' in sphere"});
    // A name that is unknown and suggests nothing still leaves the property missing.
    CHECK(body_errors("sphere { center <0, 0, 0> xyzzy 1" + kMat + "}") ==
          std::vector<std::string>{"1:27: unknown property 'xyzzy' in sphere",
                                   "1:1: missing property 'radius' in sphere"});

    l = scene("sphere { center <0, 0, 0> radius 1 radius 2" + kMat + "}\n");
    REQUIRE(l->errors() == std::vector<std::string>{"2:36: repeated property 'radius' in sphere"});
    REQUIRE(l->diags.all()[0].notes.size() == 1);
    CHECK(where(l->sources, l->diags.all()[0].notes[0].span) == "2:27");

    CHECK(body_errors("sphere { center 1 radius <1, 2, 3>" + kMat + "}") ==
          std::vector<std::string>{"1:17: 'center' must be a vector3, found number",
                                   "1:26: 'radius' must be a number, found vector3"});
    CHECK(body_errors("sphere { center <0, 0, 0> radius 0" + kMat + "}") ==
          std::vector<std::string>{"1:34: 'radius' must be > 0, found 0"});
    CHECK(body_errors("sphere { center <0, 0, 0> radius 1, 2" + kMat + "}") ==
          std::vector<std::string>{"1:37: 'radius' takes 1 value, found 2"});
    CHECK(body_errors("settings { width 0 }") ==
          std::vector<std::string>{"1:18: 'width' must be an integer from 1 to 100000, found 0"});
    CHECK(body_errors("settings { max_depth 2.5 }") ==
          std::vector<std::string>{"1:22: 'max_depth' must be an integer from 0 to 256, found 2.5"});
    CHECK(body_errors("settings { bailout 1 }") ==
          std::vector<std::string>{"1:20: 'bailout' must be in [0, 1), found 1"});
    CHECK(body_errors("settings { background <-1, 0, 0> }") ==
          std::vector<std::string>{"1:23: 'background' must have components >= 0, found <-1, 0, 0>"});
    CHECK(body_errors("settings { adaptive_supersampling 1 }") ==
          std::vector<std::string>{"1:35: 'adaptive_supersampling' must be a bool, found number"});
    CHECK(body_errors("light point { position <0, 0, 0> samples 4 }") ==
          std::vector<std::string>{"1:34: unknown property 'samples' in light point"});
    CHECK(body_errors("light area { position <0, 0, 0> u <1, 0, 0> v <0, 1, 0> sampling random }") ==
          std::vector<std::string>{"1:66: 'sampling' must be one of jittered or uniform"});
    CHECK(body_errors("sphere { center <0, 0, 0> radius 1 material { texture perlin { kind marbel } } }") ==
          std::vector<std::string>{"1:69: 'kind' must be one of noise, turbulence, marble or wood"});
    CHECK(body_errors(
              "sphere { center <0, 0, 0> radius 1 material { texture checker { colors <1, 1, 1> } } }") ==
          std::vector<std::string>{"1:65: 'colors' takes 2 values, found 1"});
}

TEST_CASE("settings: the image size limit is reported at the later of width and height", "[lower][errors]") {
    CHECK(body_errors("settings { height 100000 width 100000 }") ==
          std::vector<std::string>{
              "1:32: image size 100000 x 100000 exceeds the limit of 268435456 pixels (2^28)"});
    CHECK(body_errors("settings { width 16384 height 16384 }").empty());  // exactly 2^28
}

TEST_CASE("a scene has at most one settings and exactly one camera", "[lower][errors]") {
    auto l = scene("camera { position <0, 0, 0> look_at <0, 0, 1> }\nsettings { }\nsettings { }\n");
    CHECK(l->errors() ==
          std::vector<std::string>{"2:1: more than one camera", "4:1: more than one 'settings' block"});
    REQUIRE(l->diags.all()[0].notes.size() == 1);
    CHECK(where(l->sources, l->diags.all()[0].notes[0].span) == "1:1");
    CHECK(where(l->sources, l->diags.all()[1].notes[0].span) == "3:1");

    l = load_text("sphere { center <0, 0, 0> radius 1" + kMat + "}\n");
    CHECK(l->errors() == std::vector<std::string>{"1:1: missing camera: a scene needs one 'camera { ... }'"});
    l = load_text("", true);
    CHECK(l->errors().empty());  // a fragment needs no camera
    l = load_text("");
    CHECK(l->errors().size() == 1);
}

TEST_CASE("the camera's up must not be parallel to the view direction", "[lower][errors]") {
    auto errors = [](const std::string& camera) { return load_text(camera)->errors(); };
    CHECK(
        errors("camera { position <0, 0, 0> look_at <0, 5, 0> up <0, -2, 0> }") ==
        std::vector<std::string>{"1:50: camera 'up' is parallel to the view direction (look_at - position)"});
    CHECK(errors("camera { position <0, 0, 0> look_at <0, 5, 0> }") ==
          std::vector<std::string>{
              "1:37: camera looks along the default 'up' <0, 1, 0>: give an 'up' that is not "
              "parallel to look_at - position"});
    CHECK(errors("camera { position <1, 1, 1> look_at <1, 1, 1> }") ==
          std::vector<std::string>{"1:37: camera 'look_at' is the same point as 'position'"});
    CHECK(errors("camera { position <0, 0, 0> look_at <0, 0, 1> up <0, 0, 0> }") ==
          std::vector<std::string>{"1:50: camera 'up' must not be the zero vector"});
    CHECK(errors("camera { position <0, 0, 0> look_at <0, 0, 1> fov 180 }") ==
          std::vector<std::string>{"1:51: 'fov' must be in (0, 180), found 180"});
    CHECK(errors("camera { position <0, 0, 0> }") ==
          std::vector<std::string>{"1:1: missing property 'look_at' in camera"});
    // Parallel is a matter of direction, not of length: a tiny or huge up that is perpendicular
    // is fine (its length once underflowed and it read as parallel), and a tiny parallel one is not.
    CHECK(errors("camera { position <0, 5, 0> look_at <0, 0, 0> up <0, 0, 1e-300> }").empty());
    CHECK(errors("camera { position <0, 2, -6> look_at <0, 1, 0> up <0, 1e-300, 0> }").empty());
    CHECK(errors("camera { position <0, 5, 0> look_at <0, 0, 0> up <0, 0, 1e300> }").empty());
    CHECK(errors("camera { position <0, 1e-300, 0> look_at <0, 0, 1e-300> }").empty());
    CHECK(
        errors("camera { position <0, 0, 0> look_at <0, 5, 0> up <0, 1e-300, 0> }") ==
        std::vector<std::string>{"1:50: camera 'up' is parallel to the view direction (look_at - position)"});
}

TEST_CASE("area lights need non-zero, non-parallel edges and a bounded grid", "[lower][errors]") {
    CHECK(body_errors("light area { position <0, 0, 0> u <0, 0, 0> v <0, 0, 1> }") ==
          std::vector<std::string>{"1:35: area light edge 'u' must not be the zero vector"});
    CHECK(body_errors("light area { position <0, 0, 0> u <1, 0, 0> v <-2, 0, 0> }") ==
          std::vector<std::string>{"1:47: area light edges 'u' and 'v' are parallel"});
    CHECK(body_errors("light area { position <0, 0, 0> u <1e-300, 0, 0> v <-1e300, 0, 0> }") ==
          std::vector<std::string>{"1:52: area light edges 'u' and 'v' are parallel"});
    CHECK(body_errors("light area { position <0, 5, 0> u <1e-150, 0, 0> v <0, 0, 1e-150> }").empty());
    CHECK(body_errors("light area { position <0, 0, 0> u <1, 0, 0> v <0, 0, 1> samples 1024 }") ==
          std::vector<std::string>{"1:65: area light has 1024 x 1024 samples, more than the limit of 65536"});
    CHECK(body_errors("light area { position <0, 0, 0> u <1, 0, 0> v <0, 0, 1> samples 0 }") ==
          std::vector<std::string>{"1:65: 'samples' must be an integer from 1 to 1024, found 0"});
    CHECK(body_errors("light area { position <0, 0, 0> u <1, 0, 0> }") ==
          std::vector<std::string>{"1:1: missing property 'v' in light area"});
    CHECK(body_errors("light spto { position <0, 0, 0> }") ==
          std::vector<std::string>{"1:7: unknown light kind 'spto' (point, area or spot)"});
}

TEST_CASE("materials: base first, overrides, the reflection + transmission rule", "[lower][material]") {
    auto l = scene(
        "let glass = material { color <1, 1, 1> transmission 1 ior 1.5 }\n"
        "let tinted = material { color <1, 0.5, 0.5> base glass }\n"
        "sphere { center <0, 0, 0> radius 1 material tinted }\n");
    REQUIRE(l->errors().empty());
    const auto& m = l->scene->spec.materials[0];
    CHECK(m.transmission == 1);
    CHECK(m.ior == 1.5);
    CHECK(m.color == glm::dvec3(1, 0.5, 0.5));

    CHECK(body_errors("let m = material { transmission 0.6 reflection 0.5 }") ==
          std::vector<std::string>{"1:48: 'reflection' + 'transmission' must not exceed 1, found 0.5 + 0.6"});
    auto later = scene("let m = material { transmission 0.6 reflection 0.5 }\n");
    REQUIRE(later->diags.all()[0].notes.size() == 1);
    CHECK(where(later->sources, later->diags.all()[0].notes[0].span) == "2:33");
    // Inherited from base: the written one is the later one.
    CHECK(body_errors("let g = material { transmission 1 }\nlet m = material { base g reflection 0.1 }") ==
          std::vector<std::string>{"2:38: 'reflection' + 'transmission' must not exceed 1, found 0.1 + 1"});
    CHECK(body_errors("let m = material { bump checker { } }") ==
          std::vector<std::string>{"1:25: 'bump' must be a perlin texture, found a checker texture"});
    CHECK(body_errors("let m = material { shininess 0 ior -1 }") ==
          std::vector<std::string>{"1:30: 'shininess' must be > 0, found 0",
                                   "1:36: 'ior' must be > 0, found -1"});
}

TEST_CASE("default_material makes material optional", "[lower][material]") {
    auto l =
        scene("let default_material = material { color <0, 1, 0> }\nsphere { center <0, 0, 0> radius 1 }\n");
    REQUIRE(l->errors().empty());
    CHECK(l->scene->spec.materials[0].color == glm::dvec3(0, 1, 0));
    CHECK(body_errors("sphere { center <0, 0, 0> radius 1 }") ==
          std::vector<std::string>{"1:1: missing property 'material' in sphere"});
    CHECK(body_errors("let default_material = 3\nsphere { center <0, 0, 0> radius 1 }") ==
          std::vector<std::string>{"2:1: 'default_material' is a number, not a material"});
}

TEST_CASE("materials are deduplicated by identity and counted", "[lower][material]") {
    auto l = scene(
        "let m = material { color <1, 0, 0> }\n"
        "for i in 0 .. 3 { sphere { center <i, 0, 0> radius 0.5 material m } }\n"
        "for i in 0 .. 2 { sphere { center <i, 3, 0> radius 0.5 material { color <1, 0, 0> } } }\n"
        "triangle { <0, 0, 0>, <1, 0, 0>, <0, 1, 0> material m }\n"
        "light point { position <0, 9, 0> }\n");
    REQUIRE(l->errors().empty());
    const auto& s = l->scene->summary;
    CHECK(s.objects == 6);
    CHECK(s.triangles == 1);
    CHECK(s.lights == 1);
    CHECK(s.materials == 3);
    const auto& shapes = l->scene->spec.shapes;
    CHECK(shapes[0].material == shapes[2].material);
    CHECK(shapes[0].material == shapes[5].material);
    CHECK(shapes[3].material != shapes[4].material);
}

TEST_CASE("inline meshes convert packed and general lists", "[lower][mesh]") {
    auto l = scene(
        "mesh { vertices [<0, 0, 0>, <1, 0, 0>, <1, 1, 0>, <0, 1, 0>] faces [<0, 1, 2>, <0, 2, 3>]\n"
        "       uvs [<0, 0>, <1, 0>, <1, 1>, <0, 1>]" +
        kMat +
        "}\n"
        "let c = <0, 0, 5>\n"
        "mesh { vertices [c, c + <1, 0, 0>, c + <0, 1, 0>] faces [<0, 1, 2>] normals [<0, 0, -1>, <0, 0, "
        "-1>, <0, 0, -1>]" +
        kMat + "}\n");
    REQUIRE(l->errors().empty());
    const auto& mesh = *l->scene->spec.shapes[0].mesh;
    CHECK(mesh.vertices.size() == 4);
    CHECK(mesh.vertices[2] == glm::vec3(1, 1, 0));
    CHECK(mesh.faces[1] == glm::uvec3(0, 2, 3));
    CHECK(mesh.uvs[3] == glm::vec2(0, 1));
    const auto& general = *l->scene->spec.shapes[1].mesh;
    CHECK(general.vertices[1] == glm::vec3(1, 0, 5));
    CHECK(general.normals.size() == 3);
    CHECK(l->scene->summary.triangles == 3);
    CHECK(l->scene->summary.objects == 2);
}

TEST_CASE("bad mesh faces are reported at the face, naming it", "[lower][mesh]") {
    const std::string verts = "mesh { vertices [<0, 0, 0>, <1, 0, 0>, <1, 1, 0>, <0, 1, 0>] faces ";
    CHECK(body_errors(verts + "[<0, 1, 2>, <0, 2, 7>]" + kMat + "}") ==
          std::vector<std::string>{"1:80: face 1: index 7 is out of range (the mesh has 4 vertices)"});
    CHECK(body_errors(verts + "[<0, 1, 2.5>]" + kMat + "}") ==
          std::vector<std::string>{"1:69: face 0: index 2.5 is not an integer"});
    CHECK(body_errors(verts + "[<0, 1, 2>, <0, 1>]" + kMat + "}") ==
          std::vector<std::string>{"1:80: face 1 must be a vector3 of vertex indices, found vector2"});
    CHECK(body_errors(verts + "[]" + kMat + "}") == std::vector<std::string>{"1:68: 'faces' is empty"});
    CHECK(
        body_errors(verts + "[<0, 1, 2>] uvs [<0, 0>]" + kMat + "}") ==
        std::vector<std::string>{"1:84: 'uvs' has 1 element, but the mesh has 4 vertices (one per vertex)"});
    CHECK(body_errors("mesh { vertices [<0, 0, 0>, <1, 0, 0>, <1, 1, 0>] faces [<0, 1, 2>] normals [<0, 0, "
                      "1>, <0, 0, 0>, <0, 0, 1>]" +
                      kMat + "}") == std::vector<std::string>{"1:89: normal 1 is the zero vector"});
    CHECK(body_errors("mesh { faces [<0, 1, 2>]" + kMat + "}") ==
          std::vector<std::string>{"1:1: missing property 'vertices' in mesh"});
    CHECK(body_errors("mesh {" + kMat + "}") ==
          std::vector<std::string>{"1:1: missing property 'file' (or 'vertices' and 'faces') in mesh"});
    CHECK(body_errors("mesh { file \"a.obj\" vertices [<0, 0, 0>]" + kMat + "}") ==
          std::vector<std::string>{"1:21: 'vertices' cannot be combined with 'file' in mesh"});
    CHECK(body_errors("mesh { vertices [<1e39, 0, 0>] faces [<0, 0, 0>]" + kMat + "}") ==
          std::vector<std::string>{"1:18: vertex 0 is too large for single precision"});
}

TEST_CASE("OBJ meshes load relative to the naming file, once", "[lower][mesh]") {
    TempDir dir;
    dir.write("models/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\n");
    dir.write("models/bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 9\n");
    dir.write("parts/use.wsdi", "mesh { file \"../models/tri.obj\" material { } }\n");
    const std::string main =
        dir.write("main.wsd", std::string(kCamera) +
                                  "include \"parts/use.wsdi\"\n"
                                  "mesh { file \"models/tri.obj\" scale 2 material { } }\n");
    std::ifstream in(main);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto l = load_text(text, false, false, main);
    REQUIRE(l->errors().empty());
    CHECK(l->scene->summary.triangles == 4);
    CHECK(l->scene->spec.shapes[0].mesh == l->scene->spec.shapes[1].mesh);  // read once

    const std::string bad =
        dir.write("bad.wsd", std::string(kCamera) + "mesh { file \"models/bad.obj\" material { } }\n");
    l = load_text(std::string(kCamera) + "mesh { file \"models/bad.obj\" material { } }\n", false, false,
                  bad);
    REQUIRE(l->errors().size() == 1);
    CHECK(l->errors()[0].rfind("2:13: ", 0) == 0);
    CHECK(l->errors()[0].find("bad.obj:3") != std::string::npos);  // the OBJ file and its line

    l = load_text(std::string(kCamera) + "mesh { file \"models/none.obj\" material { } }\n", false, false,
                  bad);
    REQUIRE(l->errors().size() == 1);
    CHECK(l->errors()[0].find((dir.path / "models/none.obj").string()) != std::string::npos);
}

TEST_CASE("image paths resolve relative to the naming file", "[lower][material]") {
    auto l = load_text(std::string(kCamera) +
                           "sphere { center <0, 0, 0> radius 1 material { texture image \"tex/a.png\" } }\n",
                       false, false, "scenes/deep/s.wsd");
    REQUIRE(l->errors().empty());
    CHECK(l->scene->spec.materials[0].texture->image_path ==
          (std::filesystem::path("scenes/deep") / "tex/a.png").string());
}

TEST_CASE("build errors map back to their spans", "[lower][spec-errors]") {
    // A degenerate triangle found by the scene builder is reported at the triangle.
    auto l = load_text(std::string(kCamera) + "\ntriangle { <0, 0, 0>, <1, 0, 0>, <2, 0, 0>" + kMat + "}\n",
                       false, true);
    REQUIRE(l->errors().size() == 1);
    CHECK(l->errors()[0].rfind("3:1: ", 0) == 0);
    // A degenerate mesh face at that face's literal.
    l = load_text(std::string(kCamera) +
                      "mesh { vertices [<0, 0, 0>, <1, 0, 0>, <0, 1, 0>, <2, 0, 0>]\n"
                      "       faces [<0, 1, 2>, <0, 1, 3>]" +
                      kMat + "}\n",
                  false, true);
    REQUIRE(l->errors().size() == 1);
    CHECK(l->errors()[0].rfind("3:26: face 1", 0) == 0);
    // A missing texture at its path string.
    l = load_text(std::string(kCamera) +
                      "sphere { center <0, 0, 0> radius 1 material { texture image \"no-such.png\" } }\n",
                  false, true, "/nonexistent-dir/s.wsd");
    REQUIRE(l->errors().size() == 1);
    CHECK(l->errors()[0].rfind("2:61: ", 0) == 0);
}

TEST_CASE("an image file that no object uses is read too: missing, it is an error at its string",
          "[lower][spec-errors]") {
    // Bound to a name, in a material no object uses, or never bound: each names the file.
    for (const std::string& named : {std::string("let t = image \"no-such.png\"\n"),
                                     std::string("let m = material { texture image \"no-such.png\" }\n"),
                                     std::string("let s = sphere { center <0, 0, 0> radius 1\n"
                                                 "  material { texture image \"no-such.png\" } }\n")}) {
        auto l = load_text(std::string(kCamera) + named, false, true, "/nonexistent-dir/s.wsd");
        INFO(named);
        REQUIRE(l->errors().size() == 1);
        CHECK(l->errors()[0].find("cannot open image '/nonexistent-dir/no-such.png'") != std::string::npos);
        const Diagnostic& d = l->diags.all()[0];
        const std::string_view text = std::string_view(l->sources.file(d.span.file).text);
        CHECK(text.substr(d.span.begin, d.span.end - d.span.begin) == "\"no-such.png\"");
    }
    // Without a build (what `wsd check` of a fragment and the editor do) no file is read.
    auto l = load_text(std::string(kCamera) + "let t = image \"no-such.png\"\n", false, false,
                       "/nonexistent-dir/s.wsd");
    CHECK(l->errors().empty());
}

TEST_CASE("SpecErrors find faces given as a general list", "[lower][spec-errors]") {
    auto e = evaluate_text(
        std::string(kCamera) +
        "let f = <0, 1, 2>\nmesh { vertices [<0, 0, 0>, <1, 0, 0>, <0, 1, 0>] faces [f, <0, 2, 1>]" + kMat +
        "}\n");
    REQUIRE(e->errors().empty());
    const uint32_t tag = e->scene.spec.shapes[0].tag;
    Diagnostics diags;
    report_spec_errors(
        {wsd::render::SpecError{wsd::render::SpecItem::Shape, 0, tag, "face 1: degenerate triangle", 1}},
        e->scene, e->sources, diags);
    REQUIRE(diags.all().size() == 1);
    CHECK(where(e->sources, diags.all()[0].span) == "3:61");
    CHECK(diags.all()[0].message == "face 1: degenerate triangle");
}

TEST_CASE("SpecErrors about a field are shown at its value, or at the element when not written",
          "[lower][spec-errors]") {
    auto e =
        evaluate_text(std::string(kCamera) + "settings { height 100 }\nlight point { position <0, 5, 0> }\n" +
                      "sphere { center <0, 0, 0>  radius 2" + kMat + "}\n");
    REQUIRE(e->errors().empty());
    using wsd::render::SpecError, wsd::render::SpecItem;
    const auto& spec = e->scene.spec;
    Diagnostics diags;
    report_spec_errors({SpecError{SpecItem::Shape, 0, spec.shapes[0].tag, "bad radius", -1, "radius"},
                        SpecError{SpecItem::Shape, 0, spec.shapes[0].tag, "bad sphere", -1},
                        SpecError{SpecItem::Settings, 0, 0, "bad height", -1, "height"},
                        SpecError{SpecItem::Settings, 0, 0, "bad width", -1, "width"},
                        SpecError{SpecItem::Light, 0, spec.lights[0].tag, "bad colour", -1, "color"},
                        SpecError{SpecItem::Camera, 0, spec.camera.tag, "bad up", -1, "look_at"}},
                       e->scene, e->sources, diags);
    REQUIRE(diags.all().size() == 6);
    CHECK(where(e->sources, diags.all()[0].span) == "4:35");  // the radius value
    CHECK(where(e->sources, diags.all()[1].span) == "4:1");   // the sphere
    CHECK(where(e->sources, diags.all()[2].span) == "2:19");  // the height value
    CHECK(where(e->sources, diags.all()[3].span) == "2:1");   // width not written: the block
    CHECK(where(e->sources, diags.all()[4].span) == "3:1");   // color not written: the light
    CHECK(diags.all()[0].message == "bad radius");
    CHECK(where(e->sources, diags.all()[5].span) == "1:39");  // the look_at value

    // Materials and textures: their own values; one inherited from `base` is shown at the
    // material.
    e = evaluate_text(std::string(kCamera) +
                      "let b = material { reflection 0.5 }\n"
                      "sphere { center <0, 0, 0> radius 1 material material { base b  transmission 0.5  "
                      "texture checker { scale 2 } } }\n");
    REQUIRE(e->errors().empty());
    const auto& material = e->scene.spec.materials[0];
    diags = Diagnostics{};
    report_spec_errors({SpecError{SpecItem::Material, 0, material.tag, "m", -1, "transmission"},
                        SpecError{SpecItem::Material, 0, material.tag, "m", -1, "reflection"},
                        SpecError{SpecItem::Texture, 0, material.texture->tag, "t", -1, "scale"}},
                       e->scene, e->sources, diags);
    REQUIRE(diags.all().size() == 3);
    CHECK(where(e->sources, diags.all()[0].span) == "3:77");   // the transmission value
    CHECK(where(e->sources, diags.all()[1].span) == "3:45");   // the material
    CHECK(where(e->sources, diags.all()[2].span) == "3:106");  // the checker's scale value
}

TEST_CASE("SpecErrors in an included file carry the include chain", "[lower][spec-errors]") {
    TempDir dir;
    dir.write("parts/flat.wsdi", "\ntriangle { <0, 0, 0>, <1, 1, 1>, <2, 2, 2> material { } }\n");
    const std::string main = dir.write("main.wsd", std::string(kCamera) + "include \"parts/flat.wsdi\"\n");
    std::ifstream in(main);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto l = load_text(text, false, true, main);
    REQUIRE(l->errors().size() == 1);
    const Diagnostic& d = l->diags.all()[0];
    CHECK(l->sources.file(d.span.file).path == (dir.path / "parts/flat.wsdi").string());
    CHECK(where(l->sources, d.span) == "2:1");
    REQUIRE(d.include_chain.size() == 1);
    CHECK(where(l->sources, d.include_chain[0]) == "2:9");
}

TEST_CASE("the primitive limit counts mesh triangles", "[lower][limits]") {
    Limits small;
    small.primitives = 3;
    auto e = evaluate_text(
        "sphere { center <0, 0, 0> radius 1" + kMat +
            "}\n"
            "mesh { vertices [<0, 0, 0>, <1, 0, 0>, <0, 1, 0>] faces [<0, 1, 2>, <0, 2, 1>, <1, 2, 0>]" +
            kMat + "}\n",
        small);
    CHECK(e->errors() ==
          std::vector<std::string>{
              "2:1: the scene has more than 3 primitives (the limit; a mesh counts its triangles)"});
    CHECK(e->interpreter->aborted());
}

TEST_CASE("a scene without lights is warned about, once, at its camera", "[lower][lights]") {
    auto l = load_text(std::string(kCamera) + "sphere { center <0, 0, 0> radius 1" + kMat + "}\n");
    REQUIRE(l->scene);
    CHECK(messages(l->diags, l->sources, Severity::Warning) ==
          std::vector<std::string>{"1:1: no lights: only ambient light"});
    // A scene with a light, a fragment (lit by the scene that includes it) and a scene with
    // errors are not.
    l = load_text(std::string(kCamera) + "light point { position <0, 5, 0> }\n");
    CHECK(messages(l->diags, l->sources, Severity::Warning).empty());
    l = load_text("sphere { center <0, 0, 0> radius 1" + kMat + "}\n", true);
    CHECK(messages(l->diags, l->sources, Severity::Warning).empty());
    l = load_text(std::string(kCamera) + "sphere { center <0, 0, 0> radius 0" + kMat + "}\n");
    CHECK(messages(l->diags, l->sources, Severity::Warning).empty());
}
