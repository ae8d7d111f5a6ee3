// UTF-16/UTF-32 positions ↔ byte offsets (an invalid UTF-8 byte counts as one unit in both, as it
// is one column in wsd's messages and one replacement character in an editor), and file URIs.
#include "app/lsp_positions.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "lang/source.h"

namespace wsd::app::lsp {

namespace {

uint32_t units(const lang::Utf8Step& step, Encoding e) {
    return e == Encoding::Utf16 && step.valid && step.codepoint > 0xFFFF ? 2 : 1;
}

int hex_value(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

}  // namespace

LineIndex::LineIndex(std::string_view text) : text_(text) {
    starts_.push_back(0);
    for (uint32_t i = 0; i < text.size(); ++i) {
        if (text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
        if (text[i] == '\n' || text[i] == '\r') starts_.push_back(i + 1);
    }
}

void LineIndex::mark_long_lines(uint32_t line) const {
    if (marked_ || line_end(line) - starts_[line] <= kMarkEvery) return;
    marked_ = true;
    for (uint32_t l = 0; l < starts_.size(); ++l) {
        const uint32_t end = line_end(l);
        uint32_t utf16 = 0, utf32 = 0, next_mark = starts_[l] + kMarkEvery;
        for (uint32_t at = starts_[l]; at < end;) {
            if (at >= next_mark) {
                marks_.push_back({at, utf16, utf32});
                next_mark = at + kMarkEvery;
            }
            if (static_cast<unsigned char>(text_[at]) < 0x80) {
                ++utf16, ++utf32, ++at;
                continue;
            }
            const lang::Utf8Step step = lang::decode_utf8(text_, at);
            utf16 += units(step, Encoding::Utf16);
            utf32 += units(step, Encoding::Utf32);
            at += step.length;
        }
    }
}

uint32_t LineIndex::line_end(uint32_t line) const {
    uint32_t end = line + 1 < starts_.size() ? starts_[line + 1] : static_cast<uint32_t>(text_.size());
    while (end > starts_[line] && (text_[end - 1] == '\n' || text_[end - 1] == '\r')) --end;
    return end;
}

uint32_t LineIndex::offset(Position p, Encoding e) const {
    if (p.line >= starts_.size()) return static_cast<uint32_t>(text_.size());
    mark_long_lines(p.line);
    uint32_t at = starts_[p.line];
    const uint32_t end = line_end(p.line);
    uint32_t counted = 0;
    // Start from the line's last mark that is not past the position.
    const auto first = std::lower_bound(marks_.begin(), marks_.end(), at,
                                        [](const Mark& m, uint32_t o) { return m.offset < o; });
    const auto last =
        std::lower_bound(first, marks_.end(), end, [](const Mark& m, uint32_t o) { return m.offset < o; });
    const auto after = std::upper_bound(first, last, p.character, [&](uint32_t c, const Mark& m) {
        return c < (e == Encoding::Utf16 ? m.utf16 : m.utf32);
    });
    if (after != first) {
        at = std::prev(after)->offset;
        counted = e == Encoding::Utf16 ? std::prev(after)->utf16 : std::prev(after)->utf32;
    }
    while (at < end) {
        const lang::Utf8Step step = lang::decode_utf8(text_, at);
        const uint32_t n = units(step, e);
        if (counted + n > p.character) break;
        counted += n;
        at += step.length;
    }
    return std::min(at, end);
}

Position LineIndex::position(uint32_t offset, Encoding e) const {
    offset = std::min(offset, static_cast<uint32_t>(text_.size()));
    const auto it = std::upper_bound(starts_.begin(), starts_.end(), offset);
    const uint32_t line = static_cast<uint32_t>(it - starts_.begin()) - 1;
    mark_long_lines(line);
    Position p{line, 0};
    const uint32_t end = std::min(offset, line_end(line));
    uint32_t at = starts_[line];
    // Start from the line's last mark not past the offset.
    auto mark = std::upper_bound(marks_.begin(), marks_.end(), end,
                                 [](uint32_t o, const Mark& m) { return o < m.offset; });
    if (mark != marks_.begin() && std::prev(mark)->offset >= at) {
        at = std::prev(mark)->offset;
        p.character = e == Encoding::Utf16 ? std::prev(mark)->utf16 : std::prev(mark)->utf32;
    }
    for (; at < end;) {
        const lang::Utf8Step step = lang::decode_utf8(text_, at);
        p.character += units(step, e);
        at += step.length;
    }
    return p;
}

std::string uri_to_path(std::string_view uri) {
    constexpr std::string_view scheme = "file://";
    if (uri.substr(0, scheme.size()) != scheme) return std::string(uri);
    std::string_view rest = uri.substr(scheme.size());
    rest = rest.substr(std::min(rest.find('/'), rest.size()));  // drop an authority ("localhost")
    std::string path;
    for (size_t i = 0; i < rest.size(); ++i) {
        if (rest[i] == '%' && i + 2 < rest.size() && hex_value(rest[i + 1]) >= 0 &&
            hex_value(rest[i + 2]) >= 0) {
            path += static_cast<char>(hex_value(rest[i + 1]) * 16 + hex_value(rest[i + 2]));
            i += 2;
        } else {
            path += rest[i];
        }
    }
    return path;
}

std::string path_to_uri(std::string_view path) {
    std::error_code ec;
    std::string abs = std::filesystem::absolute(std::filesystem::path(path), ec).lexically_normal().string();
    if (ec) abs = std::string(path);
    static const char* hex = "0123456789ABCDEF";
    std::string uri = "file://";
    for (unsigned char c : abs) {
        if (std::isalnum(c) || c == '/' || c == '-' || c == '_' || c == '.' || c == '~') {
            uri += static_cast<char>(c);
        } else {
            uri += '%';
            uri += hex[c >> 4];
            uri += hex[c & 15];
        }
    }
    return uri;
}

}  // namespace wsd::app::lsp
