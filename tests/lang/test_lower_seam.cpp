// The seam between evaluation and lowering: evaluated blocks built by hand, checked against their
// tables and lowered to render specs with no interpreter and no parser (only lang/lower.h).
#include <catch2/catch.hpp>

#include "lang/lower.h"

using namespace wsd::lang;

namespace {

Span at(uint32_t begin, uint32_t end) {
    return Span{0, begin, end};
}

struct HandItem {
    std::string_view name;
    Span name_span;
    std::vector<EvaluatedValue> values;
};

// An item `name value` whose name is written at [10k, 10k+5) and its value at [10k+6, 10k+9).
HandItem item(std::string_view name, Value value, uint32_t k) {
    const Span value_span = at(10 * k + 6, 10 * k + 9);
    value.set_span(value_span);
    return {name, at(10 * k, 10 * k + 5), {{std::move(value), value_span, false}}};
}

EvaluatedBlock block(wsd::render::Element kind, std::vector<HandItem> items) {
    EvaluatedBlock b{kind, at(0, 6), at(7, 8), at(900, 901), {}, {}};
    for (HandItem& i : items) b.add(i.name, i.name_span, std::move(i.values));
    return b;
}

MaterialPtr material(Diagnostics& diags, std::vector<HandItem> items) {
    SourceManager sources;
    BlockContext ctx{sources, diags, nullptr};
    BlockReader r(block_table("material"), block(wsd::render::Element::Material, std::move(items)), diags);
    return lower_material(r, ctx);
}

}  // namespace

TEST_CASE("a hand-built sphere block lowers to a shape and its material to a render spec", "[lower][seam]") {
    Diagnostics diags;
    SourceManager sources;
    MaterialPtr red = material(diags, {item("color", Value::make_vec3({1, 0, 0}, {}), 1)});
    REQUIRE(red);
    BlockReader r(
        block_table("sphere"),
        block(wsd::render::Element::Sphere, {item("center", Value::make_vec3({1, 2, 3}, {}), 1),
                                             item("radius", Value::make_number(2, {}), 2),
                                             item("material", Value::make_material(red, {}), 3),
                                             item("translate", Value::make_vec3({0, 1, 0}, {}), 4)}),
        diags);
    BlockContext ctx{sources, diags, nullptr};
    std::optional<LoweredObject> o = lower_object(r, ctx);
    REQUIRE(o);
    CHECK(diags.all().empty());
    CHECK(o->shape.center == glm::dvec3(1, 2, 3));
    CHECK(o->shape.radius == 2);
    CHECK(o->shape.object_to_world[3] == glm::dvec4(0, 1, 0, 1));
    CHECK(o->material == red);
    // The radius's value span is where the render field `radius` was written.
    bool radius_span = false;
    for (const FieldSpan& f : o->fields)
        if (f.table_field().name == "radius") radius_span = f.begin == 26 && f.end == 29;
    CHECK(radius_span);

    SceneBuilder builder;
    for (int i = 0; i < 3; ++i) builder.add_object(LoweredObject(*o), nullptr);
    LoweredScene scene = builder.finish();
    REQUIRE(scene.spec.materials.size() == 1);  // one material value: lowered once, shared
    CHECK(scene.spec.materials[0].color == glm::dvec3(1, 0, 0));
    CHECK(scene.spec.shapes.size() == 3);
}

TEST_CASE("a material's spec applies its base first, then its own properties, textures included",
          "[lower][seam]") {
    Diagnostics diags;
    SourceManager sources;
    BlockContext ctx{sources, diags, nullptr};
    BlockReader checker(block_table("checker"),
                        block(wsd::render::Element::Checker,
                              {{"colors",
                                at(10, 16),
                                {{Value::make_vec3({1, 1, 1}, at(17, 20)), at(17, 20), false},
                                 {Value::make_vec3({0, 0, 0}, at(22, 25)), at(22, 25), false}}}}),
                        diags);
    TexturePtr tex = lower_texture(checker, ctx);
    REQUIRE(tex);
    MaterialPtr base = material(diags, {item("color", Value::make_vec3({0, 0, 1}, {}), 1),
                                        item("texture", Value::make_texture(tex, {}), 2)});
    REQUIRE(base);
    MaterialPtr m = material(diags, {item("specular", Value::make_number(0.5, {}), 1),
                                     item("base", Value::make_material(base, {}), 2)});
    REQUIRE(m);
    CHECK(diags.all().empty());
    LoweredMaterial lowered = lower_material_spec(*m);
    CHECK(lowered.spec.color == glm::dvec3(0, 0, 1));
    CHECK(lowered.spec.specular == 0.5);
    REQUIRE(lowered.spec.texture);
    CHECK(lowered.texture == tex);
    CHECK(lowered.spec.texture->color1 == glm::dvec3(1, 1, 1));
    REQUIRE(lowered.fields.size() == 1);  // its own values only: `base` sets no render field
    CHECK(lowered.fields[0].table_field().name == "specular");
}

TEST_CASE("a hand-built block is checked against its table", "[lower][seam]") {
    Diagnostics diags;
    SourceManager sources;
    HandItem kind{"kind", at(10, 14), {{Value::make_string("marbel", at(15, 21)), at(15, 21), true}}};
    BlockReader r(
        block_table("perlin"),
        block(wsd::render::Element::Perlin, {item("scael", Value::make_number(2, {}), 3), std::move(kind),
                                             item("colors", Value::make_bool(true, {}), 4)}),
        diags);
    CHECK_FALSE(r.ok());
    std::vector<std::string> messages;
    for (const Diagnostic& d : diags.all())
        messages.push_back(d.message + (d.help.empty() ? "" : " / " + d.help[0]));
    CHECK(messages == std::vector<std::string>{
                          "unknown property 'scael' in perlin / did you mean 'scale'?",
                          "'kind' must be one of noise, turbulence, marble or wood / did you mean 'marble'?",
                          "'colors' takes 2 values, found 1",
                      });
}
