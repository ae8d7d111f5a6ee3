// Positions as the Language Server Protocol counts them — a line and a character offset in UTF-16
// code units (or code points, when the client offers utf-32) — and the byte offsets wsd's spans
// use; and file URIs to paths and back.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace wsd::app::lsp {

enum class Encoding { Utf16, Utf32 };

struct Position {
    uint32_t line = 0;       // 0-based
    uint32_t character = 0;  // 0-based, in the encoding's units
};

// The lines of a text (ended by LF, CRLF or CR, as LSP and wsd's SourceManager both count them).
class LineIndex {
public:
    explicit LineIndex(std::string_view text);
    // A byte offset of the text; positions past a line's end clamp to it, past the last line to
    // the end of the text.
    uint32_t offset(Position p, Encoding e) const;
    Position position(uint32_t offset, Encoding e) const;
    Position end(Encoding e) const { return position(static_cast<uint32_t>(text_.size()), e); }

private:
    uint32_t line_end(uint32_t line) const;  // the byte offset of its line break
    // A character boundary with the units before it on its line: one every 256 bytes or so on
    // long lines, so that a conversion scans a few hundred bytes, not all of a long line (a scene
    // on one line). Made when a position on a long line is first converted.
    struct Mark {
        uint32_t offset, utf16, utf32;
    };
    static constexpr uint32_t kMarkEvery = 256;
    void mark_long_lines(uint32_t line) const;  // the marks, if `line` is long and they are not made
    std::string_view text_;
    std::vector<uint32_t> starts_;
    mutable std::vector<Mark> marks_;
    mutable bool marked_ = false;
};

// `file:///a/b%20c.wsd` → `/a/b c.wsd`; any other URI (`untitled:1`) is returned as it is.
std::string uri_to_path(std::string_view uri);
std::string path_to_uri(std::string_view path);  // an absolute path; a relative one is made absolute

}  // namespace wsd::app::lsp
