// Instancing benchmark: a closed 1,000,000-triangle UV sphere, rendered at 1024×768 (one ray a
// pixel, one point light, two threads) as
//   single    the mesh itself;
//   instance  one instance of it (the same image, bit for bit): the cost of testing triangles
//             with world vertices computed on the fly, beside the stored ones;
//   grid      1,000 instances (10×10×10, each turned and scaled), which written out flat would
//             hold 10^9 triangles (about 80 GiB).
// Prints the build and render times, the geometry's bytes and the process's peak resident
// memory (getrusage ru_maxrss), and for single/instance the closest-hit rays per CPU-second on
// one thread (the median of 5 passes). Run each mode in its own process (peak memory is per
// process). Usage: bench_instances single|instance|grid [slices stacks] (default 1000 501).
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <glm/gtc/matrix_transform.hpp>
#include <memory>
#include <string>
#include <vector>

#include "bench/uv_sphere.h"
#include "render/geometry.h"
#include "render/math.h"
#include "render/renderer.h"
#include "render/scene.h"

using namespace wsd::render;

namespace {

double cpu_now() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

using wsd::bench::uv_sphere;

SceneSpec make_scene(const std::string& mode, std::shared_ptr<MeshData> mesh) {
    SceneSpec spec;
    spec.settings.width = 1024;
    spec.settings.height = 768;
    MaterialSpec m;
    m.color = {0.8, 0.7, 0.6};
    spec.materials.push_back(m);
    ShapeSpec shape;
    shape.kind = ShapeKind::Mesh;
    shape.mesh = std::move(mesh);
    if (mode == "grid") {
        spec.camera.position = {-14, 12, -30};
        spec.camera.look_at = {13.5, 13.5, 13.5};
        spec.lights.push_back({LightKind::Point, {-20, 60, -40}});
        PrototypeSpec p;
        p.shapes.push_back(shape);
        spec.prototypes.push_back(p);
        for (int i = 0; i < 1000; ++i) {
            ShapeSpec s;
            s.kind = ShapeKind::Instance;
            const Vec3 at(3 * (i % 10), 3 * (i / 10 % 10), 3 * (i / 100));
            s.object_to_world = glm::translate(Mat4(1.0), at) *
                                glm::rotate(Mat4(1.0), 0.1 * i, glm::normalize(Vec3(1, 2, 3))) *
                                glm::scale(Mat4(1.0), Vec3(0.8 + 0.0004 * i));
            spec.shapes.push_back(s);
        }
        return spec;
    }
    spec.camera.position = {0, 0.3, -3};
    spec.camera.look_at = {0, 0, 0};
    spec.lights.push_back({LightKind::Point, {-3, 5, -4}});
    if (mode == "instance") {
        PrototypeSpec p;
        p.shapes.push_back(shape);
        spec.prototypes.push_back(p);
        ShapeSpec s;
        s.kind = ShapeKind::Instance;
        spec.shapes.push_back(s);
    } else {
        spec.shapes.push_back(shape);
    }
    return spec;
}

// Closest-hit rays per CPU-second on this thread: 512×384 camera rays, median of 5 passes.
double primary_rate(const Scene& scene) {
    const Geometry& g = scene.geometry();
    const Vec3 eye(0, 0.3, -3), fwd = glm::normalize(-eye);
    const Vec3 right = glm::normalize(glm::cross(Vec3(0, 1, 0), fwd)), up = glm::cross(fwd, right);
    std::vector<Ray> rays;
    for (int y = 0; y < 384; ++y)
        for (int x = 0; x < 512; ++x)
            rays.push_back({eye, fwd + (x / 256.0 - 1) * 0.5 * right + (1 - y / 192.0) * 0.375 * up});
    std::vector<double> rates;
    RayStats stats;
    for (int pass = 0; pass < 5; ++pass) {
        const double t0 = cpu_now();
        size_t hits = 0;
        for (const Ray& r : rays)
            hits += g.intersect(r, std::numeric_limits<double>::infinity(), stats) ? 1 : 0;
        rates.push_back(static_cast<double>(rays.size()) / (cpu_now() - t0));
        if (hits == 0) std::printf("no hits\n");
    }
    std::sort(rates.begin(), rates.end());
    const double n = 5.0 * static_cast<double>(rays.size());
    std::printf("  per ray: %.1f box tests, %.1f triangle tests\n", static_cast<double>(stats.box_tests) / n,
                static_cast<double>(stats.triangle_tests) / n);
    return rates[2];
}

}  // namespace

int main(int argc, char** argv) {
    const std::string mode = argc > 1 ? argv[1] : "single";
    if (mode != "single" && mode != "instance" && mode != "grid") {
        std::fprintf(stderr, "usage: bench_instances single|instance|grid [slices stacks]\n");
        return 2;
    }
    const int slices = argc > 3 ? std::atoi(argv[2]) : 1000, stacks = argc > 3 ? std::atoi(argv[3]) : 501;
    const SceneSpec spec = make_scene(mode, uv_sphere(slices, stacks, 1.0f));
    std::vector<SpecError> errors;
    const auto t0 = std::chrono::steady_clock::now();
    const auto scene = build_scene(spec, errors, true, 2);
    const auto t1 = std::chrono::steady_clock::now();
    if (!scene) {
        for (const SpecError& e : errors) std::fprintf(stderr, "%s\n", e.message.c_str());
        return 1;
    }
    RenderOptions options;
    options.threads = 2;
    const RenderResult r = render(*scene, options);
    const Geometry& g = scene->geometry();
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    std::printf("%s: %zu instances, %zu stored triangles, %zu rendered primitives\n", mode.c_str(),
                g.instance_count(), g.triangle_count(), g.instanced_primitive_count());
    std::printf("  build %.2f s, render %.2f s (1024x768, 2 threads), geometry %.1f MiB, peak RSS %.1f MiB\n",
                std::chrono::duration<double>(t1 - t0).count(), r.render_seconds,
                static_cast<double>(g.memory_bytes()) / (1 << 20), static_cast<double>(ru.ru_maxrss) / 1024);
    if (mode != "grid") std::printf("  closest hits: %.3g rays per CPU-second\n", primary_rate(*scene));
    return 0;
}
