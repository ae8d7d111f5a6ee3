// The Cornell box's geometry as examples/cornell.wsd builds it (camera at <0, 0, -550> looking
// down +z, fov 60; area light at <25, 500, 625>): five walls of two triangles each, six spheres
// and the dice, a box turned onto a corner: 17 shapes. Material 1 is the glass sphere's
// (transmissive); every other shape uses material 0.
#pragma once

#include <glm/gtc/matrix_transform.hpp>

#include "render/math.h"
#include "render/scene_spec.h"

namespace wsd::bench {

inline render::SceneSpec cornell_geometry() {
    using namespace wsd::render;
    SceneSpec spec;
    spec.materials.resize(2);
    spec.materials[1].transmission = 1;
    auto sphere = [&](Vec3 c, double r, uint32_t mat) {
        ShapeSpec s;
        s.kind = ShapeKind::Sphere;
        s.center = c;
        s.radius = r;
        s.material = mat;
        spec.shapes.push_back(s);
    };
    sphere({200, 0, 880}, 200, 0);
    sphere({-300, 200, 800}, 100, 0);
    sphere({-80, -180, 130}, 70, 1);
    sphere({500, -500, 550}, 100, 0);
    sphere({350, -550, 550}, 50, 0);
    sphere({-350, -500, 600}, 100, 0);
    auto quad = [&](Vec3 ll, Vec3 u, Vec3 v) {
        ShapeSpec s;
        s.kind = ShapeKind::Triangle;
        s.v[0] = ll, s.v[1] = ll + u, s.v[2] = ll + u + v;
        spec.shapes.push_back(s);
        s.v[0] = ll, s.v[1] = ll + u + v, s.v[2] = ll + v;
        spec.shapes.push_back(s);
    };
    quad({-600, -600, 0}, {1200, 0, 0}, {0, 0, 1200});
    quad({-600, -600, 0}, {0, 0, 1200}, {0, 1200, 0});
    quad({600, -600, 1200}, {0, 0, -1200}, {0, 1200, 0});
    quad({-600, -600, 1200}, {1200, 0, 0}, {0, 1200, 0});
    quad({-600, 600, 1200}, {1200, 0, 0}, {0, 0, -1200});
    ShapeSpec box;
    box.kind = ShapeKind::Box;
    box.box_min = Vec3(-125);
    box.box_max = Vec3(125);
    Mat4 m(1.0);
    m = glm::translate(Mat4(1.0), Vec3(-400, -350, 990)) *
        glm::rotate(Mat4(1.0), 35.264 * kPi / 180, Vec3(1, 0, 0)) *
        glm::rotate(Mat4(1.0), 45 * kPi / 180, Vec3(0, 0, 1));
    box.object_to_world = m;
    spec.shapes.push_back(box);
    return spec;
}

}  // namespace wsd::bench
