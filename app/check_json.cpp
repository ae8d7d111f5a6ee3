// The JSON form of diagnostics, for editors and scripts: the same diagnostics as the text form,
// each with its span as line/column pairs.
#include "app/check_json.h"

namespace wsd::app {

namespace {

const char* severity_name(lang::Severity s) {
    switch (s) {
        case lang::Severity::Error:
            return "error";
        case lang::Severity::Warning:
            return "warning";
        case lang::Severity::Note:
            return "note";
    }
    return "error";
}

nlohmann::ordered_json note_json(const lang::Note& note, const lang::SourceManager& sources) {
    const lang::LineCol at = sources.line_col(note.span.file, note.span.begin);
    return {{"message", note.message},
            {"file", sources.file(note.span.file).path},
            {"line", at.line},
            {"column", at.column}};
}

nlohmann::ordered_json diagnostic_json(const lang::Diagnostic& d, const lang::SourceManager& sources) {
    const lang::LineCol begin = sources.line_col(d.span.file, d.span.begin);
    const lang::LineCol end = sources.line_col(d.span.file, std::max(d.span.begin, d.span.end));
    std::string help;
    for (const std::string& h : d.help) help += (help.empty() ? "" : "\n") + h;
    nlohmann::ordered_json notes = nlohmann::ordered_json::array();
    for (const lang::Note& note : lang::notes_with_includes(d)) notes.push_back(note_json(note, sources));
    return {{"severity", severity_name(d.severity)},
            {"message", d.message},
            {"file", sources.file(d.span.file).path},
            {"line", begin.line},
            {"column", begin.column},
            {"end_line", end.line},
            {"end_column", end.column},
            {"help", help},
            {"notes", notes}};
}

}  // namespace

nlohmann::ordered_json check_result_json(const std::string& file, bool ok, const lang::Diagnostics& diags,
                                         const lang::SourceManager& sources) {
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (const lang::Diagnostic& d : diags.all()) list.push_back(diagnostic_json(d, sources));
    return {{"file", file}, {"ok", ok}, {"diagnostics", list}};
}

nlohmann::ordered_json positionless_json(const char* severity, const std::string& file,
                                         const std::string& message) {
    return {{"severity", severity},  {"message", message}, {"file", file},
            {"line", nullptr},       {"column", nullptr},  {"end_line", nullptr},
            {"end_column", nullptr}, {"help", ""},         {"notes", nlohmann::ordered_json::array()}};
}

nlohmann::ordered_json unreadable_file_json(const std::string& file, const std::string& message) {
    return {{"file", file},
            {"ok", false},
            {"diagnostics", nlohmann::ordered_json::array({positionless_json("error", file, message)})}};
}

}  // namespace wsd::app
