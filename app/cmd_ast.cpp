// `wsd ast FILE`: parses one file and prints its AST (lang::print_ast) on stdout. Syntax errors
// go to stderr and make the status 1; the tree, with its Bad placeholders, is printed anyway so
// that recovery can be inspected.
#include <iostream>

#include "app/commands.h"
#include "app/exit_codes.h"
#include "app/io_util.h"
#include "lang/parser.h"

namespace wsd::app {

int run_ast(const AstArgs& args) {
    std::string text, error;
    if (!read_input_file(args.file, text, error)) return fail(exit_code::io, error);
    lang::SourceManager sources;
    lang::Diagnostics diags;
    const uint32_t file = sources.add(display_path(args.file), std::move(text));
    const lang::Program program = lang::parse(file, sources, diags);
    std::cout << lang::print_ast(program, sources) << std::flush;
    if (!diags.all().empty()) std::cerr << lang::format_diagnostics(diags, sources);
    return diags.has_errors() ? exit_code::input_error : exit_code::ok;
}

}  // namespace wsd::app
