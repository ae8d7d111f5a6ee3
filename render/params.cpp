// The element tables and the checks of a value against a field. Each table lists its fields in
// the order the language reference documents them; fields with access read and write the spec
// struct, whose member initializers are the defaults.
#include "render/params.h"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace wsd::render {

namespace {

template <class C, class T>
C owner_of(T C::*);
template <class C, class T>
T type_of(T C::*);

// Access to a numeric member (int, uint32_t, double or bool) of a spec struct.
template <auto M>
FieldAccess number_member() {
    using C = decltype(owner_of(M));
    using T = decltype(type_of(M));
    FieldAccess a;
    a.number = [](const void* s) { return static_cast<double>(static_cast<const C*>(s)->*M); };
    a.set_number = [](void* s, double x) { static_cast<C*>(s)->*M = static_cast<T>(x); };
    return a;
}

// Access to a Vec3 member of a spec struct.
template <auto M>
FieldAccess vec3_member() {
    using C = decltype(owner_of(M));
    FieldAccess a;
    a.vec3 = [](const void* s) { return static_cast<const C*>(s)->*M; };
    a.set_vec3 = [](void* s, const Vec3& v) { static_cast<C*>(s)->*M = v; };
    return a;
}

// A material's own ambient: unset means settings.ambient.
FieldAccess material_ambient() {
    FieldAccess a;
    a.number = [](const void* s) { return static_cast<const MaterialSpec*>(s)->ambient.value_or(0.0); };
    a.set_number = [](void* s, double x) { static_cast<MaterialSpec*>(s)->ambient = x; };
    a.present = [](const void* s) { return static_cast<const MaterialSpec*>(s)->ambient.has_value(); };
    return a;
}

const Settings kDefaultSettings{};
const CameraSpec kDefaultCamera{};
const LightSpec kDefaultLight{};
const LightSpec kDefaultSpotLight{LightKind::Spot};
const ShapeSpec kDefaultShape{};
const MaterialSpec kDefaultMaterial{};
const TextureSpec kDefaultTexture{};

const Field kMaterialField{"material", FieldType::Material, {}, "the object's surface (a material value)", {},
                           {},         "required"};
const Field kColorsField{"colors", FieldType::Colour,     {}, "the two colours mixed", {},
                         {},       "<1, 1, 1>, <0, 0, 0>"};

std::vector<Field> light_fields(bool area) {
    std::vector<Field> f = {
        {"position",
         FieldType::Vector3,
         {},
         area ? "centre of the parallelogram" : "light position",
         vec3_member<&LightSpec::position>(),
         {},
         "required"},
        {"color", FieldType::Colour, {}, "light colour (linear)", vec3_member<&LightSpec::color>()},
        {"intensity", FieldType::Number, single_at_least(0), "multiplies the colour",
         number_member<&LightSpec::intensity>()},
    };
    if (!area) return f;
    f.push_back({"u",
                 FieldType::Vector3,
                 {},
                 "first edge vector (non-zero)",
                 vec3_member<&LightSpec::u>(),
                 {},
                 "required"});
    f.push_back({"v",
                 FieldType::Vector3,
                 {},
                 "second edge vector (non-zero, not parallel to u)",
                 vec3_member<&LightSpec::v>(),
                 {},
                 "required"});
    f.push_back({"samples",
                 FieldType::Integer,
                 between(1, kMaxLightGridSide),
                 "sample grid along u and v (one count for a square grid)",
                 {},
                 {},
                 "4"});
    f.push_back({"sampling",
                 FieldType::Word,
                 {},
                 "one jittered point a cell, or the cell centres",
                 {},
                 {"jittered", "uniform"},
                 "jittered"});
    f.push_back({"adaptive",
                 FieldType::Bool,
                 {},
                 "probe a few cells first, refine where they differ",
                 number_member<&LightSpec::adaptive>()});
    return f;
}

ElementTable settings_table() {
    return {
        Element::Settings,
        "settings",
        {{"width", FieldType::Integer, between(1, kMaxImageSide), "image width in pixels",
          number_member<&Settings::width>()},
         {"height", FieldType::Integer, between(1, kMaxImageSide), "image height in pixels",
          number_member<&Settings::height>()},
         {"supersamples", FieldType::Integer, between(1, kMaxSupersamples), "rays per pixel",
          number_member<&Settings::supersamples>()},
         {"adaptive_supersampling",
          FieldType::Bool,
          {},
          "the full grid only where a pixel differs from its neighbours",
          number_member<&Settings::adaptive_supersampling>()},
         {"exact_area_lights",
          FieldType::Bool,
          {},
          "the closed-form diffuse term where a point sees a whole area light",
          number_member<&Settings::exact_area_lights>()},
         {"aa_threshold", FieldType::Number, at_least(0),
          "the largest per-channel difference that counts as equal",
          number_member<&Settings::aa_threshold>()},
         {"bailout", FieldType::Number, Range{0, 1, false, true},
          "a secondary ray whose weight is below this is not traced", number_member<&Settings::bailout>()},
         {"max_depth", FieldType::Integer, between(0, kMaxDepth), "reflection and refraction recursion limit",
          number_member<&Settings::max_depth>()},
         {"ambient", FieldType::Number, at_least(0), "ambient term: surface colour x ambient",
          number_member<&Settings::ambient>()},
         {"background",
          FieldType::Colour,
          {},
          "colour of rays that miss",
          vec3_member<&Settings::background>()},
         {"seed", FieldType::Integer, between(0, kMaxSeed), "random seed", number_member<&Settings::seed>()},
         {"indirect_samples", FieldType::Integer, between(0, kMaxIndirectSamples),
          "Monte Carlo paths of indirect light a camera sample gathers (0: off)",
          number_member<&Settings::indirect_samples>()},
         {"indirect_bounces", FieldType::Integer, between(1, kMaxIndirectBounces),
          "the most diffuse reflections an indirect path makes",
          number_member<&Settings::indirect_bounces>()},
         {"caustic_photons", FieldType::Integer, between(0, kMaxCausticPhotons),
          "photons shot through mirrors and glass for caustics (0: none)",
          number_member<&Settings::caustic_photons>()}},
        &kDefaultSettings};
}

ElementTable camera_table() {
    return {Element::Camera,
            "camera",
            {{"position",
              FieldType::Vector3,
              {},
              "eye point",
              vec3_member<&CameraSpec::position>(),
              {},
              "required"},
             {"look_at",
              FieldType::Vector3,
              {},
              "point in the centre of the image",
              vec3_member<&CameraSpec::look_at>(),
              {},
              "required"},
             {"up",
              FieldType::Vector3,
              {},
              "must not be parallel to look_at - position",
              vec3_member<&CameraSpec::up>()},
             {"fov", FieldType::Number, Range{0, 180, true, true}, "vertical field of view in degrees",
              number_member<&CameraSpec::fov_degrees>()}},
            &kDefaultCamera};
}

ElementTable point_light_table() {
    return {Element::PointLight, "light point", light_fields(false), &kDefaultLight};
}

ElementTable area_light_table() {
    return {Element::AreaLight, "light area", light_fields(true), &kDefaultLight};
}

ElementTable spot_light_table() {
    std::vector<Field> f = light_fields(false);
    f.insert(f.begin() + 1, {"look_at",
                             FieldType::Vector3,
                             {},
                             "the point the spot's axis aims at (not the position)",
                             vec3_member<&LightSpec::look_at>(),
                             {},
                             "required"});
    f.push_back({"angle", FieldType::Number, Range{0, 90, true, false},
                 "full intensity within this many degrees of the axis", number_member<&LightSpec::angle>()});
    f.push_back({"falloff", FieldType::Number, Range{0, 90, true, false},
                 "no light beyond this many degrees from the axis (at least angle)",
                 number_member<&LightSpec::falloff>()});
    return {Element::SpotLight, "light spot", std::move(f), &kDefaultSpotLight};
}

ElementTable sphere_table() {
    return {Element::Sphere,
            "sphere",
            {{"center", FieldType::Vector3, {}, "centre", vec3_member<&ShapeSpec::center>(), {}, "required"},
             {"radius",
              FieldType::Number,
              above(0),
              "radius",
              number_member<&ShapeSpec::radius>(),
              {},
              "required"},
             kMaterialField},
            &kDefaultShape};
}

ElementTable box_table() {
    return {
        Element::Box,
        "box",
        {{"min", FieldType::Vector3, {}, "lowest corner", vec3_member<&ShapeSpec::box_min>(), {}, "required"},
         {"max",
          FieldType::Vector3,
          {},
          "highest corner (above min on every axis)",
          vec3_member<&ShapeSpec::box_max>(),
          {},
          "required"},
         kMaterialField},
        &kDefaultShape};
}

ElementTable triangle_table() {
    return {
        Element::Triangle,
        "triangle",
        {{"vertices", FieldType::Vector3, {}, "the three corners, written first", {}, {}, "required"},
         {"uv", FieldType::Vector2, {}, "texture coordinates of the three corners", {}, {}, "barycentric"},
         kMaterialField},
        &kDefaultShape};
}

ElementTable plane_table() {
    return {Element::Plane,
            "plane",
            {{"normal",
              FieldType::Vector3,
              {},
              "normal (non-zero; normalized)",
              vec3_member<&ShapeSpec::normal>(),
              {},
              "required"},
             {"distance",
              FieldType::Number,
              {},
              "the plane is normal . p = distance",
              number_member<&ShapeSpec::distance>()},
             {"uv_scale", FieldType::Number, above(0), "the texture repeats every uv_scale units",
              number_member<&ShapeSpec::uv_scale>()},
             kMaterialField},
            &kDefaultShape};
}

ElementTable mesh_table() {
    return {Element::Mesh,
            "mesh",
            {{"file", FieldType::String, {}, "an OBJ file (or vertices and faces)", {}, {}, "—"},
             {"vertices", FieldType::List, {}, "vector3 positions", {}, {}, "—"},
             {"faces", FieldType::List, {}, "vector3 of vertex indices", {}, {}, "—"},
             {"uvs", FieldType::List, {}, "one vector2 per vertex", {}, {}, "—"},
             {"normals", FieldType::List, {}, "one vector3 per vertex: smooth shading", {}, {}, "—"},
             kMaterialField},
            &kDefaultShape};
}

const Field kOpenField{"open",
                       FieldType::Bool,
                       {},
                       "no end caps: a tube, seen from inside too",
                       number_member<&ShapeSpec::open>()};

Field required_vec3(std::string_view name, std::string_view meaning, FieldAccess access) {
    return {name, FieldType::Vector3, {}, meaning, access, {}, "required"};
}

Field required_number(std::string_view name, Range range, std::string_view meaning, FieldAccess access) {
    return {name, FieldType::Number, range, meaning, access, {}, "required"};
}

ElementTable cylinder_table() {
    return {Element::Cylinder,
            "cylinder",
            {required_vec3("base", "centre of the base end", vec3_member<&ShapeSpec::base>()),
             required_vec3("cap", "centre of the other end (not base)", vec3_member<&ShapeSpec::cap>()),
             required_number("radius", above(0), "radius", number_member<&ShapeSpec::radius>()), kOpenField,
             kMaterialField},
            &kDefaultShape};
}

ElementTable cone_table() {
    return {
        Element::Cone,
        "cone",
        {required_vec3("base", "centre of the base end", vec3_member<&ShapeSpec::base>()),
         required_number("base_radius", at_least(0), "radius at base", number_member<&ShapeSpec::radius>()),
         required_vec3("cap", "centre of the other end (not base)", vec3_member<&ShapeSpec::cap>()),
         required_number("cap_radius", at_least(0), "radius at cap (not both 0)",
                         number_member<&ShapeSpec::cap_radius>()),
         kOpenField, kMaterialField},
        &kDefaultShape};
}

ElementTable torus_table() {
    return {Element::Torus,
            "torus",
            {required_number("major", above(0), "radius of the circle the tube follows (in the xz-plane)",
                             number_member<&ShapeSpec::major>()),
             required_number("minor", above(0), "radius of the tube (minor >= major: a spindle torus)",
                             number_member<&ShapeSpec::minor>()),
             kMaterialField},
            &kDefaultShape};
}

ElementTable disc_table() {
    return {Element::Disc,
            "disc",
            {required_vec3("center", "centre", vec3_member<&ShapeSpec::center>()),
             required_vec3("normal", "normal (non-zero; normalized)", vec3_member<&ShapeSpec::normal>()),
             required_number("radius", above(0), "outer radius", number_member<&ShapeSpec::radius>()),
             {"hole", FieldType::Number, at_least(0), "radius of the hole in the middle (below radius)",
              number_member<&ShapeSpec::hole>()},
             kMaterialField},
            &kDefaultShape};
}

ElementTable csg_table() {
    return {Element::Csg, "csg", {kMaterialField}, &kDefaultShape};
}

ElementTable instance_table() {
    return {Element::Instance, "object", {kMaterialField}, &kDefaultShape};
}

ElementTable material_table() {
    return {
        Element::Material,
        "material",
        {{"color", FieldType::Colour, {}, "surface colour (linear)", vec3_member<&MaterialSpec::color>()},
         {"texture", FieldType::Texture, {}, "surface colour from a texture instead of color", {}, {}, "—"},
         {"ambient",
          FieldType::Number,
          at_least(0),
          "per-material ambient override",
          material_ambient(),
          {},
          "settings.ambient"},
         {"diffuse", FieldType::Number, at_least(0), "diffuse weight (Lambert)",
          number_member<&MaterialSpec::diffuse>()},
         {"specular", FieldType::Number, at_least(0), "Phong specular weight",
          number_member<&MaterialSpec::specular>()},
         {"shininess", FieldType::Number, above(0), "Phong exponent",
          number_member<&MaterialSpec::shininess>()},
         {"reflection", FieldType::Number, between(0, 1), "mirror reflection weight",
          number_member<&MaterialSpec::reflection>()},
         {"transmission", FieldType::Number, between(0, 1), "refraction weight",
          number_member<&MaterialSpec::transmission>()},
         {"ior", FieldType::Number, above(0), "index of refraction", number_member<&MaterialSpec::ior>()},
         {"absorption",
          FieldType::Colour,
          {},
          "absorption per unit length inside",
          vec3_member<&MaterialSpec::absorption>()},
         {"emission",
          FieldType::Colour,
          {},
          "radiance the surface emits from both sides",
          vec3_member<&MaterialSpec::emission>()},
         {"bump", FieldType::Texture, {}, "Perlin normal perturbation", {}, {}, "—"},
         {"bump_strength", FieldType::Number, at_least(0), "how far the normal is bent",
          number_member<&MaterialSpec::bump_strength>()}},
        &kDefaultMaterial};
}

ElementTable checker_table() {
    return {Element::Checker,
            "checker",
            {{"scale", FieldType::Number, above(0), "the side of one square",
              number_member<&TextureSpec::checker_scale>()},
             kColorsField},
            &kDefaultTexture};
}

ElementTable perlin_table() {
    return {
        Element::Perlin,
        "perlin",
        {{"kind",
          FieldType::Word,
          {},
          "the noise function",
          {},
          {"noise", "turbulence", "marble", "wood"},
          "noise"},
         {"scale", FieldType::NumberOrVector3, {}, "frequencies a, b, c (>= 0, not all zero)", {}, {}, "1"},
         {"octaves", FieldType::Integer, between(1, kMaxOctaves), "turbulence terms L",
          number_member<&TextureSpec::octaves>()},
         kColorsField},
        &kDefaultTexture};
}

ElementTable image_table() {
    return {Element::Image,
            "image",
            {{"file", FieldType::String, {}, "PNG, JPEG, BMP, TGA or HDR file", {}, {}, "required"}},
            &kDefaultTexture};
}

ElementTable make_table(Element e) {
    switch (e) {
        case Element::Settings:
            return settings_table();
        case Element::Camera:
            return camera_table();
        case Element::PointLight:
            return point_light_table();
        case Element::AreaLight:
            return area_light_table();
        case Element::SpotLight:
            return spot_light_table();
        case Element::Sphere:
            return sphere_table();
        case Element::Box:
            return box_table();
        case Element::Triangle:
            return triangle_table();
        case Element::Plane:
            return plane_table();
        case Element::Mesh:
            return mesh_table();
        case Element::Cylinder:
            return cylinder_table();
        case Element::Cone:
            return cone_table();
        case Element::Torus:
            return torus_table();
        case Element::Disc:
            return disc_table();
        case Element::Csg:
            return csg_table();
        case Element::Instance:
            return instance_table();
        case Element::Material:
            return material_table();
        case Element::Checker:
            return checker_table();
        case Element::Perlin:
            return perlin_table();
        case Element::Image:
            return image_table();
    }
    return {e, "", {}, nullptr};
}

std::string quoted(std::string_view s) {
    return std::string(1, '\'').append(s).append(1, '\'');
}

bool finite3(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

std::string Range::describe() const {
    if (has_lo() && has_hi())
        return std::string("in ") + (lo_open ? "(" : "[") + format_number(lo) + ", " + format_number(hi) +
               (hi_open ? ")" : "]");
    if (has_lo()) return std::string(lo_open ? "> " : ">= ") + format_number(lo);
    if (has_hi()) return std::string(hi_open ? "< " : "<= ") + format_number(hi);
    return "finite";
}

const Field* ElementTable::find(std::string_view field) const {
    for (const Field& f : fields)
        if (f.name == field) return &f;
    return nullptr;
}

const ElementTable& element_table(Element element) {
    static const std::vector<ElementTable> tables = [] {
        std::vector<ElementTable> t;
        for (int i = 0; i < kElementCount; ++i) t.push_back(make_table(static_cast<Element>(i)));
        return t;
    }();
    return tables[static_cast<size_t>(element)];
}

Element element_of(const LightSpec& light) {
    switch (light.kind) {
        case LightKind::Point:
            return Element::PointLight;
        case LightKind::Area:
            return Element::AreaLight;
        case LightKind::Spot:
            return Element::SpotLight;
    }
    return Element::PointLight;
}

Element element_of(const ShapeSpec& shape) {
    switch (shape.kind) {
        case ShapeKind::Sphere:
            return Element::Sphere;
        case ShapeKind::Box:
            return Element::Box;
        case ShapeKind::Triangle:
            return Element::Triangle;
        case ShapeKind::Plane:
            return Element::Plane;
        case ShapeKind::Mesh:
            return Element::Mesh;
        case ShapeKind::Cylinder:
            return Element::Cylinder;
        case ShapeKind::Cone:
            return Element::Cone;
        case ShapeKind::Torus:
            return Element::Torus;
        case ShapeKind::Disc:
            return Element::Disc;
        case ShapeKind::Csg:
            return Element::Csg;
        case ShapeKind::Instance:
            return Element::Instance;
    }
    return Element::Sphere;
}

Element element_of(const TextureSpec& texture) {
    switch (texture.kind) {
        case TextureKind::Image:
            return Element::Image;
        case TextureKind::Checker:
            return Element::Checker;
        case TextureKind::Perlin:
            return Element::Perlin;
    }
    return Element::Checker;
}

std::string default_text(const ElementTable& table, const Field& field) {
    if (!field.default_text.empty() || !table.defaults) return std::string(field.default_text);
    const FieldAccess& a = field.access;
    if (a.present && !a.present(table.defaults)) return "—";
    if (field.type == FieldType::Bool && a.number) return a.number(table.defaults) != 0 ? "on" : "off";
    if (a.number) return format_number(a.number(table.defaults));
    if (a.vec3) return format_vec3(a.vec3(table.defaults));
    return "—";
}

std::string format_number(double x) {
    if (std::isfinite(x) && x == std::floor(x) && std::fabs(x) < 1e15) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.0f", x);
        // %.0f prints -0 as "-0", which is what the value is.
        return buf;
    }
    char buf[64];
    auto result = std::to_chars(buf, buf + sizeof buf, x);
    return std::string(buf, result.ptr);
}

std::string format_vec3(const Vec3& v) {
    std::string out(1, '<');
    out.append(format_number(v.x)).append(", ").append(format_number(v.y)).append(", ");
    return out.append(format_number(v.z)).append(1, '>');
}

std::optional<std::string> number_problem(const Field& field, double x) {
    const Range& r = field.range;
    const bool integral = field.type != FieldType::Integer || x == std::floor(x);
    if (std::isfinite(x) && integral && r.contains(x)) return std::nullopt;
    const std::string found = ", found " + format_number(x);
    if (!std::isfinite(x)) return "must be a finite number" + found;
    if (field.type == FieldType::Integer) {
        std::string message = "must be an integer";
        if (r.has_lo() && r.has_hi())
            message.append(" from ").append(format_number(r.lo)).append(" to ").append(format_number(r.hi));
        else if (r.has_lo() || r.has_hi())
            message.append(" ").append(r.describe());
        return message + found;
    }
    if (r.hi == kMaxSingle && x > kMaxSingle) return "is too large for single precision" + found;
    return "must be " + r.describe() + found;
}

std::optional<std::string> vec3_problem(const Field& field, const Vec3& v) {
    if (!finite3(v)) return "must be finite, found " + format_vec3(v);
    if (field.type != FieldType::Colour) return std::nullopt;
    if (v.x < 0 || v.y < 0 || v.z < 0) return "must have components >= 0, found " + format_vec3(v);
    if (v.x > kMaxSingle || v.y > kMaxSingle || v.z > kMaxSingle)
        return "is too large for single precision, found " + format_vec3(v);
    return std::nullopt;
}

std::optional<std::string> image_size_problem(long long width, long long height) {
    if (width * height <= kMaxPixels) return std::nullopt;
    return "image size " + std::to_string(width) + " x " + std::to_string(height) + " exceeds the limit of " +
           std::to_string(kMaxPixels) + " pixels (2^28)";
}

std::optional<std::string> light_grid_problem(long long samples_u, long long samples_v) {
    if (samples_u * samples_v <= kMaxLightSamples) return std::nullopt;
    return "area light has " + std::to_string(samples_u) + " x " + std::to_string(samples_v) +
           " samples, more than the limit of " + std::to_string(kMaxLightSamples);
}

std::optional<std::string> reflection_transmission_problem(double reflection, double transmission) {
    // Rounding slack for sums like 0.1 * 7 + 0.3 that are meant to be 1.
    if (reflection + transmission <= 1 + 1e-12) return std::nullopt;
    return "'reflection' + 'transmission' must not exceed 1, found " + format_number(reflection) + " + " +
           format_number(transmission);
}

std::optional<std::string> light_radiance_problem(const Vec3& color, double intensity) {
    const Vec3 r = color * intensity;
    if (r.x <= kMaxSingle && r.y <= kMaxSingle && r.z <= kMaxSingle) return std::nullopt;
    return "'color' x 'intensity' is too large for single precision, found " + format_vec3(color) + " x " +
           format_number(intensity);
}

std::optional<std::string> perlin_scale_problem(const Vec3& scale) {
    const Vec3& v = scale;
    if (finite3(v) && v.x >= 0 && v.y >= 0 && v.z >= 0 && v != Vec3(0)) return std::nullopt;
    return "must have components >= 0, not all zero, found " + format_vec3(v);
}

bool check_fields(const ElementTable& table, const void* spec, SpecItem item, size_t index, uint32_t tag,
                  std::vector<SpecError>& errors) {
    bool ok = true;
    for (const Field& f : table.fields) {
        const FieldAccess& a = f.access;
        if (a.present && !a.present(spec)) continue;
        std::optional<std::string> problem;
        if (a.number && f.type != FieldType::Bool)
            problem = number_problem(f, a.number(spec));
        else if (a.vec3)
            problem = vec3_problem(f, a.vec3(spec));
        if (!problem) continue;
        errors.push_back(
            {item, index, tag, std::string(table.name) + " " + quoted(f.name) + " " + *problem, -1, f.name});
        ok = false;
    }
    return ok;
}

}  // namespace wsd::render
