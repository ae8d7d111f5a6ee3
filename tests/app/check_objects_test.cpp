// `wsd check` on scenes with instances: objects and triangles counted as instanced, then what is
// stored. A fragment is checked without building the render scene.
#include <catch2/catch.hpp>

#include "app_test_util.h"

using namespace wsd::test;

TEST_CASE("check counts instances as instanced and says what is stored", "[cli][check]") {
    TempDir dir;
    write_file(dir / "many.wsdi",
               "let red = material { color <1, 0, 0> }\n"
               "let tetra = mesh { vertices [<0, 0, 0>, <1, 0, 0>, <0, 1, 0>, <0, 0, 1>]\n"
               "                   faces [<0, 2, 1>, <0, 1, 3>, <0, 3, 2>, <1, 2, 3>] }\n"
               "let pair = group { object tetra { }  sphere { center <0, 0, 0>  radius 1 } }\n"
               "plane { normal <0, 1, 0>  material red }\n"
               "for i in 0 .. 1000 { object pair { translate <i, 0, 0>  material red } }\n");
    const RunResult r = run_wsd(dir, "check many.wsdi");
    CHECK(r.status == 0);
    CHECK(
        r.out ==
        "many.wsdi: ok \xE2\x80\x94 2001 objects, 4000 triangles, 0 lights, 1 material (stored: 3 shapes, 4 "
        "triangles)\n");
}
