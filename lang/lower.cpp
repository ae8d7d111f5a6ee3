// The property tables of every block, and the lowering of settings, camera, lights and objects
// (spheres, boxes, triangles, planes; meshes in lower_mesh.cpp) into render spec elements, with
// the cross-property checks the tables cannot express. Transforms compose here too.
#include "lang/lower.h"

#include <cmath>
#include <filesystem>
#include <numbers>

namespace wsd::lang {

namespace {

const Property kMaterialProperty{"material", PropType::Material};

std::map<std::string_view, BlockTable> make_tables() {
    std::map<std::string_view, BlockTable> t;
    t["settings"] = {"settings",
                     {{"width", PropType::Integer, between(1, 100000)},
                      {"height", PropType::Integer, between(1, 100000)},
                      {"supersamples", PropType::Integer, between(1, 4096)},
                      {"adaptive_supersampling", PropType::Bool},
                      {"aa_threshold", PropType::Number, at_least(0)},
                      {"bailout", PropType::Number, Range{0, 1, false, true}},
                      {"max_depth", PropType::Integer, between(0, 256)},
                      {"ambient", PropType::Number, at_least(0)},
                      {"background", PropType::Colour},
                      {"seed", PropType::Integer, between(0, 4294967295.0)}}};
    t["camera"] = {"camera",
                   {{"position", PropType::Vector3},
                    {"look_at", PropType::Vector3},
                    {"up", PropType::Vector3},
                    {"fov", PropType::Number, Range{0, 180, true, true}}}};
    std::vector<Property> light = {{"position", PropType::Vector3},
                                   {"color", PropType::Colour},
                                   {"intensity", PropType::Number, at_least(0)}};
    t["light point"] = {"light point", light};
    for (std::string_view area_only : {"u", "v", "samples", "sampling", "adaptive"})
        t["light point"].hints.emplace_back(
            area_only, "'" + std::string(area_only) + "' belongs to area lights: write 'light area { ... }'");
    light.push_back({"u", PropType::Vector3});
    light.push_back({"v", PropType::Vector3});
    light.push_back({"samples", PropType::Integer, between(1, 1024), 1, 2});
    light.push_back({"sampling", PropType::Word, {}, 1, 1, {"jittered", "uniform"}});
    light.push_back({"adaptive", PropType::Bool});
    t["light area"] = {"light area", light};
    t["sphere"] = {"sphere",
                   {{"center", PropType::Vector3}, {"radius", PropType::Number, above(0)}, kMaterialProperty},
                   true};
    t["box"] = {"box", {{"min", PropType::Vector3}, {"max", PropType::Vector3}, kMaterialProperty}, true};
    t["triangle"] = {
        "triangle",
        {{"", PropType::Vector3, {}, 3, 3}, {"uv", PropType::Vector2, {}, 3, 3}, kMaterialProperty},
        true};
    t["plane"] = {"plane",
                  {{"normal", PropType::Vector3},
                   {"distance", PropType::Number},
                   {"uv_scale", PropType::Number, above(0)},
                   kMaterialProperty},
                  true};
    t["mesh"] = {"mesh",
                 {{"file", PropType::String},
                  {"vertices", PropType::List},
                  {"faces", PropType::List},
                  {"uvs", PropType::List},
                  {"normals", PropType::List},
                  kMaterialProperty},
                 true};
    t["material"] = {"material",
                     {{"base", PropType::Material},
                      {"color", PropType::Colour},
                      {"texture", PropType::Texture},
                      {"ambient", PropType::Number, at_least(0)},
                      {"diffuse", PropType::Number, at_least(0)},
                      {"specular", PropType::Number, at_least(0)},
                      {"shininess", PropType::Number, above(0)},
                      {"reflection", PropType::Number, between(0, 1)},
                      {"transmission", PropType::Number, between(0, 1)},
                      {"ior", PropType::Number, above(0)},
                      {"absorption", PropType::Colour},
                      {"bump", PropType::Texture},
                      {"bump_strength", PropType::Number, at_least(0)}}};
    t["checker"] = {"checker",
                    {{"scale", PropType::Number, above(0)}, {"colors", PropType::Colour, {}, 2, 2}}};
    t["perlin"] = {"perlin",
                   {{"kind", PropType::Word, {}, 1, 1, {"noise", "turbulence", "marble", "wood"}},
                    {"scale", PropType::NumberOrVector3},
                    {"octaves", PropType::Integer, between(1, 64)},
                    {"colors", PropType::Colour, {}, 2, 2}}};
    return t;
}

constexpr double kMaxPixels = 268435456.0;  // 2^28
constexpr int kMaxLightSamples = 65536;

// Two directions are treated as parallel when the sine of their angle is below this: the frame
// built from them would be dominated by rounding.
constexpr double kParallelSine = 1e-9;

bool parallel(glm::dvec3 a, glm::dvec3 b) {
    return glm::length(glm::cross(a, b)) <= kParallelSine * glm::length(a) * glm::length(b);
}

// sin and cos of an angle in degrees, exact at multiples of 90° so that quarter turns map axes
// onto axes without rounding residue.
void sin_cos_degrees(double degrees, double& s, double& c) {
    double r = std::fmod(degrees, 360.0);
    if (r < 0) r += 360.0;
    if (r == 0) {
        s = 0;
        c = 1;
        return;
    }
    if (r == 90) {
        s = 1;
        c = 0;
        return;
    }
    if (r == 180) {
        s = 0;
        c = -1;
        return;
    }
    if (r == 270) {
        s = -1;
        c = 0;
        return;
    }
    double rad = degrees * (std::numbers::pi / 180.0);
    s = std::sin(rad);
    c = std::cos(rad);
}

// A matrix written row by row as in the language reference (glm stores columns).
render::Mat4 from_rows(const double (&m)[3][3]) {
    render::Mat4 out(1.0);
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col) out[col][row] = m[row][col];
    return out;
}

std::optional<MaterialPtr> object_material(BlockReader& r, BlockContext& ctx) {
    if (const Value* m = r.value("material")) return m->material();
    if (r.has("material")) return std::nullopt;  // present but failed: already reported
    std::optional<MaterialPtr> fallback = ctx.default_material(r.keyword());
    if (!fallback) return std::nullopt;
    if (!*fallback) {
        Diagnostic& d = ctx.diags.error(r.keyword(), "missing property 'material' in " + r.table().what);
        d.help.push_back("add 'material { ... }' or 'let default_material = material { ... }'");
        return std::nullopt;
    }
    return fallback;
}

void lower_sphere(BlockReader& r, LoweredObject& o) {
    r.require("center");
    r.require("radius");
    o.shape.kind = render::ShapeKind::Sphere;
    o.shape.center = r.vec3("center", o.shape.center);
    o.shape.radius = r.number("radius", o.shape.radius);
}

void lower_box(BlockReader& r, LoweredObject& o) {
    bool ok = r.require("min") & r.require("max");
    o.shape.kind = render::ShapeKind::Box;
    o.shape.box_min = r.vec3("min", o.shape.box_min);
    o.shape.box_max = r.vec3("max", o.shape.box_max);
    if (ok && r.ok()) {
        glm::dvec3 lo = o.shape.box_min, hi = o.shape.box_max;
        if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z))
            r.fail(r.value_span("max"),
                   "box 'max' must be greater than 'min' in every component, found min " +
                       describe(*r.value("min")) + " and max " + describe(*r.value("max")));
    }
}

void lower_triangle(BlockReader& r, LoweredObject& o) {
    r.require("");
    o.shape.kind = render::ShapeKind::Triangle;
    o.is_triangle = true;
    const std::vector<Value>& v = r.values("");
    if (v.size() == 3)
        for (int i = 0; i < 3; ++i) o.shape.v[i] = v[static_cast<size_t>(i)].vec3();
    const std::vector<Value>& uv = r.values("uv");
    if (uv.size() == 3)
        o.shape.tri_uv = std::array<render::Vec2, 3>{uv[0].vec2(), uv[1].vec2(), uv[2].vec2()};
}

void lower_plane(BlockReader& r, LoweredObject& o) {
    r.require("normal");
    o.shape.kind = render::ShapeKind::Plane;
    o.shape.normal = r.vec3("normal", o.shape.normal);
    o.shape.distance = r.number("distance", o.shape.distance);
    o.shape.uv_scale = r.number("uv_scale", o.shape.uv_scale);
    if (r.value("normal") && o.shape.normal == glm::dvec3(0.0))
        r.fail(r.value_span("normal"), "plane 'normal' must not be the zero vector");
}

}  // namespace

const BlockTable& block_table(std::string_view what) {
    static const std::map<std::string_view, BlockTable> tables = make_tables();
    return tables.at(what);
}

std::string resolve_path(const SourceManager& sources, uint32_t file, const std::string& path) {
    std::filesystem::path p(path);
    if (p.is_absolute() || file >= sources.size()) return path;
    std::filesystem::path dir = std::filesystem::path(sources.file(file).path).parent_path();
    if (dir.empty()) return path;
    return (dir / p).string();
}

std::string canonical_path(const std::string& path) {
    std::error_code ec;
    std::filesystem::path abs = std::filesystem::absolute(path, ec);
    if (ec) return std::filesystem::path(path).lexically_normal().string();
    std::filesystem::path canon = std::filesystem::weakly_canonical(abs, ec);
    return ec ? abs.lexically_normal().string() : canon.string();
}

render::Mat4 rotation_matrix(glm::dvec3 degrees) {
    double s, c;
    sin_cos_degrees(degrees.x, s, c);
    render::Mat4 rx = from_rows({{1, 0, 0}, {0, c, -s}, {0, s, c}});
    sin_cos_degrees(degrees.y, s, c);
    render::Mat4 ry = from_rows({{c, 0, s}, {0, 1, 0}, {-s, 0, c}});
    sin_cos_degrees(degrees.z, s, c);
    render::Mat4 rz = from_rows({{c, -s, 0}, {s, c, 0}, {0, 0, 1}});
    return rz * ry * rx;
}

render::Mat4 compose_transforms(const std::vector<Transform>& transforms) {
    render::Mat4 m(1.0);
    for (const Transform& t : transforms) {
        render::Mat4 step(1.0);
        switch (t.kind) {
            case TransformKind::Scale:
                step[0][0] = t.v.x;
                step[1][1] = t.v.y;
                step[2][2] = t.v.z;
                break;
            case TransformKind::Rotate:
                step = rotation_matrix(t.v);
                break;
            case TransformKind::Translate:
                step[3] = glm::dvec4(t.v, 1.0);
                break;
        }
        m = step * m;
    }
    return m;
}

std::optional<render::Settings> lower_settings(const ObjectStmt& stmt, BlockContext& ctx) {
    BlockReader r(block_table("settings"), stmt.block, stmt.keyword, ctx.diags, ctx.eval);
    render::Settings s;
    s.width = static_cast<int>(r.integer("width", s.width));
    s.height = static_cast<int>(r.integer("height", s.height));
    s.supersamples = static_cast<int>(r.integer("supersamples", s.supersamples));
    s.adaptive_supersampling = r.boolean("adaptive_supersampling", s.adaptive_supersampling);
    s.aa_threshold = r.number("aa_threshold", s.aa_threshold);
    s.bailout = r.number("bailout", s.bailout);
    s.max_depth = static_cast<int>(r.integer("max_depth", s.max_depth));
    s.ambient = r.number("ambient", s.ambient);
    s.background = r.vec3("background", s.background);
    s.seed = static_cast<uint32_t>(r.integer("seed", s.seed));
    if (r.ok() && static_cast<double>(s.width) * s.height > kMaxPixels) {
        std::string later =
            !r.has("height") || (r.has("width") && written_after(r, "width", "height")) ? "width" : "height";
        r.fail(r.value_span(later), "image size " + std::to_string(s.width) + " x " +
                                        std::to_string(s.height) +
                                        " exceeds the limit of 268435456 pixels (2^28)");
    }
    if (!r.ok()) return std::nullopt;
    return s;
}

std::optional<render::CameraSpec> lower_camera(const ObjectStmt& stmt, BlockContext& ctx) {
    BlockReader r(block_table("camera"), stmt.block, stmt.keyword, ctx.diags, ctx.eval);
    r.require("position");
    r.require("look_at");
    render::CameraSpec c;
    c.position = r.vec3("position", c.position);
    c.look_at = r.vec3("look_at", c.look_at);
    c.up = r.vec3("up", c.up);
    c.fov_degrees = r.number("fov", c.fov_degrees);
    if (!r.ok()) return std::nullopt;
    glm::dvec3 forward = c.look_at - c.position;
    if (forward == glm::dvec3(0.0)) {
        r.fail(r.value_span("look_at"), "camera 'look_at' is the same point as 'position'");
    } else if (c.up == glm::dvec3(0.0)) {
        r.fail(r.value_span("up"), "camera 'up' must not be the zero vector");
    } else if (!std::isfinite(glm::length(forward)) || parallel(c.up, forward)) {
        if (r.has("up"))
            r.fail(r.value_span("up"), "camera 'up' is parallel to the view direction (look_at - position)");
        else
            r.fail(r.value_span("look_at"),
                   "camera looks along the default 'up' <0, 1, 0>: give an 'up' that is not parallel to "
                   "look_at - position");
    }
    if (!r.ok()) return std::nullopt;
    return c;
}

std::optional<render::LightSpec> lower_light(const ObjectStmt& stmt, BlockContext& ctx) {
    render::LightSpec l;
    if (stmt.name == "area") {
        l.kind = render::LightKind::Area;
    } else if (stmt.name != "point") {
        Span at = stmt.name.empty() ? stmt.keyword : stmt.name_span;
        Diagnostic& d = ctx.diags.error(
            at, stmt.name.empty() ? std::string("light needs a kind: point or area")
                                  : "unknown light kind '" + std::string(stmt.name) + "' (point or area)");
        std::string match = closest_match(stmt.name, {"point", "area"});
        if (!stmt.name.empty() && !match.empty()) d.help.push_back("did you mean '" + match + "'?");
        return std::nullopt;
    }
    bool area = l.kind == render::LightKind::Area;
    BlockReader r(block_table(area ? "light area" : "light point"), stmt.block, stmt.keyword, ctx.diags,
                  ctx.eval);
    r.require("position");
    l.position = r.vec3("position", l.position);
    l.color = r.vec3("color", l.color);
    l.intensity = r.number("intensity", l.intensity);
    if (area) {
        r.require("u");
        r.require("v");
        l.u = r.vec3("u", l.u);
        l.v = r.vec3("v", l.v);
        const std::vector<Value>& samples = r.values("samples");
        if (!samples.empty()) {
            l.samples_u = static_cast<int>(samples[0].number());
            l.samples_v = static_cast<int>(samples.size() > 1 ? samples[1].number() : samples[0].number());
        }
        l.sampling = r.word("sampling", "jittered") == "uniform" ? render::LightSampling::Uniform
                                                                 : render::LightSampling::Jittered;
        l.adaptive = r.boolean("adaptive", l.adaptive);
        if (r.ok()) {
            if (l.u == glm::dvec3(0.0))
                r.fail(r.value_span("u"), "area light edge 'u' must not be the zero vector");
            else if (l.v == glm::dvec3(0.0))
                r.fail(r.value_span("v"), "area light edge 'v' must not be the zero vector");
            else if (parallel(l.u, l.v))
                r.fail(r.value_span(written_after(r, "u", "v") ? "u" : "v"),
                       "area light edges 'u' and 'v' are parallel");
            if (static_cast<long long>(l.samples_u) * l.samples_v > kMaxLightSamples)
                r.fail(r.value_span("samples"), "area light has " + std::to_string(l.samples_u) + " x " +
                                                    std::to_string(l.samples_v) +
                                                    " samples, more than the limit of 65536");
        }
    }
    if (!r.ok()) return std::nullopt;
    return l;
}

std::optional<LoweredObject> lower_object(const ObjectStmt& stmt, BlockContext& ctx) {
    const char* what = "sphere";
    switch (stmt.block_kind) {
        case BlockKind::Sphere:
            what = "sphere";
            break;
        case BlockKind::Box:
            what = "box";
            break;
        case BlockKind::Triangle:
            what = "triangle";
            break;
        case BlockKind::Plane:
            what = "plane";
            break;
        case BlockKind::Mesh:
            what = "mesh";
            break;
        default:
            return std::nullopt;
    }
    BlockReader r(block_table(what), stmt.block, stmt.keyword, ctx.diags, ctx.eval);
    LoweredObject o;
    o.record.span = stmt.keyword;
    switch (stmt.block_kind) {
        case BlockKind::Sphere:
            lower_sphere(r, o);
            break;
        case BlockKind::Box:
            lower_box(r, o);
            break;
        case BlockKind::Triangle:
            lower_triangle(r, o);
            break;
        case BlockKind::Plane:
            lower_plane(r, o);
            break;
        default:
            lower_mesh(r, ctx, o);
            break;
    }
    std::optional<MaterialPtr> material = object_material(r, ctx);
    if (!material) r.failed();
    if (!r.ok()) return std::nullopt;
    o.material = *material;
    o.shape.object_to_world = compose_transforms(r.transforms());
    return o;
}

}  // namespace wsd::lang
