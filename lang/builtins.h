// Built-in functions (sin … srgb) and constants (pi, on, off, clock, frame). They live in a scope outside the
// file's own, so a `let` may shadow them. Each function checks its argument count and types and
// reports domain errors and non-finite results at the function's name.
#pragma once

#include <optional>
#include <string_view>
#include <vector>

#include "lang/ast.h"
#include "lang/diagnostics.h"
#include "lang/value.h"

namespace wsd::lang {

class ParamTable;

struct CallContext {
    const CallExpr& call;            // the call: its name_span, its argument expressions
    const std::vector<Value>& args;  // evaluated arguments, one per call.args
    Diagnostics& diags;
    const ParamTable* params;  // the --define values `param` reads (null: none given)
};

using BuiltinFn = std::optional<Value> (*)(const CallContext&);

struct Builtin {
    std::string_view name;
    int arity;
    BuiltinFn fn;
    int optional = 0;  // arguments that may follow the `arity` required ones
};

const std::vector<Builtin>& builtin_functions();
const Builtin* find_builtin(std::string_view name);

struct BuiltinConstant {
    std::string_view name;
    Value value;  // with an empty span
};
// The constants with a still's `clock` and `frame` (0 and 0); the interpreter replaces those two
// with the values of the frame it evaluates (AnimationTime).
const std::vector<BuiltinConstant>& builtin_constants();

// Where in an animation a scene is evaluated: `clock` and `frame` (wsd-language.md, Animation).
struct AnimationTime {
    double clock = 0;
    long long frame = 0;
};

// The sRGB transfer function, decoding: 0..1 encoded → 0..1 linear.
double srgb_to_linear(double c);

}  // namespace wsd::lang
