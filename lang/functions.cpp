// User functions: `fn` binds a function value (its declaration and its defining scope), `return`
// ends a call, and a call runs the body in a new scope inside the definition's scope, with the
// arguments bound to the parameters (missing ones take their defaults, evaluated there). Calls
// nest at most Limits::call_depth deep, each takes one step of the Limits::loop_iterations budget,
// and each starts a new count of nesting depth (the evaluator's stack is sized for that).
#include <string>

#include "lang/interpreter.h"
#include "render/text_util.h"

namespace wsd::lang {

using render::quoted;

namespace {

std::string count_of(size_t n, const char* what) {
    return std::to_string(n) + " " + what + (n == 1 ? "" : "s");
}

// "1 argument", "2 or 3 arguments", "1 to 4 arguments".
std::string arity_text(size_t min, size_t max) {
    if (min == max) return count_of(min, "argument");
    return std::to_string(min) + (max == min + 1 ? " or " : " to ") + std::to_string(max) + " arguments";
}

}  // namespace

void Interpreter::exec_fn(const FnStmt& stmt) {
    if (stmt.name.empty()) return;  // a syntax error, already reported
    auto fn = std::make_shared<FunctionValue>(FunctionValue{&stmt, scope_, chain_, diags_.include_stack()});
    bind(stmt.name, stmt.name_span, Value::make_function(std::move(fn), stmt.name_span));
}

void Interpreter::exec_return(const ReturnStmt& stmt) {
    return_value_ = eval(*stmt.value);
    returning_ = true;
}

void Interpreter::exec_call(const CallStmt& stmt) {
    const CallExpr& call = *stmt.call;
    const Binding* b = find(call.name);
    if (b && b->value && b->value->is(ValueType::Function)) {
        const FunctionPtr fn = b->value->function();  // the binding may move while the body runs
        if (std::optional<Value> result = call_function(fn, call, false)) drop_call_value(*result, call);
        return;
    }
    // A builtin, or a name that is not a function (reported there).
    if (eval_call(call)) {
        Diagnostic& d =
            diags_.warning(call.span, quoted(call.name) + " returns a value that this statement drops");
        d.help.push_back("bind it with 'let NAME = " + std::string(call.name) + "(...)'");
    }
}

namespace {

// Whether dropping a value loses objects that it holds: an object value, or a list with one.
bool holds_objects(const Value& v) {
    if (v.is(ValueType::Object)) return true;
    if (!v.is(ValueType::List) || v.list().packed) return false;
    for (const Value& item : v.list().items)
        if (holds_objects(item)) return true;
    return false;
}

}  // namespace

void Interpreter::drop_call_value(const Value& value, const CallExpr& call) {
    if (!holds_objects(value)) return;
    Diagnostic& d = diags_.warning(call.span, "the " + std::string(type_name(value.type())) + " that " +
                                                  quoted(call.name) + " returns is dropped");
    d.help.push_back("write `object " + std::string(call.name) + "() {}` to add it");
}

bool Interpreter::objects_allowed(Span at) {
    if (!expression_call_) return true;
    const std::string_view text =
        std::string_view(sources_.file(at.file).text).substr(at.begin, at.end - at.begin);
    Diagnostic& d = diags_.error(at, quoted(text) + " cannot run during a call made from an expression");
    d.notes.push_back(
        {expression_call_->span, "the call to " + quoted(expression_call_->name) + ", in an expression"});
    d.help.push_back("expressions do not add to the scene: call " + quoted(expression_call_->name) +
                     " as a statement to add what it makes");
    return false;
}

bool Interpreter::check_arity(const FunctionValue& fn, const CallExpr& call) {
    const FnStmt& decl = *fn.decl;
    const size_t n = call.args.size(), min = decl.required(), max = decl.params.size();
    if (n >= min && n <= max) return true;
    Diagnostic& d = diags_.error(
        call.span, quoted(decl.name) + " takes " + arity_text(min, max) + ", found " + std::to_string(n));
    d.notes.push_back({decl.name_span, quoted(decl.name) + " is defined here"});
    if (n < min) {
        std::string missing;
        for (size_t i = n; i < min; ++i) missing += (i > n ? ", " : "") + quoted(decl.params[i].name);
        d.help.push_back("missing: " + missing);
    }
    return false;
}

// The chain of running calls, by its first and last few (all of them when there are few).
void Interpreter::call_depth_error(const CallExpr& call) {
    Diagnostic& d = diags_.error(call.span, "calls nested too deep (the limit is " +
                                                std::to_string(limits_.call_depth) + " nested calls)");
    d.shows_calls = true;
    constexpr size_t kShown = 3;
    const size_t n = calls_.size();
    for (size_t i = 0; i < n; ++i) {
        if (i == kShown && n > 2 * kShown) {
            d.help.push_back("calls " + std::to_string(kShown + 1) + " to " + std::to_string(n - kShown) +
                             " of the chain are not shown");
            i = n - kShown;
        }
        d.notes.push_back({calls_[i]->span, "call " + std::to_string(i + 1) + " of " + std::to_string(n) +
                                                " in the chain, to " + quoted(calls_[i]->name)});
    }
    abort();
}

bool Interpreter::take_call_step(const CallExpr& call) {
    if (cancel_now() || !take_memory_step(call.name_span)) return false;
    if (iterations_ < limits_.loop_iterations) {
        ++iterations_;
        return true;
    }
    diags_.error(call.name_span, "the call to " + quoted(call.name) + " exceeds the limit of " +
                                     std::to_string(limits_.loop_iterations) +
                                     " steps in total (loop iterations and calls)");
    abort();
    return false;
}

// The arguments, evaluated in the caller's scope into the call's scope `frame` (not yet entered).
bool Interpreter::bind_arguments(const FnStmt& decl, const CallExpr& call, Scope& frame) {
    for (size_t i = 0; i < call.args.size(); ++i) {
        std::optional<Value> v = eval(*call.args[i]);
        if (!v) return false;
        frame.add(Binding{decl.params[i].name, decl.params[i].name_span, std::move(v)});
    }
    return true;
}

std::optional<Value> Interpreter::call_function(const FunctionPtr& fn, const CallExpr& call,
                                                bool in_expression) {
    const FnStmt& decl = *fn->decl;
    if (!check_arity(*fn, call)) return std::nullopt;
    if (calls_.size() >= static_cast<size_t>(limits_.call_depth)) {
        call_depth_error(call);
        return std::nullopt;
    }
    if (!take_call_step(call)) return std::nullopt;
    ScopePtr frame = new_scope();
    if (!bind_arguments(decl, call, *frame)) {
        frame->clear();
        spare_.push_back(std::move(frame));
        return std::nullopt;
    }
    const size_t errors_before = diags_.error_count();
    const size_t diagnostics_before = diags_.all().size();

    // Into the function: its scope, its file's include chain, a fresh nesting count.
    ScopePtr caller_scope = std::move(scope_);
    IncludeChain caller_chain = std::exchange(chain_, fn->chain);
    std::vector<Span> caller_includes = diags_.exchange_include_stack(fn->include_sites);
    const int caller_depth = std::exchange(depth_, 0);
    const CallExpr* caller_expression_call = expression_call_;
    if (in_expression) expression_call_ = &call;
    calls_.push_back(&call);
    frame->parent = fn->scope;
    scope_ = std::move(frame);

    // The defaults of the parameters not given, in the call's scope: each sees those before it.
    for (size_t i = call.args.size(); i < decl.params.size(); ++i)
        bind(decl.params[i].name, decl.params[i].name_span, eval(*decl.params[i].fallback));
    exec_all(decl.body);
    const bool returned = std::exchange(returning_, false);
    std::optional<Value> result = std::move(return_value_);
    return_value_.reset();

    pop_scope();
    scope_ = std::move(caller_scope);
    calls_.pop_back();
    expression_call_ = caller_expression_call;
    depth_ = caller_depth;
    diags_.exchange_include_stack(std::move(caller_includes));
    chain_ = std::move(caller_chain);
    // What went wrong inside says which call it was in.
    diags_.note_call(diagnostics_before, {call.span, "in this call to " + quoted(decl.name)});

    if (!returned) {
        if (in_expression && !stopped() && diags_.error_count() == errors_before) {
            Diagnostic& d = diags_.error(call.span, quoted(decl.name) +
                                                        " ended without 'return', but a call in an "
                                                        "expression needs a value");
            d.notes.push_back({decl.name_span, quoted(decl.name) + " is defined here"});
        }
        return std::nullopt;
    }
    if (result && in_expression) result->set_span(call.span);
    return result;
}

}  // namespace wsd::lang
