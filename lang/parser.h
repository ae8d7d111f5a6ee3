// The recursive-descent parser: tokens → AST, with panic-mode recovery so that every syntax error
// of a file is reported (up to Diagnostics::max_errors). Each parse function quotes its production
// from grammar/wsd.ebnf.
#pragma once

#include "lang/ast.h"
#include "lang/diagnostics.h"

namespace wsd::lang {

Program parse(uint32_t file, const SourceManager& sources, Diagnostics& diags);

// Nesting limit of blocks and expressions (§5): deeper input is an error, never a deep stack.
constexpr int max_nesting = 256;

// Source spans inside element `index` of a packed list, recovered by lexing its text again:
// the whole `<...>`, and for each component the span of its number with any leading '-'
// (minus is empty when there is none).
struct PackedElementSpans {
    Span element;
    int count = 0;  // components found (2 or 3)
    Span component[3];
    Span minus[3];
    Span number[3];
};
PackedElementSpans packed_element_spans(const PackedVectors& packed, size_t index,
                                        const SourceManager& sources);

}  // namespace wsd::lang
