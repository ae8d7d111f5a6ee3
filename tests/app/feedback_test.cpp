// What the commands tell the user besides the image: usage errors that the command line (not the
// scene) causes, counts in messages, the "wrote" line, statistics that add up, warnings on demand,
// and objects named by where they are written.
#include <catch2/catch.hpp>
#include <chrono>
#include <regex>
#include <sstream>

#include "app_test_util.h"

using namespace wsd::test;

TEST_CASE("render: a size the command line makes too large is a usage error", "[render][feedback]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene());
    RunResult r = run_wsd(dir, "render s.wsd --width 100000 --height 100000 -q");
    CHECK(r.status == 2);
    CHECK(r.err == "wsd: error: image size 100000x100000 exceeds 2^28 pixels\n");
    // The scene's own size is still the scene's error.
    write_file(dir / "big.wsd", "settings { width 100000  height 100000 }\n" +
                                    tiny_scene().substr(tiny_scene().find('\n') + 1));
    r = run_wsd(dir, "render big.wsd -q");
    CHECK(r.status == 1);
    CHECK(r.err.find("big.wsd:1:") != std::string::npos);
    CHECK(list_files(dir).size() == 2);
}

TEST_CASE("counts in messages agree with their nouns", "[feedback]") {
    TempDir dir;
    write_file(dir / "one.wsd",
               "settings { width 4  height 1 }\ncamera { position <0,0,-3> look_at <0,0,0> }\n"
               "light point { position <0,3,-3> }\n"
               "triangle { <0,0,0>, <1,0,0>, <0,1,0>  material { color <1,0,0> } }\n");
    RunResult r = run_wsd(dir, "check one.wsd");
    CHECK(r.status == 0);
    CHECK(r.out == "one.wsd: ok \xE2\x80\x94 1 object, 1 triangle, 1 light, 1 material\n");

    r = run_wsd(dir, "render one.wsd --tile 1/2 -q");
    CHECK(r.status == 2);
    CHECK(r.err.find("the image has only 1 row, so this tile is empty") != std::string::npos);

    r = run_wsd(dir, "render one.wsd --threads 1 --stats -q -o one.png");
    CHECK(r.status == 0);
    CHECK(r.out.find("(1 thread)") != std::string::npos);
    r = run_wsd(dir, "render one.wsd --threads 2 --stats -q -o one.png");
    CHECK(r.out.find("(2 threads)") != std::string::npos);

    write_file(dir / "two.wsd", tiny_scene());
    REQUIRE(run_wsd(dir, "render two.wsd --tile 1/3 -q -o t1.pfm").status == 0);
    r = run_wsd(dir, "merge t1.pfm -o m.png");
    CHECK(r.status == 1);
    CHECK(r.err.find("(missing tiles 2/3, 3/3)") != std::string::npos);
    REQUIRE(run_wsd(dir, "render two.wsd --tile 2/3 -q -o t2.pfm").status == 0);
    r = run_wsd(dir, "merge t1.pfm t2.pfm -o m.png");
    CHECK(r.status == 1);
    CHECK(r.err.find("(missing tile 3/3)") != std::string::npos);
}

namespace {

// A number after "KEY": in a JSON text, or -1 if absent.
double json_number(const std::string& json, const std::string& key) {
    std::smatch m;
    if (!std::regex_search(json, m, std::regex("\"" + key + "\": ([-0-9.eE+]+)"))) return -1;
    return std::stod(m[1].str());
}

// An OBJ grid of n×n quads (2n² triangles): enough geometry that building it takes measurable time.
std::string obj_grid(int n) {
    std::ostringstream out;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x) out << "v " << x << " " << y << " " << (x * y) % 7 << "\n";
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const int a = y * (n + 1) + x + 1, b = a + 1, c = a + n + 2, d = a + n + 1;
            out << "f " << a << " " << b << " " << c << " " << d << "\n";
        }
    return out.str();
}

}  // namespace

TEST_CASE("render --stats-json: parse, build and render times add up to no more than the wall time",
          "[render][feedback]") {
    TempDir dir;
    write_file(dir / "grid.obj", obj_grid(400));
    write_file(dir / "s.wsd",
               "settings { width 2  height 2 }\ncamera { position <200,200,-500> look_at <200,200,0> }\n"
               "light point { position <0,0,-100> }\n"
               "mesh { file \"grid.obj\"  material { color <1,1,1> } }\n");
    const auto start = std::chrono::steady_clock::now();
    const RunResult r = run_wsd(dir, "render s.wsd -q --stats-json s.json");
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    REQUIRE(r.status == 0);
    const std::string json = read_file(dir / "s.json");
    const double parse = json_number(json, "parse_seconds"), build = json_number(json, "build_seconds"),
                 render = json_number(json, "render_seconds");
    REQUIRE(parse >= 0);
    REQUIRE(build > 0);
    REQUIRE(render >= 0);
    CHECK(parse + build + render <= wall);
}

TEST_CASE("render says on stderr what it wrote, unless --quiet", "[render][feedback]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene());
    RunResult r = run_wsd(dir, "render s.wsd");
    REQUIRE(r.status == 0);
    CHECK(r.out.empty());
    CHECK(std::regex_search(r.err, std::regex("(^|\n)wrote s\\.png \\(16\xC3\x97"
                                              "16, [0-9]+\\.[0-9] s\\)\n$")));
    r = run_wsd(dir, "render s.wsd --tile 2/4");
    REQUIRE(r.status == 0);
    CHECK(std::regex_search(r.err,
                            std::regex("wrote s\\.tile-2-of-4\\.pfm \\(tile 2/4: rows 4 to 7 of 16\xC3\x97"
                                       "16, [0-9.]+ s\\)\n$")));
    r = run_wsd(dir, "render s.wsd --region 1,2,5,6 -o r.png");
    REQUIRE(r.status == 0);
    CHECK(std::regex_search(r.err, std::regex("wrote r\\.png \\(region 1,2,5,6 of 16\xC3\x97"
                                              "16, [0-9.]+ s\\)\n$")));
    r = run_wsd(dir, "render s.wsd -o q.png --quiet");
    REQUIRE(r.status == 0);
    CHECK(r.err.empty());
}

TEST_CASE("a mesh file's zero-area triangles are skipped with one warning; written ones stay errors",
          "[feedback][obj]") {
    TempDir dir;
    // A UV sphere's cap: quads whose last two corners are both the pole, and statements wsd skips.
    write_file(dir / "cap.obj",
               "mtllib cap.mtl\no cap\nv 1 0 0\nv 0 0 1\nv -1 0 0\nv 0 0 -1\nv 0 1 0\nusemtl white\ns 1\n"
               "f 1 2 5 5\nf 2 3 5 5\nf 3 4 5 5\nf 4 1 5 5\n");
    const std::string head =
        "camera { position <0, 0.5, -4>  look_at <0, 0.5, 0> }\nlet m = material { color <1, 1, 1> }\n";
    write_file(dir / "s.wsd",
               head + "mesh { file \"cap.obj\"  material m }\nlight point { position <0, 5, -5> }\n");
    RunResult r = run_wsd(dir, "check s.wsd");
    CHECK(r.status == 0);
    CHECK(r.out.find("4 triangles") != std::string::npos);
    CHECK(
        r.err ==
        "s.wsd:3:13: warning: cap.obj:1: ignored 4 statements that wsd does not use: 'mtllib' (line 1), 'o' "
        "(line 2), 'usemtl' (line 8), 's' (line 9)\n"
        "    3 | mesh { file \"cap.obj\"  material m }\n"
        "      |             ^~~~~~~~~\n"
        "s.wsd:3:13: warning: cap.obj:10: skipped 4 degenerate triangles (zero area), the first from this "
        "line's face\n"
        "    3 | mesh { file \"cap.obj\"  material m }\n"
        "      |             ^~~~~~~~~\n");
    CHECK(run_wsd(dir, "check s.wsd --no-warnings").err.empty());
    write_file(dir / "inline.wsd", head +
                                       "mesh { vertices [<1, 0, 0>, <0, 0, 1>, <0, 1, 0>]  faces [<0, 1, 2>, "
                                       "<0, 2, 2>]  material m }\n");
    r = run_wsd(dir, "check inline.wsd");
    CHECK(r.status == 1);
    CHECK(r.err.find("face 1: degenerate triangle") != std::string::npos);
}

TEST_CASE("render --stats and --stats-json count caustic photons, their lookups and the map's time",
          "[render][feedback]") {
    TempDir dir;
    write_file(dir / "c.wsd",
               "settings { width 8  height 8  caustic_photons 5000 }\n"
               "camera { position <0, 3, -4> look_at <0, -1, 0> }\nlight point { position <0, 10, 0> }\n"
               "sphere { center <0, 0, 0> radius 1 material { transmission 1 ior 1.5 diffuse 0 } }\n"
               "plane { normal <0, 1, 0> distance -1.5 material { color <1, 1, 1> } }\n");
    const RunResult r = run_wsd(dir, "render c.wsd -q --stats --stats-json c.json");
    REQUIRE(r.status == 0);
    const std::string json = read_file(dir / "c.json");
    CHECK(json_number(json, "photons_shot") == 5000);
    CHECK(json_number(json, "photons_stored") > 0);
    CHECK(json_number(json, "photon_lookups") > 0);
    CHECK(json_number(json, "photons_visited") >= json_number(json, "photon_lookups"));
    CHECK(json_number(json, "photon_map_seconds") > 0);
    CHECK(json_number(json, "nonfinite_samples") == 0);
    CHECK(r.out.find("Caustic photons:             5000 shot") != std::string::npos);
}
