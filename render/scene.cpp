// build_scene: validates every element of a SceneSpec against its table (render/params.h) and the
// rules that join fields, builds the geometry and every texture (one ImageCache, so each image
// file is read once), and reports each problem as a SpecError naming the element, its tag and the
// field it concerns.
#include "render/scene.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "render/aabb.h"
#include "render/csg_prims.h"
#include "render/math.h"
#include "render/params.h"

namespace wsd::render {

namespace {

bool check_settings(const Settings& s, std::vector<SpecError>& errors) {
    const ElementTable& table = element_table(Element::Settings);
    if (!check_fields(table, s, SpecItem::Settings, 0, 0, errors)) return false;
    if (auto problem = image_size_problem(s.width, s.height)) {
        errors.push_back({SpecItem::Settings, 0, 0, *problem, -1, "height"});
        return false;
    }
    return true;
}

bool check_material(const MaterialSpec& m, size_t index, std::vector<SpecError>& errors) {
    if (!check_fields(element_table(Element::Material), m, SpecItem::Material, index, m.tag, errors))
        return false;
    if (auto problem = reflection_transmission_problem(m.reflection, m.transmission)) {
        errors.push_back({SpecItem::Material, index, m.tag, *problem, -1, "transmission"});
        return false;
    }
    return true;
}

// A texture's own fields; the colours of checker and perlin against their shared field.
bool check_texture(const TextureSpec& t, size_t material, std::vector<SpecError>& errors) {
    const ElementTable& table = element_table(element_of(t));
    bool ok = check_fields(table, t, SpecItem::Texture, material, t.tag, errors);
    if (const Field* colors = table.find("colors")) {
        for (const Vec3& c : {t.color1, t.color2}) {
            if (auto problem = vec3_problem(*colors, c)) {
                errors.push_back({SpecItem::Texture, material, t.tag,
                                  std::string(table.name) + " 'colors' " + *problem, -1, "colors"});
                return false;
            }
        }
    }
    if (t.kind == TextureKind::Perlin) {
        if (auto problem = perlin_scale_problem(t.perlin_scale)) {
            errors.push_back({SpecItem::Texture, material, t.tag, "perlin 'scale' " + *problem, -1, "scale"});
            return false;
        }
    }
    return ok;
}

bool check_light(const LightSpec& l, size_t index, std::vector<SpecError>& errors) {
    if (!check_fields(element_table(element_of(l)), l, SpecItem::Light, index, l.tag, errors)) return false;
    if (auto problem = light_radiance_problem(l.color, l.intensity)) {
        errors.push_back({SpecItem::Light, index, l.tag, *problem, -1, "intensity"});
        return false;
    }
    if (l.kind == LightKind::Area) {
        if (auto problem = light_grid_problem(l.samples_u, l.samples_v)) {
            errors.push_back({SpecItem::Light, index, l.tag, *problem, -1, "samples"});
            return false;
        }
    }
    if (l.kind == LightKind::Spot && l.angle > l.falloff) {
        errors.push_back({SpecItem::Light, index, l.tag,
                          "spot light 'angle' must not exceed 'falloff', found angle " +
                              format_number(l.angle) + " and falloff " + format_number(l.falloff),
                          -1, "angle"});
        return false;
    }
    if (l.kind == LightKind::Spot && l.look_at == l.position) {
        errors.push_back({SpecItem::Light, index, l.tag,
                          "spot light 'look_at' is the same point as 'position'", -1, "look_at"});
        return false;
    }
    if (auto err = validate_light(l)) {
        errors.push_back({SpecItem::Light, index, l.tag, *err, -1});
        return false;
    }
    return true;
}

// The fields of a shape that its table checks, and a triangle's vertices; the geometric rules
// (degenerate faces, singular transforms, the primitive limit) are Geometry::build's.
bool check_shape(const ShapeSpec& s, size_t index, std::vector<SpecError>& errors) {
    const ElementTable& table = element_table(element_of(s));
    bool ok = check_fields(table, s, SpecItem::Shape, index, s.tag, errors);
    if (s.kind == ShapeKind::Triangle) {
        for (const Vec3& v : s.v) {
            if (auto problem = vec3_problem(*table.find("vertices"), v)) {
                errors.push_back(
                    {SpecItem::Shape, index, s.tag, "triangle vertex " + *problem, -1, "vertices"});
                return false;
            }
        }
    }
    return ok;
}

// World-space corners of an object-space box.
void add_box_corners(const Mat4& m, const Vec3& lo, const Vec3& hi, Vec3& out_lo, Vec3& out_hi) {
    for (int k = 0; k < 8; ++k) {
        const Vec3 c{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
        const Vec3 w = Vec3(m * glm::dvec4(c, 1.0));
        out_lo = glm::min(out_lo, w);
        out_hi = glm::max(out_hi, w);
    }
}

}  // namespace

bool Scene::may_cross_transmissive(const Vec3& a, const Vec3& b) const {
    if (transmissive_unbounded_) return true;
    const Vec3 d = b - a;
    for (const Bounds& box : transmissive_bounds_)
        if (segment_meets_box(box.lo, box.hi, a, d)) return true;
    return false;
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The box of shape `sh` through m into [lo, hi]; false for a shape without finite bounds here.
bool shape_box(const ShapeSpec& sh, const Mat4& m, Vec3& lo, Vec3& hi) {
    switch (sh.kind) {
        case ShapeKind::Sphere:
            add_box_corners(m, sh.center - Vec3(sh.radius), sh.center + Vec3(sh.radius), lo, hi);
            return true;
        case ShapeKind::Box:
            add_box_corners(m, sh.box_min, sh.box_max, lo, hi);
            return true;
        case ShapeKind::Triangle:
            for (const Vec3& v : sh.v) add_box_corners(m, v, v, lo, hi);
            return true;
        case ShapeKind::Mesh: {
            Vec3 mlo(kInf), mhi(-kInf);
            for (const glm::vec3& v : sh.mesh->vertices) {
                mlo = glm::min(mlo, Vec3(v));
                mhi = glm::max(mhi, Vec3(v));
            }
            if (!sh.mesh->vertices.empty()) add_box_corners(m, mlo, mhi, lo, hi);
            return true;
        }
        default:
            return false;
    }
}

// An instanced object's transmissive members in its own frame: those with their own
// transmissive material, and those that inherit (transmissive when the instance is).
struct PrototypeGlass {
    Vec3 own_lo{kInf}, own_hi{-kInf}, inherit_lo{kInf}, inherit_hi{-kInf};
    bool own_unbounded = false, inherit_unbounded = false;
};

PrototypeGlass prototype_glass(const SceneSpec& spec, const PrototypeSpec& p) {
    PrototypeGlass g;
    for (const ShapeSpec& m : p.shapes) {
        const bool inherit = m.material == kInheritMaterial;
        if (m.kind == ShapeKind::Csg) {  // its members' materials decide: bounded conservatively
            g.own_unbounded = true;
            continue;
        }
        if (!inherit && !(spec.materials[m.material].transmission > 0)) continue;
        if (!shape_box(m, m.object_to_world, inherit ? g.inherit_lo : g.own_lo,
                       inherit ? g.inherit_hi : g.own_hi))
            (inherit ? g.inherit_unbounded : g.own_unbounded) = true;
    }
    return g;
}

}  // namespace

void Scene::compute_transmissive_bounds(const SceneSpec& spec) {
    constexpr size_t kMaxBoxes = 16;  // beyond this, one union box (the test is linear)
    std::vector<std::optional<PrototypeGlass>> glass(spec.prototypes.size());
    for (const ShapeSpec& sh : spec.shapes) {
        // An instance without a material of its own has members that all have theirs.
        const bool has_material = sh.material < spec.materials.size();
        const bool trans = sh.kind == ShapeKind::Csg && sh.csg ? csg_transmissive(spec, *sh.csg, sh.material)
                           : has_material                      ? spec.materials[sh.material].transmission > 0
                                                               : false;
        Vec3 lo(kInf), hi(-kInf);
        const Mat4& m = sh.object_to_world;
        if (sh.kind == ShapeKind::Instance) {
            if (sh.prototype >= glass.size()) continue;
            auto& pg = glass[sh.prototype];
            if (!pg) pg = prototype_glass(spec, spec.prototypes[sh.prototype]);
            if (pg->own_unbounded || (trans && pg->inherit_unbounded)) transmissive_unbounded_ = true;
            if (pg->own_lo.x <= pg->own_hi.x) add_box_corners(m, pg->own_lo, pg->own_hi, lo, hi);
            if (trans && pg->inherit_lo.x <= pg->inherit_hi.x)
                add_box_corners(m, pg->inherit_lo, pg->inherit_hi, lo, hi);
        } else if (sh.kind == ShapeKind::Csg && sh.csg) {
            Vec3 clo, chi;
            if (!trans) continue;
            if (csg_local_bounds(spec, *sh.csg, clo, chi))
                add_box_corners(m, clo, chi, lo, hi);
            else
                transmissive_unbounded_ = true;
        } else if (trans && !shape_box(sh, m, lo, hi)) {
            transmissive_unbounded_ = true;
        }
        if (transmissive_unbounded_ || !(lo.x <= hi.x)) continue;
        // Pad by a relative margin far above the rounding of the shapes' own intersection code,
        // so the culling box is conservative (it only decides whether to look, never the result).
        const Vec3 pad = (glm::abs(lo) + glm::abs(hi) + (hi - lo)) * 1e-7;
        transmissive_bounds_.push_back({lo - pad, hi + pad});
    }
    auto& boxes = transmissive_bounds_;
    if (boxes.size() > kMaxBoxes) {
        Bounds all = boxes.front();
        for (const auto& b : boxes) {
            all.lo = glm::min(all.lo, b.lo);
            all.hi = glm::max(all.hi, b.hi);
        }
        boxes.assign(1, all);
    }
}

std::shared_ptr<const Scene> build_scene(const SceneSpec& spec, std::vector<SpecError>& errors, bool use_bvh,
                                         int threads, ImageCache* images, const std::atomic<bool>* cancel) {
    const auto start = std::chrono::steady_clock::now();
    const size_t errors_before = errors.size();
    auto scene = std::shared_ptr<Scene>(new Scene());

    const bool settings_ok = check_settings(spec.settings, errors);
    scene->settings_ = spec.settings;

    // The camera's frame needs the image size: only once the settings are valid.
    if (check_fields(element_table(Element::Camera), spec.camera, SpecItem::Camera, 0, spec.camera.tag,
                     errors) &&
        settings_ok) {
        std::string message;
        if (auto cam = Camera::create(spec.camera, spec.settings.width, spec.settings.height, message))
            scene->camera_ = *cam;
        else
            errors.push_back({SpecItem::Camera, 0, spec.camera.tag, message, -1});
    }

    for (size_t i = 0; i < spec.lights.size(); ++i) {
        const LightSpec& l = spec.lights[i];
        if (!check_light(l, i, errors)) continue;
        scene->lights_.push_back(prepare_light(l));
        if (l.kind == LightKind::Area && l.samples_u * l.samples_v > 1) scene->multi_cell_area_light_ = true;
    }

    ImageCache own_cache;
    ImageCache& cache = images ? *images : own_cache;
    bool materials_ok = true;
    for (size_t i = 0; i < spec.materials.size(); ++i) {
        const MaterialSpec& ms = spec.materials[i];
        Material m;
        if (!check_material(ms, i, errors)) materials_ok = false;
        if (ms.texture && !check_texture(*ms.texture, i, errors)) {
            materials_ok = false;
        } else if (ms.texture) {
            std::string err;
            m.texture = Texture::create(*ms.texture, cache, err);
            if (!m.texture) {
                errors.push_back({SpecItem::Texture, i, ms.texture->tag, err, -1});
                materials_ok = false;
            }
        }
        if (ms.bump && !check_texture(*ms.bump, i, errors)) {
            materials_ok = false;
        } else if (ms.bump && ms.bump_strength > 0) {
            std::string err;
            m.bump = Texture::create(*ms.bump, cache, err);
            if (!m.bump) {
                errors.push_back({SpecItem::Texture, i, ms.bump->tag, err, -1});
                materials_ok = false;
            }
        }
        m.color = ms.color;
        m.bump_strength = ms.bump_strength;
        // Indirect light replaces the ambient term.
        m.ambient = spec.settings.indirect_samples > 0 ? 0.0 : ms.ambient.value_or(spec.settings.ambient);
        m.diffuse = ms.diffuse;
        m.specular = ms.specular;
        m.shininess = ms.shininess;
        m.reflection = ms.reflection;
        m.transmission = ms.transmission;
        m.ior = ms.ior;
        m.absorption = ms.absorption;
        m.absorbs = ms.transmission > 0 && ms.absorption != Color(0);
        m.emission = ms.emission;
        m.emits = ms.emission != Color(0);
        scene->materials_.push_back(std::move(m));
    }

    bool shapes_ok = true;
    for (size_t i = 0; i < spec.shapes.size(); ++i) {
        const bool instance_without =
            spec.shapes[i].kind == ShapeKind::Instance && spec.shapes[i].material == kInheritMaterial;
        if (spec.shapes[i].material >= spec.materials.size() && !instance_without) {
            errors.push_back({SpecItem::Shape, i, spec.shapes[i].tag, "material index out of range", -1});
            shapes_ok = false;
        } else if (!check_shape(spec.shapes[i], i, errors)) {
            shapes_ok = false;
        }
        scene->object_to_world_.push_back(spec.shapes[i].object_to_world);
    }
    // An instanced object's members, checked once, at its first instance (their own tags).
    std::vector<uint8_t> checked(spec.prototypes.size(), 0);
    for (size_t i = 0; i < spec.shapes.size(); ++i) {
        const ShapeSpec& sh = spec.shapes[i];
        if (sh.kind != ShapeKind::Instance || sh.prototype >= checked.size() || checked[sh.prototype])
            continue;
        checked[sh.prototype] = 1;
        for (const ShapeSpec& m : spec.prototypes[sh.prototype].shapes) {
            if (m.material != kInheritMaterial && m.material >= spec.materials.size()) {
                errors.push_back({SpecItem::Shape, i, m.tag, "material index out of range", -1});
                shapes_ok = false;
            } else if (!check_shape(m, i, errors)) {
                shapes_ok = false;
            }
        }
    }
    if (shapes_ok) scene->geometry_ = Geometry::build(spec, errors, use_bvh, threads);
    if (errors.size() != errors_before || !scene->geometry_ || !materials_ok) return nullptr;
    if (spec.settings.indirect_samples > 0) {
        scene->emitters_ = Emitters::build(spec, errors);
        if (errors.size() != errors_before) return nullptr;
    }

    scene->effects_ = analyse_effects(spec);
    scene->compute_transmissive_bounds(spec);
    if (spec.settings.caustic_photons > 0) {
        scene->caustics_ = build_caustics(*scene, spec, threads, cancel);
        if (scene->caustics_.cancelled) return nullptr;
    }
    scene->build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return scene;
}

}  // namespace wsd::render
