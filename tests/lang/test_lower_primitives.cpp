// Lowering of cylinders, cones, tori, discs and spot lights: their properties and defaults reach
// the spec, the rules joining two properties are errors at the later value, and the language's
// tables are the render tables (one statement of each field).
#include <catch2/catch.hpp>

#include "eval_helpers.h"
#include "lang/lower.h"
#include "render/params.h"

using namespace wsd::lang;
using namespace wsd::lang::test;

TEST_CASE("cylinder, cone, torus, disc and spot light properties reach the spec", "[lower][primitives]") {
    auto l = load_text(std::string(kCamera) +
                       "light spot { position <0, 5, 0>  look_at <1, 0, 0> }\n"
                       "light spot { position <0, 5, 0>  look_at <1, 0, 0>  angle 10  falloff 10  "
                       "color <1, 0.5, 0>  intensity 2 }\n"
                       "let m = material { }\n"
                       "cylinder { base <1, 2, 3>  cap <1, 5, 3>  radius 0.5  material m }\n"
                       "cone { base <0, 0, 0>  base_radius 2  cap <0, 0, 4>  cap_radius 0.5  open on  "
                       "material m }\n"
                       "torus { major 3  minor 4  translate <1, 0, 0>  material m }\n"
                       "disc { center <1, 1, 1>  normal <0, 0, 2>  radius 3  material m }\n"
                       "disc { center <1, 1, 1>  normal <0, 0, 2>  radius 3  hole 1  material m }\n");
    REQUIRE(l->errors().empty());
    const auto& spec = l->scene->spec;
    using wsd::render::LightKind;
    using wsd::render::ShapeKind;
    REQUIRE(spec.lights.size() == 2);
    CHECK(spec.lights[0].kind == LightKind::Spot);
    CHECK(spec.lights[0].look_at == glm::dvec3(1, 0, 0));
    CHECK(spec.lights[0].angle == 30);
    CHECK(spec.lights[0].falloff == 45);
    CHECK(spec.lights[0].color == glm::dvec3(1, 1, 1));
    CHECK(spec.lights[0].intensity == 1);
    CHECK(spec.lights[1].angle == 10);
    CHECK(spec.lights[1].falloff == 10);
    CHECK(spec.lights[1].intensity == 2);
    REQUIRE(spec.shapes.size() == 5);
    CHECK(spec.shapes[0].kind == ShapeKind::Cylinder);
    CHECK(spec.shapes[0].base == glm::dvec3(1, 2, 3));
    CHECK(spec.shapes[0].cap == glm::dvec3(1, 5, 3));
    CHECK(spec.shapes[0].radius == 0.5);
    CHECK_FALSE(spec.shapes[0].open);
    CHECK(spec.shapes[1].kind == ShapeKind::Cone);
    CHECK(spec.shapes[1].radius == 2);
    CHECK(spec.shapes[1].cap_radius == 0.5);
    CHECK(spec.shapes[1].open);
    CHECK(spec.shapes[2].kind == ShapeKind::Torus);
    CHECK(spec.shapes[2].major == 3);
    CHECK(spec.shapes[2].minor == 4);
    CHECK(spec.shapes[2].object_to_world[3][0] == 1);
    CHECK(spec.shapes[3].kind == ShapeKind::Disc);
    CHECK(spec.shapes[3].center == glm::dvec3(1, 1, 1));
    CHECK(spec.shapes[3].normal == glm::dvec3(0, 0, 2));
    CHECK(spec.shapes[3].hole == 0);
    CHECK(spec.shapes[4].hole == 1);
}

TEST_CASE("the primitives' tables list the documented fields, required ones without defaults",
          "[lower][primitives][defaults]") {
    using wsd::render::Element;
    auto names = [](Element e) {
        std::vector<std::string> out;
        for (const auto& f : wsd::render::element_table(e).fields) out.emplace_back(f.name);
        return out;
    };
    CHECK(names(Element::Cylinder) == std::vector<std::string>{"base", "cap", "radius", "open", "material"});
    CHECK(names(Element::Cone) ==
          std::vector<std::string>{"base", "base_radius", "cap", "cap_radius", "open", "material"});
    CHECK(names(Element::Torus) == std::vector<std::string>{"major", "minor", "material"});
    CHECK(names(Element::Disc) == std::vector<std::string>{"center", "normal", "radius", "hole", "material"});
    CHECK(names(Element::SpotLight) ==
          std::vector<std::string>{"position", "look_at", "color", "intensity", "angle", "falloff"});
    const auto& spot = wsd::render::element_table(Element::SpotLight);
    CHECK(wsd::render::default_text(spot, *spot.find("angle")) == "30");
    CHECK(wsd::render::default_text(spot, *spot.find("falloff")) == "45");
    CHECK(wsd::render::default_text(spot, *spot.find("look_at")) == "required");
    const auto& disc = wsd::render::element_table(Element::Disc);
    CHECK(wsd::render::default_text(disc, *disc.find("hole")) == "0");
    const auto& cyl = wsd::render::element_table(Element::Cylinder);
    CHECK(wsd::render::default_text(cyl, *cyl.find("open")) == "off");
}
