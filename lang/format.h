// The formatter: the canonical text of a .wsd or .wsdi file (`wsd fmt`, the language server's
// formatting request). Comments are kept; the meaning (the AST apart from positions) is unchanged.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "lang/diagnostics.h"
#include "lang/source.h"

namespace wsd::lang {

// The canonical form of source file `file`, or nullopt (with the diagnostics `wsd check` would
// give for its syntax) when it does not parse.
std::optional<std::string> format_source(uint32_t file, const SourceManager& sources, Diagnostics& diags);

}  // namespace wsd::lang
