// The built-in constants `clock` and `frame`: a still's 0 and 0, the values of the frame the
// interpreter is given (LoadOptions::time), shadowable like every built-in, and seen by --define.
#include <catch2/catch.hpp>

#include "eval_helpers.h"
#include "lang/params.h"

using namespace wsd::lang;
using namespace wsd::lang::test;

namespace {

// The number bound to `x` after running `text` (which defines x) at `time`.
double number_at(const std::string& text, const AnimationTime& time) {
    SourceManager sources;
    Diagnostics diags;
    const uint32_t file = sources.add("t.wsd", text);
    const Program program = parse(file, sources, diags);
    SceneBuilder builder(file);
    Interpreter interpreter(sources, diags, builder);
    interpreter.set_time(time);
    interpreter.run(program);
    REQUIRE(messages(diags, sources).empty());
    const std::optional<Value> x = interpreter.lookup("x");
    REQUIRE(x);
    REQUIRE(x->is(ValueType::Number));
    return x->number();
}

}  // namespace

TEST_CASE("clock and frame are 0 and 0 in a still", "[animation]") {
    REQUIRE(value_of("clock")->number() == 0.0);
    REQUIRE(value_of("frame")->number() == 0.0);
    REQUIRE(errors_of("clock + frame").empty());
}

TEST_CASE("clock and frame take the values of the frame being evaluated", "[animation]") {
    REQUIRE(number_at("let x = clock\n", {0.25, 7}) == 0.25);
    REQUIRE(number_at("let x = frame\n", {0.25, 7}) == 7.0);
    REQUIRE(number_at("fn at() { return clock * 10 + frame }\nlet x = at()\n", {0.5, 3}) == 8.0);
}

TEST_CASE("clock and frame may be shadowed by a let", "[animation]") {
    REQUIRE(number_at("let clock = 9\nlet x = clock\n", {0.5, 3}) == 9.0);
    REQUIRE(number_at("let frame = \"f\"\nlet x = len([frame])\n", {0.5, 3}) == 1.0);
}

TEST_CASE("clock is a number, not a function", "[animation][errors]") {
    REQUIRE(errors_of("clock(1)") == std::vector<std::string>{"1:9: 'clock' is a number, not a function"});
}

TEST_CASE("load_scene passes the frame's time to the scene", "[animation]") {
    auto l = std::make_unique<Loaded>();
    LoadOptions options;
    options.build = false;
    options.time = {0.5, 12};
    l->scene = load_scene("t.wsd",
                          "camera { position <0, 0, -5>  look_at <0, 0, 0> }\n"
                          "sphere { center <clock, frame, 0>  radius 1  material { color <1, 1, 1> } }\n",
                          l->sources, l->diags, options);
    REQUIRE(l->errors().empty());
    REQUIRE(l->scene);
    REQUIRE(l->scene->spec.shapes.size() == 1);
    REQUIRE(l->scene->spec.shapes[0].center.x == 0.5);
    REQUIRE(l->scene->spec.shapes[0].center.y == 12.0);
}

TEST_CASE("a --define sees the frame's clock and frame", "[animation][define]") {
    std::string error;
    const std::optional<Value> v = evaluate_define("clock * 100 + frame", error, {0.25, 3});
    REQUIRE(v);
    REQUIRE(v->number() == 28.0);
    REQUIRE(evaluate_define("frame", error)->number() == 0.0);
}
