// param() and the evaluation of --define values. A define is parsed as the right-hand side of a
// `let` in a file of its own and evaluated by an interpreter that sees only the built-ins.
#include "lang/params.h"

#include "lang/interpreter.h"
#include "lang/lower.h"
#include "lang/parser.h"

namespace wsd::lang {

namespace {

bool positionless(const Value& v) {
    return v.is(ValueType::Number) || v.is(ValueType::Bool) || v.is(ValueType::String) || v.is_vector();
}

}  // namespace

const Value* ParamTable::read(const std::string& name) const {
    const auto it = values_.find(name);
    if (it == values_.end()) return nullptr;
    read_.insert(name);
    return &it->second;
}

std::vector<std::string> ParamTable::unread() const {
    std::vector<std::string> names;
    for (const auto& [name, value] : values_)
        if (!read_.count(name)) names.push_back(name);
    return names;
}

std::optional<Value> evaluate_define(const std::string& expr, std::string& error, const AnimationTime& time) {
    static constexpr const char* binding = "value";
    SourceManager sources;
    Diagnostics diags;
    const uint32_t file = sources.add("--define", std::string("let ") + binding + " = " + expr + "\n");
    const Program program = parse(file, sources, diags);
    std::optional<Value> value;
    if (!diags.has_errors() && program.statements.size() != 1) {
        error = "expected one expression";
        return std::nullopt;
    }
    if (!diags.has_errors()) {
        SceneBuilder builder(file);
        Interpreter interpreter(sources, diags, builder);
        interpreter.set_time(time);
        interpreter.run(program);
        value = interpreter.lookup(binding);
    }
    if (diags.has_errors() || !value) {
        error = diags.all().empty() ? "cannot be evaluated" : diags.all().front().message;
        return std::nullopt;
    }
    if (!positionless(*value)) {
        error = std::string("must be a number, bool, string or vector, not a ") + type_name(value->type());
        return std::nullopt;
    }
    value->set_span(Span{});
    return value;
}

std::optional<Value> builtin_param(const CallContext& c) {
    if (!c.args[0].is(ValueType::String)) {
        c.diags.error(c.call.args[0]->span, std::string("'param' expects a string (the name), found ") +
                                                type_name(c.args[0].type()));
        return std::nullopt;
    }
    const std::string& name = c.args[0].string();
    const Value* given = c.params ? c.params->read(name) : nullptr;
    if (!given) return c.args[1];
    if (given->type() != c.args[1].type()) {
        Diagnostic& d =
            c.diags.error(c.call.name_span, "--define " + name + " is a " + type_name(given->type()) +
                                                ", but the default of param(\"" + name + "\", ...) is a " +
                                                type_name(c.args[1].type()));
        d.help.push_back("give a " + std::string(type_name(c.args[1].type())) + " with --define " + name +
                         "=..., or change the default");
        return std::nullopt;
    }
    Value v = *given;
    v.set_span(c.call.span);
    return v;
}

}  // namespace wsd::lang
