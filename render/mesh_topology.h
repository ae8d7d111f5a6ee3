// Whether a triangle mesh bounds a solid: what CSG needs of a mesh member.
#pragma once

#include <optional>
#include <string>

#include "render/scene_spec.h"

namespace wsd::render {

// nullopt when the mesh is closed: every edge is shared by exactly two faces that use it in
// opposite directions (a consistent orientation). Vertices at the same position count as one, so
// meshes split at uv or normal seams pass. Otherwise a message naming the first wrong edge and
// face, e.g. "edge from vertex 3 to vertex 7 of face 12 (cube.obj line 30) belongs to no other
// face: the mesh is not closed".
std::optional<std::string> closed_mesh_problem(const MeshData& mesh);

}  // namespace wsd::render
