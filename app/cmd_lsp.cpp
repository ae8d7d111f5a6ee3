// `wsd lsp`: the language server on stdin/stdout (app/lsp_server.h).
#include <unistd.h>

#include <csignal>

#include "app/commands.h"
#include "app/lsp_server.h"

namespace wsd::app {

int run_lsp() {
    // A client that goes away mid-reply must end the server by the end of its input, not by SIGPIPE.
    std::signal(SIGPIPE, SIG_IGN);
    lsp::Server server(STDIN_FILENO, STDOUT_FILENO);
    return server.run();
}

}  // namespace wsd::app
