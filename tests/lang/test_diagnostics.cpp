// Diagnostics tests: the exact clang-style text (location, source line, caret and ~, tabs,
// notes, help, include chains, the error limit) and the "did you mean" matcher.
#include <catch2/catch.hpp>
#include <sstream>
#include <string>

#include "lang/diagnostics.h"

using namespace wsd::lang;

namespace {

uint32_t offset_of(const SourceManager& sources, uint32_t file, const std::string& needle) {
    return static_cast<uint32_t>(sources.file(file).text.find(needle));
}

Span span_of(const SourceManager& sources, uint32_t file, const std::string& needle) {
    const uint32_t at = offset_of(sources, file, needle);
    return {file, at, at + static_cast<uint32_t>(needle.size())};
}

}  // namespace

TEST_CASE("an error prints with its location, source line, caret and help", "[diagnostics]") {
    std::string text;
    for (int i = 1; i <= 11; ++i) text += "// line " + std::to_string(i) + "\n";
    text += "  radus 200\n}\n";  // line 12
    SourceManager sources;
    const uint32_t f = sources.add("scenes/cornell.wsd", text);
    Diagnostics diags;
    diags.error(span_of(sources, f, "radus"), "unknown property 'radus' in sphere")
        .help.push_back("did you mean 'radius'?");
    CHECK(format_diagnostics(diags, sources) ==
          "scenes/cornell.wsd:12:3: error: unknown property 'radus' in sphere\n"
          "   12 |   radus 200\n"
          "      |   ^~~~~\n"
          "      = help: did you mean 'radius'?\n");
}

TEST_CASE("notes print with their own source line; warnings say warning", "[diagnostics]") {
    SourceManager sources;
    const uint32_t f = sources.add("a.wsd", "let x = 1\nlet x = 2\n");
    Diagnostics diags;
    Diagnostic& d = diags.error({f, 14, 15}, "'x' is already defined in this scope");
    d.notes.push_back({{f, 4, 5}, "first defined here"});
    diags.warning({f, 18, 19}, "a warning");
    CHECK(diags.error_count() == 1);
    CHECK(format_diagnostics(diags, sources) ==
          "a.wsd:2:5: error: 'x' is already defined in this scope\n"
          "    2 | let x = 2\n"
          "      |     ^\n"
          "a.wsd:1:5: note: first defined here\n"
          "    1 | let x = 1\n"
          "      |     ^\n"
          "a.wsd:2:9: warning: a warning\n"
          "    2 | let x = 2\n"
          "      |         ^\n");
}

TEST_CASE("the caret line copies tabs and counts code points", "[diagnostics]") {
    SourceManager sources;
    const uint32_t f = sources.add("t.wsd", "\t\tradus 1\n\xC3\xA9t\xC3\xA9 radus\n");
    Diagnostics diags;
    diags.error({f, 2, 7}, "first");
    const uint32_t second = offset_of(sources, f, "radus\n");
    diags.error({f, second, second + 5}, "second");
    CHECK(format_diagnostics(diags, sources) ==
          "t.wsd:1:3: error: first\n"
          "    1 | \t\tradus 1\n"
          "      | \t\t^~~~~\n"
          "t.wsd:2:5: error: second\n"
          "    2 | \xC3\xA9t\xC3\xA9 radus\n"
          "      |     ^~~~~\n");
}

TEST_CASE("an error at the end of the file points past the last line", "[diagnostics]") {
    SourceManager sources;
    const uint32_t f = sources.add("t.wsd", "sphere {\n");
    Diagnostics diags;
    Diagnostic& d = diags.error({f, 9, 9}, "expected '}' to close sphere block, found end of file");
    d.notes.push_back({{f, 7, 8}, "to match this '{'"});
    CHECK(format_diagnostics(diags, sources) ==
          "t.wsd:2:1: error: expected '}' to close sphere block, found end of file\n"
          "    2 | \n"
          "      | ^\n"
          "t.wsd:1:8: note: to match this '{'\n"
          "    1 | sphere {\n"
          "      |        ^\n");
}

TEST_CASE("errors in an included file carry a note at each include site", "[diagnostics]") {
    SourceManager sources;
    const uint32_t main_file = sources.add("main.wsd", "include \"a.wsdi\"\n");
    const uint32_t a = sources.add("a.wsdi", "include \"b.wsdi\"\n");
    const uint32_t b = sources.add("b.wsdi", "let = 1\n");
    Diagnostics diags;
    diags.push_include({main_file, 8, 16});
    diags.push_include({a, 8, 16});
    diags.error({b, 4, 5}, "expected a name after 'let', found '='");
    diags.pop_include();
    diags.pop_include();
    diags.error({main_file, 0, 7}, "outside");
    REQUIRE(diags.all().size() == 2);
    CHECK(diags.all()[1].include_chain.empty());
    const std::vector<Note> notes = notes_with_includes(diags.all()[0]);
    REQUIRE(notes.size() == 2);
    CHECK(notes[0].span.file == a);  // innermost first
    CHECK(notes[1].span.file == main_file);
    CHECK(format_diagnostics(diags, sources) ==
          "b.wsdi:1:5: error: expected a name after 'let', found '='\n"
          "    1 | let = 1\n"
          "      |     ^\n"
          "a.wsdi:1:9: note: in file included from here\n"
          "    1 | include \"b.wsdi\"\n"
          "      |         ^~~~~~~~\n"
          "main.wsd:1:9: note: in file included from here\n"
          "    1 | include \"a.wsdi\"\n"
          "      |         ^~~~~~~~\n"
          "main.wsd:1:1: error: outside\n"
          "    1 | include \"a.wsdi\"\n"
          "      | ^~~~~~~\n");
}

TEST_CASE("after max_errors errors are counted but not kept", "[diagnostics]") {
    SourceManager sources;
    const uint32_t f = sources.add("t.wsd", "x\n");
    Diagnostics diags;
    for (size_t i = 0; i < Diagnostics::max_errors - 1; ++i) diags.error({f, 0, 1}, "e" + std::to_string(i));
    CHECK_FALSE(diags.too_many());
    CHECK(format_diagnostics(diags, sources).find("too many errors") == std::string::npos);
    diags.error({f, 0, 1}, "last kept");
    CHECK(diags.too_many());
    diags.error({f, 0, 1}, "dropped").notes.push_back({{f, 0, 1}, "dropped too"});
    CHECK(diags.all().size() == Diagnostics::max_errors);
    CHECK(diags.all().back().message == "last kept");
    CHECK(diags.error_count() == Diagnostics::max_errors + 1);
    const std::string text = format_diagnostics(diags, sources);
    CHECK(text.find("dropped") == std::string::npos);
    const std::string last = "\nerror: too many errors, stopping\n";
    REQUIRE(text.size() >= last.size());
    CHECK(text.substr(text.size() - last.size()) == last);
}

TEST_CASE("long lines are shown as a window around the caret", "[diagnostics]") {
    std::string line(10'000, 'a');
    line.replace(9'000, 5, "radus");
    SourceManager sources;
    const uint32_t f = sources.add("t.wsd", line + "\n");
    Diagnostics diags;
    diags.error({f, 9'000, 9'005}, "unknown");
    std::istringstream out(format_diagnostics(diags, sources));
    std::string header, source, caret;
    std::getline(out, header);
    std::getline(out, source);
    std::getline(out, caret);
    CHECK(header == "t.wsd:1:9001: error: unknown");
    CHECK(source.size() < 300);
    const size_t col = caret.find('^');
    REQUIRE(col != std::string::npos);
    CHECK(source.substr(col, 5) == "radus");
    CHECK(caret.substr(col) == "^~~~~");
}

TEST_CASE("invalid bytes are shown as replacement characters; wide line numbers widen the gutter",
          "[diagnostics]") {
    std::string text;
    for (int i = 0; i < 123'455; ++i) text += '\n';
    text +=
        "a\xFF"
        "b";
    SourceManager sources;
    const uint32_t f = sources.add("t.wsd", text);
    Diagnostics diags;
    diags.error({f, 123'456, 123'457}, "invalid UTF-8 byte 0xff");
    CHECK(format_diagnostics(diags, sources) ==
          "t.wsd:123456:2: error: invalid UTF-8 byte 0xff\n"
          "123456 | a\xEF\xBF\xBD"
          "b\n"
          "       |  ^\n");
}

TEST_CASE("closest_match suggests near misses only", "[diagnostics]") {
    const std::vector<std::string> props = {"center", "radius", "material", "look_at", "color", "colors"};
    CHECK(closest_match("radus", props) == "radius");
    CHECK(closest_match("raidus", props) == "radius");  // transposition counts one edit
    CHECK(closest_match("Radius", props) == "radius");
    CHECK(closest_match("lookat", props) == "look_at");
    CHECK(closest_match("colour", props) == "color");
    CHECK(closest_match("matrial", props) == "material");
    CHECK(closest_match("centre", props) == "center");
    CHECK(closest_match("xyz", props).empty());
    CHECK(closest_match("size", props).empty());
    CHECK(closest_match("", props).empty());
    CHECK(closest_match("radius", {}).empty());
    // One letter is too little to guess from: `f` is not taken for `if`, nor `o` for `on`.
    const std::vector<std::string> words = {"if", "in", "on", "for"};
    CHECK(closest_match("f", words).empty());
    CHECK(closest_match("o", words).empty());
    CHECK(closest_match("fo", words) == "for");
    CHECK(closest_match("iff", words) == "if");
}
