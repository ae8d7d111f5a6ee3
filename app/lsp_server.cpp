// Dispatch and documents. Diagnostics are published once the input is drained, so that a burst
// of changes is checked once, on its last text. Each request runs on the evaluator's large-stack
// thread, as `wsd check` runs scenes.
#include "app/lsp_server.h"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <filesystem>
#include <functional>
#include <thread>

#include "lang/large_stack.h"

namespace wsd::app::lsp {

namespace {

using nlohmann::json;

// JSON-RPC and LSP error codes.
constexpr int kParseError = -32700, kInvalidRequest = -32600, kMethodNotFound = -32601,
              kInvalidParams = -32602, kInternalError = -32603, kServerNotInitialized = -32002;

struct RpcError {
    int code;
    std::string message;
};

bool ends_with(const std::string& s, std::string_view tail) {
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// A line or character: an LSP uinteger (0 to 2^31 - 1), not a negative or fractional number
// (which a plain conversion would wrap or truncate to another position).
uint32_t coordinate(const json& value) {
    if (!value.is_number_unsigned() || value.get<uint64_t>() > 0x7FFFFFFFu)
        throw RpcError{kInvalidParams, "a position's line and character are integers from 0 to 2147483647"};
    return value.get<uint32_t>();
}

Position position_at(const json& p) {
    return {coordinate(p.at("line")), coordinate(p.at("character"))};
}

Position position_of(const json& params) {
    return position_at(params.at("position"));
}

// Runs `work` while another thread watches: `cancel` turns true once `limit` has passed, and with
// `on_input` as soon as a message (or the end of input) arrives, so that a long evaluation gives
// way to it.
void watching(const Reader& reader, bool on_input, std::chrono::milliseconds limit, std::atomic<bool>& cancel,
              const std::function<void()>& work) {
    int wake[2];
    if (::pipe(wake) != 0) return work();  // unwatched
    const auto deadline = std::chrono::steady_clock::now() + limit;
    std::thread watcher([&] {
        for (;;) {
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                deadline - std::chrono::steady_clock::now());
            const int ms =
                left.count() <= 0 ? 0 : static_cast<int>(std::min<long long>(left.count(), 1 << 30));
            bool input = false;
            if (on_input) {
                input = reader.wait_input(ms, wake[0]);
            } else {
                pollfd p{wake[0], POLLIN, 0};
                ::poll(&p, 1, ms);
            }
            pollfd woken{wake[0], POLLIN, 0};
            if (::poll(&woken, 1, 0) > 0) return;  // the work is done
            if (input || std::chrono::steady_clock::now() >= deadline) {
                cancel.store(true);
                return;
            }
        }
    });
    struct Join {
        int* wake;
        std::thread& watcher;
        ~Join() {
            const char byte = 0;
            while (::write(wake[1], &byte, 1) < 0 && errno == EINTR) {
            }
            watcher.join();
            ::close(wake[0]);
            ::close(wake[1]);
        }
    } join{wake, watcher};
    work();
}

json capabilities(Encoding enc) {
    return {{"positionEncoding", enc == Encoding::Utf32 ? "utf-32" : "utf-16"},
            {"textDocumentSync", {{"openClose", true}, {"change", 1}, {"save", {{"includeText", false}}}}},
            {"hoverProvider", true},
            {"completionProvider", {{"triggerCharacters", json::array()}}},
            {"definitionProvider", true},
            {"documentSymbolProvider", true},
            {"documentFormattingProvider", true}};
}

}  // namespace

std::optional<std::string> Server::open_document_text(const std::string& path) const {
    const std::filesystem::path wanted = std::filesystem::path(path).lexically_normal();
    for (const auto& [uri, doc] : documents_)
        if (std::filesystem::path(doc.path).lexically_normal() == wanted) return doc.text;
    return std::nullopt;
}

std::optional<std::string> Server::read_file(const std::string& path) const {
    // An open document's unsaved text, else the file on disk (a regular file only: not /dev/zero
    // or the server's own stdin).
    if (std::optional<std::string> text = open_document_text(path)) return text;
    std::string text, reason;
    if (!read_disk_include(path, text, reason)) return std::nullopt;
    return text;
}

void Server::send(const json& message) {
    // Messages quote the scene's text, which may hold invalid UTF-8: replaced, never thrown.
    write_message(out_fd_, message.dump(-1, ' ', false, json::error_handler_t::replace));
}

void Server::reply_error(const json& id, int code, const std::string& message) {
    send({{"jsonrpc", "2.0"}, {"id", id}, {"error", {{"code", code}, {"message", message}}}});
}

Document& Server::document(const json& params) {
    const std::string uri = params.at("textDocument").at("uri").get<std::string>();
    auto it = documents_.find(uri);
    if (it == documents_.end()) throw RpcError{kInvalidParams, "the document " + uri + " is not open"};
    return it->second;
}

bool Server::publish(const std::string& uri, std::chrono::milliseconds limit) {
    auto it = documents_.find(uri);
    json diags = json::array();
    if (it != documents_.end()) {
        const Document& doc = it->second;
        const Encoding enc = encoding_;
        const FileReader open_text = [this](const std::string& path) { return open_document_text(path); };
        // A check that takes long (a scene running to the language's limits) gives way to the
        // next message, and is done again once the input is drained.
        std::atomic<bool> cancel{false};
        watching(reader_, true, limit, cancel, [&] {
            lang::run_on_large_stack([&] { diags = diagnostics(doc, enc, open_text, &cancel); });
        });
        if (cancel.load()) return false;
    }
    json params = {{"uri", uri}, {"diagnostics", std::move(diags)}};
    if (it != documents_.end()) params["version"] = it->second.version;
    send({{"jsonrpc", "2.0"}, {"method", "textDocument/publishDiagnostics"}, {"params", std::move(params)}});
    return true;
}

void Server::due(const std::string& uri) {
    if (std::find(pending_.begin(), pending_.end(), uri) == pending_.end()) pending_.push_back(uri);
}

void Server::publish_pending() {
    while (!pending_.empty() && !reader_.input_pending()) {
        const std::string uri = pending_.front();
        pending_.erase(pending_.begin());
        // While a document not yet found slow waits, a check gets a second; one that takes longer
        // is slow, and waits behind the others (a slow document among slow ones runs to its end).
        const bool others_wait = std::any_of(pending_.begin(), pending_.end(),
                                             [&](const std::string& other) { return !slow_.count(other); });
        const std::chrono::milliseconds limit =
            others_wait ? std::chrono::milliseconds(1000) : std::chrono::hours(24 * 365);
        try {
            if (publish(uri, limit)) {
                slow_.erase(uri);
            } else {
                // Stopped for a message (checked again after it) or for the documents waiting.
                if (!reader_.input_pending()) slow_.insert(uri);
                pending_.push_back(uri);
            }
        } catch (const std::exception&) {
            // Out of memory or the like on one scene: the server goes on.
        }
    }
}

void Server::changed(const std::string& uri) {
    due(uri);
    slow_.erase(uri);  // its new text may be quick
    // Open documents that may include this one are checked again too (those that name its file).
    auto it = documents_.find(uri);
    if (it == documents_.end()) return;
    const std::string name = std::filesystem::path(it->second.path).filename().string();
    if (name.empty()) return;
    for (auto& [other, doc] : documents_) {
        if (other == uri || doc.text.find(name) == std::string::npos) continue;
        due(other);
        doc.top_level_types.reset();  // the evaluated types may come from the changed file
    }
}

void Server::notification(const std::string& method, const json& params) {
    if (method == "exit") {
        exiting_ = true;
        return;
    }
    if (!initialized_) return;  // dropped before initialize, as the protocol says
    if (method == "textDocument/didOpen") {
        const json& td = params.at("textDocument");
        Document doc;
        doc.uri = td.at("uri").get<std::string>();
        doc.path = uri_to_path(doc.uri);
        doc.text = td.at("text").get<std::string>();
        doc.version = td.value("version", 0LL);
        doc.fragment = ends_with(doc.path, ".wsdi") || td.value("languageId", "") == "wsdi";
        const std::string uri = doc.uri;
        documents_[uri] = std::move(doc);
        changed(uri);
    } else if (method == "textDocument/didChange") {
        Document& doc = document(params);
        const json& changes = params.at("contentChanges");
        if (!changes.is_array() || changes.empty()) return;
        // Full sync is what the server asks for: a change is the whole text. One with a range (a
        // client that sends edits regardless) replaces that range, in order, as LSP defines it.
        std::string text = doc.text;
        for (const json& change : changes) {
            const std::string& replacement = change.at("text").get_ref<const std::string&>();
            if (!change.contains("range")) {
                text = replacement;
                continue;
            }
            const LineIndex index(text);
            const json& range = change.at("range");
            uint32_t begin = index.offset(position_at(range.at("start")), encoding_);
            uint32_t end = index.offset(position_at(range.at("end")), encoding_);
            if (end < begin) std::swap(begin, end);
            text.replace(begin, end - begin, replacement);
        }
        doc.text = std::move(text);
        doc.version = params.at("textDocument").value("version", doc.version + 1);
        doc.parsed.reset();
        doc.top_level_types.reset();
        changed(doc.uri);
    } else if (method == "textDocument/didSave") {
        changed(document(params).uri);
    } else if (method == "textDocument/didClose") {
        const std::string uri = params.at("textDocument").at("uri").get<std::string>();
        // Documents that include it read the file on disk from now on: they are checked again.
        changed(uri);
        documents_.erase(uri);
        pending_.erase(std::remove(pending_.begin(), pending_.end(), uri), pending_.end());
        slow_.erase(uri);
        // Clear what was shown for it.
        send({{"jsonrpc", "2.0"},
              {"method", "textDocument/publishDiagnostics"},
              {"params", {{"uri", uri}, {"diagnostics", json::array()}}}});
    }
    // Anything else ($/cancelRequest, initialized, ...) needs nothing.
}

json Server::request(const std::string& method, const json& params) {
    if (shut_down_) throw RpcError{kInvalidRequest, "the server is shut down"};
    if (method == "initialize") {
        // It may be sent once only.
        if (initialized_) throw RpcError{kInvalidRequest, "the server is already initialized"};
        const json* encodings = nullptr;
        if (params.is_object() && params.contains("capabilities")) {
            const json& caps = params["capabilities"];
            if (caps.is_object() && caps.contains("general") && caps["general"].is_object() &&
                caps["general"].contains("positionEncodings"))
                encodings = &caps["general"]["positionEncodings"];
        }
        encoding_ = Encoding::Utf16;
        if (encodings && encodings->is_array())
            for (const json& e : *encodings)
                if (e == "utf-32") encoding_ = Encoding::Utf32;
        initialized_ = true;
        return {{"capabilities", capabilities(encoding_)},
                {"serverInfo", {{"name", "wsd"}, {"version", WSD_VERSION}}}};
    }
    if (!initialized_) throw RpcError{kServerNotInitialized, "the server is not initialized"};
    if (shut_down_) throw RpcError{kInvalidRequest, "the server is shut down"};
    if (method == "shutdown") {
        shut_down_ = true;
        return nullptr;
    }
    const FileReader reader = [this](const std::string& path) { return read_file(path); };
    json result;
    auto run = [&](auto&& answer) {
        Document& doc = document(params);
        const Encoding enc = encoding_;
        lang::run_on_large_stack([&] { result = answer(doc, enc); });
        return result;
    };
    if (method == "textDocument/hover") {
        // Evaluating the scene for a name's type stops after two seconds (the type is left out then).
        std::atomic<bool> cancel{false};
        watching(reader_, false, std::chrono::seconds(2), cancel, [&] {
            run([&](Document& d, Encoding e) { return hover(d, position_of(params), e, reader, &cancel); });
        });
        return result;
    }
    if (method == "textDocument/completion")
        return run([&](Document& d, Encoding e) { return completion(d, position_of(params), e, reader); });
    if (method == "textDocument/definition")
        return run([&](Document& d, Encoding e) { return definition(d, position_of(params), e, reader); });
    if (method == "textDocument/documentSymbol")
        return run([&](Document& d, Encoding e) { return document_symbols(d, e); });
    if (method == "textDocument/formatting")
        return run([&](Document& d, Encoding e) { return formatting(d, e); });
    throw RpcError{kMethodNotFound, "unknown method '" + method + "'"};
}

void Server::handle(const std::string& body) {
    json message = json::parse(body, nullptr, false);
    if (message.is_discarded()) return reply_error(nullptr, kParseError, "the message is not valid JSON");
    if (!message.is_object() || !message.contains("method") || !message["method"].is_string()) {
        // A response from the client (to nothing the server asked) is ignored; anything else is an error.
        if (message.is_object() && message.contains("id") &&
            (message.contains("result") || message.contains("error")))
            return;
        const json id = message.is_object() && message.contains("id") ? message["id"] : json(nullptr);
        return reply_error(id, kInvalidRequest, "not a JSON-RPC request or notification");
    }
    const std::string method = message["method"].get<std::string>();
    const json params = message.contains("params") ? message["params"] : json::object();
    const bool is_request = message.contains("id");
    const json id = is_request ? message["id"] : json(nullptr);
    if (is_request && !(id.is_number_integer() || id.is_string()))
        return reply_error(nullptr, kInvalidRequest, "a request id must be a number or a string");
    try {
        if (!is_request) return notification(method, params);
        json result = request(method, params);
        send({{"jsonrpc", "2.0"}, {"id", id}, {"result", std::move(result)}});
    } catch (const RpcError& e) {
        if (is_request) reply_error(id, e.code, e.message);
    } catch (const json::exception& e) {
        if (is_request) reply_error(id, kInvalidParams, std::string("invalid params: ") + e.what());
    } catch (const std::exception& e) {
        if (is_request) reply_error(id, kInternalError, std::string("internal error: ") + e.what());
    }
}

int Server::run() {
    std::string body;
    while (!exiting_) {
        if (!pending_.empty() && !reader_.input_pending()) publish_pending();
        const Reader::Result r = reader_.read(body);
        if (r == Reader::Result::End) break;
        if (r == Reader::Result::BadHeader) {
            reply_error(nullptr, kParseError, "bad message header: " + body);
            continue;
        }
        handle(body);
    }
    return shut_down_ ? 0 : 1;
}

}  // namespace wsd::app::lsp
