// The parser hard cases of docs/robustness.md as tests named by their
// R-number: R54 (malformed input, one table row per line), R55 (a large valid file), R56 (the
// semantic validation table) and a pointer to where R57 (fuzzing) runs. Each input goes through
// lang::load_scene, the whole front end that `wsd check` and `wsd render` run; an error row must
// leave no scene (so nothing is rendered) and report FILE:LINE:COL with the message.
// Where the reference and docs/wsd-language.md differ, the language reference wins.
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <clocale>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <locale>
#include <string>
#include <vector>

#include "eval_helpers.h"
#include "render/renderer.h"

using namespace wsd::lang;
using namespace wsd::lang::test;

namespace {

const std::string camera = kCamera;  // line 1 of most rows; the case itself is on line 2

struct Outcome {
    bool loaded = false;
    std::vector<std::string> errors;  // "FILE:LINE:COL: message", in report order
    std::vector<std::string> notes;   // the same form, over all errors
    std::vector<std::string> help;
    std::optional<LoadedScene> scene;
};

std::string locate(const SourceManager& sources, Span span) {
    const LineCol lc = sources.line_col(span.file, span.begin);
    return sources.file(span.file).path + ":" + std::to_string(lc.line) + ":" + std::to_string(lc.column);
}

Outcome load(const std::string& text, const std::string& path = "r54.wsd", bool build = true) {
    SourceManager sources;
    Diagnostics diags;
    LoadOptions options;
    options.build = build;
    options.threads = 1;
    Outcome out;
    out.scene = load_scene(path, text, sources, diags, options);
    out.loaded = out.scene.has_value();
    for (const Diagnostic& d : diags.all()) {
        if (d.severity != Severity::Error) continue;
        out.errors.push_back(locate(sources, d.span) + ": " + d.message);
        for (const Note& n : notes_with_includes(d))
            out.notes.push_back(locate(sources, n.span) + ": " + n.message);
        for (const std::string& h : d.help) out.help.push_back(h);
    }
    return out;
}

// One error row: the load fails, and its first error is at `at` and contains `message`.
void expect_error(const Outcome& out, const std::string& at, const std::string& message) {
    INFO("errors: " << Catch::Detail::stringify(out.errors));
    CHECK_FALSE(out.loaded);
    REQUIRE_FALSE(out.errors.empty());
    CHECK(out.errors[0].rfind(at + ": ", 0) == 0);
    CHECK(out.errors[0].find(message) != std::string::npos);
}

std::string repeat(const std::string& s, size_t n) {
    std::string out;
    out.reserve(s.size() * n);
    for (size_t i = 0; i < n; ++i) out += s;
    return out;
}

bool sanitized() {
    const char* s = std::getenv("WSD_SANITIZED");
    return s && std::string(s) == "1";
}

struct TempDir {
    std::filesystem::path path;
    TempDir() {
        static int n = 0;
        path = std::filesystem::temp_directory_path() /
               ("wsd-hard-" + std::to_string(::getpid()) + "-" + std::to_string(n++));
        std::filesystem::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    std::string write(const std::string& name, const std::string& text) const {
        const std::filesystem::path p = path / name;
        std::filesystem::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << text;
        return p.string();
    }
};

Outcome load_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return load(std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()), path);
}

struct Row {
    const char* what;
    std::string input;
    std::string at;       // FILE:LINE:COL of the first error
    std::string message;  // a substring of its message
};

void check_rows(const std::vector<Row>& rows) {
    for (const Row& row : rows) {
        INFO(row.what << ": " << row.input.substr(0, 200));
        expect_error(load(row.input), row.at, row.message);
    }
}

}  // namespace

TEST_CASE("R54: malformed input table", "[hard-cases][R54]") {
    const std::string c = camera;
    check_rows({
        {"empty file", "", "r54.wsd:1:1", "missing camera"},
        {"only comments", "// one\n/* two */\n", "r54.wsd:1:1", "missing camera"},
        {"unterminated block comment", c + "let x = 1 /* open\nto the end", "r54.wsd:2:11",
         "unterminated block comment"},
        {"nested comments: the outer opening", c + "let x = 1\n  /* outer /* inner */\n", "r54.wsd:3:3",
         "unterminated block comment"},
        {"string to the end of the file", c + "let s = \"abc", "r54.wsd:2:9", "unterminated string"},
        {"newline inside a string", c + "let s = \"ab\ncd\"\n", "r54.wsd:2:9", "unterminated string"},
        {"1e999", c + "let x = 1e999\n", "r54.wsd:2:9", "number '1e999' is too large for a double"},
        {"-1e999", c + "let x = -1e999\n", "r54.wsd:2:10", "number '1e999' is too large for a double"},
        {"1e309", c + "let x = 1e309\n", "r54.wsd:2:9", "number '1e309' is too large for a double"},
        // Geometry is single precision where it is stored as float: 1e39 fits a double, not a float.
        {"1e39 in a mesh",
         c + "mesh { vertices [<1e39, 0, 0>, <0, 1, 0>, <0, 0, 1>] faces [<0, 1, 2>] material { } }\n",
         "r54.wsd:2:18", "vertex 0 is too large for single precision"},
        {"1e39 as a sphere centre", c + "sphere { center <1e39, 0, 0>  radius 1  material { } }\n",
         "r54.wsd:2:1",
         "sphere is out of range: its bounds, after any transform, must stay within ±3.4e38 (the largest "
         "float)"},
        {"nan", c + "let x = nan\n", "r54.wsd:2:9", "unknown name 'nan'"},
        {"NaN", c + "let x = NaN\n", "r54.wsd:2:9", "unknown name 'NaN'"},
        {"inf", c + "let x = inf\n", "r54.wsd:2:9", "unknown name 'inf'"},
        {"infinity", c + "let x = -infinity\n", "r54.wsd:2:10", "unknown name 'infinity'"},
        {"+1: no unary plus", c + "let x = +1\n", "r54.wsd:2:9", "expected an expression, found '+'"},
        {"0x1p3", c + "let x = 0x1p3\n", "r54.wsd:2:9", "invalid number '0x1p3'"},
        {"1.2.3", c + "let x = 1.2.3\n", "r54.wsd:2:9", "invalid number '1.2.3'"},
        {"1e", c + "let x = 1e\n", "r54.wsd:2:9", "missing digits in the exponent of number '1e'"},
        {"1e+", c + "let x = 1e+\n", "r54.wsd:2:9", "missing digits in the exponent of number '1e+'"},
        {"1,5 as an expression", c + "let x = 1,5\n", "r54.wsd:2:10", "expected a statement, found ','"},
        {"1,5 as a one-valued property", c + "sphere { center <0, 0, 0>  radius 1,5  material { } }\n",
         "r54.wsd:2:37", "'radius' takes 1 value, found 2"},
        // Runtime errors: a binary operator at the operator, a call at the function's name.
        {"1/0", c + "let x = 1/0\n", "r54.wsd:2:10", "division by zero"},
        {"5 % 0", c + "let x = 5 % 0\n", "r54.wsd:2:11", "modulo by zero"},
        {"sqrt(-1)", c + "let x = sqrt(-1)\n", "r54.wsd:2:9", "'sqrt' of a negative number"},
        {"acos(2)", c + "let x = acos(2)\n", "r54.wsd:2:9", "'acos' of 2 is undefined"},
        {"log(0)", c + "let x = log(0)\n", "r54.wsd:2:9", "'log' of a number that is not positive"},
        {"exp(1000)", c + "let x = exp(1000)\n", "r54.wsd:2:9", "result of 'exp' is not a finite number"},
        {"pow(-8, 1/3)", c + "let x = pow(-8, 1/3)\n", "r54.wsd:2:9", "has no real value"},
        {"normalize(<0,0,0>)", c + "let x = normalize(<0,0,0>)\n", "r54.wsd:2:9",
         "'normalize' of a zero vector"},
        {"a loop of 1e9 iterations",
         c + "for i in 0 .. 1e9 { sphere { center <i, 0, 0>  radius 1  material { } } }\n", "r54.wsd:2:10",
         "loop of 1000000000 iterations exceeds the limit of 100000000"},
        {"99999999999 as width", c + "settings { width 99999999999 }\n", "r54.wsd:2:18",
         "'width' must be an integer from 1 to 100000, found 99999999999"},
        {"99999999999 as seed", c + "settings { seed 99999999999 }\n", "r54.wsd:2:17",
         "'seed' must be an integer from 0 to 4294967295, found 99999999999"},
        {"99999999999 as a mesh index",
         c + "mesh { vertices [<0, 0, 0>, <1, 0, 0>, <0, 1, 0>] faces [<0, 1, 99999999999>]  material { } "
             "}\n",
         "r54.wsd:2:58", "face 0: index 99999999999 is out of range (the mesh has 3 vertices)"},
        {"99999999999 as a loop bound", c + "for i in 0 .. 99999999999 { }\n", "r54.wsd:2:10",
         "loop of 99999999999 iterations exceeds the limit"},
        {"UTF-16 LE byte-order mark", std::string("\xFF\xFE") + "c\0a\0", "r54.wsd:1:1", "file is UTF-16"},
        {"UTF-16 BE byte-order mark", std::string("\xFE\xFF") + std::string("\0c\0a", 4), "r54.wsd:1:1",
         "file is UTF-16"},
        {"a NUL byte mid-file", c + std::string("let a = 1\0 + 2\n", 15), "r54.wsd:2:10",
         "invalid NUL byte (byte offset " + std::to_string(c.size() + 9) + ")"},
        {"truncated in a property name", c + "sphere { center <0, 0, 0>  rad", "r54.wsd:2:31",
         "expected a value for 'rad', found end of file"},
        {"truncated in a vector", c + "sphere { center <0, 0", "r54.wsd:2:22",
         "expected ',' or '>' after a vector component, found end of file"},
        {"truncated in a keyword", c + "sphe", "r54.wsd:2:1", "expected a statement, found 'sphe'"},
        {"10,000 nested parentheses", c + "let x = " + repeat("(", 10'000) + "1" + repeat(")", 10'000) + "\n",
         "r54.wsd:2:265", "nesting too deep (the limit is 256 nested blocks and expressions)"},
        {"100,000 nested blocks", c + repeat("if true { ", 100'000) + repeat("}", 100'000) + "\n",
         "r54.wsd:2:2564", "nesting too deep (the limit is 256 nested blocks and expressions)"},
        {"non-ASCII letters in a name", c + "let größe = 1\n", "r54.wsd:2:7",
         "invalid character 'ö' in name 'größe'"},
        {"unknown escape", c + "let s = \"a\\qb\"\n", "r54.wsd:2:11", "unknown escape sequence '\\q'"},
        {"undefined reference", c + "let radius = 1\nlet y = raduis\n", "r54.wsd:3:9",
         "unknown name 'raduis'"},
        {"a 2 kB file name", c + "include \"" + std::string(2000, 'f') + ".wsdi\"\n", "r54.wsd:2:9",
         "cannot read include file '" + std::string(2000, 'f') + ".wsdi'"},
        {"a 2 kB name",
         c + "let " + std::string(2000, 'n') + " = 1\nlet y = " + std::string(1999, 'n') + "m\n",
         "r54.wsd:3:9", "unknown name '" + std::string(1999, 'n') + "m'"},
    });
}

TEST_CASE("R54: invalid UTF-8 in a name, a string or a comment is an error at that byte",
          "[hard-cases][R54]") {
    // 0xFF never occurs in UTF-8; C0 80 is an overlong NUL (each byte is reported); 0x80 alone is
    // a continuation byte without a lead. The message gives the byte offset, the location line:col.
    for (const std::string bad : {"\xFF", "\xC0\x80", "\x80"}) {
        for (const std::string prefix : {"let a", "let s = \"a", "// a"}) {
            const std::string line =
                prefix + bad + (prefix[0] == 'l' && prefix[4] == 'a' ? "c = 1" : "\"") + "\n";
            const std::string at = "r54.wsd:2:" + std::to_string(prefix.size() + 1);
            char hex[8];
            std::snprintf(hex, sizeof hex, "0x%02x", static_cast<unsigned char>(bad[0]));
            INFO(line);
            expect_error(load(camera + line), at,
                         "invalid UTF-8 byte " + std::string(hex) + " (byte offset " +
                             std::to_string(camera.size() + prefix.size()) + ")");
        }
    }
}

TEST_CASE("R54: the number forms of the spec are accepted; -0 and --1 are unary minus", "[hard-cases][R54]") {
    const std::vector<std::pair<std::string, double>> numbers = {
        {"12", 12},     {"1.5", 1.5},         {".5", 0.5},   {"2.", 2},
        {"1e-3", 1e-3}, {"6.02E23", 6.02e23}, {"1e-400", 0},  // underflow is 0 (the language reference)
        {"--1", 1},     {"-0", -0.0}};
    for (const auto& [text, expected] : numbers) {
        INFO(text);
        const auto v = value_of(text);
        REQUIRE(v);
        REQUIRE(v->is(ValueType::Number));
        CHECK(v->number() == expected);
        CHECK(std::signbit(v->number()) == std::signbit(expected));
    }
}

TEST_CASE("R54: -0 does not flip a normal, a frame or a seam", "[hard-cases][R54]") {
    // The same scene with 0 and with -0 in every place a sign could matter renders the same pixels.
    const auto scene = [](const std::string& z) {
        return "settings { width 24  height 16 }\n"
               "camera { position <" +
               z + ", 1, -4>  look_at <" + z + ", 1, " + z + ">  up <" + z + ", 1, " + z +
               "> }\n"
               "light point { position <" +
               z +
               ", 5, -3> }\n"
               "plane { normal <" +
               z + ", 1, " + z + ">  distance " + z +
               "  material { texture checker { } } }\n"
               "sphere { center <" +
               z + ", 1, " + z + ">  radius 1  rotate <" + z + ", " + z + ", " + z +
               ">\n"
               "         material { texture perlin { kind marble }  bump perlin { }  reflection 0.3 } }\n";
    };
    const Outcome plus = load(scene("0"));
    const Outcome minus = load(scene("-0"));
    REQUIRE(plus.errors.empty());
    REQUIRE(minus.errors.empty());
    REQUIRE(plus.scene->scene);
    REQUIRE(minus.scene->scene);
    wsd::render::RenderOptions options;
    options.threads = 1;
    const auto a = wsd::render::render(*plus.scene->scene, options).film.rgb;
    const auto b = wsd::render::render(*minus.scene->scene, options).film.rgb;
    REQUIRE(a.size() == 24u * 16u * 3u);
    CHECK(*std::max_element(a.begin(), a.end()) > 0.1f);  // something is lit
    CHECK(a == b);
}

TEST_CASE("R54: a duplicate let and a second camera point at both places", "[hard-cases][R54]") {
    Outcome out = load(camera + "let x = 1\nlet x = 2\n");
    CHECK(out.errors == std::vector<std::string>{"r54.wsd:3:5: 'x' is already defined in this scope"});
    CHECK(out.notes.size() == 1);
    CHECK(out.notes.at(0).rfind("r54.wsd:2:5: ", 0) == 0);

    out = load(camera + "camera { position <0, 0, 5>  look_at <0, 0, 0> }\n");
    CHECK(out.errors == std::vector<std::string>{"r54.wsd:2:1: more than one camera"});
    CHECK(out.notes.size() == 1);
    CHECK(out.notes.at(0).rfind("r54.wsd:1:1: ", 0) == 0);
    CHECK_FALSE(out.loaded);
}

TEST_CASE("R54: an unknown property suggests the close one", "[hard-cases][R54]") {
    const Outcome out = load(camera + "sphere { center <0, 0, 0>  radus 1  material { } }\n");
    REQUIRE_FALSE(out.errors.empty());
    CHECK(out.errors[0] == "r54.wsd:2:28: unknown property 'radus' in sphere");
    CHECK(out.help.at(0) == "did you mean 'radius'?");
}

TEST_CASE("R54: independent errors are all reported, in source order, up to the limit", "[hard-cases][R54]") {
    // Syntax errors: the parser recovers at the next statement.
    Outcome out = load(camera + "let = 1\nlet b = )\nsphere { radius 1 2 }\n");
    CHECK(out.errors.size() == 3);
    for (size_t i = 0; i < out.errors.size(); ++i)
        CHECK(out.errors[i].rfind("r54.wsd:" + std::to_string(i + 2) + ":", 0) == 0);
    CHECK_FALSE(out.loaded);
    // Runtime and block errors: evaluation goes on after each.
    out = load(camera +
               "let a = 1 / 0\nlet b = sqrt(-1)\nsphere { center <0, 0, 0>  radius -1  material { } }\n");
    CHECK(out.errors == std::vector<std::string>{"r54.wsd:2:11: division by zero",
                                                 "r54.wsd:3:9: 'sqrt' of a negative number (-1)",
                                                 "r54.wsd:4:35: 'radius' must be > 0, found -1"});
    // 30 errors: the first 20 are kept, in order.
    out = load(camera + repeat("let = 1\n", 30));
    REQUIRE(out.errors.size() == Diagnostics::max_errors);
    CHECK(out.errors.back().rfind("r54.wsd:21:5: ", 0) == 0);
}

TEST_CASE("R54: a NUL byte does not truncate the file", "[hard-cases][R54]") {
    const Outcome out = load(camera + std::string("let a = 1\0\nlet = 2\n", 19));
    CHECK(out.errors == std::vector<std::string>{"r54.wsd:2:10: invalid NUL byte (byte offset " +
                                                     std::to_string(camera.size() + 9) + ")",
                                                 "r54.wsd:3:5: expected a name after 'let', found '='"});
}

TEST_CASE("R54: a UTF-8 byte-order mark is skipped", "[hard-cases][R54]") {
    const Outcome out = load("\xEF\xBB\xBF" + camera + "let x = 1 / 0\n");
    CHECK(out.errors == std::vector<std::string>{"r54.wsd:2:11: division by zero"});
    CHECK(load("\xEF\xBB\xBF" + camera).loaded);
}

TEST_CASE("R54: LF, CRLF and lone CR each count lines; tabs and code points count one column",
          "[hard-cases][R54]") {
    for (const std::string eol : {"\n", "\r\n", "\r"}) {
        const Outcome out = load("camera { position <0, 0, -5>  look_at <0, 0, 0> }" + eol + "// two" + eol +
                                 "let x = 1 / 0" + eol);
        CHECK(out.errors == std::vector<std::string>{"r54.wsd:3:11: division by zero"});
    }
    CHECK(load(camera + "\t\tlet x = \t1 / 0\n").errors ==
          std::vector<std::string>{"r54.wsd:2:14: division by zero"});
    CHECK(load(camera + "let s = \"größe\" + 1\n").errors ==
          std::vector<std::string>{"r54.wsd:2:17: operator '+' cannot combine string and number"});
}

TEST_CASE("R54: include cycles, missing includes and missing textures name the paths", "[hard-cases][R54]") {
    TempDir dir;
    const std::string root = dir.path.string() + "/";
    dir.write("a.wsdi", "include \"b.wsdi\"\n");
    dir.write("b.wsdi", "\ninclude \"a.wsdi\"\n");
    Outcome out = load_file(dir.write("main.wsd", camera + "include \"a.wsdi\"\n"));
    CHECK(out.errors ==
          std::vector<std::string>{root + "b.wsdi:2:9: include cycle: a.wsdi → b.wsdi → a.wsdi"});
    CHECK_FALSE(out.loaded);

    out = load_file(dir.write("self.wsd", camera + "include \"self.wsd\"\n"));
    CHECK(out.errors == std::vector<std::string>{root + "self.wsd:2:9: include cycle: self.wsd → self.wsd"});

    out = load_file(dir.write("sub/missing.wsd", camera + "include \"../none/x.wsdi\"\n"));
    CHECK(out.errors == std::vector<std::string>{root + "sub/missing.wsd:2:9: cannot read include file '" +
                                                 (dir.path / "sub/../none/x.wsdi").string() +
                                                 "': no such file or directory"});

    out =
        load_file(dir.write("sub/texture.wsd", camera + "sphere { center <0, 0, 0>  radius 1\n"
                                                        "  material { texture image \"tex/none.png\" } }\n"));
    INFO(Catch::Detail::stringify(out.errors));
    REQUIRE(out.errors.size() == 1);
    CHECK(out.errors[0].rfind(root + "sub/texture.wsd:3:28: ", 0) == 0);
    CHECK(out.errors[0].find((dir.path / "sub/tex/none.png").string()) != std::string::npos);
    CHECK_FALSE(out.loaded);
}

TEST_CASE("R54: a 10 MB line and a long list are handled", "[hard-cases][R54][large]") {
    // Release: a 10 MB line; under ASan+UBSan (WSD_SANITIZED=1) a tenth, same checks.
    const size_t scale = sanitized() ? 10 : 1;
    const std::string sphere = "sphere { center <1, 2, 3>  radius 1  material m }  ";
    const size_t spheres = 10'000'000 / sphere.size() / scale;
    Outcome out = load(camera + "let m = material { }  " + repeat(sphere, spheres) + "sphere { radus 1 }\n",
                       "r54.wsd", false);
    const size_t column = 23 + spheres * sphere.size() + 9;
    INFO(Catch::Detail::stringify(out.errors));
    REQUIRE_FALSE(out.errors.empty());
    CHECK(out.errors[0] == "r54.wsd:2:" + std::to_string(column) + ": unknown property 'radus' in sphere");

    // A loop over a long list runs in memory proportional to the list: a scope per iteration, no
    // objects. 10^7 elements also finish (wsd check: about 11 s and 2 GB, some 200 bytes per element
    // of the list literal), too much for the suite; 10^6 here, 10^5 under the sanitizers.
    const size_t elements = 1'000'000 / scale;
    out = load(camera + "let xs = [" + repeat("1,", elements) +
                   "]\nlet total = 0\n"
                   "for x in xs { let y = x + total }\nlet n = len(xs) / 0\n",
               "r54.wsd", false);
    CHECK(out.errors == std::vector<std::string>{"r54.wsd:5:17: division by zero"});
}

TEST_CASE("R54: numbers parse and print the same under a comma-decimal locale", "[hard-cases][R54]") {
    // de_DE.UTF-8 where installed; a C++ locale with ',' as the decimal point in any case.
    struct comma : std::numpunct<char> {
        char do_decimal_point() const override { return ','; }
    };
    const std::string c_locale = std::setlocale(LC_ALL, nullptr);
    const std::locale cpp_locale = std::locale::global(std::locale(std::locale::classic(), new comma));
    if (!std::setlocale(LC_ALL, "de_DE.UTF-8"))
        WARN("de_DE.UTF-8 is not installed: only the C++ locale is set");
    const auto v = value_of("1.5");
    const Outcome out = load(camera + "settings { max_depth 2.5 }\n");
    std::setlocale(LC_ALL, c_locale.c_str());
    std::locale::global(cpp_locale);
    REQUIRE(v);
    CHECK(v->number() == 1.5);
    CHECK(out.errors ==
          std::vector<std::string>{"r54.wsd:2:22: 'max_depth' must be an integer from 0 to 256, found 2.5"});
}

// R54 rows covered elsewhere as well: the end-to-end `wsd check` status and output for empty,
// garbage, NUL, bad UTF-8, deep nesting, unterminated and 100 MB input (tests/app/hostile_test.cpp);
// the nesting limit on a small thread stack ("R54: the nesting limit fits a 512 KiB thread stack",
// tests/lang/test_parser.cpp); the lexer and golden files (tests/lang/test_lexer.cpp,
// tests/golden/syntax/). The reference's `1e-400` "error or warning" is neither here: the language
// reference makes underflow 0, tested above.

TEST_CASE("R56: semantic validation table", "[hard-cases][R56]") {
    const std::string c = camera;
    const std::string sphere = c + "sphere { center <0, 0, 0>  radius 1  material { ";
    const std::string light = c + "light area { position <0, 5, 0>  ";
    check_rows({
        {"radius 0", c + "sphere { center <0, 0, 0>  radius 0  material { } }\n", "r54.wsd:2:35",
         "'radius' must be > 0, found 0"},
        {"radius < 0", c + "sphere { center <0, 0, 0>  radius -2  material { } }\n", "r54.wsd:2:35",
         "'radius' must be > 0, found -2"},
        // A degenerate triangle is found by the scene builder; an object is reported at its keyword,
        // a mesh face at the face's literal (the language reference: naming the face and the line).
        {"zero-area triangle", c + "triangle { <0, 0, 0>, <1, 1, 1>, <2, 2, 2>  material { } }\n",
         "r54.wsd:2:1", "degenerate triangle"},
        {"zero-area mesh face",
         c + "mesh { vertices [<0, 0, 0>, <1, 0, 0>, <2, 0, 0>] faces [<0, 1, 2>]  material { } }\n",
         "r54.wsd:2:58", "face 0: degenerate triangle"},
        {"mesh index out of range",
         c + "mesh { vertices [<0, 0, 0>, <1, 0, 0>, <0, 1, 0>] faces [<0, 1, 2>, <2, 1, 3>]  material { } "
             "}\n",
         "r54.wsd:2:69", "face 1: index 3 is out of range (the mesh has 3 vertices)"},
        {"negative mesh index",
         c + "mesh { vertices [<0, 0, 0>, <1, 0, 0>, <0, 1, 0>] faces [<0, -1, 2>]  material { } }\n",
         "r54.wsd:2:58", "face 0: index -1 is out of range"},
        // No NaN can be written in .wsd: `nan` is a name and a NaN result is an error where it arises.
        {"a NaN coordinate by name", c + "sphere { center <nan, 0, 0>  radius 1  material { } }\n",
         "r54.wsd:2:18", "unknown name 'nan'"},
        {"a NaN coordinate by arithmetic",
         c + "sphere { center <0 * (1e308 * 10), 0, 0>  radius 1  material { } }\n", "r54.wsd:2:29",
         "result of '*' is not a finite number"},
        {"ior 0", sphere + "ior 0 } }\n", "r54.wsd:2:53", "'ior' must be > 0, found 0"},
        {"ior < 0", sphere + "ior -1.5 } }\n", "r54.wsd:2:53", "'ior' must be > 0, found -1.5"},
        {"reflection < 0", sphere + "reflection -0.1 } }\n", "r54.wsd:2:60",
         "'reflection' must be in [0, 1], found -0.1"},
        {"reflection > 1", sphere + "reflection 1.5 } }\n", "r54.wsd:2:60",
         "'reflection' must be in [0, 1], found 1.5"},
        {"transmission < 0", sphere + "transmission -0.1 } }\n", "r54.wsd:2:62",
         "'transmission' must be in [0, 1], found -0.1"},
        {"transmission > 1", sphere + "transmission 2 } }\n", "r54.wsd:2:62",
         "'transmission' must be in [0, 1], found 2"},
        {"shininess 0", sphere + "shininess 0 } }\n", "r54.wsd:2:59", "'shininess' must be > 0, found 0"},
        {"shininess < 0", sphere + "shininess -5 } }\n", "r54.wsd:2:59", "'shininess' must be > 0, found -5"},
        {"ambient < 0", sphere + "ambient -0.5 } }\n", "r54.wsd:2:57", "'ambient' must be >= 0, found -0.5"},
        {"diffuse < 0", sphere + "diffuse -1 } }\n", "r54.wsd:2:57", "'diffuse' must be >= 0, found -1"},
        {"specular < 0", sphere + "specular -1 } }\n", "r54.wsd:2:58", "'specular' must be >= 0, found -1"},
        {"bump_strength < 0", sphere + "bump perlin { }  bump_strength -0.3 } }\n", "r54.wsd:2:80",
         "'bump_strength' must be >= 0, found -0.3"},
        {"absorption < 0", sphere + "absorption <0, -1, 0> } }\n", "r54.wsd:2:60",
         "'absorption' must have components >= 0, found <0, -1, 0>"},
        {"settings ambient < 0", c + "settings { ambient -0.1 }\n", "r54.wsd:2:20",
         "'ambient' must be >= 0, found -0.1"},
        {"width 0", c + "settings { width 0 }\n", "r54.wsd:2:18",
         "'width' must be an integer from 1 to 100000, found 0"},
        {"height < 1", c + "settings { height -3 }\n", "r54.wsd:2:19",
         "'height' must be an integer from 1 to 100000, found -3"},
        {"supersamples 0", c + "settings { supersamples 0 }\n", "r54.wsd:2:25",
         "'supersamples' must be an integer from 1 to 4096, found 0"},
        {"max_depth < 0", c + "settings { max_depth -1 }\n", "r54.wsd:2:22",
         "'max_depth' must be an integer from 0 to 256, found -1"},
        {"fov 0", "camera { position <0, 0, -5>  look_at <0, 0, 0>  fov 0 }\n", "r54.wsd:1:54",
         "'fov' must be in (0, 180), found 0"},
        {"fov 180", "camera { position <0, 0, -5>  look_at <0, 0, 0>  fov 180 }\n", "r54.wsd:1:54",
         "'fov' must be in (0, 180), found 180"},
        {"fov < 0", "camera { position <0, 0, -5>  look_at <0, 0, 0>  fov -30 }\n", "r54.wsd:1:54",
         "'fov' must be in (0, 180), found -30"},
        {"fov > 180", "camera { position <0, 0, -5>  look_at <0, 0, 0>  fov 270 }\n", "r54.wsd:1:54",
         "'fov' must be in (0, 180), found 270"},
        {"area light u zero", light + "u <0, 0, 0>  v <0, 0, 1> }\n", "r54.wsd:2:36",
         "area light edge 'u' must not be the zero vector"},
        {"area light v zero", light + "u <1, 0, 0>  v <0, 0, 0> }\n", "r54.wsd:2:49",
         "area light edge 'v' must not be the zero vector"},
        {"area light u parallel to v", light + "u <1, 0, 0>  v <-3, 0, 0> }\n", "r54.wsd:2:49",
         "area light edges 'u' and 'v' are parallel"},
        {"camera up parallel to the view",
         "camera { position <0, 0, 0>  look_at <0, 0, 5>  up <0, 0, -1> }\n", "r54.wsd:1:52",
         "camera 'up' is parallel to the view direction (look_at - position)"},
        {"camera looking along the default up", "camera { position <0, 0, 0>  look_at <0, -5, 0> }\n",
         "r54.wsd:1:38", "camera looks along the default 'up' <0, 1, 0>"},
    });
    // The boundaries that are allowed: ior 1 (an identity, R43a), reflection and transmission 0
    // and 1, max_depth 0, zero ambient, diffuse, specular, bump_strength and absorption.
    CHECK(load(sphere +
               "ior 1  transmission 1  ambient 0  diffuse 0  specular 0  bump perlin { }  bump_strength 0  "
               "absorption <0, 0, 0> } }\nsettings { max_depth 0  width 1  height 1  supersamples 1 }\n")
              .loaded);
    CHECK(load(sphere + "reflection 1  shininess 1e-9 } }\n").loaded);
}

TEST_CASE("R56: a NaN or an index out of range in an OBJ file names the file and its line",
          "[hard-cases][R56]") {
    TempDir dir;
    dir.write("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    dir.write("index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n");
    const std::string root = dir.path.string() + "/";
    Outcome out = load_file(dir.write("nan.wsd", camera + "mesh { file \"nan.obj\"  material { } }\n"));
    REQUIRE(out.errors.size() == 1);
    CHECK(out.errors[0].rfind(root + "nan.wsd:2:13: ", 0) == 0);
    CHECK(out.errors[0].find("nan.obj:2: number 'nan' is not finite") != std::string::npos);
    out = load_file(dir.write("index.wsd", camera + "mesh { file \"index.obj\"  material { } }\n"));
    REQUIRE(out.errors.size() == 1);
    CHECK(out.errors[0].rfind(root + "index.wsd:2:13: ", 0) == 0);
    CHECK(out.errors[0].find("index.obj:5: vertex index 9 out of range") != std::string::npos);
}

namespace {

// n spheres written out one per line, and the same scene as a loop.
std::string literal_spheres(size_t n) {
    std::string text = camera + "let m = material { color <1, 0.5, 0.25> }\n";
    text.reserve(text.size() + n * 64);
    for (size_t i = 0; i < n; ++i)
        text += "sphere { center <" + std::to_string(i % 1000) + ", " + std::to_string(i / 1000) +
                ", -1.25>  radius 0.375  material m }\n";
    return text;
}

}  // namespace

// R55 asks for a 100 MB scene and a 10^7-triangle OBJ, a linear parse time, memory within twice
// the final scene, and equality with the same scene loaded from a binary format. Here: 2·10^5
// spheres (11 MB) and a 2·10^6-triangle OBJ (64 MB) in Release, a tenth of the spheres and a
// hundredth of the mesh under ASan+UBSan (WSD_SANITIZED=1); the 100 MB read is
// tests/app/hostile_test.cpp's. Linear time is a speed figure, measured by bench/bench_parse
// (MB/s on a 1 M-triangle scene), not timed here. wsd has no binary scene format, so the literal
// file is compared with the same scene written as a loop. Memory is
// not asserted, and R55's bound is not met: the syntax tree holds about 1.9 KB per sphere
// statement (peak about 2.5 KB per sphere through lowering, so a 100 MB file of spheres needs
// some 4 GB), against about 0.5 KB for the sphere in the final scene.
TEST_CASE("R55: a large valid file loads completely and equals the same scene as a loop",
          "[hard-cases][R55][large]") {
    const size_t n = sanitized() ? 20'000 : 200'000;
    const std::string text = literal_spheres(n);
    {
        const Outcome literal = load(text, "r55.wsd", false);
        REQUIRE(literal.errors.empty());
        REQUIRE(literal.loaded);
        const Outcome looped =
            load(camera +
                     "let m = material { color <1, 0.5, 0.25> }\n"
                     "for i in 0 .. " +
                     std::to_string(n) +
                     " {\n"
                     "    sphere { center <i % 1000, floor(i / 1000), -1.25>  radius 0.375  material m }\n"
                     "}\n",
                 "r55.wsd", false);
        REQUIRE(looped.loaded);
        const auto& a = literal.scene->spec.shapes;
        const auto& b = looped.scene->spec.shapes;
        REQUIRE(a.size() == n);
        REQUIRE(b.size() == n);
        size_t differ = 0;
        for (size_t i = 0; i < n; ++i)
            if (a[i].center != b[i].center || a[i].radius != b[i].radius || a[i].material != b[i].material)
                ++differ;
        CHECK(differ == 0);
        CHECK(a.back().center == glm::dvec3((n - 1) % 1000, (n - 1) / 1000, -1.25));
        CHECK(literal.scene->summary.objects == n);
        CHECK(literal.scene->summary.materials == 1);
    }
}

TEST_CASE("R55: a large OBJ mesh loads completely", "[hard-cases][R55][large]") {
    // A grid of k x k squares, two triangles each.
    const size_t k = sanitized() ? 100 : 1000;
    std::string obj;
    obj.reserve((k + 1) * (k + 1) * 24 + k * k * 2 * 28);
    for (size_t y = 0; y <= k; ++y)
        for (size_t x = 0; x <= k; ++x) obj += "v " + std::to_string(x) + " " + std::to_string(y) + " 0\n";
    for (size_t y = 0; y < k; ++y)
        for (size_t x = 0; x < k; ++x) {
            const size_t v = y * (k + 1) + x + 1;  // OBJ indices start at 1
            obj += "f " + std::to_string(v) + " " + std::to_string(v + 1) + " " + std::to_string(v + k + 2) +
                   "\n";
            obj += "f " + std::to_string(v) + " " + std::to_string(v + k + 2) + " " +
                   std::to_string(v + k + 1) + "\n";
        }
    TempDir dir;
    dir.write("grid.obj", obj);
    const std::string path = dir.write("grid.wsd", camera + "mesh { file \"grid.obj\"  material { } }\n");
    std::ifstream in(path, std::ios::binary);
    const Outcome out = load(
        std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()), path, false);
    REQUIRE(out.errors.empty());
    REQUIRE(out.loaded);
    CHECK(out.scene->summary.triangles == 2 * k * k);
    const auto& mesh = *out.scene->spec.shapes.at(0).mesh;
    REQUIRE(mesh.vertices.size() == (k + 1) * (k + 1));
    REQUIRE(mesh.faces.size() == 2 * k * k);
    CHECK(mesh.vertices.back() == glm::vec3(k, k, 0));
    CHECK(mesh.faces.back() ==
          glm::uvec3((k - 1) * (k + 1) + k - 1, (k + 1) * (k + 1) - 1, (k + 1) * (k + 1) - 2));
}

// R57 (parser fuzzing in CI) is not a unit test: fuzz/fuzz_lang.cpp is a libFuzzer target over the
// whole front end (parse, print_ast, diagnostics, load_scene without building), and .ci/fuzz.sh
// runs it under ASan+UBSan for a bounded time (WSD_FUZZ_SECONDS, default 60 s), seeded with every
// scene under tests/golden and examples/. A finding is added here or in tests/golden as a
// regression case.

namespace {

// `first OP term OP term ...` with `terms` terms in all.
std::string chain(const std::string& first, const std::string& op_term, size_t terms) {
    return first + repeat(op_term, terms - 1);
}

size_t count_of(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
    return n;
}

}  // namespace

TEST_CASE("a flat chain of 150,000 terms checks, loads and prints", "[hard-cases][chain][large]") {
    // Generated scenes write such lines; a chain of one operator level is one node, walked with
    // loops, so its length costs no stack in any pass.
    const size_t terms = 150'000;
    const struct {
        std::string text;
        double value;  // or -1: a bool, true
    } chains[] = {
        {chain("1", "+1", terms), 150'000},       {chain("1", "*1", terms), 1},
        {chain("2", "-1", terms), 2 - 149'999.0}, {chain("1", "+1-1", terms / 2), 1},
        {chain("true", "&&true", terms), -1},     {chain("false", "||false", terms - 1) + "||true", -1},
    };
    for (const auto& c : chains) {
        INFO(c.text.substr(0, 20));
        const auto e = evaluate_text("let x = " + c.text + "\n");
        CHECK(e->errors().empty());
        const std::optional<Value> v = e->get("x");
        REQUIRE(v);
        if (c.value == -1)
            CHECK(v->boolean());
        else
            CHECK(v->number() == c.value);
        // The whole front end, as `wsd check` runs it, with the value used by an object.
        const std::string use = c.value == -1 ? "sphere { center <0, 0, 0>  radius 1  material { } }\n"
                                              : "sphere { center <0, 0, x * 0>  radius 1  material { } }\n";
        for (const bool build : {true, false}) {  // `wsd check`, and the load without building
            const Outcome out = load(camera + "let x = " + c.text + "\n" + use, "r54.wsd", build);
            CHECK(out.errors.empty());
            CHECK(out.loaded);
        }
    }
    // The AST dump prints the chain flat: one operand and one operator a line.
    SourceManager sources;
    Diagnostics diags;
    const uint32_t file = sources.add("chain.wsd", "let x = " + chain("1", " + 1", terms) + "\n");
    const std::string ast = print_ast(parse(file, sources, diags), sources);
    CHECK_FALSE(diags.has_errors());
    CHECK(ast.rfind("(let x @1:1\n  (chain @1:9\n    (number 1 @1:9)\n    (op + @1:11)\n", 0) == 0);
    CHECK(count_of(ast, "(op + ") == terms - 1);
    CHECK(count_of(ast, "(number 1 ") == terms);
}

TEST_CASE("a flat sum of 1,000,000 terms evaluates", "[hard-cases][chain][large]") {
    if (sanitized()) {
        WARN("skipped: WSD_SANITIZED=1");
        return;
    }
    const auto e = evaluate_text("let x = " + chain("1", "+1", 1'000'000) + "\n");
    CHECK(e->errors().empty());
    const std::optional<Value> v = e->get("x");
    REQUIRE(v);
    CHECK(v->number() == 1'000'000);
}

TEST_CASE("R86: a zero-area emitter is an error at its material; negative emission is refused",
          "[hard-cases][R86]") {
    const std::string scene = camera + "settings { indirect_samples 1 }\n" +
                              "sphere { center <0, 0, 0>  radius 1e-170  material { emission <1, 1, 1> } }\n";
    const Outcome out = load(scene, "r86.wsd");
    expect_error(out, "r86.wsd:3:52", "an emissive sphere must have a finite, non-zero area");
    expect_error(load(camera + "sphere { center <0, 0, 0>  radius 1  material { emission <0, -1, 0> } }\n"),
                 "r54.wsd:2:58", "'emission' must have components >= 0, found <0, -1, 0>");
}
