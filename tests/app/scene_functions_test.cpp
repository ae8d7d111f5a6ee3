// Scenes built with functions, groups and instances through the real `wsd`: what `wsd check`
// counts (objects and triangles as instanced, then what is stored), `--effects` naming CSG and
// nothing new for a v1 scene, `wsd ast` showing the new nodes, and the errors a function reaches.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>

#include "app_test_util.h"

using namespace wsd::test;

namespace {

const char* const kHead =
    "settings { width 16  height 16 }\n"
    "camera { position <0, 2, -5>  look_at <0, 0, 0> }\n"
    "light spot { position <0, 20, 0>  look_at <0, 0, 0>  angle 40  falloff 60 }\n"
    "let red = material { color <0.9, 0.2, 0.2> }\n";

const std::string kOk = ": ok \xE2\x80\x94 ";

// `wsd check NAME.wsd` on kHead + scene: stdout, with the exit status checked.
std::string check(const TempDir& dir, const std::string& scene, const std::string& flags = "") {
    write_file(dir / "s.wsd", kHead + scene);
    const RunResult r = run_wsd(dir, "check " + flags + " s.wsd");
    INFO(r.err);
    CHECK(r.status == 0);
    return r.out;
}

// Renders kHead + scene at 16×16; the render must succeed without a non-finite sample.
void render_ok(const TempDir& dir, const std::string& scene) {
    write_file(dir / "r.wsd", kHead + scene);
    const RunResult r = run_wsd(dir, "render r.wsd -o r.pfm --quiet --stats-json r.json");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(read_file(dir / "r.json").find("\"nonfinite_samples\": 0,") != std::string::npos);
}

}  // namespace

TEST_CASE("a function adds its objects to the group whose body calls it", "[functions][e2e]") {
    TempDir dir;
    const std::string scene =
        "fn leg(x, z, height = 0.7) {\n"
        "    cylinder { base <x, 0, z>  cap <x, height, z>  radius 0.04 }\n"
        "}\n"
        "fn table(w) {\n"
        "    return group {\n"
        "        box { min <-w, 0.7, -0.6>  max <w, 0.75, 0.6> }\n"
        "        for x in [-w + 0.1, w - 0.1] { for z in [-0.5, 0.5] { leg(x, z) } }\n"
        "    }\n"
        "}\n"
        "let t = table(1)\n"
        "object t { translate <2, 0, 0>  material red }\n"
        "object t { translate <-2, 0, 0>  material red }\n"
        "object table(0.5) { translate <0, 0, 2>  material red }\n";
    // Three tables of a top and four legs: 15 objects; two distinct group values store 10 shapes.
    CHECK(check(dir, scene) ==
          "s.wsd" + kOk + "15 objects, 0 triangles, 1 light, 1 material (stored: 10 shapes, 0 triangles)\n");
    render_ok(dir, scene);
}

TEST_CASE("an object statement reached from a call in an expression is an error with a note at the call",
          "[functions][e2e]") {
    TempDir dir;
    write_file(dir / "s.wsd", std::string(kHead) +
                                  "fn f() {\n"
                                  "    sphere { center <0, 0, 0>  radius 1  material red }\n"
                                  "    return 1\n"
                                  "}\n"
                                  "let x = f() + 1\n");
    const RunResult r = run_wsd(dir, "check s.wsd");
    CHECK(r.status == 1);
    CHECK_THAT(r.err, Catch::Contains(
                          "s.wsd:6:5: error: 'sphere' cannot run during a call made from an expression"));
    CHECK_THAT(r.err, Catch::Contains("s.wsd:9:9: note: the call to 'f', in an expression"));
}

TEST_CASE("a recursive function builds a fractal of instances: 3^depth leaves", "[functions][e2e]") {
    TempDir dir;
    for (const int depth : {1, 4, 7}) {
        const std::string scene =
            "let ball = sphere { center <0, 0, 0>  radius 0.5 }\n"
            "fn fractal(depth) {\n"
            "    if depth == 0 { return ball }\n"
            "    let child = fractal(depth - 1)\n"
            "    return group {\n"
            "        object child { scale 0.5  translate <-1, 0, 0> }\n"
            "        object child { scale 0.5  translate <1, 0, 0> }\n"
            "        object child { scale 0.5  translate <0, 1, 0> }\n"
            "    }\n"
            "}\n"
            "object fractal(" +
            std::to_string(depth) + ") { material red }\n";
        INFO("depth " << depth);
        const int leaves = int(std::lround(std::pow(3, depth)));
        // The innermost group holds three copies of the ball (an object of one primitive is stored
        // as a copy); every level above it is instances of instances.
        const std::string stored = " (stored: 3 shapes, 0 triangles)";
        CHECK(check(dir, scene) == "s.wsd" + kOk + std::to_string(leaves) + " objects" +
                                       ", 0 triangles, 1 light, 1 material" + stored + "\n");
        if (depth == 4) render_ok(dir, scene);
    }
}

TEST_CASE("random places 10,000 instanced trees, counted as instanced with what is stored",
          "[functions][e2e]") {
    TempDir dir;
    const std::string scene =
        "let bark = material { color <0.4, 0.3, 0.2> }\n"
        "let tree = group {\n"
        "    cylinder { base <0, 0, 0>  cap <0, 1, 0>  radius 0.1  material bark }\n"
        "    cone { base <0, 1, 0>  base_radius 0.5  cap <0, 2.5, 0>  cap_radius 0 }\n"
        "}\n"
        "for i in 0 .. 10000 {\n"
        "    object tree { scale 0.5 + random(i, 3)  rotate <0, 360 * random(i, 4), 0>\n"
        "                  translate <random(i, 1) * 200 - 100, 0, random(i, 2) * 200 - 100>  material red "
        "}\n"
        "}\n";
    CHECK(check(dir, scene) ==
          "s.wsd" + kOk +
              "20000 objects, 0 triangles, 1 light, 2 materials (stored: 2 shapes, 0 triangles)\n");
    render_ok(dir, scene);
}

TEST_CASE("1,000 instances of a mesh count its triangles a thousand times and store them once",
          "[functions][e2e]") {
    TempDir dir;
    fs::copy_file(fs::path(WSD_SOURCE_DIR) / "examples/models/torus.obj", dir.path() / "torus.obj");
    const std::string mesh = "let t = mesh { file \"torus.obj\" }\n";  // 64 × 32 quads: 4096 triangles
    CHECK(check(dir,
                mesh + "for i in 0 .. 1000 { object t { translate <i % 40, 0, i / 40>  material red } }\n") ==
          "s.wsd" + kOk +
              "1000 objects, 4096000 triangles, 1 light, 1 material (stored: 1 shape, 4096 triangles)\n");
    // In a group with a sphere: each instance adds both members.
    CHECK(check(dir,
                mesh + "let g = group { object t { }  sphere { center <0, 2, 0>  radius 0.5 } }\n"
                       "for i in 0 .. 1000 { object g { translate <i % 40, 0, i / 40>  material red } }\n") ==
          "s.wsd" + kOk +
              "2000 objects, 4096000 triangles, 1 light, 1 material (stored: 2 shapes, 4096 triangles)\n");
}

TEST_CASE("check --effects names CSG, and a v1 scene reports what it always did", "[effects][e2e]") {
    TempDir dir;
    write_file(dir / "tiny.wsd", tiny_scene());
    RunResult r = run_wsd(dir, "check --effects tiny.wsd");
    CHECK(r.status == 0);
    CHECK(r.out == "tiny.wsd" + kOk +
                       "2 objects, 0 triangles, 1 light, 2 materials\n"
                       "  effects:\n"
                       "    area-light soft shadows (scene-wide)\n"
                       "    reflection: sphere at tiny.wsd:5:1\n"
                       "    procedural textures: plane at tiny.wsd:4:1\n"
                       "    specular highlights: sphere at tiny.wsd:5:1\n"
                       "    supersampling (scene-wide)\n");
    const std::string out = check(dir,
                                  "let hollow = difference { box { min <-1, -1, -1>  max <1, 1, 1> }  sphere "
                                  "{ center <0, 0, 0>  radius 1.3 } }\n"
                                  "object hollow { translate <2, 0, 0>  material red }\n"
                                  "difference { box { min <-1, -1, -1>  max <1, 1, 1> }  sphere { center <0, "
                                  "0, 0>  radius 1.3 }  material red }\n",
                                  "--effects");
    CHECK_THAT(out, Catch::Contains("    CSG: difference at s.wsd:5:14, difference at s.wsd:7:1\n"));
    CHECK_THAT(out, Catch::StartsWith("s.wsd" + kOk + "2 objects, 0 triangles"));
}

TEST_CASE("wsd ast prints functions, groups, instances, CSG, the new primitives and spot lights",
          "[ast][e2e]") {
    TempDir dir;
    write_file(dir / "a.wsd",
               "fn leg(x, h = 0.7) { return cylinder { base <x, 0, 0>  cap <x, h, 0>  radius 0.04 } }\n"
               "let t = group { object leg(1) { }  material m  translate <1, 0, 0> }\n"
               "difference { box { min <0, 0, 0>  max <1, 1, 1> }  union { torus { major 1  minor 0.2 } } }\n"
               "light spot { position <0, 5, 0>  look_at <0, 0, 0> }\n"
               "leg(2)\n"
               "disc { center <0, 0, 0>  normal <0, 1, 0>  radius 1 }\n"
               "intersection { cone { base <0, 0, 0>  base_radius 1  cap <0, 1, 0>  cap_radius 0 } }\n");
    const RunResult r = run_wsd(dir, "ast a.wsd");
    CHECK(r.status == 0);
    for (const char* node :
         {"(fn leg @1:1\n  (param x @1:8)\n  (param h @1:11\n    (number 0.7 @1:15))\n  (return @1:22\n    "
          "(cylinder @1:29\n",
          "(let t @2:1\n  (group @2:9\n    (object @2:17\n      (call leg @2:24\n        (number 1 "
          "@2:28)))\n    (item material @2:36\n",
          "(difference @3:1\n  (box @3:14\n", "  (union @3:52\n    (torus @3:60\n      (item major @3:68\n",
          "(light spot @4:1\n  (item position @4:14\n", "(call leg @5:1\n  (number 2 @5:5))\n",
          "(disc @6:1\n  (item center @6:8\n", "(intersection @7:1\n  (cone @7:16\n    (item base @7:23\n"}) {
        CHECK_THAT(r.out, Catch::Contains(node));
    }
}
