// Diagnostics, definitions, document symbols and formatting for the language server (hover and
// completion are in lsp_help.cpp).
#include "app/lsp_analysis.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>

#include "lang/format.h"
#include "lang/load.h"
#include "render/file_util.h"

namespace wsd::app::lsp {

namespace {

using nlohmann::json;
using namespace lang;

std::string where(const SourceManager& sources, Span span) {
    const LineCol lc = sources.line_col(span.file, span.begin);
    return sources.file(span.file).path + ":" + std::to_string(lc.line) + ":" + std::to_string(lc.column);
}

int severity_code(Severity s) {
    switch (s) {
        case Severity::Error:
            return 1;
        case Severity::Warning:
            return 2;
        case Severity::Note:
            return 3;
    }
    return 1;
}

// File 0 is the document itself, named by its own URI (which need not be a file: an editor's
// untitled buffer).
json related(const SourceManager& sources, const std::string& document_uri, Span span,
             const std::string& message, Encoding enc) {
    const SourceFile& f = sources.file(span.file);
    const LineIndex index(f.text);
    const std::string uri = span.file == 0 ? document_uri : path_to_uri(f.path);
    return {{"location", {{"uri", uri}, {"range", range_json(index, span.begin, span.end, enc)}}},
            {"message", message}};
}

json symbol(std::string name, int kind, const LineIndex& index, Span range, Span selection, Encoding enc) {
    if (name.empty()) name = "?";
    range.begin = std::min(range.begin, selection.begin);
    range.end = std::max(range.end, selection.end);
    return {{"name", std::move(name)},
            {"kind", kind},
            {"range", range_json(index, range.begin, range.end, enc)},
            {"selectionRange", range_json(index, selection.begin, selection.end, enc)}};
}

// LSP SymbolKind values.
enum SymbolKind { Module = 2, Class = 5, Function = 12, Variable = 13, Object = 19, Struct = 23, Event = 24 };

std::string_view text_of(std::string_view text, Span span) {
    if (span.begin > text.size() || span.end < span.begin) return {};
    return text.substr(span.begin, std::min<size_t>(span.end, text.size()) - span.begin);
}

void symbols_of(StmtList list, std::string_view text, const LineIndex& index, Encoding enc, json& out) {
    for (const Stmt* s : list) {
        if (!s) continue;
        switch (s->kind) {
            case StmtKind::Let: {
                const LetStmt& l = s->as<LetStmt>();
                if (!l.name.empty())
                    out.push_back(symbol(std::string(l.name), Variable, index, s->span, l.name_span, enc));
                break;
            }
            case StmtKind::Fn: {
                const FnStmt& f = s->as<FnStmt>();
                if (!f.name.empty())
                    out.push_back(symbol(std::string(f.name), Function, index, s->span, f.name_span, enc));
                break;
            }
            case StmtKind::Object: {
                const ObjectStmt& o = s->as<ObjectStmt>();
                std::string name(text_of(text, o.keyword));
                int kind = Object;
                if (o.block_kind == BlockKind::Settings) kind = Module;
                if (o.block_kind == BlockKind::Camera) kind = Class;
                if (o.block_kind == BlockKind::Light) {
                    kind = Event;
                    if (!o.name.empty()) name += " " + std::string(o.name);
                }
                out.push_back(symbol(std::move(name), kind, index, s->span, s->keyword, enc));
                break;
            }
            case StmtKind::Group: {
                json g =
                    symbol(std::string(text_of(text, s->keyword)), Struct, index, s->span, s->keyword, enc);
                json children = json::array();
                symbols_of(s->as<GroupStmt>().body, text, index, enc, children);
                g["children"] = std::move(children);
                out.push_back(std::move(g));
                break;
            }
            case StmtKind::Instance: {
                const InstanceStmt& i = s->as<InstanceStmt>();
                std::string name = "object";
                if (i.value && i.value->kind == ExprKind::Ident)
                    name += " " + std::string(i.value->as<IdentExpr>().name);
                out.push_back(symbol(std::move(name), Object, index, s->span, s->keyword, enc));
                break;
            }
            // Objects made in loops and branches are the scene's too.
            case StmtKind::For:
                symbols_of(s->as<ForStmt>().body, text, index, enc, out);
                break;
            case StmtKind::If:
                for (const IfBranch& b : s->as<IfStmt>().branches) symbols_of(b.body, text, index, enc, out);
                break;
            case StmtKind::Include:
            case StmtKind::Item:
            case StmtKind::Return:
            case StmtKind::Call:
            case StmtKind::Bad:
                break;
        }
    }
}

}  // namespace

bool read_disk_include(const std::string& path, std::string& text, std::string& reason) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode)) {
        reason = "it is not a regular file";
        return false;
    }
    return lang::read_include_file(path, text, reason);
}

json position_json(Position p) {
    return {{"line", p.line}, {"character", p.character}};
}

json range_json(const LineIndex& index, uint32_t begin, uint32_t end, Encoding enc) {
    return {{"start", position_json(index.position(begin, enc))},
            {"end", position_json(index.position(std::max(begin, end), enc))}};
}

const ParsedFile& Document::syntax() {
    if (!parsed) parsed = parse_text(path, text);
    return *parsed;
}

json diagnostics(const Document& doc, Encoding enc, const FileReader& open_text,
                 const std::atomic<bool>* cancel) {
    SourceManager sources;
    Diagnostics diags;
    ParamTable params;
    LoadOptions options;
    options.fragment = doc.fragment;
    options.build = !doc.fragment;
    options.params = &params;
    options.cancel = cancel;
    options.read_include = [&](const std::string& path, std::string& text, std::string& reason) {
        if (std::optional<std::string> t = open_text(path)) {
            text = std::move(*t);
            return true;
        }
        return read_disk_include(path, text, reason);
    };
    json out = json::array();
    const LineIndex index(doc.text);
    try {
        load_scene(doc.path, doc.text, sources, diags, options);
    } catch (const std::exception& e) {
        out.push_back({{"range", range_json(index, 0, 0, enc)},
                       {"severity", 1},
                       {"source", "wsd"},
                       {"message", std::string("internal error: ") + e.what()}});
        return out;
    }
    for (const Diagnostic& d : diags.all()) {
        Span at = d.span;
        std::string message = d.message;
        json info = json::array();
        if (at.file != 0 && at.file < sources.size()) {
            // Shown at the document's outermost include that led there; the chain in the message.
            info.push_back(related(sources, doc.uri, at, d.message, enc));
            message = "in " + where(sources, at) + ": " + d.message;
            Span site{0, 0, 0};
            for (const Span& inc : d.include_chain) {
                message += "\n  included from " + where(sources, inc);
                if (inc.file == 0) site = inc;
            }
            at = site;
        }
        for (const std::vector<Note>* notes : {&d.notes, &d.calls})
            for (const Note& n : *notes)
                if (n.span.file < sources.size())
                    info.push_back(related(sources, doc.uri, n.span, n.message, enc));
        for (const std::string& h : d.help) message += "\nhelp: " + h;
        json diag = {{"range", range_json(index, at.begin, at.end, enc)},
                     {"severity", severity_code(d.severity)},
                     {"source", "wsd"},
                     {"message", message}};
        if (!info.empty()) diag["relatedInformation"] = std::move(info);
        out.push_back(std::move(diag));
    }
    if (diags.error_count() > Diagnostics::max_errors)
        out.push_back(
            {{"range", range_json(index, 0, 0, enc)},
             {"severity", 1},
             {"source", "wsd"},
             {"message", "too many errors (" + std::to_string(diags.error_count()) + "); only the first " +
                             std::to_string(Diagnostics::max_errors) + " are shown"}});
    return out;
}

json definition(Document& doc, Position at, Encoding enc, const FileReader& reader) {
    const ParsedFile& file = doc.syntax();
    const uint32_t offset = LineIndex(doc.text).offset(at, enc);
    const Context c = context_at(file, offset);
    Workspace ws(doc.parsed, reader);
    auto location = [&](const ParsedFile* f, Span span) -> json {
        const bool main = f == &file;
        const LineIndex index(f->text());
        return {{"uri", main ? doc.uri : path_to_uri(f->path)},
                {"range", range_json(index, span.begin, span.end, enc)}};
    };
    if (c.include) {
        if (const ParsedFile* inc = ws.included(file, *c.include)) return location(inc, Span{0, 0, 0});
        return nullptr;
    }
    if (!c.name.empty())
        if (const std::optional<Definition> d = ws.resolve(c.name, offset))
            return location(d->file, d->name_span);
    return nullptr;
}

json document_symbols(Document& doc, Encoding enc) {
    const ParsedFile& file = doc.syntax();
    json out = json::array();
    symbols_of(file.program.statements, file.text(), LineIndex(file.text()), enc, out);
    return out;
}

json formatting(const Document& doc, Encoding enc) {
    SourceManager sources;
    Diagnostics diags;
    const uint32_t id = sources.add(doc.path, doc.text);
    const std::optional<std::string> text = format_source(id, sources, diags);
    json out = json::array();
    if (!text || *text == doc.text) return out;
    const LineIndex index(doc.text);
    out.push_back(
        {{"range", range_json(index, 0, static_cast<uint32_t>(doc.text.size()), enc)}, {"newText", *text}});
    return out;
}

}  // namespace wsd::app::lsp
