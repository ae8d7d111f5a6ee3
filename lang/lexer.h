// The lexer: bytes → tokens, on demand (the parser pulls one token at a time, so a 100 MB file
// never has a token array). Lexical errors (bad numbers, strings, comments, bytes) are reported
// here and the lexer carries on, so the parser sees a plausible token stream.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "lang/diagnostics.h"
#include "lang/token.h"

namespace wsd::lang {

class Lexer {
public:
    // `diags` may be null: re-lexing text whose errors were already reported.
    Lexer(uint32_t file, std::string_view text, Diagnostics* diags);

    Token next();
    // Continue at `offset` (a token boundary). Errors at offsets already passed are not reported
    // again, so the parser may back up (to split `>=`, or to re-read a list) at no cost in noise.
    void reset(uint32_t offset) { pos_ = offset; }
    uint32_t position() const { return pos_; }
    std::string_view text() const { return text_; }
    std::string_view lexeme(const Token& t) const { return text_.substr(t.begin, t.end - t.begin); }
    // Comments skipped from now on are appended to `out` (the formatter keeps them); null: none.
    void record_comments(std::vector<Span>* out) { comments_ = out; }

private:
    Token make(TokenKind kind, uint32_t begin) const { return {kind, begin, pos_, 0}; }
    unsigned char at(uint32_t i) const;  // 0 past the end
    // `scan` is how far lexing had got: an error is reported once, however often that part of
    // the text is lexed again.
    void error(uint32_t scan, uint32_t begin, uint32_t end, std::string message, std::string help = {});
    void line_comment();
    void block_comment();
    Token number(uint32_t begin);
    double number_value(uint32_t begin, uint32_t end, bool integer);
    Token string_literal(uint32_t begin);
    Token identifier(uint32_t begin);
    void bad_bytes(uint32_t begin);    // NUL, invalid UTF-8, stray characters: no token
    uint32_t check_byte(uint32_t at);  // a NUL or non-ASCII byte in a comment or string

    uint32_t file_;
    std::string_view text_;
    Diagnostics* diags_;
    uint32_t pos_ = 0;
    uint32_t end_ = 0;
    uint32_t reported_until_ = 0;  // errors starting below this offset were already reported
    std::vector<Span>* comments_ = nullptr;
};

// The decoded contents of a string literal (with its quotes); lenient about errors the lexer
// already reported (an unknown escape keeps its character, an unterminated string ends at the
// line end).
std::string decode_string(std::string_view literal);

// The token as messages name it: "end of file", "number '1.5'", "string \"a.png\"", "'radius'".
std::string describe_token(const Token& token, std::string_view text);

}  // namespace wsd::lang
