// The recursive-descent parser, functions: `fn` definitions with their parameters, `return`
// (allowed only inside a `fn` body, checked here so that a misplaced one is an error even in code
// that never runs) and calls written as statements.
#include <utility>

#include "lang/parser_internal.h"

namespace wsd::lang::detail {

// fn_stmt = "fn" IDENT "(" [ param { "," param } ] ")" body ;
Stmt* Parser::parse_fn() {
    auto* s = stmt<FnStmt>(StmtKind::Fn, span_of(tok_));
    advance();
    if (parse_name(s->name, s->name_span, "fn")) {
        if (check(TokenKind::LParen)) {
            parse_params(*s);
        } else {
            error_here("expected '(' after 'fn " + std::string(s->name) + "', found " + found());
        }
        if (!panic_) {
            // A function body is not part of the group body it may be written in.
            const bool saved = std::exchange(return_allowed_, true);
            const int saved_bodies = std::exchange(group_bodies_, 0);
            s->body = parse_body("function body");
            return_allowed_ = saved;
            group_bodies_ = saved_bodies;
        }
    }
    s->span = span_from(s->keyword.begin);
    return s;
}

// param = IDENT [ "=" expression ] ;
// Parameters with a default come last; a name appears once. Both are reported without losing
// the parser's place, so the body is still read.
void Parser::parse_params(FnStmt& fn) {
    const Token open = tok_;
    advance();
    std::vector<Param> params;
    const std::string where = "the parameters of '" + std::string(fn.name) + "'";
    while (!check(TokenKind::RParen)) {
        if (!check(TokenKind::Ident)) {
            unclosed(open, "expected a parameter name or ')' in " + where + ", found " + found());
            break;
        }
        Param param{keep(lexeme(tok_)), span_of(tok_), nullptr};
        advance();
        if (check(TokenKind::Assign)) {
            advance();
            param.fallback = parse_expression();
            if (panic_) break;
        }
        for (const Param& other : params) {
            if (other.name != param.name) continue;
            if (Diagnostic* d =
                    error(param.name_span, "duplicate parameter '" + std::string(param.name) + "'"))
                d->notes.push_back({other.name_span, "first declared here"});
            panic_ = false;
            break;
        }
        if (!param.fallback && !params.empty() && params.back().fallback) {
            if (Diagnostic* d = error(param.name_span, "parameter '" + std::string(param.name) +
                                                           "' needs a default: it follows a parameter "
                                                           "with one"))
                d->help.push_back("parameters with defaults come last");
            panic_ = false;
        }
        params.push_back(param);
        if (check(TokenKind::Comma)) {
            advance();
            continue;
        }
        if (!check(TokenKind::RParen))
            unclosed(open, "expected ',' or ')' in " + where + ", found " + found());
        break;
    }
    if (!panic_ && check(TokenKind::RParen)) advance();
    fn.params = keep(params);
}

// return_stmt = "return" expression ;   (only inside a fn body)
Stmt* Parser::parse_return() {
    auto* s = stmt<ReturnStmt>(StmtKind::Return, span_of(tok_));
    advance();
    if (group_bodies_ > 0) {
        if (Diagnostic* d = error(s->keyword, "'return' cannot be in a group or CSG body"))
            d->help.push_back(
                "a body builds an object value: return the whole value, as in "
                "'return group { ... }'");
        panic_ = false;
    } else if (!return_allowed_) {
        if (Diagnostic* d = error(s->keyword, "'return' outside a function body"))
            d->help.push_back("'return' ends a call of a function: it belongs in 'fn NAME(...) { ... }'");
        panic_ = false;  // the value is still read, with its own errors
    }
    if (starts_expression(tok_.kind)) {
        s->value = parse_expression();
    } else {
        error_here("expected a value after 'return', found " + found());
        s->value = bad_here();
    }
    s->span = span_from(s->keyword.begin);
    return s;
}

// call_stmt = IDENT "(" [ expression { "," expression } ] ")" ;
// Entered at a name followed by '(', '[' or '.': anything but a call there is not a statement.
Stmt* Parser::parse_call_statement() {
    const Token start = tok_;
    Expr* e = parse_postfix();
    if (e->kind == ExprKind::Call) {
        auto* s = stmt<CallStmt>(StmtKind::Call, span_of(start));
        s->call = &e->as<CallExpr>();
        s->span = e->span;
        return s;
    }
    if (!panic_) error(span_of(start), "expected a statement, found " + describe_token(start, text_));
    return stmt<Stmt>(StmtKind::Bad, span_of(start));
}

// `fs[0](2)`, `v.f(1)`, `(f)(1)` or `f(1)(2)`: only a name can be called.
void Parser::not_a_callee(const Expr& callee) {
    const std::string_view text = text_.substr(callee.span.begin, callee.span.end - callee.span.begin);
    constexpr size_t max_shown = 40;
    const std::string shown = text.size() <= max_shown ? std::string(text) : "...";
    if (Diagnostic* d = error_here("only a name can be called: '(' after an expression that is not a name"))
        d->help.push_back("bind the function to a name first: 'let g = " + shown + "', then call 'g(...)'");
}

}  // namespace wsd::lang::detail
