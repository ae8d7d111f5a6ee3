// Internal to the parser (lang/parser.cpp: statements and blocks; lang/parse_expression.cpp:
// expressions, vectors and lists): the Parser class, its token helpers and its recovery state.
// Not part of the front end's interface; include lang/parser.h instead.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "lang/lexer.h"
#include "lang/parser.h"

namespace wsd::lang::detail {

// The keywords of an object block that may stand where an expression is expected.
inline bool starts_object_value(TokenKind k) {
    switch (k) {
        case TokenKind::Sphere:
        case TokenKind::Box:
        case TokenKind::Triangle:
        case TokenKind::Plane:
        case TokenKind::Mesh:
        case TokenKind::Cylinder:
        case TokenKind::Cone:
        case TokenKind::Torus:
        case TokenKind::Disc:
        case TokenKind::Group:
        case TokenKind::Union:
        case TokenKind::Intersection:
        case TokenKind::Difference:
        case TokenKind::Object:
            return true;
        default:
            return false;
    }
}

inline bool starts_expression(TokenKind k) {
    switch (k) {
        case TokenKind::Number:
        case TokenKind::String:
        case TokenKind::Ident:
        case TokenKind::True:
        case TokenKind::False:
        case TokenKind::LParen:
        case TokenKind::LBracket:
        case TokenKind::Less:
        case TokenKind::Minus:
        case TokenKind::Bang:
        case TokenKind::Material:
        case TokenKind::Image:
        case TokenKind::Checker:
        case TokenKind::Perlin:
            return true;
        default:
            return starts_object_value(k);
    }
}

class Parser {
public:
    Parser(uint32_t file, const SourceManager& sources, Diagnostics& diags)
        : file_(file), text_(sources.file(file).text), diags_(diags), lexer_(file, text_, &diags) {
        tok_ = lexer_.next();
    }

    Program parse_program();

private:
    // ---- tokens ----
    void advance() {
        prev_ = tok_;
        if (bailed_) return;  // tok_ stays at the end of the file
        if (has_peek_) {
            tok_ = peek_;
            has_peek_ = false;
        } else {
            tok_ = lexer_.next();
        }
    }
    const Token& peek() {
        if (!has_peek_) {
            peek_ = lexer_.next();
            has_peek_ = true;
        }
        return peek_;
    }
    bool check(TokenKind k) const { return tok_.kind == k; }
    Span span_of(const Token& t) const { return {file_, t.begin, t.end}; }
    Span span_from(uint32_t begin) const { return {file_, begin, std::max(begin, prev_.end)}; }
    std::string found() const { return describe_token(tok_, text_); }
    std::string_view lexeme(const Token& t) const { return text_.substr(t.begin, t.end - t.begin); }

    // ---- errors ----
    Diagnostic* error(Span span, std::string message);
    Diagnostic* error_here(std::string message) { return error(span_of(tok_), std::move(message)); }
    void unclosed(const Token& opener, std::string message);
    bool enter(const Token& at);  // nesting guard; false after the limit (the parse stops)
    void leave() { --depth_; }
    void bail();
    void synchronize(bool top_level);
    bool recover_in_block();

    // ---- statements ----
    StmtList parse_statements(bool top_level);
    Stmt* parse_statement();
    Stmt* parse_let();
    Stmt* parse_for();
    Stmt* parse_if();
    Stmt* parse_include();
    Stmt* parse_object();
    Stmt* parse_group_stmt();  // group, union, intersection, difference (parse_group.cpp)
    Stmt* parse_instance();    // object EXPR { items }
    StmtList parse_group_body(GroupStmt& group);
    bool starts_group_item();
    Expr* parse_object_value();  // an object block as an expression
    Stmt* parse_fn();
    void parse_params(FnStmt& fn);
    Stmt* parse_return();
    Stmt* parse_call_statement();
    void not_a_callee(const Expr& callee);
    StmtList parse_body(const char* what);
    bool parse_name(std::string_view& name, Span& span, const char* after);

    // ---- blocks ----
    bool parse_block(Block& block, const std::string& what, bool triangle);  // true: '}' consumed
    bool starts_vertex_list();
    Item parse_item();
    ExprList parse_value_list(const Item& item);
    static bool is_property_name(std::string_view name);
    Expr* skip_braced_block();
    bool colour_function_before_vector();

    // ---- expressions ----
    Expr* parse_expression() { return parse_binary(1); }
    Expr* parse_binary(int min_precedence);
    Expr* parse_unary();
    Expr* parse_postfix();
    Expr* parse_primary();
    Expr* parse_call(const Token& name);
    Expr* parse_group();
    Expr* parse_vector();
    Expr* parse_list();
    Expr* try_packed_list(const Token& open);
    Expr* parse_block_expr(ExprKind kind, const char* what);
    void close_vector();

    // ---- nodes (in the program's arena) ----
    template <class T>
    T* expr(ExprKind kind, Span span) {
        T* e = arena_->make<T>();
        e->kind = kind;
        e->span = span;
        return e;
    }
    template <class T>
    T* stmt(StmtKind kind, Span keyword) {
        T* s = arena_->make<T>();
        s->kind = kind;
        s->span = s->keyword = keyword;
        return s;
    }
    Expr* bad_here() { return expr<Expr>(ExprKind::Bad, {file_, tok_.begin, tok_.begin}); }
    template <class T>
    std::span<const T> keep(const std::vector<T>& items) {
        return arena_->copy(items);
    }
    std::string_view keep(std::string_view text) { return arena_->copy(text); }

    Arena* arena_ = nullptr;  // the program's, set by parse_program
    uint32_t file_;
    std::string_view text_;
    Diagnostics& diags_;
    Lexer lexer_;
    Token tok_, prev_, peek_;
    bool has_peek_ = false;
    bool panic_ = false;      // an error was reported; stay quiet until resynchronized
    bool bailed_ = false;     // nesting limit or too many errors: the parse winds down
    bool in_vector_ = false;  // directly inside a vector literal: '>' closes it
    // True only while parsing a `fn` body (a group or CSG body inside one sets it false again):
    // `return` anywhere else is an error, also in code that never runs.
    bool return_allowed_ = false;
    int depth_ = 0;
    int group_bodies_ = 0;  // group and CSG bodies being parsed, around the current token
};

}  // namespace wsd::lang::detail
