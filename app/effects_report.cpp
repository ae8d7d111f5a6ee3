// `wsd check --effects`: the renderer's own effect analysis (render::analyse_effects) printed as
// one line per effect, with the objects that call for it named by kind and by where they are
// written (file:line:col of the keyword, or of an OBJ mesh's file name).
#include "app/effects_report.h"

#include "lang/object_value.h"
#include "render/effects.h"
#include "render/photon_trace.h"

namespace wsd::app {

namespace {

constexpr size_t max_listed = 12;  // a 1000-sphere scene should not print 1000 names per effect

// A CSG by its operation, as it is written.
std::string shape_name(const render::ShapeSpec& s) {
    if (s.kind != render::ShapeKind::Csg || !s.csg) return lang::shape_word(s.kind);
    switch (s.csg->op) {
        case render::CsgOp::Union:
            return "union";
        case render::CsgOp::Intersection:
            return "intersection";
        case render::CsgOp::Difference:
            return "difference";
    }
    return "csg";
}

// "sphere at s.wsd:5:1"; an object in a loop is named at its one statement.
std::string object_name(const lang::LoadedScene& scene, const lang::SourceManager& sources, uint32_t index) {
    const render::SceneSpec& spec = scene.spec;
    std::string name = index < spec.shapes.size() ? shape_name(spec.shapes[index]) : "object";
    if (index >= scene.shape_spans.size()) return name + " #" + std::to_string(index + 1);
    const lang::Span span = scene.shape_spans[index];
    if (span.file >= sources.size()) return name + " #" + std::to_string(index + 1);
    const lang::LineCol at = sources.line_col(span.file, span.begin);
    return name + " at " + sources.file(span.file).path + ":" + std::to_string(at.line) + ":" +
           std::to_string(at.column);
}

// The objects of a list, the first max_listed by name.
void print_objects(const lang::LoadedScene& scene, const lang::SourceManager& sources,
                   const std::vector<uint32_t>& shapes, std::ostream& out) {
    for (size_t k = 0; k < shapes.size() && k < max_listed; ++k)
        out << (k ? ", " : "") << object_name(scene, sources, shapes[k]);
    if (shapes.size() > max_listed) out << " and " << shapes.size() - max_listed << " more";
}

// Caustics: the objects that focus light and those that receive it, or why none are shot.
void print_caustics(const lang::LoadedScene& scene, const lang::SourceManager& sources, std::ostream& out) {
    const render::CausticObjects objects = render::caustic_objects(scene.spec);
    const std::string skipped = render::caustics_skipped(scene.spec, objects);
    if (!skipped.empty()) {
        out << "    caustics: none shot (" << skipped << ")\n";
        return;
    }
    out << "    caustics: focused by ";
    print_objects(scene, sources, objects.focusing, out);
    out << "; received by ";
    print_objects(scene, sources, objects.receiving, out);
    out << '\n';
}

}  // namespace

void print_effects(const lang::LoadedScene& scene, const lang::SourceManager& sources, std::ostream& out) {
    const render::SceneSpec& spec = scene.spec;
    const render::EffectSet effects = render::analyse_effects(spec);
    const bool caustics_asked = spec.settings.caustic_photons > 0;
    if (effects.mask == 0 && !caustics_asked) {
        out << "  effects: none (local shading only)\n";
        return;
    }
    out << "  effects:\n";
    for (size_t i = 0; i < render::kEffectCount; ++i) {
        const auto effect = static_cast<render::Effect>(i);
        if (!effects.has(effect) || effect == render::Effect::Caustics) continue;
        out << "    " << render::effect_name(effect);
        const std::vector<uint32_t>& shapes = effects.shapes[i];
        if (effect == render::Effect::IndirectLight) {
            out << " (settings: indirect_samples " << spec.settings.indirect_samples << ", indirect_bounces "
                << spec.settings.indirect_bounces << ")\n";
            continue;
        }
        if (shapes.empty()) {
            out << " (scene-wide)\n";
            continue;
        }
        out << ": ";
        print_objects(scene, sources, shapes, out);
        out << '\n';
    }
    if (caustics_asked) print_caustics(scene, sources, out);
}

}  // namespace wsd::app
