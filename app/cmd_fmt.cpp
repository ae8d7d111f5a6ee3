// `wsd fmt FILE...`: the canonical form of each file (lang::format_source) on stdout, or with -i
// written over the file (atomically, and only when it changes), or with --check compared only.
// SIGINT and SIGTERM stop it between files, or in a rewrite with no temporary file left.
// A file that does not parse gets its diagnostics, as `wsd check` prints them, and is not touched.
#include <filesystem>
#include <iostream>

#include "app/commands.h"
#include "app/exit_codes.h"
#include "app/file_args.h"
#include "app/io_util.h"
#include "app/scene_setup.h"
#include "app/signals.h"
#include "lang/format.h"

namespace wsd::app {

namespace {

int worse(int a, int b) {
    const auto rank = [](int s) { return s == exit_code::ok ? 0 : s == exit_code::input_error ? 1 : 2; };
    return rank(b) > rank(a) ? b : a;
}

// Rewrites `path` with `text`: a new file with its permission bits, renamed over it. A symbolic
// link stays: the file it leads to is rewritten. A signal stops the write and leaves the file as
// it was.
int rewrite(const std::string& path, const std::string& text, const CancelOnSignal& signals) {
    namespace fs = std::filesystem;
    std::error_code ec;
    std::string target = path;
    if (fs::is_symlink(path, ec)) {
        target = fs::canonical(path, ec).string();
        if (ec) return fail(exit_code::io, "cannot write '" + path + "': " + ec.message());
    }
    const fs::perms perms = fs::status(target, ec).permissions();
    AtomicWrite how;
    how.cancel = signals.flag();
    if (!ec) how.mode = static_cast<unsigned>(perms & fs::perms::mask);
    std::string error;
    if (!write_file_atomic(target, text, error, how))
        return signals.cancelled() ? exit_code::ok : fail(exit_code::io, error);
    return exit_code::ok;
}

}  // namespace

int run_fmt(const FmtArgs& args) {
    const CancelOnSignal signals;
    const std::vector<std::string> paths = expand_scene_paths(args.files);
    int status = exit_code::ok;
    for (const std::string& path : paths) {
        if (signals.cancelled()) break;
        if (path == "-" && args.in_place) {
            status = worse(status, fail(exit_code::usage, "-i cannot rewrite stdin"));
            continue;
        }
        std::string text, error;
        if (!read_input_file(path, text, error)) {
            if (signals.cancelled()) break;
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
            if (*formatted != text) status = worse(status, rewrite(path, *formatted, signals));
        } else {
            std::cout << *formatted;
        }
    }
    std::cout << std::flush;
    if (signals.cancelled()) {
        std::cerr << (args.in_place ? "wsd: interrupted; no file is left half written\n"
                                    : "wsd: interrupted\n");
        return signals.exit_status();
    }
    return status;
}

}  // namespace wsd::app
