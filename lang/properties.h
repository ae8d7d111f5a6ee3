// Property tables and the block reader: every evaluated block (settings, camera, lights, objects,
// material, checker, perlin) is checked against its table here — unknown names with a "did you
// mean", repeats with a note at the first, value counts, types and ranges — and its transforms
// (scale, rotate, translate) are collected in the order written. The reader only reads values
// already evaluated (lang/evaluated.h); it never evaluates, so it knows no interpreter.
#pragma once

#include <cassert>
#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "lang/diagnostics.h"
#include "lang/evaluated.h"
#include "lang/value.h"
#include "render/params.h"

namespace wsd::lang {

// The types and ranges of properties are the render tables' (render/params.h).
using PropType = render::FieldType;

// The type as messages and the language server name it: "a number", "a colour (vector3)".
std::string expected_type(PropType t);

// A property as the language reads it: the render field it sets, plus the facts only the
// language has (the name it is written under, how many values it takes).
struct Property {
    std::string_view name;  // "" is a triangle's leading vertices
    PropType type;
    int min_values = 1, max_values = 1;
    const render::Field* field = nullptr;  // null for language-only properties (`base`, transforms)
    const std::vector<std::string_view>& words() const;
};

struct BlockTable {
    std::string what;         // "sphere", "light area", "material": used in messages
    render::Element element;  // the render element whose table this is generated from
    std::vector<Property> properties;
    bool transforms = false;  // accepts scale / rotate / translate
    // Help for names that are unknown here but mean something elsewhere (`samples` in a point light).
    std::vector<std::pair<std::string_view, std::string>> hints = {};
    const Property* find(std::string_view name) const;
};

enum class TransformKind { Scale, Rotate, Translate };
struct Transform {
    TransformKind kind;
    glm::dvec3 v;  // scale factors, rotation degrees or offset
    Span span;
};

// What the evaluator does with an item's values once the table has seen its name and count.
enum class ItemRead { Skip, Evaluate, Words };

// Checks one evaluated block against its table, reporting every problem it finds, and answers
// lowering's questions about it. A value that failed to evaluate (already reported) marks the
// block failed without another message.
//
// The check runs item by item — `admit` (name, repeat, count), then `accept` for each value
// (word, type, range) — so that an evaluator can feed it as it evaluates and every diagnostic,
// the checker's and the evaluator's, comes in source order; `admit` also says whether the values
// are evaluated at all (an unknown, repeated or miscounted item's are not; a word is read, not
// evaluated).
class BlockReader {
public:
    // Checks a whole block at once (a block built without an evaluator).
    BlockReader(const BlockTable& table, const EvaluatedBlock& block, Diagnostics& diags);
    // An empty block, fed with admit/accept/end_item (`items`, `values`: how many will be admitted).
    BlockReader(const BlockTable& table, Span keyword, Span open, Span close, Diagnostics& diags,
                size_t items = 0, size_t values = 0);

    // An item and the spans of its values (not yet evaluated): checks its name and count.
    ItemRead admit(std::string_view name, Span name_span, std::span<const Span> value_spans);
    // The next value of the item last admitted: checks and keeps it.
    void accept(EvaluatedValue value);
    void end_item();
    const EvaluatedBlock& block() const { return block_; }
    EvaluatedBlock take_block() && { return std::move(block_); }

    bool ok() const { return ok_; }
    bool has(std::string_view name) const { return slot(name) && slot(name)->item >= 0; }
    // Validated values of a present, valid property (empty otherwise).
    std::vector<Value> values(std::string_view name) const;
    const Value* value(std::string_view name) const;             // the first value, or null
    Span value_span(std::string_view name, size_t i = 0) const;  // the value expression's span
    Span name_span(std::string_view name) const;

    double number(std::string_view name, double fallback) const;
    long long integer(std::string_view name, long long fallback) const;
    bool boolean(std::string_view name, bool fallback) const;
    glm::dvec3 vec3(std::string_view name, glm::dvec3 fallback) const;
    std::string_view word(std::string_view name, std::string_view fallback) const;

    // Writes every valid property that sets a render field with access into `spec`, the spec
    // struct of the table's element (render::Settings for "settings", ...).
    template <class Spec>
    void apply(Spec& spec) const {
        assert(render::is_spec_of<Spec>(table_.element));
        apply_fields(&spec);
    }
    // The value span of every present property that sets a render field.
    std::vector<FieldSpan> field_spans() const;

    // Reports "missing property" at the keyword unless present (or present but failed), or
    // unless an unknown name in the block was already answered with "did you mean" it.
    bool require(std::string_view name);
    bool suggested(std::string_view name) const;
    void fail(Span span, std::string message);  // report an error and mark the block failed
    void failed() { ok_ = false; }              // a problem already reported elsewhere
    const std::vector<Transform>& transforms() const { return transforms_; }
    Span keyword() const { return block_.keyword; }
    const BlockTable& table() const { return table_; }
    Diagnostics& diags() { return diags_; }

private:
    struct Slot {
        int item = -1;  // index in block_.items of the first item of this name
        bool valid = false;
    };
    const Slot* slot(std::string_view name) const;
    const EvaluatedItem* item_of(const Slot* s) const {
        return s && s->item >= 0 ? &block_.items[static_cast<size_t>(s->item)] : nullptr;
    }
    void apply_fields(void* spec) const;
    void report_unknown(const EvaluatedItem& item);
    void read_transform(const EvaluatedItem& item);
    bool check_count(const Property& p, const EvaluatedItem& item);
    std::span<const EvaluatedValue> values_of(const EvaluatedItem& item) const {
        return block_.values_of(item);
    }
    bool check_word(const Property& p, const EvaluatedValue& v);
    bool check_value(const Property& p, const Value& v, Span at);

    const BlockTable& table_;
    EvaluatedBlock block_;
    Diagnostics& diags_;
    std::vector<Slot> slots_;  // parallel to table_.properties
    std::vector<Transform> transforms_;
    std::vector<std::string> suggested_;  // names offered as "did you mean"
    const Property* current_ = nullptr;   // the property of the item being accepted
    size_t next_value_ = 0;               // its next value to accept
    bool current_valid_ = false, current_transform_ = false;
    bool ok_ = true;
};

// For a block whose every item is a checked property of `table` (a block a reader found ok):
// writes the properties that set a render field with access into `spec`, the spec struct of the
// table's element, and lists the value span of each that sets a render field.
void apply_block(const BlockTable& table, const EvaluatedBlock& block, void* spec);
std::vector<FieldSpan> block_field_spans(const BlockTable& table, const EvaluatedBlock& block);

// Whether property `a` is written after property `b` in the block (by source position).
inline bool written_after(const BlockReader& r, std::string_view a, std::string_view b) {
    return r.value_span(a).begin > r.value_span(b).begin;
}

}  // namespace wsd::lang
