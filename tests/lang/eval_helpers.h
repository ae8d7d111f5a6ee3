// Helpers for the interpreter and lowering tests: run .wsd text through the parser and the
// interpreter (or the whole load_scene), and read back values and diagnostics as "L:C: message".
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lang/interpreter.h"
#include "lang/load.h"
#include "lang/parser.h"

namespace wsd::lang::test {

inline std::string where(const SourceManager& sources, Span span) {
    const LineCol lc = sources.line_col(span.file, span.begin);
    return std::to_string(lc.line) + ":" + std::to_string(lc.column);
}

inline std::vector<std::string> messages(const Diagnostics& diags, const SourceManager& sources,
                                         Severity severity = Severity::Error) {
    std::vector<std::string> out;
    for (const Diagnostic& d : diags.all())
        if (d.severity == severity) out.push_back(where(sources, d.span) + ": " + d.message);
    return out;
}

// Parse + interpret without load_scene, so that bindings can be inspected afterwards.
struct Evaluated {
    SourceManager sources;
    Diagnostics diags;
    Program program;
    SceneBuilder builder;
    std::unique_ptr<Interpreter> interpreter;
    LoweredScene scene;

    std::vector<std::string> errors() const { return messages(diags, sources); }
    std::optional<Value> get(const std::string& name) const { return interpreter->lookup(name); }
};

inline std::unique_ptr<Evaluated> evaluate_text(std::string text, Limits limits = {},
                                                const std::string& path = "t.wsd") {
    auto e = std::make_unique<Evaluated>();
    const uint32_t file = e->sources.add(path, std::move(text));
    e->program = parse(file, e->sources, e->diags);
    e->interpreter = std::make_unique<Interpreter>(e->sources, e->diags, e->builder, limits);
    if (!e->diags.has_errors()) e->interpreter->run(e->program);
    e->scene = e->builder.finish();
    return e;
}

// The value of one expression: evaluates `let x = EXPR`.
inline std::optional<Value> value_of(const std::string& expr) {
    auto e = evaluate_text("let x = " + expr + "\n");
    return e->get("x");
}

// The errors of evaluating `let x = EXPR`.
inline std::vector<std::string> errors_of(const std::string& expr) {
    return evaluate_text("let x = " + expr + "\n")->errors();
}

struct Loaded {
    SourceManager sources;
    Diagnostics diags;
    std::optional<LoadedScene> scene;
    std::vector<std::string> errors() const { return messages(diags, sources); }
};

inline std::unique_ptr<Loaded> load_text(std::string text, bool fragment = false, bool build = false,
                                         const std::string& path = "t.wsd") {
    auto l = std::make_unique<Loaded>();
    LoadOptions options;
    options.fragment = fragment;
    options.build = build;
    l->scene = load_scene(path, std::move(text), l->sources, l->diags, options);
    return l;
}

inline const char* kCamera = "camera { position <0, 0, -5>  look_at <0, 0, 0> }\n";

}  // namespace wsd::lang::test
