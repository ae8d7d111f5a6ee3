// The interpreter's scopes: a chain of heap frames from the innermost scope out to the file's top
// scope. A popped scope that nothing else holds is kept for reuse, so that a loop's iterations
// allocate nothing; one that a function still holds lives on with it. Functions and the scopes
// that hold them can form cycles of shared pointers, which the destructor breaks.
#include <algorithm>

#include "lang/builtins.h"
#include "lang/interpreter.h"
#include "render/text_util.h"

namespace wsd::lang {

const Binding* Scope::find(std::string_view name) const {
    if (!index.empty()) {
        auto it = index.find(name);
        return it == index.end() ? nullptr : &bindings[it->second];
    }
    for (const Binding& b : bindings)
        if (b.name == name) return &b;
    return nullptr;
}

void Scope::add(Binding binding) {
    constexpr size_t kIndexFrom = 16;  // linear search is faster for small scopes
    bindings.push_back(std::move(binding));
    if (bindings.back().value && bindings.back().value->is(ValueType::Function))
        functions.push_back(bindings.size() - 1);
    if (!index.empty()) {
        index.emplace(bindings.back().name, bindings.size() - 1);
    } else if (bindings.size() >= kIndexFrom) {
        for (size_t i = 0; i < bindings.size(); ++i) index.emplace(bindings[i].name, i);
    }
}

void Scope::clear() {
    bindings.clear();
    included.clear();
    functions.clear();
    if (!index.empty()) index.clear();  // clear() on an empty map still wipes its buckets
    parent.reset();
}

Interpreter::~Interpreter() {
    // A scope holds a function that holds the scope: drop every binding of every scope that may
    // be on such a cycle (the top scope and those that outlived their code).
    for (const std::weak_ptr<Scope>& weak : escaped_)
        if (ScopePtr s = weak.lock()) s->clear();
    if (top_) top_->clear();
}

const Interpreter::Included* Interpreter::visible_include(const std::string& key) const {
    for (const Scope* s = scope_.get(); s; s = s->parent.get())
        for (const Included& inc : s->included)
            if (inc.key == key) return &inc;
    return nullptr;
}

// Moves, not copies, of the shared pointers: a loop's iteration costs no reference counting.
ScopePtr Interpreter::new_scope() {
    if (spare_.empty()) return std::make_shared<Scope>();
    ScopePtr scope = std::move(spare_.back());
    spare_.pop_back();
    return scope;
}

void Interpreter::push_scope() {
    ScopePtr scope = new_scope();
    scope->parent = std::move(scope_);
    scope_ = std::move(scope);
}

void Interpreter::push_scope(ScopePtr parent) {
    ScopePtr scope = new_scope();
    scope->parent = std::move(parent);
    scope_ = std::move(scope);
}

namespace {

// How many of the references to `scope` come from functions bound in it and held by nothing else:
// those keep the scope alive only for themselves.
long self_held(const ScopePtr& scope) {
    long n = 0;
    if (scope.use_count() > 1)
        for (size_t i : scope->functions) {
            const FunctionPtr& f = scope->bindings[i].value->function();
            if (f->scope == scope && f.use_count() == 1) ++n;
        }
    return n;
}

}  // namespace

void Interpreter::prune_escaped() {
    // A scope that escaped (a call's scope that bound a function it returned, say) becomes garbage
    // once that function is dropped, but the function and the scope still hold each other: break
    // such cycles here, so that a loop making closures runs in constant memory.
    for (const std::weak_ptr<Scope>& weak : escaped_)
        if (ScopePtr s = weak.lock(); s && s.use_count() == 1 + self_held(s)) s->clear();
    std::erase_if(escaped_, [](const std::weak_ptr<Scope>& w) { return w.expired(); });
    prune_escaped_at_ = 2 * escaped_.size() + 64;
}

void Interpreter::pop_scope() {
    if (scope_ == top_ || !scope_->parent) return;
    ScopePtr popped = std::move(scope_);
    if (popped.use_count() == 1 + self_held(popped)) {
        scope_ = std::move(popped->parent);
        popped->clear();
        spare_.push_back(std::move(popped));
        return;
    }
    scope_ = popped->parent;
    escaped_.push_back(popped);
    if (escaped_.size() >= prune_escaped_at_) prune_escaped();
}

void Interpreter::bind(std::string_view name, Span span, std::optional<Value> value) {
    Scope& scope = *scope_;
    if (const Binding* first = scope.find(name)) {
        Diagnostic& d = diags_.error(span, render::quoted(name) + " is already defined in this scope");
        d.notes.push_back({first->span, "first defined here"});
        return;
    }
    scope.add(Binding{name, span, std::move(value)});
}

const Interpreter::Binding* Interpreter::find(std::string_view name) const {
    for (const Scope* s = scope_.get(); s; s = s->parent.get())
        if (const Binding* b = s->find(name)) return b;
    return nullptr;
}

// Outermost scope first, then the builtins.
std::vector<std::string> Interpreter::visible_names() const {
    std::vector<const Scope*> chain;
    for (const Scope* s = scope_.get(); s; s = s->parent.get()) chain.push_back(s);
    std::vector<std::string> names;
    for (auto it = chain.rbegin(); it != chain.rend(); ++it)
        for (const Binding& b : (*it)->bindings) names.emplace_back(b.name);
    for (const BuiltinConstant& c : builtin_constants()) names.emplace_back(c.name);
    for (const Builtin& f : builtin_functions()) names.emplace_back(f.name);
    return names;
}

// The names a call could mean: visible functions, then the builtin functions.
std::vector<std::string> Interpreter::callable_names() const {
    std::vector<std::string> names;
    for (const Scope* s = scope_.get(); s; s = s->parent.get())
        for (const Binding& b : s->bindings)
            if (b.value && b.value->is(ValueType::Function)) names.emplace_back(b.name);
    for (const Builtin& f : builtin_functions()) names.emplace_back(f.name);
    return names;
}

std::optional<Value> Interpreter::lookup(std::string_view name) const {
    const Binding* b = top_->find(name);
    if (!b) return std::nullopt;
    return b->value;
}

}  // namespace wsd::lang
