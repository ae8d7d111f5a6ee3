// `wsd render SCENE [options]`: loads the scene with the command-line overrides, renders the
// whole image or one tile/region with progress and cancellation, and writes the image (or tile
// file) atomically, then the statistics — once for a still, once per frame for --frames
// (app/frames.h). Usage errors are found before any rendering starts.
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <iterator>
#include <optional>
#include <set>
#include <stdexcept>
#include <vector>

#include "app/commands.h"
#include "app/exit_codes.h"
#include "app/frames.h"
#include "app/image_files.h"
#include "app/io_util.h"
#include "app/progress.h"
#include "app/signals.h"
#include "app/stats_report.h"
#include "app/tile_file.h"
#include "render/image_io.h"
#include "render/texture.h"

namespace wsd::app {

namespace {

// Parses a decimal integer that must fill the whole string.
bool parse_whole_int(std::string_view text, long long& value) {
    if (text.empty()) return false;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    return ec == std::errc() && end == text.data() + text.size();
}

// Thrown out of the load when --width/--height make the image larger than 2^28 pixels.
struct OversizedImage {
    int width = 0, height = 0;
};

struct TileRequest {
    int index = 0, count = 0;              // --tile I/N
    std::optional<render::Region> region;  // --region (or the tile's rows once the size is known)
};

bool parse_tile(const std::string& text, TileRequest& tile, std::string& error) {
    const size_t slash = text.find('/');
    long long i = 0, n = 0;
    if (slash == std::string::npos || !parse_whole_int(std::string_view(text).substr(0, slash), i) ||
        !parse_whole_int(std::string_view(text).substr(slash + 1), n)) {
        error = "--tile: expected I/N (e.g. 3/8), got '" + text + "'";
        return false;
    }
    if (n < 1 || n > max_image_side || i < 1 || i > n) {
        error = "--tile " + text + ": I must be between 1 and N, and N between 1 and " +
                std::to_string(max_image_side);
        return false;
    }
    tile.index = static_cast<int>(i);
    tile.count = static_cast<int>(n);
    return true;
}

bool parse_region(const std::string& text, TileRequest& tile, std::string& error) {
    long long v[4];
    size_t start = 0;
    for (int k = 0; k < 4; ++k) {
        const size_t comma = k < 3 ? text.find(',', start) : text.size();
        if (comma == std::string::npos ||
            !parse_whole_int(std::string_view(text).substr(start, comma - start), v[k]) || v[k] < 0 ||
            v[k] > max_image_side) {
            error = "--region: expected x0,y0,x1,y1 (pixels, half-open), got '" + text + "'";
            return false;
        }
        start = comma + 1;
    }
    if (v[0] >= v[2] || v[1] >= v[3]) {
        error = "--region " + text + ": the rectangle is empty (need x0 < x1 and y0 < y1)";
        return false;
    }
    tile.region = render::Region{static_cast<int>(v[0]), static_cast<int>(v[1]), static_cast<int>(v[2]),
                                 static_cast<int>(v[3])};
    return true;
}

// NAME.png, NAME.tile-I-of-N.pfm or NAME.region-….pfm; NAME-####… for the frames of --frames.
std::string default_output(const RenderArgs& args, const TileRequest& tile, bool animated) {
    const std::string stem = scene_stem(args.scene) + (animated ? "-####" : "");
    if (tile.count > 0)
        return stem + ".tile-" + std::to_string(tile.index) + "-of-" + std::to_string(tile.count) + ".pfm";
    if (tile.region) {
        const render::Region& r = *tile.region;
        return stem + ".region-" + std::to_string(r.x0) + "-" + std::to_string(r.y0) + "-" +
               std::to_string(r.x1) + "-" + std::to_string(r.y1) + ".pfm";
    }
    return stem + ".png";
}

// Resolves the tile's rows now that the image size is known; false + error for a usage error.
bool resolve_region(TileRequest& tile, const render::Settings& s, std::string& error) {
    if (tile.count > 0) {
        const long long h = s.height;
        const int y0 = static_cast<int>((tile.index - 1) * h / tile.count);
        const int y1 = static_cast<int>(tile.index * h / tile.count);
        if (y0 == y1) {
            error = "--tile " + std::to_string(tile.index) + "/" + std::to_string(tile.count) +
                    ": the image has only " + counted(static_cast<uint64_t>(s.height), "row") +
                    ", so this tile is empty";
            return false;
        }
        tile.region = render::Region{0, y0, s.width, y1};
    } else if (tile.region) {
        const render::Region& r = *tile.region;
        if (r.x1 > s.width || r.y1 > s.height) {
            error = "--region lies outside the " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                    " image";
            return false;
        }
    }
    return true;
}

// "7.3 s" under a minute, "2:05" (as progress shows durations) from a minute on.
std::string short_duration(double seconds) {
    if (seconds >= 60) return format_duration(seconds);
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f s", seconds);
    return buf;
}

// The line that tells where the image went: "wrote NAME (W×H, T)", and for a tile or region
// which part of which image.
std::string wrote_line(const std::string& output, const TileRequest& tile, const render::Settings& s,
                       double seconds) {
    const std::string size = std::to_string(s.width) + "\u00d7" + std::to_string(s.height);
    std::string what = size;
    if (tile.count > 0) {
        what = "tile " + std::to_string(tile.index) + "/" + std::to_string(tile.count) + ": rows " +
               std::to_string(tile.region->y0) + " to " + std::to_string(tile.region->y1 - 1) + " of " + size;
    } else if (tile.region) {
        const render::Region& r = *tile.region;
        what = "region " + std::to_string(r.x0) + "," + std::to_string(r.y0) + "," + std::to_string(r.x1) +
               "," + std::to_string(r.y1) + " of " + size;
    }
    return "wrote " + output + " (" + what + ", " + short_duration(seconds) + ")";
}

// Where the auxiliary images went, a line for the user ("" without them).
std::string aov_note(const std::string& output, const AovSelection& aovs) {
    if (!aovs.any()) return "";
    std::string files;
    for (const std::string& path : output_paths(output, aovs))
        if (path != output) files += (files.empty() ? "" : ", ") + path;
    if (files.empty()) {
        for (const std::string& name : aovs.names()) files += (files.empty() ? "" : ", ") + name;
        return "auxiliary images: layers " + files + " of " + output + "\n";
    }
    return "auxiliary images: " + files + "\n";
}

// What a progressive render reached, a line for the user ("" without one).
std::string progressive_note(const RenderArgs& args, const render::ProgressiveReport& p) {
    if (!p.used) return "";
    char rmse[32];
    std::snprintf(rmse, sizeof rmse, "%.4g", p.estimated_rmse);
    std::string note = "progressive: " + counted(static_cast<uint64_t>(p.passes), "pass", "passes") +
                       ", estimated RMSE " + rmse + ", samples per pixel " + std::to_string(p.samples_min) +
                       "/" + std::to_string(p.samples_median) + "/" + std::to_string(p.samples_max) +
                       " (min/median/max)";
    if (p.first_pass_over)
        note += "; the first pass alone took longer than the time limit, so the image is that pass";
    else if (p.deadline_reached)
        note += "; time limit reached after pass " + std::to_string(p.passes);
    if (args.target_error && !p.target_reached) note += "; the target was not reached";
    return note + "\n";
}

// What the frames of one run share: the scene's text (read once: stdin cannot be read again),
// the signal guard (an interruption between frames stops the run too) and the decoded texture
// images (immutable, so every frame still equals its own single render).
struct RenderRun {
    std::string text;
    CancelOnSignal signals;
    render::ImageCache images;
    std::set<std::string> warnings_shown;  // each scene warning is printed once per run
    // The --define names that no frame so far read: named after the frame for one frame (or a
    // still), after the run for several (a later frame may read what the first did not).
    std::optional<std::vector<std::string>> unread_defines;
};

// Loads the frame's scene with the command line's defines and overrides: an exit status.
int load_for_render(const RenderArgs& args, RenderRun& run, const FrameJob& job, lang::SourceManager& sources,
                    std::optional<lang::LoadedScene>& loaded) {
    const lang::AnimationTime& time = job.time;
    lang::ParamTable params;
    // A --define that fails at the run's first frame is a usage error, as for a still; one that
    // fails only at a later frame (it reads `frame` or `clock`) is that frame's failure.
    if (const int s = evaluate_defines(args.input.defines, params, time); s != exit_code::ok)
        return job.index > 0 ? exit_code::input_error : s;
    lang::LoadOptions load_options;
    load_options.params = &params;
    load_options.time = time;
    load_options.images = &run.images;
    load_options.use_bvh = !args.no_bvh;
    load_options.threads = args.threads;
    load_options.cancel = run.signals.flag();
    load_options.adjust = [&](render::SceneSpec& spec) {
        args.overrides.apply(spec);
        // A size that only the command line makes too large is a usage error, not the scene's;
        // it stops the load before anything is built.
        const render::Settings& s = spec.settings;
        if ((args.overrides.width || args.overrides.height) &&
            static_cast<long long>(s.width) * s.height > max_image_pixels)
            throw OversizedImage{s.width, s.height};
    };
    try {
        if (const int status = load_scene_text(args.scene, run.text, load_options, sources, loaded,
                                               !args.input.no_warnings, &run.warnings_shown);
            status != exit_code::ok)
            return status;
    } catch (const OversizedImage& size) {
        return fail(exit_code::usage, "image size " + std::to_string(size.width) + "x" +
                                          std::to_string(size.height) + " exceeds 2^28 pixels");
    }
    if (!loaded->scene) throw std::logic_error("load_scene built no scene");
    std::vector<std::string> unread = params.unread();
    if (run.unread_defines) {
        std::vector<std::string> still_unread;
        std::set_intersection(run.unread_defines->begin(), run.unread_defines->end(), unread.begin(),
                              unread.end(), std::back_inserter(still_unread));
        unread = std::move(still_unread);
    }
    run.unread_defines = std::move(unread);
    if (job.count == 1) warn_unread_defines(*run.unread_defines, args.input);
    return exit_code::ok;
}

// Where a frame goes: -o or the default name, with the frame number in its '#' runs (a still's
// '#' is literal).
std::string frame_output(const RenderArgs& args, const TileRequest& tile, const FrameJob& job) {
    const std::string pattern = args.output.empty() ? default_output(args, tile, job.animated) : args.output;
    return job.animated ? frame_path(pattern, job.time.frame) : pattern;
}

// Whether the frame's image goes to a tile file (which carries its auxiliary images itself).
bool writes_tile_file(const TileRequest& tile, const std::string& output) {
    return (tile.count > 0 || tile.region.has_value()) &&
           render::format_from_extension(output) == render::ImageFormat::Pfm;
}

// Checks what can be checked of a frame's outputs before it renders: the image format, the
// directories the image and --stats-json go to, and that --stats-json names neither the scene nor
// any of the files the image is written to (its auxiliary images' included). An exit status.
int check_frame_outputs(const RenderArgs& args, const TileRequest& tile, const AovSelection& aovs,
                        const FrameJob& job) {
    std::string error;
    const std::string output = frame_output(args, tile, job);
    if (!known_image_format(output)) return fail(exit_code::usage, unknown_format_message(output));
    if (!output_directory_exists(output, error)) return fail(exit_code::io, error);
    const std::string stats_path =
        job.animated ? frame_path(args.stats_json, job.time.frame) : args.stats_json;
    if (stats_path.empty()) return exit_code::ok;
    // The scene is read before the first frame renders: a --stats-json naming it would replace it.
    if (args.scene != "-" && same_path(stats_path, args.scene))
        return fail(exit_code::usage, "--stats-json names the scene '" + args.scene + "'");
    if (!output_directory_exists(stats_path, error)) return fail(exit_code::io, error);
    const std::vector<std::string> written =
        writes_tile_file(tile, output) ? std::vector<std::string>{output} : output_paths(output, aovs);
    for (const std::string& path : written) {
        if (!same_path(stats_path, path)) continue;
        if (path == output)
            return fail(exit_code::usage, "--stats-json names the image's own output '" + output + "'");
        return fail(exit_code::usage,
                    "--stats-json names the auxiliary image '" + path + "' of '" + output + "'");
    }
    return exit_code::ok;
}

// --stats (a table on stdout) and --stats-json FILE: an exit status. The JSON is the last part of
// the frame's output: when it cannot be written, the files in `written` (the image and its
// auxiliary images, just written) are removed, so that a failed frame leaves none of its output.
int report_stats(const RenderArgs& args, const FrameJob& job, const std::string& stats_json,
                 const lang::LoadedScene& loaded, const render::RenderResult& result,
                 const std::vector<std::string>& written) {
    const render::Settings& settings = loaded.spec.settings;
    std::string error;
    RenderReport report;
    report.scene = display_path(args.scene);
    if (job.animated) report.frame = job.time.frame;
    report.clock = job.time.clock;
    report.width = settings.width;
    report.height = settings.height;
    report.region_width = result.film.width;
    report.region_height = result.film.height;
    report.supersamples = settings.supersamples;
    report.threads = args.threads;
    report.stats = result.stats;
    report.parse_seconds = loaded.parse_seconds;
    // The loader times the whole build_scene call; the scene's own build time is part of it.
    report.build_seconds = loaded.build_seconds;
    report.render_seconds = result.render_seconds;
    report.photon_seconds = result.photon_seconds;
    report.peak_memory_bytes = peak_memory_bytes();
    report.effects = result.effects;
    report.progressive = result.progressive;
    report.target_error = args.target_error;
    report.time_limit = args.time_limit;
    if (args.stats) std::cout << stats_table(report) << std::flush;
    if (!stats_json.empty() && !write_file_atomic(stats_json, app::stats_json(report), error)) {
        for (const std::string& path : written) remove_output(path);
        return fail(exit_code::io, error);
    }
    return exit_code::ok;
}

// What a tile file records of the render that made it (tile_file.h).
TileMeta tile_meta(const RenderArgs& args, const TileRequest& tile, const FrameJob& job,
                   const lang::LoadedScene& loaded, const lang::SourceManager& sources) {
    const render::Settings& settings = loaded.spec.settings;
    TileMeta meta;
    meta.full_width = settings.width;
    meta.full_height = settings.height;
    meta.region = *tile.region;
    meta.scene_hash = hex64(scene_text_hash(sources));
    meta.settings_hash = hex64(
        fnv1a64(settings_fingerprint(loaded.spec, args.adaptive_lights, args.target_error, args.time_limit)));
    if (!args.input.defines.empty())
        meta.defines_hash = hex64(fnv1a64(defines_fingerprint(args.input.defines)));
    meta.seed = settings.seed;
    meta.tile_index = tile.index;
    meta.tile_count = tile.count;
    meta.scene = display_path(args.scene);
    meta.frame = job.animated ? job.time.frame : -1;
    meta.clock = job.time.clock;
    return meta;
}

// Renders one frame (or the still): evaluates the scene at the frame's time, renders the whole
// image or the tile, and writes it and its statistics.
int render_frame(const RenderArgs& args, RenderRun& run, TileRequest tile, const AovSelection& aovs,
                 const FrameJob& job) {
    const CancelOnSignal& signals = run.signals;
    if (signals.cancelled()) {
        std::cerr << "wsd: interrupted\n";
        return signals.exit_status();
    }
    // The first frame's outputs were checked before the run; each later one's are checked here,
    // before it renders (a '#' in a directory's name gives each frame its own directory).
    if (job.index > 0)
        if (const int status = check_frame_outputs(args, tile, aovs, job); status != exit_code::ok)
            return status;
    const auto start = std::chrono::steady_clock::now();
    const std::string output = frame_output(args, tile, job);
    const std::string stats_path =
        job.animated ? frame_path(args.stats_json, job.time.frame) : args.stats_json;
    std::string error;

    lang::SourceManager sources;
    std::optional<lang::LoadedScene> loaded;
    if (const int status = load_for_render(args, run, job, sources, loaded); status != exit_code::ok) {
        if (!signals.cancelled()) return status;
        std::cerr << "wsd: interrupted; no image written\n";
        return signals.exit_status();
    }
    const render::Settings& settings = loaded->spec.settings;
    if (!resolve_region(tile, settings, error)) return fail(exit_code::usage, error);

    ProgressReporter progress(progress_mode(args.quiet), job.progress_label(), job.run_start);
    render::RenderOptions options;
    options.threads = args.threads;
    options.use_bvh = !args.no_bvh;
    options.specialise = !args.general;
    options.region = tile.region;
    options.adaptive_lights = args.adaptive_lights;
    options.aovs = aovs.traced();
    if (args.target_error || args.time_limit) {
        render::Progressive progressive;
        progressive.target_error = args.target_error.value_or(0.0);
        if (args.time_limit)
            progressive.deadline = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                               std::chrono::duration<double>(*args.time_limit));
        options.progressive = progressive;
    }
    options.cancel = signals.flag();
    options.progress = [&](double fraction, const render::RayStats& so_far) {
        progress.update(job.run_fraction(fraction), so_far);
    };
    render::RenderResult result = render::render(*loaded->scene, options);
    if (aovs.samples) result.aovs.samples = result.progressive.samples;
    const bool completed = !result.cancelled && !signals.cancelled();
    if (completed) progress.update(job.run_fraction(1.0), result.stats);
    progress.finish(completed && job.index + 1 == job.count);
    if (!completed) {
        std::cerr << "wsd: interrupted; no image written\n";
        return signals.exit_status() ? signals.exit_status() : exit_code::sigint;
    }

    const bool tile_file = writes_tile_file(tile, output);
    if (tile_file) {
        TileMeta meta = tile_meta(args, tile, job, *loaded, sources);
        meta.aovs = aovs;
        if (!write_file_atomic(output, encode_tile(result.film, result.aovs, meta), error))
            return fail(exit_code::io, error);
    } else if (!write_image_with_aovs(output, result.film, result.aovs, aovs, error)) {
        return fail(exit_code::io, error);
    }
    if (args.stats || !stats_path.empty()) {
        const std::vector<std::string> written =
            tile_file ? std::vector<std::string>{output} : output_paths(output, aovs);
        if (const int status = report_stats(args, job, stats_path, *loaded, result, written);
            status != exit_code::ok)
            return status;
    }
    if (!args.quiet)
        std::cerr << wrote_line(
                         output, tile, settings,
                         std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count())
                  << '\n'
                  << std::flush;
    if (!args.quiet && !tile_file) std::cerr << aov_note(output, aovs);
    if (!args.quiet) std::cerr << progressive_note(args, result.progressive);
    if (const uint64_t n = result.stats.nonfinite_samples; n > 0)
        // Shown even with --quiet: the image is not what the scene describes there.
        std::cerr << "wsd: warning: " << n << (n == 1 ? " sample was" : " samples were")
                  << " not finite or too large for single precision (an overflow such as ambient × "
                     "colour, or emission, beyond 3.4e38) and "
                  << (n == 1 ? "was" : "were") << " written as black\n";
    return exit_code::ok;
}

}  // namespace

int run_render(const RenderArgs& args) {
    TileRequest tile;
    std::string error;
    if (!args.tile.empty() && !args.region.empty())
        return fail(exit_code::usage, "--tile and --region cannot be used together");
    if (!args.tile.empty() && !parse_tile(args.tile, tile, error)) return fail(exit_code::usage, error);
    if (!args.region.empty() && !parse_region(args.region, tile, error)) return fail(exit_code::usage, error);
    AovSelection aovs;
    if (!args.aov.empty() && !parse_aov_list(args.aov, aovs, error))
        return fail(exit_code::usage, "--aov: " + error);
    if (aovs.samples && !args.target_error && !args.time_limit)
        return fail(exit_code::usage, "--aov samples needs --target-error or --time-limit");
    FramePlan plan;
    if (const int status = plan_frames(args, plan); status != exit_code::ok) return status;

    // The first frame's outputs are checked before anything is read; a later frame's just before
    // it renders, so that the checks cost the same for any length of range. (No known extension
    // holds a digit, so a '#' in the extension is an unknown format at the first frame already.)
    FrameJob first;
    first.animated = plan.animated;
    first.time = plan.time_of(plan.from);
    if (const int status = check_frame_outputs(args, tile, aovs, first); status != exit_code::ok)
        return status;
    RenderRun run;
    if (!read_input_file(args.scene, run.text, error)) return fail(exit_code::io, error);
    const int status =
        run_frames(plan, [&](const FrameJob& frame) { return render_frame(args, run, tile, aovs, frame); });
    if (plan.count() > 1 && run.unread_defines) warn_unread_defines(*run.unread_defines, args.input);
    return status;
}

}  // namespace wsd::app
