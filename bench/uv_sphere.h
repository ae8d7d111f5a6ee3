// The closed UV sphere the benchmarks render: 2·slices·(stacks − 1) triangles sharing
// 2 + slices·(stacks − 1) vertices, consistently wound (a CSG member may be made of it).
#pragma once

#include <cmath>
#include <memory>

#include "render/scene_spec.h"

namespace wsd::bench {

inline std::shared_ptr<render::MeshData> uv_sphere(int slices, int stacks, float radius) {
    constexpr double kPi = 3.14159265358979323846;
    auto m = std::make_shared<render::MeshData>();
    m->vertices.push_back({0, radius, 0});
    for (int i = 1; i < stacks; ++i) {
        const double theta = kPi * i / stacks;
        for (int j = 0; j < slices; ++j) {
            const double phi = 2 * kPi * j / slices;
            m->vertices.push_back({static_cast<float>(radius * std::sin(theta) * std::cos(phi)),
                                   static_cast<float>(radius * std::cos(theta)),
                                   static_cast<float>(radius * std::sin(theta) * std::sin(phi))});
        }
    }
    m->vertices.push_back({0, -radius, 0});
    auto ring = [slices](int i, int j) { return static_cast<unsigned>(1 + (i - 1) * slices + (j % slices)); };
    const unsigned bottom = static_cast<unsigned>(m->vertices.size() - 1);
    for (int j = 0; j < slices; ++j) m->faces.push_back({0u, ring(1, j + 1), ring(1, j)});
    for (int i = 1; i < stacks - 1; ++i)
        for (int j = 0; j < slices; ++j) {
            m->faces.push_back({ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)});
            m->faces.push_back({ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)});
        }
    for (int j = 0; j < slices; ++j)
        m->faces.push_back({bottom, ring(stacks - 1, j), ring(stacks - 1, j + 1)});
    return m;
}

}  // namespace wsd::bench
