// Formatter tests: on every golden and example file that parses, the output is a fixed point,
// parses to the same AST apart from positions and keeps every comment in order; the same holds
// for each file squeezed onto as few lines as possible, spread one token per line, and with its
// whitespace scrambled and comments added; the style itself is pinned on small cases; files with
// syntax errors give the parser's diagnostics.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "lang/ast_equal.h"
#include "lang/format.h"
#include "lang/lexer.h"
#include "lang/parser.h"

namespace fs = std::filesystem;
using namespace wsd::lang;

namespace {

std::string read_file(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::vector<fs::path> scene_files() {
    std::vector<fs::path> files;
    for (const char* dir : {"tests/golden", "examples"}) {
        for (const auto& entry : fs::recursive_directory_iterator(fs::path(WSD_SOURCE_DIR) / dir)) {
            const std::string ext = entry.path().extension().string();
            if (entry.is_regular_file() && (ext == ".wsd" || ext == ".wsdi")) files.push_back(entry.path());
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

struct Formatted {
    std::optional<std::string> text;
    std::string errors;
};

Formatted format_text(const std::string& text, const std::string& path = "test.wsd") {
    SourceManager sources;
    Diagnostics diags;
    const uint32_t file = sources.add(path, text);
    Formatted f;
    f.text = format_source(file, sources, diags);
    f.errors = format_diagnostics(diags, sources);
    return f;
}

// The AST dump of `text` without positions; "" when it does not parse.
std::string ast_without_positions(const std::string& text) {
    SourceManager sources;
    Diagnostics diags;
    const uint32_t file = sources.add("test.wsd", text);
    const Program program = parse(file, sources, diags);
    if (diags.has_errors()) return "";
    static const std::regex position(R"( @\d+:\d+)");
    return std::regex_replace(print_ast(program, sources), position, "");
}

bool parses(const std::string& text) {
    SourceManager sources;
    Diagnostics diags;
    parse(sources.add("test.wsd", text), sources, diags);
    return !diags.has_errors();
}

// Tokens and comments of `text` as (begin, end, is comment) in order.
struct Piece {
    uint32_t begin, end;
    bool comment;
};
std::vector<Piece> pieces(const std::string& text) {
    Lexer lexer(0, text, nullptr);
    std::vector<Span> comments;
    lexer.record_comments(&comments);
    std::vector<Piece> out;
    for (Token t = lexer.next(); t.kind != TokenKind::Eof; t = lexer.next())
        out.push_back({t.begin, t.end, false});
    for (const Span& c : comments) out.push_back({c.begin, c.end, true});
    std::sort(out.begin(), out.end(), [](const Piece& a, const Piece& b) { return a.begin < b.begin; });
    return out;
}

// The comments of `text`, their line breaks as LF (the formatter writes no CR).
std::vector<std::string> comments_of(const std::string& text) {
    std::vector<std::string> out;
    for (const Piece& p : pieces(text)) {
        if (!p.comment) continue;
        std::string c;
        for (size_t i = p.begin; i < p.end; ++i) {
            if (text[i] != '\r') {
                c += text[i];
            } else {
                c += '\n';
                if (i + 1 < p.end && text[i + 1] == '\n') ++i;
            }
        }
        out.push_back(std::move(c));
    }
    return out;
}

// `text` with the whitespace between its tokens and comments replaced: by one space (a line
// break after a line comment), or by a line break everywhere. Adjacent pieces stay adjacent.
std::string relayout(const std::string& text, bool one_per_line) {
    const std::vector<Piece> ps = pieces(text);
    std::string out;
    for (size_t i = 0; i < ps.size(); ++i) {
        if (i > 0 && ps[i].begin > ps[i - 1].end) {
            const bool after_line_comment = ps[i - 1].comment && text[ps[i - 1].begin + 1] == '/';
            out += one_per_line || after_line_comment ? "\n" : " ";
        }
        out += text.substr(ps[i].begin, ps[i].end - ps[i].begin);
    }
    return out + "\n";
}

// `text` with each run of whitespace between its pieces replaced at random (seeded): by a space,
// a line break, blank lines, or with a block or line comment added; a line comment keeps its line
// break after it.
std::string scramble(const std::string& text, std::mt19937& rng) {
    static const char* const fillers[] = {" ",         "\n",      "\n\n\n",
                                          " /* c */ ", " // c\n", "\n/* two\n   lines */\n"};
    const std::vector<Piece> ps = pieces(text);
    std::string out;
    for (size_t i = 0; i < ps.size(); ++i) {
        if (i > 0 && ps[i].begin > ps[i - 1].end) {
            std::string gap = fillers[std::uniform_int_distribution<size_t>(0, 5)(rng)];
            const bool after_line_comment = ps[i - 1].comment && text[ps[i - 1].begin + 1] == '/';
            if (after_line_comment && gap.find('\n') == std::string::npos) gap += "\n";
            out += gap;
        }
        out += text.substr(ps[i].begin, ps[i].end - ps[i].begin);
    }
    return out;
}

// The formatter's promises for one input: it formats, to a fixed point, with the same AST and
// the same comments.
void check_promises(const std::string& input, const std::string& name) {
    INFO(name);
    const Formatted once = format_text(input);
    INFO(once.errors);
    REQUIRE(once.text);
    CHECK(ast_without_positions(*once.text) == ast_without_positions(input));
    CHECK(comments_of(*once.text) == comments_of(input));
    const Formatted twice = format_text(*once.text);
    REQUIRE(twice.text);
    CHECK(*twice.text == *once.text);
}

std::string fmt(const std::string& input) {
    const Formatted f = format_text(input);
    INFO(f.errors);
    REQUIRE(f.text);
    return *f.text;
}

}  // namespace

TEST_CASE("fmt on every golden and example file: fixed point, same AST, every comment", "[format]") {
    size_t formatted = 0, refused = 0;
    for (const fs::path& path : scene_files()) {
        const std::string text = read_file(path);
        if (!parses(text)) {
            INFO(path.string());
            CHECK_FALSE(format_text(text).text);
            ++refused;
            continue;
        }
        check_promises(text, path.string());
        ++formatted;
    }
    CHECK(formatted > 50);
    CHECK(refused > 0);
}

TEST_CASE("fmt on every file squeezed onto few lines and spread one token a line", "[format]") {
    for (const fs::path& path : scene_files()) {
        const std::string text = read_file(path);
        if (!parses(text)) continue;
        for (const bool spread : {false, true}) {
            const std::string variant = relayout(text, spread);
            INFO((spread ? "spread: " : "squeezed: ") + path.string());
            REQUIRE(ast_without_positions(variant) == ast_without_positions(text));
            check_promises(variant, path.string());
        }
    }
}

TEST_CASE("fmt on every file with its whitespace scrambled and comments added", "[format]") {
    std::mt19937 rng(20261127);
    for (const fs::path& path : scene_files()) {
        const std::string text = read_file(path);
        if (!parses(text)) continue;
        for (int round = 0; round < 2; ++round) {
            const std::string variant = scramble(text, rng);
            INFO("scrambled: " + path.string() + "\n" + variant);
            REQUIRE(ast_without_positions(variant) == ast_without_positions(text));
            check_promises(variant, path.string());
        }
    }
}

TEST_CASE("examples/ is kept in the canonical layout", "[format]") {
    for (const fs::path& path : scene_files()) {
        if (path.string().find("/examples/") == std::string::npos) continue;
        INFO(path.string());
        const std::string text = read_file(path);
        CHECK(fmt(text) == text);
    }
}

TEST_CASE("fmt style: one-line blocks that fit stay, others get one item a line", "[format]") {
    CHECK(fmt("sphere{radius 1 center<0,1,0>}") == "sphere { radius 1  center <0, 1, 0> }\n");
    CHECK(fmt("sphere { radius 1\n center <0,1,0> }") == "sphere {\n    radius 1\n    center <0, 1, 0>\n}\n");
    CHECK(fmt("settings {}\n") == "settings {}\n");
    // Wider than 100 columns: expanded.
    const std::string wide =
        "box { min <-1000000, -1000000, -1000000>  max <1000000, 1000000, 1000000>  "
        "material { color <0.25, 0.5, 0.75> } }\n";
    CHECK(fmt(wide) ==
          "box {\n    min <-1000000, -1000000, -1000000>\n    max <1000000, 1000000, 1000000>\n"
          "    material { color <0.25, 0.5, 0.75> }\n}\n");
    // Statements: one a line, in bodies too.
    CHECK(fmt("let a=1 let b=2") == "let a = 1\nlet b = 2\n");
    CHECK(fmt("for i in 0..3 {\nlet x=i sphere{center<x,0,0> radius 0.5}}") ==
          "for i in 0 .. 3 {\n    let x = i\n    sphere { center <x, 0, 0>  radius 0.5 }\n}\n");
    CHECK(fmt("union {\nsphere{radius 1}\nscale(2) translate<1,0,0>}") ==
          "union {\n    sphere { radius 1 }\n    scale (2)\n    translate <1, 0, 0>\n}\n");
}

TEST_CASE("fmt style: operators, calls, indexes, vectors, strings and numbers", "[format]") {
    CHECK(fmt("let a=-b*(c+d)%2-(-1)") == "let a = -b * (c + d) % 2 - (-1)\n");
    CHECK(fmt("let a = - -1") == "let a = - -1\n");
    CHECK(fmt("let a=!x&&y||z!=w") == "let a = !x && y || z != w\n");
    CHECK(fmt("let a=f(1,g(2),xs[0].x)") == "let a = f(1, g(2), xs[0].x)\n");
    CHECK(fmt("fn f(a,b=2){return a<b}") == "fn f(a, b = 2) { return a < b }\n");
    CHECK(fmt("let v=<1,-2,3>==<1,-2,3>") == "let v = <1, -2, 3> == <1, -2, 3>\n");
    CHECK(fmt("let v=<1,2>>=w") == "let v = <1, 2> >= w\n");
    // A vector in parentheses is still a vector: no spaces inside its < >.
    CHECK(fmt("let a=(<1,2,3>)") == "let a = (<1, 2, 3>)\n");
    CHECK(fmt("let a=(( /* v */ <1,2>))*2") == "let a = (( /* v */ <1, 2>)) * 2\n");
    CHECK(fmt("let m=material{color (<1,1,1>)}") == "let m = material { color (<1, 1, 1>) }\n");
    CHECK(fmt("let l=[1.50,2e3,.5,]") == "let l = [1.50, 2e3, .5,]\n");
    CHECK(fmt("let s=\"a \\\"b\\\" \\\\ \\n\\t\"") == "let s = \"a \\\"b\\\" \\\\ \\n\\t\"\n");
    CHECK(fmt("let m=material{texture image \"a.png\"}") == "let m = material { texture image \"a.png\" }\n");
    CHECK(fmt("object p{translate<0,1,0>}") == "object p { translate <0, 1, 0> }\n");
    CHECK(fmt("triangle{<0,0,0>,<1,0,0>,<0,1,0> uv <0,0>,<1,0>,<0,1>}") ==
          "triangle { <0, 0, 0>, <1, 0, 0>, <0, 1, 0>  uv <0, 0>, <1, 0>, <0, 1> }\n");
    CHECK(fmt("light point{position<0,5,0>}\ninclude \"lib.wsdi\"") ==
          "light point { position <0, 5, 0> }\ninclude \"lib.wsdi\"\n");
}

TEST_CASE("fmt style: if/else, continuation lines, blank lines", "[format]") {
    CHECK(fmt("if a {\nf(1)\n}\nelse if b { f(2) }\nelse\n{\nf(3) }") ==
          "if a {\n    f(1)\n} else if b { f(2) } else {\n    f(3)\n}\n");
    CHECK(fmt("let a = 1 +\n2") == "let a = 1 +\n    2\n");
    CHECK(fmt("let xs = [\n1,\n   2\n]") == "let xs = [\n    1,\n    2\n]\n");
    CHECK(fmt("for p in [<1,0,0>,\n<2,0,0>] {\nf(p)\n}") ==
          "for p in [<1, 0, 0>,\n    <2, 0, 0>] {\n    f(p)\n}\n");
    CHECK(fmt("let a = 1\n\n\n\nlet b = 2\n") == "let a = 1\n\nlet b = 2\n");
    // A block comment at the start of a continuation line keeps the line's indent.
    CHECK(fmt("let e = 1 +\n  /* c */ 2") == "let e = 1 +\n    /* c */ 2\n");
    CHECK(fmt("sphere {\n radius 1 +\n /* c */ /* d */ 2\n}") ==
          "sphere {\n    radius 1 +\n        /* c */ /* d */ 2\n}\n");
    CHECK(fmt("let xs = [\n1,\n /* two */ 2\n]") == "let xs = [\n    1,\n    /* two */ 2\n]\n");
    CHECK(fmt("sphere {\n /* r */ radius 1\n}") == "sphere {\n    /* r */\n    radius 1\n}\n");
    // A token that joins the line before it (`[`, `.`, `,`) after a block comment on a line of its
    // own goes on the comment's line, indented as that line would be without the comment.
    CHECK(fmt("let g = xs\n/* c */\n[0]") == "let g = xs\n    /* c */ [0]\n");
    CHECK(fmt("let s = v\n/* c */\n.x") == "let s = v\n    /* c */ .x\n");
    for (const char* input :
         {"let e = 1 +\n  /* c */ 2", "let a = f(1,\n /* c */ g(2,\n /* d */ 3))",
          "if a { f(1) }\n/* c */ else { f(2) }", "let g = xs\n/* c */\n[0]",
          "let s = xs[0]\n/* c */ /* d */\n.x", "sphere\n/* c */\n{ radius 1 }",
          "if a { f(1) }\n/* c */\nelse { f(2) }", "let a = <1\n/* c */\n, 2>",
          "sphere {\n    colors <0.8,\n/* c */\n0.8, 0.8>\n/* d */\n, <0.3, 0.3, 0.35>\n}"})
        check_promises(input, input);
    CHECK(fmt("group {\n\n  sphere { radius 1 }\n\n}\n") == "group {\n    sphere { radius 1 }\n}\n");
}

TEST_CASE("fmt keeps comments where they stand", "[format]") {
    CHECK(fmt("// head\nlet a=1 // after a\n/* block */ let b=2\n") ==
          "// head\nlet a = 1 // after a\n/* block */\nlet b = 2\n");
    CHECK(fmt("sphere { radius 1 /* r */ center <0,0,0> }") ==
          "sphere {\n    radius 1 /* r */\n    center <0, 0, 0>\n}\n");
    CHECK(fmt("sphere { // s\nradius 1\n  // before the end\n}") ==
          "sphere { // s\n    radius 1\n    // before the end\n}\n");
    CHECK(fmt("let a = f(1, // one\n2)") == "let a = f(1, // one\n    2)\n");
    CHECK(fmt("/* a\n   multi-line /* nested */ comment */\n") ==
          "/* a\n   multi-line /* nested */ comment */\n");
    CHECK(fmt("let a = 1 // last") == "let a = 1 // last\n");
    CHECK(fmt("") == "");
}

TEST_CASE("fmt: line endings, byte-order mark, fragments", "[format]") {
    CHECK(fmt("let a=1\r\nlet b=2\r\n") == "let a = 1\nlet b = 2\n");
    CHECK(fmt("\xEF\xBB\xBFlet a=1") == "\xEF\xBB\xBFlet a = 1\n");
    // Inside block comments too: CRLF and a lone CR become LF.
    CHECK(fmt("/* a\r\n   b\r   c */\r\nlet a=1\r\n") == "/* a\n   b\n   c */\nlet a = 1\n");
    CHECK(fmt("let a = 1 /* x\r\ny */ + 2") == "let a = 1 /* x\ny */ + 2\n");
    const Formatted fragment = format_text("let m=material{color<1,0,0>}", "lib.wsdi");
    REQUIRE(fragment.text);
    CHECK(*fragment.text == "let m = material { color <1, 0, 0> }\n");
}

TEST_CASE("fmt: a block the parser skips may leave brackets open or close too many", "[format]") {
    // An unknown property with a block after it (POV-Ray's `pigment { ... }`) parses as one
    // placeholder, whatever its tokens; the checker reports the property later. Its '}' closes the
    // brackets it left open, and a stray ')' or ']' in it closes nothing outside.
    CHECK(fmt("sphere { m { a[o <1, 1, 1> } }") == "sphere { m { a [o < 1, 1, 1 > } }\n");
    CHECK(fmt("sphere { m { a(o ) ] ) } }") == "sphere { m { a (o)]) } }\n");
    for (const char* input :
         {"sphere { m { a[o <1, 1, 1> } }", "sphere { m { a[o\n <1, 1, 1>\n } }",
          "sphere { m { (((\n } radius 1\n center <0, 0, 0> }", "sphere { m { ] ) ]\n x 1 }\n}",
          "sphere {\n  m { [ {\n ( } }\n  radius 1\n}\nsphere { radius 2 }"})
        check_promises(input, input);
}

TEST_CASE("fmt: tokens of a skipped block are never joined into other tokens", "[format]") {
    // Without a space between them, `. .` would lex as `..`, `. 5` as `.5`, `! ==` as `!=` `=`.
    const auto in_block = [](const std::string& tokens) {
        return "let s = sphere { radius 1  foo { " + tokens + " } }\n";
    };
    CHECK(fmt(in_block("a . . b")) == in_block("a. .b"));
    CHECK(fmt(in_block("x. .5")) == in_block("x. .5"));
    CHECK(fmt(in_block("! ==")) == in_block("! =="));
    CHECK(fmt(in_block(". 5")) == in_block(". 5"));
    CHECK(fmt(in_block("1 . 5")) == in_block("1 . 5"));
    CHECK(fmt(in_block("a . 5")) == in_block("a. 5"));
    CHECK(fmt(in_block("- -")) == in_block("- -"));
    for (const char* tokens : {"a . . b", "x. .5", "! ==", ". 5", "1 . 5", "a . 5", "! =", "- . 5", ". . ."})
        check_promises(in_block(tokens), tokens);
}

TEST_CASE("fmt refuses a file with syntax errors with the parser's diagnostics", "[format]") {
    const std::string text = "sphere { radius 1\nlet = 2\n";
    const Formatted f = format_text(text);
    CHECK_FALSE(f.text);
    SourceManager sources;
    Diagnostics diags;
    parse(sources.add("test.wsd", text), sources, diags);
    CHECK(f.errors == format_diagnostics(diags, sources));
    CHECK(f.errors.find("test.wsd:") != std::string::npos);
}

TEST_CASE("same_ast ignores positions and nothing else", "[format]") {
    const auto same = [](const std::string& a, const std::string& b) {
        SourceManager sources;
        Diagnostics diags;
        const Program pa = parse(sources.add("a.wsd", a), sources, diags);
        const Program pb = parse(sources.add("b.wsd", b), sources, diags);
        REQUIRE_FALSE(diags.has_errors());
        return same_ast(pa, pb);
    };
    CHECK(same("let a = 1 + 2 * 3", "let   a=1+2*3\n"));
    CHECK(same("mesh { vertices [<0,0,0>, <1,0,0>, <0,1,0>] faces [<0,1,2>] }",
               "mesh {\n vertices [<0, 0, 0>,\n <1, 0, 0>, <0, 1, 0>]\n faces [<0, 1, 2>]\n}"));
    CHECK(same("let a = 1.50", "let a = 1.5"));  // the same number
    CHECK_FALSE(same("let a = 1 + 2 * 3", "let a = (1 + 2) * 3"));
    CHECK_FALSE(same("let a = 1 - 2", "let a = 1 + 2"));
    CHECK_FALSE(same("let a = 1", "let b = 1"));
    CHECK_FALSE(same("let a = \"x\"", "let a = \"y\""));
    CHECK_FALSE(same("mesh { faces [<0,1,2>] }", "mesh { faces [<0,1,3>] }"));
    CHECK_FALSE(same("sphere { radius 1 }", "sphere { radius 1  center <0, 0, 0> }"));
    CHECK_FALSE(same("if a { f(1) } else { f(2) }", "if a { f(1) }"));
    CHECK_FALSE(same("fn f(a, b = 2) { return a }", "fn f(a, b = 3) { return a }"));
    CHECK_FALSE(same("let a = v.x", "let a = v.y"));
    CHECK(fmt("let a=(1).x") == "let a = (1).x\n");
}
