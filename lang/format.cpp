#include "lang/format.h"

#include "lang/parser.h"

namespace wsd::lang {

std::optional<std::string> format_source(uint32_t file, const SourceManager& sources,
                                         Diagnostics& diags) {
    parse(file, sources, diags);
    if (diags.has_errors()) return std::nullopt;
    return sources.file(file).text;
}

}  // namespace wsd::lang
