// `wsd check --effects` on a hand-made scene: a CSG is an effect named by its operation and place.
#include "app/effects_report.h"

#include <catch2/catch.hpp>
#include <sstream>

#include "lang/load.h"
#include "lang/source.h"

TEST_CASE("check --effects lists CSG with the solids that call for it", "[cli][check]") {
    using namespace wsd;
    lang::SourceManager sources;
    const uint32_t file = sources.add("s.wsd", "sphere {}\ndifference { box {} sphere {} }\n");
    lang::LoadedScene scene;
    scene.spec.materials.emplace_back();
    render::ShapeSpec ball;
    scene.spec.shapes.push_back(ball);
    auto c = std::make_shared<render::CsgSpec>();
    c->op = render::CsgOp::Difference;
    render::ShapeSpec cube;
    cube.kind = render::ShapeKind::Box;
    c->members = {cube, ball};
    render::ShapeSpec solid;
    solid.kind = render::ShapeKind::Csg;
    solid.csg = c;
    scene.spec.shapes.push_back(solid);
    scene.shape_spans = {lang::Span{file, 0, 6}, lang::Span{file, 10, 20}};
    std::ostringstream out;
    app::print_effects(scene, sources, out);
    CHECK(out.str().find("    CSG: difference at s.wsd:2:1\n") != std::string::npos);

    scene.spec.shapes.pop_back();
    std::ostringstream none;
    app::print_effects(scene, sources, none);
    CHECK(none.str().find("CSG") == std::string::npos);
}

TEST_CASE("check --effects names caustics' focusing and receiving objects, or why none are shot",
          "[cli][check]") {
    using namespace wsd;
    lang::SourceManager sources;
    const uint32_t file = sources.add("c.wsd", "sphere {}\nplane {}\n");
    lang::LoadedScene scene;
    render::MaterialSpec glass;
    glass.transmission = 1;
    glass.diffuse = 0;
    scene.spec.materials = {glass, render::MaterialSpec{}};
    render::ShapeSpec ball;
    ball.material = 0;
    render::ShapeSpec floor;
    floor.kind = render::ShapeKind::Plane;
    floor.material = 1;
    scene.spec.shapes = {ball, floor};
    scene.shape_spans = {lang::Span{file, 0, 6}, lang::Span{file, 10, 15}};
    render::LightSpec light;
    light.position = {0, 5, 0};
    scene.spec.lights.push_back(light);
    scene.spec.settings.caustic_photons = 1000;
    std::ostringstream out;
    app::print_effects(scene, sources, out);
    CHECK(out.str().find("    caustics: focused by sphere at c.wsd:1:1; received by plane at c.wsd:2:1\n") !=
          std::string::npos);

    scene.spec.materials[0] = render::MaterialSpec{};  // nothing focuses light now
    std::ostringstream none;
    app::print_effects(scene, sources, none);
    CHECK(none.str().find("    caustics: none shot (no object can focus light)\n") != std::string::npos);

    scene.spec.settings.caustic_photons = 0;
    std::ostringstream off;
    app::print_effects(scene, sources, off);
    CHECK(off.str().find("caustics") == std::string::npos);
}
