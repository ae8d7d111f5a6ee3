// Geometry benchmark: a closed 1,000,000-triangle UV sphere. Measures the Geometry build on 1
// and 2 threads (and the 2-thread build's peak memory), bytes per triangle, primary (closest-hit)
// and shadow (any-hit) rays per CPU-second on one thread (primary rays one by one, and as packets
// of 2×2 and 4×4 pixels; the renderer traces one-ray-a-pixel images in 4×4 blocks), and the same
// queries on the Cornell box's 28 primitives.
// Each rate is the median of 5 passes taken in turn with the others. Prints measured numbers
// only. Usage: bench_mesh [slices stacks] (default 1000 501).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <glm/gtc/matrix_transform.hpp>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <memory>
#include <optional>
#include <vector>

#include "app/io_util.h"
#include "bench/cornell_geometry.h"
#include "bench/memory_probe.h"
#include "bench/uv_sphere.h"
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

// Returns the memory the allocator keeps free to the system, so that a build cannot reuse it
// unseen, then resets the peak resident memory; false where the peak cannot be reset.
bool start_peak() {
#if defined(__GLIBC__)
    malloc_trim(0);
#endif
    return wsd::bench::reset_peak_memory();
}

using wsd::bench::cornell_geometry;
using wsd::bench::uv_sphere;

struct Throughput {
    double primary = 0, shadow = 0;      // rays per CPU-second
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
                        for (int k = 0; k < side * side; ++k)
                            out.push_back(camera(x + k % side, y + k / side));
        return out;
    };
    RayStats stats;
    size_t hits = 0;
    for (const Ray& r : rays) hits += g.intersect(r, std::numeric_limits<double>::infinity(), stats) ? 1 : 0;
    const RayStats primary_stats = stats;
    std::vector<Ray> shadow;
    shadow.reserve(rays.size());
    for (const Ray& r : rays) {
        auto hit = g.intersect(r, std::numeric_limits<double>::infinity(), stats);
        if (!hit) continue;
        SurfaceHit s = g.surface(r, *hit);
        Vec3 w = light - s.p;
        Vec3 o = Geometry::offset_origin(s, w);
        shadow.push_back({o, light - o});
    }
    size_t occluded = 0;
    for (const Ray& r : shadow) occluded += g.occluded(r, 1.0, stats) ? 1 : 0;

    // Rays per CPU-second of one pass of each query, the passes taken in turn (so that a noisy
    // moment falls on all of them alike), kPasses rounds, the median kept.
    const std::vector<Ray> packed4 = blocks(2), packed16 = blocks(4);
    auto single = [&] {
        size_t n = 0;
        for (const Ray& r : rays) n += g.intersect(r, std::numeric_limits<double>::infinity(), stats) ? 1 : 0;
        return n;
    };
    auto packets = [&](const std::vector<Ray>& packed, int n) {
        size_t found = 0;
        std::optional<HitRecord> out[Geometry::kMaxPacket];
        for (size_t i = 0; i + size_t(n) <= packed.size(); i += size_t(n)) {
            g.intersect_packet(&packed[i], n, std::numeric_limits<double>::infinity(), stats, out);
            for (int k = 0; k < n; ++k) found += out[k] ? 1 : 0;
        }
        return found;
    };
    auto shadows = [&] {
        size_t n = 0;
        for (const Ray& r : shadow) n += g.occluded(r, 1.0, stats) ? 1 : 0;
        return n;
    };
    constexpr int kPasses = 5;
    std::vector<double> rate[4];
    auto timed = [&](std::vector<double>& into, size_t count, auto&& pass, size_t expect) {
        const double t0 = cpu_now();
        const size_t got = pass();
        const double t1 = cpu_now();
        if (got != expect) std::printf("a pass found %zu hits, the first found %zu\n", got, expect);
        into.push_back(static_cast<double>(count) / (t1 - t0));
    };
    for (int k = 0; k < kPasses; ++k) {
        timed(rate[0], rays.size(), single, hits);
        timed(
            rate[1], packed4.size(), [&] { return packets(packed4, 4); }, hits);
        timed(
            rate[2], packed16.size(), [&] { return packets(packed16, 16); }, hits);
        timed(rate[3], shadow.size(), shadows, occluded);
    }
    auto median = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v.empty() ? 0.0 : v[v.size() / 2];
    };
    Throughput out;
    out.primary = median(rate[0]);
    out.packets4 = median(rate[1]);
    out.packets16 = median(rate[2]);
    out.shadow = shadow.empty() ? 0 : median(rate[3]);
    const double n_rays = static_cast<double>(rays.size());
    out.boxes_primary = static_cast<double>(primary_stats.box_tests) / n_rays;
    out.prims_primary = static_cast<double>(primary_stats.triangle_tests + primary_stats.sphere_tests +
                                            primary_stats.shape_box_tests) /
                        n_rays;
    out.hit_fraction = static_cast<double>(hits) / static_cast<double>(rays.size());
    out.occluded_fraction =
        shadow.empty() ? 0 : static_cast<double>(occluded) / static_cast<double>(shadow.size());
    return out;
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
    double peak_per_tri = -1;  // the 2-thread build's peak memory above what was resident before it
    for (int threads : {1, 2}) {
        std::vector<SpecError> errors;
        const bool peak = start_peak();
        const long long before = wsd::bench::resident_bytes();
        double w0 = wall_now();
        g = Geometry::build(spec, errors, true, threads);
        double w1 = wall_now();
        if (!g) {
            std::printf("build failed: %s\n", errors.empty() ? "?" : errors[0].message.c_str());
            return 1;
        }
        const auto hwm = static_cast<long long>(wsd::app::peak_memory_bytes());
        if (peak && before >= 0 && hwm > 0)
            peak_per_tri = static_cast<double>(hwm - before) / static_cast<double>(g->triangle_count());
        std::printf("build (validation + world vertices + BVH), %d thread%s: %.3f s wall\n", threads,
                    threads == 1 ? "" : "s", w1 - w0);
    }
    double bytes = static_cast<double>(g->memory_bytes());
    std::printf("memory: %.1f bytes/triangle (geometry + BVH; the MeshData itself adds %.1f)\n",
                bytes / static_cast<double>(g->triangle_count()),
                static_cast<double>(mesh.mesh->vertices.size() * 12 + mesh.mesh->faces.size() * 12) /
                    static_cast<double>(g->triangle_count()));
    if (peak_per_tri >= 0)
        std::printf(
            "build peak: %.1f bytes/triangle (2 threads; resident memory above that before the build)\n",
            peak_per_tri);

    Throughput t = measure(*g, {0.3, 0.4, -3}, {0, 0, 0}, 45, {5, 5, -5}, 1024);
    std::printf("mesh primary rays: %.2f M/CPU-s (%.1f %% hit; %.1f box tests, %.1f triangle tests a ray)\n",
                t.primary * 1e-6, 100 * t.hit_fraction, t.boxes_primary, t.prims_primary);
    std::printf(
        "mesh primary rays in packets: 2x2 pixels %.2f M/CPU-s, 4x4 pixels (the renderer's 1-spp path) %.2f "
        "M/CPU-s\n",
        t.packets4 * 1e-6, t.packets16 * 1e-6);
    std::printf("mesh shadow rays:  %.2f M/CPU-s (%.1f %% occluded)\n", t.shadow * 1e-6,
                100 * t.occluded_fraction);

    std::vector<SpecError> errors;
    auto cornell = Geometry::build(cornell_geometry(), errors, true, 1);
    auto cornell_bf = Geometry::build(cornell_geometry(), errors, false, 1);
    if (!cornell || !cornell_bf) {
        std::printf("cornell build failed\n");
        return 1;
    }
    for (auto* cg : {cornell.get(), cornell_bf.get()}) {
        Throughput c = measure(*cg, {0, 0, -550}, {0, 0, 500}, 60, {25, 500, 625}, 512);
        std::printf(
            "cornell %s: primary %.2f M/CPU-s (packets of 4: %.2f, of 16: %.2f), shadow %.2f M/CPU-s (%.1f "
            "%% occluded)\n",
            cg == cornell.get() ? "BVH  " : "brute", c.primary * 1e-6, c.packets4 * 1e-6, c.packets16 * 1e-6,
            c.shadow * 1e-6, 100 * c.occluded_fraction);
    }
    return 0;
}
