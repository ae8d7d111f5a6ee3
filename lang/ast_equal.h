// Structural equality of syntax trees, positions aside: what `wsd fmt` promises of its output
// (the same `wsd ast` apart from @LINE:COL), checked without printing either tree.
#pragma once

#include "lang/ast.h"

namespace wsd::lang {

bool same_ast(const Program& a, const Program& b);

}  // namespace wsd::lang
