// Mesh lowering: `file "x.obj"` or `"x.ply"` through render::load_mesh_file (each file read once per scene),
// or inline `vertices`/`faces`/`uvs`/`normals`. Packed lists are converted straight from the parser's
// storage; a bad face is reported at its own literal, naming the face.
#include <cfloat>
#include <cmath>

#include "lang/lower.h"
#include "render/mesh_file.h"

namespace wsd::lang {

namespace {

bool fits_float(double x) {
    return std::fabs(x) <= render::kMaxSingle;
}

std::string vertex_count_text(size_t n) {
    return std::to_string(n) + (n == 1 ? " vertex" : " vertices");
}

std::string element_count_text(size_t n) {
    return std::to_string(n) + (n == 1 ? " element" : " elements");
}

std::string too_many_faces(size_t n) {
    return std::to_string(n) + " faces, more than the limit of " + std::to_string(render::kMaxPrimitives) +
           " primitives";
}

// A list of vector3 as floats (vertices or normals); false after reporting the first bad element.
bool read_vec3_list(BlockReader& r, BlockContext& ctx, const ListValue& list, const char* noun,
                    std::vector<glm::vec3>& out) {
    out.reserve(list.size());
    const bool packed = list.packed && list.packed->dims == 3;
    for (size_t i = 0; i < list.size(); ++i) {
        glm::dvec3 v;
        if (packed) {
            const double* p = list.packed->values.data() + 3 * i;
            v = {p[0], p[1], p[2]};
        } else {
            const Value e = list.at(i, ctx.sources);  // a packed list of vector2 lands here too
            if (!e.is(ValueType::Vector3)) {
                r.fail(e.span(), std::string(noun) + " " + std::to_string(i) + " must be a vector3, found " +
                                     type_name(e.type()));
                return false;
            }
            v = e.vec3();
        }
        if (!fits_float(v.x) || !fits_float(v.y) || !fits_float(v.z)) {
            r.fail(list.span_of(i, ctx.sources),
                   std::string(noun) + " " + std::to_string(i) + " is too large for single precision");
            return false;
        }
        out.emplace_back(v);
    }
    return true;
}

bool read_faces(BlockReader& r, BlockContext& ctx, const ListValue& list, size_t vertex_count,
                render::MeshData& mesh, FaceSpans& record) {
    mesh.faces.reserve(list.size());
    const bool packed = list.packed && list.packed->dims == 3;
    if (!packed) record.spans.reserve(list.size());
    for (size_t i = 0; i < list.size(); ++i) {
        glm::dvec3 f;
        if (packed) {
            const double* p = list.packed->values.data() + 3 * i;
            f = {p[0], p[1], p[2]};
        } else {
            const Value e = list.at(i, ctx.sources);  // a packed list of vector2 lands here too
            if (!e.is(ValueType::Vector3)) {
                r.fail(e.span(), "face " + std::to_string(i) +
                                     " must be a vector3 of vertex indices, found " + type_name(e.type()));
                return false;
            }
            f = e.vec3();
            record.spans.push_back(e.span());
        }
        for (int k = 0; k < 3; ++k) {
            double x = f[k];
            std::string problem;
            if (x != std::floor(x))
                problem = "index " + format_number(x) + " is not an integer";
            else if (x < 0 || x >= static_cast<double>(vertex_count))
                problem = "index " + format_number(x) + " is out of range (the mesh has " +
                          vertex_count_text(vertex_count) + ")";
            if (!problem.empty()) {
                r.fail(list.span_of(i, ctx.sources), "face " + std::to_string(i) + ": " + problem);
                return false;
            }
        }
        mesh.faces.emplace_back(static_cast<uint32_t>(f.x), static_cast<uint32_t>(f.y),
                                static_cast<uint32_t>(f.z));
    }
    if (packed) {
        record.file = list.packed->file;
        record.offsets = list.packed->offsets;
    }
    return true;
}

bool check_per_vertex(BlockReader& r, const char* name, size_t n, size_t vertex_count) {
    if (n == vertex_count) return true;
    r.fail(r.value_span(name), std::string(1, '\'').append(name) + "' has " + element_count_text(n) +
                                   ", but the mesh has " + vertex_count_text(vertex_count) +
                                   " (one per vertex)");
    return false;
}

bool lower_inline(BlockReader& r, BlockContext& ctx, LoweredObject& o) {
    const ListValue& vertices = r.value("vertices")->list();
    const ListValue& faces = r.value("faces")->list();
    if (vertices.size() == 0) {
        r.fail(r.value_span("vertices"), "'vertices' is empty");
        return false;
    }
    if (faces.size() == 0) {
        r.fail(r.value_span("faces"), "'faces' is empty");
        return false;
    }
    if (faces.size() > render::kMaxPrimitives) {
        r.fail(r.value_span("faces"), "mesh has " + too_many_faces(faces.size()));
        return false;
    }
    auto mesh = std::make_shared<render::MeshData>();
    mesh->source_name = ctx.sources.file(r.keyword().file).path;
    if (!read_vec3_list(r, ctx, vertices, "vertex", mesh->vertices)) return false;
    const size_t nv = mesh->vertices.size();
    auto face_spans = std::make_shared<FaceSpans>();
    if (!read_faces(r, ctx, faces, nv, *mesh, *face_spans)) return false;
    o.record.faces = std::move(face_spans);
    if (const Value* uvs_value = r.value("uvs")) {
        const ListValue& uvs = uvs_value->list();
        if (!check_per_vertex(r, "uvs", uvs.size(), nv)) return false;
        mesh->uvs.reserve(nv);
        for (size_t i = 0; i < uvs.size(); ++i) {
            Value e = uvs.at(i, ctx.sources);
            if (!e.is(ValueType::Vector2)) {
                r.fail(e.span(),
                       "uv " + std::to_string(i) + " must be a vector2, found " + type_name(e.type()));
                return false;
            }
            if (!fits_float(e.vec2().x) || !fits_float(e.vec2().y)) {
                r.fail(e.span(), "uv " + std::to_string(i) + " is too large for single precision");
                return false;
            }
            mesh->uvs.emplace_back(e.vec2());
        }
    }
    if (const Value* normals_value = r.value("normals")) {
        const ListValue& normals = normals_value->list();
        if (!check_per_vertex(r, "normals", normals.size(), nv)) return false;
        if (!read_vec3_list(r, ctx, normals, "normal", mesh->normals)) return false;
        for (size_t i = 0; i < nv; ++i) {
            if (mesh->normals[i] == glm::vec3(0.0f)) {
                r.fail(normals.span_of(i, ctx.sources),
                       "normal " + std::to_string(i) + " is the zero vector");
                return false;
            }
        }
    }
    o.primitives = mesh->faces.size();
    o.shape.mesh = std::move(mesh);
    return true;
}

bool lower_file(BlockReader& r, BlockContext& ctx, LoweredObject& o) {
    const Value* name = r.value("file");
    if (!name) return false;
    Span at = r.value_span("file");
    if (name->string().empty()) {
        r.fail(at, "mesh 'file' name is empty");
        return false;
    }
    std::string path = resolve_path(ctx.sources, at.file, name->string());
    if (ctx.mesh_files) ctx.mesh_files->push_back(path);
    const std::string key = canonical_path(path);
    std::shared_ptr<const render::MeshData> mesh;
    if (ctx.obj_cache) {
        auto it = ctx.obj_cache->find(key);
        if (it != ctx.obj_cache->end()) mesh = it->second;
    }
    if (!mesh) {
        render::MeshFileResult result = render::load_mesh_file(path);
        for (const std::string& note : result.notes) ctx.diags.warning(at, note);
        if (!result.mesh) {
            r.fail(at, result.error.empty() ? "cannot read mesh file '" + path + "'" : result.error);
            return false;
        }
        mesh = std::move(result.mesh);
        if (ctx.obj_cache) (*ctx.obj_cache)[key] = mesh;
    }
    if (mesh->faces.empty()) {
        r.fail(at, "mesh file '" + path + "' has no faces");
        return false;
    }
    if (mesh->faces.size() > render::kMaxPrimitives) {
        r.fail(at, "mesh file '" + path + "' has " + too_many_faces(mesh->faces.size()));
        return false;
    }
    o.record.span = at;
    o.primitives = mesh->faces.size();
    o.shape.mesh = std::move(mesh);
    return true;
}

}  // namespace

bool lower_mesh(BlockReader& r, BlockContext& ctx, LoweredObject& o) {
    o.shape.kind = render::ShapeKind::Mesh;
    if (r.has("file")) {
        for (const char* other : {"vertices", "faces", "uvs", "normals"})
            if (r.has(other))
                r.fail(r.name_span(other),
                       std::string(1, '\'').append(other) + "' cannot be combined with 'file' in mesh");
        if (!r.ok()) return false;
        return lower_file(r, ctx, o);
    }
    if (!r.has("vertices") && !r.has("faces")) {
        if (r.suggested("file") || r.suggested("vertices") || r.suggested("faces")) {
            r.failed();  // a misspelt name already reported
            return false;
        }
        r.fail(r.keyword(), "missing property 'file' (or 'vertices' and 'faces') in mesh");
        return false;
    }
    r.require("vertices");
    r.require("faces");
    if (!r.ok()) return false;
    return lower_inline(r, ctx, o);
}

}  // namespace wsd::lang
