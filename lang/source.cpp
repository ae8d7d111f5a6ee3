// Source files: the line table (LF, CRLF and a lone CR each end a line), byte offset →
// line:column with columns in code points, and the UTF-8 decoding step shared by the lexer and
// the diagnostics printer so that both count columns the same way.
#include "lang/source.h"

#include <algorithm>
#include <limits>

namespace wsd::lang {

Utf8Step decode_utf8(std::string_view text, size_t pos) {
    const auto byte = [&](size_t i) { return static_cast<unsigned char>(text[i]); };
    const unsigned char b0 = byte(pos);
    if (b0 < 0x80) return {b0, 1, true};
    uint32_t length = 0;
    uint32_t cp = 0;
    uint32_t min_cp = 0;
    if (b0 >= 0xC2 && b0 <= 0xDF) {
        length = 2, cp = b0 & 0x1Fu, min_cp = 0x80;
    } else if (b0 >= 0xE0 && b0 <= 0xEF) {
        length = 3, cp = b0 & 0x0Fu, min_cp = 0x800;
    } else if (b0 >= 0xF0 && b0 <= 0xF4) {
        length = 4, cp = b0 & 0x07u, min_cp = 0x10000;
    } else {
        return {b0, 1, false};  // continuation byte, C0/C1 (always overlong) or F5..FF
    }
    if (pos + length > text.size()) return {b0, 1, false};
    for (uint32_t i = 1; i < length; ++i) {
        const unsigned char b = byte(pos + i);
        if ((b & 0xC0u) != 0x80u) return {b0, 1, false};
        cp = (cp << 6) | (b & 0x3Fu);
    }
    if (cp < min_cp || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return {b0, 1, false};
    return {cp, length, true};
}

uint32_t count_columns(std::string_view text, size_t begin, size_t end) {
    end = std::min(end, text.size());
    uint32_t columns = 0;
    size_t i = begin;
    while (i < end) {
        i += static_cast<unsigned char>(text[i]) < 0x80 ? 1 : decode_utf8(text, i).length;
        ++columns;
    }
    return columns;
}

size_t bom_length(std::string_view text) {
    return text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
}

uint32_t SourceManager::add(std::string path, std::string text) {
    auto file = std::make_unique<SourceFile>();
    file->path = std::move(path);
    file->text = std::move(text);
    // Offsets are 32-bit; the parser refuses a larger file, the table stops at the limit.
    const size_t n = std::min<size_t>(file->text.size(), std::numeric_limits<uint32_t>::max());
    const char* s = file->text.data();
    auto& starts = file->line_starts;
    starts.push_back(0);
    for (size_t i = 0; i < n; ++i) {
        const char c = s[i];
        if (c > '\r') continue;  // fast path: every byte above CR is not a line ending
        if (c == '\n') {
            starts.push_back(static_cast<uint32_t>(i + 1));
        } else if (c == '\r') {
            if (i + 1 < n && s[i + 1] == '\n') ++i;
            starts.push_back(static_cast<uint32_t>(i + 1));
        }
    }
    files_.push_back(std::move(file));
    return static_cast<uint32_t>(files_.size() - 1);
}

LineCol SourceManager::line_col(uint32_t file_id, uint32_t offset) const {
    const SourceFile& f = *files_[file_id];
    offset = static_cast<uint32_t>(std::min<size_t>(offset, f.text.size()));
    const auto it = std::upper_bound(f.line_starts.begin(), f.line_starts.end(), offset);
    const size_t line_index = static_cast<size_t>(it - f.line_starts.begin()) - 1;
    size_t start = f.line_starts[line_index];
    if (start == 0) start = std::min<size_t>(bom_length(f.text), offset);
    return {static_cast<uint32_t>(line_index + 1), 1 + count_columns(f.text, start, offset)};
}

std::string_view SourceManager::line_text(uint32_t file_id, uint32_t line) const {
    const SourceFile& f = *files_[file_id];
    if (line == 0 || line > f.line_starts.size()) return {};
    size_t begin = f.line_starts[line - 1];
    size_t end = line < f.line_starts.size() ? f.line_starts[line] : f.text.size();
    if (begin == 0) begin = std::min(bom_length(f.text), end);
    // Strip only this line's own ending: one LF, CRLF or CR.
    if (end > begin && f.text[end - 1] == '\n') --end;
    if (end > begin && f.text[end - 1] == '\r') --end;
    return std::string_view(f.text).substr(begin, end - begin);
}

}  // namespace wsd::lang
