// The language server's answers about one open document: its diagnostics (the whole check of
// `wsd check` on the unsaved text), hover, completion, definitions, symbols and formatting, as
// LSP JSON values.
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "app/lsp_positions.h"
#include "app/lsp_syntax.h"

namespace wsd::app::lsp {

struct Document {
    std::string uri, path, text;
    long long version = 0;
    bool fragment = false;  // a `.wsdi`: checked as a fragment (no camera required)
    // Computed when first needed after each change.
    std::shared_ptr<ParsedFile> parsed;
    std::shared_ptr<const std::map<std::string, std::string>> top_level_types;
    const ParsedFile& syntax();
};

// An included file read from disk: a regular file only (a FIFO such as /dev/stdin would block the
// server or read its own input), else as the interpreter reads it; false with the reason.
bool read_disk_include(const std::string& path, std::string& text, std::string& reason);

nlohmann::json position_json(Position p);
nlohmann::json range_json(const LineIndex& index, uint32_t begin, uint32_t end, Encoding enc);

// Every diagnostic `wsd check` gives for the document's text; those in included files are shown at
// the `include` line of the document, with the chain of includes in the message.
// Included files are an open document's unsaved text (`open_text`), else read from disk.
// `cancel` turning true stops the check early; what it returns then is to be dropped.
nlohmann::json diagnostics(const Document& doc, Encoding enc, const FileReader& open_text,
                           const std::atomic<bool>* cancel = nullptr);

// `cancel` turning true stops evaluating the scene for a name's type (the type is left out).
nlohmann::json hover(Document& doc, Position at, Encoding enc, const FileReader& reader,
                     const std::atomic<bool>* cancel = nullptr);
nlohmann::json completion(Document& doc, Position at, Encoding enc, const FileReader& reader);
nlohmann::json definition(Document& doc, Position at, Encoding enc, const FileReader& reader);
nlohmann::json document_symbols(Document& doc, Encoding enc);
// One edit replacing the whole text with its canonical form; none when it is canonical already or
// does not parse.
nlohmann::json formatting(const Document& doc, Encoding enc);

}  // namespace wsd::app::lsp
