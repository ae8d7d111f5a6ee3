// Evaluated blocks: what the interpreter makes of a block (a settings, camera, light or object
// statement, or a `material`/`checker`/`perlin` expression) before lowering reads it — its spans
// and its items, each with its name and its values evaluated. Lowering (lang/lower.h) is a plain
// function of these: it never evaluates anything, so it needs no interpreter.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "lang/source.h"
#include "lang/value.h"
#include "render/params.h"

namespace wsd::lang {

struct EvaluatedValue {
    // Empty: failed to evaluate (already reported), not evaluated (its item was rejected by the
    // table first), or written where a bare word was expected but not an identifier.
    std::optional<Value> value;
    Span span;          // the value expression's
    bool word = false;  // a bare word (`kind marble`): `value` is the identifier's name, unevaluated
};

struct EvaluatedItem {
    std::string_view name;  // "" for a triangle's leading vertices
    Span name_span;
    uint32_t first = 0, count = 0;  // its values: EvaluatedBlock::values[first, first + count)
};

struct EvaluatedBlock {
    render::Element kind;  // the element its table describes (render::Element::Sphere, ...)
    Span keyword;          // the statement's keyword, or an expression's `material {` head
    Span open, close;
    std::vector<EvaluatedItem> items;
    std::vector<EvaluatedValue> values;  // every item's values, one per value written, in order

    std::span<const EvaluatedValue> values_of(const EvaluatedItem& item) const {
        return {values.data() + item.first, item.count};
    }
    // Appends an item with its values.
    void add(std::string_view name, Span name_span, std::vector<EvaluatedValue> item_values) {
        items.push_back({name, name_span, static_cast<uint32_t>(values.size()),
                         static_cast<uint32_t>(item_values.size())});
        for (EvaluatedValue& v : item_values) values.push_back(std::move(v));
    }
};

// A `material { ... }` value: its block as evaluated, every item a checked property of the
// material table (`base`, `texture` and `bump` among them, as material and texture values). The
// render::MaterialSpec is made from it (and its base's) by lower_material_spec when an object
// uses it, once per material value.
struct MaterialValue {
    EvaluatedBlock block;  // block.keyword is the `material {` that made it
    IncludeChain chain;    // where it was written
    // The value of a property written in this block (not inherited from `base`), or null.
    const Value* property(std::string_view name) const;
};

}  // namespace wsd::lang
