// Source files and spans: a file's text, its line table, and byte-offset spans that turn into
// line:column (columns count Unicode code points; a tab is one column).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace wsd::lang {

struct Span {
    uint32_t file = 0;   // index into SourceManager
    uint32_t begin = 0;  // byte offset
    uint32_t end = 0;    // byte offset, exclusive
};

struct SourceFile {
    std::string path;     // as given (used in messages)
    std::string text;
    std::vector<uint32_t> line_starts;  // byte offset of each line's start (LF, CRLF, CR end lines)
};

struct LineCol {
    uint32_t line = 1;    // 1-based
    uint32_t column = 1;  // 1-based, in code points
};

class SourceManager {
public:
    uint32_t add(std::string path, std::string text);  // computes the line table
    const SourceFile& file(uint32_t id) const { return *files_[id]; }
    size_t size() const { return files_.size(); }
    LineCol line_col(uint32_t file, uint32_t offset) const;
    std::string_view line_text(uint32_t file, uint32_t line) const;  // without its line ending
private:
    std::vector<std::unique_ptr<SourceFile>> files_;
};

}  // namespace wsd::lang
