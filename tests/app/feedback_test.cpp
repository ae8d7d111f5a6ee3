// What the commands tell the user besides the image: usage errors that the command line (not the
// scene) causes, counts in messages, the "wrote" line, statistics that add up, warnings on demand,
// and objects named by where they are written.
#include <catch2/catch.hpp>

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
