// Packets (Geometry::intersect_packet): up to 16 rays traced in one walk of the BVH must get
// exactly the hits intersect() gives each of them — same primitive, t, slot and barycentrics —
// whether they share an origin (camera rays), start at different points, point in mixed
// directions (traced one by one), have zero or tiny direction components, or are invalid.
#include <bit>
#include <catch2/catch.hpp>
#include <iterator>
#include <optional>

#include "geometry_test_util.h"
#include "render/aabb.h"
#include "render/cpu_features.h"

using namespace wsd::render;
using namespace wsd::render::test;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Requires the packet's answers to equal the single-ray answers; returns how many rays hit.
int require_same_as_single(const Geometry& g, const Ray* rays, int n, double tmax) {
    RayStats packet_stats, single_stats;
    std::optional<HitRecord> out[Geometry::kMaxPacket];
    g.intersect_packet(rays, n, tmax, packet_stats, out);
    int hits = 0;
    for (int k = 0; k < n; ++k) {
        INFO("lane " << k << " of " << n);
        auto h = g.intersect(rays[k], tmax, single_stats);
        REQUIRE(out[k].has_value() == h.has_value());
        if (!h) continue;
        ++hits;
        REQUIRE(out[k]->prim == h->prim);
        REQUIRE(out[k]->slot == h->slot);
        REQUIRE(out[k]->t == h->t);
        REQUIRE(out[k]->b1 == h->b1);
        REQUIRE(out[k]->b2 == h->b2);
    }
    REQUIRE(packet_stats.rejected_rays == single_stats.rejected_rays);
    return hits;
}

// kMaxPacket rays around a base ray: a shared origin (camera) or origins spread by `spread`,
// and directions turned by up to `turn` (relative).
void make_packet(Rng& rng, const Ray& base, double spread, double turn, Ray* out) {
    for (int k = 0; k < Geometry::kMaxPacket; ++k) {
        Vec3 o = base.o + spread * rng.in_box(Vec3(-1), Vec3(1));
        Vec3 d = base.d + turn * glm::length(base.d) * rng.in_box(Vec3(-1), Vec3(1));
        out[k] = {o, d};
    }
}

}  // namespace

TEST_CASE("packets of rays get exactly the single-ray hits on random scenes") {
    Rng rng(20261125);
    const int scenes = 30, packets = ray_budget(40000) / scenes;
    int hits = 0, total = 0;
    for (int s = 0; s < scenes; ++s) {
        const double size = rng.log_uniform(-3, 3);
        SceneSpec spec = random_scene(rng, rng.integer(1, 300), size);
        if (s % 3 == 0)
            spec.shapes.push_back(
                mesh(perturbed_uv_sphere(21, 40, rng, rng.in_box(Vec3(-size), Vec3(size)), 0, 0.4 * size)));
        if (s % 5 == 0) spec.shapes.push_back(plane(rng.unit_vector(), rng.uniform(-size, size)));
        auto g = build_ok(spec, true);
        REQUIRE(g);
        INFO("scene " << s << " size " << size);
        for (int i = 0; i < packets; ++i) {
            Ray rays[Geometry::kMaxPacket];
            const Ray base = random_ray(rng, size);
            switch (i % 4) {
                case 0:
                    make_packet(rng, base, 0, rng.log_uniform(-6, -1), rays);
                    break;  // camera
                case 1:
                    make_packet(rng, base, size * rng.log_uniform(-6, -1), rng.log_uniform(-6, -1), rays);
                    break;
                case 2:
                    make_packet(rng, base, size * rng.uniform(0, 1), rng.uniform(0, 0.5), rays);
                    break;
                default:
                    for (Ray& r : rays) r = random_ray(rng, size);  // mixed directions
                    break;
            }
            // Both packet widths (up to 4 rays, up to 16) and every partial size.
            const int n = rng.integer(1, i % 8 < 4 ? 4 : Geometry::kMaxPacket);
            const double tmax = rng.uniform() < 0.7 ? kInf : rng.uniform(0, 2 * size);
            hits += require_same_as_single(*g, rays, n, tmax);
            total += n;
        }
    }
    // The comparison means something only if many rays hit.
    CHECK(hits > total / 5);
}

TEST_CASE("packets from a camera inside a dense mesh, and through its silhouette") {
    Rng rng(5);
    SceneSpec spec = scene_of({mesh(perturbed_uv_sphere(101, 200, rng, Vec3(0), 0))});
    auto g = build_ok(spec, true);
    REQUIRE(g);
    int hits = 0;
    for (int i = 0; i < ray_budget(20000); ++i) {
        // Outside looking at it (many rays graze the silhouette), or inside looking out.
        const bool inside = i % 2 == 1;
        const Vec3 eye = inside ? 0.5 * rng.in_box(Vec3(-1), Vec3(1)) : 3.0 * rng.unit_vector();
        const Vec3 aim = inside ? rng.unit_vector() : rng.in_box(Vec3(-1.2), Vec3(1.2)) - eye;
        Ray rays[Geometry::kMaxPacket];
        make_packet(rng, {eye, aim}, 0, rng.log_uniform(-5, -2), rays);
        hits += require_same_as_single(*g, rays, i % 4 < 2 ? 4 : Geometry::kMaxPacket, kInf);
    }
    CHECK(hits > ray_budget(20000) * 4);
}

TEST_CASE(
    "packets under the walks built for AVX and AVX-512 answer as under the baseline walk, bit for bit") {
    // The AVX walk tests eight children, eight rays' leaf boxes and four rays' triangle edges at
    // once; with AVX-512 packets of sixteen test sixteen rays' leaf boxes and eight rays' triangle
    // edges. On a CPU without them the runs take the baseline walk and agree trivially.
    const bool had = avx_walk();
    Rng rng(20261129);
    const int scenes = 12, packets = ray_budget(12000) / scenes;
    int hits = 0, total = 0;
    // Walk 0: baseline; 1: AVX; 2: AVX with AVX-512 packets.
    const auto choose = [](int walk) {
        set_avx_walk(walk >= 1);
        set_avx512_packets(walk == 2);
    };
    for (int s = 0; s < scenes; ++s) {
        const double size = rng.log_uniform(-3, 3);
        const SceneSpec spec =
            s % 2 == 0 ? mesh_scene(rng, size) : random_scene(rng, rng.integer(1, 300), size);
        auto g = build_ok(spec, true);
        REQUIRE(g);
        choose(2);
        INFO("scene " << s << " size " << size << ", AVX available " << avx_walk() << ", AVX-512 packets "
                      << avx512_packets());
        for (int i = 0; i < packets; ++i) {
            Ray rays[Geometry::kMaxPacket];
            const Ray base = random_ray(rng, size);
            make_packet(rng, base, i % 2 == 0 ? 0 : size * rng.log_uniform(-6, -1), rng.log_uniform(-6, -1),
                        rays);
            const int n = rng.integer(1, i % 4 < 2 ? 4 : Geometry::kMaxPacket);
            const double tmax = rng.uniform() < 0.7 ? kInf : rng.uniform(0, 2 * size);
            RayStats st[3];
            std::optional<HitRecord> out[3][Geometry::kMaxPacket];
            for (int walk = 0; walk < 3; ++walk) {
                choose(walk);
                g->intersect_packet(rays, n, tmax, st[walk], out[walk]);
            }
            for (int walk = 1; walk < 3; ++walk) {
                const auto &a = out[walk], &b = out[0];
                for (int k = 0; k < n; ++k) {
                    INFO("walk " << walk << ", lane " << k << " of " << n);
                    REQUIRE(a[k].has_value() == b[k].has_value());
                    if (!a[k]) continue;
                    hits += walk == 1;
                    REQUIRE(a[k]->prim == b[k]->prim);
                    REQUIRE(a[k]->slot == b[k]->slot);
                    REQUIRE(a[k]->t == b[k]->t);
                    REQUIRE(a[k]->b1 == b[k]->b1);
                    REQUIRE(a[k]->b2 == b[k]->b2);
                }
                REQUIRE(st[walk].box_tests == st[0].box_tests);  // the same nodes, leaves and rays entered
                REQUIRE(st[walk].triangle_tests == st[0].triangle_tests);
            }
            total += n;
        }
    }
    set_avx_walk(had);
    set_avx512_packets(true);  // as at start-up: where the CPU has it
    CHECK(hits > total / 5);
}

TEST_CASE("packets with zero, tiny, huge or invalid direction components fall back and agree") {
    Rng rng(9);
    SceneSpec spec = random_scene(rng, 200, 1);
    auto g = build_ok(spec, true);
    REQUIRE(g);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (int i = 0; i < 2000; ++i) {
        Ray rays[Geometry::kMaxPacket];
        make_packet(rng, random_ray(rng, 1), 0, 1e-3, rays);
        const int n = i % 2 ? 4 : Geometry::kMaxPacket;
        const int lane = rng.integer(0, n - 1), axis = rng.integer(0, 2);
        switch (i % 6) {
            case 0:
                rays[lane].d[axis] = 0;
                break;
            case 1:
                rays[lane].d[axis] = -0.0;
                break;
            case 2:
                rays[lane].d[axis] = 1e-300;
                break;  // 1/d overflows a float
            case 3:
                rays[lane].d *= 1e300;
                break;  // 1/d underflows to 0
            case 4:
                rays[lane].d[axis] = nan;
                break;  // rejected by both
            default:
                rays[lane].o[axis] = std::numeric_limits<double>::infinity();
                break;
        }
        require_same_as_single(*g, rays, n, kInf);
        require_same_as_single(*g, rays, n, -1);  // nothing within a negative limit
    }
}

TEST_CASE("a packet without a BVH is traced ray by ray with the same answers") {
    Rng rng(3);
    SceneSpec spec = random_scene(rng, 50, 1);
    auto g = build_ok(spec, false);
    REQUIRE(g);
    for (int i = 0; i < 500; ++i) {
        Ray rays[Geometry::kMaxPacket];
        make_packet(rng, random_ray(rng, 1), 0, 1e-2, rays);
        require_same_as_single(*g, rays, rng.integer(1, Geometry::kMaxPacket), kInf);
    }
}

#if defined(__SSE2__)
TEST_CASE("a packet's slab constants are RayBoxTest's, bit for bit") {
    // slab_constants4 rounds origins up and down without branches; it must agree with the
    // scalar to_float_up/down (and 1/d) for origins that round either way, floats exactly, ±0,
    // values beyond the float range and tiny ones.
    Rng rng(41);
    const double specials[] = {0.0,
                               -0.0,
                               1.0,
                               -1.0,
                               0.1,
                               -0.1,
                               1e-40,
                               -1e-40,
                               1e-300,
                               -1e-300,
                               3.4028235677973366e38,
                               -3.4028235677973366e38,
                               1e39,
                               -1e39,
                               1e300,
                               -1e300,
                               16777217.0,
                               -16777217.0};
    auto pick = [&]() -> double {
        switch (rng.integer(0, 3)) {
            case 0:
                return specials[rng.integer(0, int(std::size(specials)) - 1)];
            case 1:
                return static_cast<double>(static_cast<float>(rng.uniform(-10, 10)));  // a float
            default:
                return rng.uniform(-1, 1) * rng.log_uniform(-45, 45);
        }
    };
    for (int i = 0; i < ray_budget(20000); ++i) {
        Vec3 o[4], d[4];
        bool neg[3];
        for (int a = 0; a < 3; ++a) neg[a] = rng.uniform() < 0.5;
        for (int k = 0; k < 4; ++k) {
            for (int a = 0; a < 3; ++a) {
                o[k][a] = pick();
                const double m = std::abs(pick());
                d[k][a] = neg[a] ? -m : m;
            }
        }
        __m128 o_near[3], o_far[3], inv[3];
        slab_constants4(o, d, neg, o_near, o_far, inv);
        for (int k = 0; k < 4; ++k) {
            RayBoxTest slabs;
            slabs.init(o[k], d[k]);
            for (int a = 0; a < 3; ++a) {
                alignas(16) float on[4], of[4], iv[4];
                _mm_store_ps(on, o_near[a]);
                _mm_store_ps(of, o_far[a]);
                _mm_store_ps(iv, inv[a]);
                INFO("o " << o[k][a] << " d " << d[k][a]);
                REQUIRE(std::bit_cast<uint32_t>(on[k]) == std::bit_cast<uint32_t>(slabs.o_near[a]));
                REQUIRE(std::bit_cast<uint32_t>(of[k]) == std::bit_cast<uint32_t>(slabs.o_far[a]));
                REQUIRE(std::bit_cast<uint32_t>(iv[k]) == std::bit_cast<uint32_t>(slabs.inv[a]));
            }
        }
    }
}
#endif
