// Runtime values: type names, text for messages, equality, and element access into packed lists
// (the parser's numbers-plus-offsets storage of big vector lists).
#include "lang/value.h"

#include <cmath>

#include "render/params.h"

namespace wsd::lang {

const char* type_name(ValueType type) {
    switch (type) {
        case ValueType::Number:
            return "number";
        case ValueType::Bool:
            return "bool";
        case ValueType::String:
            return "string";
        case ValueType::Vector2:
            return "vector2";
        case ValueType::Vector3:
            return "vector3";
        case ValueType::List:
            return "list";
        case ValueType::Material:
            return "material";
        case ValueType::Texture:
            return "texture";
        case ValueType::Object:
            return "object";
        case ValueType::Function:
            return "function";
    }
    return "value";
}

Span packed_element_span(const PackedVectors& packed, size_t i, const SourceManager& sources) {
    uint32_t begin = packed.offsets[i];
    Span span{packed.file, begin, begin + 1};
    if (packed.file < sources.size()) {
        const std::string& text = sources.file(packed.file).text;
        size_t close = text.find('>', begin);
        if (close != std::string::npos) span.end = static_cast<uint32_t>(close + 1);
    }
    return span;
}

Span ListValue::span_of(size_t i, const SourceManager& sources) const {
    return packed ? packed_element_span(*packed, i, sources) : items[i].span();
}

Value ListValue::at(size_t i, const SourceManager& sources) const {
    if (!packed) return items[i];
    const double* p = packed->values.data() + i * static_cast<size_t>(packed->dims);
    Span span = packed_element_span(*packed, i, sources);
    if (packed->dims == 2) return Value::make_vec2({p[0], p[1]}, span);
    return Value::make_vec3({p[0], p[1], p[2]}, span);
}

std::string format_number(double x) {
    return render::format_number(x);  // the renderer's messages print numbers the same way
}

std::string describe(const Value& v) {
    switch (v.type()) {
        case ValueType::Number:
            return format_number(v.number());
        case ValueType::Bool:
            return v.boolean() ? "true" : "false";
        case ValueType::String:
            return std::string(1, '"').append(v.string()).append(1, '"');
        case ValueType::Vector2:
            return std::string(1, '<')
                .append(format_number(v.vec2().x))
                .append(", ")
                .append(format_number(v.vec2().y))
                .append(">");
        case ValueType::Vector3:
            return std::string(1, '<')
                .append(format_number(v.vec3().x))
                .append(", ")
                .append(format_number(v.vec3().y))
                .append(", ")
                .append(format_number(v.vec3().z))
                .append(">");
        case ValueType::Object:
            return "an object";
        default:
            return std::string("a ") + type_name(v.type());
    }
}

bool values_equal(const Value& a, const Value& b) {
    switch (a.type()) {
        case ValueType::Number:
            return a.number() == b.number();
        case ValueType::Bool:
            return a.boolean() == b.boolean();
        case ValueType::String:
            return a.string() == b.string();
        case ValueType::Vector2:
            return a.vec2() == b.vec2();
        case ValueType::Vector3:
            return a.vec3() == b.vec3();
        default:
            return false;
    }
}

}  // namespace wsd::lang
