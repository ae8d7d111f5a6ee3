// The AST walks of the language server: scopes (which names a position sees) and the node under a
// position. Both follow the interpreter's rules as far as the syntax shows them: a `let` is seen
// after its statement, a `fn` anywhere in its scope (bodies resolve names when they run), loop
// variables and parameters in their bodies, and an include's top-level names after the include.
#include "app/lsp_syntax.h"

#include "lang/lower.h"
#include "lang/parser.h"

namespace wsd::app::lsp {

namespace {

using namespace lang;

constexpr int kMaxIncludeDepth = 16;

bool contains(Span s, uint32_t offset) {
    return offset >= s.begin && offset <= s.end;
}

// The walk that finds the node under `offset`; blocks and bodies count as around the offset
// from just after their opening brace to their closing one.
class Finder {
public:
    Finder(uint32_t offset, Context& out) : at_(offset), out_(out) {}

    void stmts(StmtList list) {
        for (const Stmt* s : list)
            if (s && s->span.begin <= at_ && (at_ <= s->span.end || s == list.back())) stmt(*s);
    }

private:
    void block(const Block& b, const BlockTable* table) {
        if (!(at_ > b.open.begin && at_ <= b.close.begin)) {
            items(b, table);  // still look for the names in it
            return;
        }
        out_.block = &b;
        out_.table = table;
        out_.group = nullptr;
        items(b, table);
    }
    void items(const Block& b, const BlockTable* table) {
        for (const Item& item : b.items) {
            if (!item.name.empty() && contains(item.name_span, at_)) {
                out_.item = &item;
                out_.item_table = table;
            }
            exprs(item.values);
        }
    }
    void exprs(ExprList list) {
        for (const Expr* e : list)
            if (e) expr(*e);
    }
    void expr(const Expr& e) {
        if (!contains(e.span, at_)) return;
        switch (e.kind) {
            case ExprKind::Number:
            case ExprKind::String:
            case ExprKind::Bool:
            case ExprKind::PackedList:
            case ExprKind::Bad:
                return;
            case ExprKind::Ident:
                out_.name = e.as<IdentExpr>().name;
                out_.name_span = e.span;
                return;
            case ExprKind::Vector:
                return exprs(e.as<VectorExpr>().components);
            case ExprKind::List:
                return exprs(e.as<ListExpr>().elements);
            case ExprKind::Unary:
                return expr(*e.as<UnaryExpr>().operand);
            case ExprKind::Binary:
                return exprs(e.as<BinaryExpr>().operands);
            case ExprKind::Call: {
                const CallExpr& c = e.as<CallExpr>();
                if (contains(c.name_span, at_)) {
                    out_.name = c.name;
                    out_.name_span = c.name_span;
                }
                return exprs(c.args);
            }
            case ExprKind::Member:
                return expr(*e.as<MemberExpr>().operand);
            case ExprKind::Index:
                expr(*e.as<IndexExpr>().operand);
                return expr(*e.as<IndexExpr>().index);
            case ExprKind::Material:
            case ExprKind::Checker:
            case ExprKind::Perlin: {
                const BlockExpr& b = e.as<BlockExpr>();
                if (b.block) block(*b.block, &expression_table(e.kind));
                return;
            }
            case ExprKind::Image:
                return expr(*e.as<ImageExpr>().path);
            case ExprKind::Object:
                if (e.as<ObjectExpr>().object) stmt(*e.as<ObjectExpr>().object);
                return;
        }
    }
    void defining(const Stmt& s, Span name_span) {
        if (name_span.end > name_span.begin && contains(name_span, at_)) out_.defining = &s;
    }
    void stmt(const Stmt& s) {
        switch (s.kind) {
            case StmtKind::Let:
                defining(s, s.as<LetStmt>().name_span);
                return expr(*s.as<LetStmt>().value);
            case StmtKind::For: {
                const ForStmt& f = s.as<ForStmt>();
                defining(s, f.name_span);
                expr(*f.value);
                if (f.range_end) expr(*f.range_end);
                return stmts(f.body);
            }
            case StmtKind::If:
                for (const IfBranch& b : s.as<IfStmt>().branches) {
                    if (b.condition) expr(*b.condition);
                    stmts(b.body);
                }
                return;
            case StmtKind::Include:
                if (contains(s.as<IncludeStmt>().path_span, at_)) out_.include = &s.as<IncludeStmt>();
                return;
            case StmtKind::Object: {
                const ObjectStmt& o = s.as<ObjectStmt>();
                Diagnostics ignored;
                return block(o.block, statement_table(o, ignored));
            }
            case StmtKind::Group: {
                const GroupStmt& g = s.as<GroupStmt>();
                if (at_ > g.open.begin && at_ <= g.close.begin) {
                    out_.group = &g;
                    out_.block = nullptr;
                    out_.table = nullptr;
                }
                if (s.span.begin <= at_ && at_ <= s.span.end)
                    group_table_ = &block_table(group_keyword(g.group_kind));
                return stmts(g.body);
            }
            case StmtKind::Instance: {
                const InstanceStmt& i = s.as<InstanceStmt>();
                expr(*i.value);
                return block(i.block, &block_table("object"));
            }
            case StmtKind::Item: {
                const Item& item = s.as<ItemStmt>().item;
                // An item of a group body: its table is the group's (set by the enclosing walk).
                if (!item.name.empty() && contains(item.name_span, at_)) {
                    out_.item = &item;
                    out_.item_table = group_table_;
                }
                return exprs(item.values);
            }
            case StmtKind::Fn: {
                const FnStmt& f = s.as<FnStmt>();
                defining(s, f.name_span);
                for (const Param& p : f.params)
                    if (p.fallback) expr(*p.fallback);
                if (s.span.begin <= at_ && at_ <= s.span.end) out_.in_fn = true;
                return stmts(f.body);
            }
            case StmtKind::Return:
                return expr(*s.as<ReturnStmt>().value);
            case StmtKind::Call: {
                const CallExpr* c = s.as<CallStmt>().call;
                if (c) expr(*c);
                return;
            }
            case StmtKind::Bad:
                return;
        }
    }

public:
    void walk(StmtList list) { stmts(list); }

private:
    uint32_t at_;
    Context& out_;
    const BlockTable* group_table_ = nullptr;
};

}  // namespace

std::shared_ptr<ParsedFile> parse_text(const std::string& path, std::string text) {
    auto file = std::make_shared<ParsedFile>();
    file->path = path;
    const uint32_t id = file->sources.add(path, std::move(text));
    Diagnostics ignored;  // the diagnostics come from the full check
    file->program = parse(id, file->sources, ignored);
    return file;
}

std::string Workspace::include_path(const ParsedFile& from, const IncludeStmt& stmt) const {
    return resolve_path(from.sources, 0, std::string(stmt.path));
}

const ParsedFile* Workspace::included(const ParsedFile& from, const IncludeStmt& stmt) {
    const std::string path = include_path(from, stmt);
    const std::string key = canonical_path(path);
    auto it = files_.find(key);
    if (it == files_.end()) {
        std::optional<std::string> text = reader_(path);
        it = files_.emplace(key, text ? parse_text(path, std::move(*text)) : nullptr).first;
    }
    return it->second.get();
}

void Workspace::add_file_top_level(const ParsedFile& file, std::vector<Definition>& out, int depth) {
    if (!added_.insert(&file).second) return;
    visible_in(file, file.program.statements, UINT32_MAX, true, out, depth);
}

void Workspace::visible_in(const ParsedFile& file, StmtList list, uint32_t offset, bool top,
                           std::vector<Definition>& out, int depth) {
    // Functions of the scope first: they are visible anywhere in it.
    for (const Stmt* s : list)
        if (s && s->kind == StmtKind::Fn && !s->as<FnStmt>().name.empty())
            out.push_back(
                {Definition::Kind::Fn, s->as<FnStmt>().name, s->as<FnStmt>().name_span, &file, s, top});
    for (const Stmt* s : list) {
        if (!s || s->span.begin >= offset) break;
        const bool around = offset <= s->span.end;
        switch (s->kind) {
            case StmtKind::Let:
                if (!around && !s->as<LetStmt>().name.empty())
                    out.push_back({Definition::Kind::Let, s->as<LetStmt>().name, s->as<LetStmt>().name_span,
                                   &file, s, top});
                break;
            case StmtKind::Include:
                if (!around && depth < kMaxIncludeDepth)
                    if (const ParsedFile* inc = included(file, s->as<IncludeStmt>()))
                        add_file_top_level(*inc, out, depth + 1);
                break;
            case StmtKind::For:
                if (around) {
                    const ForStmt& f = s->as<ForStmt>();
                    if (!f.name.empty())
                        out.push_back({Definition::Kind::Loop, f.name, f.name_span, &file, s, false});
                    visible_in(file, f.body, offset, false, out, depth);
                }
                break;
            case StmtKind::If:
                if (around)
                    for (const IfBranch& b : s->as<IfStmt>().branches)
                        if (!b.body.empty() && b.body.front()->span.begin <= offset)
                            visible_in(file, b.body, offset, false, out, depth);
                break;
            case StmtKind::Group:
                if (around) visible_in(file, s->as<GroupStmt>().body, offset, false, out, depth);
                break;
            case StmtKind::Fn:
                if (around) {
                    const FnStmt& f = s->as<FnStmt>();
                    for (const Param& p : f.params)
                        out.push_back({Definition::Kind::Param, p.name, p.name_span, &file, s, false});
                    visible_in(file, f.body, offset, false, out, depth);
                }
                break;
            case StmtKind::Object:
            case StmtKind::Instance:
            case StmtKind::Item:
            case StmtKind::Return:
            case StmtKind::Call:
            case StmtKind::Bad:
                break;
        }
    }
}

std::vector<Definition> Workspace::visible_at(uint32_t offset) {
    std::vector<Definition> out;
    added_ = {main_.get()};
    visible_in(*main_, main_->program.statements, offset, true, out, 0);
    return out;
}

std::optional<Definition> Workspace::resolve(std::string_view name, uint32_t offset) {
    const std::vector<Definition> seen = visible_at(offset);
    for (auto it = seen.rbegin(); it != seen.rend(); ++it)
        if (it->name == name) return *it;
    return std::nullopt;
}

Context context_at(const ParsedFile& file, uint32_t offset) {
    Context out;
    Finder(offset, out).walk(file.program.statements);
    return out;
}

}  // namespace wsd::app::lsp
