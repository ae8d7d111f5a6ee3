// What the language server knows of a document's syntax: its AST (parsed from the unsaved text,
// errors and all), the files it includes (parsed from open documents or from disk), the names
// visible at a position, and the node under a position.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "lang/ast.h"
#include "lang/properties.h"
#include "lang/source.h"

namespace wsd::app::lsp {

// The text of a file by path: an open document's, else the file's on disk; nullopt if unreadable.
using FileReader = std::function<std::optional<std::string>(const std::string& path)>;

// One parsed file; `sources` holds it as file 0.
struct ParsedFile {
    std::string path;
    lang::SourceManager sources;
    lang::Program program;
    const std::string& text() const { return sources.file(0).text; }
};
std::shared_ptr<ParsedFile> parse_text(const std::string& path, std::string text);

// A name a `let`, `fn`, `for` or parameter defines.
struct Definition {
    enum class Kind { Let, Fn, Loop, Param } kind = Kind::Let;
    std::string_view name;
    lang::Span name_span;
    const ParsedFile* file = nullptr;
    const lang::Stmt* stmt = nullptr;  // the LetStmt, FnStmt or ForStmt
    bool top_level = false;            // in the top scope of the scene (the main file's or an include's)
};

// The parsed files of one request: the document and what it includes, each parsed once.
class Workspace {
public:
    Workspace(std::shared_ptr<ParsedFile> main, FileReader reader)
        : main_(std::move(main)), reader_(std::move(reader)) {}
    const ParsedFile& main() const { return *main_; }
    // The file an include statement of `from` names (resolved beside `from`), or null.
    const ParsedFile* included(const ParsedFile& from, const lang::IncludeStmt& stmt);
    std::string include_path(const ParsedFile& from, const lang::IncludeStmt& stmt) const;

    // The names visible at byte `offset` of the main file, the innermost last (a later one of a
    // name shadows an earlier one).
    std::vector<Definition> visible_at(uint32_t offset);
    std::optional<Definition> resolve(std::string_view name, uint32_t offset);

private:
    void add_file_top_level(const ParsedFile& file, std::vector<Definition>& out, int depth);
    void visible_in(const ParsedFile& file, lang::StmtList stmts, uint32_t offset, bool top,
                    std::vector<Definition>& out, int depth);
    std::shared_ptr<ParsedFile> main_;
    FileReader reader_;
    std::map<std::string, std::shared_ptr<ParsedFile>> files_;
    // The included files whose top level visible_at has already added: each once (a file that
    // includes itself, or two files that include the same one, would otherwise be walked again
    // at every level, exponentially often).
    std::set<const ParsedFile*> added_;
};

// What is under or around a position of the main file.
struct Context {
    // The innermost property block around the position (null at statement level) and its table
    // (null for a light of unknown kind).
    const lang::Block* block = nullptr;
    const lang::BlockTable* table = nullptr;
    // The innermost group or CSG body around it, when that is nearer than any block.
    const lang::GroupStmt* group = nullptr;
    bool in_fn = false;
    // The node under the position, if any of these.
    const lang::Item* item = nullptr;              // the position is on its name
    const lang::BlockTable* item_table = nullptr;  // the table of the item's block
    std::string_view name;                         // a name used (identifier or call)
    lang::Span name_span;
    const lang::IncludeStmt* include = nullptr;  // the position is on its path
    const lang::Stmt* defining = nullptr;        // on the name of this let / fn / for
};
Context context_at(const ParsedFile& file, uint32_t offset);

}  // namespace wsd::app::lsp
