// The lexer: whitespace and (nested) comments, numbers scanned by hand and converted with
// std::from_chars (locale-free, range-checked), strings with their escapes, identifiers and
// keywords, punctuation; and every lexical error: NUL bytes, invalid UTF-8, stray characters.
#include "lang/lexer.h"

#include <cctype>
#include <charconv>
#include <cstdio>
#include <limits>

#include "render/text_util.h"

namespace wsd::lang {

namespace {

struct Keyword {
    std::string_view word;
    TokenKind kind;
};

constexpr Keyword keywords[] = {
    {"let", TokenKind::Let},
    {"for", TokenKind::For},
    {"in", TokenKind::In},
    {"if", TokenKind::If},
    {"else", TokenKind::Else},
    {"include", TokenKind::Include},
    {"settings", TokenKind::Settings},
    {"camera", TokenKind::Camera},
    {"light", TokenKind::Light},
    {"sphere", TokenKind::Sphere},
    {"box", TokenKind::Box},
    {"triangle", TokenKind::Triangle},
    {"plane", TokenKind::Plane},
    {"mesh", TokenKind::Mesh},
    {"cylinder", TokenKind::Cylinder},
    {"cone", TokenKind::Cone},
    {"torus", TokenKind::Torus},
    {"disc", TokenKind::Disc},
    {"fn", TokenKind::Fn},
    {"return", TokenKind::Return},
    {"group", TokenKind::Group},
    {"union", TokenKind::Union},
    {"intersection", TokenKind::Intersection},
    {"difference", TokenKind::Difference},
    {"object", TokenKind::Object},
    {"material", TokenKind::Material},
    {"image", TokenKind::Image},
    {"checker", TokenKind::Checker},
    {"perlin", TokenKind::Perlin},
    {"true", TokenKind::True},
    {"false", TokenKind::False},
};

bool is_digit(unsigned char c) {
    return c >= '0' && c <= '9';
}
bool is_ident_start(unsigned char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}
bool is_ident_char(unsigned char c) {
    return is_ident_start(c) || is_digit(c);
}

std::string hex_byte(unsigned char b) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "0x%02x", b);
    return buf;
}

// POV-Ray's directive after a '#' (its length, and wsd's spelling as help), or {0, general help}.
std::pair<size_t, std::string> preprocessor_help(std::string_view rest) {
    static const std::pair<std::string_view, std::string_view> directives[] = {
        {"declare", "POV-Ray's '#declare NAME = ...' is 'let NAME = ...' in wsd"},
        {"local", "POV-Ray's '#local NAME = ...' is 'let NAME = ...' in wsd (a let is local to its block)"},
        {"include", "POV-Ray's '#include \"file\"' is 'include \"file\"' in wsd"},
        {"if", "POV-Ray's '#if (c) ... #end' is 'if c { ... }' in wsd"},
        {"for", "POV-Ray's '#for (i, a, b) ... #end' is 'for i in a .. b + 1 { ... }' in wsd"},
        {"while", "wsd has no while loop: write 'for i in a .. b { ... }' or loop over a list"},
        {"end", "wsd closes a loop or an 'if' with '}'"},
        {"version", "wsd needs no version line"},
    };
    for (const auto& [word, help] : directives) {
        if (rest.substr(0, word.size()) != word) continue;
        const char next = rest.size() > word.size() ? rest[word.size()] : ' ';
        if (!std::isalnum(static_cast<unsigned char>(next)) && next != '_')
            return {word.size(), std::string(help)};
    }
    return {0, "there is no preprocessor: use let, for, if and include"};
}

std::string code_point_name(uint32_t cp) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "U+%04X", cp);
    return buf;
}

// Quoted lexeme for a message, cut so that a 10 MB token does not become a 10 MB message.
std::string quoted(std::string_view s) {
    return render::quoted_cut(s, 40);
}

}  // namespace

TokenKind keyword_kind(std::string_view word) {
    if (word.size() < 2 || word.size() > 12) return TokenKind::Ident;  // the longest is "intersection"
    for (const Keyword& k : keywords)
        if (k.word == word) return k.kind;
    return TokenKind::Ident;
}

std::string_view token_spelling(TokenKind kind) {
    for (const Keyword& k : keywords)
        if (k.kind == kind) return k.word;
    switch (kind) {
        case TokenKind::LBrace:
            return "{";
        case TokenKind::RBrace:
            return "}";
        case TokenKind::LParen:
            return "(";
        case TokenKind::RParen:
            return ")";
        case TokenKind::LBracket:
            return "[";
        case TokenKind::RBracket:
            return "]";
        case TokenKind::Less:
            return "<";
        case TokenKind::Greater:
            return ">";
        case TokenKind::Comma:
            return ",";
        case TokenKind::Assign:
            return "=";
        case TokenKind::Dot:
            return ".";
        case TokenKind::DotDot:
            return "..";
        case TokenKind::Plus:
            return "+";
        case TokenKind::Minus:
            return "-";
        case TokenKind::Star:
            return "*";
        case TokenKind::Slash:
            return "/";
        case TokenKind::Percent:
            return "%";
        case TokenKind::EqEq:
            return "==";
        case TokenKind::NotEq:
            return "!=";
        case TokenKind::LessEq:
            return "<=";
        case TokenKind::GreaterEq:
            return ">=";
        case TokenKind::AndAnd:
            return "&&";
        case TokenKind::OrOr:
            return "||";
        case TokenKind::Bang:
            return "!";
        default:
            return "";
    }
}

bool is_statement_keyword(TokenKind kind) {
    switch (kind) {
        case TokenKind::Let:
        case TokenKind::For:
        case TokenKind::If:
        case TokenKind::Include:
        case TokenKind::Settings:
        case TokenKind::Camera:
        case TokenKind::Light:
        case TokenKind::Sphere:
        case TokenKind::Box:
        case TokenKind::Triangle:
        case TokenKind::Plane:
        case TokenKind::Mesh:
        case TokenKind::Cylinder:
        case TokenKind::Cone:
        case TokenKind::Torus:
        case TokenKind::Disc:
        case TokenKind::Group:
        case TokenKind::Union:
        case TokenKind::Intersection:
        case TokenKind::Difference:
        case TokenKind::Object:
        case TokenKind::Fn:
        case TokenKind::Return:
            return true;
        default:
            return false;
    }
}

Lexer::Lexer(uint32_t file, std::string_view text, Diagnostics* diags)
    : file_(file), text_(text), diags_(diags) {
    end_ = static_cast<uint32_t>(std::min<size_t>(text.size(), std::numeric_limits<uint32_t>::max()));
    pos_ = static_cast<uint32_t>(bom_length(text));
    if (text.size() >= 2 &&
        ((text[0] == '\xFF' && text[1] == '\xFE') || (text[0] == '\xFE' && text[1] == '\xFF'))) {
        error(0, 0, 2, "file is UTF-16 (it starts with a UTF-16 byte-order mark)", "save the file as UTF-8");
        pos_ = end_;
    }
}

void Lexer::error(uint32_t scan, uint32_t begin, uint32_t end, std::string message, std::string help) {
    if (!diags_ || scan < reported_until_) return;
    reported_until_ = scan + 1;
    Diagnostic& d = diags_->error({file_, begin, end}, std::move(message));
    if (!help.empty()) d.help.push_back(std::move(help));
}

unsigned char Lexer::at(uint32_t i) const {
    return i < end_ ? static_cast<unsigned char>(text_[i]) : 0;
}

uint32_t Lexer::check_byte(uint32_t i) {
    const unsigned char c = at(i);
    if (c == 0) {
        error(i, i, i + 1, "invalid NUL byte (byte offset " + std::to_string(i) + ")");
        return 1;
    }
    const Utf8Step step = decode_utf8(text_.substr(0, end_), i);
    if (!step.valid)
        error(i, i, i + 1, "invalid UTF-8 byte " + hex_byte(c) + " (byte offset " + std::to_string(i) + ")");
    return step.length;
}

void Lexer::line_comment() {
    uint32_t p = pos_ + 2;
    while (p < end_) {
        const unsigned char c = at(p);
        if (c == '\n' || c == '\r') break;
        p += (c >= 0x80 || c == 0) ? check_byte(p) : 1;
    }
    pos_ = p;
}

void Lexer::block_comment() {
    const uint32_t open = pos_;
    uint32_t p = pos_ + 2;
    int depth = 1;
    while (p < end_) {
        const unsigned char c = at(p);
        if (c == '*' && at(p + 1) == '/') {
            p += 2;
            if (--depth == 0) {
                pos_ = p;
                return;
            }
        } else if (c == '/' && at(p + 1) == '*') {
            p += 2;
            ++depth;
        } else {
            p += (c >= 0x80 || c == 0) ? check_byte(p) : 1;
        }
    }
    pos_ = end_;
    error(end_, open, open + 2, "unterminated block comment");
}

Token Lexer::next() {
    for (;;) {
        if (diags_ && diags_->too_many()) return {TokenKind::Eof, end_, end_, 0};
        // Whitespace and comments.
        while (pos_ < end_) {
            const unsigned char c = at(pos_);
            if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
                ++pos_;
            } else if (c == '/' && (at(pos_ + 1) == '/' || at(pos_ + 1) == '*')) {
                const uint32_t begin = pos_;
                if (at(pos_ + 1) == '/')
                    line_comment();
                else
                    block_comment();
                if (comments_) comments_->push_back({file_, begin, pos_});
            } else {
                break;
            }
        }
        if (pos_ >= end_) return {TokenKind::Eof, end_, end_, 0};
        const uint32_t begin = pos_;
        const unsigned char c = at(pos_);
        const unsigned char c1 = at(pos_ + 1);
        const auto one = [&](TokenKind k) {
            pos_ += 1;
            return make(k, begin);
        };
        const auto two = [&](TokenKind k) {
            pos_ += 2;
            return make(k, begin);
        };
        switch (c) {
            case '{':
                return one(TokenKind::LBrace);
            case '}':
                return one(TokenKind::RBrace);
            case '(':
                return one(TokenKind::LParen);
            case ')':
                return one(TokenKind::RParen);
            case '[':
                return one(TokenKind::LBracket);
            case ']':
                return one(TokenKind::RBracket);
            case ',':
                return one(TokenKind::Comma);
            case '+':
                return one(TokenKind::Plus);
            case '-':
                return one(TokenKind::Minus);
            case '*':
                return one(TokenKind::Star);
            case '/':
                return one(TokenKind::Slash);
            case '%':
                return one(TokenKind::Percent);
            case '<':
                return c1 == '=' ? two(TokenKind::LessEq) : one(TokenKind::Less);
            case '>':
                return c1 == '=' ? two(TokenKind::GreaterEq) : one(TokenKind::Greater);
            case '=':
                return c1 == '=' ? two(TokenKind::EqEq) : one(TokenKind::Assign);
            case '!':
                return c1 == '=' ? two(TokenKind::NotEq) : one(TokenKind::Bang);
            case '&':
                if (c1 == '&') return two(TokenKind::AndAnd);
                break;
            case '|':
                if (c1 == '|') return two(TokenKind::OrOr);
                break;
            case '.':
                if (c1 == '.') return two(TokenKind::DotDot);
                if (is_digit(c1)) return number(begin);
                return one(TokenKind::Dot);
            case '"':
                return string_literal(begin);
            default:
                if (is_digit(c)) return number(begin);
                if (is_ident_start(c)) return identifier(begin);
                break;
        }
        bad_bytes(begin);
    }
}

Token Lexer::number(uint32_t begin) {
    uint32_t p = begin;
    bool integer = true;
    while (is_digit(at(p))) ++p;
    // A '.' followed by another '.' is never part of a number: `0..3` is 0, .., 3.
    if (at(p) == '.' && at(p + 1) != '.') {
        integer = false;
        ++p;
        while (is_digit(at(p))) ++p;
    }
    if (at(p) == 'e' || at(p) == 'E') {
        uint32_t q = p + 1;
        if (at(q) == '+' || at(q) == '-') ++q;
        if (is_digit(at(q))) {
            integer = false;
            p = q;
            while (is_digit(at(p))) ++p;
        } else {
            uint32_t r = q;
            while (is_ident_char(at(r))) ++r;
            pos_ = r;
            const std::string lex(text_.substr(begin, r - begin));
            if (r == q)
                error(begin, begin, r, "missing digits in the exponent of number " + quoted(lex));
            else
                error(begin, begin, r, "invalid number " + quoted(lex));
            return make(TokenKind::Number, begin);
        }
    }
    // `12px`, `0x1F`, `1.2.3`: one bad token, not a number followed by a name or by another number.
    const auto continues = [this](uint32_t q) {
        return is_ident_char(at(q)) || (at(q) == '.' && is_digit(at(q + 1)));
    };
    if (continues(p)) {
        while (continues(p)) ++p;
        pos_ = p;
        error(begin, begin, p, "invalid number " + quoted(text_.substr(begin, p - begin)));
        return make(TokenKind::Number, begin);
    }
    pos_ = p;
    Token t = make(TokenKind::Number, begin);
    t.number = number_value(begin, p, integer);
    return t;
}

double Lexer::number_value(uint32_t begin, uint32_t end, bool integer) {
    const char* first = text_.data() + begin;
    const char* last = text_.data() + end;
    if (integer && end - begin <= 15) {
        // Exact in a double; the common case of mesh indices and integer coordinates.
        uint64_t v = 0;
        for (const char* s = first; s != last; ++s) v = v * 10 + static_cast<uint64_t>(*s - '0');
        return static_cast<double>(v);
    }
    double value = 0;
    const auto [ptr, ec] = std::from_chars(first, last, value, std::chars_format::general);
    if (ec == std::errc() && ptr == last) return value;
    if (ec != std::errc::result_out_of_range) {
        error(begin, begin, end, "invalid number " + quoted(text_.substr(begin, end - begin)));
        return 0;
    }
    // Out of range: overflow is an error, underflow is 0. The decimal exponent of the first
    // significant digit tells the two apart (the exponent is read with saturation).
    long long lead = 0;
    bool seen_point = false, found = false;
    long long int_digits = 0, frac_zeros = 0;
    const char* s = first;
    for (; s != last && *s != 'e' && *s != 'E'; ++s) {
        if (*s == '.') {
            seen_point = true;
        } else if (!found && *s == '0') {
            if (seen_point) ++frac_zeros;
        } else {
            if (!found) {
                found = true;
                lead = seen_point ? -(frac_zeros + 1) : 0;
            }
            if (!seen_point) ++int_digits;
        }
    }
    if (found && int_digits > 0) lead = int_digits - 1;
    long long exponent = 0;
    if (s != last) {
        ++s;
        const bool negative = *s == '-';
        if (*s == '+' || *s == '-') ++s;
        for (; s != last; ++s) exponent = std::min<long long>(exponent * 10 + (*s - '0'), 1'000'000'000);
        if (negative) exponent = -exponent;
    }
    if (found && lead + exponent > 0) {
        error(begin, begin, end,
              "number " + quoted(text_.substr(begin, end - begin)) + " is too large for a double");
    }
    return 0;
}

Token Lexer::string_literal(uint32_t begin) {
    uint32_t p = begin + 1;
    for (;;) {
        const unsigned char c = at(p);
        if (p >= end_ || c == '\n' || c == '\r') {
            pos_ = p;
            error(begin, begin, p, "unterminated string", "a string ends with '\"' on the same line");
            return make(TokenKind::String, begin);
        }
        if (c == '"') {
            pos_ = p + 1;
            return make(TokenKind::String, begin);
        }
        if (c == '\\') {
            const unsigned char e = at(p + 1);
            if (e == '"' || e == '\\' || e == 'n' || e == 't') {
                p += 2;
                continue;
            }
            if (p + 1 >= end_ || e == '\n' || e == '\r') {
                ++p;
                continue;  // reported as unterminated
            }
            const uint32_t len = e < 0x80 ? 1 : decode_utf8(text_.substr(0, end_), p + 1).length;
            const bool printable = e >= 0x20 && e != 0x7F && decode_utf8(text_.substr(0, end_), p + 1).valid;
            error(p, p, p + 1 + len,
                  printable ? "unknown escape sequence " + quoted(text_.substr(p, 1 + len))
                            : std::string("unknown escape sequence"),
                  "the escapes are \\\" \\\\ \\n \\t");
            ++p;
            continue;  // the escaped byte itself is checked as an ordinary character
        }
        p += (c >= 0x80 || c == 0) ? check_byte(p) : 1;
    }
}

Token Lexer::identifier(uint32_t begin) {
    uint32_t p = begin + 1;
    while (is_ident_char(at(p))) ++p;
    if (at(p) >= 0x80) {
        // `größe`: one error for the whole word, which stays a name so that parsing goes on.
        const uint32_t bad = p;
        bool extended = false;
        for (;;) {
            if (is_ident_char(at(p))) {
                ++p;
                continue;
            }
            if (at(p) < 0x80) break;
            const Utf8Step step = decode_utf8(text_.substr(0, end_), p);
            if (!step.valid) break;
            p += step.length;
            extended = true;
        }
        if (extended) {
            const uint32_t len = decode_utf8(text_.substr(0, end_), bad).length;
            pos_ = p;
            error(bad, bad, bad + len,
                  "invalid character " + quoted(text_.substr(bad, len)) + " in name " +
                      quoted(text_.substr(begin, p - begin)),
                  "names use ASCII letters, digits and '_'");
            return make(TokenKind::Ident, begin);
        }
        p = bad;
    }
    pos_ = p;
    return make(keyword_kind(text_.substr(begin, p - begin)), begin);
}

void Lexer::bad_bytes(uint32_t begin) {
    const unsigned char c = at(begin);
    uint32_t p = begin;
    const std::string offset = " (byte offset " + std::to_string(begin) + ")";
    if (c == 0) {
        while (p < end_ && at(p) == 0) ++p;  // a run of NULs is one error
        pos_ = p;
        error(begin, begin, p, "invalid NUL byte" + offset);
        return;
    }
    if (c >= 0x80) {
        const Utf8Step step = decode_utf8(text_.substr(0, end_), begin);
        if (!step.valid) {
            // A run of invalid bytes (binary garbage) is one error.
            while (p < end_ && at(p) >= 0x80 && !decode_utf8(text_.substr(0, end_), p).valid) ++p;
            pos_ = p;
            error(begin, begin, p, "invalid UTF-8 byte " + hex_byte(c) + offset);
            return;
        }
        pos_ = begin + step.length;
        error(begin, begin, pos_,
              "invalid character " + quoted(text_.substr(begin, step.length)) + " (" +
                  code_point_name(step.codepoint) + ")");
        return;
    }
    pos_ = begin + 1;
    if (c < 0x20 || c == 0x7F) {
        error(begin, begin, pos_, "invalid control character " + code_point_name(c) + offset);
        return;
    }
    std::string help;
    if (c == '&') help = "the logical and is '&&'";
    if (c == '|') help = "the logical or is '||'";
    if (c == '\'') help = "strings use double quotes";
    if (c == ';') help = "statements need no ';'";
    if (c == '#') {
        // A POV-Ray directive is one error over `#word`, and the rest of its line is skipped, so
        // that `#declare R = 2` is not reported again word by word.
        auto [length, directive_help] = preprocessor_help(std::string_view(text_).substr(pos_));
        if (length > 0) {
            const auto word_end = static_cast<uint32_t>(pos_ + length);
            error(begin, begin, word_end,
                  "POV-Ray's directive " + quoted(text_.substr(begin, word_end - begin)) + " is not wsd",
                  directive_help);
            pos_ = word_end;
            while (pos_ < text_.size() && text_[pos_] != '\n' && text_[pos_] != '\r') ++pos_;
            return;
        }
        help = std::move(directive_help);
    }
    error(begin, begin, pos_, "invalid character " + quoted(text_.substr(begin, 1)), help);
}

std::string decode_string(std::string_view literal) {
    std::string out;
    if (literal.empty()) return out;
    size_t end = literal.size();
    if (end >= 2 && literal[end - 1] == '"') --end;
    out.reserve(end);
    for (size_t i = 1; i < end; ++i) {
        const char c = literal[i];
        if (c == '\\' && i + 1 < end) {
            const char e = literal[++i];
            out += e == 'n' ? '\n' : e == 't' ? '\t' : e;
        } else {
            out += c;
        }
    }
    return out;
}

std::string describe_token(const Token& token, std::string_view text) {
    const std::string_view lexeme = token.begin <= token.end && token.end <= text.size()
                                        ? text.substr(token.begin, token.end - token.begin)
                                        : std::string_view{};
    switch (token.kind) {
        case TokenKind::Eof:
            return "end of file";
        case TokenKind::Number:
            return "number " + quoted(lexeme);
        case TokenKind::String: {
            const std::string q = quoted(lexeme);  // 'text' → string "text" (quotes already inside)
            return "string " + q.substr(1, q.size() - 2);
        }
        default:
            return quoted(lexeme);
    }
}

}  // namespace wsd::lang
