// CSG from `.wsd` text through the real `wsd`: a glass union with no inner surfaces renders as the
// one sphere it equals, byte for byte; cut surfaces show the subtracting member's material (its
// own, else the CSG's); a plane member is a half-space; a closed mesh member (split at uv seams)
// agrees with the analytic shape; members that are not solids are refused with the reason.
#include <array>
#include <catch2/catch.hpp>
#include <filesystem>

#include "app_test_util.h"
#include "pfm_probe.h"

using namespace wsd::test;

namespace {

const char* const kHead =
    "settings { width 48  height 48  supersamples 1  max_depth 8 }\n"
    "camera { position <0, 2, -5>  look_at <0, 0.5, 0> }\n"
    "light point { position <3, 8, -5> }\n"
    "plane { normal <0, 1, 0>  distance -1  material { texture checker { scale 0.5 } } }\n"
    "let red = material { color <0.9, 0.2, 0.2> }\n"
    "let green = material { color <0.2, 0.9, 0.2> }\n"
    "let blue = material { color <0.2, 0.2, 0.9> }\n"
    "let steel = material { color <0.6, 0.6, 0.6>  specular 0.8  reflection 0.3 }\n"
    "let glass = material { color <1, 1, 1>  transmission 1  ior 1.5  absorption <0.2, 0.4, 0.1> }\n";

// Renders the scene (kHead + `scene`) to NAME.pfm; the render must succeed without a non-finite
// sample.
PfmImage render(const TempDir& dir, const std::string& name, const std::string& scene) {
    write_file(dir / (name + ".wsd"), kHead + scene);
    const RunResult r =
        run_wsd(dir, "render " + name + ".wsd -o " + name + ".pfm --quiet --stats-json " + name + ".json");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(read_file(dir / (name + ".json")).find("\"nonfinite_samples\": 0,") != std::string::npos);
    return parse_pfm(read_file(dir / (name + ".pfm")));
}

// Pixels where channel `c` is more than twice each other channel (and not black).
int dominated_by(const PfmImage& img, int c) {
    int n = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const float* p = img.at(x, y);
            if (p[c] > 0.05f && p[c] > 2 * p[(c + 1) % 3] && p[c] > 2 * p[(c + 2) % 3]) ++n;
        }
    return n;
}

}  // namespace

TEST_CASE("a glass CSG without inner surfaces renders as the one sphere it equals", "[csg][e2e]") {
    TempDir dir;
    const PfmImage one = render(dir, "one", "sphere { center <0, 0.5, 0>  radius 1  material glass }\n");
    REQUIRE(one.width == 48);
    const std::string ball = "sphere { center <0, 0.5, 0>  radius 1 }";
    const std::vector<std::pair<std::string, std::string>> equal = {
        {"coincident", "union { " + ball + "  " + ball + "  material glass }"},
        {"contained", "union { " + ball + "  sphere { center <0.2, 0.5, 0>  radius 0.5 }  material glass }"},
        {"one_member", "union { " + ball + "  material glass }"},
        {"difference_of_one", "difference { " + ball + "  material glass }"},
        {"intersection_with_a_larger_box",
         "intersection { " + ball + "  box { min <-2, -2, -2>  max <2, 2, 2> }  material glass }"},
        {"nested", "union { difference { union { " + ball + " } }  material glass }"},
    };
    for (const auto& [name, scene] : equal) {
        INFO(name);
        render(dir, name, scene + "\n");
        CHECK(read_file(dir / (name + ".pfm")) == read_file(dir / "one.pfm"));
    }
    // The statistics count the member spheres that rays meet, not only those they test.
    const std::string stats = read_file(dir / "coincident.json");
    CHECK(stats.find("\"sphere_tests\": 0,") == std::string::npos);
    CHECK(stats.find("\"sphere_hits\": 0,") == std::string::npos);
    // The comparison sees an inner surface: two spheres written apart are not one solid.
    write_file(dir / "two.wsd",
               std::string(kHead) + ("sphere { center <0, 0.5, 0>  radius 1  material glass }\n"
                                     "sphere { center <0.2, 0.5, 0>  radius 0.5  material glass }\n"));
    REQUIRE(run_wsd(dir, "render two.wsd -o two.pfm --quiet").status == 0);
    CHECK(read_file(dir / "two.pfm") != read_file(dir / "one.pfm"));
}

TEST_CASE("a difference's cut surface shows the subtracting member's material", "[csg][e2e]") {
    TempDir dir;
    const std::string box = "box { min <-1, -0.5, -1>  max <1, 1.5, 1>  material red }";
    // The centre pixel looks into a dimple cut by the sphere into the red box's front face.
    const PfmImage csg_material = render(
        dir, "a", "difference { " + box + "  sphere { center <0, 0.5, -1>  radius 0.6 }  material blue }\n");
    const float* centre = csg_material.at(24, 24);
    CHECK(centre[2] > 2 * centre[0]);
    CHECK(dominated_by(csg_material, 0) > 100);  // the box's own faces
    CHECK(dominated_by(csg_material, 2) > 50);   // the dimple
    const PfmImage own_material =
        render(dir, "b",
               "difference { " + box +
                   "  sphere { center <0, 0.5, -1>  radius 0.6  material green }  material blue }\n");
    centre = own_material.at(24, 24);
    CHECK(centre[1] > 2 * centre[0]);
    CHECK(centre[1] > 2 * centre[2]);
    CHECK(dominated_by(own_material, 2) == 0);

    // The reference's example: the sphere's cuts take the CSG's blue, the box keeps its red.
    const PfmImage example =
        render(dir, "example",
               "difference {\n"
               "    box { min <-1, -1, -1>  max <1, 1, 1>  material red }\n"
               "    sphere { center <0, 0, 0>  radius 1.3 }\n"
               "    cylinder { base <0, -2, 0>  cap <0, 2, 0>  radius 0.5  material steel }\n"
               "    material blue\n"
               "    rotate <0, 30, 0>  translate <0, 0.5, 0>\n"
               "}\n");
    CHECK(dominated_by(example, 0) > 100);
    CHECK(dominated_by(example, 2) > 50);
}

TEST_CASE("a plane member is the half-space behind its normal", "[csg][e2e]") {
    TempDir dir;
    const std::string ball = "sphere { center <0, 0.5, 0>  radius 1  material red }";
    const PfmImage by_plane =
        render(dir, "plane",
               "intersection { " + ball +
                   "  plane { normal <0, 1, 0>  distance 0.75  material blue }  rotate <-30, 10, 0> }\n");
    const PfmImage by_box =
        render(dir, "box",
               "difference { " + ball +
                   "  box { min <-3, 0.75, -3>  max <3, 4, 3>  material blue }  rotate <-30, 10, 0> }\n");
    CHECK(dominated_by(by_plane, 2) > 100);  // the flat cut, facing the camera
    CHECK(pixels_differing(by_plane, by_box, 1e-3f) <= 48 * 48 / 100);
}

TEST_CASE("a closed mesh split at uv seams is a CSG member and agrees with the analytic torus",
          "[csg][e2e]") {
    TempDir dir;
    fs::copy_file(fs::path(WSD_SOURCE_DIR) / "examples/models/torus.obj", dir.path() / "torus.obj");
    const std::string box = "box { min <-1.5, -0.2, -1.5>  max <1.5, 0.2, 1.5>  material red }";
    const PfmImage mesh = render(
        dir, "mesh",
        "difference { " + box +
            "  mesh { file \"torus.obj\"  material blue }  rotate <-60, 0, 0>  translate <0, 0.5, 0> }\n");
    const PfmImage torus = render(
        dir, "torus",
        "difference { " + box +
            "  torus { major 1  minor 0.35  material blue }  rotate <-60, 0, 0>  translate <0, 0.5, 0> }\n");
    CHECK(dominated_by(mesh, 2) > 20);  // the groove the torus cuts
    CHECK(pixels_differing(mesh, torus, 1e-2f) <= 48 * 48 * 2 / 100);
}

TEST_CASE("an open or inconsistently oriented mesh in a CSG is refused with the edge at fault",
          "[csg][e2e]") {
    TempDir dir;
    write_file(dir / "open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n");
    write_file(dir / "flipped.obj",
               "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    write_file(dir / "closed.obj",
               "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    for (const char* file : {"open", "flipped", "closed"}) {
        write_file(dir / "s.wsd", std::string(kHead) + "difference { box { min <0, 0, 0>  max <1, 1, 1> }\n" +
                                      "  mesh { file \"" + file + ".obj\" }  material red }\n");
        const RunResult r = run_wsd(dir, "check s.wsd");
        INFO(file << ": " << r.err);
        if (std::string(file) == "closed") {
            CHECK(r.status == 0);
            continue;
        }
        CHECK(r.status == 1);
        CHECK_THAT(r.err,
                   Catch::Contains("s.wsd:11:3: error: 'mesh' is not a solid; CSG needs closed shapes"));
        CHECK_THAT(r.err, Catch::Contains("s.wsd:10:1: note: in this 'difference'"));
        CHECK_THAT(r.err, Catch::Contains(std::string("(") + file + ".obj line 5)"));
        CHECK_THAT(r.err, Catch::Contains(std::string(file) == "open" ? "belongs to no other face"
                                                                      : "not consistently oriented"));
    }
}

TEST_CASE("a CSG's solid does not depend on member order or on how subtracted members are grouped",
          "[csg][e2e]") {
    TempDir dir;
    const std::string a = "sphere { center <-0.4, 0.5, 0>  radius 0.8 }";
    const std::string b = "sphere { center <0.4, 0.6, 0.1>  radius 0.7 }";
    const std::string c = "cylinder { base <0, -2, 0>  cap <0, 2, 0>  radius 0.3 }";
    const std::string d = "box { min <-1, 0, -1>  max <1, 1.2, 1> }";
    const std::vector<std::array<std::string, 2>> same = {
        {"union { " + a + "  " + b + "  material glass }", "union { " + b + "  " + a + "  material glass }"},
        {"intersection { " + a + "  " + b + "  material glass }",
         "intersection { " + b + "  " + a + "  material glass }"},
        {"difference { " + d + "  " + a + "  " + c + "  material glass }",
         "difference { " + d + "  union { " + a + "  " + c + " }  material glass }"},
        {"difference { " + d + "  " + a + "  " + c + "  material red }",
         "difference { " + d + "  union { " + a + "  " + c + " }  material red }"},
    };
    const PfmImage empty = render(dir, "empty", "");
    for (const auto& [first, second] : same) {
        INFO(first);
        const PfmImage one = render(dir, "one", first + "\n");
        render(dir, "two", second + "\n");
        CHECK(pixels_differing(one, empty, 1e-3f) > 30);
        CHECK(read_file(dir / "one.pfm") == read_file(dir / "two.pfm"));
    }
}
