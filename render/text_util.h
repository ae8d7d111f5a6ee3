// Text for messages, shared by every module: a name, path or lexeme in single quotes.
#pragma once

#include <string>
#include <string_view>

namespace wsd::render {

// `s` in single quotes; past `max_len` bytes it is cut (never inside a UTF-8 character) and "..."
// marks the cut, so that a 10 MB token does not become a 10 MB message.
inline std::string quoted_cut(std::string_view s, size_t max_len) {
    const bool cut = s.size() > max_len;
    size_t len = s.size();
    if (cut) {
        len = max_len;
        while (len > 0 && (static_cast<unsigned char>(s[len]) & 0xC0u) == 0x80u) --len;
    }
    std::string out;
    out.reserve(len + 5);
    out += '\'';
    out.append(s.substr(0, len));
    if (cut) out += "...";
    out += '\'';
    return out;
}

// `s` in single quotes. One overload per argument type, so that a call never finds std::quoted
// (<iomanip>) through argument-dependent lookup instead.
inline std::string quoted(std::string_view s) {
    return quoted_cut(s, std::string_view::npos);
}
inline std::string quoted(const std::string& s) {
    return quoted(std::string_view(s));
}
inline std::string quoted(const char* s) {
    return quoted(std::string_view(s));
}

}  // namespace wsd::render
