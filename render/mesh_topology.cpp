// Closed-mesh check (mesh_topology.h): directed edges keyed by welded vertex ids, sorted once.
#include "render/mesh_topology.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <tuple>
#include <vector>

#include "render/mesh_file.h"

namespace wsd::render {

namespace {

struct Edge {
    uint32_t a, b;  // welded ids, a < b
    uint32_t face;
    uint32_t from, to;  // the face's own vertex indices, in its direction
    bool forward;       // the face runs a → b
};

}  // namespace

std::optional<std::string> closed_mesh_problem(const MeshData& m) {
    if (m.faces.empty()) return "the mesh has no faces, so it encloses no volume";
    const size_t nv = m.vertices.size();
    // Weld: vertices at the same position are one vertex; adding +0 makes -0 and +0 one key, since
    // an OBJ writer's seam often prints the same point once as 0 and once as -0.
    std::map<std::tuple<uint32_t, uint32_t, uint32_t>, uint32_t> ids;
    std::vector<uint32_t> weld(nv);
    for (size_t i = 0; i < nv; ++i) {
        const glm::vec3 p = m.vertices[i] + glm::vec3(0.0f);
        uint32_t bits[3];
        std::memcpy(bits, &p, sizeof bits);
        weld[i] = ids.emplace(std::make_tuple(bits[0], bits[1], bits[2]), uint32_t(ids.size())).first->second;
    }
    std::vector<Edge> edges;
    edges.reserve(3 * m.faces.size());
    for (size_t f = 0; f < m.faces.size(); ++f) {
        const uint32_t v[3] = {m.faces[f].x, m.faces[f].y, m.faces[f].z};
        for (int k = 0; k < 3; ++k) {
            if (v[k] >= nv)
                return face_name(m, f) + " uses vertex " + std::to_string(v[k]) +
                       ", out of range (the mesh has " + std::to_string(nv) + " vertices)";
        }
        for (int k = 0; k < 3; ++k) {
            const uint32_t from = v[k], to = v[(k + 1) % 3];
            const uint32_t a = weld[from], b = weld[to];
            if (a == b) return face_name(m, f) + " has two corners at the same position";
            edges.push_back({std::min(a, b), std::max(a, b), uint32_t(f), from, to, a < b});
        }
    }
    std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
        return std::tie(x.a, x.b, x.face) < std::tie(y.a, y.b, y.face);
    });
    auto name = [&](const Edge& e) {
        return "edge from vertex " + std::to_string(e.from) + " to vertex " + std::to_string(e.to) + " of " +
               face_name(m, e.face);
    };
    for (size_t i = 0; i < edges.size();) {
        size_t j = i;
        while (j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b) ++j;
        const size_t n = j - i;
        if (n == 1) return name(edges[i]) + " belongs to no other face: the mesh is not closed";
        if (n > 2)
            return name(edges[i]) + " is shared by " + std::to_string(n) +
                   " faces (a closed surface shares each edge between two)";
        if (edges[i].forward == edges[i + 1].forward)
            return name(edges[i + 1]) + " runs the same way in " + face_name(m, edges[i].face) +
                   ": the faces are not consistently oriented";
        i = j;
    }
    return std::nullopt;
}

}  // namespace wsd::render
