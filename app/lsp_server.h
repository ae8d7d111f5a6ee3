// The language server: reads JSON-RPC messages, keeps the open documents, answers requests and
// publishes diagnostics. Every malformed message gets a JSON-RPC error (or, for a notification,
// is dropped); nothing a client sends ends it but `exit` or the end of its input.
#pragma once

#include <chrono>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "app/lsp_analysis.h"
#include "app/lsp_transport.h"

namespace wsd::app::lsp {

class Server {
public:
    Server(int in_fd, int out_fd) : reader_(in_fd), out_fd_(out_fd) {}
    // Serves until `exit` or the end of input; returns the exit status (0 after `shutdown`, else 1).
    int run();

private:
    void handle(const std::string& body);
    nlohmann::json request(const std::string& method, const nlohmann::json& params);
    void notification(const std::string& method, const nlohmann::json& params);
    void changed(const std::string& uri);  // its diagnostics, and those of documents naming it, are due
    // False when the check stopped early, for input or at `limit` (the document is still due).
    bool publish(const std::string& uri, std::chrono::milliseconds limit);
    void due(const std::string& uri);  // its diagnostics are due (once in the queue)
    void publish_pending();
    void send(const nlohmann::json& message);
    void reply_error(const nlohmann::json& id, int code, const std::string& message);
    Document& document(const nlohmann::json& params);
    std::optional<std::string> open_document_text(const std::string& path) const;
    std::optional<std::string> read_file(const std::string& path) const;

    Reader reader_;
    int out_fd_;
    Encoding encoding_ = Encoding::Utf16;
    bool initialized_ = false, shut_down_ = false, exiting_ = false;
    std::map<std::string, Document> documents_;  // by URI
    std::vector<std::string> pending_;           // URIs whose diagnostics are due, oldest first
    std::set<std::string> slow_;                 // those whose check was stopped at its time limit
};

}  // namespace wsd::app::lsp
