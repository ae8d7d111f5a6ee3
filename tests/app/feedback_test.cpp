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
