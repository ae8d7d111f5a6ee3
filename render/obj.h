// Wavefront OBJ reading: v, vt, vn, f (polygons fan-triangulated; negative indices; v, v/vt,
// v/vt/vn and v//vn forms). Comments and unused statements (usemtl, mtllib, o, g, s) are skipped
// with one note per file; so are zero-area triangles (a UV sphere's pole quads repeat a vertex),
// with one note that counts them, unless no triangle is left.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "render/limits.h"
#include "render/mesh_file.h"
#include "render/scene_spec.h"

namespace wsd::render {

// The language's limit on a mesh's triangle count (wsd-language.md §5: 2^24 primitives).
inline constexpr size_t kMaxObjTriangles = kMaxPrimitives;

// load_obj reads the whole file (regular files only) and parses it; `path` names it in messages.
// Indices may refer forward (checked once the file is read). MeshData has one uv and normal per
// vertex, so corners sharing a `v` with different `vt`/`vn` become separate vertices. In a file
// where only some faces have vt (or vn), the others get the uv a mesh without uvs would use (their
// barycentrics) and flat normals; a single face mixing corners with and without them is an error.
MeshFileResult load_obj(const std::string& path);
MeshFileResult parse_obj(const std::string& name, std::string_view text);

}  // namespace wsd::render
