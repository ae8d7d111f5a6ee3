// `wsd fmt FILE...`: the canonical form of each file (lang::format_source) on stdout, or with -i
// written over the file (atomically, and only when it changes), or with --check compared only.
// A file that does not parse gets its diagnostics, as `wsd check` prints them, and is not touched.
#include <filesystem>
#include <iostream>

#include "app/commands.h"
#include "app/exit_codes.h"
#include "app/file_args.h"
#include "app/io_util.h"
#include "app/scene_setup.h"
#include "lang/format.h"

namespace wsd::app {

namespace {

int worse(int a, int b) {
    const auto rank = [](int s) { return s == exit_code::ok ? 0 : s == exit_code::input_error ? 1 : 2; };
    return rank(b) > rank(a) ? b : a;
}

// Rewrites `path` with `text`, keeping its permission bits.
int rewrite(const std::string& path, const std::string& text) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::perms perms = fs::status(path, ec).permissions();
    std::string error;
    if (!write_file_atomic(path, text, error)) return fail(exit_code::io, error);
    if (!ec) fs::permissions(path, perms, ec);
    return exit_code::ok;
}

}  // namespace

int run_fmt(const FmtArgs& args) {
    const std::vector<std::string> paths = expand_scene_paths(args.files);
    int status = exit_code::ok;
    for (const std::string& path : paths) {
        if (path == "-" && args.in_place) {
            status = worse(status, fail(exit_code::usage, "-i cannot rewrite stdin"));
            continue;
        }
        std::string text, error;
        if (!read_input_file(path, text, error)) {
            status = worse(status, fail(exit_code::io, error));
            continue;
        }
        lang::SourceManager sources;
        lang::Diagnostics diags;
        const uint32_t file = sources.add(display_path(path), text);
        const std::optional<std::string> formatted = lang::format_source(file, sources, diags);
        if (!formatted) {
            std::cerr << lang::format_diagnostics(diags, sources);
            status = worse(status, exit_code::input_error);
            continue;
        }
        if (args.check) {
            if (*formatted != text) {
                std::cout << display_path(path) << "\n";
                status = worse(status, exit_code::input_error);
            }
        } else if (args.in_place) {
            if (*formatted != text) status = worse(status, rewrite(path, *formatted));
        } else {
            std::cout << *formatted;
        }
    }
    std::cout << std::flush;
    return status;
}

}  // namespace wsd::app
