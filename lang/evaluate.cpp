// Expression evaluation: literals, names (user scopes, then builtins), vectors and lists (packed
// lists shared, not copied), operators with the language's type rules, calls, members and
// indexing. Errors of binary operators point at the operator, of calls at the function's name.
// Material and texture expressions are blocks: evaluate_block.cpp.
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
            return Value::make_number(expr.as<NumberExpr>().value, expr.span);
        case ExprKind::String:
            return Value::make_string(std::string(expr.as<StringExpr>().text), expr.span);
        case ExprKind::Bool:
            return Value::make_bool(expr.as<BoolExpr>().value, expr.span);
        case ExprKind::Ident:
            return eval_ident(expr.as<IdentExpr>());
        case ExprKind::Vector:
            return eval_vector(expr.as<VectorExpr>());
        case ExprKind::List:
            return eval_list(expr.as<ListExpr>());
        case ExprKind::PackedList: {
            auto list = std::make_shared<ListValue>();
            list->packed = expr.as<PackedListExpr>().packed;  // shared: a million vertices are not copied
            return Value::make_list(std::move(list), expr.span);
        }
        case ExprKind::Unary:
            return eval_unary(expr.as<UnaryExpr>());
        case ExprKind::Binary:
            return eval_binary(expr.as<BinaryExpr>());
        case ExprKind::Call:
            return eval_call(expr.as<CallExpr>());
        case ExprKind::Object:
            return eval_object(expr.as<ObjectExpr>());
        case ExprKind::Member:
            return eval_member(expr.as<MemberExpr>());
        case ExprKind::Index:
            return eval_index(expr.as<IndexExpr>());
        case ExprKind::Material:
        case ExprKind::Checker:
        case ExprKind::Perlin:
            return eval_block_expr(expr.as<BlockExpr>());
        case ExprKind::Image:
            return eval_image(expr.as<ImageExpr>());
        case ExprKind::Bad:
            return std::nullopt;  // the parser reported it
    }
    return std::nullopt;
}

std::optional<Value> Interpreter::eval_ident(const IdentExpr& expr) {
    const std::string_view name = expr.name;
    if (const Binding* b = find(name)) return b->value;  // empty if its definition failed
    if (name == "clock") return Value::make_number(time_.clock, expr.span);
    if (name == "frame") return Value::make_number(static_cast<double>(time_.frame), expr.span);
    for (const BuiltinConstant& c : builtin_constants()) {
        if (c.name == name) {
            Value v = c.value;
            v.set_span(expr.span);
            return v;
        }
    }
    if (find_builtin(name)) {
        diags_.error(expr.span, quoted(name) + " is a function: call it as " + std::string(name) + "(...)");
        return std::nullopt;
    }
    Diagnostic& d = diags_.error(expr.span, "unknown name " + quoted(name));
    std::string match = closest_match(name, visible_names());
    if (!match.empty()) d.help.push_back("did you mean '" + match + "'?");
    return std::nullopt;
}

// The parser gives a vector literal 2 or 3 components.
std::optional<Value> Interpreter::eval_vector(const VectorExpr& expr) {
    glm::dvec3 v(0.0);
    bool ok = true;
    const size_t n = expr.components.size();
    for (size_t i = 0; i < n; ++i) {
        const Expr& component = *expr.components[i];
        std::optional<Value> c = eval(component);
        if (!c) {
            ok = false;
            continue;
        }
        if (!c->is(ValueType::Number)) {
            diags_.error(component.span,
                         std::string("vector components must be numbers, found ") + type_name(c->type()));
            ok = false;
            continue;
        }
        v[static_cast<int>(i)] = c->number();
    }
    if (!ok) return std::nullopt;
    if (n == 2) return Value::make_vec2({v.x, v.y}, expr.span);
    return Value::make_vec3(v, expr.span);
}

std::optional<Value> Interpreter::eval_list(const ListExpr& expr) {
    auto list = std::make_shared<ListValue>();
    list->items.reserve(expr.elements.size());
    bool ok = true;
    for (const Expr* e : expr.elements) {
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

std::optional<Value> Interpreter::eval_unary(const UnaryExpr& expr) {
    std::optional<Value> v = eval(*expr.operand);
    if (!v) return std::nullopt;
    if (expr.op == UnaryOp::Not) {
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

std::optional<Value> Interpreter::eval_logical(const BinaryExpr& expr) {
    const BinaryOp op = expr.ops[0].op;
    const bool is_or = op == BinaryOp::Or;
    auto needs_bools = [&](size_t link, const Value& v, const char* side) {
        diags_.error(expr.ops[link].span,
                     quoted(binary_op_text(op)) + " needs bools, found " + type_name(v.type()) + side);
    };
    std::optional<Value> a = eval(*expr.operands[0]);
    if (!a) return std::nullopt;
    if (!a->is(ValueType::Bool)) {
        needs_bools(0, *a, " on the left");
        return std::nullopt;
    }
    bool result = a->boolean();
    for (size_t i = 1; i < expr.operands.size(); ++i) {
        if (result == is_or) break;
        std::optional<Value> b = eval(*expr.operands[i]);
        if (!b) return std::nullopt;
        if (!b->is(ValueType::Bool)) {
            needs_bools(i - 1, *b, " on the right");
            return std::nullopt;
        }
        result = b->boolean();
    }
    return Value::make_bool(result, expr.span);
}

// A chain of one level, left to right: `a - b + c` is `(a - b) + c`. Every operand is evaluated
// even after a step failed (as the tree would), so independent errors are all reported.
std::optional<Value> Interpreter::eval_binary(const BinaryExpr& expr) {
    const BinaryOp first = expr.ops[0].op;
    if (first == BinaryOp::And || first == BinaryOp::Or) return eval_logical(expr);
    std::optional<Value> acc = eval(*expr.operands[0]);
    const size_t n = expr.operands.size();
    for (size_t i = 1; i < n; ++i) {
        std::optional<Value> b = eval(*expr.operands[i]);
        if (!acc || !b) {
            acc.reset();
            continue;
        }
        const Span span =
            i + 1 == n ? expr.span
                       : Span{expr.span.file, expr.operands[0]->span.begin, expr.operands[i]->span.end};
        const BinaryStep step{expr.ops[i - 1].op, expr.ops[i - 1].span, span};
        switch (step.op) {
            case BinaryOp::Eq:
            case BinaryOp::Ne:
            case BinaryOp::Lt:
            case BinaryOp::Le:
            case BinaryOp::Gt:
            case BinaryOp::Ge:
                acc = compare(step, *acc, *b);
                break;
            default:
                acc = arithmetic(step, *acc, *b);
                break;
        }
    }
    return acc;
}

std::optional<Value> Interpreter::compare(const BinaryStep& step, const Value& a, const Value& b) {
    const BinaryOp op = step.op;
    const auto sym = [op] { return quoted(binary_op_text(op)); };  // for messages only
    if (op == BinaryOp::Eq || op == BinaryOp::Ne) {
        if (a.type() != b.type()) {
            diags_.error(step.op_span, std::string("cannot compare ") + type_name(a.type()) + " with " +
                                           type_name(b.type()) + " using " + sym());
            return std::nullopt;
        }
        if (a.is(ValueType::List) || a.is(ValueType::Material) || a.is(ValueType::Texture) ||
            a.is(ValueType::Object) || a.is(ValueType::Function)) {
            diags_.error(step.op_span,
                         std::string("cannot compare ") + type_name(a.type()) + "s using " + sym());
            return std::nullopt;
        }
        bool equal = values_equal(a, b);
        return Value::make_bool(op == BinaryOp::Eq ? equal : !equal, step.span);
    }
    if (!a.is(ValueType::Number) || !b.is(ValueType::Number)) {
        diags_.error(step.op_span, sym() + " compares numbers, found " + type_name(a.type()) + " and " +
                                       type_name(b.type()));
        return std::nullopt;
    }
    const double x = a.number(), y = b.number();
    bool r = op == BinaryOp::Lt ? x < y : op == BinaryOp::Le ? x <= y : op == BinaryOp::Gt ? x > y : x >= y;
    return Value::make_bool(r, step.span);
}

std::optional<Value> Interpreter::arithmetic(const BinaryStep& step, const Value& a, const Value& b) {
    const BinaryOp op = step.op;
    const auto sym = [op] { return quoted(binary_op_text(op)); };  // for messages only
    auto fail = [&](const std::string& message) -> std::optional<Value> {
        diags_.error(step.op_span, message);
        return std::nullopt;
    };
    auto mismatch = [&]() {
        return fail("operator " + sym() + " cannot combine " + type_name(a.type()) + " and " +
                    type_name(b.type()));
    };
    auto result = [&](ValueType type, glm::dvec3 v) -> std::optional<Value> {
        if (!finite3(v)) return fail("result of " + sym() + " is not a finite number");
        if (type == ValueType::Number) return Value::make_number(v.x, step.span);
        return make_vector(type, v, step.span);
    };

    if (a.is(ValueType::String) && b.is(ValueType::String) && op == BinaryOp::Add) {
        if (a.string().size() + b.string().size() > kMaxStringLength)
            return fail("string longer than the limit of " + std::to_string(kMaxStringLength) + " bytes");
        return Value::make_string(a.string() + b.string(), step.span);
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

std::optional<Value> Interpreter::eval_call(const CallExpr& expr) {
    const std::string_view name = expr.name;
    if (const Binding* b = find(name)) {
        if (!b->value) return std::nullopt;
        if (b->value->is(ValueType::Function)) {
            const FunctionPtr fn = b->value->function();  // the binding may move while the body runs
            return call_function(fn, expr, true);
        }
        Diagnostic& d = diags_.error(
            expr.name_span, quoted(name) + " is a " + type_name(b->value->type()) + ", not a function");
        d.notes.push_back({b->span, quoted(name) + " is defined here"});
        return std::nullopt;
    }
    const Builtin* f = find_builtin(name);
    if (!f) {
        for (const BuiltinConstant& c : builtin_constants()) {
            if (c.name == name) {
                diags_.error(expr.name_span,
                             quoted(name) + " is a " + type_name(c.value.type()) + ", not a function");
                return std::nullopt;
            }
        }
        Diagnostic& d = diags_.error(expr.name_span, "unknown function " + quoted(name));
        std::string match = closest_match(name, callable_names());
        if (!match.empty()) d.help.push_back("did you mean '" + match + "'?");
        return std::nullopt;
    }
    const size_t max_arity = static_cast<size_t>(f->arity + f->optional);
    if (expr.args.size() < static_cast<size_t>(f->arity) || expr.args.size() > max_arity) {
        const std::string takes = f->optional == 0 ? std::to_string(f->arity)
                                  : f->optional == 1
                                      ? std::to_string(f->arity) + " or " + std::to_string(max_arity)
                                      : std::to_string(f->arity) + " to " + std::to_string(max_arity);
        diags_.error(expr.span, quoted(name) + " takes " + takes +
                                    (max_arity == 1 ? " argument" : " arguments") + ", found " +
                                    std::to_string(expr.args.size()));
        return std::nullopt;
    }
    std::vector<Value> args;
    args.reserve(expr.args.size());
    bool ok = true;
    for (const Expr* e : expr.args) {
        std::optional<Value> v = eval(*e);
        if (!v) {
            ok = false;
            continue;
        }
        args.push_back(std::move(*v));
    }
    if (!ok) return std::nullopt;
    return f->fn(CallContext{expr, args, diags_, params_});
}

std::optional<Value> Interpreter::eval_member(const MemberExpr& expr) {
    std::optional<Value> v = eval(*expr.operand);
    if (!v) return std::nullopt;
    const std::string_view field = expr.field;
    if (v->is(ValueType::Vector3)) {
        int i = field == "x" || field == "r"   ? 0
                : field == "y" || field == "g" ? 1
                : field == "z" || field == "b" ? 2
                                               : -1;
        if (i >= 0) return Value::make_number(v->vec3()[i], expr.span);
        diags_.error(expr.field_span,
                     "vector3 has no component " + quoted(field) + " (it has x, y, z and r, g, b)");
        return std::nullopt;
    }
    if (v->is(ValueType::Vector2)) {
        int i = field == "x" || field == "u" ? 0 : field == "y" || field == "v" ? 1 : -1;
        if (i >= 0) return Value::make_number(v->vec2()[i], expr.span);
        diags_.error(expr.field_span,
                     "vector2 has no component " + quoted(field) + " (it has x, y and u, v)");
        return std::nullopt;
    }
    std::string access = ".";
    access += field;
    diags_.error(expr.field_span, quoted(access) + " needs a vector, found " + type_name(v->type()));
    return std::nullopt;
}

std::optional<Value> Interpreter::eval_index(const IndexExpr& expr) {
    std::optional<Value> base = eval(*expr.operand);
    std::optional<Value> index = eval(*expr.index);
    if (!base || !index) return std::nullopt;
    if (!base->is(ValueType::List)) {
        diags_.error(expr.bracket, std::string("cannot index a ") + type_name(base->type()) +
                                       ": only lists can be indexed");
        return std::nullopt;
    }
    const Span at = expr.index->span;
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
