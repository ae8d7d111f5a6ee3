// User functions: recursion, closures, defaults, functions as values, the call-depth limit and
// its chain, the step budget, includes per call, and the deterministic `random`.
#include <unistd.h>

#include <bit>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>

#include "eval_helpers.h"
#include "lang/builtins.h"

using namespace wsd::lang;
using namespace wsd::lang::test;

namespace {

double number(const Evaluated& e, const std::string& name) {
    std::optional<Value> v = e.get(name);
    REQUIRE(v);
    REQUIRE(v->is(ValueType::Number));
    return v->number();
}

struct TempDir {
    std::filesystem::path path;
    TempDir() {
        static int n = 0;
        path = std::filesystem::temp_directory_path() /
               ("wsd-fn-" + std::to_string(::getpid()) + "-" + std::to_string(n++));
        std::filesystem::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    std::string write(const std::string& name, const std::string& text) const {
        const std::filesystem::path p = path / name;
        std::ofstream(p, std::ios::binary) << text;
        return p.string();
    }
};

std::unique_ptr<Loaded> load_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return load_text(text, false, false, path);
}

// The reference for `random`: splitmix64's finaliser over the arguments' component counts and
// IEEE bits, as documented in docs/wsd-language.md.
uint64_t mix(uint64_t z) {
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}
double reference_random(const std::vector<std::vector<double>>& args) {
    uint64_t h = 0;
    for (const auto& a : args) {
        h = mix(h ^ a.size());
        for (double x : a) h = mix(h ^ (x == 0 ? 0 : std::bit_cast<uint64_t>(x)));
    }
    return static_cast<double>(h >> 11) * 0x1.0p-53;
}

// Calls the builtin directly (no interpreter): for the many calls of the uniformity check.
double call_random(const std::vector<Value>& args) {
    Arena arena;
    std::vector<Expr*> exprs;
    for (size_t i = 0; i < args.size(); ++i) {
        auto* e = arena.make<NumberExpr>();
        e->kind = ExprKind::Number;
        exprs.push_back(e);
    }
    CallExpr call;
    call.kind = ExprKind::Call;
    call.name = "random";
    call.args = arena.copy(exprs);
    Diagnostics diags;
    std::optional<Value> v = find_builtin("random")->fn(CallContext{call, args, diags, nullptr});
    REQUIRE(v);
    return v->number();
}

}  // namespace

TEST_CASE("recursion: factorial, fibonacci and mutual recursion", "[functions]") {
    auto e = evaluate_text(
        "fn fact(n) { if n <= 1 { return 1 } return n * fact(n - 1) }\n"
        "fn fib(n) { if n < 2 { return n } return fib(n - 1) + fib(n - 2) }\n"
        "fn even(n) { if n == 0 { return true } return odd(n - 1) }\n"
        "fn odd(n) { if n == 0 { return false } return even(n - 1) }\n"
        "let a = fact(20)\n"
        "let b = fib(25)\n"
        "let c = even(200)\n"
        "let d = odd(200)\n");
    REQUIRE(e->errors().empty());
    CHECK(number(*e, "a") == 2432902008176640000.0);
    CHECK(number(*e, "b") == 75025);
    CHECK(e->get("c")->boolean());
    CHECK_FALSE(e->get("d")->boolean());
}

TEST_CASE("a trailing comma is allowed in a call's arguments, as in a parameter list", "[functions]") {
    auto e = evaluate_text(
        "fn add(a, b = 10,) { return a + b }\n"
        "let one = add(1,)\n"
        "let two = add(1, 2,)\n"
        "add(3,)\n");
    REQUIRE(e->errors().empty());
    CHECK(number(*e, "one") == 11);
    CHECK(number(*e, "two") == 3);
    // One comma at the end only, and not alone.
    CHECK_FALSE(evaluate_text("fn f(a) { return a }\nlet x = f(1,,)\n")->errors().empty());
    CHECK_FALSE(evaluate_text("fn f(a = 1) { return a }\nlet x = f(,)\n")->errors().empty());
}

TEST_CASE("names in a body resolve when it runs, in the defining scope", "[functions]") {
    SECTION("a function called before what it calls is defined") {
        auto e = evaluate_text("fn f() { return g() }\nlet x = f()\nfn g() { return 1 }\n");
        CHECK(e->errors() == std::vector<std::string>{"1:17: unknown function 'g'"});
    }
    SECTION("the caller's names are not visible") {
        auto e = evaluate_text(
            "let k = 1\nfn get() { return k }\nfn caller() { let k = 2\n return get() }\n"
            "let x = caller()\n");
        REQUIRE(e->errors().empty());
        CHECK(number(*e, "x") == 1);
    }
    SECTION("a default is evaluated in the definition's scope and sees earlier parameters") {
        auto e = evaluate_text(
            "let s = 10\nfn f(a, b = a * 2, c = a + b + s) { return c }\n"
            "fn h() { let s = 1000\n return f(1) }\nlet x = h()\nlet y = f(1, 5)\nlet z = f(1, 5, 0)\n");
        REQUIRE(e->errors().empty());
        CHECK(number(*e, "x") == 13);
        CHECK(number(*e, "y") == 16);
        CHECK(number(*e, "z") == 0);
    }
}

TEST_CASE("closures keep their defining scope; one made in a loop sees that iteration", "[functions]") {
    auto e = evaluate_text(
        "fn make(n) { fn get(x) { return x + n } return get }\n"
        "let gs = [make(1), make(10), make(100)]\n"
        "let g = gs[1]\n"
        "let a = g(5)\n"
        "fn call_with(f, x) { return f(x) }\n"
        "let sums = [0, 0, 0]\n"
        "fn loop_check() {\n"
        "  for i in 0 .. 3 { fn add_i(x) { return x + i } if call_with(add_i, 1) != i + 1 { return false } "
        "}\n"
        "  return true\n"
        "}\n"
        "let b = loop_check()\n");
    REQUIRE(e->errors().empty());
    CHECK(number(*e, "a") == 15);
    CHECK(e->get("b")->boolean());
}

TEST_CASE("closures that are dropped are freed, also those bound in their own call's scope", "[functions]") {
    // Each call binds `get` in its own scope and returns it: the scope and the function hold each
    // other until the loop drops the function.
    auto e = evaluate_text(
        "fn make(n) { fn get(x) { return x + n } return get }\n"
        "let kept = make(7)\n"
        "for i in 0 .. 10000 { let g = make(i)  if g(1) != i + 1 { let wrong = 1 / 0 } }\n"
        "let a = kept(1)\n");
    REQUIRE(e->errors().empty());
    CHECK(number(*e, "a") == 8);
    CHECK(e->interpreter->escaped_scopes_alive() < 200);
}

TEST_CASE("functions are values of type function", "[functions]") {
    auto e = evaluate_text(
        "fn twice(f, x) { return f(f(x)) }\nfn inc(x) { return x + 1 }\n"
        "let f = inc\nlet fs = [inc, twice]\nlet a = twice(inc, 1)\nlet t = fs[1]\nlet b = t(f, 10)\n");
    REQUIRE(e->errors().empty());
    REQUIRE(e->get("f"));
    CHECK(e->get("f")->is(ValueType::Function));
    CHECK(std::string(type_name(e->get("f")->type())) == "function");
    CHECK(number(*e, "a") == 3);
    CHECK(number(*e, "b") == 12);
}

TEST_CASE("a call statement adds the objects its body creates, up to a return", "[functions]") {
    auto l = load_text(std::string(kCamera) +
                       "let default_material = material { color <1, 1, 1> }\n"
                       "fn leg(x, z, h = 0.7) { sphere { center <x, h, z> radius 0.1 } }\n"
                       "fn two() { leg(0, 0) leg(1, 1)\n return 5\n leg(2, 2) }\n"
                       "for x in [-1, 1] { for z in [-1, 1] { leg(x, z) } }\n"
                       "two()\n");
    REQUIRE(l->errors().empty());
    REQUIRE(l->scene);
    CHECK(l->scene->summary.objects == 6);
    CHECK(l->scene->spec.shapes[0].center == glm::dvec3(-1, 0.7, -1));
}

TEST_CASE("an object statement during a call from an expression is an error with a note at the call",
          "[functions]") {
    auto e = evaluate_text(
        "fn ball() { sphere { center <0, 0, 0> radius 1 material { color <1, 1, 1> } }\n return 1 }\n"
        "fn outer() { ball()\n return 2 }\n"
        "let x = outer()\n");
    REQUIRE(e->errors() ==
            std::vector<std::string>{"1:13: 'sphere' cannot run during a call made from an expression"});
    const Diagnostic& d = e->diags.all()[0];
    REQUIRE(d.notes.size() == 1);
    CHECK(where(e->sources, d.notes[0].span) == "5:9");
    CHECK(d.notes[0].message == "the call to 'outer', in an expression");
}

TEST_CASE("R77: calls nest at most 256 deep; the error names the chain", "[functions][limits]") {
    SECTION("256 nested calls are allowed") {
        auto e = evaluate_text(
            "fn down(n) { if n == 0 { return 0 } return down(n - 1) + 1 }\nlet x = down(255)\n");
        REQUIRE(e->errors().empty());
        CHECK(number(*e, "x") == 255);
    }
    SECTION("the 257th is an error at that call, with the first and last three calls") {
        auto e = evaluate_text(
            "fn down(n) { if n == 0 { return 0 } return down(n - 1) + 1 }\nlet x = down(256)\nlet y = 1\n");
        REQUIRE(e->errors() ==
                std::vector<std::string>{"1:44: calls nested too deep (the limit is 256 nested calls)"});
        const Diagnostic& d = e->diags.all()[0];
        REQUIRE(d.notes.size() == 6);
        CHECK(where(e->sources, d.notes[0].span) == "2:9");
        CHECK(d.notes[0].message == "call 1 of 256 in the chain, to 'down'");
        CHECK(where(e->sources, d.notes[1].span) == "1:44");
        CHECK(d.notes[3].message == "call 254 of 256 in the chain, to 'down'");
        CHECK(d.notes[5].message == "call 256 of 256 in the chain, to 'down'");
        CHECK(d.help == std::vector<std::string>{"calls 4 to 253 of the chain are not shown"});
        CHECK(e->interpreter->aborted());
        CHECK_FALSE(e->get("y"));  // evaluation stopped
    }
    SECTION("a short chain is shown whole") {
        Limits limits;
        limits.call_depth = 4;
        auto e = evaluate_text("fn f(n) { return f(n + 1) }\nlet x = f(0)\n", limits);
        REQUIRE(e->errors().size() == 1);
        CHECK(e->diags.all()[0].notes.size() == 4);
        CHECK(e->diags.all()[0].help.empty());
    }
}

TEST_CASE("R77: 256 nested calls, each nesting expressions deeply, do not overflow the stack",
          "[functions][limits]") {
    // 240 unary minuses around each recursive call: about 62,000 levels of evaluation in all.
    std::string minuses;
    for (int i = 0; i < 240; ++i) minuses += "-";
    auto e = evaluate_text("fn f(n) { if n == 0 { return 0 } return " + minuses +
                           "f(n - 1) + 1 }\nlet x = f(255)\n");
    REQUIRE(e->errors().empty());
    CHECK(number(*e, "x") == 255);
}

TEST_CASE("R77: a runaway recursion ends at the step budget", "[functions][limits]") {
    Limits limits;
    limits.loop_iterations = 10000;
    auto e = evaluate_text("fn f(n) { if n > 0 { f(n - 1)\n f(n - 1) } }\nf(40)\nlet after = 1\n", limits);
    REQUIRE(e->errors().size() == 1);
    CHECK(e->errors()[0].find("the call to 'f' exceeds the limit of 10000 steps in total") !=
          std::string::npos);
    CHECK(e->interpreter->iterations() == 10000);
    CHECK_FALSE(e->get("after"));
}

TEST_CASE("calls and loop iterations share the step budget", "[functions][limits]") {
    Limits limits;
    limits.loop_iterations = 100;
    auto e = evaluate_text("fn f() { return 1 }\nfor i in 0 .. 60 { let x = f() }\n", limits);
    REQUIRE(e->errors().size() == 1);
    CHECK(e->errors()[0].rfind("2:28: the call to 'f' exceeds the limit of 100 steps", 0) == 0);
}

TEST_CASE("a loop left by return takes only the steps it ran", "[functions][limits]") {
    Limits limits;
    limits.loop_iterations = 1000;
    auto e = evaluate_text(
        "fn find(xs) { for x in xs { if x > 1 { return x } }\n return 0 }\n"
        "fn first() { for i in 0 .. 600 { if i == 2 { return i } }\n return 0 }\n"
        "let a = first() + first() + find([1, 2, 3, 4, 5, 6, 7, 8, 9]) + find([5, 1, 1, 1, 1, 1, 1])\n",
        limits);
    REQUIRE(e->errors().empty());
    CHECK(number(*e, "a") == 11);
    CHECK(e->interpreter->iterations() == 4 + 3 + 3 + 2 + 1);  // 4 calls, 3 + 3 + 2 + 1 iterations
}

TEST_CASE("an include in a function body runs once per call", "[functions][include]") {
    TempDir dir;
    dir.write("ball.wsdi", "sphere { center <0, 0, 0> radius 1 material { color <1, 1, 1> } }\n");
    dir.write("ten.wsdi", "let ten = 10\n");
    const std::string main =
        dir.write("main.wsd", std::string(kCamera) +
                                  "fn put() { include \"ball.wsdi\" }\n"
                                  "for i in 0 .. 3 { put() }\n"
                                  "fn tenfold(k) { include \"ten.wsdi\"\n return ten * k }\n"
                                  "let a = tenfold(1) + tenfold(2)\n"
                                  "sphere { center <a, 0, 0> radius 1 material { color <1, 1, 1> } }\n");
    auto l = load_file(main);
    REQUIRE(l->errors().empty());
    REQUIRE(l->scene);
    CHECK(l->scene->summary.objects == 4);
    CHECK(l->scene->spec.shapes.back().center.x == 30);
}

TEST_CASE("errors in a body carry the include chain of its definition", "[functions][include]") {
    TempDir dir;
    dir.write("lib.wsdi", "fn broken() { return 1 / 0 }\n");
    dir.write("user.wsdi", "let y = broken()\n");
    const std::string main = dir.write(
        "main.wsd", std::string(kCamera) + "include \"lib.wsdi\"\nif true { include \"user.wsdi\" }\n");
    auto l = load_file(main);
    REQUIRE(l->errors() == std::vector<std::string>{"1:24: division by zero"});
    const Diagnostic& d = l->diags.all()[0];
    REQUIRE(d.include_chain.size() == 1);
    CHECK(where(l->sources, d.include_chain[0]) == "2:9");
}

TEST_CASE("random is a fixed hash of its arguments", "[functions][random]") {
    auto e = evaluate_text(
        "let a = random(1)\nlet b = random(0)\nlet c = random(-0)\nlet d = random(1, 2)\n"
        "let f = random(<1, 2>)\nlet g = random(<0.5, -2, 3>, 7, <1, 1>)\nlet h = random(1e300)\n");
    REQUIRE(e->errors().empty());
    CHECK(number(*e, "a") == reference_random({{1}}));
    CHECK(number(*e, "b") == reference_random({{0}}));
    CHECK(number(*e, "c") == number(*e, "b"));
    CHECK(number(*e, "d") == reference_random({{1}, {2}}));
    CHECK(number(*e, "f") == reference_random({{1, 2}}));
    CHECK(number(*e, "d") != number(*e, "f"));
    CHECK(number(*e, "g") == reference_random({{0.5, -2, 3}, {7}, {1, 1}}));
    CHECK(number(*e, "h") == reference_random({{1e300}}));
    // Pinned (and computed independently): the same numbers on every machine and in every version.
    CHECK(number(*e, "a") == 0x1.76354874c3f7fp-1);
    CHECK(number(*e, "b") == 0x1.7906ac21d0e58p-2);
    CHECK(number(*e, "d") == 0x1.a00a7c4a8f948p-4);
}

TEST_CASE("random is uniform on [0, 1)", "[functions][random]") {
    constexpr int kCalls = 100000, kBins = 20;
    std::vector<int> bins(kBins, 0);
    double sum = 0;
    for (int i = 0; i < kCalls; ++i) {
        const double r = i % 2 == 0 ? call_random({Value::make_number(i, {})})
                                    : call_random({Value::make_number(i, {}), Value::make_number(7, {})});
        REQUIRE(r >= 0);
        REQUIRE(r < 1);
        sum += r;
        ++bins[static_cast<size_t>(r * kBins)];
    }
    // The standard error of the mean is 0.29 / sqrt(1e5) = 0.0009.
    CHECK(std::abs(sum / kCalls - 0.5) < 0.005);
    const double expected = double(kCalls) / kBins;
    double chi2 = 0;
    for (int b : bins) chi2 += (b - expected) * (b - expected) / expected;
    CHECK(chi2 < 43.8);  // the 99.9th percentile of chi-squared with 19 degrees of freedom
}
