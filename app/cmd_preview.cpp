// `wsd preview SCENE`: serves a live preview page (preview_server.h), renders the scene in stages
// on a thread of its own (preview_render.h) and renders again whenever the scene or a file it
// names is saved (preview_watch.h), until Ctrl-C or SIGTERM.
#include <csignal>
#include <iostream>
#include <thread>

#include "app/commands.h"
#include "app/exit_codes.h"
#include "app/io_util.h"
#include "app/preview_render.h"
#include "app/preview_server.h"
#include "app/preview_state.h"
#include "app/preview_watch.h"
#include "app/scene_setup.h"
#include "app/signals.h"

namespace wsd::app {

namespace {

constexpr int kPollMs = 100;  // how often the watch list and the signals are looked at

std::string url(const std::string& host, int port) {
    const bool ipv6 = host.find(':') != std::string::npos;
    return "http://" + (ipv6 ? "[" + host + "]" : host) + ":" + std::to_string(port) + "/";
}

}  // namespace

int run_preview(const PreviewArgs& args) {
    std::string error;
    if (args.scene == "-") return fail(exit_code::usage, "preview needs a scene file, not stdin");
    std::string text;  // read once here only to refuse what is not a readable file, as `check` does
    if (!read_input_file(args.scene, text, error)) return fail(exit_code::io, error);
    lang::ParamTable params;
    if (const int status = evaluate_defines(args.defines, params); status != exit_code::ok) return status;
    // A page closed mid-answer must not end the server.
    std::signal(SIGPIPE, SIG_IGN);
    FileWatcher watcher;
    if (!watcher.ok()) return fail(exit_code::io, watcher.error());
    watcher.watch({args.scene}, false);  // before the first load: a save during it is seen

    CancelOnSignal signals;
    PreviewState state;
    PreviewServer server(state);
    if (!server.bind(args.host, args.port, error)) return fail(exit_code::io, error);

    PreviewRenderer renderer(state, args.scene, args.threads, &params);
    std::thread render_thread([&renderer] { renderer.run(); });
    server.start();
    renderer.request();
    std::cout << "wsd preview: " << url(args.host, server.port()) << " shows " << args.scene
              << " (Ctrl-C stops)" << std::endl;

    while (!signals.cancelled()) {
        std::vector<std::string> files;
        bool whole_directories = false;
        if (renderer.take_watch_list(files, whole_directories)) watcher.watch(files, whole_directories);
        if (watcher.wait(kPollMs)) renderer.request();
    }
    renderer.stop();
    state.stop();
    server.stop();
    render_thread.join();
    std::cout << "wsd preview: stopped" << std::endl;
    return exit_code::ok;
}

}  // namespace wsd::app
