// Lowering: blocks (settings, camera, lights, objects, materials, textures) → render::SceneSpec
// elements, each checked against its property table (generated from the render element tables of
// render/params.h), and the SceneBuilder that assembles them with a span table, so that errors
// found later by render::build_scene map back to the element, the value or the face they concern.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "lang/ast.h"
#include "lang/diagnostics.h"
#include "lang/load.h"
#include "lang/properties.h"
#include "lang/value.h"
#include "render/scene_spec.h"

namespace wsd::lang {

// Where each face of an inline mesh was written, to report SpecError::face at that face.
struct FaceSpans {
    uint32_t file = 0;
    std::vector<uint32_t> offsets;  // packed faces: byte offset of each face's '<'
    std::vector<Span> spans;        // faces given as a general list
};

// What a spec element's `tag` points at (one per element: kept small).
struct SpanRecord {
    Span span;                               // the element's keyword, or an image's/OBJ file's path string
    IncludeChain chain;                      // the includes that led to the file of `span`
    std::shared_ptr<const FaceSpans> faces;  // inline meshes
    // The values written in the element: LoweredScene::field_spans[fields_begin, fields_end).
    uint32_t fields_begin = 0, fields_end = 0;
};

// A lowered settings, camera or light block: the spec element and where its values were written.
template <class Spec>
struct Lowered {
    Spec spec;
    std::vector<FieldSpan> fields;
};

using ObjCache = std::map<std::string, std::shared_ptr<const render::MeshData>>;

struct BlockContext {
    const SourceManager& sources;
    Diagnostics& diags;
    EvalFn eval;
    IncludeChain chain;
    // The material of an object that names none: nullptr when no `default_material` is in
    // scope, std::nullopt when one is but cannot be used (already reported).
    std::function<std::optional<MaterialPtr>(Span keyword)> default_material;
    ObjCache* obj_cache = nullptr;
};

struct LoweredObject {
    render::ShapeSpec shape;
    MaterialPtr material;
    size_t primitives = 1;  // 1, or a mesh's triangles
    bool is_triangle = false;
    SpanRecord record;
    std::vector<FieldSpan> fields;
};

std::optional<Lowered<render::Settings>> lower_settings(const ObjectStmt& stmt, BlockContext& ctx);
std::optional<Lowered<render::CameraSpec>> lower_camera(const ObjectStmt& stmt, BlockContext& ctx);
std::optional<Lowered<render::LightSpec>> lower_light(const ObjectStmt& stmt, BlockContext& ctx);
std::optional<LoweredObject> lower_object(const ObjectStmt& stmt, BlockContext& ctx);
// ExprKind::Material / Image, Checker, Perlin; null after reporting an error.
MaterialPtr lower_material(const BlockExpr& expr, BlockContext& ctx);
TexturePtr lower_texture(const Expr& expr, BlockContext& ctx);

// Mesh geometry from `file` or `vertices`/`faces`/`uvs`/`normals` (lower_mesh.cpp).
bool lower_mesh(BlockReader& reader, BlockContext& ctx, LoweredObject& object);

// Transforms in the order written, composed for column vectors: the last one written is leftmost.
render::Mat4 compose_transforms(const std::vector<Transform>& transforms);
// Rx, then Ry, then Rz (degrees), with exact values at multiples of 90°.
render::Mat4 rotation_matrix(glm::dvec3 degrees);

// `path` relative to the directory of the file that names it (absolute paths unchanged).
std::string resolve_path(const SourceManager& sources, uint32_t file, const std::string& path);
// The identity of a file for "read once" and include cycles: absolute, symlinks resolved.
std::string canonical_path(const std::string& path);

// The property tables, by block: "settings", "camera", "light point", "light area", "sphere",
// "box", "triangle", "plane", "mesh", "material", "checker", "perlin"; each generated from the
// render element table of the same name.
const BlockTable& block_table(std::string_view what);

struct LoweredScene {
    render::SceneSpec spec;
    std::vector<SpanRecord> spans;       // indexed by every tag; spans[0] is the main file's start
    std::vector<FieldSpan> field_spans;  // SpanRecord::fields_begin/end index this
    uint32_t settings_tag = 0;
    bool has_camera = false;
    CheckSummary summary;
};

// Collects lowered elements as statements run, deduplicating materials by identity.
class SceneBuilder {
public:
    explicit SceneBuilder(uint32_t main_file = 0);

    // The interpreter rejects a second settings or camera before lowering it.
    void set_settings(const Lowered<render::Settings>& settings, Span keyword, IncludeChain chain);
    void set_camera(const Lowered<render::CameraSpec>& camera, Span keyword, IncludeChain chain);
    void add_light(const Lowered<render::LightSpec>& light, Span keyword, IncludeChain chain);
    void add_object(LoweredObject&& object, IncludeChain chain);
    size_t primitives() const { return primitives_; }
    const render::SceneSpec& spec() const { return scene_.spec; }
    LoweredScene finish();

private:
    uint32_t record(SpanRecord r, const std::vector<FieldSpan>& fields = {});
    uint32_t material_index(const MaterialPtr& material);
    uint32_t texture_tag(const TexturePtr& texture);

    LoweredScene scene_;
    std::unordered_map<const MaterialValue*, uint32_t> material_ids_;
    std::vector<MaterialPtr> materials_;  // keeps every used material alive: identities stay unique
    size_t primitives_ = 0;
};

// Each SpecError from render::build_scene as an error at the value of the field it concerns when
// that was written, else at a mesh face's own span when known, else at its element's span; with
// the include-chain notes of the file it is in.
void report_spec_errors(const std::vector<render::SpecError>& errors, const LoweredScene& scene,
                        const SourceManager& sources, Diagnostics& diags);

}  // namespace wsd::lang
