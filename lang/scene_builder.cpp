// The SceneBuilder: assembles lowered elements into a render::SceneSpec as statements run, with
// one span record per tag, and maps render::build_scene's SpecErrors back to those spans.
#include "lang/lower.h"

namespace wsd::lang {

namespace {

SpanRecord plain(Span span, IncludeChain chain) {
    SpanRecord r;
    r.span = span;
    r.chain = std::move(chain);
    return r;
}

}  // namespace

SceneBuilder::SceneBuilder(uint32_t main_file) {
    // Tag 0: the start of the main file, for errors about elements without a source.
    scene_.spans.push_back(plain(Span{main_file, 0, 0}, nullptr));
}

uint32_t SceneBuilder::record(SpanRecord r) {
    scene_.spans.push_back(std::move(r));
    return static_cast<uint32_t>(scene_.spans.size() - 1);
}

void SceneBuilder::set_settings(const render::Settings& settings, Span keyword, IncludeChain chain) {
    scene_.spec.settings = settings;
    scene_.settings_tag = record(plain(keyword, std::move(chain)));
}

void SceneBuilder::set_camera(render::CameraSpec camera, Span keyword, IncludeChain chain) {
    camera.tag = record(plain(keyword, std::move(chain)));
    scene_.spec.camera = camera;
    scene_.has_camera = true;
}

void SceneBuilder::add_light(render::LightSpec light, Span keyword, IncludeChain chain) {
    light.tag = record(plain(keyword, std::move(chain)));
    scene_.spec.lights.push_back(light);
    ++scene_.summary.lights;
}

uint32_t SceneBuilder::texture_tag(const TexturePtr& texture) {
    return record(plain(texture->span, texture->chain));
}

uint32_t SceneBuilder::material_index(const MaterialPtr& material) {
    auto it = material_ids_.find(material.get());
    if (it != material_ids_.end()) return it->second;
    render::MaterialSpec spec = material->spec;
    spec.tag = record(plain(material->span, material->chain));
    if (spec.texture && material->texture) spec.texture->tag = texture_tag(material->texture);
    if (spec.bump && material->bump) spec.bump->tag = texture_tag(material->bump);
    uint32_t index = static_cast<uint32_t>(scene_.spec.materials.size());
    scene_.spec.materials.push_back(std::move(spec));
    materials_.push_back(material);
    material_ids_.emplace(material.get(), index);
    return index;
}

void SceneBuilder::add_object(LoweredObject&& object, IncludeChain chain) {
    object.shape.material = material_index(object.material);
    object.record.chain = std::move(chain);
    object.shape.tag = record(std::move(object.record));
    ++scene_.summary.objects;
    if (object.is_triangle) ++scene_.summary.triangles;
    if (object.shape.kind == render::ShapeKind::Mesh) scene_.summary.triangles += object.primitives;
    primitives_ += object.primitives;
    scene_.spec.shapes.push_back(std::move(object.shape));
}

LoweredScene SceneBuilder::finish() {
    scene_.summary.materials = scene_.spec.materials.size();
    material_ids_.clear();
    materials_.clear();
    LoweredScene out = std::move(scene_);
    scene_ = LoweredScene{};
    return out;
}

namespace {

bool mentions_face(const std::string& message) {
    return message.find("face") != std::string::npos;
}

// Where to report a SpecError, and its message with the face and OBJ line when it concerns one.
std::pair<Span, std::string> locate(const render::SpecError& e, const SpanRecord& rec,
                                    const LoweredScene& scene, const SourceManager& sources) {
    std::string message = e.message.empty() ? "invalid scene element" : e.message;
    if (e.face < 0) return {rec.span, message};
    const size_t face = static_cast<size_t>(e.face);
    std::string prefix = mentions_face(message) ? "" : "face " + std::to_string(face) + ": ";
    if (rec.faces && face < rec.faces->offsets.size()) {
        PackedVectors probe;
        probe.file = rec.faces->file;
        probe.offsets = {rec.faces->offsets[face]};
        return {packed_element_span(probe, 0, sources), prefix + message};
    }
    if (rec.faces && face < rec.faces->spans.size()) return {rec.faces->spans[face], prefix + message};
    if (!prefix.empty() && rec.obj && e.item == render::SpecItem::Shape &&
        e.index < scene.spec.shapes.size()) {
        const auto& mesh = scene.spec.shapes[e.index].mesh;
        if (mesh && face < mesh->face_lines.size())
            prefix = "face " + std::to_string(face) + " (" + mesh->source_name + " line " +
                     std::to_string(mesh->face_lines[face]) + "): ";
    }
    return {rec.span, prefix + message};
}

}  // namespace

void report_spec_errors(const std::vector<render::SpecError>& errors, const LoweredScene& scene,
                        const SourceManager& sources, Diagnostics& diags) {
    for (const render::SpecError& e : errors) {
        if (diags.too_many()) return;
        uint32_t tag = e.item == render::SpecItem::Settings ? scene.settings_tag : e.tag;
        const SpanRecord& rec = tag < scene.spans.size() ? scene.spans[tag] : scene.spans[0];
        auto [span, message] = locate(e, rec, scene, sources);
        std::vector<Span> chain;
        for (const IncludeSite* s = rec.chain.get(); s; s = s->parent.get()) chain.push_back(s->site);
        for (auto it = chain.rbegin(); it != chain.rend(); ++it) diags.push_include(*it);
        diags.error(span, message);
        for (size_t i = 0; i < chain.size(); ++i) diags.pop_include();
    }
}

}  // namespace wsd::lang
