// The property tables of every block, and the lowering of checked settings, camera, light and
// object blocks (spheres, boxes, triangles, planes, cylinders, cones, tori, discs; meshes in
// lower_mesh.cpp) into render spec elements, with the cross-property checks the tables cannot
// express. Transforms compose here too.
#include "lang/lower.h"

#include <cmath>
#include <filesystem>
#include <numbers>

#include "render/math.h"

namespace wsd::lang {

namespace {

std::string quoted(std::string_view s) {
    return std::string(1, '\'').append(s).append(1, '\'');
}

// A block's table as the render element table gives it: every field a property of that name,
// taking one value.
BlockTable generated(render::Element element, bool transforms = false) {
    const render::ElementTable& t = render::element_table(element);
    BlockTable b{std::string(t.name), element, {}, transforms};
    for (const render::Field& f : t.fields) b.properties.push_back({f.name, f.type, 1, 1, &f});
    return b;
}

// What the language adds to a field: the name it is written under and its number of values.
void written_as(BlockTable& b, std::string_view field, std::string_view name, int min_values,
                int max_values) {
    for (Property& p : b.properties) {
        if (p.field && p.field->name == field) {
            p.name = name;
            p.min_values = min_values;
            p.max_values = max_values;
        }
    }
}

std::map<std::string_view, BlockTable> make_tables() {
    using render::Element;
    std::map<std::string_view, BlockTable> t;
    t["settings"] = generated(Element::Settings);
    t["camera"] = generated(Element::Camera);
    t["light area"] = generated(Element::AreaLight);
    written_as(t["light area"], "samples", "samples", 1, 2);
    t["light point"] = generated(Element::PointLight);
    for (const Property& p : t["light area"].properties)
        if (!t["light point"].find(p.name))
            t["light point"].hints.emplace_back(
                p.name, quoted(p.name).append(" belongs to area lights: write 'light area { ... }'"));
    t["sphere"] = generated(Element::Sphere, true);
    t["box"] = generated(Element::Box, true);
    t["triangle"] = generated(Element::Triangle, true);
    written_as(t["triangle"], "vertices", "", 3, 3);
    written_as(t["triangle"], "uv", "uv", 3, 3);
    t["plane"] = generated(Element::Plane, true);
    t["mesh"] = generated(Element::Mesh, true);
    t["cylinder"] = generated(Element::Cylinder, true);
    t["cone"] = generated(Element::Cone, true);
    t["torus"] = generated(Element::Torus, true);
    t["disc"] = generated(Element::Disc, true);
    t["light spot"] = generated(Element::SpotLight);
    // POV-Ray's words for the same things.
    t["light spot"].hints.emplace_back("point_at", "a spot light aims at its 'look_at'");
    t["light spot"].hints.emplace_back("radius", "POV-Ray's spotlight 'radius' is wsd's 'angle'");
    t["cone"].hints.emplace_back("radius", "a cone has a 'base_radius' and a 'cap_radius'");
    t["torus"].hints.emplace_back("center", "a torus is centred at the origin: place it with 'translate'");
    t["torus"].hints.emplace_back("radius", "a torus has a 'major' and a 'minor' radius");
    // The items of group and CSG bodies and of `object` blocks: material and the transforms.
    for (const char* what : {"group", "union", "intersection", "difference"}) {
        t[what] = generated(Element::Csg, true);
        t[what].what = what;
    }
    t["object"] = generated(Element::Instance, true);
    t["object"].what = "object";
    t["material"] = generated(Element::Material);
    // `base` is the language's own: a copy of another material value, applied first.
    t["material"].properties.insert(t["material"].properties.begin(), {"base", render::FieldType::Material});
    t["checker"] = generated(Element::Checker);
    written_as(t["checker"], "colors", "colors", 2, 2);
    t["perlin"] = generated(Element::Perlin);
    written_as(t["perlin"], "colors", "colors", 2, 2);
    return t;
}

bool parallel(glm::dvec3 a, glm::dvec3 b) {
    // As unit vectors (safe_normalize rescales tiny and huge ones), so that the test neither
    // underflows nor overflows: a direction is a direction, whatever its length.
    const glm::dvec3 ua = render::safe_normalize(a, glm::dvec3(0.0)),
                     ub = render::safe_normalize(b, glm::dvec3(0.0));
    return glm::length(glm::cross(ua, ub)) <= render::kParallelSine;
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
    // Present but failed, or meant by a misspelt name: already reported.
    if (r.has("material") || r.suggested("material")) return std::nullopt;
    if (ctx.material_optional) return MaterialPtr{};
    const DefaultMaterial& fallback = ctx.default_material;
    if (!fallback.value) {
        Diagnostic& d = ctx.diags.error(r.keyword(), "missing property 'material' in " + r.table().what);
        d.help.push_back("add 'material { ... }' or 'let default_material = material { ... }'");
        if (ctx.call)
            d.notes.push_back({*ctx.call, "added by this call, and nothing enclosing it gives a material"});
        return std::nullopt;
    }
    const std::optional<Value>& v = *fallback.value;
    if (!v) return std::nullopt;  // its definition failed: already reported
    if (!v->is(ValueType::Material)) {
        Diagnostic& d = ctx.diags.error(
            r.keyword(), std::string("'default_material' is a ") + type_name(v->type()) + ", not a material");
        d.notes.push_back({fallback.defined_at, "'default_material' is defined here"});
        if (ctx.call)
            d.notes.push_back({*ctx.call, "added by this call, and nothing enclosing it gives a material"});
        return std::nullopt;
    }
    return v->material();
}

void lower_sphere(BlockReader& r, LoweredObject& o) {
    r.require("center");
    r.require("radius");
    o.shape.kind = render::ShapeKind::Sphere;
}

void lower_box(BlockReader& r, LoweredObject& o) {
    bool ok = r.require("min") & r.require("max");
    o.shape.kind = render::ShapeKind::Box;
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
    const std::vector<Value> v = r.values("");
    if (v.size() == 3)
        for (int i = 0; i < 3; ++i) o.shape.v[i] = v[static_cast<size_t>(i)].vec3();
    const std::vector<Value> uv = r.values("uv");
    if (uv.size() == 3)
        o.shape.tri_uv = std::array<render::Vec2, 3>{uv[0].vec2(), uv[1].vec2(), uv[2].vec2()};
}

void lower_plane(BlockReader& r, LoweredObject& o) {
    r.require("normal");
    o.shape.kind = render::ShapeKind::Plane;
    if (r.value("normal") && o.shape.normal == glm::dvec3(0.0))
        r.fail(r.value_span("normal"), "plane 'normal' must not be the zero vector");
}

// The later of two properties as written (the one a cross-property error points at), or the one
// that is present.
std::string_view later_of(const BlockReader& r, std::string_view a, std::string_view b) {
    if (!r.has(a)) return b;
    if (!r.has(b)) return a;
    return written_after(r, a, b) ? a : b;
}

void lower_cylinder(BlockReader& r, LoweredObject& o) {
    bool ok = r.require("base") & r.require("cap") & r.require("radius");
    o.shape.kind = render::ShapeKind::Cylinder;
    if (ok && r.ok() && o.shape.base == o.shape.cap)
        r.fail(r.value_span(later_of(r, "base", "cap")), "cylinder 'base' and 'cap' are the same point " +
                                                             describe(*r.value("cap")) +
                                                             ": the cylinder has no axis");
}

void lower_cone(BlockReader& r, LoweredObject& o) {
    bool ok = r.require("base") & r.require("cap") & r.require("base_radius") & r.require("cap_radius");
    o.shape.kind = render::ShapeKind::Cone;
    if (!ok || !r.ok()) return;
    if (o.shape.base == o.shape.cap)
        r.fail(r.value_span(later_of(r, "base", "cap")), "cone 'base' and 'cap' are the same point " +
                                                             describe(*r.value("cap")) +
                                                             ": the cone has no axis");
    else if (o.shape.radius == 0 && o.shape.cap_radius == 0)
        r.fail(r.value_span(later_of(r, "base_radius", "cap_radius")),
               "cone 'base_radius' and 'cap_radius' are both 0: the cone has no width");
}

void lower_torus(BlockReader& r, LoweredObject& o) {
    r.require("major");
    r.require("minor");
    o.shape.kind = render::ShapeKind::Torus;
}

void lower_disc(BlockReader& r, LoweredObject& o) {
    bool ok = r.require("center") & r.require("normal") & r.require("radius");
    o.shape.kind = render::ShapeKind::Disc;
    if (!ok || !r.ok()) return;
    if (o.shape.normal == glm::dvec3(0.0))
        r.fail(r.value_span("normal"), "disc 'normal' must not be the zero vector");
    else if (!(o.shape.hole < o.shape.radius))
        r.fail(r.value_span(later_of(r, "hole", "radius")),
               "disc 'hole' must be less than 'radius', found hole " + render::format_number(o.shape.hole) +
                   " and radius " + render::format_number(o.shape.radius));
}

void check_spot(BlockReader& r, const render::LightSpec& l) {
    r.require("look_at");
    if (!r.ok()) return;
    if (l.look_at == l.position)
        r.fail(r.value_span(later_of(r, "position", "look_at")),
               "spot light 'look_at' is the same point as 'position': the spot has no axis");
    else if (l.angle > l.falloff)
        r.fail(r.value_span(later_of(r, "angle", "falloff")),
               "spot light 'angle' must not exceed 'falloff', found angle " + render::format_number(l.angle) +
                   " and falloff " + render::format_number(l.falloff));
}

}  // namespace

const BlockTable& block_table(std::string_view what) {
    static const std::map<std::string_view, BlockTable> tables = make_tables();
    return tables.at(what);
}

const BlockTable* statement_table(const ObjectStmt& stmt, Diagnostics& diags) {
    switch (stmt.block_kind) {
        case BlockKind::Settings:
            return &block_table("settings");
        case BlockKind::Camera:
            return &block_table("camera");
        case BlockKind::Light:
            break;
        case BlockKind::Sphere:
            return &block_table("sphere");
        case BlockKind::Box:
            return &block_table("box");
        case BlockKind::Triangle:
            return &block_table("triangle");
        case BlockKind::Plane:
            return &block_table("plane");
        case BlockKind::Mesh:
            return &block_table("mesh");
        case BlockKind::Cylinder:
            return &block_table("cylinder");
        case BlockKind::Cone:
            return &block_table("cone");
        case BlockKind::Torus:
            return &block_table("torus");
        case BlockKind::Disc:
            return &block_table("disc");
    }
    if (stmt.name == "area") return &block_table("light area");
    if (stmt.name == "point") return &block_table("light point");
    if (stmt.name == "spot") return &block_table("light spot");
    Span at = stmt.name.empty() ? stmt.keyword : stmt.name_span;
    Diagnostic& d = diags.error(
        at, stmt.name.empty() ? std::string("light needs a kind: point, area or spot")
                              : "unknown light kind '" + std::string(stmt.name) + "' (point, area or spot)");
    std::string match = closest_match(stmt.name, {"point", "area", "spot"});
    if (!stmt.name.empty() && !match.empty()) d.help.push_back("did you mean '" + match + "'?");
    return nullptr;
}

Span head_span(const BlockExpr& expr) {
    Span s = expr.span;
    if (expr.block && expr.block->open.end > s.begin && expr.block->open.end <= s.end &&
        expr.block->open.file == s.file)
        s.end = expr.block->open.end;
    return s;
}

const BlockTable& expression_table(ExprKind kind) {
    return block_table(kind == ExprKind::Checker  ? "checker"
                       : kind == ExprKind::Perlin ? "perlin"
                                                  : "material");
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

std::optional<Lowered<render::Settings>> lower_settings(BlockReader& r) {
    render::Settings s;
    r.apply(s);
    if (r.ok()) {
        if (auto problem = render::image_size_problem(s.width, s.height)) {
            std::string later = !r.has("height") || (r.has("width") && written_after(r, "width", "height"))
                                    ? "width"
                                    : "height";
            r.fail(r.value_span(later), *problem);
        }
    }
    if (!r.ok()) return std::nullopt;
    return Lowered<render::Settings>{s, r.field_spans()};
}

std::optional<Lowered<render::CameraSpec>> lower_camera(BlockReader& r) {
    r.require("position");
    r.require("look_at");
    render::CameraSpec c;
    r.apply(c);
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
    return Lowered<render::CameraSpec>{c, r.field_spans()};
}

std::optional<Lowered<render::LightSpec>> lower_light(BlockReader& r) {
    render::LightSpec l;
    const bool area = r.table().element == render::Element::AreaLight;
    if (area) l.kind = render::LightKind::Area;
    if (r.table().element == render::Element::SpotLight) l.kind = render::LightKind::Spot;
    r.require("position");
    r.apply(l);
    if (r.ok()) {
        if (auto problem = render::light_radiance_problem(l.color, l.intensity))
            r.fail(r.value_span(r.has("intensity") ? "intensity" : "color"), *problem);
    }
    if (l.kind == render::LightKind::Spot) check_spot(r, l);
    if (area) {
        r.require("u");
        r.require("v");
        const std::vector<Value> samples = r.values("samples");
        if (!samples.empty()) {
            l.samples_u = static_cast<int>(samples[0].number());
            l.samples_v = static_cast<int>(samples.size() > 1 ? samples[1].number() : samples[0].number());
        }
        l.sampling = r.word("sampling", "jittered") == "uniform" ? render::LightSampling::Uniform
                                                                 : render::LightSampling::Jittered;
        if (r.ok()) {
            if (l.u == glm::dvec3(0.0))
                r.fail(r.value_span("u"), "area light edge 'u' must not be the zero vector");
            else if (l.v == glm::dvec3(0.0))
                r.fail(r.value_span("v"), "area light edge 'v' must not be the zero vector");
            else if (parallel(l.u, l.v))
                r.fail(r.value_span(written_after(r, "u", "v") ? "u" : "v"),
                       "area light edges 'u' and 'v' are parallel");
            if (auto problem = render::light_grid_problem(l.samples_u, l.samples_v))
                r.fail(r.value_span("samples"), *problem);
        }
    }
    if (!r.ok()) return std::nullopt;
    return Lowered<render::LightSpec>{l, r.field_spans()};
}

std::optional<LoweredObject> lower_object(BlockReader& r, BlockContext& ctx) {
    LoweredObject o;
    o.record.span = r.keyword();
    r.apply(o.shape);
    switch (r.table().element) {
        case render::Element::Sphere:
            lower_sphere(r, o);
            break;
        case render::Element::Box:
            lower_box(r, o);
            break;
        case render::Element::Triangle:
            lower_triangle(r, o);
            break;
        case render::Element::Plane:
            lower_plane(r, o);
            break;
        case render::Element::Mesh:
            lower_mesh(r, ctx, o);
            break;
        case render::Element::Cylinder:
            lower_cylinder(r, o);
            break;
        case render::Element::Cone:
            lower_cone(r, o);
            break;
        case render::Element::Torus:
            lower_torus(r, o);
            break;
        case render::Element::Disc:
            lower_disc(r, o);
            break;
        default:
            return std::nullopt;
    }
    std::optional<MaterialPtr> material = object_material(r, ctx);
    if (!material) r.failed();
    if (!r.ok()) return std::nullopt;
    o.material = *material;
    o.shape.object_to_world = compose_transforms(r.transforms());
    o.fields = r.field_spans();
    return o;
}

}  // namespace wsd::lang
