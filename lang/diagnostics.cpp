// The diagnostics sink (errors up to max_errors, include-chain notes), the clang-style printer
// (file:line:col, source line, caret with ~ under the span, notes, help) and the "did you mean"
// edit-distance matcher.
#include "lang/diagnostics.h"

#include <algorithm>
#include <cctype>
#include <string_view>

namespace wsd::lang {

void Diagnostics::note_call(size_t first, const Note& call) {
    for (size_t i = first; i < diags_.size(); ++i) {
        Diagnostic& d = diags_[i];
        if (d.shows_calls || d.calls.size() >= kMaxCallNotes) continue;
        // A note of the diagnostic's own may name the call already ("added by this call").
        const auto same = [&call](const Note& n) {
            return n.span.file == call.span.file && n.span.begin == call.span.begin;
        };
        if (std::none_of(d.notes.begin(), d.notes.end(), same)) d.calls.push_back(call);
    }
}

Diagnostic& Diagnostics::error(Span span, std::string message) {
    ++errors_;
    if (errors_ > max_errors) {
        discarded_ = Diagnostic{};
        return discarded_;
    }
    Diagnostic& d = diags_.emplace_back();
    d.severity = Severity::Error;
    d.span = span;
    d.message = std::move(message);
    d.include_chain.assign(include_stack_.rbegin(), include_stack_.rend());
    return d;
}

Diagnostic& Diagnostics::warning(Span span, std::string message) {
    Diagnostic& d = diags_.emplace_back();
    d.severity = Severity::Warning;
    d.span = span;
    d.message = std::move(message);
    d.include_chain.assign(include_stack_.rbegin(), include_stack_.rend());
    return d;
}

void Diagnostics::push_include(Span include_site) {
    include_stack_.push_back(include_site);
}

void Diagnostics::pop_include() {
    if (!include_stack_.empty()) include_stack_.pop_back();
}

std::vector<Note> notes_with_includes(const Diagnostic& diag) {
    std::vector<Note> notes = diag.notes;
    notes.insert(notes.end(), diag.calls.begin(), diag.calls.end());
    for (const Span& site : diag.include_chain) notes.push_back({site, "in file included from here"});
    return notes;
}

namespace {

// Longest source line shown; a longer one is cut to a window around the caret.
constexpr uint32_t max_shown_columns = 160;

const char* severity_name(Severity s) {
    switch (s) {
        case Severity::Error:
            return "error";
        case Severity::Warning:
            return "warning";
        case Severity::Note:
            return "note";
    }
    return "error";
}

size_t digits(uint32_t n) {
    size_t d = 1;
    while (n >= 10) n /= 10, ++d;
    return d;
}

// The shown line and its caret line. Invalid bytes and control characters other than tab are
// shown as U+FFFD so the terminal never receives raw garbage; the caret line copies tabs.
struct Snippet {
    std::string line;
    std::string caret;
};

Snippet make_snippet(std::string_view line, uint32_t caret_col, uint32_t caret_len) {
    // Window [first, first + max_shown_columns) in columns, containing the caret's start.
    uint32_t first = 1;
    if (caret_col > max_shown_columns / 2) first = caret_col - max_shown_columns / 2;
    const uint32_t last = first + max_shown_columns;  // exclusive
    Snippet s;
    if (first > 1) s.line += "...", s.caret += "   ";
    uint32_t col = 1;
    size_t i = 0;
    bool cut_right = false;
    while (i < line.size()) {
        const Utf8Step step = decode_utf8(line, i);
        if (col >= last) {
            cut_right = true;
            break;
        }
        if (col >= first) {
            const bool control = step.valid && (step.codepoint < 0x20 || step.codepoint == 0x7F);
            if (step.valid && step.codepoint == '\t') {
                s.line += '\t';
            } else if (!step.valid || control) {
                s.line += "\xEF\xBF\xBD";
            } else {
                s.line.append(line.substr(i, step.length));
            }
            const char pad = step.valid && step.codepoint == '\t' ? '\t' : ' ';
            if (col < caret_col) {
                s.caret += pad;
            } else if (col < caret_col + caret_len) {
                s.caret += col == caret_col ? '^' : '~';
            }
        }
        i += step.length;
        ++col;
    }
    if (cut_right) s.line += "...";
    // A caret at or past the end of the line (end of file, a missing token) still shows.
    if (caret_col >= col && caret_col >= first) {
        s.caret.append(caret_col - std::max(col, first), ' ');
        s.caret += '^';
    }
    while (!s.caret.empty() && s.caret.back() == ' ') s.caret.pop_back();
    return s;
}

struct Located {
    const SourceFile* file = nullptr;
    LineCol begin;
    uint32_t caret_len = 1;
};

Located locate(const SourceManager& sources, Span span) {
    Located loc;
    if (span.file >= sources.size()) return loc;
    loc.file = &sources.file(span.file);
    loc.begin = sources.line_col(span.file, span.begin);
    const LineCol end = sources.line_col(span.file, std::max(span.end, span.begin));
    if (end.line == loc.begin.line) {
        loc.caret_len = std::max<uint32_t>(1, end.column - loc.begin.column);
    } else {
        // A span over several lines is underlined to the end of its first line.
        const std::string_view text = sources.line_text(span.file, loc.begin.line);
        const uint32_t line_cols = count_columns(text, 0, text.size());
        loc.caret_len = line_cols >= loc.begin.column ? line_cols - loc.begin.column + 1 : 1;
    }
    return loc;
}

void append_located(std::string& out, const SourceManager& sources, Span span, Severity severity,
                    const std::string& message, size_t width) {
    const Located loc = locate(sources, span);
    if (!loc.file) {
        out += severity_name(severity);
        out += ": " + message + "\n";
        return;
    }
    out += loc.file->path + ":" + std::to_string(loc.begin.line) + ":" + std::to_string(loc.begin.column) +
           ": " + severity_name(severity) + ": " + message + "\n";
    const Snippet snip =
        make_snippet(sources.line_text(span.file, loc.begin.line), loc.begin.column, loc.caret_len);
    const std::string number = std::to_string(loc.begin.line);
    out.append(width - number.size(), ' ');
    out += number + " | " + snip.line + "\n";
    out.append(width + 1, ' ');
    out += "| " + snip.caret + "\n";
}

}  // namespace

std::string format_diagnostics(const Diagnostics& diags, const SourceManager& sources) {
    std::string out;
    for (const Diagnostic& d : diags.all()) {
        const std::vector<Note> notes = notes_with_includes(d);
        // One gutter width per diagnostic so its snippets line up.
        size_t width = 5;
        const auto widen = [&](Span s) {
            if (s.file < sources.size())
                width = std::max(width, digits(sources.line_col(s.file, s.begin).line));
        };
        widen(d.span);
        for (const Note& n : notes) widen(n.span);
        append_located(out, sources, d.span, d.severity, d.message, width);
        for (const std::string& h : d.help) {
            out.append(width + 1, ' ');
            out += "= help: " + h + "\n";
        }
        for (const Note& n : notes) append_located(out, sources, n.span, Severity::Note, n.message, width);
    }
    if (diags.too_many()) out += "error: too many errors, stopping\n";
    return out;
}

namespace {

std::string lower(std::string_view s) {
    std::string r(s);
    for (char& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return r;
}

// Optimal string alignment distance (Levenshtein plus transposition of neighbours).
size_t edit_distance(const std::string& a, const std::string& b) {
    const size_t n = a.size(), m = b.size();
    std::vector<std::vector<size_t>> d(n + 1, std::vector<size_t>(m + 1));
    for (size_t i = 0; i <= n; ++i) d[i][0] = i;
    for (size_t j = 0; j <= m; ++j) d[0][j] = j;
    for (size_t i = 1; i <= n; ++i) {
        for (size_t j = 1; j <= m; ++j) {
            const size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    }
    return d[n][m];
}

}  // namespace

std::string closest_match(std::string_view word, const std::vector<std::string>& candidates) {
    // Long words get a proportionally larger budget (about one edit per three letters), short
    // ones one edit; a candidate is never suggested if the edits would replace most of it. A
    // word of one letter is most likely a name of the scene's own (`f` is not a misspelt `if`).
    constexpr size_t max_word = 64;
    if (word.size() < 2 || word.size() > max_word) return "";
    const std::string w = lower(word);
    const size_t budget = std::max<size_t>(1, w.size() / 3);
    std::string best;
    size_t best_distance = budget + 1;
    for (const std::string& c : candidates) {
        if (c.size() > max_word) continue;
        const size_t d = edit_distance(w, lower(c));
        if (d < best_distance && d < c.size()) best = c, best_distance = d;
    }
    return best;
}

}  // namespace wsd::lang
