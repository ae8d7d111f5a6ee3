// Diagnostics: library code reports errors, warnings and notes to a sink and returns; only app/
// prints. The printer renders them clang-style: file:line:col, the source line, a caret with ~
// under the span, notes at related spans, help lines.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "lang/source.h"

namespace wsd::lang {

enum class Severity { Error, Warning, Note };

struct Note {
    Span span;
    std::string message;
};

struct Diagnostic {
    Severity severity = Severity::Error;
    Span span;
    std::string message;            // lower-case, no trailing period
    std::vector<Note> notes;        // printed after, each with its own source line
    std::vector<std::string> help;  // "= help: ..." lines
    // The `include` sites that led to the file of `span`, innermost first (filled by the sink
    // from push_include); printed after the notes as "in file included from here" notes.
    std::vector<Span> include_chain;
    // The function calls that led to `span`, innermost first (added by the interpreter as each
    // call returns); printed after the notes, before the include chain. Empty when the
    // diagnostic shows a chain of calls itself.
    std::vector<Note> calls;
    bool shows_calls = false;
};

class Diagnostics {
public:
    static constexpr size_t max_errors = 20;

    // Past max_errors an error is counted but not kept: the returned reference is a scratch
    // diagnostic, so callers may still add notes and help to it.
    Diagnostic& error(Span span, std::string message);
    Diagnostic& warning(Span span, std::string message);
    size_t error_count() const { return errors_; }
    bool has_errors() const { return errors_ > 0; }
    bool too_many() const { return errors_ >= max_errors; }
    const std::vector<Diagnostic>& all() const { return diags_; }
    // Notes `call` on every diagnostic from all()[first] on, up to kMaxCallNotes a diagnostic
    // (the innermost calls, where a deep recursion went wrong).
    static constexpr size_t kMaxCallNotes = 8;
    void note_call(size_t first, const Note& call);
    // Include chain: notes appended to every diagnostic reported while a file is being included.
    void push_include(Span include_site);
    void pop_include();
    // The include sites in effect (outermost first), and a swap of them: a function's body runs
    // with the includes that led to its definition, wherever it is called from.
    const std::vector<Span>& include_stack() const { return include_stack_; }
    std::vector<Span> exchange_include_stack(std::vector<Span> sites) {
        std::swap(sites, include_stack_);
        return sites;
    }

private:
    std::vector<Diagnostic> diags_;
    std::vector<Span> include_stack_;
    size_t errors_ = 0;
    Diagnostic discarded_;
};

// The notes printed for a diagnostic, in order: its own notes, then one per include site.
std::vector<Note> notes_with_includes(const Diagnostic& diag);

// Clang-style text of every diagnostic; "too many errors" after max_errors.
std::string format_diagnostics(const Diagnostics& diags, const SourceManager& sources);

// "did you mean": the closest candidate within a small edit distance, or "".
std::string closest_match(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace wsd::lang
