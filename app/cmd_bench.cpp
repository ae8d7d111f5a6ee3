// `wsd bench SCENE`: renders a high-quality reference, then sweeps one knob at a time around the
// scene's own settings (supersamples, light samples, max depth, adaptive supersampling, adaptive
// lights, bailout) and renders progressively to a few error targets, timing each setting (median of --repeat
// runs) and measuring its error against the reference. Every render goes through lang::load_scene and
// render::render, like `wsd render`.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "app/bench_report.h"
#include "app/commands.h"
#include "app/exit_codes.h"
#include "app/io_util.h"
#include "app/progress.h"
#include "app/signals.h"
#include "render/limits.h"
#include "render/scene.h"

namespace wsd::app {

namespace {

constexpr int quick_max_side = 32;

struct Setting {
    std::string knob, value;
    SceneOverrides overrides;
    std::optional<double> target_error;  // progressive rendering to this target
};

struct SceneFacts {
    int width = 0, height = 0, supersamples = 1, max_depth = 0;
    uint32_t seed = 0;
    bool area_lights = false;
    int caustic_photons = 0;
    std::string light_grid;  // of the first area light, e.g. "4x4"
    int indirect_samples = 0, indirect_bounces = 3;
};

double cpu_seconds_now() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// One setting: load and build once, render `repeat` times. Returns an exit status.
struct RunResult {
    render::Film film;
    render::RayStats stats;
    double wall = 0, cpu = 0;
    std::optional<double> estimated_rmse;  // progressive renders
};

// The scene's diagnostics were shown by the first load (run_bench); these loads print errors only.
int run_setting(const std::string& path, const std::string& text, const SceneOverrides& overrides,
                std::optional<double> target_error, const BenchArgs& args, const lang::ParamTable& params,
                int repeat, const CancelOnSignal& signals, const std::string& label, RunResult& out) {
    lang::LoadOptions load_options;
    load_options.params = &params;
    load_options.threads = args.threads;
    load_options.cancel = signals.flag();
    load_options.adjust = [&](render::SceneSpec& spec) { overrides.apply(spec); };
    lang::SourceManager sources;
    std::optional<lang::LoadedScene> loaded;
    const double cpu0_load = cpu_seconds_now();
    if (const int s = load_scene_text(path, text, load_options, sources, loaded, false); s != exit_code::ok)
        return signals.cancelled() ? signals.exit_status() : s;
    const double cpu1 = cpu_seconds_now();
    if (!loaded->scene) throw std::logic_error("load_scene built no scene");
    // Caustic photons are shot while the scene is built, once for every repeat: their time is
    // added to each render's (the load's CPU time in the share the photon map took of the build).
    const double photon_wall = loaded->scene->caustic_build().seconds;
    const double photon_cpu =
        loaded->scene->build_seconds() > 0
            ? (cpu1 - cpu0_load) * std::min(1.0, photon_wall / loaded->scene->build_seconds())
            : 0.0;
    std::vector<double> walls, cpus;
    for (int r = 0; r < repeat; ++r) {
        ProgressReporter progress(progress_mode(args.quiet), label);
        render::RenderOptions options;
        options.threads = args.threads;
        options.cancel = signals.flag();
        if (target_error) options.progressive = render::Progressive{*target_error, {}};
        options.progress = [&](double fraction, const render::RayStats& so_far) {
            progress.update(fraction, so_far);
        };
        const double cpu0 = cpu_seconds_now();
        const auto wall0 = std::chrono::steady_clock::now();
        render::RenderResult result = render::render(*loaded->scene, options);
        walls.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count() +
                        photon_wall);
        cpus.push_back(cpu_seconds_now() - cpu0 + photon_cpu);
        progress.finish(!result.cancelled);
        if (result.cancelled || signals.cancelled())
            return signals.exit_status() ? signals.exit_status() : exit_code::sigint;
        out.film = std::move(result.film);
        out.stats = result.stats;
        if (result.progressive.used) out.estimated_rmse = result.progressive.estimated_rmse;
    }
    out.wall = median(walls);
    out.cpu = median(cpus);
    return exit_code::ok;
}

std::vector<Setting> sweep(const SceneFacts& facts, const SceneOverrides& base, bool quick,
                           std::vector<std::string>& notes) {
    std::vector<Setting> settings;
    auto add = [&](const std::string& knob, const std::string& value, auto&& change) {
        Setting s{knob, value, base, {}};
        change(s.overrides);
        settings.push_back(std::move(s));
    };
    const std::vector<int> supersamples = quick ? std::vector<int>{1, 4, 16} : std::vector<int>{1, 4, 16, 64};
    for (const int n : supersamples)
        add("supersamples", std::to_string(n), [&](SceneOverrides& o) { o.supersamples = n; });
    if (facts.area_lights) {
        const std::vector<int> sides = quick ? std::vector<int>{1, 2, 4} : std::vector<int>{1, 2, 4, 8, 10};
        for (const int n : sides)
            add("light_samples", std::to_string(n * n), [&](SceneOverrides& o) { o.light_samples = n; });
    } else {
        notes.push_back("light_samples and adaptive_lights skipped: the scene has no area light");
    }
    const int max_depth = quick ? 2 : 8;
    for (int d = 0; d <= max_depth; ++d)
        add("max_depth", std::to_string(d), [&](SceneOverrides& o) { o.max_depth = d; });
    // Adaptive supersampling only matters with several samples per pixel.
    const int aa_samples = std::max(facts.supersamples, 16);
    if (aa_samples != facts.supersamples)
        notes.push_back("adaptive_aa rows use " + std::to_string(aa_samples) + " supersamples");
    for (const bool on : {false, true})
        add("adaptive_aa", on ? "on" : "off", [&](SceneOverrides& o) {
            o.adaptive_supersampling = on;
            o.supersamples = aa_samples;
        });
    if (facts.area_lights)
        for (const bool on : {false, true})
            add("adaptive_lights", on ? "on" : "off", [&](SceneOverrides& o) { o.adaptive_lights = on; });
    if (facts.area_lights)
        for (const bool on : {false, true})
            add("exact_area_lights", on ? "on" : "off", [&](SceneOverrides& o) { o.exact_area_lights = on; });
    // Adaptive depth: 0 traces every reflected and refracted ray; 1/512 is the default.
    const std::vector<std::pair<std::string, double>> bailouts =
        quick ? std::vector<std::pair<std::string, double>>{{"0", 0.0}, {"1/512", 1.0 / 512}, {"1/8", 0.125}}
              : std::vector<std::pair<std::string, double>>{
                    {"0", 0.0}, {"1/512", 1.0 / 512}, {"1/64", 1.0 / 64}, {"1/8", 0.125}, {"1/2", 0.5}};
    for (const auto& [label, value] : bailouts)
        add("bailout", label, [&, v = value](SceneOverrides& o) { o.bailout = v; });
    // Progressive rendering to a target (the scene's supersamples do not apply).
    const std::vector<std::pair<std::string, double>> targets =
        quick ? std::vector<std::pair<std::string, double>>{{"0.04", 0.04}, {"0.02", 0.02}}
              : std::vector<std::pair<std::string, double>>{
                    {"0.04", 0.04}, {"0.02", 0.02}, {"0.01", 0.01}, {"0.005", 0.005}};
    for (const auto& [label, value] : targets) {
        add("target_error", label, [](SceneOverrides&) {});
        settings.back().target_error = value;
    }
    if (facts.indirect_samples > 0) {
        const std::vector<int> paths = quick ? std::vector<int>{1, 4, 16} : std::vector<int>{1, 4, 16, 64};
        for (const int n : paths)
            add("indirect_samples", std::to_string(n), [&](SceneOverrides& o) { o.indirect_samples = n; });
        const std::vector<int> bounces = quick ? std::vector<int>{1, 2, 3} : std::vector<int>{1, 2, 3, 5, 8};
        for (const int b : bounces)
            add("indirect_bounces", std::to_string(b), [&](SceneOverrides& o) { o.indirect_bounces = b; });
    } else {
        notes.push_back("indirect_samples and indirect_bounces skipped: the scene has no indirect light");
    }
    // Caustic photons: from a sixteenth of the scene's own count to four times it.
    if (facts.caustic_photons > 0) {
        const std::vector<int> shares = quick ? std::vector<int>{1, 4, 16} : std::vector<int>{1, 4, 16, 64};
        for (const int share : shares) {
            const long long n =
                std::min<long long>(render::kMaxCausticPhotons,
                                    std::max<long long>(1, (long long)facts.caustic_photons * share / 16));
            add("caustic_photons", std::to_string(n),
                [&, n](SceneOverrides& o) { o.caustic_photons = int(n); });
        }
    } else {
        notes.push_back("caustic_photons skipped: the scene asks for no caustic photons");
    }
    return settings;
}

int prepare_directory(const std::string& dir, std::string& error) {
    std::error_code ec;
    if (std::filesystem::is_directory(dir, ec)) return exit_code::ok;
    if (std::filesystem::exists(std::filesystem::symlink_status(dir, ec))) {
        error = "cannot use '" + dir + "' as the output directory: it exists and is not a directory";
        return exit_code::io;
    }
    // The directory itself is created; a missing parent is not (wsd-cli.md, exit status 3).
    if (!std::filesystem::create_directory(dir, ec)) {
        error = "cannot create output directory '" + dir +
                "': " + (ec ? ec.message() : "it exists and is not a directory");
        return exit_code::io;
    }
    return exit_code::ok;
}

// The scene's own settings (size, samples, depth, seed, area lights), read without building it.
int read_scene_facts(const BenchArgs& args, const std::string& text, const lang::ParamTable& params,
                     SceneFacts& facts) {
    lang::LoadOptions options;
    options.build = false;
    options.params = &params;
    lang::SourceManager sources;
    std::optional<lang::LoadedScene> loaded;
    if (const int s = load_scene_text(args.scene, text, options, sources, loaded, !args.input.no_warnings);
        s != exit_code::ok)
        return s;
    warn_unread_defines(params, args.input);
    const render::Settings& st = loaded->spec.settings;
    facts.width = st.width;
    facts.height = st.height;
    facts.supersamples = st.supersamples;
    facts.max_depth = st.max_depth;
    facts.seed = st.seed;
    facts.indirect_samples = st.indirect_samples;
    facts.indirect_bounces = st.indirect_bounces;
    facts.caustic_photons = st.caustic_photons;
    for (const render::LightSpec& l : loaded->spec.lights)
        if (l.kind == render::LightKind::Area && !facts.area_lights) {
            facts.area_lights = true;
            facts.light_grid = std::to_string(l.samples_u) + "x" + std::to_string(l.samples_v);
        }
    return exit_code::ok;
}

// The reference image's settings: far more samples than the sweep, another seed, nothing adaptive.
SceneOverrides reference_overrides(const BenchArgs& args, const SceneFacts& facts, const SceneOverrides& base,
                                   BenchInfo& info) {
    SceneOverrides reference = base;
    // 256 = a 16×16 grid, four times the largest supersampling in the sweep, and another seed:
    // with the sweep's own seed and sample count, the 64-sample row would share the reference's
    // jitter and its error would read as far smaller than it is.
    reference.supersamples = args.reference_supersamples ? args.reference_supersamples : 256;
    reference.seed = facts.seed ^ 0x9E3779B9u;
    const int ref_light = args.reference_light_samples ? args.reference_light_samples : (args.quick ? 8 : 16);
    if (facts.area_lights) reference.light_samples = ref_light;
    reference.max_depth = args.reference_depth >= 0 ? args.reference_depth : std::max(facts.max_depth, 10);
    reference.adaptive_supersampling = false;
    reference.adaptive_lights = false;
    reference.exact_area_lights = false;
    reference.bailout = 0.0;
    // Indirect light: the scene's paths a camera sample (the reference's many camera samples
    // multiply them), and at least 8 bounces.
    if (facts.indirect_samples > 0) reference.indirect_bounces = std::max(facts.indirect_bounces, 8);
    // Caustics: eight times the sweep's largest photon count (32 times the scene's own).
    if (facts.caustic_photons > 0)
        reference.caustic_photons =
            int(std::min<long long>(render::kMaxCausticPhotons, 32LL * facts.caustic_photons));
    info.reference_settings =
        "supersamples " + std::to_string(*reference.supersamples) +
        (facts.area_lights ? ", light samples " + std::to_string(ref_light) + "x" + std::to_string(ref_light)
                           : std::string()) +
        ", max depth " + std::to_string(*reference.max_depth) +
        (facts.indirect_samples > 0 ? ", indirect samples " + std::to_string(facts.indirect_samples) +
                                          ", indirect bounces " + std::to_string(*reference.indirect_bounces)
                                    : std::string()) +
        (reference.caustic_photons ? ", caustic photons " + std::to_string(*reference.caustic_photons)
                                   : std::string()) +
        ", no adaptive sampling, bailout 0, seed " + std::to_string(*reference.seed);
    return reference;
}

}  // namespace

int run_bench(const BenchArgs& args) {
    const int repeat = args.repeat > 0 ? args.repeat : (args.quick ? 1 : 3);
    std::string text, error;
    if (!read_input_file(args.scene, text, error)) return fail(exit_code::io, error);

    lang::ParamTable params;
    if (const int s = evaluate_defines(args.input.defines, params); s != exit_code::ok) return s;

    SceneFacts facts;
    if (const int st = read_scene_facts(args, text, params, facts); st != exit_code::ok) return st;
    SceneOverrides base;
    int width = args.width ? args.width : facts.width, height = args.height ? args.height : facts.height;
    if (args.quick && !args.width && !args.height) {
        const double scale = std::min(1.0, static_cast<double>(quick_max_side) / std::max(width, height));
        width = std::max(1, static_cast<int>(std::lround(width * scale)));
        height = std::max(1, static_cast<int>(std::lround(height * scale)));
    }
    base.width = width;
    base.height = height;
    if (static_cast<long long>(width) * height > max_image_pixels)
        return fail(exit_code::usage, "image size exceeds 2^28 pixels");

    if (const int s = prepare_directory(args.dir, error); s != exit_code::ok) return fail(s, error);
    const std::filesystem::path dir(args.dir);
    for (const char* name : {"bench.csv", "bench.md", "bench.svg"})
        if (!output_directory_exists((dir / name).string(), error)) return fail(exit_code::io, error);

    BenchInfo info;
    info.scene = display_path(args.scene);
    info.width = width;
    info.height = height;
    info.repeat = repeat;
    info.scene_settings = "supersamples " + std::to_string(facts.supersamples) +
                          (facts.area_lights ? ", light samples " + facts.light_grid : std::string()) +
                          ", max depth " + std::to_string(facts.max_depth);

    const SceneOverrides reference = reference_overrides(args, facts, base, info);

    CancelOnSignal signals;
    const bool verbose = !args.quiet;
    if (verbose)
        std::cerr << "bench: reference (" << info.reference_settings << ") at " << width << "x" << height
                  << "\n";
    RunResult ref;
    if (const int s =
            run_setting(args.scene, text, reference, {}, args, params, 1, signals, "bench reference", ref);
        s != exit_code::ok) {
        if (s >= exit_code::sigint) std::cerr << "wsd: interrupted; nothing written\n";
        return s;
    }
    info.reference_seconds = ref.wall;
    const DisplayImage ref_display = to_display(ref.film);

    const std::vector<Setting> settings = sweep(facts, base, args.quick, info.notes);
    std::vector<BenchRow> rows;
    for (size_t i = 0; i < settings.size(); ++i) {
        const Setting& setting = settings[i];
        RunResult run;
        const std::string label = "bench [" + std::to_string(i + 1) + "/" + std::to_string(settings.size()) +
                                  "] " + setting.knob + " " + setting.value;
        if (const int s = run_setting(args.scene, text, setting.overrides, setting.target_error, args, params,
                                      repeat, signals, label, run);
            s != exit_code::ok) {
            if (s >= exit_code::sigint) std::cerr << "wsd: interrupted; nothing written\n";
            return s;
        }
        BenchRow row;
        row.knob = setting.knob;
        row.value = setting.value;
        row.wall_seconds = run.wall;
        row.cpu_seconds = run.cpu;
        row.stats = run.stats;
        row.error = compare(to_display(run.film), ref_display);
        row.estimated_rmse = run.estimated_rmse;
        if (verbose) {
            std::ostringstream line;
            line.precision(4);
            line << "bench: [" << i + 1 << "/" << settings.size() << "] " << row.knob << " " << row.value
                 << ": " << row.wall_seconds << " s, RMSE " << row.error.rmse;
            if (row.estimated_rmse) line << " (estimated " << *row.estimated_rmse << ")";
            line << "\n";
            std::cerr << line.str() << std::flush;
        }
        rows.push_back(std::move(row));
    }
    mark_pareto(rows);

    std::cout << bench_table(rows) << std::flush;
    for (const auto& [name, content] : {std::pair<std::string, std::string>{"bench.csv", bench_csv(rows)},
                                        {"bench.md", bench_markdown(rows, info)},
                                        {"bench.svg", bench_svg(rows, info)}})
        if (!write_file_atomic((dir / name).string(), content, error)) return fail(exit_code::io, error);
    if (verbose) std::cerr << "bench: wrote " << (dir / "bench.csv").string() << ", bench.md, bench.svg\n";
    return exit_code::ok;
}

}  // namespace wsd::app
