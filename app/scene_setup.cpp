// Loading scenes for the commands: file or stdin, overrides, diagnostics to stderr, and the
// fingerprints that tile files carry so that `wsd merge` can refuse mismatched tiles.
#include "app/scene_setup.h"

#include <iostream>
#include <map>
#include <new>
#include <sstream>

#include "app/exit_codes.h"
#include "app/io_util.h"

namespace wsd::app {

void SceneOverrides::apply(render::SceneSpec& spec) const {
    render::Settings& s = spec.settings;
    if (width) s.width = *width;
    if (height) s.height = *height;
    if (supersamples) s.supersamples = *supersamples;
    if (max_depth) s.max_depth = *max_depth;
    if (seed) s.seed = *seed;
    if (adaptive_supersampling) s.adaptive_supersampling = *adaptive_supersampling;
    if (bailout) s.bailout = *bailout;
    if (indirect_samples) s.indirect_samples = *indirect_samples;
    if (indirect_bounces) s.indirect_bounces = *indirect_bounces;
    if (caustic_photons) s.caustic_photons = *caustic_photons;
    if (exact_area_lights) s.exact_area_lights = *exact_area_lights;
    for (render::LightSpec& light : spec.lights) {
        if (light.kind != render::LightKind::Area) continue;
        if (light_samples) light.samples_u = light.samples_v = *light_samples;
        if (adaptive_lights) light.adaptive = *adaptive_lights;
    }
}

std::string display_path(const std::string& path) {
    return path == "-" ? "<stdin>" : path;
}

int evaluate_defines(const std::vector<std::string>& defines, lang::ParamTable& params,
                     const lang::AnimationTime& time) {
    for (const std::string& define : defines) {
        const size_t eq = define.find('=');
        if (eq == std::string::npos || eq == 0)
            return fail(exit_code::usage, "--define '" + define + "': expected NAME=EXPR");
        const std::string name = define.substr(0, eq);
        std::string error;
        std::optional<lang::Value> value = lang::evaluate_define(define.substr(eq + 1), error, time);
        if (!value) return fail(exit_code::usage, "--define " + name + ": " + error);
        params.set(name, std::move(*value));
    }
    return exit_code::ok;
}

std::string defines_fingerprint(const std::vector<std::string>& defines) {
    std::map<std::string, std::string> last;
    for (const std::string& define : defines) {
        const size_t eq = define.find('=');
        last[define.substr(0, eq)] = define;
    }
    std::string out;
    for (const auto& [name, define] : last) out += std::to_string(define.size()) + ":" + define + ";";
    return out;
}

namespace {

std::vector<std::string> unread_name_warnings(const std::vector<std::string>& unread,
                                              const SceneInputArgs& input) {
    std::vector<std::string> messages;
    if (input.no_warnings) return messages;
    for (const std::string& name : unread)
        messages.push_back("--define " + name + " was not used: no param(\"" + name +
                           "\", ...) call read it");
    return messages;
}

}  // namespace

std::vector<std::string> unread_define_warnings(const lang::ParamTable& params, const SceneInputArgs& input) {
    return unread_name_warnings(params.unread(), input);
}

void warn_unread_defines(const lang::ParamTable& params, const SceneInputArgs& input) {
    warn_unread_defines(params.unread(), input);
}

void warn_unread_defines(const std::vector<std::string>& unread, const SceneInputArgs& input) {
    for (const std::string& message : unread_name_warnings(unread, input)) warn(message);
}

namespace {

// The errors of `diags` alone, for --no-warnings (their notes and help stay with them).
lang::Diagnostics errors_only(const lang::Diagnostics& diags) {
    lang::Diagnostics errors;
    for (const lang::Diagnostic& d : diags.all())
        if (d.severity == lang::Severity::Error) errors.error(d.span, d.message) = d;
    return errors;
}

// The warnings of `diags` (which has no errors) not already in `shown` (by file, offset and
// message), which gains them.
lang::Diagnostics without_shown(const lang::Diagnostics& diags, std::set<std::string>& shown) {
    lang::Diagnostics kept;
    for (const lang::Diagnostic& d : diags.all()) {
        const std::string key =
            std::to_string(d.span.file) + ":" + std::to_string(d.span.begin) + ":" + d.message;
        if (shown.insert(key).second) kept.warning(d.span, d.message) = d;
    }
    return kept;
}

}  // namespace

int load_scene_text(const std::string& path, const std::string& text, const lang::LoadOptions& options,
                    lang::SourceManager& sources, std::optional<lang::LoadedScene>& scene, bool warnings,
                    std::set<std::string>* shown) {
    lang::Diagnostics diags;
    try {
        scene = lang::load_scene(display_path(path), text, sources, diags, options);
    } catch (const std::bad_alloc&) {
        // The scene's own size (a nest of instance groups, say), not a bug: what memory_budget
        // checks before building can only be counted once the scene has been evaluated.
        scene.reset();
        return fail(exit_code::input_error, display_path(path) +
                                                ": out of memory while loading the scene (it needs more "
                                                "memory than this process may use)");
    }
    if (!warnings) diags = errors_only(diags);
    if (shown && !diags.has_errors()) diags = without_shown(diags, *shown);
    if (!diags.all().empty()) std::cerr << lang::format_diagnostics(diags, sources);
    if (diags.has_errors()) {
        scene.reset();
        return exit_code::input_error;
    }
    if (!scene && options.cancel && options.cancel->load()) return exit_code::sigint;  // the caller says so
    if (!scene) return fail(exit_code::input_error, display_path(path) + ": the scene could not be loaded");
    return exit_code::ok;
}

int load_scene_file(const std::string& path, const lang::LoadOptions& options, lang::SourceManager& sources,
                    std::optional<lang::LoadedScene>& scene, bool warnings) {
    std::string text, error;
    if (!read_input_file(path, text, error)) return fail(exit_code::io, error);
    return load_scene_text(path, text, options, sources, scene, warnings);
}

uint64_t scene_text_hash(const lang::SourceManager& sources) {
    uint64_t h = fnv1a64("wsd-scene");
    for (size_t i = 0; i < sources.size(); ++i) {
        const std::string& text = sources.file(static_cast<uint32_t>(i)).text;
        h = fnv1a64(std::to_string(text.size()) + ":", h);
        h = fnv1a64(text, h);
    }
    return h;
}

std::string settings_fingerprint(const render::SceneSpec& spec, bool adaptive_lights,
                                 const std::optional<double>& target_error,
                                 const std::optional<double>& time_limit) {
    const render::Settings& s = spec.settings;
    std::ostringstream out;
    out.precision(17);
    out << "size=" << s.width << "x" << s.height << ";supersamples=" << s.supersamples
        << ";adaptive=" << s.adaptive_supersampling << ";aa_threshold=" << s.aa_threshold
        << ";bailout=" << s.bailout << ";max_depth=" << s.max_depth << ";ambient=" << s.ambient
        << ";background=" << s.background.r << "," << s.background.g << "," << s.background.b
        << ";adaptive_lights=" << adaptive_lights << (s.exact_area_lights ? ";exact_area_lights=1" : "")
        << ";lights=";
    for (const render::LightSpec& light : spec.lights)
        out << light.samples_u << "x" << light.samples_v << (light.adaptive ? "a" : "") << ",";
    if (s.indirect_samples > 0) out << ";indirect=" << s.indirect_samples << "x" << s.indirect_bounces;
    // A progressive render takes other samples than the grid; without either option the text
    // stays what it was before progressive rendering existed.
    if (target_error) out << ";target_error=" << *target_error;
    if (time_limit) out << ";time_limit=" << *time_limit;
    return out.str();
}

}  // namespace wsd::app
