// The editor grammars (editors/vscode/syntaxes/wsd.tmLanguage.json and editors/vim/syntax/wsd.vim)
// name exactly the words the language knows: its keywords (the lexer's), the property names of
// every block and the words properties take (the property tables, generated from the render
// tables), the light kinds, and the built-in functions and constants. A word added to the
// language and not to a grammar, or left in a grammar after leaving the language, fails here
// with the list the grammar should have.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "lang/builtins.h"
#include "lang/lexer.h"
#include "lang/lower.h"
#include "render/params.h"

using namespace wsd;
namespace fs = std::filesystem;

namespace {

using Words = std::set<std::string>;

std::string read_text(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    REQUIRE(in);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string joined(const Words& words, const char* separator) {
    std::string out;
    for (const std::string& w : words) out += (out.empty() ? "" : separator) + w;
    return out;
}

// What the language knows, from its own tables.
struct LanguageWords {
    Words keywords, properties, property_words, light_kinds, functions, constants;
};

LanguageWords language_words() {
    LanguageWords w;
    for (int k = 0; k < 256; ++k) {
        const auto kind = static_cast<lang::TokenKind>(k);
        const std::string_view spelling = lang::token_spelling(kind);
        if (!spelling.empty() && lang::keyword_kind(spelling) == kind) w.keywords.emplace(spelling);
    }
    // Every block with a property table: the render elements' (by their names), and the group and
    // CSG blocks, which share one element.
    std::vector<std::string> blocks = {"group", "union", "intersection", "difference"};
    for (int e = 0; e < render::kElementCount; ++e) {
        const std::string name(render::element_table(static_cast<render::Element>(e)).name);
        blocks.push_back(name);
        if (name.starts_with("light ")) w.light_kinds.insert(name.substr(6));
    }
    for (const std::string& block : blocks) {
        const lang::BlockTable* table = nullptr;
        try {
            table = &lang::block_table(block);
        } catch (const std::out_of_range&) {
            continue;  // an element written without a block (`image "file"`, the CSG element)
        }
        for (const lang::Property& p : table->properties) {
            if (!p.name.empty() && !w.keywords.count(std::string(p.name))) w.properties.emplace(p.name);
            for (std::string_view word : p.words()) w.property_words.emplace(word);
        }
        if (table->transforms)
            for (const char* t : {"scale", "rotate", "translate"}) w.properties.insert(t);
    }
    for (const lang::Builtin& b : lang::builtin_functions()) w.functions.emplace(b.name);
    for (const lang::BuiltinConstant& c : lang::builtin_constants()) w.constants.emplace(c.name);
    return w;
}

// The alternatives of a regular expression's group that starts at `open` (just past its '('),
// split at top-level `separator`s, up to `close`.
Words alternatives(const std::string& regex, size_t open, const std::string& separator,
                   const std::string& close) {
    const size_t end = regex.find(close, open);
    REQUIRE(end != std::string::npos);
    Words out;
    const std::string list = regex.substr(open, end - open);
    for (size_t at = 0;;) {
        const size_t next = list.find(separator, at);
        out.insert(list.substr(at, next == std::string::npos ? std::string::npos : next - at));
        if (next == std::string::npos) break;
        at = next + separator.size();
    }
    return out;
}

// The words of a TextMate rule: its match's first capturing group, `(a|b|c)`.
Words textmate_words(const nlohmann::json& grammar, const std::string& rule) {
    INFO("TextMate rule " << rule);
    REQUIRE(grammar["repository"].contains(rule));
    const std::string regex = grammar["repository"][rule]["match"].get<std::string>();
    size_t open = regex.find('(');
    while (open != std::string::npos && open + 1 < regex.size() && regex[open + 1] == '?')
        open = regex.find('(', open + 1);
    REQUIRE(open != std::string::npos);
    return alternatives(regex, open + 1, "|", ")");
}

// The words of a Vim syntax group: those of its `syn keyword` lines (without their options), and
// of the last `\%(a\|b\)` group of its `syn match` lines.
Words vim_words(const std::string& syntax, const std::string& group) {
    Words out;
    std::istringstream lines(syntax);
    for (std::string line; std::getline(lines, line);) {
        std::istringstream items(line);
        std::string command, name;
        items >> command >> name;
        if (command != "syn" || name.empty()) continue;
        std::string what = name;
        items >> name;
        if (name != group) continue;
        if (what == "keyword") {
            static const Words options = {"contained", "transparent", "skipwhite", "skipnl",
                                          "skipempty", "conceal",     "fold",      "display"};
            for (std::string word; items >> word;)
                if (word.find('=') == std::string::npos && !options.count(word)) out.insert(word);
        } else if (what == "match") {
            const size_t open = line.rfind("\\%(");
            REQUIRE(open != std::string::npos);
            const Words words = alternatives(line, open + 3, "\\|", "\\)");
            out.insert(words.begin(), words.end());
        }
    }
    return out;
}

void check_same(const std::string& what, const Words& grammar, const Words& language) {
    INFO(what << ": the grammar lists " << joined(grammar, " ") << "\nthe language knows "
              << joined(language, " ") << "\n(as a TextMate alternation: " << joined(language, "|") << ")");
    CHECK(grammar == language);
}

}  // namespace

TEST_CASE("the language's word lists are what the editor grammars are checked against", "[editors]") {
    const LanguageWords w = language_words();
    CHECK(w.keywords.count("sphere"));
    CHECK(w.keywords.count("let"));
    CHECK(w.properties.count("radius"));
    CHECK(w.properties.count("look_at"));
    CHECK(w.properties.count("translate"));
    CHECK(w.properties.count("base"));            // the material's own, not a render field's
    CHECK_FALSE(w.properties.count("material"));  // a keyword, highlighted as one
    CHECK(w.property_words.count("jittered"));
    CHECK(w.light_kinds == Words{"area", "point", "spot"});
    CHECK(w.functions.count("atan2"));
    CHECK(w.constants.count("pi"));
}

TEST_CASE("the VS Code grammar lists every keyword, property, word and built-in of the language",
          "[editors]") {
    const LanguageWords w = language_words();
    const auto grammar = nlohmann::json::parse(
        read_text(fs::path(WSD_SOURCE_DIR) / "editors" / "vscode" / "syntaxes" / "wsd.tmLanguage.json"));
    const std::vector<std::string> keyword_rules = {
        "control-keywords", "declaration-keywords", "block-keywords", "csg-keywords",
        "group-keywords",   "value-keywords",       "booleans"};
    size_t keyword_count = 0;
    Words keywords;
    for (const std::string& rule : keyword_rules) {
        const Words words = textmate_words(grammar, rule);
        keyword_count += words.size();
        keywords.insert(words.begin(), words.end());
    }
    check_same("keywords", keywords, w.keywords);
    CHECK(keyword_count == keywords.size());  // each keyword in one rule
    check_same("properties", textmate_words(grammar, "properties"), w.properties);
    check_same("property words", textmate_words(grammar, "property-values"), w.property_words);
    check_same("light kinds", textmate_words(grammar, "light-kinds"), w.light_kinds);
    check_same("built-in functions", textmate_words(grammar, "builtin-functions"), w.functions);
    check_same("built-in constants", textmate_words(grammar, "builtin-constants"), w.constants);
    // Every rule the grammar names is defined.
    for (const auto& pattern : grammar["repository"]["code"]["patterns"]) {
        const std::string include = pattern["include"].get<std::string>();
        INFO(include);
        CHECK(grammar["repository"].contains(include.substr(1)));
    }
}

TEST_CASE("the Vim syntax file lists every keyword, property, word and built-in of the language",
          "[editors]") {
    const LanguageWords w = language_words();
    const std::string syntax = read_text(fs::path(WSD_SOURCE_DIR) / "editors" / "vim" / "syntax" / "wsd.vim");
    Words keywords;
    for (const char* group :
         {"wsdControl", "wsdDeclaration", "wsdBlock", "wsdCsg", "wsdGroup", "wsdValueBlock", "wsdBoolean"}) {
        const Words words = vim_words(syntax, group);
        INFO(group);
        CHECK_FALSE(words.empty());
        keywords.insert(words.begin(), words.end());
    }
    check_same("keywords", keywords, w.keywords);
    check_same("properties", vim_words(syntax, "wsdProperty"), w.properties);
    check_same("property words", vim_words(syntax, "wsdPropertyValue"), w.property_words);
    check_same("light kinds", vim_words(syntax, "wsdLightKind"), w.light_kinds);
    check_same("built-in functions", vim_words(syntax, "wsdFunction"), w.functions);
    check_same("built-in constants", vim_words(syntax, "wsdConstant"), w.constants);
}
