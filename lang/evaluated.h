// Evaluated blocks: what the interpreter makes of a block (a settings, camera, light or object
// statement, or a `material`/`checker`/`perlin` expression) before lowering reads it — its spans
// and its items, each with its name and its values evaluated. Lowering (lang/lower.h) is a plain
// function of these: it never evaluates anything, so it needs no interpreter.
#pragma once

#include <optional>
#include <string_view>
#include <vector>

#include "lang/source.h"
#include "lang/value.h"

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
    std::vector<EvaluatedValue> values;  // one per value written
};

struct EvaluatedBlock {
    Span keyword;  // the statement's keyword, or an expression's `material {` head
    Span open, close;
    std::vector<EvaluatedItem> items;
};

}  // namespace wsd::lang
