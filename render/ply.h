// PLY (Stanford polygon file) reading, the format scanned models come in: ASCII and binary in
// either byte order. The `vertex` element gives positions (x y z), and optionally normals
// (nx ny nz) and texture coordinates (u v, s t, texture_u texture_v or texture_s texture_t); the
// `face` element's list property `vertex_indices` (or `vertex_index`) gives polygons of any vertex
// count, fanned into triangles. Other elements and properties (colours, confidence, edges, …)
// are skipped with one note per file; so are zero-area triangles, as in OBJ files.
#pragma once

#include <string>
#include <string_view>

#include "render/mesh_file.h"

namespace wsd::render {

// True when `bytes` starts like a PLY file ("ply", optional blanks and a line end).
bool looks_like_ply(std::string_view bytes);

// Parses a whole PLY file; `name` names it in messages ("FILE:LINE: …" for the header and ASCII
// bodies, "FILE: vertex 12: …" or "FILE: face 7: …" in binary bodies).
MeshFileResult parse_ply(const std::string& name, std::string_view bytes);

}  // namespace wsd::render
