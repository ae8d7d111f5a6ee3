// `wsd check FILE...`: runs every stage but rendering on each file (a `.wsdi` as a fragment, with
// no camera required) and prints `FILE: ok — …` for each that passes; with --format json, one
// JSON array of every file's diagnostics instead. The status is the worst over all files.
#include <algorithm>
#include <iostream>

#include "app/check_json.h"
#include "app/commands.h"
#include "app/effects_report.h"
#include "app/exit_codes.h"
#include "app/file_args.h"
#include "app/io_util.h"
#include "app/scene_setup.h"

namespace wsd::app {

namespace {

bool is_fragment(const std::string& path) {
    return path.size() >= 5 && path.compare(path.size() - 5, 5, ".wsdi") == 0;
}

// Severity order of statuses for "the worst over all files".
int rank(int status) {
    switch (status) {
        case exit_code::ok:
            return 0;
        case exit_code::input_error:
            return 1;
        case exit_code::io:
            return 2;
        default:
            return 3;
    }
}

// One file's check for --format json: its result object, with what the text form prints beside
// the scene's diagnostics (too many errors, unused defines); nothing is printed.
int check_json(const std::string& path, const lang::LoadOptions& options, const SceneInputArgs& input,
               nlohmann::ordered_json& results) {
    const bool warnings = !input.no_warnings;
    std::string text, error;
    if (!read_input_file(path, text, error)) {
        results.push_back(unreadable_file_json(display_path(path), error));
        return exit_code::io;
    }
    lang::SourceManager sources;
    lang::Diagnostics all;
    const std::optional<lang::LoadedScene> scene =
        lang::load_scene(display_path(path), std::move(text), sources, all, options);
    lang::Diagnostics shown;
    for (const lang::Diagnostic& d : all.all()) {
        if (d.severity == lang::Severity::Error)
            shown.error(d.span, d.message) = d;
        else if (warnings)
            shown.warning(d.span, d.message) = d;
    }
    const bool ok = !all.has_errors() && scene.has_value();
    nlohmann::ordered_json result = check_result_json(display_path(path), ok, shown, sources);
    nlohmann::ordered_json& list = result["diagnostics"];
    if (all.too_many())
        list.push_back(positionless_json("error", display_path(path), "too many errors, stopping"));
    if (ok)
        for (const std::string& message : unread_define_warnings(*options.params, input))
            list.push_back(positionless_json("warning", display_path(path), message));
    results.push_back(std::move(result));
    return ok ? exit_code::ok : exit_code::input_error;
}

}  // namespace

int run_check(const CheckArgs& args) {
    int worst = exit_code::ok;
    nlohmann::ordered_json results = nlohmann::ordered_json::array();
    for (const std::string& path : expand_scene_paths(args.files, !args.input.no_warnings)) {
        // Each file reads the defines afresh: one that a file does not use is a warning for it.
        lang::ParamTable params;
        if (const int s = evaluate_defines(args.input.defines, params); s != exit_code::ok) return s;
        lang::LoadOptions options;
        options.fragment = is_fragment(path);
        options.build = !options.fragment;
        options.params = &params;
        if (args.json) {
            const int status = check_json(path, options, args.input, results);
            if (rank(status) > rank(worst)) worst = status;
            continue;
        }
        lang::SourceManager sources;
        std::optional<lang::LoadedScene> scene;
        const int status = load_scene_file(path, options, sources, scene, !args.input.no_warnings);
        if (status == exit_code::ok) {
            warn_unread_defines(params, args.input);
            const lang::CheckSummary& s = scene->summary;
            std::cout << display_path(path) << ": ok \u2014 " << counted(s.objects, "object") << ", "
                      << counted(s.triangles, "triangle") << ", " << counted(s.lights, "light") << ", "
                      << counted(s.materials, "material");
            // Instances share geometry: what is stored, beside what is counted as instanced.
            if (s.instances > 0)
                std::cout << " (stored: " << counted(s.stored_shapes, "shape") << ", "
                          << counted(s.stored_triangles, "triangle") << ")";
            std::cout << "\n";
            if (args.effects) print_effects(*scene, sources, std::cout);
        }
        std::cout << std::flush;
        if (rank(status) > rank(worst)) worst = status;
    }
    // File names need not be UTF-8: a byte that is not becomes U+FFFD rather than an exception.
    if (args.json)
        std::cout << results.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace)
                  << std::endl;
    return worst;
}

}  // namespace wsd::app
