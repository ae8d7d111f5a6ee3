// The SceneBuilder: assembles lowered elements into a render::SceneSpec as statements run (a
// material value is lowered to its spec when an object first uses it, once per value), with one
// span record per tag (and the value spans of its fields), and maps render::build_scene's
// SpecErrors back to those spans by the element, field and face they name.
#include "lang/lower.h"

namespace wsd::lang {

namespace {

// What a shape stores: 1 shape (a CSG with its members counts once), and its triangles.
void count_stored(const render::ShapeSpec& s, size_t& triangles) {
    if (s.kind == render::ShapeKind::Triangle) ++triangles;
    if (s.kind == render::ShapeKind::Mesh && s.mesh) triangles += s.mesh->faces.size();
    if (s.kind == render::ShapeKind::Csg && s.csg)
        for (const render::ShapeSpec& m : s.csg->members) count_stored(m, triangles);
}

SpanRecord plain(Span span, IncludeChain chain) {
    SpanRecord r;
    r.span = span;
    r.chain = std::move(chain);
    return r;
}

}  // namespace

uint32_t SceneBuilder::record(SpanRecord r, const std::vector<FieldSpan>& fields) {
    r.fields_begin = static_cast<uint32_t>(scene_.field_spans.size());
    scene_.field_spans.insert(scene_.field_spans.end(), fields.begin(), fields.end());
    r.fields_end = static_cast<uint32_t>(scene_.field_spans.size());
    scene_.spans.push_back(std::move(r));
    return static_cast<uint32_t>(scene_.spans.size() - 1);
}

void SceneBuilder::set_settings(const Lowered<render::Settings>& settings, Span keyword, IncludeChain chain) {
    scene_.spec.settings = settings.spec;
    scene_.settings_tag = record(plain(keyword, std::move(chain)), settings.fields);
}

void SceneBuilder::set_camera(const Lowered<render::CameraSpec>& camera, Span keyword, IncludeChain chain) {
    scene_.spec.camera = camera.spec;
    scene_.spec.camera.tag = record(plain(keyword, std::move(chain)), camera.fields);
    scene_.has_camera = true;
}

void SceneBuilder::add_light(const Lowered<render::LightSpec>& light, Span keyword, IncludeChain chain) {
    scene_.spec.lights.push_back(light.spec);
    scene_.spec.lights.back().tag = record(plain(keyword, std::move(chain)), light.fields);
    ++scene_.summary.lights;
}

uint32_t SceneBuilder::texture_tag(const TexturePtr& texture) {
    return record(plain(texture->span, texture->chain), texture->fields);
}

uint32_t SceneBuilder::material_index(const MaterialPtr& material) {
    auto it = material_ids_.find(material.get());
    if (it != material_ids_.end()) return it->second;
    // Lowered once per material value, however many objects use it.
    LoweredMaterial lowered = lower_material_spec(*material);
    render::MaterialSpec& spec = lowered.spec;
    spec.tag = record(plain(material->block.keyword, material->chain), lowered.fields);
    if (spec.texture) spec.texture->tag = texture_tag(lowered.texture);
    if (spec.bump) spec.bump->tag = texture_tag(lowered.bump);
    uint32_t index = static_cast<uint32_t>(scene_.spec.materials.size());
    scene_.spec.materials.push_back(std::move(spec));
    materials_.push_back(material);
    material_ids_.emplace(material.get(), index);
    return index;
}

void SceneBuilder::add_object(LoweredObject&& object, IncludeChain chain) {
    object.shape.material = material_index(object.material);
    object.record.chain = std::move(chain);
    object.shape.tag = record(std::move(object.record), object.fields);
    ++scene_.summary.objects;
    if (object.is_triangle) ++scene_.summary.triangles;
    if (object.shape.kind == render::ShapeKind::Mesh) scene_.summary.triangles += object.primitives;
    primitives_ += object.primitives;
    scene_.spec.shapes.push_back(std::move(object.shape));
}

LoweredScene SceneBuilder::finish() {
    drop_object_caches();
    CheckSummary& summary = scene_.summary;
    summary.materials = scene_.spec.materials.size();
    summary.instances = instances_;
    auto stored = [&summary](const render::ShapeSpec& s) {
        if (s.kind == render::ShapeKind::Instance) return;
        ++summary.stored_shapes;
        count_stored(s, summary.stored_triangles);
    };
    for (const render::ShapeSpec& s : scene_.spec.shapes) stored(s);
    for (const render::PrototypeSpec& p : scene_.spec.prototypes)
        for (const render::ShapeSpec& s : p.shapes) stored(s);
    material_ids_.clear();
    materials_.clear();
    LoweredScene out = std::move(scene_);
    scene_ = LoweredScene{};
    return out;
}

namespace {

// Where to report a SpecError: the value of its field, else its face, else its element.
Span locate(const render::SpecError& e, const SpanRecord& rec, const LoweredScene& scene,
            const SourceManager& sources) {
    if (!e.field.empty())
        for (uint32_t i = rec.fields_begin; i < rec.fields_end; ++i)
            if (scene.field_spans[i].table_field().name == e.field)
                return Span{rec.span.file, scene.field_spans[i].begin, scene.field_spans[i].end};
    if (e.face < 0 || !rec.faces) return rec.span;
    const size_t face = static_cast<size_t>(e.face);
    if (face < rec.faces->offsets.size()) {
        PackedVectors probe;
        probe.file = rec.faces->file;
        probe.offsets = {rec.faces->offsets[face]};
        return packed_element_span(probe, 0, sources);
    }
    if (face < rec.faces->spans.size()) return rec.faces->spans[face];
    return rec.span;
}

}  // namespace

void report_spec_errors(const std::vector<render::SpecError>& errors, const LoweredScene& scene,
                        const SourceManager& sources, Diagnostics& diags) {
    for (const render::SpecError& e : errors) {
        if (diags.too_many()) return;
        uint32_t tag = e.item == render::SpecItem::Settings ? scene.settings_tag : e.tag;
        const SpanRecord& rec = tag < scene.spans.size() ? scene.spans[tag] : scene.spans[0];
        const Span span = locate(e, rec, scene, sources);
        const std::string message = e.message.empty() ? "invalid scene element" : e.message;
        error_in_includes(diags, rec.chain, span, message);
    }
}

void error_in_includes(Diagnostics& diags, const IncludeChain& chain, Span span, std::string message) {
    std::vector<Span> sites;
    for (const IncludeSite* s = chain.get(); s; s = s->parent.get()) sites.push_back(s->site);
    for (auto it = sites.rbegin(); it != sites.rend(); ++it) diags.push_include(*it);
    diags.error(span, std::move(message));
    for (size_t i = 0; i < sites.size(); ++i) diags.pop_include();
}

}  // namespace wsd::lang
