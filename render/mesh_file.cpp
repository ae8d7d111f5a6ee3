#include "render/mesh_file.h"

#include "render/file_util.h"
#include "render/obj.h"
#include "render/ply.h"

namespace wsd::render {

MeshFileResult load_mesh_file(const std::string& path) {
    FileBytes file;
    std::string reason;
    if (!read_whole_file(path, file, reason)) {
        MeshFileResult result;
        result.error = "cannot read mesh file '" + path + "': " + reason;
        return result;
    }
    if (looks_like_ply(file.view())) return parse_ply(path, file.view());
    // A file named .ply is not read as OBJ: its OBJ diagnostics would only mislead.
    if (extension_lower(path) == ".ply") {
        MeshFileResult result;
        result.error = path + ":1: not a PLY file: its first line is not 'ply'";
        return result;
    }
    return parse_obj(path, file.view());
}

std::string face_name(const MeshData& m, size_t face) {
    std::string s = "face " + std::to_string(face);
    if (face < m.face_lines.size()) {
        if (!m.source_name.empty())
            s += " (" + m.source_name + " " + m.face_origin + " " + std::to_string(m.face_lines[face]) + ")";
        else
            s += " (element " + std::to_string(m.face_lines[face]) + ")";
    }
    return s;
}

}  // namespace wsd::render
