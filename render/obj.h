// Wavefront OBJ reading: v, vt, vn, f (polygons fan-triangulated; negative indices; v, v/vt,
// v/vt/vn and v//vn forms). Comments and unused statements (usemtl, mtllib, o, g, s) are skipped.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "render/scene_spec.h"

namespace wsd::render {

struct ObjResult {
    std::shared_ptr<MeshData> mesh;     // null on error
    std::string error;                  // "FILE:LINE: message" on error
    std::vector<std::string> notes;     // at most one per skipped statement kind, "FILE:LINE: ..."
};

ObjResult load_obj(const std::string& path);
ObjResult parse_obj(const std::string& name, std::string_view text);

}  // namespace wsd::render
