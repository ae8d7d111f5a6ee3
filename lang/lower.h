// Lowering: plain functions from checked evaluated blocks (settings, camera, lights, objects,
// materials, textures; lang/properties.h) to render::SceneSpec elements, with the rules that span
// several properties, and the SceneBuilder that assembles them with a span table, so that errors
// found later by render::build_scene map back to the element, the value or the face they concern.
// Lowering evaluates nothing and knows no interpreter: the interpreter evaluates a block, then
// hands it here.
#pragma once

#include <cstdint>
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

// The `default_material` binding in scope where a block is written: the material of an object
// that names none.
struct DefaultMaterial {
    const std::optional<Value>* value = nullptr;  // null: none in scope; empty: its definition failed
    Span defined_at;
};

// What lowering needs besides the block: where it was written and what is in scope there.
struct BlockContext {
    const SourceManager& sources;
    Diagnostics& diags;
    IncludeChain chain;
    DefaultMaterial default_material = {};
    ObjCache* obj_cache = nullptr;
    std::vector<std::string>* mesh_files = nullptr;  // set: each mesh file's path is added, read or not
    // An object written as a value or in a group or CSG body may take its material from what
    // encloses it: without one of its own it lowers with a null material instead of an error.
    bool material_optional = false;
    // The outermost user-function call running, when there is one: an object that lacks a
    // material names it as what added the object.
    std::optional<Span> call = std::nullopt;
};

struct LoweredObject {
    render::ShapeSpec shape;
    MaterialPtr material;
    size_t primitives = 1;  // 1, or a mesh's triangles
    bool is_triangle = false;
    SpanRecord record;
    std::vector<FieldSpan> fields;
};

// The table a block statement's items are read against; null after reporting an unknown light kind
// (whose block is then not evaluated).
const BlockTable* statement_table(const ObjectStmt& stmt, Diagnostics& diags);
// The table of a `material`, `checker` or `perlin` expression.
const BlockTable& expression_table(ExprKind kind);
// The head of a block expression: from its first token to the end of its '{', so that messages
// underline `material {` rather than the whole block.
Span head_span(const BlockExpr& expr);

// Each takes the block checked against the table statement_table / expression_table gave; each
// returns nothing (or null) after reporting an error.
std::optional<Lowered<render::Settings>> lower_settings(BlockReader& r);
std::optional<Lowered<render::CameraSpec>> lower_camera(BlockReader& r);
std::optional<Lowered<render::LightSpec>> lower_light(BlockReader& r);
std::optional<LoweredObject> lower_object(BlockReader& r, BlockContext& ctx);
MaterialPtr lower_material(BlockReader& r, BlockContext& ctx);

// A material value's render spec, with the textures it names (its own or its base's) and the
// value spans of its own block.
struct LoweredMaterial {
    render::MaterialSpec spec;
    TexturePtr texture, bump;  // what spec.texture / spec.bump were made from
    std::vector<FieldSpan> fields;
};
LoweredMaterial lower_material_spec(const MaterialValue& material);
TexturePtr lower_texture(BlockReader& r, BlockContext& ctx);  // checker, perlin
// `image "file"`: `path` is the evaluated file name, written at `path_span`.
TexturePtr lower_image(const Value& path, Span path_span, BlockContext& ctx);

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

class ObjectLowering;

// Collects lowered elements as statements run, deduplicating materials by identity.
class SceneBuilder {
public:
    explicit SceneBuilder(uint32_t main_file = 0);
    ~SceneBuilder();
    SceneBuilder(const SceneBuilder&) = delete;
    SceneBuilder& operator=(const SceneBuilder&) = delete;

    // The interpreter rejects a second settings or camera before lowering it.
    void set_settings(const Lowered<render::Settings>& settings, Span keyword, IncludeChain chain);
    void set_camera(const Lowered<render::CameraSpec>& camera, Span keyword, IncludeChain chain);
    void add_light(const Lowered<render::LightSpec>& light, Span keyword, IncludeChain chain);
    void add_object(LoweredObject&& object, IncludeChain chain);
    // An object value added at `added_by` (a statement's keyword), with its materials resolved
    // (lang/lower_instances.cpp): a group is flattened into world shapes, `object` of a group or a
    // mesh adds instances of one prototype per distinct value, CSG becomes one solid. A surface with
    // no material at all is an error at its object's keyword, with a note at `added_by`.
    void add_object_value(const ObjectPtr& value, Span added_by, Diagnostics& diags);
    // What add_object_value would add beyond the value's own evaluation, counted without making it:
    // instance shapes and planes copied per instance (each sum saturates at SIZE_MAX).
    struct Expansion {
        size_t instances = 0, copies = 0;
        Expansion& operator+=(const Expansion& o) {
            instances = instances > SIZE_MAX - o.instances ? SIZE_MAX : instances + o.instances;
            copies = copies > SIZE_MAX - o.copies ? SIZE_MAX : copies + o.copies;
            return *this;
        }
    };
    Expansion expansion(const ObjectPtr& value);
    size_t primitives() const { return primitives_; }  // stored primitives (distinct geometry)
    size_t instances() const { return instances_; }
    const render::SceneSpec& spec() const { return scene_.spec; }
    LoweredScene finish();

private:
    uint32_t record(SpanRecord r, const std::vector<FieldSpan>& fields = {});
    uint32_t material_index(const MaterialPtr& material);
    uint32_t texture_tag(const TexturePtr& texture);
    void drop_object_caches();

    LoweredScene scene_;
    std::unordered_map<const MaterialValue*, uint32_t> material_ids_;
    std::vector<MaterialPtr> materials_;  // keeps every used material alive: identities stay unique
    size_t primitives_ = 0;
    size_t instances_ = 0;
    std::unique_ptr<ObjectLowering> objects_;
    friend class ObjectLowering;
};

// An error at `span` reported with the include sites of `chain` as its notes, as if it were
// reported while those includes ran.
void error_in_includes(Diagnostics& diags, const IncludeChain& chain, Span span, std::string message);

// Each SpecError from render::build_scene as an error at the value of the field it concerns when
// that was written, else at a mesh face's own span when known, else at its element's span; with
// the include-chain notes of the file it is in.
void report_spec_errors(const std::vector<render::SpecError>& errors, const LoweredScene& scene,
                        const SourceManager& sources, Diagnostics& diags);

}  // namespace wsd::lang
