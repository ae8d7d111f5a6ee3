// `wsd check --format json`: one file's diagnostics as the JSON object the command prints
// (docs/wsd-cli.md): lines and columns 1-based, the end exclusive, notes with the include chain.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "lang/diagnostics.h"
#include "lang/source.h"

namespace wsd::app {

// {"file", "ok", "diagnostics": [...]} for the diagnostics of one file's check.
nlohmann::ordered_json check_result_json(const std::string& file, bool ok, const lang::Diagnostics& diags,
                                         const lang::SourceManager& sources);

// A diagnostic without a position (its lines and columns null): an unreadable file, "too many
// errors, stopping", an unused --define. `severity` is "error" or "warning".
nlohmann::ordered_json positionless_json(const char* severity, const std::string& file,
                                         const std::string& message);

// The object for a file that could not be read: one error without a position.
nlohmann::ordered_json unreadable_file_json(const std::string& file, const std::string& message);

}  // namespace wsd::app
