// Object values, groups, instances and CSG, checked on the lowered render::SceneSpec: values add
// nothing until added; statement-level groups flatten with composed transforms; `object` of a group
// or a mesh shares one prototype per distinct value; nested instances become top-level instances;
// material inheritance (own, innermost enclosing, default_material) and kInheritMaterial; CSG
// members, solids and their errors; `wsd check`'s counts as instanced and as stored.
#include <catch2/catch.hpp>

#include "eval_helpers.h"
#include "lang/lower.h"

using namespace wsd::lang;
using namespace wsd::lang::test;
using wsd::render::kInheritMaterial;
using wsd::render::ShapeKind;
using wsd::render::ShapeSpec;

namespace {

const std::string kHead =
    std::string(kCamera) +
    "let red = material { color <1, 0, 0> }\n"
    "let blue = material { color <0, 0, 1> }\n"
    "let green = material { color <0, 1, 0> }  let tri = triangle { <0, 0, 0>, <1, 0, 0>, <0, 1, 0> }\n";

// A closed tetrahedron, consistently oriented.
const std::string kTetra =
    "mesh { vertices [<0, 0, 0>, <1, 0, 0>, <0, 1, 0>, <0, 0, 1>]\n"
    "       faces [<0, 2, 1>, <0, 1, 3>, <0, 3, 2>, <1, 2, 3>] ";

std::unique_ptr<Loaded> load(const std::string& body) {
    auto l = load_text(kHead + body);
    INFO(format_diagnostics(l->diags, l->sources));
    return l;
}

const wsd::render::SceneSpec& spec_of(const Loaded& l) {
    REQUIRE(l.scene.has_value());
    return l.scene->spec;
}

// The material a shape shows, by its colour's red, green and blue (kInheritMaterial: "inherit").
std::string colour(const wsd::render::SceneSpec& spec, uint32_t material) {
    if (material == kInheritMaterial) return "inherit";
    REQUIRE(material < spec.materials.size());
    const glm::dvec3 c = spec.materials[material].color;
    return c == glm::dvec3(1, 0, 0)   ? "red"
           : c == glm::dvec3(0, 0, 1) ? "blue"
           : c == glm::dvec3(0, 1, 0) ? "green"
                                      : "other";
}

glm::dvec3 apply(const wsd::render::Mat4& m, glm::dvec3 p) {
    return glm::dvec3(m * glm::dvec4(p, 1.0));
}

}  // namespace

TEST_CASE("an object block written as a value adds nothing until it is added", "[objects]") {
    auto e = evaluate_text(kHead +
                           "let ball = sphere { center <0, 0, 0>  radius 1 }\n"
                           "let pair = group { sphere { center <0, 0, 0>  radius 1 }  material red }\n");
    CHECK(e->errors().empty());
    REQUIRE(e->get("ball"));
    CHECK(e->get("ball")->is(ValueType::Object));
    CHECK(type_name(e->get("pair")->type()) == std::string("object"));
    CHECK(e->scene.spec.shapes.empty());
}

TEST_CASE("a group added as a statement is flattened, the members' transforms first", "[objects]") {
    auto l = load(
        "group {\n"
        "    sphere { center <0, 0, 0>  radius 1  translate <1, 0, 0> }\n"
        "    box { min <0, 0, 0>  max <1, 1, 1>  material blue }\n"
        "    scale 2  translate <0, 1, 0>  material red\n"
        "}\n");
    const auto& spec = spec_of(*l);
    REQUIRE(spec.shapes.size() == 2);
    CHECK(spec.prototypes.empty());
    CHECK(spec.shapes[0].kind == ShapeKind::Sphere);
    CHECK(apply(spec.shapes[0].object_to_world, {0, 0, 0}) == glm::dvec3(2, 1, 0));
    CHECK(colour(spec, spec.shapes[0].material) == "red");   // the group's
    CHECK(colour(spec, spec.shapes[1].material) == "blue");  // its own
    CHECK(l->scene->summary.objects == 2);
    CHECK(l->scene->summary.instances == 0);
}

TEST_CASE("1000 objects of one group share one prototype", "[objects]") {
    auto l = load(
        "let tree = group { sphere { center <0, 2, 0>  radius 1 }  box { min <0, 0, 0>  max <1, 1, 1> } }\n"
        "for i in 0 .. 1000 { object tree { translate <i, 0, 0>  material green } }\n");
    const auto& spec = spec_of(*l);
    REQUIRE(spec.prototypes.size() == 1);
    CHECK(spec.prototypes[0].shapes.size() == 2);
    REQUIRE(spec.shapes.size() == 1000);
    for (const ShapeSpec& s : spec.shapes) {
        CHECK(s.kind == ShapeKind::Instance);
        CHECK(s.prototype == 0);
        CHECK(colour(spec, s.material) == "green");
    }
    CHECK(apply(spec.shapes[999].object_to_world, {0, 0, 0}) == glm::dvec3(999, 0, 0));
    for (const ShapeSpec& s : spec.prototypes[0].shapes) CHECK(s.material == kInheritMaterial);
    CHECK(l->scene->summary.objects == 2000);
    CHECK(l->scene->summary.instances == 1000);
    CHECK(l->scene->summary.stored_shapes == 2);
}

TEST_CASE("distinct values are distinct prototypes; each material variant of one value is shared",
          "[objects]") {
    auto l = load(
        "for i in 0 .. 3 { object group { sphere { center <0, 0, 0>  radius 1 } } { material red } }\n"
        "let g = group { sphere { center <0, 0, 0>  radius 1  material blue } }\n"
        "object g { material red }\n"
        "object g { }\n"
        "object g { material green }\n");
    const auto& spec = spec_of(*l);
    // Three loop values, and g once: its sphere has its own material, so what adds g does not matter.
    CHECK(spec.prototypes.size() == 4);
    REQUIRE(spec.shapes.size() == 6);
    CHECK(spec.shapes[3].prototype == spec.shapes[4].prototype);
    CHECK(spec.shapes[3].prototype == spec.shapes[5].prototype);
    CHECK(spec.shapes[3].material == kInheritMaterial);
}

TEST_CASE("material inheritance: own, then the innermost enclosing, then default_material", "[objects]") {
    auto l = load(
        "let default_material = material { color <0.5, 0.5, 0.5> }\n"
        "let inner = group { sphere { center <0, 0, 0>  radius 1 }  material blue }\n"
        "let outer = group {\n"
        "    object inner { }\n"                                       // blue: inner's own
        "    sphere { center <0, 0, 0>  radius 1 }\n"                  // the instance's (inherit)
        "    sphere { center <0, 0, 0>  radius 1  material green }\n"  // its own
        "    group { sphere { center <0, 0, 0>  radius 1 } }\n"        // the instance's (inherit)
        "}\n"
        "object outer { material red }\n"
        "object outer { }\n"  // no material given: default_material where each was written
        "sphere { center <0, 0, 0>  radius 1 }\n");
    const auto& spec = spec_of(*l);
    // outer's own geometry (3 spheres) in two variants, and inner's once (its material is its own).
    REQUIRE(spec.prototypes.size() == 3);
    const auto& with_red = spec.prototypes[spec.shapes[0].prototype].shapes;
    REQUIRE(with_red.size() == 3);
    CHECK(with_red[0].material == kInheritMaterial);
    CHECK(colour(spec, with_red[1].material) == "green");
    CHECK(with_red[2].material == kInheritMaterial);
    CHECK(colour(spec, spec.shapes[0].material) == "red");
    const auto& plain = spec.prototypes[spec.shapes[2].prototype].shapes;
    REQUIRE(plain.size() == 3);
    CHECK(colour(spec, plain[0].material) == "other");  // default_material
    CHECK(spec.shapes[2].material == kInheritMaterial);
    // The nested instance of inner, once per instance of outer, with inner's own material.
    CHECK(spec.shapes[1].kind == ShapeKind::Instance);
    CHECK(spec.shapes[1].prototype == spec.shapes[3].prototype);
    CHECK(colour(spec, spec.prototypes[spec.shapes[1].prototype].shapes[0].material) == "blue");
}

TEST_CASE("nested instances become top-level instances with composed transforms", "[objects]") {
    auto l = load("let leaf = " + kTetra + " material green }\n" +
                  "let branch = group { object leaf { translate <0, 2, 0> }  scale 2 }\n"
                  "let tree = group {\n"
                  "    box { min <0, 0, 0>  max <1, 1, 1>  material red }\n"
                  "    object branch { translate <10, 0, 0> }\n"
                  "}\n"
                  "object tree { translate <100, 0, 0> }\n");
    const auto& spec = spec_of(*l);
    for (const auto& p : spec.prototypes)
        for (const ShapeSpec& s : p.shapes) CHECK(s.kind != ShapeKind::Instance);
    // tree's box, and leaf's mesh (branch holds nothing but the instance of leaf).
    REQUIRE(spec.prototypes.size() == 2);
    REQUIRE(spec.shapes.size() == 2);
    CHECK(spec.prototypes[spec.shapes[0].prototype].shapes[0].kind == ShapeKind::Box);
    const ShapeSpec& leaf = spec.shapes[1];
    CHECK(spec.prototypes[leaf.prototype].shapes[0].kind == ShapeKind::Mesh);
    // leaf's translate, then branch's scale, then branch's instance, then tree's instance.
    CHECK(apply(leaf.object_to_world, {0, 0, 0}) == glm::dvec3(110, 4, 0));
    CHECK(apply(leaf.object_to_world, {1, 0, 0}) == glm::dvec3(112, 4, 0));
    CHECK(l->scene->summary.triangles == 4);
    CHECK(l->scene->summary.objects == 2);
}

TEST_CASE("an object of one primitive is copied flat, of a mesh is an instance", "[objects]") {
    auto l = load(
        "let ball = sphere { center <0, 0, 0>  radius 1 }\n"
        "object ball { material red  translate <3, 0, 0> }\n"
        "let tetra = " +
        kTetra + " }\n" + "object tetra { material blue }\n");
    const auto& spec = spec_of(*l);
    REQUIRE(spec.shapes.size() == 2);
    CHECK(spec.shapes[0].kind == ShapeKind::Sphere);
    CHECK(apply(spec.shapes[0].object_to_world, {0, 0, 0}) == glm::dvec3(3, 0, 0));
    CHECK(colour(spec, spec.shapes[0].material) == "red");
    CHECK(spec.shapes[1].kind == ShapeKind::Instance);
    CHECK(spec.prototypes.size() == 1);
}

TEST_CASE("CSG members keep their materials; one without takes the CSG's", "[objects]") {
    auto l = load(
        "difference {\n"
        "    box { min <-1, -1, -1>  max <1, 1, 1>  material red }\n"
        "    sphere { center <0, 0, 0>  radius 1.3 }\n"
        "    intersection { sphere { center <0, 0, 0>  radius 1 }  " +
        kTetra + " } material green }\n" +
        "    material blue  translate <0, 5, 0>\n"
        "}\n");
    const auto& spec = spec_of(*l);
    REQUIRE(spec.shapes.size() == 1);
    const ShapeSpec& csg = spec.shapes[0];
    CHECK(csg.kind == ShapeKind::Csg);
    CHECK(colour(spec, csg.material) == "blue");
    CHECK(apply(csg.object_to_world, {0, 0, 0}) == glm::dvec3(0, 5, 0));
    REQUIRE(csg.csg);
    CHECK(csg.csg->op == wsd::render::CsgOp::Difference);
    REQUIRE(csg.csg->members.size() == 3);
    CHECK(colour(spec, csg.csg->members[0].material) == "red");
    CHECK(csg.csg->members[1].material == kInheritMaterial);
    CHECK(csg.csg->members[1].object_to_world == wsd::render::Mat4(1.0));  // the CSG's frame
    const ShapeSpec& nested = csg.csg->members[2];
    CHECK(nested.kind == ShapeKind::Csg);
    CHECK(colour(spec, nested.material) == "green");
    REQUIRE(nested.csg->members.size() == 2);
    CHECK(nested.csg->members[0].material == kInheritMaterial);
    CHECK(l->scene->summary.objects == 1);
}

TEST_CASE("object instances in a CSG are expanded into members; a one-member difference is that member",
          "[objects]") {
    auto l = load(
        "let ball = sphere { center <0, 0, 0>  radius 1 }\n"
        "union { object ball { translate <1, 0, 0> }  object ball { material red } material blue }\n"
        "difference { object ball { scale 2 }  translate <0, 3, 0>  material green }\n");
    const auto& spec = spec_of(*l);
    REQUIRE(spec.shapes.size() == 2);
    REQUIRE(spec.shapes[0].kind == ShapeKind::Csg);
    const auto& members = spec.shapes[0].csg->members;
    REQUIRE(members.size() == 2);
    CHECK(members[0].kind == ShapeKind::Sphere);
    CHECK(apply(members[0].object_to_world, {0, 0, 0}) == glm::dvec3(1, 0, 0));
    CHECK(members[0].material == kInheritMaterial);
    CHECK(colour(spec, members[1].material) == "red");
    CHECK(spec.shapes[1].kind == ShapeKind::Sphere);
    CHECK(apply(spec.shapes[1].object_to_world, {1, 0, 0}) == glm::dvec3(2, 3, 0));
    CHECK(colour(spec, spec.shapes[1].material) == "green");
}

TEST_CASE("a CSG instanced under a material shares its members, which inherit", "[objects]") {
    auto l = load(
        "let lens = intersection { sphere { center <0, 0, 0>  radius 1 }  sphere { center <1, 0, 0>  radius "
        "1 } }\n"
        "object lens { material red }\n"
        "object lens { material blue  translate <0, 2, 0> }\n");
    const auto& spec = spec_of(*l);
    REQUIRE(spec.shapes.size() == 2);
    CHECK(spec.shapes[0].csg == spec.shapes[1].csg);
    CHECK(colour(spec, spec.shapes[0].material) == "red");
    CHECK(colour(spec, spec.shapes[1].material) == "blue");
    CHECK(spec.shapes[0].csg->members[0].material == kInheritMaterial);
}

TEST_CASE("CSG members must be solids", "[objects]") {
    auto errors = [](const std::string& body) { return load(body)->errors(); };
    CHECK(errors("union { sphere { center <0, 0, 0>  radius 1 }  object tri { }  material red }\n") ==
          std::vector<std::string>{"5:48: 'triangle' is not a solid; CSG needs closed shapes"});
    CHECK(errors("intersection { triangle { <0, 0, 0>, <1, 0, 0>, <0, 1, 0> }  material red }\n") ==
          std::vector<std::string>{"5:16: 'triangle' is not a solid; CSG needs closed shapes"});
    CHECK(errors("let g = group { sphere { center <0, 0, 0>  radius 1 } }\n"
                 "union { object g { }  material red }\n") ==
          std::vector<std::string>{"6:9: 'group' is not a solid; CSG needs closed shapes"});
    CHECK(errors("union { mesh { vertices [<0, 0, 0>, <1, 0, 0>, <0, 1, 0>]  faces [<0, 1, 2>] }  material "
                 "red }\n") ==
          std::vector<std::string>{"5:9: 'mesh' is not a solid; CSG needs closed shapes"});
    CHECK(errors("union { " + kTetra + "}  material red }\n").empty());
    CHECK(errors("difference { }\n") ==
          std::vector<std::string>{"5:1: empty 'difference': CSG needs at least one solid"});
    auto l = load("union { sphere { center <0, 0, 0>  radius 1 }  object tri { }  material red }\n");
    REQUIRE(!l->diags.all().empty());
    const Diagnostic& d = l->diags.all()[0];
    REQUIRE(d.notes.size() == 1);
    CHECK(where(l->sources, d.notes[0].span) == "5:1");
    CHECK(d.notes[0].message == "in this 'union'");
}

TEST_CASE("an object that reaches the scene without a material is an error with a note", "[objects]") {
    auto l = load(
        "let g = group {\n"
        "    sphere { center <0, 0, 0>  radius 1 }\n"
        "}\n"
        "object g { }\n");
    CHECK(l->errors() == std::vector<std::string>{"6:5: missing property 'material' in sphere"});
    REQUIRE(l->diags.all().size() >= 1);
    const Diagnostic& d = l->diags.all()[0];
    REQUIRE(d.notes.size() == 1);
    CHECK(where(l->sources, d.notes[0].span) == "8:1");
    // The same value given a material is fine.
    CHECK(load("let g = group { sphere { center <0, 0, 0>  radius 1 } }\nobject g { material red }\n")
              ->errors()
              .empty());
}

TEST_CASE("check counts as instanced, and what is stored", "[objects]") {
    auto l = load("let tetra = " + kTetra + " material red }\n" +
                  "plane { normal <0, 1, 0>  material blue }\n"
                  "for i in 0 .. 1000 { object tetra { translate <i, 0, 0> } }\n");
    REQUIRE(l->scene);
    const CheckSummary& s = l->scene->summary;
    CHECK(s.objects == 1001);
    CHECK(s.triangles == 4000);
    CHECK(s.instances == 1000);
    CHECK(s.stored_shapes == 2);
    CHECK(s.stored_triangles == 4);
}

TEST_CASE("the instance limit is its own, apart from stored primitives", "[objects]") {
    Limits limits;
    limits.instances = 10;
    limits.primitives = 100;
    auto e = evaluate_text(
        kHead + "let t = " + kTetra + " material red }\n" + "for i in 0 .. 10 { object t { } }\n", limits);
    CHECK(e->errors().empty());
    auto over = evaluate_text(
        kHead + "let t = " + kTetra + " material red }\n" + "for i in 0 .. 11 { object t { } }\n", limits);
    CHECK(over->errors() ==
          std::vector<std::string>{"7:20: the scene has more than 10 instances (the limit)"});
}

TEST_CASE("object values nest at most 1000 levels deep", "[objects]") {
    auto chain = [](int levels) {
        std::string text = kHead + "let v0 = sphere { center <0, 0, 0>  radius 1  material red }\n";
        for (int i = 1; i < levels; ++i)
            text += "let v" + std::to_string(i) + " = object v" + std::to_string(i - 1) + " { }\n";
        return text + "object v" + std::to_string(levels - 1) + " { }\n";
    };
    auto ok = load_text(chain(999));
    CHECK(ok->errors().empty());
    REQUIRE(ok->scene);
    CHECK(ok->scene->spec.shapes.size() == 1);
    auto deep = load_text(chain(1000));
    CHECK(deep->errors() ==
          std::vector<std::string>{
              "1005:1: object values nested too deep (the limit is 1000 levels of groups, CSG "
              "and instances)"});
}

TEST_CASE("an object statement in a group written as a statement adds a world instance", "[objects]") {
    auto l = load(
        "let tree = group { box { min <0, 0, 0>  max <1, 1, 1> } }\n"
        "group { object tree { translate <1, 0, 0> }  rotate <0, 90, 0>  translate <0, 1, 0>  material red "
        "}\n");
    const auto& spec = spec_of(*l);
    REQUIRE(spec.shapes.size() == 1);
    const ShapeSpec& s = spec.shapes[0];
    CHECK(s.kind == ShapeKind::Instance);
    CHECK(colour(spec, s.material) == "red");  // the enclosing group's, through the instance
    // translate <1, 0, 0>, then a quarter turn about y (x goes to -z), then translate <0, 1, 0>.
    CHECK(apply(s.object_to_world, {0, 0, 0}) == glm::dvec3(0, 1, -1));
    REQUIRE(l->scene->shape_spans.size() == 1);
    CHECK(where(l->sources, l->scene->shape_spans[0]) == "6:9");  // the `object` that added it
}

TEST_CASE("the primitive limit counts stored primitives: a prototype once", "[objects]") {
    Limits limits;
    limits.primitives = 10;
    // 4 triangles stored once, however often the mesh is instanced.
    auto shared = evaluate_text(
        kHead + "let t = " + kTetra + " material red }\n" + "for i in 0 .. 100 { object t { } }\n", limits);
    CHECK(shared->errors().empty());
    // A group written as a statement is stored once per statement: the third crosses the limit.
    auto flat =
        evaluate_text(kHead + "for i in 0 .. 3 { group { " + kTetra + " material red } } }\n", limits);
    CHECK(flat->errors() ==
          std::vector<std::string>{"5:19: the scene has more than 10 primitives (the limit; a "
                                   "mesh counts its triangles, stored once per distinct value)"});
}

TEST_CASE("an object of a closed mesh in a CSG is a member copy, not an instance", "[objects]") {
    auto l =
        load("let tetra = " + kTetra + " }\n" +
             "intersection { object tetra { translate <0, 0, 1> }  sphere { center <0, 0, 0>  radius 1 }  "
             "material red }\n");
    const auto& spec = spec_of(*l);
    CHECK(spec.prototypes.empty());
    REQUIRE(spec.shapes.size() == 1);
    const auto& members = spec.shapes[0].csg->members;
    REQUIRE(members.size() == 2);
    CHECK(members[0].kind == ShapeKind::Mesh);
    CHECK(apply(members[0].object_to_world, {0, 0, 0}) == glm::dvec3(0, 0, 1));
    CHECK(members[0].material == kInheritMaterial);
    CHECK(l->scene->summary.triangles == 4);
    CHECK(l->scene->summary.stored_triangles == 4);
}

TEST_CASE("instances that a recursion multiplies are refused before any is made", "[objects]") {
    Limits limits;
    limits.instances = 1000;
    const std::string fractal =
        "let ball = sphere { center <0, 0, 0>  radius 1 }\n"
        "fn f(d) {\n"
        "    if d == 0 { return ball }\n"
        "    let c = f(d - 1)\n"
        "    return group { object c { }  object c { translate <1, 0, 0> }  object c { translate <2, 0, 0> } "
        "}\n"
        "}\n";
    auto ok = evaluate_text(kHead + fractal + "object f(7) { material red }\n", limits);  // 3^6 instances
    CHECK(ok->errors().empty());
    CHECK(ok->scene.summary.instances == 729);
    auto over = evaluate_text(kHead + fractal + "object f(8) { material red }\n", limits);  // 3^7
    CHECK(over->errors() ==
          std::vector<std::string>{"11:1: the scene has more than 1000 instances (the limit)"});
    CHECK(over->scene.summary.instances == 0);
    // 3^59 instances: counted without making them (a saturating count), so this ends at once.
    auto huge = evaluate_text(kHead + fractal + "object f(60) { material red }\n", limits);
    CHECK(huge->errors() ==
          std::vector<std::string>{"11:1: the scene has more than 1000 instances (the limit)"});
}

TEST_CASE("a CSG that a recursion doubles is refused at the primitive limit, before it is copied",
          "[objects]") {
    Limits limits;
    limits.primitives = 1000;
    const std::string doubling =
        "let ball = sphere { center <0, 0, 0>  radius 1 }\n"
        "fn f(d) {\n"
        "    if d == 0 { return ball }\n"
        "    let c = f(d - 1)\n"
        "    return union { object c { }  object c { translate <0.1, 0, 0> } }\n"
        "}\n";
    CHECK(evaluate_text(kHead + doubling + "object f(9) { material red }\n", limits)->errors().empty());
    auto over = evaluate_text(kHead + doubling + "object f(60) { material red }\n", limits);
    REQUIRE(over->errors().size() == 1);
    CHECK(over->errors()[0] ==
          "9:12: this 'union' has more than 1000 primitives (the limit; nested CSG and instances in it are "
          "copies)");
}
