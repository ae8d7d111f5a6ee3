// --define NAME=EXPR (-D) and param("NAME", DEFAULT) through the real binary: the value reaches
// the scene in check, render and bench; a bad EXPR is a usage error naming the define; a type
// other than the default's is an error at the call; a define nothing reads is a warning, which
// --no-warnings silences with every other warning.
#include <catch2/catch.hpp>

#include "app_test_util.h"

using namespace wsd::test;

namespace {

// `count` spheres in a row, `count` from param("count", 2); 16×16 pixels.
const char* counted_scene =
    "let count = param(\"count\", 2)\n"
    "let tint = param(\"tint\", <1, 1, 1>)\n"
    "settings { width 16  height 16 }\n"
    "camera { position <0, 0, -4>  look_at <0, 0, 0> }\n"
    "light point { position <0, 4, -4> }\n"
    "for i in 0 .. count { sphere { center <i - 2, 0, 0>  radius 0.5  material { color tint } } }\n";

}  // namespace

TEST_CASE("--define sets what param returns in check, render and bench", "[define]") {
    TempDir dir;
    write_file(dir / "s.wsd", counted_scene);
    RunResult r = run_wsd(dir, "check s.wsd");
    CHECK(r.status == 0);
    CHECK(r.out.find("2 objects") != std::string::npos);
    r = run_wsd(dir, "check s.wsd -D count=5");
    CHECK(r.status == 0);
    CHECK(r.out.find("5 objects") != std::string::npos);
    CHECK(r.err.empty());
    // EXPR is an expression with the built-ins; -D repeats; the option may come before the file.
    r = run_wsd(dir, "check -D 'count=floor(sqrt(10))' --define 'tint=rgb(255, 0, 0)' s.wsd");
    CHECK(r.status == 0);
    CHECK(r.out.find("3 objects") != std::string::npos);
    CHECK(r.err.empty());

    REQUIRE(run_wsd(dir, "render s.wsd -q -o two.pfm").status == 0);
    REQUIRE(run_wsd(dir, "render s.wsd -q -o four.pfm -D count=4").status == 0);
    REQUIRE(run_wsd(dir, "render s.wsd -q -o two-again.pfm -D count=2").status == 0);
    CHECK(read_file(dir / "two.pfm") != read_file(dir / "four.pfm"));
    CHECK(read_file(dir / "two.pfm") == read_file(dir / "two-again.pfm"));

    r = run_wsd(dir, "bench s.wsd --quick -q -o b -D count=3 -D unused=1");
    CHECK(r.status == 0);
    CHECK(r.err == "wsd: warning: --define unused was not used: no param(\"unused\", ...) call read it\n");
}

TEST_CASE("--define errors: a bad EXPR is a usage error, a wrong type an error at param", "[define]") {
    TempDir dir;
    write_file(dir / "s.wsd", counted_scene);
    RunResult r = run_wsd(dir, "render s.wsd -q -D count=abc");
    CHECK(r.status == 2);
    CHECK(r.err == "wsd: error: --define count: unknown name 'abc'\n");
    r = run_wsd(dir, "check s.wsd -D 'count=1 +'");
    CHECK(r.status == 2);
    CHECK(r.err.find("wsd: error: --define count: ") == 0);
    r = run_wsd(dir, "check s.wsd -D count");
    CHECK(r.status == 2);
    CHECK(r.err.find("--define 'count': expected NAME=EXPR") != std::string::npos);
    r = run_wsd(dir, "bench s.wsd --quick -D 'tint=material { color <1, 0, 0> }'");
    CHECK(r.status == 2);
    CHECK(r.err.find("--define tint: must be a number, bool, string or vector, not a material") !=
          std::string::npos);

    r = run_wsd(dir, "check s.wsd -D 'count=\"many\"'");
    CHECK(r.status == 1);
    CHECK(r.err.find("s.wsd:1:13: error: --define count is a string, but the default of "
                     "param(\"count\", ...) is a number") != std::string::npos);
    r = run_wsd(dir, "check s.wsd -D 'count=<1, 2>'");
    CHECK(r.status == 1);
    CHECK(r.err.find("--define count is a vector2") != std::string::npos);
    CHECK(list_files(dir) == std::vector<std::string>{"s.wsd"});
}

TEST_CASE("an unread --define is a warning; --no-warnings silences warnings", "[define]") {
    TempDir dir;
    write_file(dir / "s.wsd", counted_scene);
    RunResult r = run_wsd(dir, "check s.wsd -D cuont=3");
    CHECK(r.status == 0);
    CHECK(r.err == "wsd: warning: --define cuont was not used: no param(\"cuont\", ...) call read it\n");
    r = run_wsd(dir, "check s.wsd -D cuont=3 --no-warnings");
    CHECK(r.status == 0);
    CHECK(r.err.empty());

    // A scene warning (an OBJ statement wsd does not use) and its silencing, in every command.
    write_file(dir / "tri.obj", "o thing\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string mesh = "mesh { file \"tri.obj\"  material { color <1, 1, 1> } }\n";
    write_file(dir / "w.wsd", counted_scene + mesh);
    r = run_wsd(dir, "check w.wsd");
    REQUIRE(r.status == 0);
    REQUIRE(r.err.find("warning:") != std::string::npos);
    CHECK(run_wsd(dir, "check w.wsd --no-warnings").err.empty());
    CHECK(run_wsd(dir, "render w.wsd -q --no-warnings").err.empty());
    CHECK(run_wsd(dir, "bench w.wsd --quick -q -o b --no-warnings").err.empty());
    // Errors still show.
    write_file(dir / "e.wsd", counted_scene + mesh + "let x = 1 / 0\n");
    r = run_wsd(dir, "check e.wsd --no-warnings");
    CHECK(r.status == 1);
    CHECK(r.err.find("error:") != std::string::npos);
    CHECK(r.err.find("warning:") == std::string::npos);
}

TEST_CASE("examples/soft-shadows.wsd takes its variant from --define", "[define]") {
    TempDir dir;
    const std::string scene = shell_quote(std::string(WSD_SOURCE_DIR) + "/examples/soft-shadows.wsd");
    const std::string size = " -q --width 40 --height 30";
    RunResult r = run_wsd(dir, "render " + scene + size + " -o default.pfm");
    REQUIRE(r.status == 0);
    CHECK(r.err.empty());
    r = run_wsd(dir, "render " + scene + size + " -o three.pfm -D variant=3");
    REQUIRE(r.status == 0);
    CHECK(r.err.empty());  // the define was read
    REQUIRE(run_wsd(dir, "render " + scene + size + " -o zero.pfm -D variant=0").status == 0);
    CHECK(read_file(dir / "default.pfm") == read_file(dir / "three.pfm"));
    CHECK(read_file(dir / "default.pfm") != read_file(dir / "zero.pfm"));
}
