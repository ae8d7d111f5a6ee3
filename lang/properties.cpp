// The generic block reader: checks each item of a block against its property table (name, count,
// type, range) and collects transforms. Block-specific rules (required alternatives, cross-checks
// such as reflection + transmission <= 1) live with each block's lowering in lower.cpp.
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

const std::vector<std::string_view>& Property::words() const {
    static const std::vector<std::string_view> none;
    return field ? field->words : none;
}

const Property* BlockTable::find(std::string_view name) const {
    for (const Property& p : properties)
        if (p.name == name) return &p;
    return nullptr;
}

BlockReader::BlockReader(const BlockTable& table, const Block& block, Span keyword, Diagnostics& diags,
                         const EvalFn& eval)
    : table_(table), keyword_(keyword), diags_(diags), eval_(eval), slots_(table.properties.size()) {
    for (const Item& item : block.items) {
        if (diags_.too_many()) {
            ok_ = false;
            return;
        }
        read_item(item);
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

void BlockReader::read_item(const Item& item) {
    if (table_.transforms && (item.name == "scale" || item.name == "rotate" || item.name == "translate")) {
        read_transform(item);
        return;
    }
    const Property* p = table_.find(item.name);
    if (!p) {
        if (item.name.empty()) {
            Span at = item.values.empty() ? item.name_span : item.values[0]->span;
            fail(at, "expected a property name in " + table_.what);
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
        ok_ = false;
        return;
    }
    Slot& s = slots_[static_cast<size_t>(p - table_.properties.data())];
    if (s.item) {
        Span at = item.name.empty() && !item.values.empty() ? item.values[0]->span : item.name_span;
        Span first =
            s.item->name.empty() && !s.item->values.empty() ? s.item->values[0]->span : s.item->name_span;
        Diagnostic& d = diags_.error(at, "repeated property " + quoted(item.name) + " in " + table_.what);
        d.notes.push_back({first, "first given here"});
        ok_ = false;
        return;
    }
    s.item = &item;
    if (!check_count(*p, item)) {
        ok_ = false;
        return;
    }
    bool valid = true;
    for (const Expr* e : item.values) {
        std::optional<Value> v = read_value(*p, *e);
        if (!v) {
            valid = false;
            continue;
        }
        s.values.push_back(std::move(*v));
    }
    s.valid = valid;
    if (!valid) {
        ok_ = false;
        s.values.clear();
    }
}

bool BlockReader::check_count(const Property& p, const Item& item) {
    int n = static_cast<int>(item.values.size());
    if (n >= p.min_values && n <= p.max_values) return true;
    std::string what = p.name.empty() ? table_.what : quoted(p.name);
    std::string wanted = p.min_values == p.max_values
                             ? std::to_string(p.min_values)
                             : std::to_string(p.min_values) + " or " + std::to_string(p.max_values);
    std::string noun = p.name.empty() ? " vertices" : (p.max_values == 1 ? " value" : " values");
    std::string message = what + " takes " + wanted + noun + ", found " + std::to_string(n);
    if (n > p.max_values)
        diags_.error(item.values[static_cast<size_t>(p.max_values)]->span, message);
    else
        diags_.error(item.name.empty() ? keyword_ : item.name_span, message);
    return false;
}

std::optional<Value> BlockReader::read_value(const Property& p, const Expr& expr) {
    if (p.type == PropType::Word) {
        // Enumerated values are bare words: read the identifier's name, never evaluate it.
        const std::string_view word = expr.kind == ExprKind::Ident ? expr.as<IdentExpr>().name : "";
        if (expr.kind != ExprKind::Ident ||
            std::find(p.words().begin(), p.words().end(), word) == p.words().end()) {
            Diagnostic& d =
                diags_.error(expr.span, quoted(p.name) + " must be one of " + join_words(p.words()));
            if (expr.kind == ExprKind::Ident) {
                std::vector<std::string> candidates(p.words().begin(), p.words().end());
                std::string match = closest_match(word, candidates);
                if (!match.empty()) d.help.push_back("did you mean '" + match + "'?");
            }
            return std::nullopt;
        }
        return Value::make_string(std::string(word), expr.span);
    }
    std::optional<Value> v = eval_(expr);
    if (!v) return std::nullopt;
    if (!check_value(p, *v, expr)) return std::nullopt;
    return v;
}

bool BlockReader::check_value(const Property& p, const Value& v, const Expr& expr) {
    auto name = [&] { return p.name.empty() ? "a vertex of " + table_.what : quoted(p.name); };
    if (!type_matches(p.type, v)) {
        diags_.error(expr.span,
                     name() + " must be " + expected_type(p.type) + ", found " + type_name(v.type()));
        return false;
    }
    if (!p.field) return true;
    std::optional<std::string> problem;
    if (v.is(ValueType::Number) && (p.type == PropType::Number || p.type == PropType::Integer))
        problem = render::number_problem(*p.field, v.number());
    else if (v.is(ValueType::Vector3))
        problem = render::vec3_problem(*p.field, v.vec3());
    if (!problem) return true;
    diags_.error(expr.span, name() + " " + *problem);
    return false;
}

void BlockReader::read_transform(const Item& item) {
    Property p{item.name, item.name == "scale" ? PropType::NumberOrVector3 : PropType::Vector3};
    if (!check_count(p, item)) {
        ok_ = false;
        return;
    }
    const Expr& expr = *item.values[0];
    std::optional<Value> v = eval_(expr);
    if (!v) {
        ok_ = false;
        return;
    }
    if (!check_value(p, *v, expr)) {
        ok_ = false;
        return;
    }
    Transform t{TransformKind::Translate, {0, 0, 0}, expr.span};
    if (item.name == "scale") {
        t.kind = TransformKind::Scale;
        t.v = v->is(ValueType::Number) ? glm::dvec3(v->number()) : v->vec3();
        for (int i = 0; i < 3; ++i) {
            double m = std::fabs(t.v[i]);
            if (m < render::kMinScale || m > render::kMaxScale) {
                fail(expr.span,
                     "'scale' factors must have a magnitude in [1e-12, 1e12], found " + describe(*v));
                return;
            }
        }
    } else {
        t.kind = item.name == "rotate" ? TransformKind::Rotate : TransformKind::Translate;
        t.v = v->vec3();
    }
    transforms_.push_back(t);
}

const std::vector<Value>& BlockReader::values(std::string_view name) const {
    static const std::vector<Value> none;
    const Slot* s = slot(name);
    return s && s->valid ? s->values : none;
}

const Value* BlockReader::value(std::string_view name) const {
    const std::vector<Value>& v = values(name);
    return v.empty() ? nullptr : &v[0];
}

Span BlockReader::value_span(std::string_view name, size_t i) const {
    const Slot* s = slot(name);
    if (!s || !s->item) return keyword_;
    if (i < s->item->values.size()) return s->item->values[i]->span;
    return s->item->name_span;
}

Span BlockReader::name_span(std::string_view name) const {
    const Slot* s = slot(name);
    return s && s->item ? s->item->name_span : keyword_;
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

void BlockReader::apply_fields(void* spec) const {
    for (size_t i = 0; i < slots_.size(); ++i) {
        const Slot& s = slots_[i];
        const render::Field* f = table_.properties[i].field;
        if (!s.valid || s.values.empty() || !f) continue;
        const Value& v = s.values[0];
        if (f->access.set_number && v.is(ValueType::Number)) f->access.set_number(spec, v.number());
        if (f->access.set_number && v.is(ValueType::Bool)) f->access.set_number(spec, v.boolean() ? 1 : 0);
        if (f->access.set_vec3 && v.is(ValueType::Vector3)) f->access.set_vec3(spec, v.vec3());
    }
}

std::vector<FieldSpan> BlockReader::field_spans() const {
    std::vector<FieldSpan> out;
    out.reserve(slots_.size());
    const render::Field* first = render::element_table(table_.element).fields.data();
    for (size_t i = 0; i < slots_.size(); ++i) {
        const render::Field* f = table_.properties[i].field;
        if (!slots_[i].item || !f) continue;
        const Span at = value_span(table_.properties[i].name);
        out.push_back({at.begin, at.end, table_.element, static_cast<uint8_t>(f - first)});
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
        fail(keyword_, table_.what + " needs its three vertices first");
    else
        fail(keyword_, "missing property " + quoted(name) + " in " + table_.what);
    return false;
}

}  // namespace wsd::lang
