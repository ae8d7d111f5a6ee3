// `wsd lsp`: the language server on stdin/stdout (app/lsp_server.h).
#include <fcntl.h>
#include <unistd.h>

#include <csignal>

#include "app/commands.h"
#include "app/lsp_server.h"

namespace wsd::app {

namespace {

// The protocol keeps the pipe on a descriptor of its own, and `fd` becomes /dev/null: a scene that
// names /dev/stdin or /dev/stdout (an include, a mesh, a texture) must not read the messages, and
// nothing else may write into them.
int take_over(int fd, int flags) {
    const int own = ::fcntl(fd, F_DUPFD_CLOEXEC, 3);
    const int null = ::open("/dev/null", flags | O_CLOEXEC);
    if (own < 0 || null < 0) {
        if (own >= 0) ::close(own);
        if (null >= 0) ::close(null);
        return fd;
    }
    ::dup2(null, fd);
    ::close(null);
    return own;
}

}  // namespace

int run_lsp() {
    // A client that goes away mid-reply must end the server by the end of its input, not by SIGPIPE.
    std::signal(SIGPIPE, SIG_IGN);
    const int in = take_over(STDIN_FILENO, O_RDONLY);
    const int out = take_over(STDOUT_FILENO, O_WRONLY);
    lsp::Server server(in, out);
    return server.run();
}

}  // namespace wsd::app
