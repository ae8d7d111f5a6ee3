// Lexer and source-file tests: every token kind with its span, the number forms and their
// errors, strings, nested comments, bad bytes, the line table and columns, and hostile input.
#include <catch2/catch.hpp>
#include <random>
#include <string>
#include <vector>

#include "lang/lexer.h"

using namespace wsd::lang;

namespace {

struct Lexed {
    SourceManager sources;
    Diagnostics diags;
    std::vector<Token> tokens;  // without the final Eof
    uint32_t file = 0;
    std::string text(const Token& t) const {
        return sources.file(file).text.substr(t.begin, t.end - t.begin);
    }
    std::vector<std::string> errors() const {
        std::vector<std::string> out;
        for (const Diagnostic& d : diags.all()) out.push_back(d.message);
        return out;
    }
    LineCol error_at(size_t i) const { return sources.line_col(file, diags.all().at(i).span.begin); }
};

Lexed lex(std::string text) {
    Lexed r;
    r.file = r.sources.add("test.wsd", std::move(text));
    Lexer lexer(r.file, r.sources.file(r.file).text, &r.diags);
    for (size_t guard = 0; guard < 10'000'000; ++guard) {
        const Token t = lexer.next();
        if (t.kind == TokenKind::Eof) break;
        r.tokens.push_back(t);
    }
    return r;
}

std::vector<TokenKind> kinds(const Lexed& l) {
    std::vector<TokenKind> k;
    for (const Token& t : l.tokens) k.push_back(t.kind);
    return k;
}

}  // namespace

TEST_CASE("every punctuation token has its kind and span", "[lexer]") {
    const std::string src = "{ } ( ) [ ] < > , = . .. + - * / % == != <= >= && || !";
    const Lexed l = lex(src);
    const std::vector<TokenKind> expected = {
        TokenKind::LBrace,    TokenKind::RBrace,  TokenKind::LParen,  TokenKind::RParen, TokenKind::LBracket,
        TokenKind::RBracket,  TokenKind::Less,    TokenKind::Greater, TokenKind::Comma,  TokenKind::Assign,
        TokenKind::Dot,       TokenKind::DotDot,  TokenKind::Plus,    TokenKind::Minus,  TokenKind::Star,
        TokenKind::Slash,     TokenKind::Percent, TokenKind::EqEq,    TokenKind::NotEq,  TokenKind::LessEq,
        TokenKind::GreaterEq, TokenKind::AndAnd,  TokenKind::OrOr,    TokenKind::Bang};
    REQUIRE(kinds(l) == expected);
    CHECK(l.diags.all().empty());
    // Each token's span is exactly its spelling, at the offset where it stands.
    size_t pos = 0;
    for (const Token& t : l.tokens) {
        const std::string spelling(token_spelling(t.kind));
        pos = src.find(spelling, pos);
        CHECK(t.begin == pos);
        CHECK(t.end == pos + spelling.size());
        CHECK(l.text(t) == spelling);
        pos = t.end;
    }
}

TEST_CASE("keywords are reserved, other words are identifiers", "[lexer]") {
    const Lexed l =
        lex("let for in if else include settings camera light sphere box triangle plane "
            "mesh material image checker perlin true false point radius _x9 lets Sphere");
    const std::vector<TokenKind> expected = {
        TokenKind::Let,     TokenKind::For,      TokenKind::In,     TokenKind::If,    TokenKind::Else,
        TokenKind::Include, TokenKind::Settings, TokenKind::Camera, TokenKind::Light, TokenKind::Sphere,
        TokenKind::Box,     TokenKind::Triangle, TokenKind::Plane,  TokenKind::Mesh,  TokenKind::Material,
        TokenKind::Image,   TokenKind::Checker,  TokenKind::Perlin, TokenKind::True,  TokenKind::False,
        TokenKind::Ident,   TokenKind::Ident,    TokenKind::Ident,  TokenKind::Ident, TokenKind::Ident};
    CHECK(kinds(l) == expected);
    CHECK(l.text(l.tokens[21]) == "radius");
    CHECK(l.text(l.tokens.back()) == "Sphere");
}

TEST_CASE("number forms and values", "[lexer]") {
    const Lexed l = lex("12 1.5 .5 2. 1e-3 6.02E23 0 007 1e+2 123456789012345678901234567890");
    REQUIRE(l.tokens.size() == 10);
    for (const Token& t : l.tokens) CHECK(t.kind == TokenKind::Number);
    CHECK(l.tokens[0].number == 12);
    CHECK(l.tokens[1].number == 1.5);
    CHECK(l.tokens[2].number == 0.5);
    CHECK(l.tokens[3].number == 2.0);
    CHECK(l.tokens[4].number == 1e-3);
    CHECK(l.tokens[5].number == 6.02e23);
    CHECK(l.tokens[6].number == 0);
    CHECK(l.tokens[7].number == 7);
    CHECK(l.tokens[8].number == 100);
    CHECK(l.tokens[9].number == 123456789012345678901234567890.0);
    CHECK(l.text(l.tokens[3]) == "2.");
    CHECK(l.text(l.tokens[2]) == ".5");
    CHECK(l.diags.all().empty());
}

TEST_CASE("a dot followed by a dot is never part of a number", "[lexer]") {
    const Lexed l = lex("0..3 1...2 x.y 2.x");
    CHECK(kinds(l) == std::vector<TokenKind>{TokenKind::Number, TokenKind::DotDot, TokenKind::Number,
                                             TokenKind::Number, TokenKind::DotDot, TokenKind::Number,
                                             TokenKind::Ident, TokenKind::Dot, TokenKind::Ident,
                                             TokenKind::Number});
    CHECK(l.tokens[0].number == 0);
    CHECK(l.tokens[2].number == 3);
    CHECK(l.tokens[5].number == 0.2);  // `1...2` is 1, .., .2
    // `2.x` is one bad number, not 2. followed by a name.
    REQUIRE(l.errors().size() == 1);
    CHECK(l.errors()[0] == "invalid number '2.x'");
}

TEST_CASE("overflow is an error, underflow is zero", "[lexer]") {
    const Lexed l = lex("1e999 1e309 1.8e308 1e-400 0.0000001e-330 0e999 1.7e308");
    REQUIRE(l.tokens.size() == 7);
    CHECK(l.errors() == std::vector<std::string>{"number '1e999' is too large for a double",
                                                 "number '1e309' is too large for a double",
                                                 "number '1.8e308' is too large for a double"});
    CHECK(l.tokens[0].number == 0);
    CHECK(l.tokens[3].number == 0);
    CHECK(l.tokens[4].number == 0);
    CHECK(l.tokens[5].number == 0);
    CHECK(l.tokens[6].number == 1.7e308);
    CHECK(l.error_at(1).column == 7);
}

TEST_CASE("malformed numbers are errors at the literal", "[lexer]") {
    const Lexed l = lex("1e 1e+ 2E- 12px 0x1p3");
    CHECK(kinds(l) == std::vector<TokenKind>(5, TokenKind::Number));
    CHECK(l.errors() == std::vector<std::string>{"missing digits in the exponent of number '1e'",
                                                 "missing digits in the exponent of number '1e+'",
                                                 "missing digits in the exponent of number '2E-'",
                                                 "invalid number '12px'", "invalid number '0x1p3'"});
    CHECK(l.error_at(3).column == 12);
    CHECK(l.diags.all()[3].span.end - l.diags.all()[3].span.begin == 4);
}

TEST_CASE("strings, escapes and their errors", "[lexer]") {
    const Lexed ok = lex(R"("a\"b\\c\nd\te" "")");
    REQUIRE(ok.tokens.size() == 2);
    CHECK(ok.diags.all().empty());
    CHECK(decode_string(ok.text(ok.tokens[0])) == "a\"b\\c\nd\te");
    CHECK(decode_string(ok.text(ok.tokens[1])).empty());

    const Lexed bad = lex("\"ab\\qc\" \"x\\\n");
    REQUIRE(bad.errors().size() == 2);
    CHECK(bad.errors()[0] == "unknown escape sequence '\\q'");
    CHECK(bad.error_at(0).column == 4);  // at the backslash
    CHECK(bad.errors()[1] == "unterminated string");
    CHECK(bad.error_at(1).column == 9);  // at the opening quote

    const Lexed eof = lex("let s = \"abc");
    REQUIRE(eof.errors() == std::vector<std::string>{"unterminated string"});
    CHECK(eof.error_at(0).column == 9);
    CHECK(eof.tokens.back().kind == TokenKind::String);
}

TEST_CASE("comments nest; an unterminated one is reported where it opened", "[lexer]") {
    const Lexed l = lex("a // line /* not a block\nb /* x /* nested */ still comment */ c");
    CHECK(kinds(l) == std::vector<TokenKind>(3, TokenKind::Ident));
    CHECK(l.diags.all().empty());

    const Lexed open = lex("x\n  /* outer /* inner */ to the end\n");
    REQUIRE(open.errors() == std::vector<std::string>{"unterminated block comment"});
    CHECK(open.error_at(0).line == 2);
    CHECK(open.error_at(0).column == 3);

    const Lexed slash = lex("a/b/*c*/d");
    CHECK(kinds(slash) ==
          std::vector<TokenKind>{TokenKind::Ident, TokenKind::Slash, TokenKind::Ident, TokenKind::Ident});
}

TEST_CASE("NUL bytes and invalid UTF-8 are errors at that byte", "[lexer]") {
    const Lexed nul = lex(std::string("a \0 b", 5));
    REQUIRE(nul.errors().size() == 1);
    CHECK(nul.errors()[0] == "invalid NUL byte (byte offset 2)");
    CHECK(kinds(nul) == std::vector<TokenKind>{TokenKind::Ident, TokenKind::Ident});

    const Lexed ff = lex("x \xFF y");
    REQUIRE(ff.errors().size() == 1);
    CHECK(ff.errors()[0] == "invalid UTF-8 byte 0xff (byte offset 2)");
    CHECK(ff.error_at(0).column == 3);

    const Lexed overlong = lex("// comment \xC0\x80\nz");
    REQUIRE(overlong.errors().size() == 2);  // both bytes of the overlong form are invalid
    CHECK(overlong.errors()[0] == "invalid UTF-8 byte 0xc0 (byte offset 11)");

    const Lexed cont = lex("\"str \x80\"");
    REQUIRE(cont.errors() == std::vector<std::string>{"invalid UTF-8 byte 0x80 (byte offset 5)"});

    const Lexed nul_in_string = lex(std::string("\"a\0b\"", 5));
    CHECK(nul_in_string.errors() == std::vector<std::string>{"invalid NUL byte (byte offset 2)"});

    // Valid UTF-8 in comments and strings is fine.
    CHECK(lex("// größe ✓\n\"größe ✓\"").diags.all().empty());
}

TEST_CASE("non-ASCII letters and stray characters are invalid outside strings", "[lexer]") {
    const Lexed word = lex("let größe = 1");
    REQUIRE(word.errors().size() == 1);
    CHECK(word.errors()[0] == "invalid character 'ö' in name 'größe'");
    CHECK(word.error_at(0).column == 7);
    CHECK(kinds(word) ==
          std::vector<TokenKind>{TokenKind::Let, TokenKind::Ident, TokenKind::Assign, TokenKind::Number});

    const Lexed stray = lex("a # b ; c & d");
    CHECK(stray.errors() == std::vector<std::string>{"invalid character '#'", "invalid character ';'",
                                                     "invalid character '&'"});
    CHECK(kinds(stray).size() == 4);

    const Lexed times = lex("2 × 3");
    CHECK(times.errors() == std::vector<std::string>{"invalid character '×' (U+00D7)"});
}

TEST_CASE("byte-order marks", "[lexer]") {
    const Lexed utf8 = lex("\xEF\xBB\xBFsphere");
    REQUIRE(utf8.tokens.size() == 1);
    CHECK(utf8.tokens[0].begin == 3);
    CHECK(utf8.sources.line_col(utf8.file, 3).column == 1);
    CHECK(utf8.diags.all().empty());

    const Lexed utf16 = lex("\xFF\xFEs\0p\0");
    CHECK(utf16.tokens.empty());
    CHECK(utf16.errors() ==
          std::vector<std::string>{"file is UTF-16 (it starts with a UTF-16 byte-order mark)"});
}

TEST_CASE("re-lexing after reset reports nothing twice", "[lexer]") {
    SourceManager sources;
    Diagnostics diags;
    const uint32_t f = sources.add("t.wsd", "1e999 /* open");
    Lexer lexer(f, sources.file(f).text, &diags);
    while (lexer.next().kind != TokenKind::Eof) {
    }
    REQUIRE(diags.error_count() == 2);
    lexer.reset(0);
    while (lexer.next().kind != TokenKind::Eof) {
    }
    CHECK(diags.error_count() == 2);
}

TEST_CASE("line table: LF, CRLF and a lone CR each end a line", "[source]") {
    SourceManager sources;
    const uint32_t f = sources.add("t.wsd", "a\nb\r\nc\rd\n\te\xC3\xA9x\n");
    const SourceFile& file = sources.file(f);
    CHECK(file.line_starts == std::vector<uint32_t>{0, 2, 5, 7, 9, 15});
    CHECK(sources.line_text(f, 1) == "a");
    CHECK(sources.line_text(f, 2) == "b");
    CHECK(sources.line_text(f, 3) == "c");
    CHECK(sources.line_text(f, 4) == "d");
    CHECK(sources.line_text(f, 5) == "\te\xC3\xA9x");
    CHECK(sources.line_text(f, 6).empty());
    CHECK(sources.line_col(f, 5).line == 3);
    CHECK(sources.line_col(f, 7).line == 4);
    // Columns count code points; a tab is one column: `\t e é x` → x is column 4.
    const uint32_t x = static_cast<uint32_t>(file.text.find('x'));
    CHECK(sources.line_col(f, x).line == 5);
    CHECK(sources.line_col(f, x).column == 4);
    // The end of the file is a position too.
    CHECK(sources.line_col(f, static_cast<uint32_t>(file.text.size())).line == 6);
    CHECK(sources.line_col(f, static_cast<uint32_t>(file.text.size())).column == 1);
}

TEST_CASE("UTF-8 decoding accepts valid and rejects invalid sequences", "[source]") {
    CHECK(decode_utf8("\xE2\x9C\x93", 0).codepoint == 0x2713);
    CHECK(decode_utf8("\xF0\x9F\x98\x80", 0).length == 4);
    CHECK_FALSE(decode_utf8("\xC0\x80", 0).valid);          // overlong
    CHECK_FALSE(decode_utf8("\xED\xA0\x80", 0).valid);      // surrogate
    CHECK_FALSE(decode_utf8("\xF4\x90\x80\x80", 0).valid);  // above U+10FFFF
    CHECK_FALSE(decode_utf8("\xE2\x9C", 0).valid);          // truncated
    CHECK_FALSE(decode_utf8("\x80", 0).valid);
    CHECK(count_columns("a\xC3\xA9\xFF"
                        "b",
                        0, 5) == 4);
}

TEST_CASE("hostile input never crashes the lexer", "[lexer]") {
    CHECK(lex("").tokens.empty());
    CHECK(lex("   \n\r\n\t ").tokens.empty());
    CHECK(lex("/*").errors().size() == 1);
    CHECK(lex("\"").errors().size() == 1);
    CHECK(lex("\"\\").errors().size() == 1);
    CHECK(lex("1e").errors().size() == 1);
    CHECK(lex(".").tokens.size() == 1);
    std::mt19937 rng(12345);
    for (int round = 0; round < 200; ++round) {
        std::string garbage(static_cast<size_t>(rng() % 400), '\0');
        for (char& c : garbage) c = static_cast<char>(rng() & 0xFF);
        const Lexed l = lex(garbage);
        CHECK(l.diags.all().size() <= Diagnostics::max_errors);
        for (const Token& t : l.tokens) CHECK((t.begin <= t.end && t.end <= garbage.size()));
    }
}

TEST_CASE("a large generated input lexes completely", "[lexer]") {
    std::string text;
    const int n = 200'000;
    for (int i = 0; i < n; ++i) text += "<" + std::to_string(i) + ", -" + std::to_string(i) + ".25, 1e-3>,\n";
    const Lexed l = lex(text);
    CHECK(l.diags.all().empty());
    REQUIRE(l.tokens.size() == static_cast<size_t>(n) * 9);
    CHECK(l.tokens[9 * 1234 + 1].number == 1234);
    CHECK(l.tokens[9 * 1234 + 4].number == 1234.25);
    CHECK(l.sources.line_col(l.file, l.tokens.back().begin).line == static_cast<uint32_t>(n));
}
