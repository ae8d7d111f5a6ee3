// Mesh files: what reading one gives (a mesh, or an error, and notes), the reader chosen by the
// file's first bytes (PLY files start with "ply"; anything else but a `.ply` is read as OBJ), and
// the name a face goes by in messages.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "render/scene_spec.h"

namespace wsd::render {

struct MeshFileResult {
    std::shared_ptr<MeshData> mesh;  // null on error
    std::string error;               // "FILE:LINE: message" (or "FILE: ..." where there is no line) on error
    // Warnings about what was skipped (unused statements or properties, zero-area triangles).
    std::vector<std::string> notes;
};

// Reads `path` whole and parses it as PLY (when it starts with "ply") or OBJ; a file named
// `.ply` that does not start with "ply" is an error.
MeshFileResult load_mesh_file(const std::string& path);

// "face 12 (models/bunny.obj line 40)": face `face` of `m` with where it came from, for messages.
std::string face_name(const MeshData& m, size_t face);

}  // namespace wsd::render
