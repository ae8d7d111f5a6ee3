// The block reader: checks each item of an evaluated block against its property table (name,
// count, word, type, range) and collects transforms. Block-specific rules (required alternatives,
// cross-checks such as reflection + transmission <= 1) live with each block's lowering in
// lower.cpp and lower_material.cpp.
#include "lang/properties.h"

#include <algorithm>
#include <cmath>

#include "render/text_util.h"

namespace wsd::lang {

namespace {

using render::quoted;

std::string join_words(const std::vector<std::string_view>& words) {
    std::string out;
    for (size_t i = 0; i < words.size(); ++i) {
        if (i) out += i + 1 == words.size() ? " or " : ", ";
        out += words[i];
    }
    return out;
}

bool type_matches(PropType t, const Value& v) {
    switch (t) {
        case PropType::Number:
        case PropType::Integer:
            return v.is(ValueType::Number);
        case PropType::Bool:
            return v.is(ValueType::Bool);
        case PropType::String:
            return v.is(ValueType::String);
        case PropType::Vector2:
            return v.is(ValueType::Vector2);
        case PropType::Vector3:
        case PropType::Colour:
            return v.is(ValueType::Vector3);
        case PropType::Material:
            return v.is(ValueType::Material);
        case PropType::Texture:
            return v.is(ValueType::Texture);
        case PropType::List:
            return v.is(ValueType::List);
        case PropType::NumberOrVector3:
            return v.is(ValueType::Number) || v.is(ValueType::Vector3);
        case PropType::Word:
            return false;
    }
    return false;
}

const std::vector<std::string_view> kTransformNames = {"scale", "rotate", "translate"};

Property transform_property(std::string_view name) {
    return {name, name == "scale" ? PropType::NumberOrVector3 : PropType::Vector3};
}

// POV-Ray's words for what wsd spells otherwise, answered wherever they are written as a property.
const std::pair<std::string_view, std::string_view> kPovRayWords[] = {
    {"pigment",
     "wsd has no 'pigment': write 'material { color <r, g, b> }' (or a 'texture' in the material)"},
    {"finish", "wsd has no 'finish': write ambient, diffuse, specular, reflection ... in 'material { ... }'"},
    {"light_source", "a light is a statement of its own: 'light point { position ... }'"},
    {"location", "a camera's eye point is its 'position'"},
    {"angle", "a camera's field of view is 'fov' (vertical, in degrees)"},
};

// Help for a name that belongs in an object's material.
std::optional<std::string> material_hint(std::string_view name) {
    if (name == "color" || name == "colour")
        return std::string("a colour belongs in a material: write 'material { color ... }'");
    if (name == "texture")
        return std::string("a texture belongs in a material: write 'material { texture ... }'");
    return std::nullopt;
}

}  // namespace

std::string expected_type(PropType t) {
    switch (t) {
        case PropType::Number:
            return "a number";
        case PropType::Integer:
            return "an integer";
        case PropType::Bool:
            return "a bool";
        case PropType::String:
            return "a string";
        case PropType::Vector2:
            return "a vector2";
        case PropType::Vector3:
            return "a vector3";
        case PropType::Colour:
            return "a colour (vector3)";
        case PropType::Material:
            return "a material";
        case PropType::Texture:
            return "a texture";
        case PropType::List:
            return "a list";
        case PropType::Word:
            return "a word";
        case PropType::NumberOrVector3:
            return "a number or a vector3";
    }
    return "a value";
}

const std::vector<std::string_view>& Property::words() const {
    static const std::vector<std::string_view> none;
    return field ? field->words : none;
}

const Property* BlockTable::find(std::string_view name) const {
    for (const Property& p : properties)
        if (p.name == name) return &p;
    return nullptr;
}

BlockReader::BlockReader(const BlockTable& table, Span keyword, Span open, Span close, Diagnostics& diags,
                         size_t items, size_t values)
    : table_(table),
      block_{table.element, keyword, open, close, {}, {}},
      diags_(diags),
      slots_(table.properties.size()) {
    block_.items.reserve(items);
    block_.values.reserve(values);
}

BlockReader::BlockReader(const BlockTable& table, const EvaluatedBlock& block, Diagnostics& diags)
    : BlockReader(table, block.keyword, block.open, block.close, diags, block.items.size(),
                  block.values.size()) {
    assert(block.kind == table.element);
    std::vector<Span> spans;
    for (const EvaluatedItem& item : block.items) {
        if (diags_.too_many()) {
            ok_ = false;
            return;
        }
        spans.clear();
        for (const EvaluatedValue& v : block.values_of(item)) spans.push_back(v.span);
        if (admit(item.name, item.name_span, spans) != ItemRead::Skip)
            for (const EvaluatedValue& v : block.values_of(item)) accept(v);
        end_item();
    }
}

void BlockReader::fail(Span span, std::string message) {
    diags_.error(span, std::move(message));
    ok_ = false;
}

const BlockReader::Slot* BlockReader::slot(std::string_view name) const {
    for (size_t i = 0; i < slots_.size(); ++i)
        if (table_.properties[i].name == name) return &slots_[i];
    return nullptr;
}

ItemRead BlockReader::admit(std::string_view name, Span name_span, std::span<const Span> value_spans) {
    block_.items.push_back({name, name_span, static_cast<uint32_t>(block_.values.size()),
                            static_cast<uint32_t>(value_spans.size())});
    for (Span v : value_spans) block_.values.push_back({std::nullopt, v, false});  // filled by accept
    const EvaluatedItem& it = block_.items.back();
    next_value_ = 0;
    current_ = nullptr;
    current_transform_ = false;
    if (table_.transforms && (it.name == "scale" || it.name == "rotate" || it.name == "translate")) {
        if (!check_count(transform_property(it.name), it)) {
            ok_ = false;
            return ItemRead::Skip;
        }
        current_transform_ = true;
        return ItemRead::Evaluate;
    }
    const Property* p = table_.find(it.name);
    if (!p) {
        report_unknown(it);
        return ItemRead::Skip;
    }
    Slot& s = slots_[static_cast<size_t>(p - table_.properties.data())];
    if (s.item >= 0) {
        const EvaluatedItem& prior = block_.items[static_cast<size_t>(s.item)];
        Span at = it.name.empty() && it.count ? values_of(it)[0].span : it.name_span;
        Span first = prior.name.empty() && prior.count ? values_of(prior)[0].span : prior.name_span;
        Diagnostic& d = diags_.error(at, "repeated property " + quoted(it.name) + " in " + table_.what);
        d.notes.push_back({first, "first given here"});
        ok_ = false;
        return ItemRead::Skip;
    }
    s.item = static_cast<int>(block_.items.size() - 1);
    if (!check_count(*p, it)) {
        ok_ = false;
        return ItemRead::Skip;
    }
    current_ = p;
    current_valid_ = true;
    return p->type == PropType::Word ? ItemRead::Words : ItemRead::Evaluate;
}

void BlockReader::accept(EvaluatedValue value) {
    const EvaluatedItem& item = block_.items.back();
    if (next_value_ >= item.count) return;
    EvaluatedValue& v = block_.values[item.first + next_value_++];
    v = std::move(value);
    if (current_transform_) {
        if (next_value_ == 1) read_transform(item);
        return;
    }
    if (!current_) return;
    bool good = current_->type == PropType::Word ? check_word(*current_, v)
                                                 : v.value && check_value(*current_, *v.value, v.span);
    if (!good) {
        current_valid_ = false;
        v.value.reset();
    }
}

void BlockReader::end_item() {
    if (current_) {
        Slot& s = slots_[static_cast<size_t>(current_ - table_.properties.data())];
        s.valid = current_valid_ && next_value_ == block_.items.back().count;
        if (!s.valid) ok_ = false;
    }
    current_ = nullptr;
    current_transform_ = false;
}

void BlockReader::report_unknown(const EvaluatedItem& item) {
    ok_ = false;
    if (item.name.empty()) {
        Span at = item.count ? values_of(item)[0].span : item.name_span;
        diags_.error(at, "expected a property name in " + table_.what);
        return;
    }
    Diagnostic& d =
        diags_.error(item.name_span, "unknown property " + quoted(item.name) + " in " + table_.what);
    std::vector<std::string> candidates;
    for (const Property& q : table_.properties)
        if (!q.name.empty()) candidates.emplace_back(q.name);
    if (table_.transforms)
        for (std::string_view t : kTransformNames) candidates.emplace_back(t);
    bool hinted = false;
    for (const auto& [name, hint] : table_.hints) {
        if (name == item.name) {
            d.help.push_back(hint);
            hinted = true;
        }
    }
    std::string match = hinted ? "" : closest_match(item.name, candidates);
    if (!match.empty()) {
        d.help.push_back("did you mean '" + match + "'?");
        suggested_.push_back(match);
    }
    for (const auto& [word, hint] : kPovRayWords)
        if (word == item.name) d.help.emplace_back(hint);
    if (table_.transforms && table_.find("material")) {
        if (auto hint = material_hint(item.name)) d.help.push_back(*hint);
    }
}

bool BlockReader::check_count(const Property& p, const EvaluatedItem& item) {
    int n = static_cast<int>(item.count);
    if (n >= p.min_values && n <= p.max_values) return true;
    std::string what = p.name.empty() ? table_.what : quoted(p.name);
    std::string wanted = p.min_values == p.max_values
                             ? std::to_string(p.min_values)
                             : std::to_string(p.min_values) + " or " + std::to_string(p.max_values);
    std::string noun = p.name.empty() ? " vertices" : (p.max_values == 1 ? " value" : " values");
    std::string message = what + " takes " + wanted + noun + ", found " + std::to_string(n);
    if (n > p.max_values)
        diags_.error(values_of(item)[static_cast<size_t>(p.max_values)].span, message);
    else
        diags_.error(item.name.empty() ? block_.keyword : item.name_span, message);
    return false;
}

// Enumerated values are bare words: the identifier's name, never evaluated.
bool BlockReader::check_word(const Property& p, const EvaluatedValue& v) {
    const std::string_view word = v.word && v.value ? std::string_view(v.value->string()) : "";
    if (v.word && v.value && std::find(p.words().begin(), p.words().end(), word) != p.words().end())
        return true;
    Diagnostic& d = diags_.error(v.span, quoted(p.name) + " must be one of " + join_words(p.words()));
    if (v.word) {
        std::vector<std::string> candidates(p.words().begin(), p.words().end());
        std::string match = closest_match(word, candidates);
        if (!match.empty()) d.help.push_back("did you mean '" + match + "'?");
    }
    return false;
}

bool BlockReader::check_value(const Property& p, const Value& v, Span at) {
    auto name = [&] { return p.name.empty() ? "a vertex of " + table_.what : quoted(p.name); };
    if (!type_matches(p.type, v)) {
        diags_.error(at, name() + " must be " + expected_type(p.type) + ", found " + type_name(v.type()));
        return false;
    }
    if (!p.field) return true;
    std::optional<std::string> problem;
    if (v.is(ValueType::Number) && (p.type == PropType::Number || p.type == PropType::Integer))
        problem = render::number_problem(*p.field, v.number());
    else if (v.is(ValueType::Vector3))
        problem = render::vec3_problem(*p.field, v.vec3());
    if (!problem) return true;
    diags_.error(at, name() + " " + *problem);
    return false;
}

void BlockReader::read_transform(const EvaluatedItem& item) {
    const EvaluatedValue& ev = values_of(item)[0];
    if (!ev.value || !check_value(transform_property(item.name), *ev.value, ev.span)) {
        ok_ = false;
        return;
    }
    const Value& v = *ev.value;
    Transform t{TransformKind::Translate, {0, 0, 0}, ev.span};
    if (item.name == "scale") {
        t.kind = TransformKind::Scale;
        t.v = v.is(ValueType::Number) ? glm::dvec3(v.number()) : v.vec3();
        for (int i = 0; i < 3; ++i) {
            double m = std::fabs(t.v[i]);
            static_assert(render::kMinScale == 1e-12 && render::kMaxScale == 1e12,
                          "the message below writes the bounds as 1e-12 and 1e12");
            if (m < render::kMinScale || m > render::kMaxScale) {
                fail(ev.span, "'scale' factors must have a magnitude in [1e-12, 1e12], found " + describe(v));
                return;
            }
        }
    } else {
        t.kind = item.name == "rotate" ? TransformKind::Rotate : TransformKind::Translate;
        t.v = v.vec3();
    }
    transforms_.push_back(t);
}

std::vector<Value> BlockReader::values(std::string_view name) const {
    std::vector<Value> out;
    const Slot* s = slot(name);
    if (s && s->valid)
        for (const EvaluatedValue& v : values_of(*item_of(s))) out.push_back(*v.value);
    return out;
}

const Value* BlockReader::value(std::string_view name) const {
    const Slot* s = slot(name);
    if (!s || !s->valid || !item_of(s)->count) return nullptr;
    return &*values_of(*item_of(s))[0].value;
}

Span BlockReader::value_span(std::string_view name, size_t i) const {
    const EvaluatedItem* item = item_of(slot(name));
    if (!item) return block_.keyword;
    if (i < item->count) return values_of(*item)[i].span;
    return item->name_span;
}

Span BlockReader::name_span(std::string_view name) const {
    const EvaluatedItem* item = item_of(slot(name));
    return item ? item->name_span : block_.keyword;
}

double BlockReader::number(std::string_view name, double fallback) const {
    const Value* v = value(name);
    return v ? v->number() : fallback;
}

long long BlockReader::integer(std::string_view name, long long fallback) const {
    const Value* v = value(name);
    return v ? static_cast<long long>(v->number()) : fallback;
}

bool BlockReader::boolean(std::string_view name, bool fallback) const {
    const Value* v = value(name);
    return v ? v->boolean() : fallback;
}

glm::dvec3 BlockReader::vec3(std::string_view name, glm::dvec3 fallback) const {
    const Value* v = value(name);
    return v ? v->vec3() : fallback;
}

std::string_view BlockReader::word(std::string_view name, std::string_view fallback) const {
    const Value* v = value(name);
    return v ? std::string_view(v->string()) : fallback;
}

namespace {

void set_field(const render::Field& f, const Value& v, void* spec) {
    if (f.access.set_number && v.is(ValueType::Number)) f.access.set_number(spec, v.number());
    if (f.access.set_number && v.is(ValueType::Bool)) f.access.set_number(spec, v.boolean() ? 1 : 0);
    if (f.access.set_vec3 && v.is(ValueType::Vector3)) f.access.set_vec3(spec, v.vec3());
}

FieldSpan field_span(const BlockTable& table, const render::Field& f, Span at) {
    const render::Field* first = render::element_table(table.element).fields.data();
    return {at.begin, at.end, table.element, static_cast<uint8_t>(&f - first)};
}

}  // namespace

void BlockReader::apply_fields(void* spec) const {
    for (size_t i = 0; i < slots_.size(); ++i) {
        const Slot& s = slots_[i];
        const render::Field* f = table_.properties[i].field;
        if (!s.valid || !f || !item_of(&s)->count) continue;
        set_field(*f, *values_of(*item_of(&s))[0].value, spec);
    }
}

std::vector<FieldSpan> BlockReader::field_spans() const {
    std::vector<FieldSpan> out;
    out.reserve(slots_.size());
    for (size_t i = 0; i < slots_.size(); ++i) {
        const render::Field* f = table_.properties[i].field;
        if (slots_[i].item < 0 || !f) continue;
        out.push_back(field_span(table_, *f, value_span(table_.properties[i].name)));
    }
    return out;
}

void apply_block(const BlockTable& table, const EvaluatedBlock& block, void* spec) {
    for (const EvaluatedItem& item : block.items) {
        const Property* p = table.find(item.name);
        if (p && p->field && item.count && block.values_of(item)[0].value)
            set_field(*p->field, *block.values_of(item)[0].value, spec);
    }
}

std::vector<FieldSpan> block_field_spans(const BlockTable& table, const EvaluatedBlock& block) {
    // In table order, as BlockReader::field_spans lists them.
    std::vector<FieldSpan> out;
    for (const Property& p : table.properties) {
        if (!p.field) continue;
        for (const EvaluatedItem& item : block.items) {
            if (item.name != p.name) continue;
            out.push_back(
                field_span(table, *p.field, item.count ? block.values_of(item)[0].span : item.name_span));
            break;
        }
    }
    return out;
}

bool BlockReader::suggested(std::string_view name) const {
    return std::find(suggested_.begin(), suggested_.end(), name) != suggested_.end();
}

bool BlockReader::require(std::string_view name) {
    if (has(name)) return true;
    if (suggested(name)) {
        ok_ = false;  // the unknown name that meant it is already reported
        return false;
    }
    if (name.empty())
        fail(block_.keyword, table_.what + " needs its three vertices first");
    else
        fail(block_.keyword, "missing property " + quoted(name) + " in " + table_.what);
    return false;
}

}  // namespace wsd::lang
