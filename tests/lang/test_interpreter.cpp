// Interpreter tests: precedence, vectors, strings and lists (the packed form shared, not copied),
// scoping and shadowing, loops and the iteration budget, if, include (relative paths, once per
// scene, cycles, depth, errors inside included files), every builtin, every runtime error, and the
// evaluator's own recursion guard.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "eval_helpers.h"
#include "lang/builtins.h"

using namespace wsd::lang;
using namespace wsd::lang::test;

namespace {

double num(const std::string& expr) {
    auto v = value_of(expr);
    REQUIRE(v);
    REQUIRE(v->is(ValueType::Number));
    return v->number();
}

bool boolean(const std::string& expr) {
    auto v = value_of(expr);
    REQUIRE(v);
    REQUIRE(v->is(ValueType::Bool));
    return v->boolean();
}

glm::dvec3 vec3(const std::string& expr) {
    auto v = value_of(expr);
    REQUIRE(v);
    REQUIRE(v->is(ValueType::Vector3));
    return v->vec3();
}

glm::dvec2 vec2(const std::string& expr) {
    auto v = value_of(expr);
    REQUIRE(v);
    REQUIRE(v->is(ValueType::Vector2));
    return v->vec2();
}

// The single error of `let x = EXPR`, as "COLUMN: message" (the expression starts at column 9).
std::string error_of(const std::string& expr) {
    auto errors = errors_of(expr);
    REQUIRE(errors.size() == 1);
    const std::string& e = errors[0];
    REQUIRE(e.rfind("1:", 0) == 0);
    return e.substr(2);
}

struct TempDir {
    std::filesystem::path path;
    TempDir() {
        path = std::filesystem::temp_directory_path() /
               ("wsd-h2-" + std::to_string(::getpid()) + "-" + std::to_string(counter()++));
        std::filesystem::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    static int& counter() {
        static int n = 0;
        return n;
    }
    std::string write(const std::string& name, const std::string& text) const {
        std::filesystem::path p = path / name;
        std::filesystem::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << text;
        return p.string();
    }
};

std::unique_ptr<Loaded> load_file(const std::string& path, bool fragment = false) {
    std::ifstream in(path, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return load_text(text, fragment, false, path);
}

}  // namespace

TEST_CASE("operators follow the precedence table", "[interpreter]") {
    CHECK(num("1 + 2 * 3") == 7);
    CHECK(num("(1 + 2) * 3") == 9);
    CHECK(num("2 - 3 - 4") == -5);
    CHECK(num("8 / 4 / 2") == 1);
    CHECK(num("-2 * 3 + 1") == -5);
    CHECK(num("--1") == 1);
    CHECK(num("2 * 3 % 4") == 2);
    CHECK(boolean("1 + 2 < 4 && 3 > 2"));
    CHECK(boolean("!false || false"));
    CHECK_FALSE(boolean("!(false || true)"));
    CHECK(boolean("1 < 2 == 2 < 3"));
    CHECK(boolean("true || false && false"));
    CHECK(boolean("1 != 2"));
    CHECK(boolean("2 >= 2 && 2 <= 2 && !(2 > 2)"));
}

TEST_CASE("a chain of one level evaluates left to right", "[interpreter][chain]") {
    CHECK(num("1 + 2 + 3 + 4 + 5") == 15);
    CHECK(num("10 - 1 - 2 - 3") == 4);
    CHECK(num("10 - 1 + 2 - 3 + 4") == 12);
    CHECK(num("2 * 3 * 4 * 5") == 120);
    CHECK(num("100 / 2 / 5 * 3 % 7") == 2);
    CHECK(num("1 + 2 * 3 * 2 - 4 / 2 / 2 + 1") == 13);
    CHECK(num("(1 + 2 + 3) * (4 - 2 - 1)") == 6);
    CHECK(num("1e308 - 1e308 + 1e308") == 1e308);  // (1e308 - 1e308) + 1e308: no overflow
    CHECK(vec3("<1, 1, 1> + <1, 2, 3> - <0, 1, 0> * 2 + <1, 0, 0>") == glm::dvec3(3, 1, 4));
    CHECK(value_of("\"a\" + \"b\" + \"c\"")->string() == "abc");
    CHECK(boolean("true && true && true && 1 < 2"));
    CHECK_FALSE(boolean("true && true && false && true"));
    CHECK(boolean("false || false || false || true"));
    CHECK_FALSE(boolean("false || false || false"));
    CHECK(boolean("1 < 2 == true != false"));
    CHECK(boolean("false || true && false || true"));
}

TEST_CASE("a chain's errors point where the left-deep tree's did", "[interpreter][chain][errors]") {
    // `a + b + c` means `(a + b) + c`: a failing `a + b` is reported at its own operator, and the
    // operands after it are still evaluated (their errors reported) but not combined.
    CHECK(errors_of("1 + \"a\" + 2") ==
          std::vector<std::string>{"1:11: operator '+' cannot combine number and string"});
    CHECK(errors_of("1 + 1 + 1 / 0 + \"a\"") == std::vector<std::string>{"1:19: division by zero"});
    CHECK(errors_of("1 / 0 + 2 / 0 + 3") ==
          std::vector<std::string>{"1:11: division by zero", "1:19: division by zero"});
    CHECK(errors_of("1 + 2 + \"a\" - 3") ==
          std::vector<std::string>{"1:15: operator '+' cannot combine number and string"});
    CHECK(errors_of("\"a\" + \"b\" - 1") ==
          std::vector<std::string>{"1:19: operator '-' cannot combine string and number"});
    CHECK(errors_of("1e308 + 1e308 - 1e308") ==
          std::vector<std::string>{"1:15: result of '+' is not a finite number"});
    // Short-circuit from the left: nothing after the deciding operand runs.
    CHECK(errors_of("false && 1 / 0 == 1 && 1 / 0 == 1").empty());
    CHECK(errors_of("true || undefined || undefined").empty());
    CHECK(errors_of("true && true && 1") ==
          std::vector<std::string>{"1:22: '&&' needs bools, found number on the right"});
    CHECK(errors_of("1 && true && true") ==
          std::vector<std::string>{"1:11: '&&' needs bools, found number on the left"});
    CHECK(errors_of("false || false || 2 || true") ==
          std::vector<std::string>{"1:24: '||' needs bools, found number on the right"});
    CHECK(errors_of("1 < 2 < 3") ==
          std::vector<std::string>{"1:15: '<' compares numbers, found bool and number"});
}

TEST_CASE("a flat 601-term sum is not nesting", "[interpreter][chain][limits]") {
    std::string sum = "1";
    for (int i = 1; i < 601; ++i) sum += " + 1";
    CHECK(num(sum) == 601);
    std::string product = "1";
    for (int i = 1; i < 5000; ++i) product += " * 1";
    CHECK(num(product) == 1);
}

TEST_CASE("% is fmod and keeps the sign of the dividend", "[interpreter]") {
    CHECK(num("7 % 3") == 1);
    CHECK(num("-7 % 3") == -1);
    CHECK(num("7 % -3") == 1);
    CHECK(num("5.5 % 2") == Approx(1.5));
    CHECK(std::signbit(num("-0")));
}

TEST_CASE("vectors combine component-wise and with numbers", "[interpreter]") {
    CHECK(vec3("<1, 2, 3> + <1, 1, 1>") == glm::dvec3(2, 3, 4));
    CHECK(vec3("<1, 2, 3> - <1, 1, 1>") == glm::dvec3(0, 1, 2));
    CHECK(vec3("<1, 2, 3> * <2, 3, 4>") == glm::dvec3(2, 6, 12));
    CHECK(vec3("<2, 6, 12> / <2, 3, 4>") == glm::dvec3(1, 2, 3));
    CHECK(vec3("<1, 2, 3> * 2") == glm::dvec3(2, 4, 6));
    CHECK(vec3("2 * <1, 2, 3>") == glm::dvec3(2, 4, 6));
    CHECK(vec3("<2, 4, 6> / 2") == glm::dvec3(1, 2, 3));
    CHECK(vec3("-<1, -2, 3>") == glm::dvec3(-1, 2, -3));
    CHECK(vec2("<1, 2> + <3, 4>") == glm::dvec2(4, 6));
    CHECK(vec2("<1, 2> * 3") == glm::dvec2(3, 6));
    CHECK(num("<1, 2, 3>.x + <1, 2, 3>.y * 10 + <1, 2, 3>.z * 100") == 321);
    CHECK(num("<4, 5, 6>.r + <4, 5, 6>.g + <4, 5, 6>.b") == 15);
    CHECK(num("<7, 8>.u * 10 + <7, 8>.v") == 78);
    CHECK(boolean("<1, 2, 3> == <1, 2, 3>"));
    CHECK(boolean("<1, 2> != <1, 3>"));
    CHECK(vec3("<1 + 1, 2 * 2, -(3)>") == glm::dvec3(2, 4, -3));
    CHECK(boolean("<1, 2, 3> == <1, 2, 3> && <1, 2> == <1, 2>"));
}

TEST_CASE("strings concatenate and compare", "[interpreter]") {
    auto v = value_of("\"ab\" + \"cd\"");
    REQUIRE(v);
    CHECK(v->string() == "abcd");
    CHECK(boolean("\"a\" == \"a\""));
    CHECK(boolean("\"a\" != \"b\""));
}

TEST_CASE("lists index from 0 and count with len", "[interpreter]") {
    CHECK(num("[10, 20, 30][1]") == 20);
    CHECK(num("len([1, true, \"x\", <1, 2>])") == 4);
    CHECK(num("len([])") == 0);
    CHECK(num("len([1, 2,])") == 2);
    CHECK(num("[[1, 2], [3, 4]][1][0]") == 3);
    CHECK(vec3("[<1, 2, 3>, <4, 5, 6>][1]") == glm::dvec3(4, 5, 6));
}

TEST_CASE("a packed list shares the parser's storage", "[interpreter]") {
    auto e = evaluate_text("let v = [<1, 2, 3>, <4, 5, 6>, <7, 8, 9>]\nlet w = v\nlet p = v[2]\n");
    REQUIRE(e->errors().empty());
    const Expr& value = *e->program.statements[0]->as<LetStmt>().value;
    REQUIRE(value.kind == ExprKind::PackedList);
    const auto& literal = value.as<PackedListExpr>();
    auto v = e->get("v");
    auto w = e->get("w");
    REQUIRE(v);
    REQUIRE(w);
    CHECK(v->list().packed.get() == literal.packed.get());
    CHECK(w->list().packed.get() == literal.packed.get());
    CHECK(v->list().items.empty());
    auto p = e->get("p");
    REQUIRE(p);
    CHECK(p->vec3() == glm::dvec3(7, 8, 9));
    // The element keeps the span of its literal.
    CHECK(where(e->sources, p->span()) == "1:32");
    CHECK(p->span().end - p->span().begin == std::string("<7, 8, 9>").size());
}

TEST_CASE("lets bind once per scope; inner scopes shadow", "[interpreter]") {
    auto e = evaluate_text("let a = 1\nlet a = 2\n");
    REQUIRE(e->errors() == std::vector<std::string>{"2:5: 'a' is already defined in this scope"});
    REQUIRE(e->diags.all()[0].notes.size() == 1);
    CHECK(where(e->sources, e->diags.all()[0].notes[0].span) == "1:5");
    CHECK(e->get("a")->number() == 1);

    e = evaluate_text("let a = 1\nif true { let a = 2  let b = a }\nlet c = a\n");
    CHECK(e->errors().empty());
    CHECK(e->get("c")->number() == 1);
    CHECK_FALSE(e->get("b"));  // the if body's scope is gone

    // A loop variable lives in the body's scope; rebinding it there is an error.
    e = evaluate_text("for i in 0 .. 2 { let i = 5 }\n");
    CHECK(e->errors() == std::vector<std::string>{"1:23: 'i' is already defined in this scope"});
}

TEST_CASE("builtins live outside the file's scope and can be shadowed", "[interpreter]") {
    auto e = evaluate_text(
        "let floor = material { color <1, 0, 0> }\nlet pi = 3\nlet x = pi * 2\nlet y = sin(0)\n");
    CHECK(e->errors().empty());
    CHECK(e->get("x")->number() == 6);
    CHECK(e->get("floor")->is(ValueType::Material));
    // A shadowed function is not callable any more.
    e = evaluate_text("let floor = 3\nlet y = floor(1.5)\n");
    CHECK(e->errors() == std::vector<std::string>{"2:9: 'floor' is a number, not a function"});
}

TEST_CASE("a failed let does not cascade into unknown names", "[interpreter]") {
    auto e = evaluate_text("let a = 1 / 0\nlet b = a + 1\nlet c = b * 2\n");
    CHECK(e->errors() == std::vector<std::string>{"1:11: division by zero"});
}

TEST_CASE("for runs over integer ranges and lists", "[interpreter]") {
    auto l = load_text(
        "for i in 0 .. 5 { sphere { center <i, 0, 0> radius 1 material { } } }\n"
        "for i in 3 .. 1 { sphere { center <i, 0, 0> radius 1 material { } } }\n"
        "for i in -2 .. -2 { sphere { center <i, 0, 0> radius 1 material { } } }\n"
        "for c in [<0, 1, 0>, <0, 2, 0>] { sphere { center c radius 1 material { } } }\n",
        true);
    REQUIRE(l->errors().empty());
    REQUIRE(l->scene);
    CHECK(l->scene->summary.objects == 7);
    CHECK(l->scene->spec.shapes[4].center == glm::dvec3(4, 0, 0));
    CHECK(l->scene->spec.shapes[6].center == glm::dvec3(0, 2, 0));

    // The loop variable is fresh in every iteration, and so is the body's scope.
    auto e = evaluate_text("for i in 0 .. 3 { let sq = i * i }\n");
    CHECK(e->errors().empty());
    CHECK(e->interpreter->iterations() == 3);
}

TEST_CASE("for range bounds must be integers; the target must be a range or a list", "[interpreter]") {
    CHECK(evaluate_text("for i in 0.5 .. 3 { }")->errors() ==
          std::vector<std::string>{"1:10: 'for' range bounds must be integers, found 0.5"});
    CHECK(evaluate_text("for i in 0 .. <1, 2> { }")->errors() ==
          std::vector<std::string>{"1:15: 'for' range bounds must be numbers, found vector2"});
    CHECK(evaluate_text("for i in 5 { }")->errors() ==
          std::vector<std::string>{"1:10: 'for' needs a list or a range 'A .. B', found number"});
}

TEST_CASE("a loop longer than the iteration budget is refused before it starts", "[interpreter]") {
    auto e = evaluate_text("for i in 0 .. 1e12 { let y = 1 / 0 }\n");
    REQUIRE(e->errors().size() == 1);
    CHECK(e->errors()[0].rfind("1:10: loop of 1000000000000 iterations exceeds the limit", 0) == 0);
    CHECK(e->interpreter->iterations() == 0);

    Limits small;
    small.loop_iterations = 10;
    e = evaluate_text("for i in 0 .. 4 { for j in 0 .. 2 { } }\nfor k in [1, 2, 3] { }\n", small);
    CHECK(e->errors().size() == 1);  // 4 + 4·2 = 12 > 10: the fourth inner loop is refused
    CHECK(e->interpreter->iterations() == 10);
    CHECK(e->interpreter->aborted());
}

TEST_CASE("an error in a loop body is reported once", "[interpreter]") {
    auto e = evaluate_text("for i in 0 .. 1000 { let x = 1 / 0 }\n");
    CHECK(e->errors().size() == 1);
}

TEST_CASE("if takes the first true branch and never evaluates the others", "[interpreter]") {
    auto e = evaluate_text(
        "let v = 2\n"
        "if v == 1 { let a = 1 / 0 } else if v == 2 { let b = 1 } else { let c = sqrt(-1) }\n"
        "if false { let d = [1][5] }\n"
        "if true { } else { let e = undefined_name }\n");
    CHECK(e->errors().empty());
    CHECK(evaluate_text("if 1 { }")->errors() ==
          std::vector<std::string>{"1:4: 'if' condition must be a bool, found number"});
    CHECK(evaluate_text("let x = 2\nif x { }")->errors() ==
          std::vector<std::string>{"2:4: 'if' condition must be a bool, found number"});
    // && and || short-circuit.
    CHECK(evaluate_text("let x = false && 1 / 0 == 1\nlet y = true || [1][9] == 1")->errors().empty());
}

TEST_CASE("every builtin function computes its value", "[interpreter][builtins]") {
    const double pi = std::numbers::pi;
    CHECK(num("sin(pi / 2)") == Approx(1));
    CHECK(num("cos(pi)") == Approx(-1));
    CHECK(num("tan(pi / 4)") == Approx(1));
    CHECK(num("asin(1)") == Approx(pi / 2));
    CHECK(num("acos(-1)") == Approx(pi));
    CHECK(num("atan(1)") == Approx(pi / 4));
    CHECK(num("atan2(1, -1)") == Approx(3 * pi / 4));
    CHECK(num("sqrt(16)") == 4);
    CHECK(num("pow(2, 10)") == 1024);
    CHECK(num("pow(-8, 3)") == -512);
    CHECK(num("exp(0)") == 1);
    CHECK(num("log(exp(2))") == Approx(2));
    CHECK(num("abs(-3)") == 3);
    CHECK(vec3("abs(<-1, 2, -3>)") == glm::dvec3(1, 2, 3));
    CHECK(num("floor(-1.5)") == -2);
    CHECK(num("ceil(-1.5)") == -1);
    CHECK(num("round(2.5)") == 3);
    CHECK(num("round(-2.5)") == -3);
    CHECK(num("round(0.49999999)") == 0);
    CHECK(vec2("floor(<1.5, -1.5>)") == glm::dvec2(1, -2));
    CHECK(num("min(3, -2)") == -2);
    CHECK(num("max(3, -2)") == 3);
    CHECK(vec3("min(<1, 5, 3>, <2, 4, 3>)") == glm::dvec3(1, 4, 3));
    CHECK(num("clamp(5, 0, 1)") == 1);
    CHECK(num("clamp(-5, 0, 1)") == 0);
    CHECK(num("clamp(0.5, 0, 1)") == 0.5);
    CHECK(num("mix(2, 4, 0.25)") == 2.5);
    CHECK(vec3("mix(<0, 0, 0>, <2, 4, 8>, 0.5)") == glm::dvec3(1, 2, 4));
    CHECK(num("radians(180)") == Approx(pi));
    CHECK(num("degrees(pi)") == Approx(180));
    CHECK(num("length(<3, 4>)") == 5);
    CHECK(num("length(<2, 3, 6>)") == 7);
    CHECK(vec3("normalize(<0, 3, 4>)") == glm::dvec3(0, 0.6, 0.8));
    CHECK(num("dot(<1, 2, 3>, <4, 5, 6>)") == 32);
    CHECK(vec3("cross(<1, 0, 0>, <0, 1, 0>)") == glm::dvec3(0, 0, 1));
    CHECK(num("len([1, 2, 3])") == 3);
    CHECK(num("pi") == pi);
    CHECK(boolean("on"));
    CHECK_FALSE(boolean("off"));
}

TEST_CASE("rgb and srgb decode with the sRGB transfer function", "[interpreter][builtins]") {
    CHECK(vec3("rgb(255, 255, 255)") == glm::dvec3(1, 1, 1));
    CHECK(vec3("rgb(0, 0, 0)") == glm::dvec3(0, 0, 0));
    const double mid = std::pow((128.0 / 255.0 + 0.055) / 1.055, 2.4);
    CHECK(vec3("rgb(128, 0, 255)").x == Approx(mid).epsilon(1e-15));
    CHECK(vec3("srgb(0.5, 0.04, 1)").x == Approx(std::pow((0.5 + 0.055) / 1.055, 2.4)).epsilon(1e-15));
    CHECK(vec3("srgb(0.5, 0.04, 1)").y == Approx(0.04 / 12.92).epsilon(1e-15));  // the linear segment
    CHECK(srgb_to_linear(0.04045) == Approx(0.04045 / 12.92));
    // Continuous at the knee.
    CHECK(srgb_to_linear(0.0404501) == Approx(0.04045 / 12.92).epsilon(1e-5));
}

TEST_CASE("every runtime error is reported where the spec says", "[interpreter][errors]") {
    // Binary operators at the operator (column of the operator), calls at the function's name.
    CHECK(error_of("1 / 0") == "11: division by zero");
    CHECK(error_of("5 % 0") == "11: modulo by zero");
    CHECK(error_of("<1, 2, 3> / <1, 0, 1>") == "19: division by zero (a component of the divisor is 0)");
    CHECK(error_of("<1, 2> / 0") == "16: division by zero");
    CHECK(error_of("1e308 * 10") == "15: result of '*' is not a finite number");
    CHECK(error_of("1e308 + 1e308") == "15: result of '+' is not a finite number");
    CHECK(error_of("sqrt(-1)") == "9: 'sqrt' of a negative number (-1)");
    CHECK(error_of("acos(2)") == "9: 'acos' of 2 is undefined (outside [-1, 1])");
    CHECK(error_of("asin(-2)") == "9: 'asin' of -2 is undefined (outside [-1, 1])");
    CHECK(error_of("log(0)") == "9: 'log' of a number that is not positive (0)");
    CHECK(error_of("exp(1000)") == "9: result of 'exp' is not a finite number");
    CHECK(error_of("pow(-8, 1 / 3)") == "9: 'pow(-8, 0.3333333333333333)' has no real value");
    CHECK(error_of("pow(0, -1)") == "9: result of 'pow' is not a finite number");
    CHECK(error_of("normalize(<0, 0, 0>)") == "9: 'normalize' of a zero vector");
    CHECK(error_of("clamp(1, 2, 1)") == "9: 'clamp' needs lo <= hi, found lo 2 and hi 1");
    CHECK(error_of("rgb(300, 0, 0)") == "13: 'rgb' components must be in [0, 255], found 300");
    CHECK(error_of("srgb(0, -0.5, 0)") == "17: 'srgb' components must be in [0, 1], found -0.5");
    // Argument counts at the call, argument types at the argument.
    CHECK(error_of("sin(1, 2)") == "9: 'sin' takes 1 argument, found 2");
    CHECK(error_of("atan2(1)") == "9: 'atan2' takes 2 arguments, found 1");
    CHECK(error_of("sin(<1, 2, 3>)") == "13: 'sin' expects a number, found vector3");
    CHECK(error_of("len(1)") == "13: 'len' expects a list, found number");
    CHECK(error_of("dot(<1, 2>, <1, 2, 3>)") ==
          "21: 'dot' expects a vector2 like its first argument, found vector3");
    CHECK(error_of("cross(<1, 2>, <1, 2>)") == "15: 'cross' expects a vector3, found vector2");
    // Type errors of operators.
    CHECK(error_of("\"a\" - \"b\"") == "13: operator '-' cannot combine string and string");
    CHECK(error_of("true + 1") == "14: operator '+' cannot combine bool and number");
    CHECK(error_of("<1, 2> + <1, 2, 3>") == "16: operator '+' cannot combine vector2 and vector3");
    CHECK(error_of("2 / <1, 2>") == "11: operator '/' cannot combine number and vector2");
    CHECK(error_of("<1, 2> % 2") == "16: operator '%' cannot combine vector2 and number");
    CHECK(error_of("!1") == "9: operator '!' needs a bool, found number");
    CHECK(error_of("-true") == "9: operator '-' needs a number or a vector, found bool");
    CHECK(error_of("1 && true") == "11: '&&' needs bools, found number on the left");
    CHECK(error_of("false || 1") == "15: '||' needs bools, found number on the right");
    // Comparisons.
    CHECK(error_of("1 == <1, 2>") == "11: cannot compare number with vector2 using '=='");
    CHECK(error_of("1 < \"a\"") == "11: '<' compares numbers, found number and string");
    CHECK(error_of("[1] == [1]") == "13: cannot compare lists using '=='");
    CHECK(error_of("<1, 2> < <3, 4>") == "16: '<' compares numbers, found vector2 and vector2");
    // Names and calls.
    CHECK(error_of("undefined_name") == "9: unknown name 'undefined_name'");
    CHECK(error_of("nan") == "9: unknown name 'nan'");
    CHECK(error_of("sin") == "9: 'sin' is a function: call it as sin(...)");
    CHECK(error_of("pi(1)") == "9: 'pi' is a number, not a function");
    CHECK(error_of("frobnicate(1)") == "9: unknown function 'frobnicate'");
    // Members and indexing.
    CHECK(error_of("<1, 2, 3>.u") == "19: vector3 has no component 'u' (it has x, y, z and r, g, b)");
    CHECK(error_of("<1, 2>.z") == "16: vector2 has no component 'z' (it has x, y and u, v)");
    CHECK(error_of("(1).x") == "13: '.x' needs a vector, found number");
    CHECK(error_of("[1, 2][2]") == "16: index 2 is out of range for a list of 2 elements");
    CHECK(error_of("[1, 2][-1]") == "16: index -1 is out of range for a list of 2 elements");
    CHECK(error_of("[1, 2][0.5]") == "16: a list index must be an integer, found 0.5");
    CHECK(error_of("[1, 2][\"a\"]") == "16: a list index must be a number, found string");
    CHECK(error_of("1[0]") == "10: cannot index a number: only lists can be indexed");
    CHECK(error_of("<1, true, 3>") == "13: vector components must be numbers, found bool");
}

TEST_CASE("unknown names suggest a close one", "[interpreter][errors]") {
    auto e = evaluate_text("let radius = 2\nlet y = raduis * 2\nlet z = sqr(2)\n");
    REQUIRE(e->diags.all().size() == 2);
    CHECK(e->diags.all()[0].help == std::vector<std::string>{"did you mean 'radius'?"});
    CHECK(e->diags.all()[1].help == std::vector<std::string>{"did you mean 'sqrt'?"});
}

TEST_CASE("the evaluator survives a 10,000-deep expression tree", "[interpreter][limits]") {
    // Built by hand: the parser would refuse it, but the evaluator must not rely on that.
    SourceManager sources;
    const uint32_t file = sources.add("deep.wsd", std::string(20000, ' '));
    Arena arena;
    auto* one = arena.make<NumberExpr>();
    one->kind = ExprKind::Number;
    one->value = 1;
    Expr* e = one;
    for (int i = 0; i < 10000; ++i) {
        auto* u = arena.make<UnaryExpr>();
        u->kind = ExprKind::Unary;
        u->op = UnaryOp::Neg;
        u->span = Span{file, static_cast<uint32_t>(i), static_cast<uint32_t>(i + 1)};
        u->op_span = u->span;
        u->operand = e;
        e = u;
    }
    Diagnostics diags;
    SceneBuilder builder(file);
    Interpreter interpreter(sources, diags, builder);
    CHECK_FALSE(interpreter.evaluate(*e));
    REQUIRE(diags.error_count() == 1);
    CHECK(diags.all()[0].message.rfind("nesting too deep", 0) == 0);
}

TEST_CASE("a 100,000-sphere loop evaluates", "[interpreter][scale]") {
    auto l = load_text(
        std::string(kCamera) +
        "let m = material { color <1, 0.5, 0.25> }\n"
        "for i in 0 .. 100000 { sphere { center <i % 100, floor(i / 100), 0> radius 0.4 material m } }\n");
    REQUIRE(l->errors().empty());
    REQUIRE(l->scene);
    CHECK(l->scene->summary.objects == 100000);
    CHECK(l->scene->summary.materials == 1);
    CHECK(l->scene->spec.shapes.back().center == glm::dvec3(99, 999, 0));
}

TEST_CASE("include runs a file in the scope where it stands, once per scope", "[interpreter][include]") {
    TempDir dir;
    dir.write("lib/materials.wsdi", "let red = material { color <1, 0, 0> }\ninclude \"shapes.wsdi\"\n");
    dir.write("lib/shapes.wsdi", "sphere { center <0, 0, 0> radius 1 material red }\n");
    const std::string main =
        dir.write("main.wsd", std::string(kCamera) +
                                  "include \"lib/materials.wsdi\"\n"
                                  "include \"lib/materials.wsdi\"\n"  // skipped: already included
                                  "include \"lib/shapes.wsdi\"\n"     // skipped too, with a warning
                                  "sphere { center <0, 2, 0> radius 1 material red }\n");
    auto l = load_file(main);
    REQUIRE(l->errors().empty());
    REQUIRE(l->scene);
    CHECK(l->scene->summary.objects == 2);
    CHECK(l->scene->summary.materials == 1);
    CHECK(l->sources.size() == 3);
}

TEST_CASE("an include inside a block scope binds there", "[interpreter][include]") {
    TempDir dir;
    dir.write("defs.wsdi", "let size = 3\n");
    const std::string main =
        dir.write("main.wsd", "if true { include \"defs.wsdi\"  let inner = size }\nlet outer = size\n");
    auto l = load_file(main, true);
    CHECK(l->errors() == std::vector<std::string>{"2:13: unknown name 'size'"});
}

TEST_CASE("errors inside an included file are reported there with the include chain",
          "[interpreter][include]") {
    TempDir dir;
    dir.write("a.wsdi", "include \"b.wsdi\"\n");
    dir.write("b.wsdi", "let x = 1\nlet y = x / 0\n");
    const std::string main = dir.write("main.wsd", "\ninclude \"a.wsdi\"\n");
    auto l = load_file(main, true);
    REQUIRE(l->diags.all().size() == 1);
    const Diagnostic& d = l->diags.all()[0];
    CHECK(l->sources.file(d.span.file).path == (dir.path / "b.wsdi").string());
    CHECK(where(l->sources, d.span) == "2:11");
    const std::vector<Note> notes = notes_with_includes(d);
    REQUIRE(notes.size() == 2);
    CHECK(l->sources.file(notes[0].span.file).path == (dir.path / "a.wsdi").string());  // innermost first
    CHECK(where(l->sources, notes[0].span) == "1:9");
    CHECK(l->sources.file(notes[1].span.file).path == main);
    CHECK(where(l->sources, notes[1].span) == "2:9");
}

TEST_CASE("include cycles are errors; a file including itself too", "[interpreter][include]") {
    TempDir dir;
    dir.write("a.wsdi", "include \"b.wsdi\"\n");
    dir.write("b.wsdi", "let q = 1\ninclude \"a.wsdi\"\n");
    const std::string main = dir.write("main.wsd", "include \"a.wsdi\"\n");
    auto l = load_file(main, true);
    REQUIRE(l->errors().size() == 1);
    CHECK(l->errors()[0] == "2:9: include cycle: a.wsdi → b.wsdi → a.wsdi");
    CHECK(l->sources.file(l->diags.all()[0].span.file).path == (dir.path / "b.wsdi").string());

    const std::string self = dir.write("self.wsd", "let a = 1\ninclude \"self.wsd\"\n");
    l = load_file(self, true);
    CHECK(l->errors() == std::vector<std::string>{"2:9: include cycle: self.wsd → self.wsd"});
}

TEST_CASE("a missing include names the path that was tried", "[interpreter][include]") {
    TempDir dir;
    const std::string main = dir.write("main.wsd", "include \"sub/none.wsdi\"\nlet a = b\n");
    auto l = load_file(main, true);
    const std::string tried = (dir.path / "sub/none.wsdi").string();
    CHECK(l->errors() == std::vector<std::string>{"1:9: cannot read include file '" + tried +
                                                  "': no such file or directory"});
    l = load_file(dir.write("dir.wsd", "include \"sub\"\n"), true);
    std::filesystem::create_directories(dir.path / "sub");
    l = load_file((dir.path / "dir.wsd").string(), true);
    CHECK(l->errors() == std::vector<std::string>{"1:9: cannot read include file '" +
                                                  (dir.path / "sub").string() + "': it is a directory"});
}

TEST_CASE("syntax errors in an included file stop the evaluation", "[interpreter][include]") {
    TempDir dir;
    dir.write("bad.wsdi", "let = 3\n");
    const std::string main = dir.write("main.wsd", "include \"bad.wsdi\"\nlet y = missing_from_bad\n");
    auto l = load_file(main, true);
    REQUIRE(l->diags.error_count() >= 1);
    for (const Diagnostic& d : l->diags.all()) {
        CHECK(l->sources.file(d.span.file).path == (dir.path / "bad.wsdi").string());
        CHECK(d.include_chain.size() == 1);
    }
}

TEST_CASE("includes nest at most 64 deep", "[interpreter][include][limits]") {
    TempDir dir;
    // Names built with append: GCC 12's -Wrestrict misreads "f" + std::to_string(i) once inlined here.
    const auto name = [](char prefix, int i) {
        return std::string(1, prefix).append(std::to_string(i)).append(".wsdi");
    };
    for (int i = 0; i < 70; ++i) dir.write(name('f', i), "include \"" + name('f', i + 1) + "\"\n");
    dir.write("f70.wsdi", "let done = 1\n");
    auto l = load_file((dir.path / "f0.wsdi").string(), true);
    REQUIRE(l->errors().size() == 1);
    CHECK(l->errors()[0] == "1:9: includes nested too deep (limit 64)");
    CHECK(l->sources.file(l->diags.all()[0].span.file).path == (dir.path / "f64.wsdi").string());

    for (int i = 0; i < 64; ++i) dir.write(name('g', i), "include \"" + name('g', i + 1) + "\"\n");
    dir.write("g64.wsdi", "let done = 1\n");
    l = load_file((dir.path / "g0.wsdi").string(), true);
    CHECK(l->errors().empty());
}

// A camera and a light, so that the only warnings are the includes'.
const std::string kLitCamera = std::string(kCamera) + "light point { position <0, 5, -5> }\n";

TEST_CASE("an include runs again in each loop iteration and in sibling scopes", "[interpreter][include]") {
    TempDir dir;
    dir.write("place.wsdi", "sphere { center <i, 0, 0> radius 0.4 material material { } }\n");
    const std::string main =
        dir.write("main.wsd", kLitCamera + "for i in 0 .. 3 { include \"place.wsdi\" }\n");
    auto l = load_file(main);
    REQUIRE(l->errors().empty());
    REQUIRE(l->scene);
    CHECK(l->scene->summary.objects == 3);
    CHECK(l->scene->spec.shapes.back().center == glm::dvec3(2, 0, 0));
    CHECK(messages(l->diags, l->sources, Severity::Warning).empty());
}

TEST_CASE("a file included in every loop iteration is read and parsed once", "[interpreter][include]") {
    TempDir dir;
    dir.write("place.wsdi", "sphere { center <i, 0, 0> radius 0.4 material material { } }\n");
    const std::string main =
        dir.write("main.wsd", kLitCamera + "for i in 0 .. 1000 { include \"place.wsdi\" }\n");
    auto l = load_file(main);
    REQUIRE(l->errors().empty());
    REQUIRE(l->scene);
    CHECK(l->scene->summary.objects == 1000);
    CHECK(l->scene->spec.shapes.back().center == glm::dvec3(999, 0, 0));
    // One source for the scene, one for the include: memory does not grow with the iterations.
    CHECK(l->sources.size() == 2);
}

TEST_CASE("an include after an if-scoped include of the same file defines its names",
          "[interpreter][include]") {
    TempDir dir;
    dir.write("lib.wsdi", "let size = 3\n");
    const std::string main = dir.write(
        "main.wsd", "let c = true\nif c { include \"lib.wsdi\" }\ninclude \"lib.wsdi\"\nlet s = size\n");
    auto l = load_file(main, true);
    CHECK(l->errors().empty());
}

TEST_CASE("an include of a file already included in an enclosing scope is skipped",
          "[interpreter][include]") {
    TempDir dir;
    dir.write("lib.wsdi", "let size = 3\n");
    dir.write("obj.wsdi", "sphere { center <0, 0, 0> radius 1 material material { } }\n");
    const std::string main =
        dir.write("main.wsd", kLitCamera +
                                  "include \"lib.wsdi\"\n"
                                  "include \"obj.wsdi\"\n"
                                  "if true { include \"lib.wsdi\"  include \"obj.wsdi\" }\n");
    auto l = load_file(main);
    REQUIRE(l->errors().empty());  // lib.wsdi would rebind 'size' in the same scope if it ran again
    REQUIRE(l->scene);
    CHECK(l->scene->summary.objects == 1);
    // Only the skipped include that would have added objects warns, with a note at the first.
    const auto warnings = messages(l->diags, l->sources, Severity::Warning);
    REQUIRE(warnings.size() == 1);
    CHECK(
        warnings[0] ==
        "5:39: include of 'obj.wsdi' skipped: it was already included in this scope or an enclosing one, so "
        "its objects are not added again");
    const Diagnostic* w = nullptr;
    for (const Diagnostic& d : l->diags.all())
        if (d.severity == Severity::Warning) w = &d;
    REQUIRE(w);
    REQUIRE(w->notes.size() == 1);
    CHECK(where(l->sources, w->notes[0].span) == "4:9");
}
