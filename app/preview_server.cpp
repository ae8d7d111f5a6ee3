// The preview's routes on a cpp-httplib server. Each event stream holds one of the server's
// threads; it sends a snapshot whenever the state's version changes and a comment every few
// seconds otherwise (so a closed page is noticed), and ends when the state stops. Short read and
// keep-alive timeouts keep a slow or idle client from holding a thread for long, and stop() shuts
// the open connections down so that none can keep the server from ending.
#include "app/preview_server.h"

#include <httplib.h>
#include <sys/socket.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>

#include "app/connection_shutdown.h"
#include "app/preview_page.h"

namespace wsd::app {

namespace {

constexpr int kKeepAliveMs = 2000;
// Event streams hold a thread each, so at most kEventStreams are served at once (more are
// answered 503) and the other threads stay free for pages, images and kept-alive connections.
constexpr size_t kServerThreads = 64;
constexpr int kEventStreams = 32;
constexpr time_t kReadTimeoutSeconds = 1;     // a request's bytes arrive within this, or it ends
constexpr time_t kIdleConnectionSeconds = 1;  // a kept-alive connection waits this for the next one

}  // namespace

struct PreviewServer::Impl {
    explicit Impl(const PreviewState& s) : state(s) {}
    const PreviewState& state;
    httplib::Server server;
    std::atomic<bool> listening_ended{false};
    std::atomic<int> event_streams{0};
};

namespace {

// One of the event streams counted in Impl::event_streams, given back with the stream.
struct EventStreamSlot {
    explicit EventStreamSlot(std::atomic<int>& c) : count(c) {}
    ~EventStreamSlot() { --count; }
    EventStreamSlot(const EventStreamSlot&) = delete;
    EventStreamSlot& operator=(const EventStreamSlot&) = delete;
    std::atomic<int>& count;
};

}  // namespace

PreviewServer::PreviewServer(const PreviewState& state) : impl_(std::make_unique<Impl>(state)) {
    httplib::Server& server = impl_->server;
    const PreviewState& st = state;
    // cpp-httplib's default sets SO_REUSEPORT, with which a second server would share a port in
    // use instead of being refused it; SO_REUSEADDR alone still allows a quick restart.
    server.set_socket_options([](socket_t sock) {
        int yes = 1;
        setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    });
    server.new_task_queue = [] { return new httplib::ThreadPool(kServerThreads); };
    server.set_read_timeout(kReadTimeoutSeconds, 0);
    server.set_keep_alive_timeout(kIdleConnectionSeconds);
    server.Get("/", [](const httplib::Request&, httplib::Response& res) {
        const std::string_view page = preview_page_html();
        res.set_header("Cache-Control", "no-store");
        res.set_content(page.data(), page.size(), "text/html; charset=utf-8");
    });
    // No route serves part of a resource: a Range header is ignored, as HTTP allows (cpp-httplib
    // would answer the event stream 206 without a Content-Range, and the image in many parts).
    server.set_pre_routing_handler([](const httplib::Request& req, httplib::Response&) {
        const_cast<httplib::Request&>(req).ranges.clear();  // the server's own, not const
        return httplib::Server::HandlerResponse::Unhandled;
    });
    // The preview's resources are read only: other methods on them are 405 with the methods
    // allowed (cpp-httplib's default would be 400 or 404, as for a path that does not exist).
    const auto not_allowed = [](const httplib::Request& req, httplib::Response& res) {
        res.status = 405;
        res.set_header("Allow", "GET, HEAD");
        res.set_content(req.method + " is not allowed on " + req.path + " (use GET or HEAD)\n", "text/plain");
    };
    const char* resources = "/|/status|/image|/events";
    server.Post(resources, not_allowed);
    server.Put(resources, not_allowed);
    server.Patch(resources, not_allowed);
    server.Delete(resources, not_allowed);
    server.Get("/status", [&st](const httplib::Request&, httplib::Response& res) {
        res.set_header("Cache-Control", "no-store");
        res.set_content(snapshot_json(st.snapshot()), "application/json");
    });
    server.Get("/image", [&st](const httplib::Request&, httplib::Response& res) {
        res.set_header("Cache-Control", "no-store");
        std::string png = st.image_png();
        if (png.empty()) {
            res.status = 404;
            res.set_content("no image yet\n", "text/plain");
            return;
        }
        res.set_content(png, "image/png");
    });
    Impl& impl = *impl_;
    server.Get("/events", [&st, &impl](const httplib::Request&, httplib::Response& res) {
        res.set_header("Cache-Control", "no-store");
        if (++impl.event_streams > kEventStreams) {
            --impl.event_streams;
            res.status = 503;
            res.set_header("Retry-After", "5");
            res.set_content("too many open event streams (close some preview pages)\n", "text/plain");
            return;
        }
        auto slot = std::make_shared<EventStreamSlot>(impl.event_streams);
        auto seen = std::make_shared<uint64_t>(~uint64_t(0));
        res.set_chunked_content_provider(
            "text/event-stream", [&st, seen, slot](size_t, httplib::DataSink& sink) {
                bool stopping = false;
                const PreviewSnapshot s = st.wait_change(*seen, kKeepAliveMs, stopping);
                if (stopping) {
                    sink.done();
                    return true;
                }
                std::string message;
                if (s.version != *seen) {
                    *seen = s.version;
                    message = "data: " + snapshot_json(s) + "\n\n";
                } else {
                    message = ": keep-alive\n\n";
                }
                return sink.write(message.data(), message.size());
            });
    });
}

PreviewServer::~PreviewServer() {
    stop();
}

bool PreviewServer::bind(const std::string& host, int port, std::string& error) {
    httplib::Server& server = impl_->server;
    errno = 0;
    bool ok = false;
    if (port == 0) {
        port_ = server.bind_to_any_port(host);
        ok = port_ > 0;
    } else {
        ok = server.bind_to_port(host, port);
        port_ = port;
    }
    if (ok) return true;
    const int err = errno;
    error = "cannot listen on " + host + ":" + std::to_string(port);
    if (err == EADDRINUSE)
        error += ": the port is in use (choose another with --port)";
    else if (err != 0)
        error += std::string(": ") + std::strerror(err);
    else
        error += " (is the host an address of this machine, and the port free?)";
    return false;
}

void PreviewServer::start() {
    thread_ = std::thread([this] {
        impl_->server.listen_after_bind();
        impl_->listening_ended = true;
    });
    // stop() only reaches a server that is running: wait for it (the socket already listens, so
    // no connection is lost meanwhile).
    for (int i = 0; i < 1000 && !impl_->server.is_running(); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
}

void PreviewServer::stop() {
    impl_->server.stop();
    if (!thread_.joinable()) return;
    // The listening socket is closed, so no connection is added; those open end once shut down
    // (a connection accepted just before is shut down on a later round).
    for (int i = 0; i < 500 && !impl_->listening_ended; ++i) {
        shut_connections_down(port_);
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    thread_.join();
}

}  // namespace wsd::app
