// load_scene: the whole front end — parse, evaluate (which lowers each block as it runs), check
// for a camera (and warn about a scene without lights), apply the command line's adjustments, build the
// render scene and map its errors back to spans — stopping after any stage that reported errors.
#include "lang/load.h"

#include <chrono>
#include <set>

#include "lang/interpreter.h"
#include "lang/lower.h"
#include "lang/parser.h"
#include "render/emitters.h"
#include "render/memory_budget.h"
#include "render/texture.h"

namespace wsd::lang {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Refuses a scene whose build would need more memory than the machine can give, at the shape
// that needs the most (or the file's start), with both figures. True when it fits.
bool fits_in_memory(const render::SceneSpec& spec, const LoadedScene& loaded, uint32_t file,
                    Diagnostics& diags) {
    const render::MemoryAvailable available = render::available_memory();
    if (!available.error.empty()) {
        diags.error(Span{file, 0, 0}, available.error);
        return false;
    }
    if (!available.bytes) return true;
    const render::MemoryEstimate need = render::estimate_memory(spec);
    if (need.bytes <= *available.bytes) return true;
    const Span at = need.largest_shape < loaded.shape_spans.size() && need.largest_shape_bytes > 0
                        ? loaded.shape_spans[need.largest_shape]
                        : Span{file, 0, 0};
    Diagnostic& d = diags.error(at, "the scene needs about " + render::memory_text(need.bytes) +
                                        " to build and render, more than the " +
                                        render::memory_text(*available.bytes) + " of " + available.source);
    d.help.push_back(std::to_string(need.primitives) + " primitives, " + std::to_string(need.instances) +
                     " instances and " + std::to_string(need.pixels) +
                     " pixels; the shape here needs about " + render::memory_text(need.largest_shape_bytes));
    return false;
}

// Every image file the scene names is read, as every mesh file is, also one that no object's
// material uses: a missing or undecodable file is an error at the string that names it. Those the
// build used were read (and reported) there.
void check_unused_images(const std::vector<TexturePtr>& named, const render::SceneSpec& spec,
                         render::ImageCache* images, Diagnostics& diags) {
    std::set<std::string> used;
    for (const render::MaterialSpec& m : spec.materials)
        if (m.texture && m.texture->kind == render::TextureKind::Image) used.insert(m.texture->image_path);
    for (const TexturePtr& t : named) {
        if (diags.too_many()) return;
        const std::string& image_path = t->spec.image_path;
        if (used.count(image_path)) continue;
        std::string error;
        if (images ? images->get(image_path, error) : render::load_image(image_path, error)) continue;
        error_in_includes(diags, t->chain, t->span,
                          error.empty() ? "cannot read image '" + image_path + "'" : error);
    }
}

}  // namespace

std::optional<LoadedScene> load_scene(const std::string& path, std::string text, SourceManager& sources,
                                      Diagnostics& diags, const LoadOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    const size_t errors_before = diags.error_count();
    const uint32_t file = sources.add(path, std::move(text));

    LoweredScene lowered;
    bool camera_seen = false, aborted = false;
    std::vector<TexturePtr> named_images;
    {
        // The AST and the interpreter (with everything they hold, such as packed vertex lists)
        // are released before the render scene is built, to keep peak memory down.
        Program program = parse(file, sources, diags);
        if (diags.error_count() > errors_before) return std::nullopt;
        SceneBuilder builder(file);
        {
            Interpreter interpreter(sources, diags, builder);
            interpreter.set_params(options.params);
            interpreter.set_time(options.time);
            interpreter.set_file_reader(&options.read_include);
            interpreter.set_mesh_files(options.mesh_files);
            interpreter.set_cancel(options.cancel);
            interpreter.run(program);
            if (interpreter.cancelled()) return std::nullopt;
            camera_seen = interpreter.camera_seen();
            aborted = interpreter.aborted();
            named_images = interpreter.named_images();
        }
        // A run stopped by an error is not lowered: that would copy every shape it made, and one
        // stopped for memory has little to spare.
        if (aborted && diags.error_count() > errors_before) return std::nullopt;
        lowered = builder.finish();
    }
    if (!options.fragment && !camera_seen && !aborted && !diags.too_many())
        diags.error(Span{file, 0, 0}, "missing camera: a scene needs one 'camera { ... }'");
    if (diags.error_count() > errors_before) return std::nullopt;

    LoadedScene loaded;
    loaded.summary = lowered.summary;
    loaded.shape_spans.reserve(lowered.spec.shapes.size());
    for (const render::ShapeSpec& shape : lowered.spec.shapes)
        loaded.shape_spans.push_back(shape.tag < lowered.spans.size() ? lowered.spans[shape.tag].span
                                                                      : Span{});
    if (options.adjust) options.adjust(lowered.spec);
    loaded.parse_seconds = seconds_since(start);

    if (options.build && !options.fragment) {
        if (!fits_in_memory(lowered.spec, loaded, file, diags)) return std::nullopt;
        const auto build_start = std::chrono::steady_clock::now();
        std::vector<render::SpecError> errors;
        loaded.scene = render::build_scene(lowered.spec, errors, options.use_bvh, options.threads,
                                           options.images, options.cancel);
        loaded.build_seconds = seconds_since(build_start);
        if (!loaded.scene && errors.empty() && options.cancel && options.cancel->load()) return std::nullopt;
        if (!errors.empty()) report_spec_errors(errors, lowered, sources, diags);
        if (!loaded.scene && diags.error_count() == errors_before)
            diags.error(Span{file, 0, 0}, "the scene could not be built");
        if (diags.error_count() > errors_before) return std::nullopt;
        check_unused_images(named_images, lowered.spec, options.images, diags);
        if (diags.error_count() > errors_before) return std::nullopt;
    }
    if (!options.fragment && lowered.spec.settings.indirect_samples > 0) {
        // An emissive plane has infinite area: it cannot be sampled as a light.
        for (size_t i = 0; i < lowered.spec.shapes.size(); ++i) {
            const render::ShapeSpec& shape = lowered.spec.shapes[i];
            if (shape.kind != render::ShapeKind::Plane || shape.material >= lowered.spec.materials.size() ||
                lowered.spec.materials[shape.material].emission == render::Color(0))
                continue;
            Diagnostic& d = diags.warning(loaded.shape_spans[i],
                                          "an emissive plane is seen but not sampled as a light (its area is "
                                          "infinite): it lights the scene only where indirect paths meet it");
            d.help.push_back("use a box, disc or mesh for a glowing panel");
        }
    }
    if (!options.fragment && lowered.spec.lights.empty() && !render::has_emission(lowered.spec)) {
        // Not an error: an ambient-only scene is valid, but it is rarely what was meant.
        const Span at = lowered.has_camera ? lowered.spans[lowered.spec.camera.tag].span : Span{file, 0, 0};
        Diagnostic& d = diags.warning(at, "no lights: only ambient light");
        d.help.push_back("add a light, e.g. 'light point { position <0, 10, -10> }'");
    }
    loaded.spec = std::move(lowered.spec);
    return loaded;
}

}  // namespace wsd::lang
