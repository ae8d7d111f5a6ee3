// Every texture and every bump kind on cylinders (closed and open), cones (to an apex, and open),
// tori (ring and spindle), discs with a hole and a CSG of them, lit by spot lights (one with a
// hard edge), written in `.wsd` and rendered by the real `wsd` — as written and as instances of
// groups under rotation and scale: no sample may be non-finite.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>

#include "app_test_util.h"
#include "pfm_probe.h"

using namespace wsd::test;

namespace {

std::string textured_scene(bool instanced) {
    const std::vector<std::string> textures = {"image \"earth.png\"",
                                               "checker { scale 0.2 }",
                                               "perlin { kind noise scale 4 }",
                                               "perlin { kind turbulence scale 3 }",
                                               "perlin { kind marble scale 2 }",
                                               "perlin { kind wood scale 2 }"};
    const std::vector<std::string> bumps = {"noise", "turbulence", "marble", "wood"};
    const std::vector<std::string> shapes = {
        "cylinder { base <0, 0, 0>  cap <0, 1, 0>  radius 0.4",
        "cylinder { base <0, 0, 0>  cap <0.3, 1, 0.2>  radius 0.4  open on",
        "cone { base <0, 0, 0>  base_radius 0.5  cap <0, 1, 0>  cap_radius 0",
        "cone { base <0, 0, 0>  base_radius 0.1  cap <0, 1, 0>  cap_radius 0.5  open on",
        "torus { major 0.5  minor 0.2  rotate <60, 0, 0>  translate <0, 0.5, 0>",
        "torus { major 0.3  minor 0.4  rotate <30, 0, 0>  translate <0, 0.5, 0>",
        "disc { center <0, 0.5, 0>  normal <0.2, 0.5, -1>  radius 0.5  hole 0.15",
        "difference { cylinder { base <0, 0, 0>  cap <0, 1, 0>  radius 0.45 }  "
        "torus { major 0.45  minor 0.2  translate <0, 0.5, 0> }"};
    std::string s =
        "settings { width 64  height 48  supersamples 1 }\n"
        "camera { position <3.5, 4.5, -3.5>  look_at <3.5, 0.3, 2.5>  fov 70 }\n"
        "light spot { position <3.5, 8, -4>  look_at <3.5, 0, 2>  angle 25  falloff 40 }\n"
        "light spot { position <0, 5, -3>  look_at <0, 0, 0>  angle 20  falloff 20  color <1, 0.8, 0.6> }\n"
        "plane { normal <0, 1, 0>  distance 0  material { color <0.7, 0.7, 0.7> } }\n";
    for (size_t j = 0; j < textures.size(); ++j)
        for (size_t i = 0; i < shapes.size(); ++i) {
            std::string material = "material { texture " + textures[j] + "  specular 0.3";
            if ((i + j) % 2 == 0)
                material += "  bump perlin { kind " + bumps[(i + j) % 4] + "  scale 6 }  bump_strength " +
                            std::to_string(0.2 + 0.3 * double((i * j) % 3));
            material += " }";
            const std::string place = "translate <" + std::to_string(i) + ", 0, " + std::to_string(j) + ">";
            std::string name = "g";
            name += std::to_string(i);
            name += "_";
            name += std::to_string(j);
            if (instanced)
                s += "let " + name + " = group { " + shapes[i] + "  " + material + " }  " + place +
                     " }\nobject " + name + " { rotate <0, 17, 0>  scale 0.9 }\n";
            else
                s += shapes[i] + "  " + material + "  " + place + " }\n";
        }
    return s;
}

}  // namespace

TEST_CASE("every texture and bump on the new primitives under spot lights renders finite",
          "[e2e][textures]") {
    TempDir dir;
    fs::copy_file(fs::path(WSD_SOURCE_DIR) / "examples/textures/earth.png", dir.path() / "earth.png");
    for (const bool instanced : {false, true}) {
        INFO((instanced ? "instanced" : "as written"));
        write_file(dir / "s.wsd", textured_scene(instanced));
        const RunResult check = run_wsd(dir, "check s.wsd");
        CHECK(check.status == 0);
        CHECK_THAT(check.out,
                   Catch::Contains(": ok \xE2\x80\x94 49 objects, 0 triangles, 2 lights, 49 materials"));
        const RunResult r = run_wsd(dir, "render s.wsd -o s.pfm --quiet --stats-json s.json");
        INFO(r.err);
        REQUIRE(r.status == 0);
        CHECK(read_file(dir / "s.json").find("\"nonfinite_samples\": 0,") != std::string::npos);
        const PfmImage img = parse_pfm(read_file(dir / "s.pfm"));
        REQUIRE(img.width == 64);
        // Not a blank image: the textured shapes vary the colour from pixel to pixel.
        PfmImage shifted = img;
        std::rotate(shifted.rgb.begin(), shifted.rgb.begin() + 3, shifted.rgb.end());
        CHECK(pixels_differing(img, shifted, 1e-2f) > 64 * 48 / 4);
    }
}
