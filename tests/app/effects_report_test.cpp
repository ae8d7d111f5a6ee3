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
