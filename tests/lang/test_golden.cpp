// The golden-file driver: every .wsd / .wsdi under tests/golden carries its expected diagnostics
// in comments (`// error: L:C: message`, see tests/golden/README.md); each is loaded through
// lang::load_scene and must report exactly those. NAME.ast beside NAME.wsd pins print_ast.
// WSD_UPDATE_AST=1 in the environment rewrites the .ast files instead of comparing them.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "lang/load.h"
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

std::vector<fs::path> golden_files() {
    std::vector<fs::path> files;
    const fs::path root = fs::path(WSD_SOURCE_DIR) / "tests" / "golden";
    for (const auto& entry : fs::recursive_directory_iterator(root)) {
        const std::string ext = entry.path().extension().string();
        if (entry.is_regular_file() && (ext == ".wsd" || ext == ".wsdi")) files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    return files;
}

struct Expected {
    std::vector<std::string> errors, warnings, notes, help;
};

// Comments `// error: ...`, `// warning: ...`, `// note: ...`, `// help: ...` anywhere in the file;
// a line may hold several (each runs to the next one or to the end of the line).
Expected read_expectations(const std::string& text) {
    static const std::regex marker(R"(//\s*(error|warning|note|help):\s*)");
    Expected e;
    // LF, CRLF and a lone CR each end a line, as in the language.
    size_t begin = 0;
    while (begin <= text.size()) {
        size_t end = text.find_first_of("\r\n", begin);
        if (end == std::string::npos) end = text.size();
        const std::string line = text.substr(begin, end - begin);
        std::vector<std::smatch> marks;
        for (auto it = std::sregex_iterator(line.begin(), line.end(), marker); it != std::sregex_iterator();
             ++it)
            marks.push_back(*it);
        for (size_t i = 0; i < marks.size(); ++i) {
            const size_t from = static_cast<size_t>(marks[i].position(0) + marks[i].length(0));
            const size_t to =
                i + 1 < marks.size() ? static_cast<size_t>(marks[i + 1].position(0)) : line.size();
            std::string message = line.substr(from, to - from);
            while (!message.empty() && std::isspace(static_cast<unsigned char>(message.back())))
                message.pop_back();
            const std::string kind = marks[i][1];
            auto& list = kind == "error"     ? e.errors
                         : kind == "warning" ? e.warnings
                         : kind == "note"    ? e.notes
                                             : e.help;
            list.push_back(message);
        }
        if (end < text.size() && text[end] == '\r' && end + 1 < text.size() && text[end + 1] == '\n') ++end;
        begin = end + 1;
    }
    return e;
}

// "L:C: message" in the golden file itself, "FILE:L:C: message" elsewhere (FILE relative to
// the golden file's directory).
std::string describe(const SourceManager& sources, Span span, const std::string& message,
                     const fs::path& golden) {
    if (span.file >= sources.size()) return "?:?: " + message;
    const LineCol lc = sources.line_col(span.file, span.begin);
    const fs::path file = fs::path(sources.file(span.file).path).lexically_normal();
    std::string where;
    if (file != golden.lexically_normal())
        where = file.lexically_relative(golden.parent_path()).generic_string() + ":";
    return where + std::to_string(lc.line) + ":" + std::to_string(lc.column) + ": " + message;
}

void check_golden(const fs::path& path) {
    const std::string text = read_file(path);
    const Expected expected = read_expectations(text);

    SourceManager sources;
    Diagnostics diags;
    LoadOptions options;
    options.build = true;
    options.fragment = path.extension() == ".wsdi";
    const auto loaded = load_scene(path.string(), text, sources, diags, options);

    Expected actual;
    for (const Diagnostic& d : diags.all()) {
        if (d.severity == Severity::Error)
            actual.errors.push_back(describe(sources, d.span, d.message, path));
        if (d.severity == Severity::Warning)
            actual.warnings.push_back(describe(sources, d.span, d.message, path));
        for (const Note& n : notes_with_includes(d))
            actual.notes.push_back(describe(sources, n.span, n.message, path));
        for (const std::string& h : d.help) actual.help.push_back(h);
    }
    INFO(format_diagnostics(diags, sources));
    CHECK(actual.errors == expected.errors);
    if (!expected.warnings.empty()) CHECK(actual.warnings == expected.warnings);
    if (!expected.notes.empty()) CHECK(actual.notes == expected.notes);
    if (!expected.help.empty()) CHECK(actual.help == expected.help);
    if (expected.errors.empty()) CHECK(loaded.has_value());

    fs::path ast_path = path;
    ast_path.replace_extension(".ast");
    if (fs::exists(ast_path)) {
        SourceManager ast_sources;
        Diagnostics ast_diags;
        const uint32_t file = ast_sources.add(path.filename().string(), text);
        const std::string printed = print_ast(parse(file, ast_sources, ast_diags), ast_sources);
        if (std::getenv("WSD_UPDATE_AST")) {
            std::ofstream(ast_path, std::ios::binary) << printed;
        } else {
            CHECK(printed == read_file(ast_path));
        }
    }
}

}  // namespace

TEST_CASE("golden files report exactly the diagnostics written in them", "[golden]") {
    const std::vector<fs::path> files = golden_files();
    REQUIRE(!files.empty());
    const fs::path root = fs::path(WSD_SOURCE_DIR) / "tests" / "golden";
    for (const fs::path& path : files) {
        DYNAMIC_SECTION(path.lexically_relative(root).generic_string()) {
            check_golden(path);
        }
    }
}
