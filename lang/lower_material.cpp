// Lowering of checked material and texture blocks into values: `material { ... }` (with `base`
// applied first and the reflection + transmission <= 1 rule), `image "file"` (resolved relative to
// the file naming it), `checker { ... }` and `perlin { ... }`.
#include <cmath>

#include "lang/lower.h"

namespace wsd::lang {

namespace {

std::optional<render::PerlinKind> perlin_kind(std::string_view word) {
    if (word == "noise") return render::PerlinKind::Noise;
    if (word == "turbulence") return render::PerlinKind::Turbulence;
    if (word == "marble") return render::PerlinKind::Marble;
    if (word == "wood") return render::PerlinKind::Wood;
    return std::nullopt;
}

void read_colors(const BlockReader& r, render::TextureSpec& spec) {
    const std::vector<Value> colors = r.values("colors");
    if (colors.size() == 2) {
        spec.color1 = colors[0].vec3();
        spec.color2 = colors[1].vec3();
    }
}

}  // namespace

TexturePtr lower_image(const Value& path_value, Span path_span, BlockContext& ctx) {
    const Value* path = &path_value;
    if (!path->is(ValueType::String)) {
        ctx.diags.error(
            path_span, std::string("'image' needs a file name (a string), found ") + type_name(path->type()));
        return nullptr;
    }
    if (path->string().empty()) {
        ctx.diags.error(path_span, "'image' file name is empty");
        return nullptr;
    }
    auto t = std::make_shared<TextureValue>();
    t->spec.kind = render::TextureKind::Image;
    t->spec.image_path = resolve_path(ctx.sources, path_span.file, path->string());
    t->span = path_span;
    t->chain = ctx.chain;
    return t;
}

namespace {

TexturePtr lower_checker(BlockReader& r, BlockContext& ctx) {
    if (!r.ok()) return nullptr;
    auto t = std::make_shared<TextureValue>();
    t->spec.kind = render::TextureKind::Checker;
    r.apply(t->spec);
    read_colors(r, t->spec);
    t->fields = r.field_spans();
    t->span = r.keyword();
    t->chain = ctx.chain;
    return t;
}

TexturePtr lower_perlin(BlockReader& r, BlockContext& ctx) {
    auto t = std::make_shared<TextureValue>();
    t->spec.kind = render::TextureKind::Perlin;
    t->spec.perlin = perlin_kind(r.word("kind", "noise")).value_or(render::PerlinKind::Noise);
    if (const Value* scale = r.value("scale")) {
        if (scale->is(ValueType::Number)) {
            if (scale->number() <= 0)
                r.fail(r.value_span("scale"), "perlin 'scale' must be > 0, found " + describe(*scale));
            t->spec.perlin_scale = glm::dvec3(scale->number());
        } else {
            t->spec.perlin_scale = scale->vec3();
            if (auto problem = render::perlin_scale_problem(t->spec.perlin_scale))
                r.fail(r.value_span("scale"), "perlin 'scale' " + *problem);
        }
    }
    r.apply(t->spec);
    read_colors(r, t->spec);
    if (!r.ok()) return nullptr;
    t->fields = r.field_spans();
    t->span = r.keyword();
    t->chain = ctx.chain;
    return t;
}

}  // namespace

TexturePtr lower_texture(BlockReader& r, BlockContext& ctx) {
    return r.table().element == render::Element::Perlin ? lower_perlin(r, ctx) : lower_checker(r, ctx);
}

MaterialPtr lower_material(BlockReader& r, BlockContext& ctx) {
    // `base` first, wherever it is written: the other properties override it.
    const Value* base = r.value("base");
    render::MaterialSpec s = base ? lower_material_spec(*base->material()).spec : render::MaterialSpec{};
    r.apply(s);
    if (const Value* bump = r.value("bump")) {
        if (bump->texture()->spec.kind != render::TextureKind::Perlin) {
            const char* kind =
                bump->texture()->spec.kind == render::TextureKind::Image ? "an image" : "a checker";
            r.fail(r.value_span("bump"),
                   std::string("'bump' must be a perlin texture, found ") + kind + " texture");
        }
    }
    std::optional<std::string> sum_problem;
    if (r.ok()) sum_problem = render::reflection_transmission_problem(s.reflection, s.transmission);
    if (sum_problem) {
        // At the later of the two as written; a value inherited from `base` counts as earlier.
        bool has_r = r.has("reflection"), has_t = r.has("transmission");
        std::string later = has_r && (!has_t || written_after(r, "reflection", "transmission"))
                                ? "reflection"
                                : "transmission";
        std::string other = later == "reflection" ? "transmission" : "reflection";
        Diagnostic& d = ctx.diags.error(r.value_span(later), *sum_problem);
        Span other_span = r.has(other) ? r.value_span(other) : r.value_span("base");
        d.notes.push_back(
            {other_span, "'" + other + "' is " +
                             format_number(other == "reflection" ? s.reflection : s.transmission) +
                             (r.has(other) ? " here" : ", from 'base'")});
        r.failed();
    }
    if (!r.ok()) return nullptr;
    auto m = std::make_shared<MaterialValue>();
    m->block = std::move(r).take_block();
    m->chain = ctx.chain;
    return m;
}

LoweredMaterial lower_material_spec(const MaterialValue& material) {
    // The `base` chain, applied from its root: each block's properties override its base's.
    std::vector<const MaterialValue*> chain;
    for (const MaterialValue* m = &material; m;) {
        chain.push_back(m);
        const Value* base = m->property("base");
        m = base ? base->material().get() : nullptr;
    }
    LoweredMaterial out;
    const BlockTable& table = block_table("material");
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
        apply_block(table, (*it)->block, &out.spec);
        if (const Value* t = (*it)->property("texture")) out.texture = t->texture();
        if (const Value* b = (*it)->property("bump")) out.bump = b->texture();
    }
    if (out.texture) out.spec.texture = out.texture->spec;
    if (out.bump) out.spec.bump = out.bump->spec;
    out.fields = block_field_spans(table, material.block);
    return out;
}

const Value* MaterialValue::property(std::string_view name) const {
    for (const EvaluatedItem& item : block.items)
        if (item.name == name && item.count && block.values_of(item)[0].value)
            return &*block.values_of(item)[0].value;
    return nullptr;
}

}  // namespace wsd::lang
