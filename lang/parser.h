// The recursive-descent parser: tokens → AST, with panic-mode recovery so that every syntax error
// of a file is reported (up to Diagnostics::max_errors). Each parse function quotes its production
// from grammar/wsd.ebnf.
#pragma once

#include "lang/ast.h"
#include "lang/diagnostics.h"

namespace wsd::lang {

Program parse(uint32_t file, const SourceManager& sources, Diagnostics& diags);

}  // namespace wsd::lang
