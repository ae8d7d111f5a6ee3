// Geometry benchmark: a closed 1,000,000-triangle UV sphere. Measures the Geometry build on 1
// and 2 threads, bytes per triangle, primary (closest-hit) and shadow (any-hit) rays per
// CPU-second on one thread (primary rays one by one, and as packets of 2×2 and 4×4 pixels; the
// renderer traces one-ray-a-pixel images in 4×4 blocks), and the same queries on the Cornell
// box's 28 primitives.
// Prints measured numbers only. Usage: bench_mesh [slices stacks] (default 1000 501).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <optional>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "render/geometry.h"
#include "render/math.h"

using namespace wsd::render;

namespace {

double cpu_now() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double wall_now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Closed UV sphere: 2·slices·(stacks−1) triangles sharing 2 + slices·(stacks−1) vertices.
std::shared_ptr<MeshData> uv_sphere(int slices, int stacks, float radius) {
    auto m = std::make_shared<MeshData>();
    m->vertices.push_back({0, radius, 0});
    for (int i = 1; i < stacks; ++i) {
        double theta = kPi * i / stacks;
        for (int j = 0; j < slices; ++j) {
            double phi = 2 * kPi * j / slices;
            m->vertices.push_back({static_cast<float>(radius * std::sin(theta) * std::cos(phi)),
                                   static_cast<float>(radius * std::cos(theta)),
                                   static_cast<float>(radius * std::sin(theta) * std::sin(phi))});
        }
    }
    m->vertices.push_back({0, -radius, 0});
    auto ring = [slices](int i, int j) { return static_cast<unsigned>(1 + (i - 1) * slices + (j % slices)); };
    const unsigned bottom = static_cast<unsigned>(m->vertices.size() - 1);
    for (int j = 0; j < slices; ++j) m->faces.push_back({0u, ring(1, j + 1), ring(1, j)});
    for (int i = 1; i < stacks - 1; ++i)
        for (int j = 0; j < slices; ++j) {
            m->faces.push_back({ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)});
            m->faces.push_back({ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)});
        }
    for (int j = 0; j < slices; ++j) m->faces.push_back({bottom, ring(stacks - 1, j), ring(stacks - 1, j + 1)});
    return m;
}

struct Throughput {
    double primary = 0, shadow = 0;  // rays per CPU-second
    double packets4 = 0, packets16 = 0;  // primary rays per CPU-second in 2×2 and 4×4-pixel packets
    double boxes_primary = 0, prims_primary = 0;  // tests per primary ray
    double hit_fraction = 0, occluded_fraction = 0;
};

// A size×size pinhole camera at `eye` looking at `target`; shadow rays from every hit to `light`.
Throughput measure(const Geometry& g, Vec3 eye, Vec3 target, double fov_deg, Vec3 light, int size) {
    Vec3 fwd = glm::normalize(target - eye);
    Vec3 right = glm::normalize(glm::cross(Vec3(0, 1, 0), fwd));
    Vec3 up = glm::cross(fwd, right);
    double h = std::tan(fov_deg * kPi / 360);
    std::vector<Ray> rays;
    rays.reserve(static_cast<size_t>(size) * size);
    // In 16×16 tiles, the order the renderer traces pixels in.
    for (int ty = 0; ty < size; ty += 16)
        for (int tx = 0; tx < size; tx += 16)
            for (int y = ty; y < std::min(ty + 16, size); ++y)
                for (int x = tx; x < std::min(tx + 16, size); ++x) {
                    double sx = (2 * (x + 0.5) / size - 1) * h, sy = (1 - 2 * (y + 0.5) / size) * h;
                    rays.push_back({eye, fwd + sx * right + sy * up});
                }
    // The same rays in square blocks of side×side pixels, one packet each (the renderer traces
    // one-ray-a-pixel images in 4×4 blocks).
    auto camera = [&](int x, int y) {
        double sx = (2 * (x + 0.5) / size - 1) * h, sy = (1 - 2 * (y + 0.5) / size) * h;
        return Ray{eye, fwd + sx * right + sy * up};
    };
    auto blocks = [&](int side) {
        std::vector<Ray> out;
        out.reserve(rays.size());
        for (int ty = 0; ty < size; ty += 16)
            for (int tx = 0; tx < size; tx += 16)
                for (int y = ty; y < std::min(ty + 16, size); y += side)
                    for (int x = tx; x < std::min(tx + 16, size); x += side)
                        for (int k = 0; k < side * side; ++k) out.push_back(camera(x + k % side, y + k / side));
        return out;
    };
    RayStats stats;
    std::vector<Ray> shadow;
    shadow.reserve(rays.size());
    size_t hits = 0;
    double t0 = cpu_now();
    for (const Ray& r : rays) {
        auto hit = g.intersect(r, std::numeric_limits<double>::infinity(), stats);
        hits += hit ? 1 : 0;
    }
    double t1 = cpu_now();
    const RayStats primary_stats = stats;
    // Primary rays as packets: rays per CPU-second; the hits must be the single-ray hits.
    auto packets = [&](int side) {
        const std::vector<Ray> packed = blocks(side);
        const int n = side * side;
        size_t packet_hits = 0;
        RayStats packet_stats;
        std::optional<HitRecord> out[Geometry::kMaxPacket];
        const double p0 = cpu_now();
        for (size_t i = 0; i + size_t(n) <= packed.size(); i += size_t(n)) {
            g.intersect_packet(&packed[i], n, std::numeric_limits<double>::infinity(), packet_stats, out);
            for (int k = 0; k < n; ++k) packet_hits += out[k] ? 1 : 0;
        }
        const double p1 = cpu_now();
        if (packet_hits != hits) std::printf("packet hits %zu differ from single-ray hits %zu\n", packet_hits, hits);
        return static_cast<double>(packed.size()) / (p1 - p0);
    };
    const double packets4 = packets(2), packets16 = packets(4);
    for (const Ray& r : rays) {
        auto hit = g.intersect(r, std::numeric_limits<double>::infinity(), stats);
        if (!hit) continue;
        SurfaceHit s = g.surface(r, *hit);
        Vec3 w = light - s.p;
        Vec3 o = Geometry::offset_origin(s, w);
        shadow.push_back({o, light - o});
    }
    size_t occluded = 0;
    double t2 = cpu_now();
    for (const Ray& r : shadow) occluded += g.occluded(r, 1.0, stats) ? 1 : 0;
    double t3 = cpu_now();
    Throughput out;
    out.primary = static_cast<double>(rays.size()) / (t1 - t0);
    out.packets4 = packets4;
    out.packets16 = packets16;
    out.shadow = shadow.empty() ? 0 : static_cast<double>(shadow.size()) / (t3 - t2);
    const double n_rays = static_cast<double>(rays.size());
    out.boxes_primary = static_cast<double>(primary_stats.box_tests) / n_rays;
    out.prims_primary = static_cast<double>(primary_stats.triangle_tests + primary_stats.sphere_tests +
                                            primary_stats.shape_box_tests) / n_rays;
    out.hit_fraction = static_cast<double>(hits) / static_cast<double>(rays.size());
    out.occluded_fraction = shadow.empty() ? 0 : static_cast<double>(occluded) / static_cast<double>(shadow.size());
    return out;
}

SceneSpec cornell_geometry() {
    SceneSpec spec;
    spec.materials.resize(2);
    spec.materials[1].transmission = 1;
    auto sphere = [&](Vec3 c, double r, uint32_t mat) {
        ShapeSpec s;
        s.kind = ShapeKind::Sphere;
        s.center = c;
        s.radius = r;
        s.material = mat;
        spec.shapes.push_back(s);
    };
    sphere({200, 0, 880}, 200, 0);
    sphere({-300, 200, 800}, 100, 0);
    sphere({-80, -180, 130}, 70, 1);
    sphere({500, -500, 550}, 100, 0);
    sphere({350, -550, 550}, 50, 0);
    sphere({-350, -500, 600}, 100, 0);
    auto quad = [&](Vec3 ll, Vec3 u, Vec3 v) {
        ShapeSpec s;
        s.kind = ShapeKind::Triangle;
        s.v[0] = ll, s.v[1] = ll + u, s.v[2] = ll + u + v;
        spec.shapes.push_back(s);
        s.v[0] = ll, s.v[1] = ll + u + v, s.v[2] = ll + v;
        spec.shapes.push_back(s);
    };
    quad({-600, -600, 0}, {1200, 0, 0}, {0, 0, 1200});
    quad({-600, -600, 0}, {0, 0, 1200}, {0, 1200, 0});
    quad({600, -600, 1200}, {0, 0, -1200}, {0, 1200, 0});
    quad({-600, -600, 1200}, {1200, 0, 0}, {0, 1200, 0});
    quad({-600, 600, 1200}, {1200, 0, 0}, {0, 0, -1200});
    ShapeSpec box;
    box.kind = ShapeKind::Box;
    box.box_min = Vec3(-125);
    box.box_max = Vec3(125);
    Mat4 m(1.0);
    m = glm::translate(Mat4(1.0), Vec3(-400, -350, 990)) *
        glm::rotate(Mat4(1.0), 35.264 * kPi / 180, Vec3(1, 0, 0)) *
        glm::rotate(Mat4(1.0), 45 * kPi / 180, Vec3(0, 0, 1));
    box.object_to_world = m;
    spec.shapes.push_back(box);
    return spec;
}

}  // namespace

int main(int argc, char** argv) {
    int slices = argc > 2 ? std::atoi(argv[1]) : 1000;
    int stacks = argc > 2 ? std::atoi(argv[2]) : 501;
    SceneSpec spec;
    spec.materials.resize(1);
    ShapeSpec mesh;
    mesh.kind = ShapeKind::Mesh;
    mesh.mesh = uv_sphere(slices, stacks, 1.0f);
    spec.shapes.push_back(mesh);
    std::printf("mesh: %zu triangles, %zu vertices\n", mesh.mesh->faces.size(), mesh.mesh->vertices.size());

    std::unique_ptr<Geometry> g;
    for (int threads : {1, 2}) {
        std::vector<SpecError> errors;
        double w0 = wall_now();
        g = Geometry::build(spec, errors, true, threads);
        double w1 = wall_now();
        if (!g) {
            std::printf("build failed: %s\n", errors.empty() ? "?" : errors[0].message.c_str());
            return 1;
        }
        std::printf("build (validation + world vertices + BVH), %d thread%s: %.3f s wall\n", threads,
                    threads == 1 ? "" : "s", w1 - w0);
    }
    double bytes = static_cast<double>(g->memory_bytes());
    std::printf("memory: %.1f bytes/triangle (geometry + BVH; the MeshData itself adds %.1f)\n",
                bytes / static_cast<double>(g->triangle_count()),
                static_cast<double>(mesh.mesh->vertices.size() * 12 + mesh.mesh->faces.size() * 12) /
                    static_cast<double>(g->triangle_count()));

    Throughput t = measure(*g, {0.3, 0.4, -3}, {0, 0, 0}, 45, {5, 5, -5}, 1024);
    std::printf("mesh primary rays: %.2f M/CPU-s (%.1f %% hit; %.1f node tests, %.1f triangle tests a ray)\n",
                t.primary * 1e-6, 100 * t.hit_fraction, t.boxes_primary, t.prims_primary);
    std::printf("mesh primary rays in packets: 2x2 pixels %.2f M/CPU-s, 4x4 pixels (the renderer's 1-spp path) %.2f M/CPU-s\n",
                t.packets4 * 1e-6, t.packets16 * 1e-6);
    std::printf("mesh shadow rays:  %.2f M/CPU-s (%.1f %% occluded)\n", t.shadow * 1e-6, 100 * t.occluded_fraction);

    std::vector<SpecError> errors;
    auto cornell = Geometry::build(cornell_geometry(), errors, true, 1);
    auto cornell_bf = Geometry::build(cornell_geometry(), errors, false, 1);
    if (!cornell || !cornell_bf) {
        std::printf("cornell build failed\n");
        return 1;
    }
    for (auto* cg : {cornell.get(), cornell_bf.get()}) {
        Throughput c = measure(*cg, {0, 0, -550}, {0, 0, 500}, 60, {25, 500, 625}, 512);
        std::printf("cornell %s: primary %.2f M/CPU-s (packets of 4: %.2f, of 16: %.2f), shadow %.2f M/CPU-s (%.1f %% occluded)\n",
                    cg == cornell.get() ? "BVH  " : "brute", c.primary * 1e-6, c.packets4 * 1e-6, c.packets16 * 1e-6,
                    c.shadow * 1e-6, 100 * c.occluded_fraction);
    }
    return 0;
}
