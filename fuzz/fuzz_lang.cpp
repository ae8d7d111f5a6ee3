// libFuzzer target for the language front end: arbitrary bytes through the source manager, the
// lexer and parser, the AST printer and the diagnostics printer, the formatter (which must format
// every file that parses, and its own output to the same text), then through load_scene without
// building (evaluation and lowering). Built with -DWSD_FUZZ=ON and clang; seed it with the
// examples and golden files: wsd_fuzz_lang -max_total_time=60 corpus/ examples/ tests/golden/syntax/
#include <cstddef>
#include <cstdint>
#include <string>

#include "lang/format.h"
#include "lang/load.h"
#include "lang/parser.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    {
        wsd::lang::SourceManager sources;
        wsd::lang::Diagnostics diags;
        const uint32_t file = sources.add("fuzz.wsd", text);
        const wsd::lang::Program program = wsd::lang::parse(file, sources, diags);
        (void)wsd::lang::print_ast(program, sources);
        (void)wsd::lang::format_diagnostics(diags, sources);
        wsd::lang::Diagnostics format_diags;
        const std::optional<std::string> formatted = wsd::lang::format_source(file, sources, format_diags);
        if (formatted.has_value() == diags.has_errors()) __builtin_trap();  // formats exactly what parses
        if (formatted) {
            const uint32_t again_file = sources.add("fuzz-formatted.wsd", *formatted);
            const std::optional<std::string> again =
                wsd::lang::format_source(again_file, sources, format_diags);
            if (!again || *again != *formatted) __builtin_trap();  // idempotent
        }
    }
    {
        // A directory that does not exist: relative includes and files resolve to nothing.
        wsd::lang::SourceManager sources;
        wsd::lang::Diagnostics diags;
        wsd::lang::LoadOptions options;
        options.build = false;
        (void)wsd::lang::load_scene("/nonexistent-wsd-fuzz/fuzz.wsd", text, sources, diags, options);
        (void)wsd::lang::format_diagnostics(diags, sources);
    }
    return 0;
}
