// build_scene: validates the parts of a SceneSpec the renderer relies on (settings, camera,
// lights, materials), builds the geometry and every texture (one ImageCache, so each image file
// is read once), and reports each problem as a SpecError naming the list element and its tag.
#include "render/scene.h"

#include <chrono>
#include <cmath>
#include <limits>

#include "render/math.h"

namespace wsd::render {

namespace {

bool non_negative3(const Vec3& v) {
    return finite3(v) && v.x >= 0 && v.y >= 0 && v.z >= 0;
}

void check_settings(const Settings& s, std::vector<SpecError>& errors) {
    auto fail = [&errors](const char* msg) { errors.push_back({SpecItem::Settings, 0, 0, msg, -1}); };
    if (s.width < 1 || s.width > 100000 || s.height < 1 || s.height > 100000)
        fail("width and height must be between 1 and 100000");
    else if (long(s.width) * long(s.height) > (1L << 28))
        fail("width × height must be at most 2^28 pixels");
    if (s.supersamples < 1 || s.supersamples > 4096) fail("supersamples must be between 1 and 4096");
    if (!(s.aa_threshold >= 0) || !std::isfinite(s.aa_threshold))
        fail("aa_threshold must be a finite number >= 0");
    if (!(s.bailout >= 0 && s.bailout < 1)) fail("bailout must be in [0, 1)");
    if (s.max_depth < 0 || s.max_depth > 256) fail("max_depth must be between 0 and 256");
    if (!(s.ambient >= 0) || !std::isfinite(s.ambient)) fail("ambient must be a finite number >= 0");
    if (!finite3(s.background)) fail("background must be finite");
}

std::optional<std::string> check_material(const MaterialSpec& m) {
    if (!non_negative3(m.color)) return "material color must be finite and non-negative";
    if (m.ambient && !(*m.ambient >= 0 && std::isfinite(*m.ambient)))
        return "material ambient must be a finite number >= 0";
    if (!(m.diffuse >= 0) || !std::isfinite(m.diffuse)) return "diffuse must be a finite number >= 0";
    if (!(m.specular >= 0) || !std::isfinite(m.specular)) return "specular must be a finite number >= 0";
    if (!(m.shininess > 0) || !std::isfinite(m.shininess)) return "shininess must be a finite number > 0";
    if (!(m.reflection >= 0 && m.reflection <= 1)) return "reflection must be in [0, 1]";
    if (!(m.transmission >= 0 && m.transmission <= 1)) return "transmission must be in [0, 1]";
    // Rounding slack for sums like 0.7 + 0.3 written by the user (a validation tolerance).
    if (m.reflection + m.transmission > 1 + 1e-12) return "reflection + transmission must not exceed 1";
    if (!(m.ior > 0) || !std::isfinite(m.ior)) return "ior must be a finite number > 0";
    if (!non_negative3(m.absorption)) return "absorption must be finite and non-negative";
    if (!(m.bump_strength >= 0) || !std::isfinite(m.bump_strength))
        return "bump_strength must be a finite number >= 0";
    return std::nullopt;
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
    for (const Bounds& box : transmissive_bounds_) {
        double t0 = 0, t1 = 1;
        bool hit = true;
        for (int i = 0; i < 3 && hit; ++i) {
            if (d[i] == 0) {
                hit = a[i] >= box.lo[i] && a[i] <= box.hi[i];
                continue;
            }
            const double inv = 1.0 / d[i];
            double n = (box.lo[i] - a[i]) * inv, f = (box.hi[i] - a[i]) * inv;
            if (n > f) std::swap(n, f);
            t0 = n > t0 ? n : t0;
            t1 = f < t1 ? f : t1;
            hit = t0 <= t1;
        }
        if (hit) return true;
    }
    return false;
}

void Scene::compute_transmissive_bounds(const SceneSpec& spec) {
    constexpr size_t kMaxBoxes = 16;  // beyond this, one union box (the test is linear)
    for (const ShapeSpec& sh : spec.shapes) {
        if (!(spec.materials[sh.material].transmission > 0)) continue;
        Vec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
        const Mat4& m = sh.object_to_world;
        switch (sh.kind) {
            case ShapeKind::Sphere:
                add_box_corners(m, sh.center - Vec3(sh.radius), sh.center + Vec3(sh.radius), lo, hi);
                break;
            case ShapeKind::Box:
                add_box_corners(m, sh.box_min, sh.box_max, lo, hi);
                break;
            case ShapeKind::Triangle:
                for (const Vec3& v : sh.v) add_box_corners(m, v, v, lo, hi);
                break;
            case ShapeKind::Mesh: {
                Vec3 mlo(std::numeric_limits<double>::infinity()),
                    mhi(-std::numeric_limits<double>::infinity());
                for (const glm::vec3& v : sh.mesh->vertices) {
                    mlo = glm::min(mlo, Vec3(v));
                    mhi = glm::max(mhi, Vec3(v));
                }
                if (!sh.mesh->vertices.empty()) add_box_corners(m, mlo, mhi, lo, hi);
                break;
            }
            case ShapeKind::Plane:
                transmissive_unbounded_ = true;
                break;
        }
        if (sh.kind == ShapeKind::Plane || !(lo.x <= hi.x)) continue;
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
                                         int threads) {
    const auto start = std::chrono::steady_clock::now();
    const size_t errors_before = errors.size();
    auto scene = std::shared_ptr<Scene>(new Scene());

    check_settings(spec.settings, errors);
    scene->settings_ = spec.settings;

    std::string message;
    if (auto cam = Camera::create(spec.camera, spec.settings.width, spec.settings.height, message))
        scene->camera_ = *cam;
    else
        errors.push_back({SpecItem::Camera, 0, spec.camera.tag, message, -1});

    for (size_t i = 0; i < spec.lights.size(); ++i) {
        const LightSpec& l = spec.lights[i];
        if (auto err = validate_light(l)) {
            errors.push_back({SpecItem::Light, i, l.tag, *err, -1});
            continue;
        }
        scene->lights_.push_back(prepare_light(l));
        if (l.kind == LightKind::Area && l.samples_u * l.samples_v > 1) scene->multi_cell_area_light_ = true;
    }

    ImageCache cache;
    bool materials_ok = true;
    for (size_t i = 0; i < spec.materials.size(); ++i) {
        const MaterialSpec& ms = spec.materials[i];
        Material m;
        if (auto err = check_material(ms)) {
            errors.push_back({SpecItem::Material, i, ms.tag, *err, -1});
            materials_ok = false;
        }
        if (ms.texture) {
            std::string err;
            m.texture = Texture::create(*ms.texture, cache, err);
            if (!m.texture) {
                errors.push_back({SpecItem::Texture, i, ms.texture->tag, err, -1});
                materials_ok = false;
            }
        }
        if (ms.bump && ms.bump_strength > 0) {
            std::string err;
            m.bump = Texture::create(*ms.bump, cache, err);
            if (!m.bump) {
                errors.push_back({SpecItem::Texture, i, ms.bump->tag, err, -1});
                materials_ok = false;
            }
        }
        m.color = ms.color;
        m.bump_strength = ms.bump_strength;
        m.ambient = ms.ambient.value_or(spec.settings.ambient);
        m.diffuse = ms.diffuse;
        m.specular = ms.specular;
        m.shininess = ms.shininess;
        m.reflection = ms.reflection;
        m.transmission = ms.transmission;
        m.ior = ms.ior;
        m.absorption = ms.absorption;
        m.absorbs = ms.transmission > 0 && ms.absorption != Color(0);
        scene->materials_.push_back(std::move(m));
    }

    bool shapes_ok = true;
    for (size_t i = 0; i < spec.shapes.size(); ++i) {
        if (spec.shapes[i].material >= spec.materials.size()) {
            errors.push_back({SpecItem::Shape, i, spec.shapes[i].tag, "material index out of range", -1});
            shapes_ok = false;
        }
        scene->object_to_world_.push_back(spec.shapes[i].object_to_world);
    }
    if (shapes_ok) scene->geometry_ = Geometry::build(spec, errors, use_bvh, threads);
    if (errors.size() != errors_before || !scene->geometry_ || !materials_ok) return nullptr;

    scene->effects_ = analyse_effects(spec);
    scene->compute_transmissive_bounds(spec);
    scene->build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return scene;
}

}  // namespace wsd::render
