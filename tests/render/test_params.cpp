// The element tables of render/params.h: their defaults and access, and build_scene's validation
// against them (one SpecError per bad field, naming the field).
#include <catch2/catch.hpp>
#include <functional>
#include <string>
#include <vector>

#include "render/params.h"
#include "scene_builders.h"

namespace {

using namespace wsd::render;
using wsd::test::add_material;
using wsd::test::basic_scene;
using wsd::test::matte;
using wsd::test::point_light;
using wsd::test::sphere;

// The errors build_scene reports for the basic scene after `change`, as "field: message".
std::vector<std::string> field_errors(const std::function<void(SceneSpec&)>& change) {
    SceneSpec spec = basic_scene(8, 8);
    spec.lights.push_back(point_light({0, 5, -5}));
    spec.shapes.push_back(sphere({0, 0, 0}, 1, add_material(spec, matte(Color(1)))));
    change(spec);
    std::vector<SpecError> errors;
    CHECK_FALSE(build_scene(spec, errors, true, 1));
    std::vector<std::string> out;
    for (const SpecError& e : errors) out.push_back(std::string(e.field) + ": " + e.message);
    return out;
}

}  // namespace

TEST_CASE("element tables: defaults come from the spec structs, access reads and writes them", "[params]") {
    const ElementTable& settings = element_table(Element::Settings);
    CHECK(default_text(settings, *settings.find("width")) == "640");
    CHECK(default_text(settings, *settings.find("bailout")) == "0.001953125");
    CHECK(default_text(settings, *settings.find("adaptive_supersampling")) == "off");
    CHECK(default_text(settings, *settings.find("background")) == "<0, 0, 0>");
    const ElementTable& material = element_table(Element::Material);
    CHECK(default_text(material, *material.find("ambient")) == "settings.ambient");
    CHECK(default_text(element_table(Element::Sphere), *element_table(Element::Sphere).find("radius")) ==
          "required");
    for (int e = 0; e < kElementCount; ++e) {
        const ElementTable& t = element_table(static_cast<Element>(e));
        CHECK(t.element == static_cast<Element>(e));
        CHECK(!t.name.empty());
        for (const Field& f : t.fields) {
            INFO(t.name << " " << f.name);
            CHECK(!f.meaning.empty());
            CHECK(!default_text(t, f).empty());
            CHECK(bool(f.access.number) == bool(f.access.set_number));
            CHECK(bool(f.access.vec3) == bool(f.access.set_vec3));
        }
    }
    Settings s;
    settings.find("max_depth")->access.set_number(&s, 5);
    CHECK(s.max_depth == 5);
    LightSpec l;
    element_table(Element::AreaLight).find("color")->access.set_vec3(&l, Vec3(0.5, 1, 2));
    CHECK(l.color == Vec3(0.5, 1, 2));
    MaterialSpec m;
    CHECK_FALSE(material.find("ambient")->access.present(&m));
    material.find("ambient")->access.set_number(&m, 0.5);
    CHECK(m.ambient == 0.5);
}

TEST_CASE("element tables take their bounds from render/limits.h", "[params]") {
    const ElementTable& settings = element_table(Element::Settings);
    CHECK(settings.find("width")->range.hi == kMaxImageSide);
    CHECK(settings.find("supersamples")->range.hi == kMaxSupersamples);
    CHECK(settings.find("max_depth")->range.hi == kMaxDepth);
    CHECK(element_table(Element::AreaLight).find("samples")->range.hi == kMaxLightGridSide);
    CHECK(element_table(Element::Perlin).find("octaves")->range.hi == kMaxOctaves);
    CHECK(element_table(Element::PointLight).find("intensity")->range.hi == kMaxSingle);
}

TEST_CASE("a value against its field: ranges, integers, colours in single precision", "[params]") {
    const ElementTable& settings = element_table(Element::Settings);
    CHECK(number_problem(*settings.find("width"), 640) == std::nullopt);
    CHECK(number_problem(*settings.find("width"), 0) == "must be an integer from 1 to 100000, found 0");
    CHECK(number_problem(*settings.find("width"), 2.5) == "must be an integer from 1 to 100000, found 2.5");
    CHECK(number_problem(*settings.find("bailout"), 1) == "must be in [0, 1), found 1");
    CHECK(number_problem(*settings.find("ambient"), 1.0 / 0.0) == "must be a finite number, found inf");
    const Field& intensity = *element_table(Element::PointLight).find("intensity");
    CHECK(number_problem(intensity, -1) == "must be >= 0, found -1");
    CHECK(number_problem(intensity, 3e38) == std::nullopt);
    CHECK(number_problem(intensity, 1e39) == "is too large for single precision, found 1e+39");
    const Field& color = *element_table(Element::Material).find("color");
    CHECK(vec3_problem(color, Vec3(1, 0, 3e38)) == std::nullopt);
    CHECK(vec3_problem(color, Vec3(1, -1, 0)) == "must have components >= 0, found <1, -1, 0>");
    CHECK(vec3_problem(color, Vec3(1e39, 0, 0)) == "is too large for single precision, found <1e+39, 0, 0>");
    // Geometry is double precision: only finiteness.
    CHECK(vec3_problem(*element_table(Element::Sphere).find("center"), Vec3(1e300, 0, 0)) == std::nullopt);
    CHECK(light_radiance_problem(Vec3(1e20), 1e20).has_value());
    CHECK(reflection_transmission_problem(0.1 * 7, 0.3) == std::nullopt);  // rounding slack
    CHECK(reflection_transmission_problem(0.7, 0.5).has_value());
}

TEST_CASE("build_scene checks every element against its table and names the field", "[params]") {
    CHECK(field_errors([](SceneSpec& s) { s.shapes[0].radius = -1; }) ==
          std::vector<std::string>{"radius: sphere 'radius' must be > 0, found -1"});
    CHECK(field_errors([](SceneSpec& s) { s.settings.width = 0; }) ==
          std::vector<std::string>{"width: settings 'width' must be an integer from 1 to 100000, found 0"});
    CHECK(field_errors([](SceneSpec& s) { s.settings.width = s.settings.height = 100000; }) ==
          std::vector<std::string>{
              "height: image size 100000 x 100000 exceeds the limit of 268435456 pixels (2^28)"});
    CHECK(field_errors([](SceneSpec& s) { s.camera.fov_degrees = 180; }) ==
          std::vector<std::string>{"fov: camera 'fov' must be in (0, 180), found 180"});
    CHECK(field_errors([](SceneSpec& s) { s.lights[0].color = Color(1e39, 1, 1); }) ==
          std::vector<std::string>{
              "color: light point 'color' is too large for single precision, found <1e+39, 1, 1>"});
    CHECK(field_errors([](SceneSpec& s) {
              s.materials[0].reflection = 0.7;
              s.materials[0].transmission = 0.5;
          }) == std::vector<std::string>{
                    "transmission: 'reflection' + 'transmission' must not exceed 1, found 0.7 + 0.5"});
    CHECK(field_errors([](SceneSpec& s) {
              TextureSpec t;
              t.color2 = Color(0, -1, 0);
              s.materials[0].texture = t;
          }) ==
          std::vector<std::string>{"colors: checker 'colors' must have components >= 0, found <0, -1, 0>"});
    CHECK(field_errors([](SceneSpec& s) {
              s.lights[0].kind = LightKind::Area;
              s.lights[0].u = Vec3(1, 0, 0);
              s.lights[0].v = Vec3(0, 0, 1);
              s.lights[0].samples_u = s.lights[0].samples_v = 1024;
          }) == std::vector<std::string>{
                    "samples: area light has 1024 x 1024 samples, more than the limit of 65536"});
    // A triangle's vertices have no access of their own but the same rule.
    CHECK(field_errors([](SceneSpec& s) {
              s.shapes[0].kind = ShapeKind::Triangle;
              s.shapes[0].v[1] = Vec3(0, 1.0 / 0.0, 0);
          }) == std::vector<std::string>{"vertices: triangle vertex must be finite, found <0, inf, 0>"});
}
