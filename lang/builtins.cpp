// The built-in functions and constants. Argument types are checked here (errors at the argument),
// domain errors and non-finite results are reported at the function's name; the interpreter has
// already checked the argument count.
#include "lang/builtins.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "lang/params.h"

namespace wsd::lang {

double srgb_to_linear(double c) {
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

namespace {

// A number or a vector as up to three components; lets the component-wise functions share code.
struct Numeric {
    int dims = 0;  // 0 = number, 2 or 3 = vector
    glm::dvec3 v{0.0};
};

Numeric numeric(const Value& value) {
    if (value.is(ValueType::Number)) return {0, {value.number(), 0, 0}};
    if (value.is(ValueType::Vector2)) return {2, {value.vec2(), 0}};
    return {3, value.vec3()};
}

Value make_numeric(const Numeric& n, Span span) {
    if (n.dims == 0) return Value::make_number(n.v.x, span);
    if (n.dims == 2) return Value::make_vec2({n.v.x, n.v.y}, span);
    return Value::make_vec3(n.v, span);
}

std::string quoted_name(const CallContext& c) {
    std::string quoted = "'";
    quoted.append(c.call.name).append("'");
    return quoted;
}

void type_error(const CallContext& c, size_t i, const char* expected) {
    c.diags.error(c.call.args[i]->span,
                  quoted_name(c) + " expects " + expected + ", found " + type_name(c.args[i].type()));
}

bool want(const CallContext& c, size_t i, ValueType type) {
    if (c.args[i].is(type)) return true;
    type_error(c, i, (std::string("a ") + type_name(type)).c_str());
    return false;
}

bool want_numeric(const CallContext& c, size_t i) {
    const Value& a = c.args[i];
    if (a.is(ValueType::Number) || a.is_vector()) return true;
    type_error(c, i, "a number or a vector");
    return false;
}

bool want_vector(const CallContext& c, size_t i) {
    if (c.args[i].is_vector()) return true;
    type_error(c, i, "a vector");
    return false;
}

// Argument i must have the same type as argument 0 (min, max, clamp, mix, dot).
bool want_same(const CallContext& c, size_t i) {
    if (c.args[i].type() == c.args[0].type()) return true;
    c.diags.error(c.call.args[i]->span, quoted_name(c) + " expects a " + type_name(c.args[0].type()) +
                                            " like its first argument, found " + type_name(c.args[i].type()));
    return false;
}

std::optional<Value> finite(const CallContext& c, const Numeric& n) {
    bool ok = std::isfinite(n.v.x) && std::isfinite(n.v.y) && std::isfinite(n.v.z);
    if (!ok) {
        c.diags.error(c.call.name_span, "result of " + quoted_name(c) + " is not a finite number");
        return std::nullopt;
    }
    return make_numeric(n, c.call.span);
}

std::optional<Value> finite_number(const CallContext& c, double x) {
    return finite(c, Numeric{0, {x, 0, 0}});
}

std::optional<Value> domain_error(const CallContext& c, const std::string& message) {
    c.diags.error(c.call.name_span, message);
    return std::nullopt;
}

template <class F>
std::optional<Value> unary_number(const CallContext& c, F f) {
    if (!want(c, 0, ValueType::Number)) return std::nullopt;
    return finite_number(c, f(c.args[0].number()));
}

template <class F>
std::optional<Value> componentwise(const CallContext& c, F f) {
    if (!want_numeric(c, 0)) return std::nullopt;
    Numeric n = numeric(c.args[0]);
    n.v = {f(n.v.x), f(n.v.y), f(n.v.z)};
    return finite(c, n);
}

std::optional<Value> fn_sin(const CallContext& c) {
    return unary_number(c, [](double x) { return std::sin(x); });
}
std::optional<Value> fn_cos(const CallContext& c) {
    return unary_number(c, [](double x) { return std::cos(x); });
}
std::optional<Value> fn_tan(const CallContext& c) {
    return unary_number(c, [](double x) { return std::tan(x); });
}
std::optional<Value> fn_atan(const CallContext& c) {
    return unary_number(c, [](double x) { return std::atan(x); });
}
std::optional<Value> fn_exp(const CallContext& c) {
    return unary_number(c, [](double x) { return std::exp(x); });
}
std::optional<Value> fn_radians(const CallContext& c) {
    return unary_number(c, [](double x) { return x * (std::numbers::pi / 180.0); });
}
std::optional<Value> fn_degrees(const CallContext& c) {
    return unary_number(c, [](double x) { return x * (180.0 / std::numbers::pi); });
}

std::optional<Value> inverse_trig(const CallContext& c, double (*f)(double)) {
    if (!want(c, 0, ValueType::Number)) return std::nullopt;
    double x = c.args[0].number();
    if (x < -1.0 || x > 1.0)
        return domain_error(c,
                            quoted_name(c) + " of " + format_number(x) + " is undefined (outside [-1, 1])");
    return finite_number(c, f(x));
}
std::optional<Value> fn_asin(const CallContext& c) {
    return inverse_trig(c, [](double x) { return std::asin(x); });
}
std::optional<Value> fn_acos(const CallContext& c) {
    return inverse_trig(c, [](double x) { return std::acos(x); });
}

std::optional<Value> fn_atan2(const CallContext& c) {
    if (!want(c, 0, ValueType::Number) || !want(c, 1, ValueType::Number)) return std::nullopt;
    return finite_number(c, std::atan2(c.args[0].number(), c.args[1].number()));
}

std::optional<Value> fn_sqrt(const CallContext& c) {
    if (!want(c, 0, ValueType::Number)) return std::nullopt;
    double x = c.args[0].number();
    if (x < 0) return domain_error(c, "'sqrt' of a negative number (" + format_number(x) + ")");
    return finite_number(c, std::sqrt(x));
}

std::optional<Value> fn_log(const CallContext& c) {
    if (!want(c, 0, ValueType::Number)) return std::nullopt;
    double x = c.args[0].number();
    if (x <= 0) return domain_error(c, "'log' of a number that is not positive (" + format_number(x) + ")");
    return finite_number(c, std::log(x));
}

std::optional<Value> fn_pow(const CallContext& c) {
    if (!want(c, 0, ValueType::Number) || !want(c, 1, ValueType::Number)) return std::nullopt;
    double x = c.args[0].number(), y = c.args[1].number();
    double r = std::pow(x, y);
    if (std::isnan(r))
        return domain_error(c, "'pow(" + format_number(x) + ", " + format_number(y) + ")' has no real value");
    return finite_number(c, r);
}

std::optional<Value> fn_abs(const CallContext& c) {
    return componentwise(c, [](double x) { return std::fabs(x); });
}
std::optional<Value> fn_floor(const CallContext& c) {
    return componentwise(c, [](double x) { return std::floor(x); });
}
std::optional<Value> fn_ceil(const CallContext& c) {
    return componentwise(c, [](double x) { return std::ceil(x); });
}
// std::round rounds halves away from zero, as the language requires.
std::optional<Value> fn_round(const CallContext& c) {
    return componentwise(c, [](double x) { return std::round(x); });
}

std::optional<Value> min_max(const CallContext& c, bool is_min) {
    if (!want_numeric(c, 0) || !want_same(c, 1)) return std::nullopt;
    Numeric a = numeric(c.args[0]), b = numeric(c.args[1]);
    a.v = is_min ? glm::min(a.v, b.v) : glm::max(a.v, b.v);
    return finite(c, a);
}
std::optional<Value> fn_min(const CallContext& c) {
    return min_max(c, true);
}
std::optional<Value> fn_max(const CallContext& c) {
    return min_max(c, false);
}

std::optional<Value> fn_clamp(const CallContext& c) {
    if (!want_numeric(c, 0) || !want_same(c, 1) || !want_same(c, 2)) return std::nullopt;
    Numeric x = numeric(c.args[0]), lo = numeric(c.args[1]), hi = numeric(c.args[2]);
    for (int i = 0; i < 3; ++i) {
        if (lo.v[i] > hi.v[i])
            return domain_error(c, "'clamp' needs lo <= hi, found lo " + describe(c.args[1]) + " and hi " +
                                       describe(c.args[2]));
    }
    x.v = glm::min(glm::max(x.v, lo.v), hi.v);
    return finite(c, x);
}

std::optional<Value> fn_mix(const CallContext& c) {
    if (!want_numeric(c, 0) || !want_same(c, 1) || !want(c, 2, ValueType::Number)) return std::nullopt;
    Numeric a = numeric(c.args[0]), b = numeric(c.args[1]);
    double t = c.args[2].number();
    a.v = a.v * (1.0 - t) + b.v * t;
    return finite(c, a);
}

std::optional<Value> fn_length(const CallContext& c) {
    if (!want_vector(c, 0)) return std::nullopt;
    return finite_number(c, glm::length(numeric(c.args[0]).v));
}

std::optional<Value> fn_normalize(const CallContext& c) {
    if (!want_vector(c, 0)) return std::nullopt;
    Numeric n = numeric(c.args[0]);
    double len = glm::length(n.v);
    if (len == 0) return domain_error(c, "'normalize' of a zero vector");
    n.v /= len;
    return finite(c, n);
}

std::optional<Value> fn_dot(const CallContext& c) {
    if (!want_vector(c, 0) || !want_same(c, 1)) return std::nullopt;
    return finite_number(c, glm::dot(numeric(c.args[0]).v, numeric(c.args[1]).v));
}

std::optional<Value> fn_cross(const CallContext& c) {
    if (!want(c, 0, ValueType::Vector3) || !want(c, 1, ValueType::Vector3)) return std::nullopt;
    return finite(c, Numeric{3, glm::cross(c.args[0].vec3(), c.args[1].vec3())});
}

std::optional<Value> fn_len(const CallContext& c) {
    if (!want(c, 0, ValueType::List)) return std::nullopt;
    return Value::make_number(static_cast<double>(c.args[0].list().size()), c.call.span);
}

std::optional<Value> colour(const CallContext& c, double full_scale) {
    glm::dvec3 rgb{0.0};
    for (size_t i = 0; i < 3; ++i) {
        if (!want(c, i, ValueType::Number)) return std::nullopt;
        double x = c.args[i].number();
        if (x < 0 || x > full_scale) {
            c.diags.error(c.call.args[i]->span, quoted_name(c) + " components must be in [0, " +
                                                    format_number(full_scale) + "], found " +
                                                    format_number(x));
            return std::nullopt;
        }
        rgb[static_cast<int>(i)] = srgb_to_linear(x / full_scale);
    }
    return finite(c, Numeric{3, rgb});
}
std::optional<Value> fn_rgb(const CallContext& c) {
    return colour(c, 255.0);
}
std::optional<Value> fn_srgb(const CallContext& c) {
    return colour(c, 1.0);
}

// splitmix64's finaliser (with its increment): every input bit affects every output bit.
uint64_t mix64(uint64_t z) {
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

// The IEEE-754 bits of x, with -0 as 0 (and every NaN as one NaN, though values are never NaN).
uint64_t hash_bits(double x) {
    if (x == 0) return 0;
    if (std::isnan(x)) return 0x7ff8000000000000ULL;
    return std::bit_cast<uint64_t>(x);
}

// A hash of the arguments' bits, the same on every machine: each argument mixes in its number of
// components (1, 2 or 3), then each component; the top 53 bits become a number in [0, 1).
std::optional<Value> fn_random(const CallContext& c) {
    uint64_t h = 0;
    for (size_t i = 0; i < c.args.size(); ++i) {
        if (!want_numeric(c, i)) return std::nullopt;
        const Numeric n = numeric(c.args[i]);
        const int count = n.dims == 0 ? 1 : n.dims;
        h = mix64(h ^ static_cast<uint64_t>(count));
        for (int k = 0; k < count; ++k) h = mix64(h ^ hash_bits(n.v[k]));
    }
    return Value::make_number(static_cast<double>(h >> 11) * 0x1.0p-53, c.call.span);
}

}  // namespace

const std::vector<Builtin>& builtin_functions() {
    static const std::vector<Builtin> table = {
        {"sin", 1, fn_sin},
        {"cos", 1, fn_cos},
        {"tan", 1, fn_tan},
        {"asin", 1, fn_asin},
        {"acos", 1, fn_acos},
        {"atan", 1, fn_atan},
        {"atan2", 2, fn_atan2},
        {"sqrt", 1, fn_sqrt},
        {"pow", 2, fn_pow},
        {"exp", 1, fn_exp},
        {"log", 1, fn_log},
        {"abs", 1, fn_abs},
        {"floor", 1, fn_floor},
        {"ceil", 1, fn_ceil},
        {"round", 1, fn_round},
        {"min", 2, fn_min},
        {"max", 2, fn_max},
        {"clamp", 3, fn_clamp},
        {"mix", 3, fn_mix},
        {"radians", 1, fn_radians},
        {"degrees", 1, fn_degrees},
        {"length", 1, fn_length},
        {"normalize", 1, fn_normalize},
        {"dot", 2, fn_dot},
        {"cross", 2, fn_cross},
        {"len", 1, fn_len},
        {"rgb", 3, fn_rgb},
        {"srgb", 3, fn_srgb},
        {"param", 2, builtin_param},
        {"random", 1, fn_random, 2},
    };
    return table;
}

const Builtin* find_builtin(std::string_view name) {
    for (const Builtin& b : builtin_functions())
        if (b.name == name) return &b;
    return nullptr;
}

const std::vector<BuiltinConstant>& builtin_constants() {
    static const std::vector<BuiltinConstant> table = {
        {"pi", Value::make_number(std::numbers::pi, Span{})},
        {"on", Value::make_bool(true, Span{})},
        {"off", Value::make_bool(false, Span{})},
        {"clock", Value::make_number(0, Span{})},
        {"frame", Value::make_number(0, Span{})},
    };
    return table;
}

}  // namespace wsd::lang
