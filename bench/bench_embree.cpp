// Side-by-side benchmark: wsd's geometry against Embree 3 on the same scenes and the same rays,
// one thread, one after the other in one run. Built only when CMake finds Embree (Debian's
// libembree-dev); wsd itself never links it.
//
// Scenes (every primitive opaque, so that shadow rays see all of them on both sides):
//   cornell  the Cornell box's geometry (bench/cornell_geometry.h): 10 wall triangles, 6 spheres
//            and the dice box. Embree gets the same walls, the spheres as its sphere primitive
//            (RTC_GEOMETRY_TYPE_SPHERE_POINT: centre and radius in float; all are integers, so
//            exact) and the box as 12 triangles (its 8 corners transformed in double and rounded
//            to float): 28 primitives.
//   mesh1m   a closed UV sphere of 1,000,000 triangles whose vertices are pushed out along the
//            radius by Perlin noise (r = 1 + 0.1·noise(4p)), in a closed room of 12 triangles.
//   mesh10m  the same at 10,001,406 triangles (3163 slices, 1582 stacks).
// Rays, generated once and given to both as the same float values (wsd traces them in double):
//   primary  one ray a pixel through a pinhole camera, in 4×4-pixel blocks within 16×16 tiles
//            (the renderer's order); traced one by one, and as packets of the 16 rays of a block
//            (wsd: Geometry::intersect_packet; Embree: rtcIntersect16).
//   shadow   from every primary hit to a random point on a square area light (any hit, t < 1).
//   diffuse  from every primary hit, a cosine-distributed direction about the surface normal on
//            the side the ray came from (incoherent).
//   Secondary origins are wsd's error-bounded offset origins, rounded to float away from the
//   surface (so that both sides start on the same side of it); Embree's tnear is 0.
// Rates are rays per CPU-second of the tracing thread, the median of the passes taken in turn
// (wsd, Embree, wsd, ...). Hits are compared ray by ray: the same primitive (wsd's shape and its
// triangle; any of a box's 12 triangles counts as the box) and distances apart by at most 1e-5
// of the float scale along the ray (the distance travelled plus the origin's distance from the
// world's origin). Rays where the two differ are classified: tie (different primitives at the
// same t: a shared edge or vertex), origin (one side hits within 1e-5 of the scene's size from
// the origin), edge (the nearer hit lies within 1e-5 of the float scale from its triangle's or
// box's edge), grazing (the same for a sphere's silhouette), t (same primitive, t apart), other;
// and counted by whose hit is the nearer (or the only) one. Embree runs with its defaults
// (RTC_BUILD_QUALITY_MEDIUM, no RTC_SCENE_FLAG_ROBUST; its own choice of ISA at run time).
//
// Prints human-readable lines and, for bench/performance.sh, one `row|...` line per query and
// one `build|...` line per scene. Usage: bench_embree [--quick] [--robust] [--baseline]
// [--no-avx512] [SCENE...] (quick: meshes of a hundredth the size, one pass, and no mesh10m unless
// named; robust: Embree in its robust mode, RTC_SCENE_FLAG_ROBUST; baseline: wsd's walks test
// nodes, triangles and packets with baseline x86-64 instructions even where the CPU has AVX;
// no-avx512: packets keep to AVX where the CPU has AVX-512; SCENE: cornell, mesh1m, mesh10m).
#include <embree3/rtcore.h>
#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bench/same_rays.h"
#include "render/cpu_features.h"
#include "render/geometry.h"
#include "render/geometry_impl.h"
#include "render/math.h"

using namespace wsd::render;
using namespace wsd::bench;

namespace {

double cpu_now() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double wall_now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// CPU time of the whole process (every thread), for builds.
double process_cpu() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    auto sec = [](timeval t) {
        return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
    };
    return sec(u.ru_utime) + sec(u.ru_stime);
}

double peak_rss_mib() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return static_cast<double>(u.ru_maxrss) / 1024.0;
}

constexpr double kTRelTolerance = 1e-5;
constexpr double kEdgeTolerance = 1e-5;

// ---- Embree's copy of a scene: one Embree geometry per wsd shape, its ID the shape's index.

struct EmbreeScene {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    ~EmbreeScene() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

Vec3f world_float(const Mat4& m, const Vec3& p) {
    const glm::dvec4 w = m * glm::dvec4(p, 1.0);
    return Vec3f(static_cast<float>(w.x), static_cast<float>(w.y), static_cast<float>(w.z));
}

void add_triangles(RTCDevice dev, RTCScene scene, unsigned id, const std::vector<Vec3f>& verts,
                   const std::vector<glm::uvec3>& faces) {
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), verts.size()));
    std::memcpy(v, verts.data(), verts.size() * sizeof(Vec3f));
    auto* f = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned), faces.size()));
    std::memcpy(f, faces.data(), faces.size() * sizeof(glm::uvec3));
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(scene, g, id);
    rtcReleaseGeometry(g);
}

void box_corners(const ShapeSpec& s, std::vector<Vec3f>& verts, std::vector<glm::uvec3>& faces) {
    for (int k = 0; k < 8; ++k)
        verts.push_back(world_float(s.object_to_world,
                                    Vec3(k & 1 ? s.box_max.x : s.box_min.x, k & 2 ? s.box_max.y : s.box_min.y,
                                         k & 4 ? s.box_max.z : s.box_min.z)));
    const unsigned quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                                  {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    for (const auto& q : quads) {
        faces.push_back({q[0], q[1], q[2]});
        faces.push_back({q[0], q[2], q[3]});
    }
}

// Embree's robust mode (RTC_SCENE_FLAG_ROBUST: no cracks between triangles that share an edge,
// at some speed), from --robust.
bool g_robust = false;

bool build_embree(const SceneSpec& spec, EmbreeScene& e) {
    e.device = rtcNewDevice("threads=2");
    if (!e.device) return false;
    e.scene = rtcNewScene(e.device);
    if (g_robust) rtcSetSceneFlags(e.scene, RTC_SCENE_FLAG_ROBUST);
    for (size_t i = 0; i < spec.shapes.size(); ++i) {
        const ShapeSpec& s = spec.shapes[i];
        const unsigned id = static_cast<unsigned>(i);
        std::vector<Vec3f> verts;
        std::vector<glm::uvec3> faces;
        switch (s.kind) {
            case ShapeKind::Triangle:
                for (const Vec3& p : s.v) verts.push_back(world_float(s.object_to_world, p));
                faces.push_back({0, 1, 2});
                add_triangles(e.device, e.scene, id, verts, faces);
                break;
            case ShapeKind::Mesh:
                verts.reserve(s.mesh->vertices.size());
                for (const Vec3f& p : s.mesh->vertices)
                    verts.push_back(world_float(s.object_to_world, Vec3(p)));
                add_triangles(e.device, e.scene, id, verts, s.mesh->faces);
                break;
            case ShapeKind::Box:
                box_corners(s, verts, faces);
                add_triangles(e.device, e.scene, id, verts, faces);
                break;
            case ShapeKind::Sphere: {
                RTCGeometry g = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
                auto* p = static_cast<float*>(rtcSetNewGeometryBuffer(
                    g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
                p[0] = static_cast<float>(s.center.x), p[1] = static_cast<float>(s.center.y);
                p[2] = static_cast<float>(s.center.z), p[3] = static_cast<float>(s.radius);
                rtcCommitGeometry(g);
                rtcAttachGeometryByID(e.scene, g, id);
                rtcReleaseGeometry(g);
                break;
            }
            default:
                std::printf("shape kind not supported by this benchmark\n");
                return false;
        }
    }
    rtcCommitScene(e.scene);
    return rtcGetDeviceError(e.device) == RTC_ERROR_NONE;
}

// ---- Queries.

struct Hit {
    bool found = false;
    double t = 0;
    uint32_t shape = 0, local = 0;  // wsd's shape and its triangle (0 for spheres and boxes)
    double u = 0, v = 0;            // Embree's barycentrics (triangles)
};

void set_ray(RTCRay& er, const Ray& r, double tmax) {
    er.org_x = static_cast<float>(r.o.x), er.org_y = static_cast<float>(r.o.y),
    er.org_z = static_cast<float>(r.o.z);
    er.dir_x = static_cast<float>(r.d.x), er.dir_y = static_cast<float>(r.d.y),
    er.dir_z = static_cast<float>(r.d.z);
    er.tnear = 0;
    er.tfar = static_cast<float>(std::min(tmax, static_cast<double>(std::numeric_limits<float>::max())));
    er.time = 0;
    er.mask = 0xffffffffu;
    er.id = 0;
    er.flags = 0;
}

Hit embree_closest(const SceneDef& d, RTCScene scene, const Ray& r, double tmax) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    set_ray(rh.ray, r, tmax);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &ctx, &rh);
    Hit h;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
    h.found = true;
    h.t = rh.ray.tfar;
    h.shape = rh.hit.geomID;
    const ShapeKind k = d.spec.shapes[h.shape].kind;
    h.local = k == ShapeKind::Mesh ? rh.hit.primID : 0;
    h.u = rh.hit.u, h.v = rh.hit.v;
    return h;
}

Hit wsd_closest(const Geometry& g, const Ray& r, double tmax) {
    RayStats stats;
    auto hit = g.intersect(r, tmax, stats);
    Hit h;
    if (!hit) return h;
    const auto& impl = g.impl();
    h.found = true;
    h.t = hit->t;
    h.shape = impl.shape_of(hit->prim);
    h.local = hit->prim - impl.shapes[h.shape].first_prim;
    return h;
}

// The scale float arithmetic works at along a ray up to distance t: the distance travelled plus
// the origin's distance from the world's origin.
double float_scale(const Ray& r, double t) {
    return t * glm::length(r.d) + glm::length(r.o);
}

// How far the hit point lies from an edge of its triangle or box (in the plane of the face);
// for a sphere, how far the ray's line passes from the sphere's silhouette. In world units.
double edge_distance(const SceneDef& d, const Hit& h, const Ray& r) {
    const ShapeSpec& s = d.spec.shapes[h.shape];
    const Vec3 p = r.o + h.t * r.d;
    auto tri_min_bary = [&](Vec3 a, Vec3 b, Vec3 c) {
        const Vec3 n = glm::cross(b - a, c - a);
        const double area2 = glm::dot(n, n);
        const double b0 = glm::dot(glm::cross(b - p, c - p), n) / area2;
        const double b1 = glm::dot(glm::cross(c - p, a - p), n) / area2;
        // Barycentric i times the height over edge i (twice the area over the edge's length).
        const double h2 = std::sqrt(area2);
        return std::min({std::abs(b0) * h2 / glm::length(c - b), std::abs(b1) * h2 / glm::length(a - c),
                         std::abs(1 - b0 - b1) * h2 / glm::length(b - a)});
    };
    switch (s.kind) {
        case ShapeKind::Triangle:
            return tri_min_bary(s.v[0], s.v[1], s.v[2]);
        case ShapeKind::Mesh: {
            const glm::uvec3 f = s.mesh->faces[h.local];
            return tri_min_bary(Vec3(s.mesh->vertices[f.x]), Vec3(s.mesh->vertices[f.y]),
                                Vec3(s.mesh->vertices[f.z]));
        }
        case ShapeKind::Box: {
            const glm::dvec4 q = glm::inverse(s.object_to_world) * glm::dvec4(p, 1.0);
            double near[3];
            for (int a = 0; a < 3; ++a) {
                near[a] = std::min(std::abs(q[a] - s.box_min[a]), std::abs(q[a] - s.box_max[a]));
            }
            std::sort(near, near + 3);
            // On a face one is ~0; near an edge the second is small too (object units: the
            // benchmark's boxes are only turned and moved).
            return near[1];
        }
        case ShapeKind::Sphere: {
            const Vec3 dn = glm::normalize(r.d);
            const Vec3 oc = s.center - r.o;
            const double dist = glm::length(oc - glm::dot(oc, dn) * dn);
            return std::abs(dist - s.radius);
        }
        default:
            return 1;
    }
}

enum Why { kTie, kOrigin, kEdge, kGrazing, kT, kOther, kWhyCount };
constexpr const char* kWhyName[kWhyCount] = {"tie", "origin", "edge", "grazing", "t", "other"};

// The two distances apart, as a fraction of the float scale along the ray.
double t_difference(const Hit& a, const Hit& b, const Ray& r) {
    return std::abs(a.t - b.t) * glm::length(r.d) / float_scale(r, std::max(a.t, b.t));
}
bool same_t(const Hit& a, const Hit& b, const Ray& r) {
    return t_difference(a, b, r) <= kTRelTolerance;
}

Why classify_one(const SceneDef& d, const Hit& h, const Ray& r) {
    if (h.t * glm::length(r.d) < 1e-5 * d.scale) return kOrigin;
    if (edge_distance(d, h, r) < kEdgeTolerance * float_scale(r, h.t))
        return d.spec.shapes[h.shape].kind == ShapeKind::Sphere ? kGrazing : kEdge;
    return kOther;
}

Why classify(const SceneDef& d, const Hit& a, const Hit& b, const Ray& r) {
    if (a.found && b.found) {
        if (a.shape == b.shape && a.local == b.local) return kT;
        if (same_t(a, b, r)) return kTie;
        // Different primitives at different distances: the nearer one is what the other missed.
        const Why wa = classify_one(d, a, r), wb = classify_one(d, b, r);
        return a.t < b.t ? wa : wb;
    }
    return classify_one(d, a.found ? a : b, r);
}

struct Compare {
    size_t differ = 0;
    size_t why[kWhyCount] = {};
    size_t nearer_wsd = 0, nearer_embree = 0;  // whose hit (or occluder) is the nearer one / the only one
    double max_rel_t = 0;                      // t_difference over the rays that agree
    std::string text() const {
        std::string s;
        for (int k = 0; k < kWhyCount; ++k)
            if (why[k])
                s += (s.empty() ? "" : ", ") + std::string(kWhyName[k]) + " " + std::to_string(why[k]);
        if (differ)
            s += "; nearer hit: wsd " + std::to_string(nearer_wsd) + ", Embree " +
                 std::to_string(nearer_embree);
        return s.empty() ? "-" : s;
    }
};

Compare compare_closest(const SceneDef& d, const Geometry& g, RTCScene scene, const RaySet& set) {
    Compare c;
    for (const Ray& r : set.rays) {
        const Hit a = wsd_closest(g, r, set.tmax), b = embree_closest(d, scene, r, set.tmax);
        const bool same =
            a.found == b.found && (!a.found || (a.shape == b.shape && a.local == b.local && same_t(a, b, r)));
        if (same) {
            if (a.found) c.max_rel_t = std::max(c.max_rel_t, t_difference(a, b, r));
            continue;
        }
        ++c.differ;
        ++c.why[classify(d, a, b, r)];
        const bool embree_nearer = b.found && (!a.found || b.t < a.t);
        ++(embree_nearer ? c.nearer_embree : c.nearer_wsd);
    }
    return c;
}

bool embree_occluded(RTCScene scene, const Ray& r, double tmax) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay er;
    set_ray(er, r, tmax);
    rtcOccluded1(scene, &ctx, &er);
    return er.tfar < 0;
}

Compare compare_occluded(const SceneDef& d, const Geometry& g, RTCScene scene, const RaySet& set) {
    Compare c;
    RayStats stats;
    for (const Ray& r : set.rays) {
        const bool a = g.occluded(r, set.tmax, stats), b = embree_occluded(scene, r, set.tmax);
        if (a == b) continue;
        ++c.differ;
        ++(a ? c.nearer_wsd : c.nearer_embree);
        // The occluder the side that found one sees first.
        const Hit h = a ? wsd_closest(g, r, set.tmax) : embree_closest(d, scene, r, set.tmax);
        ++c.why[h.found ? classify_one(d, h, r) : kOther];
    }
    return c;
}

// ---- Timing.

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

struct Pair {
    std::vector<double> wsd, embree;
};

template <class F>
double rate_of(size_t rays, F&& pass, size_t& found) {
    const double t0 = cpu_now();
    found = pass();
    const double t1 = cpu_now();
    return static_cast<double>(rays) / (t1 - t0);
}

// `work`: wsd's RayStats over one pass of the rays (child boxes and triangles tested).
void print_row(const std::string& scene, const std::string& query, const Pair& p, size_t rays, size_t found,
               const Compare& c, const RayStats& work) {
    const double w = median(p.wsd), e = median(p.embree);
    const double n = static_cast<double>(rays);
    const double boxes = static_cast<double>(work.box_tests) / n,
                 tris = static_cast<double>(work.triangle_tests) / n;
    std::printf(
        "%-8s %-16s wsd %7.2f M/CPU-s  Embree %7.2f M/CPU-s  ratio %.2f  (%zu rays, %.1f %% %s; %zu differ: "
        "%s; wsd per ray: %.1f child boxes, %.2f triangle tests)\n",
        scene.c_str(), query.c_str(), w * 1e-6, e * 1e-6, w / e, rays, 100.0 * static_cast<double>(found) / n,
        query.rfind("shadow", 0) == 0 ? "occluded" : "hit", c.differ, c.text().c_str(), boxes, tris);
    std::printf("row|%s|%s|%.3f|%.3f|%.2f|%zu|%zu|%s|%.1e|%.1f|%.2f\n", scene.c_str(), query.c_str(),
                w * 1e-6, e * 1e-6, w / e, rays, c.differ, c.text().c_str(), c.max_rel_t, boxes, tris);
}

int run_scene(const SceneDef& d, int passes) {
    size_t tris = 0, embree_prims = 0;
    for (const auto& s : d.spec.shapes) {
        const size_t n = s.kind == ShapeKind::Mesh       ? s.mesh->faces.size()
                         : s.kind == ShapeKind::Triangle ? 1
                                                         : 0;
        tris += n;
        embree_prims += s.kind == ShapeKind::Box ? 12 : s.kind == ShapeKind::Sphere ? 1 : n;
    }
    std::printf("%s: %zu shapes, %zu triangles; Embree %zu primitives\n", d.name.c_str(),
                d.spec.shapes.size(), tris, embree_prims);

    std::vector<SpecError> errors;
    const double c0 = process_cpu(), w0 = wall_now();
    auto g = Geometry::build(d.spec, errors, true, 2);
    const double w1 = wall_now(), c1 = process_cpu();
    if (!g) {
        std::printf("wsd build failed: %s\n", errors.empty() ? "?" : errors[0].message.c_str());
        return 1;
    }
    EmbreeScene e;
    double w2 = wall_now();
    if (!build_embree(d.spec, e)) {
        std::printf("Embree build failed\n");
        return 1;
    }
    double w3 = wall_now();
    size_t mesh_bytes = 0;
    for (const auto& s : d.spec.shapes)
        if (s.kind == ShapeKind::Mesh) mesh_bytes += s.mesh->vertices.size() * 12 + s.mesh->faces.size() * 12;
    const double per_tri = tris ? static_cast<double>(g->memory_bytes()) / static_cast<double>(tris) : 0;
    const double mesh_per_tri = tris ? static_cast<double>(mesh_bytes) / static_cast<double>(tris) : 0;
    std::printf(
        "%s build, 2 threads: wsd %.3f s wall, %.3f s CPU (%.1f bytes/triangle: geometry + BVH; the MeshData "
        "adds %.1f), Embree %.3f s wall; peak RSS %.0f MiB\n",
        d.name.c_str(), w1 - w0, c1 - c0, per_tri, mesh_per_tri, w3 - w2, peak_rss_mib());
    // Rows name the scene, and Embree's robust mode when it is on.
    const std::string label = d.name + (g_robust ? ", Embree robust" : "");
    std::printf("build|%s|%zu|%.3f|%.3f|%.1f|%.1f|%.3f\n", label.c_str(), tris, w1 - w0, c1 - c0, per_tri,
                mesh_per_tri, w3 - w2);

    const RaySet primary = primary_rays(d);
    RaySet shadow, diffuse;
    secondary_rays(d, *g, primary, shadow, diffuse);
    const RTCScene scene = e.scene;
    RayStats stats;

    auto wsd_single = [&](const RaySet& set) {
        size_t n = 0;
        for (const Ray& r : set.rays) n += g->intersect(r, set.tmax, stats) ? 1 : 0;
        return n;
    };
    auto wsd_shadow = [&](const RaySet& set) {
        size_t n = 0;
        for (const Ray& r : set.rays) n += g->occluded(r, set.tmax, stats) ? 1 : 0;
        return n;
    };
    auto wsd_packets = [&](const RaySet& set) {
        size_t n = 0;
        std::optional<HitRecord> out[16];
        for (size_t i = 0; i + 16 <= set.rays.size(); i += 16) {
            g->intersect_packet(&set.rays[i], 16, set.tmax, stats, out);
            for (auto& o : out) n += o ? 1 : 0;
        }
        return n;
    };
    auto embree_single = [&](const RaySet& set) {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        size_t n = 0;
        RTCRayHit rh;
        for (const Ray& r : set.rays) {
            set_ray(rh.ray, r, set.tmax);
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(scene, &ctx, &rh);
            n += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? 1 : 0;
        }
        return n;
    };
    auto embree_shadow = [&](const RaySet& set) {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        size_t n = 0;
        RTCRay er;
        for (const Ray& r : set.rays) {
            set_ray(er, r, set.tmax);
            rtcOccluded1(scene, &ctx, &er);
            n += er.tfar < 0 ? 1 : 0;
        }
        return n;
    };
    // Packets: converted to Embree's SOA layout beforehand, copied in before each call (a renderer
    // fills its packet anyway; the copy is part of the timed loop, as wsd's packet set-up is).
    std::vector<RTCRayHit16> soa;
    soa.resize(primary.rays.size() / 16);
    for (size_t p = 0; p < soa.size(); ++p) {
        RTCRayHit16& rh = soa[p];
        for (int k = 0; k < 16; ++k) {
            const Ray& r = primary.rays[p * 16 + size_t(k)];
            rh.ray.org_x[k] = static_cast<float>(r.o.x), rh.ray.org_y[k] = static_cast<float>(r.o.y);
            rh.ray.org_z[k] = static_cast<float>(r.o.z), rh.ray.dir_x[k] = static_cast<float>(r.d.x);
            rh.ray.dir_y[k] = static_cast<float>(r.d.y), rh.ray.dir_z[k] = static_cast<float>(r.d.z);
            rh.ray.tnear[k] = 0, rh.ray.tfar[k] = std::numeric_limits<float>::infinity();
            rh.ray.time[k] = 0, rh.ray.mask[k] = 0xffffffffu, rh.ray.id[k] = 0, rh.ray.flags[k] = 0;
            rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        }
    }
    auto embree_packets = [&](const RaySet&) {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        alignas(64) int valid[16];
        std::fill(valid, valid + 16, -1);
        alignas(64) RTCRayHit16 rh;
        size_t n = 0;
        for (const RTCRayHit16& src : soa) {
            std::memcpy(&rh, &src, sizeof rh);
            rtcIntersect16(valid, scene, &ctx, &rh);
            for (int k = 0; k < 16; ++k) n += rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID ? 1 : 0;
        }
        return n;
    };

    struct Query {
        std::string name;
        const RaySet* set;
        std::function<size_t(const RaySet&)> wsd, embree;
        bool occlusion;
    };
    const Query queries[] = {
        {"primary", &primary, wsd_single, embree_single, false},
        {"primary 16-packets", &primary, wsd_packets, embree_packets, false},
        {"shadow", &shadow, wsd_shadow, embree_shadow, true},
        {"diffuse", &diffuse, wsd_single, embree_single, false},
    };
    std::vector<Pair> rates(std::size(queries));
    std::vector<size_t> found(std::size(queries));
    for (int k = 0; k < passes; ++k)
        for (size_t q = 0; q < std::size(queries); ++q) {
            size_t fw = 0, fe = 0;
            rates[q].wsd.push_back(rate_of(
                queries[q].set->rays.size(), [&] { return queries[q].wsd(*queries[q].set); }, fw));
            rates[q].embree.push_back(rate_of(
                queries[q].set->rays.size(), [&] { return queries[q].embree(*queries[q].set); }, fe));
            found[q] = fw;
        }
    for (size_t q = 0; q < std::size(queries); ++q) {
        const Query& qq = queries[q];
        // Packets give the same hits as single rays on both sides (wsd: bit for bit), so the
        // comparison of single rays stands for them.
        const Compare c =
            qq.occlusion ? compare_occluded(d, *g, scene, *qq.set) : compare_closest(d, *g, scene, *qq.set);
        stats = RayStats{};
        qq.wsd(*qq.set);
        print_row(label, qq.name, rates[q], qq.set->rays.size(), found[q], c, stats);
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false;
    std::vector<std::string> only;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--quick")
            quick = true;
        else if (a == "--robust")
            g_robust = true;
        else if (a == "--baseline")
            set_avx_walk(false);
        else if (a == "--no-avx512")
            set_avx512_packets(false);
        else if (a == "cornell" || a == "mesh1m" || a == "mesh10m")
            only.push_back(a);
        else {
            std::printf(
                "usage: bench_embree [--quick] [--robust] [--baseline] [--no-avx512] "
                "[cornell|mesh1m|mesh10m]...\n");
            return 2;
        }
    }
    auto wanted = [&](const char* name) {
        return only.empty() ? !(quick && std::string(name) == "mesh10m")
                            : std::find(only.begin(), only.end(), name) != only.end();
    };
    std::printf(
        "Embree %d.%d.%d, %s mode, one tracing thread; t tolerance %.0e, edge tolerance %.0e (of the float "
        "scale); wsd's walks: %s\n",
        RTC_VERSION_MAJOR, RTC_VERSION_MINOR, RTC_VERSION_PATCH, g_robust ? "robust" : "default",
        kTRelTolerance, kEdgeTolerance,
        avx512_packets() ? "AVX, AVX-512 packets"
        : avx_walk()     ? "AVX"
                         : "baseline x86-64");
    int status = 0;
    if (wanted("cornell")) status = run_scene(cornell_scene(), quick ? 1 : 5);
    if (status == 0 && wanted("mesh1m"))
        status =
            run_scene(displaced_mesh_scene("mesh1m", quick ? 100 : 1000, quick ? 51 : 501), quick ? 1 : 5);
    if (status == 0 && wanted("mesh10m"))
        status =
            run_scene(displaced_mesh_scene("mesh10m", quick ? 317 : 3163, quick ? 159 : 1582), quick ? 1 : 3);
    return status;
}
