// The live preview's HTTP server (cpp-httplib): the page at /, server-sent events at /events (a
// JSON snapshot of the PreviewState on every change), the image on show at /image and the
// current snapshot at /status. A slow or idle connection is closed after a second.
#pragma once

#include <memory>
#include <string>
#include <thread>

#include "app/preview_state.h"

namespace wsd::app {

class PreviewServer {
public:
    explicit PreviewServer(const PreviewState& state);
    ~PreviewServer();  // stops and joins
    PreviewServer(const PreviewServer&) = delete;
    PreviewServer& operator=(const PreviewServer&) = delete;

    // Binds to host:port (port 0: any free port); false + error when it cannot.
    bool bind(const std::string& host, int port, std::string& error);
    int port() const { return port_; }

    void start();  // serves on a thread of its own
    // Closes the listening socket and shuts down the open connections (a client that is slow, idle
    // or not reading cannot hold it up). The state must be stopped first, so that open event
    // streams end cleanly.
    void stop();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::thread thread_;
    int port_ = 0;
};

}  // namespace wsd::app
