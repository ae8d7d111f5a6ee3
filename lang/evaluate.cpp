// Expression evaluation: literals, names (user scopes, then builtins), vectors and lists (packed
// lists shared, not copied), operators with the language's type rules, calls, members and
// indexing. Errors of binary operators point at the operator, of calls at the function's name.
#include <cmath>

#include "lang/builtins.h"
#include "lang/interpreter.h"
#include "render/math.h"
#include "render/text_util.h"

namespace wsd::lang {

namespace {

constexpr size_t kMaxStringLength = size_t(1) << 24;

using render::finite3;
using render::quoted;

// Vectors computed as three components; a vector2 keeps z = 0 and drops it again.
glm::dvec3 components(const Value& v) {
    return v.is(ValueType::Vector2) ? glm::dvec3(v.vec2(), 0.0) : v.vec3();
}

Value make_vector(ValueType type, glm::dvec3 v, Span span) {
    return type == ValueType::Vector2 ? Value::make_vec2({v.x, v.y}, span) : Value::make_vec3(v, span);
}

}  // namespace

std::optional<Value> Interpreter::eval(const Expr& expr) {
    DepthGuard guard(*this, expr.span);
    if (!guard.ok() || stopped()) return std::nullopt;
    switch (expr.kind) {
        case ExprKind::Number:
            return Value::make_number(expr.number, expr.span);
        case ExprKind::String:
            return Value::make_string(expr.text, expr.span);
        case ExprKind::Bool:
            return Value::make_bool(expr.boolean, expr.span);
        case ExprKind::Ident:
            return eval_ident(expr);
        case ExprKind::Vector:
            return eval_vector(expr);
        case ExprKind::List:
            return eval_list(expr);
        case ExprKind::PackedList: {
            if (!expr.packed) return std::nullopt;
            auto list = std::make_shared<ListValue>();
            list->packed = expr.packed;  // shared with the AST: a million vertices are not copied
            return Value::make_list(std::move(list), expr.span);
        }
        case ExprKind::Unary:
            return eval_unary(expr);
        case ExprKind::Binary:
            return eval_binary(expr);
        case ExprKind::Call:
            return eval_call(expr);
        case ExprKind::Member:
            return eval_member(expr);
        case ExprKind::Index:
            return eval_index(expr);
        case ExprKind::Material: {
            BlockContext ctx = context();
            MaterialPtr m = lower_material(expr, ctx);
            if (!m) return std::nullopt;
            Span span = m->span;
            return Value::make_material(std::move(m), span);
        }
        case ExprKind::Image:
        case ExprKind::Checker:
        case ExprKind::Perlin: {
            BlockContext ctx = context();
            TexturePtr t = lower_texture(expr, ctx);
            if (!t) return std::nullopt;
            return Value::make_texture(std::move(t), expr.span);
        }
        case ExprKind::Bad:
            return std::nullopt;  // the parser reported it
    }
    return std::nullopt;
}

std::optional<Value> Interpreter::eval_ident(const Expr& expr) {
    if (const Binding* b = find(expr.text)) return b->value;  // empty if its definition failed
    for (const BuiltinConstant& c : builtin_constants()) {
        if (c.name == expr.text) {
            Value v = c.value;
            v.set_span(expr.span);
            return v;
        }
    }
    if (find_builtin(expr.text)) {
        diags_.error(expr.span, quoted(expr.text) + " is a function: call it as " + expr.text + "(...)");
        return std::nullopt;
    }
    Diagnostic& d = diags_.error(expr.span, "unknown name " + quoted(expr.text));
    std::string match = closest_match(expr.text, visible_names());
    if (!match.empty()) d.help.push_back("did you mean '" + match + "'?");
    return std::nullopt;
}

std::optional<Value> Interpreter::eval_vector(const Expr& expr) {
    glm::dvec3 v(0.0);
    bool ok = true;
    const size_t n = expr.args.size();
    for (size_t i = 0; i < n && i < 3; ++i) {
        std::optional<Value> c = eval(*expr.args[i]);
        if (!c) {
            ok = false;
            continue;
        }
        if (!c->is(ValueType::Number)) {
            diags_.error(expr.args[i]->span,
                         std::string("vector components must be numbers, found ") + type_name(c->type()));
            ok = false;
            continue;
        }
        v[static_cast<int>(i)] = c->number();
    }
    if (!ok) return std::nullopt;
    if (n == 2) return Value::make_vec2({v.x, v.y}, expr.span);
    if (n == 3) return Value::make_vec3(v, expr.span);
    diags_.error(expr.span, "a vector has 2 or 3 components, found " + std::to_string(n));
    return std::nullopt;
}

std::optional<Value> Interpreter::eval_list(const Expr& expr) {
    auto list = std::make_shared<ListValue>();
    list->items.reserve(expr.args.size());
    bool ok = true;
    for (const ExprPtr& e : expr.args) {
        std::optional<Value> v = eval(*e);
        if (!v) {
            ok = false;
            if (stopped()) break;
            continue;
        }
        list->items.push_back(std::move(*v));
    }
    if (!ok) return std::nullopt;
    return Value::make_list(std::move(list), expr.span);
}

std::optional<Value> Interpreter::eval_unary(const Expr& expr) {
    if (expr.args.empty()) return std::nullopt;
    std::optional<Value> v = eval(*expr.args[0]);
    if (!v) return std::nullopt;
    if (expr.unary_op == UnaryOp::Not) {
        if (v->is(ValueType::Bool)) return Value::make_bool(!v->boolean(), expr.span);
        diags_.error(expr.op_span, std::string("operator '!' needs a bool, found ") + type_name(v->type()));
        return std::nullopt;
    }
    if (v->is(ValueType::Number)) return Value::make_number(-v->number(), expr.span);
    if (v->is_vector()) return make_vector(v->type(), -components(*v), expr.span);
    diags_.error(expr.op_span,
                 std::string("operator '-' needs a number or a vector, found ") + type_name(v->type()));
    return std::nullopt;
}

std::optional<Value> Interpreter::eval_logical(const Expr& expr) {
    // Short-circuit: the right operand runs only when it decides the result.
    const bool is_or = expr.binary_op == BinaryOp::Or;
    std::optional<Value> a = eval(*expr.args[0]);
    if (!a) return std::nullopt;
    if (!a->is(ValueType::Bool)) {
        diags_.error(expr.op_span, quoted(binary_op_text(expr.binary_op)) + " needs bools, found " +
                                       type_name(a->type()) + " on the left");
        return std::nullopt;
    }
    if (a->boolean() == is_or) return Value::make_bool(is_or, expr.span);
    std::optional<Value> b = eval(*expr.args[1]);
    if (!b) return std::nullopt;
    if (!b->is(ValueType::Bool)) {
        diags_.error(expr.op_span, quoted(binary_op_text(expr.binary_op)) + " needs bools, found " +
                                       type_name(b->type()) + " on the right");
        return std::nullopt;
    }
    return Value::make_bool(b->boolean(), expr.span);
}

std::optional<Value> Interpreter::eval_binary(const Expr& expr) {
    if (expr.args.size() != 2) return std::nullopt;
    if (expr.binary_op == BinaryOp::And || expr.binary_op == BinaryOp::Or) return eval_logical(expr);
    std::optional<Value> a = eval(*expr.args[0]);
    std::optional<Value> b = eval(*expr.args[1]);
    if (!a || !b) return std::nullopt;
    switch (expr.binary_op) {
        case BinaryOp::Eq:
        case BinaryOp::Ne:
        case BinaryOp::Lt:
        case BinaryOp::Le:
        case BinaryOp::Gt:
        case BinaryOp::Ge:
            return compare(expr, *a, *b);
        default:
            return arithmetic(expr, *a, *b);
    }
}

std::optional<Value> Interpreter::compare(const Expr& expr, const Value& a, const Value& b) {
    const BinaryOp op = expr.binary_op;
    const std::string sym = quoted(binary_op_text(op));
    if (op == BinaryOp::Eq || op == BinaryOp::Ne) {
        if (a.type() != b.type()) {
            diags_.error(expr.op_span, std::string("cannot compare ") + type_name(a.type()) + " with " +
                                           type_name(b.type()) + " using " + sym);
            return std::nullopt;
        }
        if (a.is(ValueType::List) || a.is(ValueType::Material) || a.is(ValueType::Texture)) {
            diags_.error(expr.op_span,
                         std::string("cannot compare ") + type_name(a.type()) + "s using " + sym);
            return std::nullopt;
        }
        bool equal = values_equal(a, b);
        return Value::make_bool(op == BinaryOp::Eq ? equal : !equal, expr.span);
    }
    if (!a.is(ValueType::Number) || !b.is(ValueType::Number)) {
        diags_.error(expr.op_span,
                     sym + " compares numbers, found " + type_name(a.type()) + " and " + type_name(b.type()));
        return std::nullopt;
    }
    const double x = a.number(), y = b.number();
    bool r = op == BinaryOp::Lt ? x < y : op == BinaryOp::Le ? x <= y : op == BinaryOp::Gt ? x > y : x >= y;
    return Value::make_bool(r, expr.span);
}

std::optional<Value> Interpreter::arithmetic(const Expr& expr, const Value& a, const Value& b) {
    const BinaryOp op = expr.binary_op;
    const std::string sym = quoted(binary_op_text(op));
    auto fail = [&](const std::string& message) -> std::optional<Value> {
        diags_.error(expr.op_span, message);
        return std::nullopt;
    };
    auto mismatch = [&]() {
        return fail("operator " + sym + " cannot combine " + type_name(a.type()) + " and " +
                    type_name(b.type()));
    };
    auto result = [&](ValueType type, glm::dvec3 v) -> std::optional<Value> {
        if (!finite3(v)) return fail("result of " + sym + " is not a finite number");
        if (type == ValueType::Number) return Value::make_number(v.x, expr.span);
        return make_vector(type, v, expr.span);
    };

    if (a.is(ValueType::String) && b.is(ValueType::String) && op == BinaryOp::Add) {
        if (a.string().size() + b.string().size() > kMaxStringLength)
            return fail("string longer than the limit of " + std::to_string(kMaxStringLength) + " bytes");
        return Value::make_string(a.string() + b.string(), expr.span);
    }
    if (a.is(ValueType::Number) && b.is(ValueType::Number)) {
        const double x = a.number(), y = b.number();
        switch (op) {
            case BinaryOp::Add:
                return result(ValueType::Number, {x + y, 0, 0});
            case BinaryOp::Sub:
                return result(ValueType::Number, {x - y, 0, 0});
            case BinaryOp::Mul:
                return result(ValueType::Number, {x * y, 0, 0});
            case BinaryOp::Div:
                if (y == 0) return fail("division by zero");
                return result(ValueType::Number, {x / y, 0, 0});
            case BinaryOp::Mod:
                if (y == 0) return fail("modulo by zero");
                return result(ValueType::Number, {std::fmod(x, y), 0, 0});
            default:
                return mismatch();
        }
    }
    if (a.is_vector() && a.type() == b.type()) {
        const glm::dvec3 x = components(a), y = components(b);
        const int dims = a.is(ValueType::Vector2) ? 2 : 3;
        switch (op) {
            case BinaryOp::Add:
                return result(a.type(), x + y);
            case BinaryOp::Sub:
                return result(a.type(), x - y);
            case BinaryOp::Mul:
                return result(a.type(), x * y);
            case BinaryOp::Div: {
                glm::dvec3 q(0.0);
                for (int i = 0; i < dims; ++i) {
                    if (y[i] == 0) return fail("division by zero (a component of the divisor is 0)");
                    q[i] = x[i] / y[i];
                }
                return result(a.type(), q);
            }
            default:
                return mismatch();
        }
    }
    if (a.is_vector() && b.is(ValueType::Number) && (op == BinaryOp::Mul || op == BinaryOp::Div)) {
        const double y = b.number();
        if (op == BinaryOp::Div && y == 0) return fail("division by zero");
        return result(a.type(), op == BinaryOp::Mul ? components(a) * y : components(a) / y);
    }
    if (a.is(ValueType::Number) && b.is_vector() && op == BinaryOp::Mul)
        return result(b.type(), a.number() * components(b));
    return mismatch();
}

std::optional<Value> Interpreter::eval_call(const Expr& expr) {
    const std::string& name = expr.text;
    if (const Binding* b = find(name)) {
        if (!b->value) return std::nullopt;
        Diagnostic& d = diags_.error(
            expr.op_span, quoted(name) + " is a " + type_name(b->value->type()) + ", not a function");
        d.notes.push_back({b->span, quoted(name) + " is defined here"});
        return std::nullopt;
    }
    const Builtin* f = find_builtin(name);
    if (!f) {
        for (const BuiltinConstant& c : builtin_constants()) {
            if (c.name == name) {
                diags_.error(expr.op_span,
                             quoted(name) + " is a " + type_name(c.value.type()) + ", not a function");
                return std::nullopt;
            }
        }
        Diagnostic& d = diags_.error(expr.op_span, "unknown function " + quoted(name));
        std::vector<std::string> names;
        for (const Builtin& g : builtin_functions()) names.emplace_back(g.name);
        std::string match = closest_match(name, names);
        if (!match.empty()) d.help.push_back("did you mean '" + match + "'?");
        return std::nullopt;
    }
    if (expr.args.size() != static_cast<size_t>(f->arity)) {
        diags_.error(expr.span, quoted(name) + " takes " + std::to_string(f->arity) +
                                    (f->arity == 1 ? " argument" : " arguments") + ", found " +
                                    std::to_string(expr.args.size()));
        return std::nullopt;
    }
    std::vector<Value> args;
    args.reserve(expr.args.size());
    bool ok = true;
    for (const ExprPtr& e : expr.args) {
        std::optional<Value> v = eval(*e);
        if (!v) {
            ok = false;
            continue;
        }
        args.push_back(std::move(*v));
    }
    if (!ok) return std::nullopt;
    return f->fn(CallContext{expr, args, diags_});
}

std::optional<Value> Interpreter::eval_member(const Expr& expr) {
    if (expr.args.empty()) return std::nullopt;
    std::optional<Value> v = eval(*expr.args[0]);
    if (!v) return std::nullopt;
    const std::string& field = expr.text;
    if (v->is(ValueType::Vector3)) {
        int i = field == "x" || field == "r"   ? 0
                : field == "y" || field == "g" ? 1
                : field == "z" || field == "b" ? 2
                                               : -1;
        if (i >= 0) return Value::make_number(v->vec3()[i], expr.span);
        diags_.error(expr.op_span,
                     "vector3 has no component " + quoted(field) + " (it has x, y, z and r, g, b)");
        return std::nullopt;
    }
    if (v->is(ValueType::Vector2)) {
        int i = field == "x" || field == "u" ? 0 : field == "y" || field == "v" ? 1 : -1;
        if (i >= 0) return Value::make_number(v->vec2()[i], expr.span);
        diags_.error(expr.op_span, "vector2 has no component " + quoted(field) + " (it has x, y and u, v)");
        return std::nullopt;
    }
    diags_.error(expr.op_span, quoted("." + field) + " needs a vector, found " + type_name(v->type()));
    return std::nullopt;
}

std::optional<Value> Interpreter::eval_index(const Expr& expr) {
    if (expr.args.size() != 2) return std::nullopt;
    std::optional<Value> base = eval(*expr.args[0]);
    std::optional<Value> index = eval(*expr.args[1]);
    if (!base || !index) return std::nullopt;
    if (!base->is(ValueType::List)) {
        diags_.error(expr.op_span, std::string("cannot index a ") + type_name(base->type()) +
                                       ": only lists can be indexed");
        return std::nullopt;
    }
    const Span at = expr.args[1]->span;
    if (!index->is(ValueType::Number)) {
        diags_.error(at, std::string("a list index must be a number, found ") + type_name(index->type()));
        return std::nullopt;
    }
    const double i = index->number();
    if (i != std::floor(i)) {
        diags_.error(at, "a list index must be an integer, found " + format_number(i));
        return std::nullopt;
    }
    const size_t size = base->list().size();
    if (i < 0 || i >= static_cast<double>(size)) {
        diags_.error(at, "index " + format_number(i) + " is out of range for a list of " +
                             std::to_string(size) + (size == 1 ? " element" : " elements"));
        return std::nullopt;
    }
    return base->list().at(static_cast<size_t>(i), sources_);
}

}  // namespace wsd::lang
