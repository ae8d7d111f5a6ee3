// Tokens of the .wsd language: kinds, the reserved-keyword table and the human-readable
// spelling used in "expected X, found Y" messages.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace wsd::lang {

enum class TokenKind : uint8_t {
    Eof,
    Number,
    String,
    Ident,
    // Reserved keywords.
    Let,
    For,
    In,
    If,
    Else,
    Include,
    Settings,
    Camera,
    Light,
    Sphere,
    Box,
    Triangle,
    Plane,
    Mesh,
    Cylinder,
    Cone,
    Torus,
    Disc,
    Fn,
    Return,
    Group,
    Union,
    Intersection,
    Difference,
    Object,
    Material,
    Image,
    Checker,
    Perlin,
    True,
    False,
    // Punctuation.
    LBrace,
    RBrace,
    LParen,
    RParen,
    LBracket,
    RBracket,
    Less,
    Greater,
    Comma,
    Assign,
    Dot,
    DotDot,
    Plus,
    Minus,
    Star,
    Slash,
    Percent,
    EqEq,
    NotEq,
    LessEq,
    GreaterEq,
    AndAnd,
    OrOr,
    Bang,
};

struct Token {
    TokenKind kind = TokenKind::Eof;
    uint32_t begin = 0;  // byte offsets in the file
    uint32_t end = 0;
    double number = 0;  // Number: the value (0 after a reported error)
};

// The keyword for an identifier spelling, or Ident.
TokenKind keyword_kind(std::string_view word);

// Fixed spelling of a keyword or punctuation kind ("sphere", "{", "..."); "" for the others.
std::string_view token_spelling(TokenKind kind);

// Statement keywords: the tokens a statement starts with, where recovery resynchronizes.
bool is_statement_keyword(TokenKind kind);

}  // namespace wsd::lang
