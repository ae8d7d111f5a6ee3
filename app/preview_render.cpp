// The preview's render loop: load → diagnostics or stages (each a build and a render at its size)
// → PNG → PreviewState.
#include "app/preview_render.h"

#include <stb_image_write.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <nlohmann/json.hpp>
#include <set>

#include "app/io_util.h"
#include "app/stats_report.h"
#include "lang/load.h"
#include "render/file_util.h"
#include "render/image_io.h"
#include "render/scene.h"
#include "render/texture.h"

namespace wsd::app {

namespace {

using Clock = std::chrono::steady_clock;

// The caustic photons of a coarse stage at most: a big photon map is shot for the full size only.
constexpr int kCoarsePhotons = 20000;

void append_bytes(void* context, void* data, int size) {
    if (size > 0) static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
}

// Reads an include from disk as the interpreter does, noting its path in `tried`: an include that
// cannot be read (yet) is watched too.
lang::IncludeReader noting_reader(std::vector<std::string>& tried) {
    return [&tried](const std::string& path, std::string& text, std::string& reason) {
        tried.push_back(path);
        return lang::read_include_file(path, text, reason);
    };
}

// Every file the load read (the scene and its includes), tried to read (`tried`: includes and mesh
// files, found or not) or names (textures, OBJ meshes), once each.
std::vector<std::string> named_files(const std::string& scene, const lang::SourceManager& sources,
                                     const std::vector<std::string>& tried, const lang::LoadedScene* loaded) {
    std::vector<std::string> files{scene};
    std::set<std::string> seen{scene};
    auto add = [&](const std::string& path) {
        if (!path.empty() && path != "--define" && seen.insert(path).second) files.push_back(path);
    };
    for (size_t i = 0; i < sources.size(); ++i) add(sources.file(static_cast<uint32_t>(i)).path);
    for (const std::string& path : tried) add(path);
    if (!loaded) return files;
    for (const render::MaterialSpec& m : loaded->spec.materials)
        if (m.texture && m.texture->kind == render::TextureKind::Image) add(m.texture->image_path);
    auto add_mesh = [&](const render::ShapeSpec& shape) {
        // An inline mesh names the scene file it is written in; an OBJ mesh its file.
        if (shape.mesh) add(shape.mesh->source_name);
    };
    for (const render::ShapeSpec& shape : loaded->spec.shapes) add_mesh(shape);
    for (const render::PrototypeSpec& prototype : loaded->spec.prototypes)
        for (const render::ShapeSpec& shape : prototype.shapes) add_mesh(shape);
    return files;
}

// The description of one stage: the scene's own `full` settings and `lights`, at the stage's size.
void apply_stage(render::SceneSpec& spec, const PreviewStage& stage, const render::Settings& full,
                 const std::vector<render::LightSpec>& lights) {
    render::Settings& s = spec.settings;
    s = full;
    spec.lights = lights;
    s.width = full.width / stage.divisor;
    s.height = full.height / stage.divisor;
    if (!stage.coarse) return;
    s.supersamples = 1;
    s.adaptive_supersampling = false;
    s.caustic_photons = std::min(s.caustic_photons, kCoarsePhotons);
    for (render::LightSpec& light : spec.lights) {
        light.samples_u = std::min(light.samples_u, stage.light_grid);
        light.samples_v = std::min(light.samples_v, stage.light_grid);
    }
}

}  // namespace

std::vector<PreviewStage> preview_stages(int width, int height) {
    std::vector<PreviewStage> stages;
    for (int divisor : {8, 4, 2})
        if (width / divisor >= 8 && height / divisor >= 8) stages.push_back({divisor, true, 4});
    stages.push_back({1, false, 0});
    return stages;
}

std::string encode_png(int width, int height, const std::vector<float>& rgb) {
    std::vector<unsigned char> bytes(rgb.size());
    for (size_t i = 0; i < bytes.size(); ++i) {
        const double x = rgb[i] > 0 ? std::min(double(rgb[i]), 1.0) : 0.0;  // NaN → 0
        bytes[i] = static_cast<unsigned char>(std::lround(render::srgb_encode(x) * 255.0));
    }
    std::string png;
    stbi_write_png_to_func(append_bytes, &png, width, height, 3, bytes.data(), width * 3);
    return png;
}

PreviewRenderer::PreviewRenderer(PreviewState& state, std::string scene_path, int threads,
                                 const lang::ParamTable* params)
    : state_(state), scene_(std::move(scene_path)), threads_(threads), params_(params) {}

void PreviewRenderer::request() {
    std::lock_guard lock(mutex_);
    ++requested_;
    cancel_.store(true);
    cv_.notify_all();
}

void PreviewRenderer::stop() {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    cancel_.store(true);
    cv_.notify_all();
}

bool PreviewRenderer::take_watch_list(std::vector<std::string>& files, bool& whole_directories) {
    std::lock_guard lock(mutex_);
    if (!files_changed_) return false;
    files = files_;
    whole_directories = files_failed_;
    files_changed_ = false;
    return true;
}

void PreviewRenderer::publish_files(const std::vector<std::string>& files, bool failed) {
    {
        std::lock_guard lock(mutex_);
        if (files == files_ && failed == files_failed_) return;
        files_ = files;
        files_failed_ = failed;
        files_changed_ = true;
    }
    state_.set_files(nlohmann::json(files).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

void PreviewRenderer::run() {
    for (;;) {
        uint64_t generation = 0;
        {
            std::unique_lock lock(mutex_);
            cv_.wait(lock, [&] { return stopping_ || requested_ > started_; });
            if (stopping_) return;
            started_ = requested_;
            generation = started_;
            cancel_.store(false);
        }
        render_generation(generation);
    }
}

void PreviewRenderer::render_generation(uint64_t generation) {
    state_.begin_generation(generation);
    std::string text, error;
    if (!read_input_file(scene_, text, error)) {
        state_.set_diagnostics("wsd: error: " + error + "\n");
        publish_files({scene_}, true);
        return;
    }
    // The scene is loaded (and checked, textures and all) as the first stage; each later stage
    // builds the same description at its own size.
    render::Settings full;
    std::vector<render::LightSpec> lights;
    std::vector<PreviewStage> stages;
    render::ImageCache images;  // one per load: a saved texture is read again
    lang::LoadOptions options;
    options.threads = threads_;
    options.images = &images;
    options.params = params_;
    options.cancel = &cancel_;  // a save or Ctrl-C abandons a long evaluation or photon map
    std::vector<std::string> tried;
    options.read_include = noting_reader(tried);
    options.mesh_files = &tried;  // a broken or missing mesh fails the load: its file is watched
    options.adjust = [&](render::SceneSpec& spec) {
        full = spec.settings;
        lights = spec.lights;
        stages = preview_stages(full.width, full.height);
        apply_stage(spec, stages[0], full, lights);
    };
    lang::SourceManager sources;
    lang::Diagnostics diags;
    std::optional<lang::LoadedScene> loaded;
    try {
        loaded = lang::load_scene(scene_, text, sources, diags, options);
    } catch (const std::exception& e) {
        diags.error({}, std::string("the scene could not be loaded: ") + e.what());
    }
    if (superseded()) return;
    const bool ok = loaded && !diags.has_errors();
    if (ok) {
        publish_files(named_files(scene_, sources, tried, &*loaded), false);
    } else {
        // When only the build failed (a missing or broken texture), the description without the
        // build still names the files to watch for the fix.
        lang::LoadOptions unbuilt;
        unbuilt.build = false;
        unbuilt.params = params_;
        unbuilt.cancel = &cancel_;
        unbuilt.read_include = noting_reader(tried);
        unbuilt.mesh_files = &tried;
        lang::SourceManager unbuilt_sources;
        lang::Diagnostics unbuilt_diags;
        std::optional<lang::LoadedScene> described;
        try {
            described = lang::load_scene(scene_, text, unbuilt_sources, unbuilt_diags, unbuilt);
        } catch (const std::exception&) {
            described.reset();
        }
        if (superseded()) return;
        if (described && !unbuilt_diags.has_errors())
            publish_files(named_files(scene_, unbuilt_sources, tried, &*described), true);
        else
            publish_files(named_files(scene_, sources, tried, nullptr), true);
    }
    if (!ok) {
        std::string message = lang::format_diagnostics(diags, sources);
        if (message.empty()) message = scene_ + ": the scene could not be loaded\n";
        state_.set_diagnostics(message);
        return;
    }
    state_.set_diagnostics("");
    state_.set_phase("rendering");

    const double total_pixels = [&] {
        double sum = 0;
        for (const PreviewStage& st : stages)
            sum += double(full.width / st.divisor) * double(full.height / st.divisor);
        return sum;
    }();
    double done_pixels = 0;
    for (size_t i = 0; i < stages.size(); ++i) {
        if (superseded()) return;
        const PreviewStage& st = stages[i];
        std::shared_ptr<const render::Scene> scene = loaded->scene;
        if (i > 0) {
            render::SceneSpec stage_spec = loaded->spec;
            apply_stage(stage_spec, st, full, lights);
            std::vector<render::SpecError> errors;
            scene = render::build_scene(stage_spec, errors, true, threads_, &images, &cancel_);
            if (superseded()) return;
            if (!scene) {  // the load built the same description, so this is not expected
                state_.set_diagnostics(scene_ + ": " + (errors.empty() ? "build failed" : errors[0].message) +
                                       "\n");
                return;
            }
        }
        const render::Settings& s = scene->settings();
        const double stage_pixels = double(s.width) * double(s.height);
        render::RenderOptions ro;
        ro.threads = threads_;
        ro.cancel = &cancel_;
        Clock::time_point last = Clock::now();
        std::mutex progress_mutex;
        ro.progress = [&](double fraction, const render::RayStats&) {
            std::lock_guard lock(progress_mutex);
            const Clock::time_point now = Clock::now();
            if (now - last < std::chrono::milliseconds(100)) return;
            last = now;
            state_.set_progress((done_pixels + fraction * stage_pixels) / total_pixels);
        };
        const render::RenderResult result = render::render(*scene, ro);
        if (result.cancelled || superseded()) return;
        done_pixels += stage_pixels;
        state_.set_progress(done_pixels / total_pixels);
        state_.set_image(encode_png(result.film.width, result.film.height, result.film.rgb),
                         result.film.width, result.film.height, full.width, full.height, int(i + 1),
                         int(stages.size()));
        if (!st.coarse) {
            RenderReport report;
            report.scene = scene_;
            report.width = report.region_width = s.width;
            report.height = report.region_height = s.height;
            report.supersamples = s.supersamples;
            report.threads = threads_;
            report.stats = result.stats;
            report.parse_seconds = loaded->parse_seconds;
            report.build_seconds = scene->build_seconds();
            report.render_seconds = result.render_seconds;
            report.peak_memory_bytes = peak_memory_bytes();
            report.effects = result.effects;
            state_.set_stats(stats_json(report));
        }
    }
    state_.set_phase("done");
}

}  // namespace wsd::app
