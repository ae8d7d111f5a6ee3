// The recursive-descent parser, object values and bodies: `group`, `union`, `intersection` and
// `difference` bodies (statements and the items material, scale, rotate, translate), `object EXPR
// { items }` instances, and object blocks written where an expression is expected.
#include "lang/parser_internal.h"

namespace wsd::lang::detail {

namespace {

const std::vector<std::string> group_items = {"material", "scale", "rotate", "translate"};

GroupKind group_kind(TokenKind kind) {
    switch (kind) {
        case TokenKind::Union:
            return GroupKind::Union;
        case TokenKind::Intersection:
            return GroupKind::Intersection;
        case TokenKind::Difference:
            return GroupKind::Difference;
        default:
            return GroupKind::Group;
    }
}

}  // namespace

// object_value = object_keyword block | "triangle" triangle_block | group_stmt | instance_stmt ;
// The statement's node, wrapped: written here it is a value instead of being added.
Expr* Parser::parse_object_value() {
    const uint32_t begin = tok_.begin;
    Stmt* s;
    if (check(TokenKind::Object)) {
        s = parse_instance();
    } else if (check(TokenKind::Group) || check(TokenKind::Union) || check(TokenKind::Intersection) ||
               check(TokenKind::Difference)) {
        s = parse_group_stmt();
    } else {
        s = parse_object();
    }
    auto* e = expr<ObjectExpr>(ExprKind::Object, span_from(begin));
    e->object = s;
    return e;
}

// group_stmt = ( "group" | "union" | "intersection" | "difference" ) group_body ;
Stmt* Parser::parse_group_stmt() {
    auto* s = stmt<GroupStmt>(StmtKind::Group, span_of(tok_));
    s->group_kind = group_kind(tok_.kind);
    advance();
    s->open = s->close = span_of(tok_);
    if (check(TokenKind::LBrace)) {
        s->body = parse_group_body(*s);
    } else {
        error_here("expected '{' after '" + std::string(group_keyword(s->group_kind)) + "', found " +
                   found());
    }
    s->span = span_from(s->keyword.begin);
    return s;
}

// The four names that start an item in a group or CSG body; any other name starts a statement.
bool Parser::starts_group_item() {
    if (check(TokenKind::Material)) return true;
    if (!check(TokenKind::Ident)) return false;
    const std::string_view word = lexeme(tok_);
    return word == "scale" || word == "rotate" || word == "translate";
}

// group_body = "{" { group_item | statement } "}" ;
// group_item = "material" block | ( "material" | "scale" | "rotate" | "translate" ) value_list ;
StmtList Parser::parse_group_body(GroupStmt& group) {
    const Token open = tok_;
    if (!enter(open)) return {};
    advance();
    const bool saved_vector = in_vector_;
    in_vector_ = false;
    const std::string word = group_keyword(group.group_kind);
    std::vector<Stmt*> body;
    ++group_bodies_;
    while (!check(TokenKind::Eof) && !check(TokenKind::RBrace)) {
        if (starts_group_item()) {
            auto* item = stmt<ItemStmt>(StmtKind::Item, span_of(tok_));
            item->item = parse_item();
            item->span = span_from(item->keyword.begin);
            body.push_back(item);
        } else if (check(TokenKind::Ident) && peek().kind != TokenKind::LParen &&
                   peek().kind != TokenKind::Assign) {
            // `radius 1` in a group: a property, not a statement; `x = 1` is left to the statement
            // parser's own message.
            const std::string name(lexeme(tok_));
            body.push_back(stmt<Stmt>(StmtKind::Bad, span_of(tok_)));
            if (Diagnostic* d = error_here("'" + name + "' is not an item of a " + word)) {
                const std::string match = closest_match(name, group_items);
                if (!match.empty()) d->help.push_back("did you mean '" + match + "'?");
                d->help.push_back(
                    "a " + word +
                    " body holds statements and the items material, scale, rotate and translate");
            }
            advance();
        } else {
            body.push_back(parse_statement());
        }
        if (panic_) synchronize(false);
    }
    if (check(TokenKind::RBrace)) {
        group.close = span_of(tok_);
        advance();
    } else {
        group.close = {file_, tok_.begin, tok_.begin};
        unclosed(open, "expected '}' to close the " + word + " body, found " + found());
    }
    --group_bodies_;
    in_vector_ = saved_vector;
    leave();
    return keep(body);
}

// instance_stmt = "object" expression block ;
Stmt* Parser::parse_instance() {
    auto* s = stmt<InstanceStmt>(StmtKind::Instance, span_of(tok_));
    advance();
    s->block.open = s->block.close = span_of(tok_);
    if (check(TokenKind::LBrace)) {
        // POV-Ray's `object { NAME ... }`: the value is written before the block in wsd.
        const std::string name = peek().kind == TokenKind::Ident ? std::string(lexeme(peek())) : "NAME";
        if (Diagnostic* d = error_here("expected an object value after 'object', found '{'"))
            d->help.push_back("the value comes before the block: write 'object " + name +
                              " { ... }' (POV-Ray's spelling is 'object { " + name + " ... }')");
    } else {
        s->value = parse_expression();
        if (!panic_) {
            if (check(TokenKind::LBrace)) {
                if (parse_block(s->block, "object block", false)) panic_ = false;
            } else {
                error_here("expected '{' after the value of 'object', found " + found());
            }
        }
    }
    if (!s->value) s->value = bad_here();
    s->span = span_from(s->keyword.begin);
    return s;
}

}  // namespace wsd::lang::detail
