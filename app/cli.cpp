// The command line: one CLI11 subcommand per command, value checks that make bad values usage
// errors (status 2), and the mapping of CLI11's own errors onto wsd's exit statuses.
#include <CLI/CLI.hpp>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/exit_codes.h"
#include "app/frames.h"
#include "app/image_files.h"
#include "lang/diagnostics.h"

namespace wsd::app {

namespace {

// An option whose value may not be empty: `-o ""` is a mistake, not the option left out.
const CLI::Validator non_empty(
    [](std::string& text) -> std::string { return text.empty() ? "an empty value" : ""; }, "TEXT");

// A whole decimal integer between lo and hi. CLI11's Range would call "abc" out of range; a
// value that is not an integer at all deserves its own message.
CLI::Validator integer_in(long long lo, long long hi) {
    const std::string range = std::to_string(lo) + " to " + std::to_string(hi);
    return CLI::Validator(
        [lo, hi, range](std::string& text) -> std::string {
            long long value = 0;
            const char* begin = text.data() + (text.size() > 1 && text[0] == '+' ? 1 : 0);
            const char* end = text.data() + text.size();
            const auto [ptr, ec] = std::from_chars(begin, end, value);
            if (text.empty() || ec == std::errc::invalid_argument || ptr != end)
                return "'" + text + "' is not an integer";
            if (ec == std::errc::result_out_of_range || value < lo || value > hi)
                return text + " is not in the range " + range;
            return "";
        },
        "INT in [" + std::to_string(lo) + " - " + std::to_string(hi) + "]");
}

// Whether `text` is, whole, a number strtod reads (into `value`): no leading space, nothing after,
// and decimal, as the language writes numbers (strtod would read 0x10 as 16).
bool read_number(const std::string& text, double& value) {
    if (text.find_first_of("xX") != std::string::npos) return false;
    char* end = nullptr;
    value = std::strtod(text.c_str(), &end);
    return !text.empty() && end == text.c_str() + text.size() &&
           !std::isspace(static_cast<unsigned char>(text[0]));
}

// A finite number > 0 and at most `hi` (written `hi_text`); NaN, infinities, zero and negatives
// are usage errors.
CLI::Validator positive_number(double hi, const std::string& hi_text) {
    return CLI::Validator(
        [hi, hi_text](std::string& text) -> std::string {
            double value = 0;
            if (!read_number(text, value)) return "'" + text + "' is not a number";
            if (!std::isfinite(value) || value <= 0 || value > hi)
                return text + " is not a number > 0 and at most " + hi_text;
            return "";
        },
        "NUMBER > 0");
}

// Any number strtod reads, whole (whether it may be infinite or NaN is the command's to say).
const CLI::Validator a_number(
    [](std::string& text) -> std::string {
        double value = 0;
        return read_number(text, value) ? "" : "'" + text + "' is not a number";
    },
    "NUMBER");

// The arguments of the command line that no option or positional took (`--bogus`), when `e` is
// about a missing or an unexpected argument.
std::vector<std::string> unexpected_arguments(CLI::App& app, const CLI::ParseError& e) {
    std::vector<std::string> rest;
    if (!dynamic_cast<const CLI::RequiredError*>(&e) && !dynamic_cast<const CLI::ExtrasError*>(&e))
        return rest;
    rest = app.remaining();  // `wsd -V`: before any command
    for (CLI::App* sub : app.get_subcommands())
        for (const std::string& arg : sub->remaining()) rest.push_back(arg);
    return rest;
}

// CLI11's own wording of a parse error, in wsd's where CLI11's says little: an option given more
// than once ("--aov: At Most 1 required but received 2"), a value it could not convert, an option
// without its value, and the `unexpected` arguments of the command line.
std::string parse_error_message(const CLI::ParseError& e, const std::vector<std::string>& unexpected) {
    // CLI11 checks required arguments before unexpected ones, so `wsd check --bogus` would say
    // that FILE is required: the unexpected argument is the mistake to name.
    if (!unexpected.empty()) {
        std::string text = unexpected.size() == 1 ? "The following argument was not expected:"
                                                  : "The following arguments were not expected:";
        for (const std::string& arg : unexpected) text += " " + arg;
        // `wsd check -x.wsd`: a file whose name starts with '-' reads as an option.
        std::error_code ec;
        for (const std::string& arg : unexpected)
            if (arg.size() > 1 && arg[0] == '-' && std::filesystem::exists(arg, ec))
                return text + " (to name the file '" + arg + "', write `-- " + arg + "` or `./" + arg + "`)";
        return text;
    }
    const std::string text = e.what();
    // "--width: 1 required INT:INT in [1 - 100000] missing": an option given without its value.
    if (const size_t required_at = text.find(": 1 required ");
        text.starts_with('-') && required_at != std::string::npos && text.ends_with(" missing"))
        return text.substr(0, required_at) + " needs a value";
    const std::string at_most = ": At Most 1 required but received ";
    if (const size_t at = text.find(at_most); at != std::string::npos)
        return text.substr(0, at) + " was given " + text.substr(at + at_most.size()) +
               " times; it takes one value";
    const std::string convert = "Could not convert: ", equals = " = ";
    if (text.rfind(convert, 0) == 0)
        if (const size_t at = text.find(equals, convert.size()); at != std::string::npos)
            return text.substr(convert.size(), at - convert.size()) + ": '" +
                   text.substr(at + equals.size()) + "' is not a value it takes";
    return text;
}

void add_define_option(CLI::App& cmd, std::vector<std::string>& defines) {
    cmd.add_option("-D,--define", defines,
                   "NAME=EXPR: the value param(\"NAME\", DEFAULT) returns in the scene (repeatable)")
        ->allow_extra_args(false)  // `-D a=1 SCENE`: SCENE is not a second define
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

void add_scene_input(CLI::App& cmd, SceneInputArgs& input) {
    add_define_option(cmd, input.defines);
    cmd.add_flag("--no-warnings", input.no_warnings, "print errors only");
}

void usage_hint() {
    std::cerr << "Run `wsd --help` (or `wsd COMMAND --help`) for usage.\n";
}

// The subcommand named `name`, or null.
CLI::App* find_command(CLI::App& app, const std::string& name) {
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
        if (sub->get_name() == name) return sub;
    return nullptr;
}

// "unknown command 'rendr'; did you mean 'render'?" as a usage error.
int unknown_command(CLI::App& app, const std::string& name) {
    std::vector<std::string> names;
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
        names.push_back(sub->get_name());
    const std::string match = lang::closest_match(name, names);
    std::cerr << "wsd: error: unknown command '" << name << "'";
    if (!match.empty()) std::cerr << "; did you mean '" << match << "'?";
    std::cerr << '\n';
    usage_hint();
    return exit_code::usage;
}

int missing_command(CLI::App& app) {
    std::cerr << "wsd: error: a command is required:";
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
        std::cerr << ' ' << sub->get_name();
    std::cerr << '\n';
    usage_hint();
    return exit_code::usage;
}

// `wsd help [COMMAND]`: the help of wsd, or of one command as `wsd COMMAND --help` prints it.
int print_help(CLI::App& app, const std::string& topic) {
    if (topic.empty()) {
        // app.help() would describe the selected subcommand, `help` itself.
        std::cout << app.get_formatter()->make_help(&app, "wsd", CLI::AppFormatMode::Normal) << std::flush;
        return exit_code::ok;
    }
    CLI::App* command = find_command(app, topic);
    if (!command) return unknown_command(app, topic);
    std::cout << command->help("wsd") << std::flush;
    return exit_code::ok;
}

struct RenderOptionRefs {
    int width = 0, height = 0, supersamples = 0, light_samples = 0, max_depth = 0;
    int indirect_samples = 0, indirect_bounces = 0;
    long long seed = 0;
    bool adaptive_aa = false;
    CLI::Option *o_width = nullptr, *o_height = nullptr, *o_supersamples = nullptr,
                *o_light_samples = nullptr, *o_max_depth = nullptr, *o_seed = nullptr,
                *o_indirect_samples = nullptr, *o_indirect_bounces = nullptr;

    void add(CLI::App& cmd) {
        o_width = cmd.add_option("--width", width, "image width in pixels (replaces the scene's)")
                      ->check(integer_in(1, max_image_side));
        o_height = cmd.add_option("--height", height, "image height in pixels")
                       ->check(integer_in(1, max_image_side));
        o_supersamples = cmd.add_option("--supersamples", supersamples, "rays per pixel")
                             ->check(integer_in(1, max_supersamples));
        o_light_samples =
            cmd.add_option("--light-samples", light_samples, "every area light becomes an N×N grid")
                ->check(integer_in(1, max_light_grid_side));
        o_max_depth = cmd.add_option("--max-depth", max_depth, "reflection/refraction depth limit")
                          ->check(integer_in(0, max_depth_limit));
        o_seed = cmd.add_option("--seed", seed, "random seed (0 … 4294967295)")
                     ->check(integer_in(0LL, 4294967295LL));
        cmd.add_flag("--adaptive-aa", adaptive_aa, "adaptive supersampling (full grid only at edges)");
        o_indirect_samples =
            cmd.add_option("--indirect-samples", indirect_samples, "indirect paths a camera sample (0 = off)")
                ->check(integer_in(0, render::kMaxIndirectSamples));
        o_indirect_bounces = cmd.add_option("--indirect-bounces", indirect_bounces,
                                            "the most diffuse reflections a path makes")
                                 ->check(integer_in(1, render::kMaxIndirectBounces));
    }

    SceneOverrides overrides() const {
        SceneOverrides o;
        if (o_width->count()) o.width = width;
        if (o_height->count()) o.height = height;
        if (o_supersamples->count()) o.supersamples = supersamples;
        if (o_light_samples->count()) o.light_samples = light_samples;
        if (o_max_depth->count()) o.max_depth = max_depth;
        if (o_seed->count()) o.seed = static_cast<uint32_t>(seed);
        if (adaptive_aa) o.adaptive_supersampling = true;
        if (o_indirect_samples->count()) o.indirect_samples = indirect_samples;
        if (o_indirect_bounces->count()) o.indirect_bounces = indirect_bounces;
        return o;
    }
};

CLI::App* add_render_command(CLI::App& app, RenderArgs& args, RenderOptionRefs& refs) {
    CLI::App* cmd = app.add_subcommand("render", "render an image");
    cmd->add_option("SCENE", args.scene, "scene file; - = stdin")->required();
    cmd->add_option("-o,--output", args.output,
                    "output image (.png .jpg .jpeg .bmp .tga .hdr .pfm .exr); default ./NAME.png")
        ->check(non_empty);
    refs.add(*cmd);
    add_scene_input(*cmd, args.input);
    cmd->add_option("--threads", args.threads, "render threads; 0 = all cores")->check(integer_in(0, 4096));
    cmd->add_flag("--no-bvh", args.no_bvh, "test every object (no bounding volume hierarchy)");
    cmd->add_flag("--general", args.general,
                  "use the general integrator with every effect enabled (same image, slower; for checking)");
    cmd->add_flag("--stats", args.stats, "print render statistics at the end");
    cmd->add_option("--stats-json", args.stats_json, "write render statistics as JSON; - = stdout")
        ->check(non_empty)
        ->transform([](std::string path) { return path == "-" ? std::string("/dev/stdout") : path; });
    cmd->add_flag("-q,--quiet", args.quiet, "no progress output");
    cmd->add_flag("--adaptive-lights", args.adaptive_lights, "adaptive sampling on every area light");
    cmd->add_option("--tile", args.tile, "render tile I of N (rows), e.g. 3/8; output a .pfm tile")
        ->check(non_empty);
    cmd->add_option("--region", args.region, "render the pixels x0,y0,x1,y1 (half-open)")->check(non_empty);
    cmd->add_option("--target-error", args.target_error,
                    "E: progressive passes until every pixel's estimated display-space error is at most E")
        ->check(positive_number(1e9, "1e9"));
    cmd->add_option("--time-limit", args.time_limit,
                    "T: progressive passes until T seconds have passed (checked between passes)")
        ->check(positive_number(1e9, "1e9 seconds"));
    cmd->add_option("--aov", args.aov,
                    "auxiliary images, any of albedo,normal,depth,samples: layers of an .exr, else "
                    "NAME.albedo.pfm …")
        ->check(CLI::Validator(
            [](std::string& text) {
                AovSelection selection;
                std::string error;
                return parse_aov_list(text, selection, error) ? std::string() : error;
            },
            "LIST"));
    cmd->add_option("--frames", args.frames,
                    "A-B: render frames A to B, clock going from 0 to 1; '#'s in -o become the frame number")
        ->check(non_empty);
    cmd->add_option("--frame", args.frame, "N: render only frame N of --frames (a farm's task)")
        ->check(integer_in(0, max_frame_number));
    cmd->add_option("--clock", args.clock, "X: the value of clock in a still (default 0)")->check(a_number);
    return cmd;
}

CLI::App* add_bench_command(CLI::App& app, BenchArgs& args) {
    CLI::App* cmd = app.add_subcommand("bench", "measure error against time for each setting");
    cmd->add_option("SCENE", args.scene, "scene file")->required();
    add_scene_input(*cmd, args.input);
    cmd->add_option("-o,--output", args.dir, "directory for bench.csv, bench.md, bench.svg (default .)")
        ->check(non_empty);
    cmd->add_option("--repeat", args.repeat,
                    "runs per setting; the median is reported (default 3, or 1 with --quick)")
        ->check(integer_in(1, 1000));
    cmd->add_flag("--quick", args.quick,
                  "a small sweep at a small size (at most 32 pixels a side; for tests)");
    cmd->add_option("--reference-supersamples", args.reference_supersamples,
                    "supersamples of the reference image (default 256; the reference uses another seed)")
        ->check(integer_in(1, max_supersamples));
    cmd->add_option("--reference-light-samples", args.reference_light_samples,
                    "N: area lights use an N×N grid in the reference (default 16, or 8 with --quick)")
        ->check(integer_in(1, max_light_grid_side));
    cmd->add_option("--reference-depth", args.reference_depth,
                    "max depth of the reference (default max(scene, 10))")
        ->check(integer_in(0, max_depth_limit));
    cmd->add_option("--threads", args.threads, "render threads; 0 = all cores")->check(integer_in(0, 4096));
    cmd->add_option("--width", args.width, "image width (default the scene's)")
        ->check(integer_in(1, max_image_side));
    cmd->add_option("--height", args.height, "image height")->check(integer_in(1, max_image_side));
    cmd->add_flag("-q,--quiet", args.quiet, "no progress output");
    return cmd;
}

}  // namespace

int run_cli(int argc, char** argv) {
    if (std::getenv("WSD_TEST_INTERNAL_ERROR"))  // lets the tests reach exit status 4
        throw std::logic_error("forced by WSD_TEST_INTERNAL_ERROR");

    CLI::App app{"wsd: a scene-description language and a Whitted ray tracer", "wsd"};
    app.set_version_flag("--version", std::string("wsd ") + WSD_VERSION);
    app.require_subcommand(1);
    app.footer(
        "Exit status: 0 ok, 1 input errors, 2 usage errors, 3 unreadable input or "
        "unwritable output, 4 internal error, 130/143 interrupted.");

    CheckArgs check_args;
    CLI::App* check =
        app.add_subcommand("check", "parse, evaluate, load referenced files and validate; render nothing");
    check
        ->add_option("FILE", check_args.files,
                     "scene files (.wsd), fragments (.wsdi) or directories; - = stdin")
        ->required();
    check->add_flag("--effects", check_args.effects,
                    "list the effects the scene uses and the objects that call for each");
    add_scene_input(*check, check_args.input);
    check
        ->add_option_function<std::string>(
            "--format", [&](const std::string& f) { check_args.json = f == "json"; },
            "text (default) or json: the diagnostics as one JSON array on stdout")
        ->check(CLI::IsMember({"text", "json"}));

    AstArgs ast_args;
    CLI::App* ast = app.add_subcommand("ast", "print the abstract syntax tree");
    ast->add_option("FILE", ast_args.file, "scene file; - = stdin")->required();

    RenderArgs render_args;
    RenderOptionRefs render_refs;
    CLI::App* render = add_render_command(app, render_args, render_refs);

    DiffArgs diff_args;
    CLI::App* diff = app.add_subcommand("diff", "compare two images (RMSE, PSNR, max error, SSIM)");
    diff->add_option("A", diff_args.a, "first image")->required();
    diff->add_option("B", diff_args.b, "second image")->required();
    diff->add_option("-o,--output", diff_args.heatmap, "write a heat map of the per-pixel error")
        ->check(non_empty);

    MergeArgs merge_args;
    CLI::App* merge = app.add_subcommand("merge", "assemble tiles rendered with --tile or --region");
    merge->add_option("TILE", merge_args.tiles, "tile files (.pfm)")->required();
    merge->add_option("-o,--output", merge_args.output, "output image")->required()->check(non_empty);

    BenchArgs bench_args;
    CLI::App* bench = add_bench_command(app, bench_args);

    FmtArgs fmt_args;
    CLI::App* fmt = app.add_subcommand("fmt", "print the canonical layout of scene files (-i: rewrite them)");
    fmt->add_option("FILE", fmt_args.files, "files (.wsd, .wsdi) or directories; - = stdin")->required();
    CLI::Option* fmt_in_place =
        fmt->add_flag("-i,--in-place", fmt_args.in_place, "rewrite the files that are not canonical");
    fmt->add_flag("--check", fmt_args.check, "change nothing; name the files that are not canonical")
        ->excludes(fmt_in_place);
    CLI::App* lsp = app.add_subcommand("lsp", "a language server on stdin/stdout (Language Server Protocol)");
    PreviewArgs preview_args;
    CLI::App* preview = app.add_subcommand("preview", "a live preview page that renders again on every save");
    preview->add_option("SCENE", preview_args.scene, "scene file")->required();
    preview->add_option("--port", preview_args.port, "TCP port (default 8642; 0 = any free one)")
        ->check(integer_in(0, 65535));
    preview->add_option("--host", preview_args.host, "address to serve on (default 127.0.0.1)")
        ->check(non_empty);
    add_define_option(*preview, preview_args.defines);
    preview->add_option("--threads", preview_args.threads, "render threads; 0 = all cores")
        ->check(integer_in(0, 4096));

    std::string help_topic;
    CLI::App* help = app.add_subcommand("help", "print the help of wsd or of one command");
    help->add_option("COMMAND", help_topic, "the command to explain");

    // CLI11 reports both a missing and an unknown first word as "A subcommand is required".
    if (argc < 2) return missing_command(app);
    if (argv[1][0] != '-' && !find_command(app, argv[1])) return unknown_command(app, argv[1]);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) {
            app.exit(e);  // --help, --version
            return exit_code::ok;
        }
        std::cerr << "wsd: error: " << parse_error_message(e, unexpected_arguments(app, e)) << '\n';
        usage_hint();
        return exit_code::usage;
    }

    if (*help) return print_help(app, help_topic);
    if (*check) return run_check(check_args);
    if (*ast) return run_ast(ast_args);
    if (*fmt) return run_fmt(fmt_args);
    if (*render) {
        render_args.overrides = render_refs.overrides();
        return run_render(render_args);
    }
    if (*diff) return run_diff(diff_args);
    if (*merge) return run_merge(merge_args);
    if (*bench) return run_bench(bench_args);
    if (*lsp) return run_lsp();
    if (*preview) return run_preview(preview_args);
    return exit_code::usage;
}

}  // namespace wsd::app
