// The recursive-descent parser, expressions: precedence climbing over the binary levels, unary
// and postfix operators, primaries, vector literals (where '>' closes and a bare comparison needs
// parentheses) and lists, with the packed fast path for lists of numeric vector literals.
#include "lang/parser_internal.h"

namespace wsd::lang::detail {

namespace {

struct BinaryInfo {
    BinaryOp op;
    int precedence;  // 0: not a binary operator
};

constexpr int comparison_precedence = 4;

BinaryInfo binary_info(TokenKind k) {
    switch (k) {
        case TokenKind::OrOr:
            return {BinaryOp::Or, 1};
        case TokenKind::AndAnd:
            return {BinaryOp::And, 2};
        case TokenKind::EqEq:
            return {BinaryOp::Eq, 3};
        case TokenKind::NotEq:
            return {BinaryOp::Ne, 3};
        case TokenKind::Less:
            return {BinaryOp::Lt, 4};
        case TokenKind::LessEq:
            return {BinaryOp::Le, 4};
        case TokenKind::Greater:
            return {BinaryOp::Gt, 4};
        case TokenKind::GreaterEq:
            return {BinaryOp::Ge, 4};
        case TokenKind::Plus:
            return {BinaryOp::Add, 5};
        case TokenKind::Minus:
            return {BinaryOp::Sub, 5};
        case TokenKind::Star:
            return {BinaryOp::Mul, 6};
        case TokenKind::Slash:
            return {BinaryOp::Div, 6};
        case TokenKind::Percent:
            return {BinaryOp::Mod, 6};
        default:
            return {BinaryOp::Add, 0};
    }
}

}  // namespace

// expression     = or_expr ;
// or_expr        = and_expr { "||" and_expr } ;
// and_expr       = equality { "&&" equality } ;
// equality       = comparison { ( "==" | "!=" ) comparison } ;
// comparison     = additive { ( "<" | "<=" | ">" | ">=" ) additive } ;
// additive       = multiplicative { ( "+" | "-" ) multiplicative } ;
// multiplicative = unary { ( "*" | "/" | "%" ) unary } ;
// and inside a vector literal (component = v_or_expr):
// v_or_expr  = v_and_expr { "||" v_and_expr } ;
// v_and_expr = v_equality { "&&" v_equality } ;
// v_equality = additive { ( "==" | "!=" ) additive } ;
// One precedence-climbing loop for all levels: operands of an operator of precedence p are
// parsed at p + 1, so a chain of any length uses constant stack. Operators of one level in a row
// (`a + b - c + ...`) make one flat Binary node, not a left-deep tree: a generated 100,000-term
// sum is one node with 100,000 operands, which every later pass walks with a loop.
Expr* Parser::parse_binary(int min_precedence) {
    Expr* left = parse_unary();
    // The chain this loop is building: levels only fall along one loop (higher ones were taken
    // by the recursive call), so an operator of another level starts a new chain with the
    // previous one as its first operand.
    int chain_precedence = 0;
    std::vector<Expr*> operands;
    std::vector<BinaryLink> ops;
    auto finish_chain = [&] {
        if (chain_precedence == 0) return;
        auto* chain = expr<BinaryExpr>(ExprKind::Binary,
                                       {file_, operands.front()->span.begin, operands.back()->span.end});
        chain->operands = keep(operands);
        chain->ops = keep(ops);
        operands.clear();
        ops.clear();
        left = chain;
    };
    for (;;) {
        const BinaryInfo info = binary_info(tok_.kind);
        if (info.precedence == 0 || info.precedence < min_precedence) break;
        if (in_vector_ && info.precedence == comparison_precedence) {
            if (check(TokenKind::Greater) || check(TokenKind::GreaterEq)) break;  // closes the vector
            const std::string op(lexeme(tok_));
            if (Diagnostic* d =
                    error_here("comparison '" + op + "' inside a vector literal needs parentheses"))
                d->help.push_back("write the comparison in parentheses: <(a " + op + " b), ...>");
        }
        const Token op = tok_;
        advance();
        Expr* right = parse_binary(info.precedence + 1);
        if (chain_precedence != info.precedence) {
            finish_chain();
            operands.push_back(left);
            chain_precedence = info.precedence;
        }
        ops.push_back({info.op, span_of(op)});
        operands.push_back(right);
    }
    finish_chain();
    return left;
}

// unary = ( "-" | "!" ) unary | postfix ;
Expr* Parser::parse_unary() {
    const Token op = tok_;
    if (!enter(op)) return bad_here();
    Expr* result;
    if (check(TokenKind::Minus) || check(TokenKind::Bang)) {
        advance();
        Expr* operand = parse_unary();
        auto* u = expr<UnaryExpr>(ExprKind::Unary, {file_, op.begin, operand->span.end});
        u->op = op.kind == TokenKind::Minus ? UnaryOp::Neg : UnaryOp::Not;
        u->op_span = span_of(op);
        u->operand = operand;
        result = u;
    } else {
        result = parse_postfix();
    }
    leave();
    return result;
}

// postfix = primary { "." IDENT | "[" expression "]" } ;
// Each field or index nests the tree one level deeper (its operand is inside it), so each counts
// against the nesting limit like a parenthesis: `a[0][0]...` is nesting, not a flat chain.
Expr* Parser::parse_postfix() {
    Expr* e = parse_primary();
    int levels = 0;
    while (!panic_) {
        if ((check(TokenKind::Dot) || check(TokenKind::LBracket)) && !enter(tok_)) break;
        ++levels;
        if (check(TokenKind::Dot)) {
            advance();
            if (!check(TokenKind::Ident)) {
                error_here("expected a field name after '.', found " + found());
                break;
            }
            auto* m = expr<MemberExpr>(ExprKind::Member, {file_, e->span.begin, tok_.end});
            m->operand = e;
            m->field = keep(lexeme(tok_));
            m->field_span = span_of(tok_);
            advance();
            e = m;
        } else if (check(TokenKind::LBracket)) {
            const Token open = tok_;
            advance();
            const bool saved_vector = in_vector_;
            in_vector_ = false;
            Expr* index = parse_expression();
            in_vector_ = saved_vector;
            if (check(TokenKind::RBracket)) {
                advance();
            } else {
                unclosed(open, "expected ']' after the index, found " + found());
            }
            auto* ix = expr<IndexExpr>(ExprKind::Index, span_from(e->span.begin));
            ix->operand = e;
            ix->index = index;
            ix->bracket = span_of(open);
            e = ix;
        } else {
            --levels;
            break;
        }
    }
    // Nothing else may follow an operand with '(': a call's callee is a name.
    if (!panic_ && check(TokenKind::LParen) && e->kind != ExprKind::Bad) {
        const bool parenthesized = e->span.begin < text_.size() && text_[e->span.begin] == '(';
        if (e->kind == ExprKind::Index || e->kind == ExprKind::Member || e->kind == ExprKind::Call ||
            parenthesized)
            not_a_callee(*e);
    }
    for (; levels > 0; --levels) leave();
    return e;
}

// primary = NUMBER | STRING | "true" | "false" | IDENT [ "(" [ expression { "," expression } ] ")" ]
//         | "(" expression ")" | vector | list | "material" block | "image" expression
//         | "checker" block | "perlin" block | object_value ;
Expr* Parser::parse_primary() {
    const Token t = tok_;
    switch (t.kind) {
        case TokenKind::Number: {
            advance();
            auto* e = expr<NumberExpr>(ExprKind::Number, span_of(t));
            e->value = t.number;
            return e;
        }
        case TokenKind::String: {
            advance();
            auto* e = expr<StringExpr>(ExprKind::String, span_of(t));
            e->text = keep(decode_string(lexeme(t)));
            return e;
        }
        case TokenKind::True:
        case TokenKind::False: {
            advance();
            auto* e = expr<BoolExpr>(ExprKind::Bool, span_of(t));
            e->value = t.kind == TokenKind::True;
            return e;
        }
        case TokenKind::Ident: {
            advance();
            if (check(TokenKind::LParen)) return parse_call(t);
            auto* e = expr<IdentExpr>(ExprKind::Ident, span_of(t));
            e->name = keep(lexeme(t));
            return e;
        }
        case TokenKind::LParen:
            return parse_group();
        case TokenKind::Less:
            return parse_vector();
        case TokenKind::LBracket:
            return parse_list();
        case TokenKind::Material:
            return parse_block_expr(ExprKind::Material, "material");
        case TokenKind::Checker:
            return parse_block_expr(ExprKind::Checker, "checker");
        case TokenKind::Perlin:
            return parse_block_expr(ExprKind::Perlin, "perlin");
        case TokenKind::Image: {
            advance();
            Expr* path = parse_expression();
            auto* e = expr<ImageExpr>(ExprKind::Image, {file_, t.begin, path->span.end});
            e->path = path;
            return e;
        }
        default:
            if (starts_object_value(t.kind)) return parse_object_value();
            error_here("expected an expression, found " + found());
            return bad_here();
    }
}

// IDENT "(" [ expression { "," expression } [ "," ] ] ")"   (the call form of primary)
Expr* Parser::parse_call(const Token& name) {
    auto* e = expr<CallExpr>(ExprKind::Call, {});
    e->name = keep(lexeme(name));
    e->name_span = span_of(name);
    const Token open = tok_;
    advance();
    const bool saved_vector = in_vector_;
    in_vector_ = false;
    std::vector<Expr*> args;
    if (!check(TokenKind::RParen)) {
        for (;;) {
            args.push_back(parse_expression());
            if (panic_) break;
            if (check(TokenKind::Comma)) {
                advance();
                if (check(TokenKind::RParen)) break;  // a trailing comma, as in a parameter list
                continue;
            }
            if (!check(TokenKind::RParen))
                unclosed(open, "expected ',' or ')' in the call to '" + std::string(e->name) + "', found " +
                                   found());
            break;
        }
    }
    in_vector_ = saved_vector;
    if (check(TokenKind::RParen)) advance();
    e->args = keep(args);
    e->span = span_from(name.begin);
    return e;
}

// "(" expression ")"   (the parenthesized form of primary; the node's span covers the parentheses)
Expr* Parser::parse_group() {
    const Token open = tok_;
    advance();
    const bool saved_vector = in_vector_;
    in_vector_ = false;
    Expr* e = parse_expression();
    in_vector_ = saved_vector;
    if (check(TokenKind::RParen)) {
        advance();
        e->span = span_from(open.begin);
    } else {
        unclosed(open, "expected ')', found " + found());
    }
    return e;
}

// vector    = "<" component "," component [ "," component ] ">" ;
// component = v_or_expr ;
Expr* Parser::parse_vector() {
    const Token open = tok_;
    advance();
    auto* e = expr<VectorExpr>(ExprKind::Vector, {});
    std::vector<Expr*> components;
    const bool saved_vector = in_vector_;
    in_vector_ = true;
    for (;;) {
        components.push_back(parse_expression());
        if (panic_) break;
        const bool closing = check(TokenKind::Greater) || check(TokenKind::GreaterEq);
        if (check(TokenKind::Comma) && components.size() < 3) {
            const Token comma = tok_;
            advance();
            if (check(TokenKind::Greater) || check(TokenKind::GreaterEq)) {
                error(span_of(comma), "trailing comma in a vector literal");
                close_vector();
                break;
            }
            continue;
        }
        if (closing) {
            close_vector();
            if (components.size() < 2)
                error(span_from(open.begin), "a vector literal needs 2 or 3 components, found 1");
            break;
        }
        if (components.size() == 3) {
            if (Diagnostic* d = error_here("expected '>' to close the vector, found " + found())) {
                d->notes.push_back({span_of(open), "to match this '<'"});
                d->help.push_back("a vector literal has 2 or 3 components");
            }
        } else {
            unclosed(open, std::string(components.size() == 1 ? "expected ','" : "expected ',' or '>'") +
                               " after a vector component, found " + found());
        }
        break;
    }
    in_vector_ = saved_vector;
    e->components = keep(components);
    e->span = span_from(open.begin);
    return e;
}

// A vector literal's closing '>'. When the lexer read `>=` there, only the '>' is taken and the
// rest is lexed again: `<1,2,3>==v` is the vector, `==`, v.
void Parser::close_vector() {
    const Token closer = tok_;
    if (check(TokenKind::Greater)) {
        advance();
        return;
    }
    prev_ = {TokenKind::Greater, closer.begin, closer.begin + 1, 0};
    has_peek_ = false;
    lexer_.reset(closer.begin + 1);
    tok_ = lexer_.next();
    if (check(TokenKind::Assign)) {
        if (Diagnostic* d =
                error(span_of(closer), "comparison '>=' inside a vector literal needs parentheses"))
            d->help.push_back("at a vector literal's own level '>' closes it; write <(a >= b), ...>");
    }
}

// list = "[" [ expression { "," expression } [ "," ] ] "]" ;
Expr* Parser::parse_list() {
    const Token open = tok_;
    advance();
    if (check(TokenKind::Less) && !has_peek_) {
        if (Expr* packed = try_packed_list(open)) return packed;
    }
    auto* e = expr<ListExpr>(ExprKind::List, {});
    std::vector<Expr*> elements;
    const bool saved_vector = in_vector_;
    in_vector_ = false;
    while (!check(TokenKind::RBracket)) {
        if (!starts_expression(tok_.kind)) {
            unclosed(open, "expected a list element or ']', found " + found());
            break;
        }
        elements.push_back(parse_expression());
        if (panic_) break;
        if (check(TokenKind::Comma)) {
            advance();
            continue;
        }
        if (!check(TokenKind::RBracket)) unclosed(open, "expected ',' or ']' in the list, found " + found());
        break;
    }
    in_vector_ = saved_vector;
    if (check(TokenKind::RBracket)) advance();
    e->elements = keep(elements);
    e->span = span_from(open.begin);
    return e;
}

// The packed form of list: `[<1, 2, 3>, <-4, 5, 6>, ...]` becomes numbers plus element offsets,
// with no node per element, so a million-triangle inline mesh stays small. At the first element
// that is not such a literal the attempt is abandoned and the list re-read from its '[' (the
// lexer does not repeat its errors), so the result is always what the generic list would mean.
Expr* Parser::try_packed_list(const Token& open) {
    const Token restart = tok_;
    const Token restart_prev = prev_;
    const uint32_t restart_pos = lexer_.position();
    auto packed = std::make_shared<PackedVectors>();
    packed->file = file_;
    size_t dims = 0;
    while (check(TokenKind::Less)) {
        const uint32_t offset = tok_.begin;
        advance();
        double v[3] = {0, 0, 0};
        size_t n = 0;
        bool closed = false;
        while (n < 3) {
            const bool negative = check(TokenKind::Minus);
            if (negative) advance();
            if (!check(TokenKind::Number)) break;
            v[n++] = negative ? -tok_.number : tok_.number;
            advance();
            if (check(TokenKind::Comma)) {
                advance();
                continue;
            }
            closed = check(TokenKind::Greater);
            break;
        }
        if (!closed || n < 2 || (dims != 0 && n != dims)) break;
        advance();
        dims = n;
        packed->values.insert(packed->values.end(), v, v + n);
        packed->offsets.push_back(offset);
        if (check(TokenKind::Comma)) {
            advance();
            if (check(TokenKind::Less)) continue;
        }
        if (!check(TokenKind::RBracket)) break;
        advance();
        packed->dims = static_cast<int>(dims);
        auto* e = expr<PackedListExpr>(ExprKind::PackedList, span_from(open.begin));
        e->packed = std::move(packed);
        return e;
    }
    tok_ = restart;
    prev_ = restart_prev;
    has_peek_ = false;
    lexer_.reset(restart_pos);
    return nullptr;
}

// "material" block | "checker" block | "perlin" block   (the block forms of primary)
Expr* Parser::parse_block_expr(ExprKind kind, const char* what) {
    const Token keyword = tok_;
    advance();
    auto* e = expr<BlockExpr>(kind, {});
    e->block = arena_->make<Block>();
    if (check(TokenKind::LBrace)) {
        parse_block(*e->block, std::string(what) + " block", false);
    } else {
        error_here("expected '{' after '" + std::string(what) + "', found " + found());
    }
    e->span = span_from(keyword.begin);
    return e;
}

}  // namespace wsd::lang::detail
