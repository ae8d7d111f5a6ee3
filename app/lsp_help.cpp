// Hover and completion. A property's help is generated from the tables the language checks blocks
// against (lang/properties.h, built from render/params.h): its type, range, words, default and
// meaning. A name's help says where it is defined and the type of its value — from evaluating the
// scene for top-level names, else from the syntax of its definition.
#include <algorithm>
#include <set>

#include "app/lsp_analysis.h"
#include "lang/interpreter.h"
#include "lang/lexer.h"
#include "lang/lower.h"
#include "lang/parser.h"
#include "render/params.h"

namespace wsd::app::lsp {

namespace {

using nlohmann::json;
using namespace lang;

// LSP CompletionItemKind values.
enum ItemKind {
    FunctionItem = 3,
    VariableItem = 6,
    PropertyItem = 10,
    KeywordItem = 14,
    EnumMemberItem = 20
};

std::string join(const std::vector<std::string_view>& words) {
    std::string out;
    for (size_t i = 0; i < words.size(); ++i) out.append(i ? ", " : "").append(words[i]);
    return out;
}

// The help of one property of `table`, in Markdown.
std::string property_help(const BlockTable& table, const Property& p) {
    std::string name = p.name.empty() ? "vertices" : std::string(p.name);
    std::string out = "**" + name + "** (" + table.what + "): " + expected_type(p.type);
    if (p.max_values > 1)
        out += p.min_values == p.max_values
                   ? ", " + std::to_string(p.max_values) + " values"
                   : ", " + std::to_string(p.min_values) + " to " + std::to_string(p.max_values) + " values";
    if (p.field) {
        if (p.field->range.has_lo() || p.field->range.has_hi()) out += ", " + p.field->range.describe();
        if (!p.words().empty()) out += ": one of " + join(p.words());
        out += "\n\nDefault: " + render::default_text(render::element_table(table.element), *p.field);
        if (!p.field->meaning.empty()) out += "\n\n" + std::string(p.field->meaning);
    }
    return out;
}

const Property* transform_property(const BlockTable& table, std::string_view name) {
    static const Property scale{"scale", PropType::NumberOrVector3}, rotate{"rotate", PropType::Vector3},
        translate{"translate", PropType::Vector3};
    if (!table.transforms) return nullptr;
    if (name == "scale") return &scale;
    if (name == "rotate") return &rotate;
    if (name == "translate") return &translate;
    return nullptr;
}

std::string location_text(const Definition& d) {
    const LineCol lc = d.file->sources.line_col(0, d.name_span.begin);
    return d.file->path + ":" + std::to_string(lc.line) + ":" + std::to_string(lc.column);
}

// The type of an expression as far as its syntax tells, or "".
std::string syntax_type(const Expr& e) {
    switch (e.kind) {
        case ExprKind::Number:
            return "number";
        case ExprKind::String:
            return "string";
        case ExprKind::Bool:
            return "bool";
        case ExprKind::Vector:
            return e.as<VectorExpr>().components.size() == 2 ? "vector2" : "vector3";
        case ExprKind::List:
        case ExprKind::PackedList:
            return "list";
        case ExprKind::Material:
            return "material";
        case ExprKind::Image:
        case ExprKind::Checker:
        case ExprKind::Perlin:
            return "texture";
        case ExprKind::Object:
            return "object";
        case ExprKind::Unary:
            return e.as<UnaryExpr>().op == UnaryOp::Not ? "bool" : syntax_type(*e.as<UnaryExpr>().operand);
        case ExprKind::Binary:
            return e.as<BinaryExpr>().ops.empty() || e.as<BinaryExpr>().ops[0].op <= BinaryOp::Ge ? "bool"
                                                                                                  : "";
        case ExprKind::Ident:
        case ExprKind::Call:
        case ExprKind::Member:
        case ExprKind::Index:
        case ExprKind::Bad:
            return "";
    }
    return "";
}

// The types of the scene's top-level names, from running it (without lowering's build); none when
// `cancel` stopped the run.
std::optional<std::map<std::string, std::string>> evaluate_top_level(const Document& doc, Workspace& ws,
                                                                     const FileReader& reader,
                                                                     const std::atomic<bool>* cancel) {
    std::map<std::string, std::string> out;
    SourceManager sources;
    Diagnostics diags;
    const uint32_t file = sources.add(doc.path, doc.text);
    Program program = parse(file, sources, diags);
    if (diags.has_errors()) return out;
    SceneBuilder builder(file);
    Interpreter interpreter(sources, diags, builder);
    // Includes as the server sees them: open documents' unsaved text, else the files on disk.
    const IncludeReader read = [&](const std::string& path, std::string& text, std::string& reason) {
        std::optional<std::string> t = reader(path);
        if (!t) reason = "it cannot be read";
        if (t) text = std::move(*t);
        return t.has_value();
    };
    interpreter.set_file_reader(&read);
    interpreter.set_cancel(cancel);
    interpreter.run(program);
    if (interpreter.cancelled()) return std::nullopt;
    for (const Definition& d : ws.visible_at(UINT32_MAX))
        if (d.top_level)
            if (const std::optional<Value> v = interpreter.lookup(d.name))
                out[std::string(d.name)] = type_name(v->type());
    return out;
}

std::string name_help(Document& doc, Workspace& ws, const Definition& d, const FileReader& reader,
                      const std::atomic<bool>* cancel) {
    std::string out = "```wsd\n";
    const FnStmt* fn = d.kind == Definition::Kind::Fn ? &d.stmt->as<FnStmt>() : nullptr;
    std::string type;
    if (fn) {
        out += "fn " + std::string(d.name) + "(";
        for (size_t i = 0; i < fn->params.size(); ++i)
            out += (i ? ", " : "") + std::string(fn->params[i].name) + (fn->params[i].fallback ? " = …" : "");
        out += ")";
        type = "function";
    } else {
        out += (d.kind == Definition::Kind::Let    ? "let "
                : d.kind == Definition::Kind::Loop ? "for "
                                                   : "parameter ") +
               std::string(d.name);
        if (d.top_level) {
            if (!doc.top_level_types)
                if (auto types = evaluate_top_level(doc, ws, reader, cancel))
                    doc.top_level_types =
                        std::make_shared<std::map<std::string, std::string>>(std::move(*types));
            if (doc.top_level_types) {
                auto it = doc.top_level_types->find(std::string(d.name));
                if (it != doc.top_level_types->end()) type = it->second;
            }
        }
        if (type.empty() && d.kind == Definition::Kind::Let) type = syntax_type(*d.stmt->as<LetStmt>().value);
        if (type.empty() && d.kind == Definition::Kind::Loop)
            type = d.stmt->as<ForStmt>().range_end ? "number" : "an element of the list";
    }
    out += "\n```\n";
    if (!type.empty()) out += "Type: " + type + "\n\n";
    out += "Defined at " + location_text(d);
    return out;
}

json hover_json(const std::string& markdown, const LineIndex& index, Span span, Encoding enc) {
    return {{"contents", {{"kind", "markdown"}, {"value", markdown}}},
            {"range", range_json(index, span.begin, span.end, enc)}};
}

json item(std::string_view label, int kind, const std::string& detail = {}) {
    json j = {{"label", label}, {"kind", kind}};
    if (!detail.empty()) j["detail"] = detail;
    return j;
}

bool word_char(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}

// Whether `offset` is inside a comment or a string (also at the end of one left open, as a line
// comment is up to its line's end).
bool in_comment_or_string(std::string_view text, uint32_t offset) {
    std::vector<Span> comments;
    Lexer lexer(0, text, nullptr);
    lexer.record_comments(&comments);
    for (Token t = lexer.next(); t.kind != TokenKind::Eof && t.begin < offset; t = lexer.next())
        if (t.kind == TokenKind::String) {
            const bool closed = t.end - t.begin >= 2 && text[t.end - 1] == '"';
            if (offset < t.end || (offset == t.end && !closed)) return true;
        }
    for (const Span& c : comments) {
        if (c.begin >= offset) break;
        const bool line = text[c.begin + 1] == '/';
        const bool closed = !line && c.end - c.begin >= 4 && text.substr(c.end - 2, 2) == "*/";
        if (offset < c.end || (offset == c.end && !closed)) return true;
    }
    return false;
}

}  // namespace

json hover(Document& doc, Position at, Encoding enc, const FileReader& reader,
           const std::atomic<bool>* cancel) {
    const ParsedFile& file = doc.syntax();
    const LineIndex index(doc.text);
    const uint32_t offset = index.offset(at, enc);
    const Context c = context_at(file, offset);
    if (c.item && c.item_table) {
        const Property* p = c.item_table->find(c.item->name);
        if (!p) p = transform_property(*c.item_table, c.item->name);
        if (p) return hover_json(property_help(*c.item_table, *p), index, c.item->name_span, enc);
        return nullptr;
    }
    Workspace ws(doc.parsed, reader);
    if (c.defining) {
        for (const Definition& d : ws.visible_at(c.defining->span.end + 1))
            if (d.stmt == c.defining)
                return hover_json(name_help(doc, ws, d, reader, cancel), index, d.name_span, enc);
        Workspace inner(doc.parsed, reader);
        for (const Definition& d : inner.visible_at(offset))
            if (d.stmt == c.defining)
                return hover_json(name_help(doc, ws, d, reader, cancel), index, d.name_span, enc);
        return nullptr;
    }
    if (!c.name.empty())
        if (const std::optional<Definition> d = ws.resolve(c.name, offset))
            return hover_json(name_help(doc, ws, *d, reader, cancel), index, c.name_span, enc);
    if (c.include) {
        const std::string path = ws.include_path(file, *c.include);
        return hover_json("Includes `" + path + "`" + (ws.included(file, *c.include) ? "" : " (not found)"),
                          index, c.include->path_span, enc);
    }
    return nullptr;
}

json completion(Document& doc, Position at, Encoding enc, const FileReader& reader) {
    const ParsedFile& file = doc.syntax();
    const std::string& text = doc.text;
    const uint32_t offset = LineIndex(text).offset(at, enc);
    json items = json::array();
    if (in_comment_or_string(text, offset)) return items;  // prose and paths: nothing to offer
    const Context c = context_at(file, offset);
    Workspace ws(doc.parsed, reader);
    std::set<std::string> seen;
    auto add = [&](std::string_view label, int kind, const std::string& detail = {}) {
        if (!label.empty() && seen.insert(std::string(label)).second)
            items.push_back(item(label, kind, detail));
    };
    auto add_names = [&] {
        const std::vector<Definition> names = ws.visible_at(offset);
        for (auto it = names.rbegin(); it != names.rend(); ++it)
            add(it->name, it->kind == Definition::Kind::Fn ? FunctionItem : VariableItem);
    };
    auto add_properties = [&](const BlockTable& table) {
        for (const Property& p : table.properties) add(p.name, PropertyItem, expected_type(p.type));
        if (table.transforms)
            for (const char* t : {"scale", "rotate", "translate"}) add(t, PropertyItem, "a transform");
    };

    // The word being typed and the token before it (comments are not tokens: a `*/` or a comment
    // ending in ',' says nothing of what comes next).
    uint32_t word_begin = offset;
    while (word_begin > 0 && word_char(text[word_begin - 1])) --word_begin;
    Lexer lexer(0, text, nullptr);
    Token last{TokenKind::Eof, 0, 0, 0};
    for (Token t = lexer.next(); t.kind != TokenKind::Eof && t.end <= word_begin; t = lexer.next()) last = t;
    const uint32_t before = last.end;
    const std::string_view between = std::string_view(text).substr(before, word_begin - before);
    const bool new_line = between.find_first_of("\r\n") != std::string_view::npos;
    const char prev = before > 0 ? text[before - 1] : '\0';
    const std::string_view lexeme = lexer.lexeme(last);
    const std::string_view prev_word =
        before > 0 && !lexeme.empty() && word_char(lexeme.back()) && word_char(lexeme.front())
            ? lexeme
            : std::string_view();

    if (c.block && c.table) {
        // A property name starts an item: after '{', on a new line, or after a whole value.
        const Property* prev_property =
            !prev_word.empty() && !std::isdigit(static_cast<unsigned char>(prev_word.front()))
                ? c.table->find(prev_word)
                : nullptr;
        bool name_position = true;
        if (prev == '{')
            name_position = true;
        else if (std::string_view(",(<[=+-*/%!&|").find(prev) != std::string_view::npos && prev != '\0')
            name_position = false;
        else if (new_line)
            name_position = true;
        else if (prev_property)
            name_position = false;
        if (name_position) {
            add_properties(*c.table);
            return items;
        }
        if (prev_property)
            for (std::string_view w : prev_property->words()) add(w, EnumMemberItem);
        add_names();
        for (TokenKind k : {TokenKind::Material, TokenKind::Image, TokenKind::Checker, TokenKind::Perlin,
                            TokenKind::True, TokenKind::False})
            add(token_spelling(k), KeywordItem);
        return items;
    }
    // Statement level (the top, a body, or a group with its items).
    if (c.group) add_properties(block_table(group_keyword(c.group->group_kind)));
    for (int k = static_cast<int>(TokenKind::Let); k <= static_cast<int>(TokenKind::False); ++k) {
        const TokenKind kind = static_cast<TokenKind>(k);
        if (!is_statement_keyword(kind)) continue;
        if (kind == TokenKind::Return && !c.in_fn) continue;
        add(token_spelling(kind), KeywordItem);
    }
    if (prev_word == "if" || prev == '}') add("else", KeywordItem);
    add_names();
    return items;
}

}  // namespace wsd::app::lsp
