// Scopes and function values. A scope is a heap frame linked to its lexically enclosing scope,
// shared by whatever still needs it: the interpreter while its code runs, and every function
// defined in it (a function keeps its defining scope alive, so a function made in a loop sees
// that iteration's variable). A function's body runs in a new scope whose parent is the scope of
// the definition, never the caller's. Names resolve when code runs, in the scopes as they are then.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "lang/ast.h"
#include "lang/value.h"

namespace wsd::lang {

struct Binding {
    std::string_view name;  // in the AST, which outlives the run
    Span span;
    std::optional<Value> value;  // empty: its definition failed (already reported)
};

// A file included in a scope: a second include of it there or in a scope it encloses is skipped.
struct Included {
    std::string key;  // canonical path
    Span site;        // the include that ran it
};

struct Scope {
    std::vector<Binding> bindings;
    std::unordered_map<std::string_view, size_t> index;  // built once a scope grows large
    std::vector<Included> included;
    std::vector<size_t> functions;  // the bindings that hold a function value
    std::shared_ptr<Scope> parent;  // the lexically enclosing scope; null for the file's top scope

    const Binding* find(std::string_view name) const;
    void add(Binding binding);  // a name not bound here yet
    void clear();
};
using ScopePtr = std::shared_ptr<Scope>;

struct FunctionValue {
    const FnStmt* decl;  // in a Program the interpreter keeps until it is destroyed
    ScopePtr scope;      // where it was defined: its body's enclosing scope
    // The include statements that led to its file, as the interpreter and the diagnostics hold
    // them: errors in the body carry these notes wherever it is called from.
    IncludeChain chain;
    std::vector<Span> include_sites;  // outermost first
};

}  // namespace wsd::lang
