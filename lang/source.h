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
    std::string path;  // as given (used in messages)
    std::string text;
    std::vector<uint32_t> line_starts;  // byte offset of each line's start (LF, CRLF, CR end lines)
};

struct LineCol {
    uint32_t line = 1;    // 1-based
    uint32_t column = 1;  // 1-based, in code points
};

// One step of UTF-8 decoding at `pos`: a valid sequence gives its code point and length; an
// invalid byte (bad lead, truncated or overlong sequence, surrogate, > U+10FFFF) gives valid =
// false and length 1, so every byte of a broken sequence is reported on its own.
struct Utf8Step {
    uint32_t codepoint = 0;
    uint32_t length = 1;
    bool valid = true;
};
Utf8Step decode_utf8(std::string_view text, size_t pos);

// Code points (invalid bytes count one each) in text[begin, end): the column distance.
uint32_t count_columns(std::string_view text, size_t begin, size_t end);

// Number of bytes of a leading UTF-8 byte-order mark (0 or 3); the lexer and columns skip it.
size_t bom_length(std::string_view text);

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
