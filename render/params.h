// The parameter tables of every scene element (settings, camera, each light kind, each shape kind,
// material and each texture kind): for each field its name, type, range, default and meaning. They
// are the one statement of what a scene element accepts: the language's property tables are
// generated from them, build_scene validates a SceneSpec against them, and the messages about a
// value out of range are written here once.
#pragma once

#include <cassert>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "render/limits.h"
#include "render/scene_spec.h"

namespace wsd::render {

enum class FieldType : uint8_t {
    Number,
    Integer,  // a number with an integral value
    Bool,
    String,
    Vector2,
    Vector3,  // a point or direction, double precision
    Colour,   // a vector3 with components in [0, kMaxSingle]
    Material,
    Texture,
    List,
    Word,  // one of the field's `words`
    NumberOrVector3,
};

// An interval of numbers. An upper bound of kMaxSingle is single precision's, not the field's
// own: it is left out of descriptions and has its own message.
struct Range {
    double lo = -std::numeric_limits<double>::infinity();
    double hi = std::numeric_limits<double>::infinity();
    bool lo_open = false, hi_open = false;
    bool contains(double x) const { return (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi); }
    bool has_lo() const { return lo != -std::numeric_limits<double>::infinity(); }
    bool has_hi() const { return hi != std::numeric_limits<double>::infinity() && hi != kMaxSingle; }
    std::string describe() const;  // "> 0", "in [0, 1)", ">= 0"
};

constexpr Range at_least(double lo) {
    return Range{lo, std::numeric_limits<double>::infinity(), false, false};
}
constexpr Range above(double lo) {
    return Range{lo, std::numeric_limits<double>::infinity(), true, false};
}
constexpr Range between(double lo, double hi) {
    return Range{lo, hi, false, false};
}
// Light values: >= lo and representable in single precision.
constexpr Range single_at_least(double lo) {
    return Range{lo, kMaxSingle, false, false};
}

// Reads and writes one field of an element's spec struct (Settings, CameraSpec, LightSpec,
// ShapeSpec, MaterialSpec or TextureSpec, as the table says). Null for fields that are read by
// hand (lists, words, textures, a triangle's vertices, a light's two sample counts ...).
struct FieldAccess {
    double (*number)(const void* spec) = nullptr;  // Number, Integer, Bool (0 or 1)
    void (*set_number)(void* spec, double x) = nullptr;
    Vec3 (*vec3)(const void* spec) = nullptr;  // Vector3, Colour
    void (*set_vec3)(void* spec, const Vec3& v) = nullptr;
    bool (*present)(const void* spec) = nullptr;  // optional fields: null means always present
};

struct Field {
    std::string_view name;
    FieldType type;
    Range range = {};
    std::string_view meaning = {};
    FieldAccess access = {};
    std::vector<std::string_view> words = {};  // Word
    // For fields without access: the default as written ("required" when there is none, "—"
    // when absence means "not used"). Fields with access take it from the spec struct.
    std::string_view default_text = {};
};

enum class Element : uint8_t {
    Settings,
    Camera,
    PointLight,
    AreaLight,
    SpotLight,
    Sphere,
    Box,
    Triangle,
    Plane,
    Mesh,
    Cylinder,
    Cone,
    Torus,
    Disc,
    Csg,       // union, intersection, difference: one table (their items are the same)
    Instance,  // object EXPR { ... }
    Material,
    Checker,
    Perlin,
    Image,
};
inline constexpr int kElementCount = static_cast<int>(Element::Image) + 1;

struct ElementTable {
    Element element;
    std::string_view name;  // "sphere", "light area": as in the language, and in messages
    std::vector<Field> fields;
    const void* defaults = nullptr;  // a default-constructed spec struct of this element

    const Field* find(std::string_view field) const;
};

const ElementTable& element_table(Element element);

// Whether Spec is the struct that the access of `element`'s fields reads and writes.
template <class Spec>
constexpr bool is_spec_of(Element e) {
    if constexpr (std::is_same_v<Spec, Settings>) return e == Element::Settings;
    if constexpr (std::is_same_v<Spec, CameraSpec>) return e == Element::Camera;
    if constexpr (std::is_same_v<Spec, LightSpec>) return e >= Element::PointLight && e <= Element::SpotLight;
    if constexpr (std::is_same_v<Spec, ShapeSpec>) return e >= Element::Sphere && e <= Element::Instance;
    if constexpr (std::is_same_v<Spec, MaterialSpec>) return e == Element::Material;
    if constexpr (std::is_same_v<Spec, TextureSpec>) return e >= Element::Checker && e <= Element::Image;
    return false;
}
Element element_of(const LightSpec& light);
Element element_of(const ShapeSpec& shape);
Element element_of(const TextureSpec& texture);

// The default of a field as text (from the spec struct when the field has access).
std::string default_text(const ElementTable& table, const Field& field);

// Numbers as messages show them: the shortest text that reads back to the same double, integers
// without exponent; vectors as <x, y, z>.
std::string format_number(double x);
std::string format_vec3(const Vec3& v);

// Why a value does not fit a field, as the end of a sentence that starts with the field's name
// ("must be > 0, found 0", "is too large for single precision, found 1e+39"), or nullopt.
std::optional<std::string> number_problem(const Field& field, double x);
std::optional<std::string> vec3_problem(const Field& field, const Vec3& v);

// The rules that join two fields, shared by the language and build_scene.
std::optional<std::string> image_size_problem(long long width, long long height);
std::optional<std::string> light_grid_problem(long long samples_u, long long samples_v);
std::optional<std::string> reflection_transmission_problem(double reflection, double transmission);
// A light's colour × intensity, which is what shading sums, in single precision.
std::optional<std::string> light_radiance_problem(const Vec3& color, double intensity);
// A perlin texture's frequencies, as a vector (a single number n is <n, n, n>).
std::optional<std::string> perlin_scale_problem(const Vec3& scale);

// Checks every field of `spec` that has access against `table`, appending one SpecError (with
// `item`, `index`, `tag` and the field's name) per field out of range. False if any.
bool check_fields(const ElementTable& table, const void* spec, SpecItem item, size_t index, uint32_t tag,
                  std::vector<SpecError>& errors);
template <class Spec>
bool check_fields(const ElementTable& table, const Spec& spec, SpecItem item, size_t index, uint32_t tag,
                  std::vector<SpecError>& errors) {
    assert(is_spec_of<Spec>(table.element));
    return check_fields(table, static_cast<const void*>(&spec), item, index, tag, errors);
}

}  // namespace wsd::render
