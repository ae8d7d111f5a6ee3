// CSG benchmark: closest-hit rays per CPU-second on one thread against one solid filling the view
// (the same screen area as the sphere it is compared with): a sphere; a lens (the intersection of
// two spheres); a box minus a sphere; a union of three spheres; a closed 20,000-triangle mesh
// minus a sphere. Rays come from a 512 × 512 orthographic grid over the solid's silhouette box.
// Then the scenes of bench/scenes/{csg_intersection, csg_difference}.wsd beside the same grid of
// spheres, built by hand (a 10×10 grid of one solid on a plane, one point light's shadows):
// CPU time of the process (one render thread) per camera or shadow ray, at 400×400.
// Each number is the median of 5 passes taken in turn with the others. Prints measured numbers only.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bench/uv_sphere.h"
#include "render/geometry.h"
#include "render/math.h"
#include "render/renderer.h"

using namespace wsd::render;

namespace {

double process_cpu_now() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double cpu_now() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

ShapeSpec sphere(Vec3 c, double r) {
    ShapeSpec s;
    s.kind = ShapeKind::Sphere;
    s.center = c;
    s.radius = r;
    return s;
}

ShapeSpec box(Vec3 lo, Vec3 hi) {
    ShapeSpec s;
    s.kind = ShapeKind::Box;
    s.box_min = lo;
    s.box_max = hi;
    return s;
}

ShapeSpec csg(CsgOp op, std::vector<ShapeSpec> members) {
    auto c = std::make_shared<CsgSpec>();
    c->op = op;
    for (auto& m : members) m.material = kInheritMaterial;
    c->members = std::move(members);
    ShapeSpec s;
    s.kind = ShapeKind::Csg;
    s.csg = c;
    return s;
}

// Closed UV sphere of 2·slices·(stacks − 1) triangles, as a mesh shape.
ShapeSpec uv_sphere(int slices, int stacks, float radius) {
    ShapeSpec s;
    s.kind = ShapeKind::Mesh;
    s.mesh = wsd::bench::uv_sphere(slices, stacks, radius);
    return s;
}

struct Case {
    std::string name;
    std::unique_ptr<Geometry> geom;
    double best[5] = {};
    size_t hits = 0;
};

std::unique_ptr<Geometry> make(ShapeSpec s) {
    SceneSpec spec;
    spec.materials.emplace_back();
    s.material = 0;
    spec.shapes.push_back(std::move(s));
    std::vector<SpecError> errors;
    auto g = Geometry::build(spec, errors, true, 1);
    if (!g) {
        for (const auto& e : errors) std::fprintf(stderr, "%s\n", e.message.c_str());
        std::exit(1);
    }
    return g;
}

// The 10×10 grid of bench/scenes/sphere.wsd with each cell made by `cell(x, y)`.
SceneSpec grid_scene(const std::function<ShapeSpec(double, double)>& cell) {
    SceneSpec spec;
    spec.settings.width = spec.settings.height = 400;
    spec.camera.position = {0, 0, -14};
    spec.camera.look_at = {0, 0, 0};
    spec.camera.fov_degrees = 45;
    LightSpec light;
    light.position = {-6, 8, -12};
    spec.lights.push_back(light);
    MaterialSpec m;
    m.color = {0.8, 0.7, 0.6};
    m.specular = 0.3;
    spec.materials.push_back(m);
    m.color = {0.9, 0.9, 0.9};
    m.specular = 0;
    spec.materials.push_back(m);
    ShapeSpec floor;
    floor.kind = ShapeKind::Plane;
    floor.normal = {0, 0, -1};
    floor.distance = -1;
    floor.material = 1;
    spec.shapes.push_back(floor);
    for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 10; ++j) {
            ShapeSpec s = cell(i - 4.5, j - 4.5);
            s.material = 0;
            spec.shapes.push_back(s);
        }
    return spec;
}

void render_scenes() {
    struct Scn {
        std::string name;
        std::shared_ptr<const Scene> scene;
        double per_ray[5] = {};
    };
    std::vector<Scn> scenes;
    auto add = [&](std::string name, const SceneSpec& spec) {
        std::vector<SpecError> errors;
        auto sc = build_scene(spec, errors, true, 1);
        if (!sc) std::exit(1);
        scenes.push_back({std::move(name), sc});
    };
    add("spheres (sphere.wsd)", grid_scene([](double x, double y) { return sphere({x, y, 0}, 0.45); }));
    add("lenses (csg_intersection.wsd)", grid_scene([](double x, double y) {
            return csg(CsgOp::Intersection, {sphere({x, y, -0.15}, 0.45), sphere({x, y, 0.15}, 0.45)});
        }));
    add("dented boxes (csg_difference.wsd)", grid_scene([](double x, double y) {
            return csg(CsgOp::Difference,
                       {box({x - 0.4, y - 0.4, -0.4}, {x + 0.4, y + 0.4, 0.4}), sphere({x, y, -0.45}, 0.3)});
        }));
    RenderOptions opt;
    opt.threads = 1;
    for (int pass = 0; pass < 5; ++pass)
        for (Scn& s : scenes) {
            const double t0 = process_cpu_now();
            const RenderResult r = render(*s.scene, opt);
            const double rays = static_cast<double>(r.stats.camera_rays + r.stats.shadow_rays);
            s.per_ray[pass] = (process_cpu_now() - t0) / rays;
        }
    std::printf("400×400 renders, one thread, CPU time per camera or shadow ray (median of 5):\n");
    std::sort(scenes[0].per_ray, scenes[0].per_ray + 5);
    const double base = scenes[0].per_ray[2];
    for (Scn& s : scenes) {
        std::sort(s.per_ray, s.per_ray + 5);
        std::printf("  %-36s %6.1f ns/ray  %5.2f× the spheres'\n", s.name.c_str(), 1e9 * s.per_ray[2],
                    s.per_ray[2] / base);
    }
}

}  // namespace

int main() {
    std::vector<Case> cases;
    auto add = [&](std::string name, ShapeSpec s) { cases.push_back({std::move(name), make(std::move(s))}); };
    add("sphere", sphere({0, 0, 0}, 1));
    add("lens: intersection of 2 spheres",
        csg(CsgOp::Intersection, {sphere({0, 0, -0.6}, 1.2), sphere({0, 0, 0.6}, 1.2)}));
    add("box minus sphere",
        csg(CsgOp::Difference, {box({-0.8, -0.8, -0.8}, {0.8, 0.8, 0.8}), sphere({0, 0, -0.8}, 0.6)}));
    add("union of 3 spheres",
        csg(CsgOp::Union, {sphere({-0.4, 0, 0}, 0.6), sphere({0.4, 0, 0}, 0.6), sphere({0, 0.4, 0}, 0.6)}));
    add("20,000-triangle mesh minus sphere",
        csg(CsgOp::Difference, {uv_sphere(100, 101, 1), sphere({0, 0, -1}, 0.5)}));
    const int n = 512;
    std::vector<Ray> rays;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            rays.push_back({{-1 + (i + 0.5) * 2.0 / n, -1 + (j + 0.5) * 2.0 / n, -5}, {0.01, 0.02, 1}});
    for (int pass = 0; pass < 5; ++pass)
        for (Case& c : cases) {
            RayStats stats;
            size_t hits = 0;
            const double t0 = cpu_now();
            for (const Ray& r : rays) hits += c.geom->intersect(r, 1e30, stats) ? 1 : 0;
            c.best[pass] = static_cast<double>(rays.size()) / (cpu_now() - t0);
            c.hits = hits;
        }
    std::printf("closest-hit rays per CPU-second, one thread, %d rays a pass (median of 5):\n", n * n);
    const double base = [&] {
        std::vector<double> v(cases[0].best, cases[0].best + 5);
        std::sort(v.begin(), v.end());
        return v[2];
    }();
    for (Case& c : cases) {
        std::sort(c.best, c.best + 5);
        std::printf("  %-36s %8.2f Mrays/s  %6.1f ns/ray  %5.2f× the sphere's time  (%zu hits)\n",
                    c.name.c_str(), c.best[2] / 1e6, 1e9 / c.best[2], base / c.best[2], c.hits);
    }
    render_scenes();
    return 0;
}
