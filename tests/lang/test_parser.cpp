// Parser tests: precedence, the vector-literal rule, lists and their packed form, blocks and
// items (triangle vertices, the material shorthand), statements, recovery, the error limit,
// the nesting limit (also on a small thread stack) and hostile input.
#include <pthread.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "lang/parser.h"

using namespace wsd::lang;

namespace {

struct Parsed {
    SourceManager sources;
    Diagnostics diags;
    Program program;
    std::vector<std::string> errors() const {
        std::vector<std::string> out;
        for (const Diagnostic& d : diags.all()) {
            const LineCol lc = sources.line_col(d.span.file, d.span.begin);
            out.push_back(std::to_string(lc.line) + ":" + std::to_string(lc.column) + ": " + d.message);
        }
        return out;
    }
    std::string ast() const { return print_ast(program, sources); }
};

std::unique_ptr<Parsed> parse_text(std::string text) {
    auto p = std::make_unique<Parsed>();
    const uint32_t f = p->sources.add("t.wsd", std::move(text));
    p->program = parse(f, p->sources, p->diags);
    return p;
}

const char* op_name(BinaryOp op) {
    static const char* names[] = {"||", "&&", "==", "!=", "<", "<=", ">", ">=", "+", "-", "*", "/", "%"};
    return names[static_cast<int>(op)];
}

// Compact shape of an expression, without positions: (+ 1 (* 2 3)).
std::string shape(const Expr& e);

std::string shape_of(const char* head, ExprList items, const Block* block = nullptr) {
    std::string s = std::string("(") + head;
    for (const Expr* a : items) s += " " + shape(*a);
    if (block) s += " {" + std::to_string(block->items.size()) + " items}";
    return s + ")";
}

std::string shape(const Expr& e) {
    std::ostringstream s;
    switch (e.kind) {
        case ExprKind::Number:
            s << e.as<NumberExpr>().value;
            break;
        case ExprKind::String:
            s << '"' << e.as<StringExpr>().text << '"';
            break;
        case ExprKind::Bool:
            s << (e.as<BoolExpr>().value ? "true" : "false");
            break;
        case ExprKind::Ident:
            s << e.as<IdentExpr>().name;
            break;
        case ExprKind::Bad:
            s << "BAD";
            break;
        case ExprKind::Object:
            s << "(object value)";
            break;
        case ExprKind::PackedList: {
            const PackedVectors& packed = *e.as<PackedListExpr>().packed;
            s << "(packed " << packed.dims << "x" << packed.size() << ")";
            break;
        }
        case ExprKind::Binary: {
            // A flat chain shown as the left-deep tree it means: a - b + c is (+ (- a b) c).
            const auto& chain = e.as<BinaryExpr>();
            std::string acc = shape(*chain.operands[0]);
            for (size_t i = 1; i < chain.operands.size(); ++i)
                acc = std::string("(") + op_name(chain.ops[i - 1].op) + " " + acc + " " +
                      shape(*chain.operands[i]) + ")";
            s << acc;
            break;
        }
        case ExprKind::Vector:
            s << shape_of("vec", e.as<VectorExpr>().components);
            break;
        case ExprKind::List:
            s << shape_of("list", e.as<ListExpr>().elements);
            break;
        case ExprKind::Unary: {
            const auto& u = e.as<UnaryExpr>();
            s << (u.op == UnaryOp::Neg ? "(neg " : "(not ") << shape(*u.operand) << ")";
            break;
        }
        case ExprKind::Call: {
            const auto& call = e.as<CallExpr>();
            s << shape_of(("call " + std::string(call.name)).c_str(), call.args);
            break;
        }
        case ExprKind::Member: {
            const auto& m = e.as<MemberExpr>();
            s << "(." << m.field << " " << shape(*m.operand) << ")";
            break;
        }
        case ExprKind::Index: {
            const auto& ix = e.as<IndexExpr>();
            s << "(index " << shape(*ix.operand) << " " << shape(*ix.index) << ")";
            break;
        }
        case ExprKind::Material:
            s << shape_of("material", {}, e.as<BlockExpr>().block);
            break;
        case ExprKind::Checker:
            s << shape_of("checker", {}, e.as<BlockExpr>().block);
            break;
        case ExprKind::Perlin:
            s << shape_of("perlin", {}, e.as<BlockExpr>().block);
            break;
        case ExprKind::Image:
            s << "(image " << shape(*e.as<ImageExpr>().path) << ")";
            break;
    }
    return s.str();
}

const Expr& let_value(const Program& program, size_t i = 0) {
    return *program.statements[i]->as<LetStmt>().value;
}

// The shape of `let x = EXPR`, or the errors.
std::string expr_shape(const std::string& expr) {
    const auto p = parse_text("let x = " + expr);
    if (p->diags.has_errors()) return "ERROR " + p->errors().front();
    REQUIRE(p->program.statements.size() == 1);
    return shape(let_value(p->program));
}

}  // namespace

TEST_CASE("operators of one level in a row make one flat chain", "[parser][chain]") {
    const auto p = parse_text("let x = 1 - 2 + 3 - 4 * 5 * 6 + (7 + 8) + 9");
    REQUIRE(p->errors().empty());
    REQUIRE(let_value(p->program).kind == ExprKind::Binary);
    const auto& sum = let_value(p->program).as<BinaryExpr>();
    REQUIRE(sum.operands.size() == 6);  // 1, 2, 3, 4 * 5 * 6, (7 + 8), 9
    REQUIRE(sum.ops.size() == 5);
    CHECK(sum.ops[0].op == BinaryOp::Sub);
    CHECK(sum.ops[1].op == BinaryOp::Add);
    CHECK(sum.ops[2].op == BinaryOp::Sub);
    CHECK(sum.operands[3]->as<BinaryExpr>().operands.size() == 3);  // 4 * 5 * 6
    CHECK(sum.operands[4]->as<BinaryExpr>().operands.size() == 2);  // parentheses close a chain
    CHECK(p->sources.line_col(sum.ops[2].span.file, sum.ops[2].span.begin).column == 19);
    CHECK(sum.span.begin == 8);
    CHECK(sum.span.end == 43);
    const auto logic = parse_text("let x = a && b && c || d || e && f");
    const auto& any = let_value(logic->program).as<BinaryExpr>();
    REQUIRE(any.operands.size() == 3);  // a && b && c, d, e && f
    CHECK(any.operands[0]->as<BinaryExpr>().operands.size() == 3);
    CHECK(any.operands[2]->as<BinaryExpr>().operands.size() == 2);
}

TEST_CASE("operator precedence and associativity", "[parser]") {
    CHECK(expr_shape("1 + 2 * 3") == "(+ 1 (* 2 3))");
    CHECK(expr_shape("1 - 2 - 3") == "(- (- 1 2) 3)");
    CHECK(expr_shape("8 / 4 % 3 * 2") == "(* (% (/ 8 4) 3) 2)");
    CHECK(expr_shape("a || b && c == d < e + f * -g") == "(|| a (&& b (== c (< d (+ e (* f (neg g)))))))");
    CHECK(expr_shape("!a == b") == "(== (not a) b)");
    CHECK(expr_shape("--1") == "(neg (neg 1))");
    CHECK(expr_shape("-v.x") == "(neg (.x v))");
    CHECK(expr_shape("xs[i + 1].y") == "(.y (index xs (+ i 1)))");
    CHECK(expr_shape("f(1, g(2), [3])[0]") == "(index (call f 1 (call g 2) (list 3)) 0)");
    CHECK(expr_shape("f()") == "(call f)");
    CHECK(expr_shape("(1 + 2) * 3") == "(* (+ 1 2) 3)");
    CHECK(expr_shape("a <= b != c >= d") == "(!= (<= a b) (>= c d))");
    CHECK(expr_shape("\"a\" + \"b\"") == "(+ \"a\" \"b\")");
    CHECK(expr_shape("true && false") == "(&& true false)");
}

TEST_CASE("'<' opens a vector where an expression is expected", "[parser]") {
    CHECK(expr_shape("<1, 2, 3>") == "(vec 1 2 3)");
    CHECK(expr_shape("<1, 2>") == "(vec 1 2)");
    CHECK(expr_shape("<1, 2, 3> * 2") == "(* (vec 1 2 3) 2)");
    CHECK(expr_shape("a < b") == "(< a b)");
    CHECK(expr_shape("<a + 1, -b, c * 2> / 255") == "(/ (vec (+ a 1) (neg b) (* c 2)) 255)");
    CHECK(expr_shape("<1, 2, 3>==v") == "(== (vec 1 2 3) v)");
    CHECK(expr_shape("<1, 2, 3> == <1, 2, 3>") == "(== (vec 1 2 3) (vec 1 2 3))");
    CHECK(expr_shape("<(a < b), 1>") == "(vec (< a b) 1)");
    CHECK(expr_shape("<f(a < b), xs[a > b]>") == "(vec (call f (< a b)) (index xs (> a b)))");
    CHECK(expr_shape("<<1, 2>.x, 2, 3>") == "(vec (.x (vec 1 2)) 2 3)");
    CHECK(expr_shape("<1, <2, 3>>") == "(vec 1 (vec 2 3))");
    CHECK(expr_shape("<a == b, c != d>") == "(vec (== a b) (!= c d))");
    CHECK(expr_shape("<1, 2>.x < 3") == "(< (.x (vec 1 2)) 3)");
}

TEST_CASE("vector literal errors", "[parser]") {
    CHECK(expr_shape("<a < b, 1>") == "ERROR 1:12: comparison '<' inside a vector literal needs parentheses");
    CHECK(expr_shape("<a <= b, 1>") ==
          "ERROR 1:12: comparison '<=' inside a vector literal needs parentheses");
    CHECK(expr_shape("<1, a >= b, 2>") ==
          "ERROR 1:15: comparison '>=' inside a vector literal needs parentheses");
    CHECK(expr_shape("<1>") == "ERROR 1:9: a vector literal needs 2 or 3 components, found 1");
    CHECK(expr_shape("<1, 2, 3, 4>") == "ERROR 1:17: expected '>' to close the vector, found ','");
    CHECK(expr_shape("<1, 2,>") == "ERROR 1:14: trailing comma in a vector literal");
    CHECK(expr_shape("<1, 2") ==
          "ERROR 1:14: expected ',' or '>' after a vector component, found end of file");
    CHECK(expr_shape("<1 2>") == "ERROR 1:12: expected ',' after a vector component, found number '2'");
}

TEST_CASE("lists, trailing commas, and the packed form", "[parser]") {
    CHECK(expr_shape("[]") == "(list)");
    CHECK(expr_shape("[1, 2,]") == "(list 1 2)");
    CHECK(expr_shape("[[1], [], \"s\"]") == "(list (list 1) (list) \"s\")");
    CHECK(expr_shape("[<1, 2, 3>, <-4, 5, 6>,]") == "(packed 3x2)");
    CHECK(expr_shape("[<0, 1>]") == "(packed 2x1)");
    // Anything but numeric vector literals of one size falls back to the generic list.
    CHECK(expr_shape("[<1, 2, 3>, x]") == "(list (vec 1 2 3) x)");
    CHECK(expr_shape("[<1, 2, 3>, <1, 2>]") == "(list (vec 1 2 3) (vec 1 2))");
    CHECK(expr_shape("[<1, 2, 3>, <1, 2, 3 + 1>]") == "(list (vec 1 2 3) (vec 1 2 (+ 3 1)))");
    CHECK(expr_shape("[<1, 2, 3> * 2]") == "(list (* (vec 1 2 3) 2))");
    CHECK(expr_shape("[<1, --2, 3>]") == "(list (vec 1 (neg (neg 2)) 3))");
    CHECK(expr_shape("[<1, 2, 3>==v]") == "(list (== (vec 1 2 3) v))");
    CHECK(expr_shape("[<1, 2, 3>][0]") == "(index (packed 3x1) 0)");
    CHECK(expr_shape("[1, 2") == "ERROR 1:14: expected ',' or ']' in the list, found end of file");

    const auto p = parse_text("let m = [<1, -2, 3.5>,\n  <4, 5, 6e2>]");
    REQUIRE_FALSE(p->diags.has_errors());
    const Expr& e = let_value(p->program);
    REQUIRE(e.kind == ExprKind::PackedList);
    const PackedVectors& pv = *e.as<PackedListExpr>().packed;
    CHECK(pv.dims == 3);
    CHECK(pv.values == std::vector<double>{1, -2, 3.5, 4, 5, 600});
    CHECK(pv.offsets == std::vector<uint32_t>{9, 25});
    const PackedElementSpans s = packed_element_spans(pv, 1, p->sources);
    CHECK(s.count == 3);
    CHECK(s.element.begin == 25);
    CHECK(s.element.end == 36);
    const PackedElementSpans s0 = packed_element_spans(pv, 0, p->sources);
    CHECK(s0.minus[1].end - s0.minus[1].begin == 1);
    CHECK(s0.component[1].begin == 13);
    CHECK(s0.number[1].begin == 14);
    CHECK(s0.minus[0].begin == s0.minus[0].end);
}

TEST_CASE("a packed list prints exactly like the generic list it replaces", "[parser]") {
    const std::string elements = "<1, -2, 3>, <4.5, 5, -0>,\n <7, 8, 9e-1>";
    const auto packed = parse_text("let a = [" + elements + "]");
    const auto generic = parse_text("let a = [" + elements + ", x]");
    REQUIRE(let_value(packed->program).kind == ExprKind::PackedList);
    REQUIRE(let_value(generic->program).kind == ExprKind::List);
    // Drop the list header line and compare the element lines, closing parens aside.
    const auto element_lines = [](const std::string& ast) {
        std::vector<std::string> lines;
        std::istringstream in(ast);
        std::string line;
        while (std::getline(in, line)) {
            while (!line.empty() && line.back() == ')') line.pop_back();
            if (line.find("(vector") != std::string::npos || line.find("(number") != std::string::npos ||
                line.find("(unary") != std::string::npos)
                lines.push_back(line);
        }
        return lines;
    };
    const std::vector<std::string> p = element_lines(packed->ast());
    CHECK(p.size() == 3 + 9 + 2);  // vectors, numbers, two minus signs
    CHECK(p == element_lines(generic->ast()));
}

TEST_CASE("blocks: items, several values, the material forms", "[parser]") {
    const auto p = parse_text(
        "sphere { center <0, 1, 0>  radius 1 + r  material glass }\n"
        "light area { position p  u <1, 0, 0>  samples 8, 4  sampling jittered }\n"
        "box { material { color <1, 0, 0> }  translate <1, 2, 3> }\n"
        "plane { normal <0, 1, 0>  material material { base m }  material wall[3] }\n"
        "mesh { vertices [<0,0,0>, <1,0,0>, <0,1,0>]  faces [<0, 1, 2>]  uvs [] }\n");
    REQUIRE(p->errors().empty());
    REQUIRE(p->program.statements.size() == 5);
    std::vector<const ObjectStmt*> s;
    for (const Stmt* st : p->program.statements) s.push_back(&st->as<ObjectStmt>());
    CHECK(s[0]->block_kind == BlockKind::Sphere);
    REQUIRE(s[0]->block.items.size() == 3);
    CHECK(s[0]->block.items[1].name == "radius");
    CHECK(shape(*s[0]->block.items[1].values[0]) == "(+ 1 r)");
    CHECK(shape(*s[0]->block.items[2].values[0]) == "glass");
    CHECK(s[1]->block_kind == BlockKind::Light);
    CHECK(s[1]->name == "area");
    CHECK(s[1]->block.items[2].values.size() == 2);
    CHECK(shape(*s[1]->block.items[3].values[0]) == "jittered");
    CHECK(shape(*s[2]->block.items[0].values[0]) == "(material {1 items})");
    CHECK(s[2]->block.items[0].name == "material");
    CHECK(shape(*s[3]->block.items[1].values[0]) == "(material {1 items})");
    CHECK(shape(*s[3]->block.items[2].values[0]) == "(index wall 3)");
    CHECK(shape(*s[4]->block.items[0].values[0]) == "(packed 3x3)");
    CHECK(shape(*s[4]->block.items[2].values[0]) == "(list)");
    CHECK(s[0]->block.open.begin == 7);
    CHECK(p->sources.file(0).text[s[0]->block.close.begin] == '}');
}

TEST_CASE("a triangle's leading vertices form an item without a name", "[parser]") {
    const auto first_item = [](const std::string& block) {
        const auto p = parse_text("triangle " + block);
        REQUIRE(p->errors().empty());
        const Item& item = p->program.statements[0]->as<ObjectStmt>().block.items[0];
        std::string s = "[" + std::string(item.name) + "]";
        for (const Expr* v : item.values) s += " " + shape(*v);
        return s;
    };
    CHECK(first_item("{ <0,0,0>, <1,0,0>, <0,1,0>  uv <0,0>, <1,0>, <0,1>  material m }") ==
          "[] (vec 0 0 0) (vec 1 0 0) (vec 0 1 0)");
    CHECK(first_item("{ a, b, c  material m }") == "[] a b c");
    CHECK(first_item("{ v[0], v[1], v[2] }") == "[] (index v 0) (index v 1) (index v 2)");
    CHECK(first_item("{ c - u, f(1), c }") == "[] (- c u) (call f 1) c");
    CHECK(first_item("{ uv <0,0>, <1,0>, <0,1> }") == "[uv] (vec 0 0) (vec 1 0) (vec 0 1)");
    CHECK(first_item("{ material m }") == "[material] m");
    CHECK(first_item("{ material { color c } }") == "[material] (material {1 items})");
    // Other blocks have no unnamed items.
    const auto p = parse_text("sphere { <0, 0, 0> }");
    CHECK(p->errors() ==
          std::vector<std::string>{"1:10: expected a property name or '}' in sphere block, found '<'"});
}

TEST_CASE("statements", "[parser]") {
    const auto p = parse_text(
        "let n = 3\n"
        "for i in 0..n { let y = i }\n"
        "for c in [red, green] { }\n"
        "if n > 2 { } else if n == 1 { let z = 1 } else { include \"a.wsdi\" }\n"
        "if true { }\n"
        "include \"dir/b \\\"q\\\".wsdi\"\n"
        "settings { width 10 } camera { fov 60 }");
    REQUIRE(p->errors().empty());
    const auto& s = p->program.statements;
    REQUIRE(s.size() == 8);
    CHECK(s[0]->kind == StmtKind::Let);
    CHECK(s[0]->as<LetStmt>().name == "n");
    CHECK(p->sources.line_col(0, s[0]->as<LetStmt>().name_span.begin).column == 5);
    CHECK(s[1]->kind == StmtKind::For);
    const auto& range = s[1]->as<ForStmt>();
    CHECK(shape(*range.value) == "0");
    CHECK(shape(*range.range_end) == "n");
    CHECK(range.body.size() == 1);
    CHECK(s[2]->as<ForStmt>().range_end == nullptr);
    CHECK(shape(*s[2]->as<ForStmt>().value) == "(list red green)");
    const auto& branches = s[3]->as<IfStmt>().branches;
    REQUIRE(branches.size() == 3);
    CHECK(shape(*branches[1].condition) == "(== n 1)");
    CHECK(branches[2].condition == nullptr);
    REQUIRE(branches[2].body.size() == 1);
    CHECK(branches[2].body[0]->kind == StmtKind::Include);
    CHECK(p->sources.line_col(0, branches[2].keyword.begin).column == 43);
    CHECK(s[4]->as<IfStmt>().branches.size() == 1);
    CHECK(s[5]->as<IncludeStmt>().path == "dir/b \"q\".wsdi");
    CHECK(s[6]->as<ObjectStmt>().block_kind == BlockKind::Settings);
    CHECK(s[7]->as<ObjectStmt>().block_kind == BlockKind::Camera);
    CHECK(s[7]->span.end == p->sources.file(0).text.size());
}

TEST_CASE("comments between a call statement's name and its '(' are whitespace", "[parser]") {
    for (const char* text : {"f/*c*/()", "f /* a /* nested */ b */ (1)", "f // c\n(2)", "f\n/* c */\n(3)"}) {
        INFO(text);
        const auto p = parse_text(text);
        CHECK(p->errors().empty());
        REQUIRE(p->program.statements.size() == 1);
        CHECK(p->program.statements[0]->kind == StmtKind::Call);
    }
    const auto assign = parse_text("x /* c */ = 3");
    REQUIRE(assign->diags.all().size() == 1);
    CHECK(assign->diags.all()[0].help == std::vector<std::string>{"to bind a name, write 'let x = ...'"});
}

TEST_CASE("syntax errors, with recovery at the next statement", "[parser]") {
    const auto p = parse_text(
        "sphere { center <0, 0, 0>  radius }\n"  // 1
        "sphre { radius 1 }\n"                   // 2
        "let = 4\n"                              // 3
        "box { min <0,0,0> max <1,1,1>\n"        // 4
        "let ok = (1 + 2\n"                      // 5
        "let y = 1 +\n"                          // 6
        "}\n"                                    // 7
        "light { position <0,0,0> }\n"           // 8
        "let sphere = 2 let w = 1\n"             // 9
        "if x { } else { } else { }\n"           // 10
        "for i in 0 .. 3 {\n");                  // 11
    CHECK(p->errors() == std::vector<std::string>{
                             "1:35: expected a value for 'radius', found '}'",
                             "2:1: expected a statement, found 'sphre'",
                             "3:5: expected a name after 'let', found '='",
                             "5:1: expected '}' to close box block, found 'let'",
                             "6:1: expected ')', found 'let'", "7:1: expected an expression, found '}'",
                             "8:7: expected the light kind (point, area or spot) after 'light', found '{'",
                             "9:5: expected a name after 'let', found keyword 'sphere'",
                             "10:19: 'else' without a matching 'if'",
                             "12:1: expected '}' to close the for body, found end of file"});
    const auto& d = p->diags.all();
    CHECK(d[1].help == std::vector<std::string>{"did you mean 'sphere'?"});
    REQUIRE(d[3].notes.size() == 1);
    CHECK(d[3].notes[0].message == "to match this '{'");
    CHECK(p->sources.line_col(0, d[3].notes[0].span.begin).line == 4);
    REQUIRE(d[4].notes.size() == 1);
    CHECK(d[4].notes[0].message == "to match this '('");
    CHECK(d[7].help == std::vector<std::string>{"'sphere' is a reserved word; choose another name"});
    // The statement after a reserved-word name still parses.
    bool found_w = false;
    for (const Stmt* s : p->program.statements)
        found_w |= s->kind == StmtKind::Let && s->as<LetStmt>().name == "w";
    CHECK(found_w);

    const auto assign = parse_text("x = 3");
    REQUIRE(assign->diags.all().size() == 1);
    CHECK(assign->diags.all()[0].help == std::vector<std::string>{"to bind a name, write 'let x = ...'"});
    CHECK(parse_text("}}} let x = 1 }")->errors() ==
          std::vector<std::string>{"1:1: unexpected '}' with no open block",
                                   "1:15: unexpected '}' with no open block"});
}

TEST_CASE("a lexical error found while peeking does not disturb the error being reported", "[parser]") {
    // Regression (found by fuzzing): the help of "expected a statement" looked one token ahead,
    // and a lexical error there reallocated the diagnostics under the parser's feet.
    for (int before = 0; before < 12; ++before) {
        std::string text;
        for (int i = 0; i < before; ++i) text += "sphere { 1 }\n";
        text += "sphre \x84 = 2\n";
        const auto p = parse_text(text);
        const auto& d = p->diags.all();
        REQUIRE(d.size() == static_cast<size_t>(before) + 2);
        CHECK(d[static_cast<size_t>(before)].message == "expected a statement, found 'sphre'");
        CHECK(d[static_cast<size_t>(before)].help == std::vector<std::string>{"did you mean 'sphere'?"});
        CHECK(d.back().message.rfind("invalid UTF-8 byte 0x84", 0) == 0);
    }
}

TEST_CASE("the parser stops after max_errors errors", "[parser]") {
    std::string text;
    for (int i = 0; i < 100; ++i) text += "let = " + std::to_string(i) + "\n";
    const auto p = parse_text(text);
    CHECK(p->diags.all().size() == Diagnostics::max_errors);
    CHECK(p->diags.too_many());
    CHECK(p->errors().back() == "20:5: expected a name after 'let', found '='");
}

namespace {

std::string nested(const std::string& open, const std::string& middle, const std::string& close, int n) {
    std::string s;
    s.reserve((open.size() + close.size()) * static_cast<size_t>(n) + middle.size());
    for (int i = 0; i < n; ++i) s += open;
    s += middle;
    for (int i = 0; i < n; ++i) s += close;
    return s;
}

}  // namespace

TEST_CASE("nesting deeper than the limit is one error, never a stack overflow", "[parser]") {
    const std::vector<std::string> deep = {
        "let x = " + nested("(", "1", ")", 10'000),
        "let x = " + nested("[", "1", "]", 10'000),
        "let x = " + nested("<", "1, 2", ", 3>", 10'000),
        "let x = " + nested("-", "1", "", 10'000),
        "let x = " + nested("f(", "1", ")", 10'000),
        "let x = " + nested("", "a", "[0]", 100'000),
        "let x = " + nested("", "a", ".x", 100'000),
        nested("if true { ", "", "}", 10'000),
        "let m = " + nested("material { base ", "m", " }", 10'000),
        "sphere { material " + nested("{ base material ", "m", "}", 10'000) + " }",
        "let x = " + nested("(", "", "", 100'000),
    };
    for (const std::string& text : deep) {
        // No timing here (unit tests never time): a hang or runaway recursion would show as a
        // crash or ctest's timeout; bench_parse measures speed.
        const auto p = parse_text(text);
        INFO(text.substr(0, 40));
        REQUIRE(p->diags.all().size() == 1);
        CHECK(p->diags.all()[0].message ==
              "nesting too deep (the limit is 256 nested blocks and expressions)");
    }
    // Just under the limit is fine.
    CHECK(parse_text("let x = " + nested("(", "1", ")", 200))->errors().empty());
    CHECK(parse_text("let x = " + nested("", "a", "[0]", 250))->errors().empty());
    CHECK(parse_text(nested("if true { ", "", "}", 200))->errors().empty());
}

namespace {

void* parse_deep(void* result) {
    // 250 levels of each kind of nesting, on a small stack.
    const std::string texts[] = {
        "let x = " + nested("(", "1", ")", 250),
        "let x = " + nested("<", "1, 2", ", 3>", 250),
        nested("if true { ", "", "}", 250),
        "let x = " + nested("(", "1", ")", 10'000),
    };
    bool ok = true;
    for (const std::string& t : texts) {
        const auto p = parse_text(t);
        ok = ok && p->diags.all().size() <= 1;
    }
    *static_cast<bool*>(result) = ok;
    return nullptr;
}

}  // namespace

TEST_CASE("R54: the nesting limit fits a 512 KiB thread stack", "[parser]") {
    // R54 asks for a small stack (it suggests 256 KiB). One nesting level of a parenthesised
    // expression costs five frames (binary, unary, postfix, primary, group: about 1.2 KiB in the
    // optimised build, measured with -fstack-usage), so the 256 levels the language allows need
    // about 300 KiB: the optimised build is held to 512 KiB. AddressSanitizer puts redzones around
    // every local and makes each frame several times larger, so sanitized builds get 8 MiB (the
    // main thread's default, where `wsd` parses).
#if defined(__SANITIZE_ADDRESS__)
    constexpr size_t stack_bytes = size_t{8} << 20;
#else
    constexpr size_t stack_bytes = size_t{512} << 10;
#endif
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    pthread_attr_setstacksize(&attr, stack_bytes);
    pthread_t thread;
    bool ok = false;
    REQUIRE(pthread_create(&thread, &attr, parse_deep, &ok) == 0);
    pthread_join(thread, nullptr);
    pthread_attr_destroy(&attr);
    CHECK(ok);
}

TEST_CASE("hostile input never crashes the parser", "[parser]") {
    CHECK(parse_text("")->program.statements.empty());
    CHECK(parse_text("// only a comment")->errors().empty());
    CHECK(parse_text("sphere {")->errors() ==
          std::vector<std::string>{"1:9: expected '}' to close sphere block, found end of file"});
    CHECK(parse_text("let s = \"abc")->errors() == std::vector<std::string>{"1:9: unterminated string"});
    CHECK(parse_text("/* /* */")->errors() == std::vector<std::string>{"1:1: unterminated block comment"});
    CHECK(parse_text("}}}")->errors().size() == 1);
    CHECK(parse_text(std::string(100'000, '{'))->diags.all().size() == 1);
    CHECK(parse_text(std::string(100'000, '<'))->diags.all().size() <= 2);
    std::mt19937 rng(7);
    const std::string alphabet = "{}()[]<>,=.+-*/%!&|\"\\ \n\tlet for in if else sphere material x 1 2.5e3";
    for (int round = 0; round < 300; ++round) {
        std::string text;
        const size_t n = rng() % 300;
        for (size_t i = 0; i < n; ++i) {
            text += (rng() % 8 == 0) ? static_cast<char>(rng() & 0xFF) : alphabet[rng() % alphabet.size()];
        }
        const auto p = parse_text(text);
        CHECK(p->diags.all().size() <= Diagnostics::max_errors);
        (void)p->ast();
    }
}

TEST_CASE("every example scene parses without errors", "[parser]") {
    namespace fs = std::filesystem;
    size_t count = 0;
    for (const auto& entry : fs::recursive_directory_iterator(fs::path(WSD_SOURCE_DIR) / "examples")) {
        const std::string ext = entry.path().extension().string();
        if (ext != ".wsd" && ext != ".wsdi") continue;
        std::ifstream in(entry.path(), std::ios::binary);
        std::ostringstream ss;
        ss << in.rdbuf();
        const auto p = parse_text(ss.str());
        INFO(entry.path().string());
        CHECK(p->errors().empty());
        ++count;
    }
    CHECK(count >= 5);
}

TEST_CASE("line endings: an error on line 3 is on line 3 with LF, CRLF and CR", "[parser]") {
    for (const std::string eol : {"\n", "\r\n", "\r"}) {
        const auto p = parse_text("let a = 1" + eol + "// comment" + eol + "  let = 2" + eol);
        CHECK(p->errors() == std::vector<std::string>{"3:7: expected a name after 'let', found '='"});
    }
}
