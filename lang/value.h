// Runtime values of the .wsd language: number, bool, string, vector2, vector3, list, material,
// texture, object (a material is its evaluated block: lang/evaluated.h; an object is an evaluated
// object tree: lang/object_value.h) and function (lang/environment.h). Every value keeps the span
// it came from. Lists are immutable and shared; a list of numeric vector literals shares the
// parser's packed storage instead of one Value per element.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "lang/ast.h"
#include "lang/source.h"
#include "render/params.h"
#include "render/scene_spec.h"

namespace wsd::lang {

// The include statements that led to a file, innermost first: errors found after evaluation (while
// building the render scene) replay them as include-chain notes.
struct IncludeSite {
    Span site;
    std::shared_ptr<const IncludeSite> parent;
};
using IncludeChain = std::shared_ptr<const IncludeSite>;

struct ListValue;
struct MaterialValue;
struct TextureValue;
struct ObjectValue;
struct FunctionValue;
using ListPtr = std::shared_ptr<const ListValue>;
using MaterialPtr = std::shared_ptr<const MaterialValue>;
using TexturePtr = std::shared_ptr<const TextureValue>;
using ObjectPtr = std::shared_ptr<const ObjectValue>;  // lang/object_value.h
using FunctionPtr = std::shared_ptr<const FunctionValue>;

// The order matches the variant's alternatives in Value.
enum class ValueType : uint8_t {
    Number,
    Bool,
    String,
    Vector2,
    Vector3,
    List,
    Material,
    Texture,
    Object,
    Function
};

const char* type_name(ValueType type);  // "number", "vector3", ...

class Value {
public:
    Value() = default;
    static Value make_number(double x, Span span) { return Value(x, span); }
    static Value make_bool(bool b, Span span) { return Value(b, span); }
    static Value make_string(std::string s, Span span) { return Value(std::move(s), span); }
    static Value make_vec2(glm::dvec2 v, Span span) { return Value(v, span); }
    static Value make_vec3(glm::dvec3 v, Span span) { return Value(v, span); }
    static Value make_list(ListPtr l, Span span) { return Value(std::move(l), span); }
    static Value make_material(MaterialPtr m, Span span) { return Value(std::move(m), span); }
    static Value make_texture(TexturePtr t, Span span) { return Value(std::move(t), span); }
    static Value make_object(ObjectPtr o, Span span) { return Value(std::move(o), span); }
    static Value make_function(FunctionPtr f, Span span) { return Value(std::move(f), span); }

    ValueType type() const { return static_cast<ValueType>(payload_.index()); }
    bool is(ValueType t) const { return type() == t; }
    bool is_vector() const { return is(ValueType::Vector2) || is(ValueType::Vector3); }
    const Span& span() const { return span_; }
    void set_span(Span s) { span_ = s; }

    double number() const { return std::get<double>(payload_); }
    bool boolean() const { return std::get<bool>(payload_); }
    const std::string& string() const { return std::get<std::string>(payload_); }
    glm::dvec2 vec2() const { return std::get<glm::dvec2>(payload_); }
    glm::dvec3 vec3() const { return std::get<glm::dvec3>(payload_); }
    const ListValue& list() const { return *std::get<ListPtr>(payload_); }
    const ListPtr& list_ptr() const { return std::get<ListPtr>(payload_); }
    const MaterialPtr& material() const { return std::get<MaterialPtr>(payload_); }
    const TexturePtr& texture() const { return std::get<TexturePtr>(payload_); }
    const ObjectPtr& object() const { return std::get<ObjectPtr>(payload_); }
    const FunctionPtr& function() const { return std::get<FunctionPtr>(payload_); }

private:
    using Payload = std::variant<double, bool, std::string, glm::dvec2, glm::dvec3, ListPtr, MaterialPtr,
                                 TexturePtr, ObjectPtr, FunctionPtr>;
    template <class T>
    Value(T&& x, Span span) : payload_(std::forward<T>(x)), span_(span) {}
    Payload payload_{0.0};
    Span span_;
};

struct ListValue {
    std::vector<Value> items;                     // used unless `packed` is set
    std::shared_ptr<const PackedVectors> packed;  // shared with the AST, never copied

    size_t size() const { return packed ? packed->size() : items.size(); }
    // Element i; a packed element becomes a vector value spanning its literal.
    Value at(size_t i, const SourceManager& sources) const;
    Span span_of(size_t i, const SourceManager& sources) const;
};

// The span of element i of a packed list: from its '<' to the matching '>' (packed elements are
// plain numeric literals, so the first '>' closes them).
Span packed_element_span(const PackedVectors& packed, size_t i, const SourceManager& sources);

// Where a property's value was written, by the render field it sets: errors that build_scene
// reports about a field are shown at its value. Kept small (one per written field of every
// object): the value is in the file of its block's keyword.
struct FieldSpan {
    uint32_t begin, end;      // the value's bytes
    render::Element element;  // the field: element_table(element).fields[field]
    uint8_t field;
    const render::Field& table_field() const { return render::element_table(element).fields[field]; }
};

struct TextureValue {
    render::TextureSpec spec;
    Span span;                      // image: the path string; checker/perlin: the keyword
    IncludeChain chain;             // where it was written
    std::vector<FieldSpan> fields;  // the values written in its block
};

// Text for messages: numbers in shortest round-trip form (integers without exponent), vectors
// as <x, y, z>, strings quoted; lists, materials and textures by their type.
std::string format_number(double x);
std::string describe(const Value& v);

// Same-type equality (numbers, bools, strings, vectors); callers check the types first.
bool values_equal(const Value& a, const Value& b);

}  // namespace wsd::lang
