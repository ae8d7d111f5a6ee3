// The recursive-descent parser, statements and blocks: one function per production of
// grammar/wsd.ebnf (quoted above it), panic-mode recovery (an error silences further errors until
// the parser resynchronizes at the next statement), and a nesting counter instead of a deep
// stack. Expressions, vectors and lists are in parse_expression.cpp; group and CSG bodies, `object`
// and object blocks written as values in parse_group.cpp.
#include <limits>

#include "lang/lower.h"
#include "lang/parser_internal.h"

namespace wsd::lang {

namespace detail {

namespace {

const std::vector<std::string> statement_words = {
    "let",   "for",      "if",           "include",    "settings", "camera", "light", "sphere",
    "box",   "triangle", "plane",        "mesh",       "cylinder", "cone",   "torus", "disc",
    "group", "union",    "intersection", "difference", "object",   "fn",     "return"};

// The offset of the first character at or after `p` that is neither whitespace nor in a comment,
// as the lexer skips them (block comments nest; an unterminated one runs to the end).
size_t skip_blanks(std::string_view text, size_t p) {
    while (p < text.size()) {
        const char c = text[p];
        if (c == ' ' || c == '\t' || c == '\r' || c == '\n') {
            ++p;
        } else if (text.compare(p, 2, "//") == 0) {
            while (p < text.size() && text[p] != '\n' && text[p] != '\r') ++p;
        } else if (text.compare(p, 2, "/*") == 0) {
            int depth = 0;
            while (p < text.size()) {
                if (text.compare(p, 2, "/*") == 0) {
                    ++depth;
                    p += 2;
                } else if (text.compare(p, 2, "*/") == 0) {
                    p += 2;
                    if (--depth == 0) break;
                } else {
                    ++p;
                }
            }
        } else {
            break;
        }
    }
    return p;
}

}  // namespace

Diagnostic* Parser::error(Span span, std::string message) {
    if (panic_ || bailed_) return nullptr;
    panic_ = true;
    Diagnostic* d = &diags_.error(span, std::move(message));
    if (diags_.too_many()) bail();
    return d;
}

void Parser::unclosed(const Token& opener, std::string message) {
    if (Diagnostic* d = error_here(std::move(message)))
        d->notes.push_back({span_of(opener), "to match this '" + std::string(lexeme(opener)) + "'"});
}

bool Parser::enter(const Token& at) {
    if (bailed_) return false;
    if (++depth_ <= max_nesting) return true;
    --depth_;
    error(span_of(at), "nesting too deep (the limit is " + std::to_string(max_nesting) +
                           " nested blocks and expressions)");
    bail();
    return false;
}

void Parser::bail() {
    bailed_ = true;
    has_peek_ = false;
    const auto end = static_cast<uint32_t>(text_.size());
    tok_ = {TokenKind::Eof, end, end, 0};
}

// Panic mode ends at the next statement keyword or at the `}` closing the enclosing body,
// skipping balanced braces in between. At the top level there is no enclosing body: a stray `}`
// is skipped with the rest, so `}}}` is one error.
void Parser::synchronize(bool top_level) {
    int depth = 0;
    while (!check(TokenKind::Eof)) {
        if (depth == 0 && is_statement_keyword(tok_.kind)) break;
        if (check(TokenKind::LBrace)) {
            ++depth;
        } else if (check(TokenKind::RBrace)) {
            if (depth == 0 && !top_level) break;
            if (depth > 0) --depth;
        }
        advance();
    }
    panic_ = false;
}

// After an error inside a block: skip to its closing `}` (consumed: true), or stop before a
// statement keyword or the end of the file (false).
bool Parser::recover_in_block() {
    int depth = 0;
    while (!check(TokenKind::Eof)) {
        if (depth == 0 && is_statement_keyword(tok_.kind)) return false;
        if (check(TokenKind::LBrace)) {
            ++depth;
        } else if (check(TokenKind::RBrace)) {
            if (depth == 0) {
                advance();
                return true;
            }
            --depth;
        }
        advance();
    }
    return false;
}

// program = { statement } EOF ;
Program Parser::parse_program() {
    Program program;
    program.file = file_;
    arena_ = program.arena.get();
    if (text_.size() >= std::numeric_limits<uint32_t>::max()) {
        diags_.error({file_, 0, 0}, "file is too large (the limit is 4 GiB)");
        return program;
    }
    program.statements = parse_statements(true);
    return program;
}

StmtList Parser::parse_statements(bool top_level) {
    std::vector<Stmt*> statements;
    while (!check(TokenKind::Eof)) {
        if (check(TokenKind::RBrace)) {
            if (!top_level) break;
            error_here("unexpected '}' with no open block");
            advance();
        } else {
            statements.push_back(parse_statement());
        }
        if (panic_) synchronize(top_level);
    }
    return keep(statements);
}

// statement = let_stmt | for_stmt | if_stmt | include_stmt | object_stmt | group_stmt | instance_stmt
//           | fn_stmt | return_stmt | call_stmt ;
Stmt* Parser::parse_statement() {
    switch (tok_.kind) {
        case TokenKind::Let:
            return parse_let();
        case TokenKind::Fn:
            return parse_fn();
        case TokenKind::Return:
            return parse_return();
        case TokenKind::For:
            return parse_for();
        case TokenKind::If:
            return parse_if();
        case TokenKind::Include:
            return parse_include();
        case TokenKind::Settings:
        case TokenKind::Camera:
        case TokenKind::Light:
        case TokenKind::Sphere:
        case TokenKind::Box:
        case TokenKind::Triangle:
        case TokenKind::Plane:
        case TokenKind::Mesh:
        case TokenKind::Cylinder:
        case TokenKind::Cone:
        case TokenKind::Torus:
        case TokenKind::Disc:
            return parse_object();
        case TokenKind::Group:
        case TokenKind::Union:
        case TokenKind::Intersection:
        case TokenKind::Difference:
            return parse_group_stmt();
        case TokenKind::Object:
            return parse_instance();
        default:
            break;
    }
    Stmt* bad = stmt<Stmt>(StmtKind::Bad, span_of(tok_));
    if (check(TokenKind::Else)) {
        error_here("'else' without a matching 'if'");
    } else {
        // `x = 3`: a look at the raw text, not the lexer, so that no lexical error is reported
        // ahead of this one.
        std::string help;
        if (check(TokenKind::Ident)) {
            const std::string word(lexeme(tok_));
            const size_t p = skip_blanks(text_, tok_.end);
            // A call, or something called that is not a name (`fs[0](2)`, reported there).
            if (p < text_.size() && (text_[p] == '(' || text_[p] == '[' || text_[p] == '.'))
                return parse_call_statement();
            const bool assign =
                p < text_.size() && text_[p] == '=' && (p + 1 == text_.size() || text_[p + 1] != '=');
            const std::string match = closest_match(word, statement_words);
            if (assign)
                help = "to bind a name, write 'let " + word + " = ...'";
            else if (word == "light_source")
                help = "a light is written 'light point { position ... }' (or 'light area { ... }')";
            else if (word == "merge")
                help = "POV-Ray's 'merge' is 'union' in wsd: a union of solids has no inner surfaces";
            else if (!match.empty())
                help = "did you mean '" + match + "'?";
        }
        if (group_bodies_ > 0 && (check(TokenKind::Material) || lexeme(tok_) == "scale" ||
                                  lexeme(tok_) == "rotate" || lexeme(tok_) == "translate"))
            help =
                "a group's items (material, scale, rotate, translate) are written directly in its body, not "
                "inside 'if' or 'for'";
        if (Diagnostic* d = error_here("expected a statement, found " + found()); d && !help.empty())
            d->help.push_back(help);
    }
    advance();
    return bad;
}

bool Parser::parse_name(std::string_view& name, Span& span, const char* after) {
    // `for in xs`: the name is missing, not spelled `in`.
    const bool keyword =
        tok_.kind >= TokenKind::Let && tok_.kind <= TokenKind::False && !check(TokenKind::In);
    if (check(TokenKind::Ident) || keyword) {
        if (!check(TokenKind::Ident)) {
            // A reserved word in a name's place: report it and read it as the name, so the rest
            // of the statement parses normally.
            const std::string word(lexeme(tok_));
            if (Diagnostic* d = error_here("expected a name after '" + std::string(after) +
                                           "', found keyword '" + word + "'"))
                d->help.push_back("'" + word + "' is a reserved word; choose another name");
            panic_ = false;
        }
        name = keep(lexeme(tok_));
        span = span_of(tok_);
        advance();
        return true;
    }
    error_here("expected a name after '" + std::string(after) + "', found " + found());
    return false;
}

// let_stmt = "let" IDENT "=" expression ;
Stmt* Parser::parse_let() {
    auto* s = stmt<LetStmt>(StmtKind::Let, span_of(tok_));
    advance();
    if (parse_name(s->name, s->name_span, "let")) {
        if (check(TokenKind::Assign)) {
            advance();
            if (!colour_function_before_vector()) s->value = parse_expression();
        } else {
            error_here("expected '=' after 'let " + std::string(s->name) + "', found " + found());
        }
    }
    if (!s->value) s->value = bad_here();
    s->span = span_from(s->keyword.begin);
    return s;
}

// for_stmt = "for" IDENT "in" expression [ ".." expression ] body ;
Stmt* Parser::parse_for() {
    auto* s = stmt<ForStmt>(StmtKind::For, span_of(tok_));
    advance();
    if (parse_name(s->name, s->name_span, "for")) {
        if (check(TokenKind::In)) {
            advance();
            s->value = parse_expression();
            if (check(TokenKind::DotDot)) {
                advance();
                s->range_end = parse_expression();
            }
            if (!panic_) s->body = parse_body("for body");
        } else {
            error_here("expected 'in' after 'for " + std::string(s->name) + "', found " + found());
        }
    }
    if (!s->value) s->value = bad_here();
    s->span = span_from(s->keyword.begin);
    return s;
}

// if_stmt = "if" expression body { "else" "if" expression body } [ "else" body ] ;
Stmt* Parser::parse_if() {
    auto* s = stmt<IfStmt>(StmtKind::If, span_of(tok_));
    std::vector<IfBranch> branches;
    IfBranch first{nullptr, {}, s->keyword};
    advance();
    first.condition = parse_expression();
    if (!panic_) first.body = parse_body("if body");
    branches.push_back(first);
    while (!panic_ && check(TokenKind::Else)) {
        IfBranch branch{nullptr, {}, span_of(tok_)};
        advance();
        if (check(TokenKind::If)) {
            advance();
            branch.condition = parse_expression();
            if (!panic_) branch.body = parse_body("if body");
            branches.push_back(branch);
        } else {
            branch.body = parse_body("else body");
            branches.push_back(branch);
            break;
        }
    }
    s->branches = keep(branches);
    s->span = span_from(s->keyword.begin);
    return s;
}

// include_stmt = "include" STRING ;
Stmt* Parser::parse_include() {
    auto* s = stmt<IncludeStmt>(StmtKind::Include, span_of(tok_));
    advance();
    if (check(TokenKind::String)) {
        s->path = keep(decode_string(lexeme(tok_)));
        s->path_span = span_of(tok_);
        advance();
    } else {
        error_here("expected a file name string after 'include', found " + found());
    }
    s->span = span_from(s->keyword.begin);
    return s;
}

// body = "{" { statement } "}" ;
StmtList Parser::parse_body(const char* what) {
    if (!check(TokenKind::LBrace)) {
        error_here("expected '{' to start the " + std::string(what) + ", found " + found());
        return {};
    }
    const Token open = tok_;
    if (!enter(open)) return {};
    advance();
    const StmtList statements = parse_statements(false);
    if (check(TokenKind::RBrace)) {
        advance();
    } else {
        unclosed(open, "expected '}' to close the " + std::string(what) + ", found " + found());
    }
    leave();
    return statements;
}

namespace {

BlockKind block_kind(TokenKind kind) {
    switch (kind) {
        case TokenKind::Settings:
            return BlockKind::Settings;
        case TokenKind::Camera:
            return BlockKind::Camera;
        case TokenKind::Light:
            return BlockKind::Light;
        case TokenKind::Sphere:
            return BlockKind::Sphere;
        case TokenKind::Box:
            return BlockKind::Box;
        case TokenKind::Triangle:
            return BlockKind::Triangle;
        case TokenKind::Plane:
            return BlockKind::Plane;
        case TokenKind::Cylinder:
            return BlockKind::Cylinder;
        case TokenKind::Cone:
            return BlockKind::Cone;
        case TokenKind::Torus:
            return BlockKind::Torus;
        case TokenKind::Disc:
            return BlockKind::Disc;
        default:
            return BlockKind::Mesh;
    }
}

}  // namespace

// object_stmt    = object_keyword block | "light" IDENT block | "triangle" triangle_block ;
// object_keyword = "settings" | "camera" | "sphere" | "box" | "plane" | "mesh" ;
Stmt* Parser::parse_object() {
    auto* s = stmt<ObjectStmt>(StmtKind::Object, span_of(tok_));
    const TokenKind kind = tok_.kind;
    const std::string word(lexeme(tok_));
    s->block_kind = block_kind(kind);
    advance();
    if (kind == TokenKind::Light) {
        if (check(TokenKind::Ident)) {
            s->name = keep(lexeme(tok_));
            s->name_span = span_of(tok_);
            advance();
        } else {
            error_here("expected the light kind (point, area or spot) after 'light', found " + found());
            // With the block right there, read it anyway: its own errors are still worth having.
            if (check(TokenKind::LBrace)) panic_ = false;
        }
    }
    if (!panic_) {
        if (check(TokenKind::LBrace)) {
            // A statement whose block recovered at its own `}` ended cleanly: the next statement
            // is parsed normally, with its own errors.
            if (parse_block(s->block, word + " block", kind == TokenKind::Triangle)) panic_ = false;
        } else {
            error_here(
                "expected '{' after '" +
                (kind == TokenKind::Light && !s->name.empty() ? "light " + std::string(s->name) : word) +
                "', found " + found());
        }
    }
    s->span = span_from(s->keyword.begin);
    return s;
}

// block          = "{" { item } "}" ;
// triangle_block = "{" [ value_list ] { item } "}" ;
bool Parser::parse_block(Block& block, const std::string& what, bool triangle) {
    const Token open = tok_;
    block.open = span_of(open);
    block.close = span_of(open);
    if (!enter(open)) return false;
    bool closed = false;
    advance();
    const bool saved_vector = in_vector_;
    in_vector_ = false;
    std::vector<Item> items;
    if (triangle && starts_vertex_list()) {
        const Span at{file_, tok_.begin, tok_.begin};
        Item vertices{{}, at, {}};
        vertices.values = parse_value_list(vertices);
        items.push_back(vertices);
    }
    for (;;) {
        if (panic_) {
            closed = recover_in_block();
            if (closed) block.close = span_of(prev_);
            break;
        }
        if (check(TokenKind::RBrace)) {
            block.close = span_of(tok_);
            advance();
            closed = true;
            break;
        }
        if (check(TokenKind::Eof) || is_statement_keyword(tok_.kind)) {
            block.close = {file_, tok_.begin, tok_.begin};
            unclosed(open, "expected '}' to close " + what + ", found " + found());
            break;
        }
        if (check(TokenKind::Ident) || check(TokenKind::Material)) {
            items.push_back(parse_item());
        } else {
            error_here("expected a property name or '}' in " + what + ", found " + found());
        }
    }
    block.items = keep(items);
    in_vector_ = saved_vector;
    leave();
    return closed;
}
// The lookahead rule of triangle_block (see the grammar): does the block start with vertices?
bool Parser::starts_vertex_list() {
    if (!starts_expression(tok_.kind) || starts_object_value(tok_.kind)) return false;
    if (!check(TokenKind::Ident) && !check(TokenKind::Material)) return true;
    switch (peek().kind) {
        case TokenKind::Number:
        case TokenKind::String:
        case TokenKind::Ident:
        case TokenKind::True:
        case TokenKind::False:
        case TokenKind::Less:
        case TokenKind::Bang:
        case TokenKind::Material:
        case TokenKind::Image:
        case TokenKind::Checker:
        case TokenKind::Perlin:
            return false;
        case TokenKind::LBrace:
            return !check(TokenKind::Material);
        default:
            return true;
    }
}

// item          = "material" block | property_name value_list ;
// property_name = IDENT | "material" ;
Item Parser::parse_item() {
    Item item{keep(lexeme(tok_)), span_of(tok_), {}};
    const bool material = check(TokenKind::Material);
    advance();
    if (material && check(TokenKind::LBrace)) {
        const uint32_t begin = tok_.begin;
        auto* e = expr<BlockExpr>(ExprKind::Material, {});
        e->block = arena_->make<Block>();
        parse_block(*e->block, "material block", false);
        e->span = span_from(begin);
        item.values = keep(std::vector<Expr*>{e});
        return item;
    }
    item.values = parse_value_list(item);
    return item;
}

// value_list = expression { "," expression } ;
// A list ends at the first token that cannot continue an expression, so two slips read
// wrongly as values get messages of their own, at the word that caused them: POV-Ray's
// `color rgb <1, 0, 0>` (a function name before a vector, which parses as `rgb < 1`, ...) and a
// property with no value, `center radius 1` (where `radius` becomes the centre's value).
ExprList Parser::parse_value_list(const Item& item) {
    if (check(TokenKind::LBrace) && !item.name.empty() && !is_property_name(item.name)) {
        // `pigment { ... }`: a word no block knows, with a POV-Ray block after it. The block is
        // skipped and the block reader reports the unknown property with wsd's spelling.
        return keep(std::vector<Expr*>{skip_braced_block()});
    }
    // No property takes an object value: an object keyword there starts the next statement.
    if (!starts_expression(tok_.kind) || starts_object_value(tok_.kind)) {
        if (item.name.empty())
            error_here("expected a value, found " + found());
        else
            error_here("expected a value for '" + std::string(item.name) + "', found " + found());
        return keep(std::vector<Expr*>{bad_here()});
    }
    if (colour_function_before_vector()) return keep(std::vector<Expr*>{bad_here()});
    std::vector<Expr*> values{parse_expression()};
    while (!panic_ && check(TokenKind::Comma)) {
        advance();
        values.push_back(parse_expression());
    }
    const bool literal_follows = check(TokenKind::Number) || check(TokenKind::String) ||
                                 check(TokenKind::True) || check(TokenKind::False);
    if (!panic_ && !item.name.empty() && values.size() == 1 && values[0]->kind == ExprKind::Ident &&
        literal_follows) {
        const std::string word(values[0]->as<IdentExpr>().name);
        if (Diagnostic* d = error(item.name_span, "'" + std::string(item.name) + "' has no value"))
            d->help.push_back("'" + word + "' is read as its value, and " + found() +
                              " is left over; write a value after '" + std::string(item.name) + "'");
    }
    return keep(values);
}

// Whether any block accepts `name` as a property (or a transform).
bool Parser::is_property_name(std::string_view name) {
    static const char* const tables[] = {"settings", "camera",   "light area", "light point",
                                         "sphere",   "box",      "triangle",   "plane",
                                         "mesh",     "material", "checker",    "perlin"};
    if (name == "scale" || name == "rotate" || name == "translate") return true;
    for (const char* t : tables)
        if (block_table(t).find(name)) return true;
    return false;
}

// Skips `{ ... }` with its nested braces, as one placeholder value; an unclosed one is an error.
Expr* Parser::skip_braced_block() {
    const Token open = tok_;
    const uint32_t begin = tok_.begin;
    int depth = 0;
    do {
        if (check(TokenKind::LBrace)) ++depth;
        if (check(TokenKind::RBrace)) --depth;
        advance();
    } while (depth > 0 && !check(TokenKind::Eof));
    if (depth > 0) unclosed(open, "expected '}' to close this block, found " + found());
    Expr* bad = bad_here();
    bad->span = span_from(begin);
    return bad;
}

// `rgb <1, 0, 0>` or `srgb <...>` as an item's or a let's value: the colour functions written as
// POV-Ray's colour keywords. Reported at the name (true) when a vector literal follows on the same line.
bool Parser::colour_function_before_vector() {
    if (!check(TokenKind::Ident)) return false;
    const std::string_view name = lexeme(tok_);
    if ((name != "rgb" && name != "srgb") || peek().kind != TokenKind::Less) return false;
    // The raw text up to the closing '>' on the same line: components made of numbers, names,
    // arithmetic and parentheses, and at least one comma.
    size_t p = peek().end, commas = 0;
    const std::string_view component_chars =
        " \t.+-*/()_0123456789abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ";
    for (; p < text_.size() && text_[p] != '>'; ++p) {
        if (text_[p] == ',')
            ++commas;
        else if (component_chars.find(text_[p]) == std::string_view::npos)
            return false;
    }
    if (p == text_.size() || commas == 0) return false;
    const std::string vector(text_.substr(peek().begin, p + 1 - peek().begin));
    const std::string example = name == "rgb" ? "rgb(255, 0, 0)" : "srgb(1, 0, 0)";
    if (Diagnostic* d = error_here("'" + std::string(name) + "' is a function, not a colour keyword"))
        d->help.push_back("call it with parentheses, " + example +
                          ", or write the colour as a vector: " + vector);
    return true;
}

}  // namespace detail

Program parse(uint32_t file, const SourceManager& sources, Diagnostics& diags) {
    return detail::Parser(file, sources, diags).parse_program();
}

}  // namespace wsd::lang
