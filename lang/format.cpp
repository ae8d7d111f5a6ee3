// The formatter. It lays out the file's own tokens and comments again, never rewriting one: the
// parser's AST only says what each token is (where a statement or an item begins, which '<' opens
// a vector, which '-' is binary, which '(' and '[' call and index), so numbers, strings and
// parentheses stay as written and the meaning cannot change. The result is checked anyway: it must
// parse to the same AST (positions aside) with the same comments, or nothing is returned.
//
// The style (docs/wsd-cli.md, "Formatting"): four spaces a level; a block or body written on one
// line stays on one line when it holds no comment and fits in 100 columns, its items two spaces
// apart; otherwise `{` ends its line, each statement or item starts its own line and `}` stands
// alone. Line breaks inside a statement are kept (continuation lines indent four more, or to the
// open bracket's level); blank lines between lines are kept, at most one in a row.
#include "lang/format.h"

#include <algorithm>
#include <vector>

#include "lang/ast.h"
#include "lang/ast_equal.h"
#include "lang/lexer.h"
#include "lang/parser.h"

namespace wsd::lang {

namespace {

constexpr size_t column_limit = 100;
constexpr uint32_t indent_width = 4;

// What the AST says about the token at an offset.
enum Role : uint8_t {
    item_start = 1,    // a statement, or an item of a block or body, begins here
    vector_open = 2,   // '<' of a vector literal
    vector_close = 4,  // its '>' (found while lexing)
    binary_minus = 8,  // '-' between two operands
    callee = 16,       // the name of a call or fn: its '(' follows with no space
    index_open = 32,   // '[' of an index
};

struct Mark {
    uint32_t offset;
    uint8_t role;
};

// Walks the AST and marks the offsets of the tokens whose role the layout needs.
class Marker {
public:
    Marker(uint32_t file, std::string_view text) : lexer_(file, text, nullptr) {}

    std::vector<Mark> marks;

    void statements(StmtList list) {
        for (const Stmt* s : list) {
            mark(s->span.begin, item_start);
            statement(*s);
        }
    }

private:
    void mark(uint32_t offset, uint8_t role) { marks.push_back({offset, role}); }
    // The offset of a vector's '<': a parenthesized vector's span begins at its first '('.
    uint32_t vector_open_at(const Expr& e) {
        if (lexer_.text()[e.span.begin] == '<') return e.span.begin;
        lexer_.reset(e.span.begin);
        Token t = lexer_.next();
        while (t.kind != TokenKind::Less && t.kind != TokenKind::Eof) t = lexer_.next();
        return t.begin;
    }
    void exprs(ExprList list) {
        for (const Expr* e : list) expr(*e);
    }
    void statement(const Stmt& s);
    void expr(const Expr& e);
    void block(const Block& b) {
        for (const Item& it : b.items) item(it);
    }
    void item(const Item& it) {
        if (!it.name.empty())
            mark(it.name_span.begin, item_start);
        else if (!it.values.empty())
            mark(it.values[0]->span.begin, item_start);
        exprs(it.values);
    }

    Lexer lexer_;
};

void Marker::statement(const Stmt& s) {
    switch (s.kind) {
        case StmtKind::Let:
            expr(*s.as<LetStmt>().value);
            break;
        case StmtKind::For: {
            const auto& loop = s.as<ForStmt>();
            expr(*loop.value);
            if (loop.range_end) expr(*loop.range_end);
            statements(loop.body);
            break;
        }
        case StmtKind::If:
            for (const IfBranch& branch : s.as<IfStmt>().branches) {
                if (branch.condition) expr(*branch.condition);
                statements(branch.body);
            }
            break;
        case StmtKind::Include:
        case StmtKind::Bad:
            break;
        case StmtKind::Object:
            block(s.as<ObjectStmt>().block);
            break;
        case StmtKind::Group:
            statements(s.as<GroupStmt>().body);
            break;
        case StmtKind::Instance:
            expr(*s.as<InstanceStmt>().value);
            block(s.as<InstanceStmt>().block);
            break;
        case StmtKind::Item:
            item(s.as<ItemStmt>().item);
            break;
        case StmtKind::Fn: {
            const auto& fn = s.as<FnStmt>();
            mark(fn.name_span.begin, callee);
            for (const Param& p : fn.params)
                if (p.fallback) expr(*p.fallback);
            statements(fn.body);
            break;
        }
        case StmtKind::Return:
            expr(*s.as<ReturnStmt>().value);
            break;
        case StmtKind::Call:
            expr(*s.as<CallStmt>().call);
            break;
    }
}

void Marker::expr(const Expr& e) {
    switch (e.kind) {
        case ExprKind::Number:
        case ExprKind::String:
        case ExprKind::Bool:
        case ExprKind::Ident:
        case ExprKind::Bad:
            return;
        case ExprKind::Vector:
            mark(vector_open_at(e), vector_open);
            exprs(e.as<VectorExpr>().components);
            return;
        case ExprKind::List:
            exprs(e.as<ListExpr>().elements);
            return;
        case ExprKind::PackedList:
            for (const uint32_t offset : e.as<PackedListExpr>().packed->offsets) mark(offset, vector_open);
            return;
        case ExprKind::Unary:
            expr(*e.as<UnaryExpr>().operand);
            return;
        case ExprKind::Binary: {
            const auto& b = e.as<BinaryExpr>();
            for (const BinaryLink& link : b.ops)
                if (link.op == BinaryOp::Sub) mark(link.span.begin, binary_minus);
            exprs(b.operands);
            return;
        }
        case ExprKind::Call:
            mark(e.as<CallExpr>().name_span.begin, callee);
            exprs(e.as<CallExpr>().args);
            return;
        case ExprKind::Member:
            expr(*e.as<MemberExpr>().operand);
            return;
        case ExprKind::Index:
            expr(*e.as<IndexExpr>().operand);
            mark(e.as<IndexExpr>().bracket.begin, index_open);
            expr(*e.as<IndexExpr>().index);
            return;
        case ExprKind::Material:
        case ExprKind::Checker:
        case ExprKind::Perlin:
            block(*e.as<BlockExpr>().block);
            return;
        case ExprKind::Image:
            expr(*e.as<ImageExpr>().path);
            return;
        case ExprKind::Object:
            statement(*e.as<ObjectExpr>().object);
            return;
    }
}

// A token or a comment, in source order.
struct Element {
    TokenKind kind = TokenKind::Eof;  // Eof for a comment
    uint8_t role = 0;
    bool comment = false;
    bool line_comment = false;
    uint32_t begin = 0, end = 0;

    bool is(TokenKind k) const { return !comment && kind == k; }
    bool opens_bracket() const {
        return is(TokenKind::LParen) || is(TokenKind::LBracket) || (role & vector_open);
    }
    bool closes() const {
        return is(TokenKind::RBrace) || is(TokenKind::RParen) || is(TokenKind::RBracket) ||
               (role & vector_close);
    }
};

// The tokens (with their roles) and comments of the text. A '>=' that closes a vector is split
// as the parser splits it.
std::vector<Element> elements(uint32_t file, std::string_view text, std::vector<Mark> marks) {
    std::stable_sort(marks.begin(), marks.end(),
                     [](const Mark& a, const Mark& b) { return a.offset < b.offset; });
    Lexer lexer(file, text, nullptr);
    std::vector<Span> comments;
    lexer.record_comments(&comments);
    std::vector<Element> tokens;
    // The open brackets. Inside a block the parser skipped (an unknown property's `{ ... }`),
    // brackets need not balance: a '}' closes whatever its block left open.
    enum class Open : uint8_t { brace, bracket, vector };
    std::vector<Open> open;
    size_t m = 0;
    for (;;) {
        const Token t = lexer.next();
        if (t.kind == TokenKind::Eof) break;
        Element e;
        e.kind = t.kind;
        e.begin = t.begin;
        e.end = t.end;
        while (m < marks.size() && marks[m].offset < t.begin) ++m;
        for (; m < marks.size() && marks[m].offset == t.begin; ++m) e.role |= marks[m].role;
        switch (t.kind) {
            case TokenKind::LParen:
            case TokenKind::LBracket:
                open.push_back(Open::bracket);
                break;
            case TokenKind::LBrace:
                open.push_back(Open::brace);
                break;
            case TokenKind::Less:
                if (e.role & vector_open) open.push_back(Open::vector);
                break;
            case TokenKind::RParen:
            case TokenKind::RBracket:
                if (!open.empty() && open.back() != Open::brace) open.pop_back();
                break;
            case TokenKind::RBrace:
                while (!open.empty() && open.back() != Open::brace) open.pop_back();
                if (!open.empty()) open.pop_back();
                break;
            case TokenKind::Greater:
            case TokenKind::GreaterEq:
                if (!open.empty() && open.back() == Open::vector) {
                    open.pop_back();
                    e.role |= vector_close;
                    e.kind = TokenKind::Greater;
                    e.end = e.begin + 1;
                    lexer.reset(e.end);
                }
                break;
            default:
                break;
        }
        tokens.push_back(e);
    }
    // Merge the comments in.
    std::vector<Element> all;
    all.reserve(tokens.size() + comments.size());
    size_t c = 0;
    for (const Element& t : tokens) {
        for (; c < comments.size() && comments[c].begin < t.begin; ++c) {
            Element e;
            e.comment = true;
            e.line_comment = text[comments[c].begin + 1] == '/';
            e.begin = comments[c].begin;
            e.end = comments[c].end;
            all.push_back(e);
        }
        all.push_back(t);
    }
    for (; c < comments.size(); ++c) {
        Element e;
        e.comment = true;
        e.line_comment = text[comments[c].begin + 1] == '/';
        e.begin = comments[c].begin;
        e.end = comments[c].end;
        all.push_back(e);
    }
    return all;
}

// Whether the characters `last` and `first` may join across a token boundary: word characters
// and '.' (`a.5`, `..`), anything then '=' (`!=`, `<=`), '/' then anything (`//`), `&&`, `||`.
bool may_join(char last, char first) {
    const auto word = [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
               c == '.';
    };
    return (word(last) && word(first)) || first == '=' || last == '/' ||
           (last == first && (last == '&' || last == '|'));
}

// Whether tokens a and b, written with nothing between them, still lex as a and b: `. 5` must
// not become the number `.5`, nor `! ==` become `!=` and `=`.
bool lexes_apart(std::string_view text, const Element& a, const Element& b) {
    if (!may_join(text[a.end - 1], text[b.begin])) return true;
    std::string joined(text.substr(a.begin, a.end - a.begin));
    const uint32_t split = static_cast<uint32_t>(joined.size());
    joined += text.substr(b.begin, b.end - b.begin);
    Lexer lexer(0, joined, nullptr);
    const Token first = lexer.next();
    const Token second = lexer.next();
    return first.kind == a.kind && first.end == split && second.kind == b.kind && second.begin == split &&
           second.end == joined.size();
}

// The space between two tokens on one line, by their roles.
std::string_view role_spacing(const Element& a, const Element& b) {
    if (a.comment || b.comment) return " ";
    if (b.is(TokenKind::RBrace)) return a.is(TokenKind::LBrace) ? "" : " ";
    if (b.is(TokenKind::Comma) || b.closes()) return "";
    if (a.opens_bracket()) return "";
    if (a.is(TokenKind::Minus) && !(a.role & binary_minus)) return b.is(TokenKind::Minus) ? " " : "";
    if (a.is(TokenKind::Bang)) return "";
    if (b.is(TokenKind::LParen) && (a.role & callee)) return "";
    if (b.role & index_open) return "";
    if (b.is(TokenKind::Dot)) return a.is(TokenKind::Number) || a.is(TokenKind::LBrace) ? " " : "";
    if (a.is(TokenKind::Dot)) return "";
    if ((b.role & item_start) && !a.is(TokenKind::LBrace)) return "  ";
    return " ";
}

// The space between two tokens on one line: by their roles, and at least one where none would
// join them into other tokens (in a block the parser skipped, tokens can stand in any order).
std::string_view spacing(std::string_view text, const Element& a, const Element& b) {
    const std::string_view space = role_spacing(a, b);
    return space.empty() && !lexes_apart(text, a, b) ? " " : space;
}

// Whether element `e` goes on the line of `p` before it however they were written: `{`, `else`,
// `,`, `.`, a call's `(` and an index's `[` join the previous line.
bool joins_previous_line(const Element& p, const Element& e) {
    return e.is(TokenKind::LBrace) || e.is(TokenKind::Else) || e.is(TokenKind::Comma) ||
           e.is(TokenKind::Dot) || (e.is(TokenKind::LParen) && (p.role & callee)) || (e.role & index_open);
}

// Appends `text` with its CRLF and lone CR line breaks written as LF (a block comment's lines).
void append_lf(std::string& out, std::string_view text) {
    for (size_t i = 0; i < text.size(); ++i) {
        if (text[i] != '\r') {
            out += text[i];
            continue;
        }
        out += '\n';
        if (i + 1 < text.size() && text[i + 1] == '\n') ++i;
    }
}

// Line breaks in text[begin, end): LF, CRLF and a lone CR each count one.
uint32_t line_breaks(std::string_view text, uint32_t begin, uint32_t end) {
    uint32_t n = 0;
    for (uint32_t i = begin; i < end; ++i)
        if (text[i] == '\n' || (text[i] == '\r' && (i + 1 >= end || text[i + 1] != '\n'))) ++n;
    return n;
}

class Layout {
public:
    Layout(std::string_view text, std::vector<Element> elements) : text_(text), el_(std::move(elements)) {
        const size_t n = el_.size();
        breaks_.assign(n, 0);
        lines_prefix_.reserve(n);
        comments_.assign(n, 0);
        width_.assign(n, 0);
        match_.assign(n, 0);
        std::vector<size_t> open;
        for (size_t k = 0; k < n; ++k) {
            const Element& e = el_[k];
            if (k > 0) {
                breaks_[k] = line_breaks(text_, el_[k - 1].end, e.begin);
            }
            const uint32_t before = k > 0 ? width_[k - 1] : 0;
            width_[k] = before + static_cast<uint32_t>(k > 0 ? spacing(text_, el_[k - 1], e).size() : 0) +
                        (e.end - e.begin);
            comments_[k] = (k > 0 ? comments_[k - 1] : 0) + (e.comment ? 1 : 0);
            lines_prefix_.push_back((k > 0 ? lines_prefix_[k - 1] : 0) + breaks_[k]);
            if (e.is(TokenKind::LBrace)) open.push_back(k);
            if (e.is(TokenKind::RBrace) && !open.empty()) {
                match_[open.back()] = static_cast<uint32_t>(k);
                open.pop_back();
            }
        }
    }

    std::string run();

private:
    struct Frame {
        bool brace = false;
        bool multiline = true;
        uint32_t opener_indent = 0;  // the indent of the line the opener stands on
        uint32_t indent = 0;         // the indent of the lines inside
    };

    // Whether the block opened by element k, written on one line, stays on one line when it
    // starts at column `column`.
    bool one_line(size_t k, size_t column) const {
        const size_t j = match_[k];
        if (j <= k) return false;
        if (lines_prefix_[j] != lines_prefix_[k] || comments_[j] != comments_[k]) return false;
        const uint64_t width = uint32_t(width_[j] - width_[k]) + (el_[k].end - el_[k].begin);
        return column + width <= column_limit;
    }

    std::string_view text(const Element& e) const { return text_.substr(e.begin, e.end - e.begin); }

    std::string_view text_;
    std::vector<Element> el_;
    // Per element k (offsets and widths fit in 32 bits: the lexer reads at most 4 GiB).
    std::vector<uint32_t> breaks_;        // line breaks between element k - 1 and k
    std::vector<uint32_t> lines_prefix_;  // their running sum
    std::vector<uint32_t> comments_;      // comments among elements 0..k
    std::vector<uint32_t> width_;         // one-line width of elements 0..k (wrapping is harmless:
                                          // only differences within one block are used)
    std::vector<uint32_t> match_;         // for a '{', its '}'
};

std::string Layout::run() {
    std::string out;
    std::vector<Frame> frames;
    uint32_t line_indent = 0;
    size_t column = 0;
    const auto content_indent = [&] { return frames.empty() ? 0u : frames.back().indent; };
    const auto multiline_body = [&] { return frames.empty() || frames.back().multiline; };
    // The indent of a line that comment k starts: that of the items around it, or, when a token
    // follows the comment on its line (`1 +\n /* c */ 2`, or one that joins it from the next line,
    // `xs\n /* c */\n [0]`), the indent the line would have without the comment.
    const auto comment_line_indent = [&](size_t k) {
        size_t j = k;
        while (j + 1 < el_.size() && el_[j].comment && !el_[j].line_comment &&
               (breaks_[j + 1] == 0 || joins_previous_line(el_[j], el_[j + 1])))
            ++j;
        const Element& t = el_[j];
        if (t.comment || (t.role & item_start) || t.is(TokenKind::RBrace) || t.is(TokenKind::LBrace) ||
            t.is(TokenKind::Else))
            return content_indent();
        if (t.closes() && !frames.empty()) return frames.back().opener_indent;
        if (!frames.empty() && !frames.back().brace) return content_indent();
        return content_indent() + indent_width;
    };
    for (size_t k = 0; k < el_.size(); ++k) {
        const Element& e = el_[k];
        if (k > 0) {
            const Element& p = el_[k - 1];
            const uint32_t gap = breaks_[k];
            bool newline = false;
            uint32_t indent = 0;
            if (e.comment) {
                newline = gap > 0 || p.line_comment;
                indent = newline ? comment_line_indent(k) : content_indent();
            } else {
                // Brackets left open in a block the parser skipped close with the block.
                if (e.is(TokenKind::RBrace))
                    while (!frames.empty() && !frames.back().brace) frames.pop_back();
                const bool forced = p.line_comment || ((e.role & item_start) && multiline_body()) ||
                                    (p.is(TokenKind::LBrace) && multiline_body()) ||
                                    (e.is(TokenKind::RBrace) && multiline_body());
                newline = forced || (!joins_previous_line(p, e) && gap > 0);
                if (e.closes() && !frames.empty())
                    indent = frames.back().opener_indent;
                else if ((e.role & item_start) || (!frames.empty() && !frames.back().brace))
                    indent = content_indent();
                else
                    indent = content_indent() + indent_width;
            }
            if (newline) {
                out += '\n';
                if (gap >= 2 && !p.is(TokenKind::LBrace) && !e.is(TokenKind::RBrace)) out += '\n';
                out.append(indent, ' ');
                line_indent = indent;
                column = indent;
            } else {
                const std::string_view space = spacing(text_, p, e);
                out += space;
                column += space.size();
            }
        }
        const std::string_view t = text(e);
        if (e.comment)
            append_lf(out, t);
        else
            out += t;
        const size_t last_break = t.find_last_of("\r\n");
        column = last_break == std::string_view::npos ? column + t.size() : t.size() - last_break - 1;
        if (e.comment) continue;
        if (e.is(TokenKind::LBrace)) {
            Frame f;
            f.brace = true;
            f.multiline = !one_line(k, column - 1);
            // A body closes at the indent of its statement, also when the statement's head took
            // several lines (a long `for` list); inside brackets, at its own line's.
            f.opener_indent = frames.empty() || frames.back().brace ? content_indent() : line_indent;
            f.indent = f.opener_indent + indent_width;
            frames.push_back(f);
        } else if (e.opens_bracket()) {
            Frame f;
            f.opener_indent = line_indent;
            f.indent = line_indent + indent_width;
            frames.push_back(f);
        } else if (e.closes() && !frames.empty() && (e.is(TokenKind::RBrace) || !frames.back().brace)) {
            frames.pop_back();  // a stray ')' or ']' in a skipped block closes nothing
        }
    }
    if (!out.empty()) out += '\n';
    return out;
}

// The comments of `text`, their line breaks as LF (as the formatter writes them).
std::vector<std::string> comment_texts(uint32_t file, std::string_view text) {
    Lexer lexer(file, text, nullptr);
    std::vector<Span> comments;
    lexer.record_comments(&comments);
    while (lexer.next().kind != TokenKind::Eof) {
    }
    std::vector<std::string> texts(comments.size());
    for (size_t i = 0; i < comments.size(); ++i)
        append_lf(texts[i], text.substr(comments[i].begin, comments[i].end - comments[i].begin));
    return texts;
}

}  // namespace

std::optional<std::string> format_source(uint32_t file, const SourceManager& sources, Diagnostics& diags) {
    const Program program = parse(file, sources, diags);
    if (diags.has_errors()) return std::nullopt;
    const SourceFile& source = sources.file(file);
    const std::string_view text = source.text;

    Marker marker(file, text);
    marker.statements(program.statements);
    Layout layout(text, elements(file, text, std::move(marker.marks)));
    std::string out(text.substr(0, bom_length(text)));
    out += layout.run();

    // The guarantee: the same AST apart from positions, the same comments in the same order.
    SourceManager check_sources;
    const uint32_t check = check_sources.add(source.path, out);
    Diagnostics check_diags;
    const Program reparsed = parse(check, check_sources, check_diags);
    const bool same = !check_diags.has_errors() && same_ast(reparsed, program) &&
                      comment_texts(check, check_sources.file(check).text) == comment_texts(file, text);
    if (!same) {
        diags.error({file, 0, 0},
                    "formatting would change the meaning or the comments of this file; it is "
                    "left as it is (this is a bug in wsd fmt: please report it)");
        return std::nullopt;
    }
    return out;
}

}  // namespace wsd::lang
