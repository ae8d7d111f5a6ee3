// Caustic photons, as docs/wsd-language.md "caustics" describes them:
// - targets: the bounding spheres of the objects that can focus light (reflection or
//   transmission); every light shoots towards each target through the cone the sphere subtends
//   (the whole sphere of directions when the light is inside it), like POV-Ray's projection maps.
//   The photon budget is split over (light, target) pairs by colour × intensity × solid angle.
// - the power rule: wsd's lights have no distance falloff, so a photon's power is set where it
//   first meets a surface: for a direction density ρ(ω) (photons per steradian, summed over every
//   cone containing ω: one-sample multiple importance sampling, so overlapping cones do not count
//   twice) and a first hit at distance d, it carries light · d² / ρ — over the surface, exactly the
//   irradiance light·max(0, N·L) of the direct term. A first hit on anything that cannot focus
//   light ends the photon (the direct term already lights it).
// - from then on it travels physically: at each mirror or glass surface it reflects with weight
//   r + t·F or refracts with weight t·(1 − F)·c (Fresnel and total internal reflection as the
//   tracer computes them, Beer–Lambert absorption inside), choosing one branch at random with
//   probability proportional to the weight (Russian roulette, ending when the weights sum below
//   1) and dividing by that probability; at most max_depth bounces. It is stored wherever it
//   lands on a diffuse surface after at least one such bounce.
#include "render/photon_trace.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "render/integrator.h"
#include "render/parallel.h"
#include "render/sampling.h"
#include "render/scene.h"

namespace wsd::render {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr uint64_t kPhotonSalt = 0xc2b2ae3d27d4eb4fULL;
constexpr size_t kChunk = 4096;     // photons a parallel task: fixed, so the map is too
constexpr size_t kMaxTargets = 64;  // beyond this, one sphere around all focusing objects
// The photons an estimate uses grow as the square root of the photons stored: √stored / 4, at
// least 16 and at most 256 (more photons buy both less noise and less blur).
constexpr int kMinGather = 16, kMaxGather = 256;
// And look no farther than a quarter of the largest target's radius: where fewer photons lie that
// close, their sum is spread over that disc.
constexpr double kGatherRadius = 0.25;

struct Box {
    Vec3 lo{kInf}, hi{-kInf};
    bool empty() const { return !(lo.x <= hi.x); }
    void add(const Vec3& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void add(const Box& b) {
        if (!b.empty()) {
            add(b.lo);
            add(b.hi);
        }
    }
};

Box transformed(const Mat4& m, const Box& b) {
    Box out;
    if (b.empty()) return out;
    for (int k = 0; k < 8; ++k) {
        const Vec3 c{(k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z};
        out.add(Vec3(m * glm::dvec4(c, 1.0)));
    }
    return out;
}

// The world box of a shape, or nullopt when it has none (a plane, or a CSG or instance that
// holds one where it bounds the solid).
std::optional<Box> shape_bounds(const SceneSpec& spec, const ShapeSpec& sh, const Mat4& to_world) {
    Box b;
    switch (sh.kind) {
        case ShapeKind::Sphere:
            b.add(sh.center - Vec3(sh.radius));
            b.add(sh.center + Vec3(sh.radius));
            break;
        case ShapeKind::Box:
            b.add(sh.box_min);
            b.add(sh.box_max);
            break;
        case ShapeKind::Triangle:
            for (const Vec3& v : sh.v) b.add(v);
            break;
        case ShapeKind::Mesh:
            if (sh.mesh)
                for (const glm::vec3& v : sh.mesh->vertices) b.add(Vec3(v));
            break;
        case ShapeKind::Cylinder:
        case ShapeKind::Cone: {
            const double r = sh.kind == ShapeKind::Cylinder ? sh.radius : std::max(sh.radius, sh.cap_radius);
            for (const Vec3& p : {sh.base, sh.cap}) {
                b.add(p - Vec3(r));
                b.add(p + Vec3(r));
            }
            break;
        }
        case ShapeKind::Torus:
            b.add(Vec3(-(sh.major + sh.minor), -sh.minor, -(sh.major + sh.minor)));
            b.add(Vec3(sh.major + sh.minor, sh.minor, sh.major + sh.minor));
            break;
        case ShapeKind::Disc:
            b.add(sh.center - Vec3(sh.radius));
            b.add(sh.center + Vec3(sh.radius));
            break;
        case ShapeKind::Plane:
            return std::nullopt;
        case ShapeKind::Csg: {
            if (!sh.csg) return std::nullopt;
            const auto& members = sh.csg->members;
            // A union needs every member bounded; a difference lies in its first member; an
            // intersection in any bounded member.
            bool any = false;
            for (size_t i = 0; i < members.size(); ++i) {
                const auto mb = shape_bounds(spec, members[i], members[i].object_to_world);
                if (sh.csg->op == CsgOp::Union) {
                    if (!mb) return std::nullopt;
                    b.add(*mb);
                } else if (sh.csg->op == CsgOp::Difference) {
                    if (!mb) return std::nullopt;
                    b.add(*mb);
                    break;
                } else if (mb) {
                    b = *mb;
                    any = true;
                    break;
                }
            }
            if (sh.csg->op == CsgOp::Intersection && !any) return std::nullopt;
            break;
        }
        case ShapeKind::Instance: {
            if (sh.prototype >= spec.prototypes.size()) return std::nullopt;
            for (const ShapeSpec& m : spec.prototypes[sh.prototype].shapes) {
                const auto mb = shape_bounds(spec, m, m.object_to_world);
                if (!mb) return std::nullopt;
                b.add(*mb);
            }
            break;
        }
    }
    if (b.empty()) return std::nullopt;
    return transformed(to_world, b);
}

// Calls f(material) for every material a shape's surfaces may show: its own, and its CSG or
// instance members' (a member that inherits shows the material of what contains it).
template <class F>
void shape_materials(const SceneSpec& spec, const ShapeSpec& sh, uint32_t material, const F& f) {
    if (sh.kind == ShapeKind::Instance) {
        if (sh.prototype >= spec.prototypes.size()) return;
        for (const ShapeSpec& m : spec.prototypes[sh.prototype].shapes)
            shape_materials(spec, m, m.material == kInheritMaterial ? material : m.material, f);
        return;
    }
    if (material < spec.materials.size()) f(spec.materials[material]);
    if (sh.kind == ShapeKind::Csg && sh.csg)
        for (const ShapeSpec& m : sh.csg->members)
            shape_materials(spec, m, m.material == kInheritMaterial ? material : m.material, f);
}

bool focuses(const MaterialSpec& m) {
    return m.reflection > 0 || m.transmission > 0;
}
bool receives(const MaterialSpec& m) {
    return (1.0 - m.transmission) * m.diffuse > 0;
}

double luminance(const Color& c) {
    return (c.x + c.y + c.z) / 3.0;
}

struct Target {
    Vec3 centre;
    double radius;
};

// The cone from o to a target's sphere: its axis, the cosine of its half-angle (−1: the whole
// sphere of directions) and its solid angle.
struct Cone {
    Vec3 axis{0, 1, 0};
    double cos_half = -1;
    double solid_angle = 4 * kPi;
};

Cone cone_to(const Vec3& o, const Target& t) {
    Cone c;
    const Vec3 d = t.centre - o;
    const double dist = glm::length(d);
    if (!(dist > t.radius)) return c;
    c.axis = d / dist;
    const double s = t.radius / dist;
    c.cos_half = std::sqrt(std::max(0.0, 1.0 - s * s));
    // 1 − cos α = s² / (1 + cos α), without cancellation for far targets.
    c.solid_angle = 2 * kPi * (s * s / (1.0 + c.cos_half));
    return c;
}

// A direction uniform over the cone's solid angle from (u, v) ∈ [0, 1)².
Vec3 sample_cone(const Cone& c, Uniform2 u) {
    const double one_minus = u.u * (c.cos_half < -0.5 ? 2.0 : (1.0 - c.cos_half));
    const double cos_t = 1.0 - one_minus;
    const double sin_t = std::sqrt(std::max(0.0, one_minus * (2.0 - one_minus)));
    const double phi = 2 * kPi * u.v;
    const Vec3 w = c.axis;
    const Vec3 a = std::abs(w.x) > 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
    const Vec3 x = glm::normalize(glm::cross(a, w));
    const Vec3 y = glm::cross(w, x);
    return glm::normalize(sin_t * std::cos(phi) * x + sin_t * std::sin(phi) * y + cos_t * w);
}

Color absorb(const Material& m, double distance) {
    if (!m.absorbs) return Color(1);
    return glm::exp(-m.absorption * distance);
}

// One light's share of the photons: how many go to each target.
struct LightPlan {
    size_t light;
    std::vector<size_t> counts;   // per target
    size_t first = 0, total = 0;  // global photon indices [first, first + total)
};

class Shooter {
public:
    Shooter(const Scene& scene, std::vector<Target> targets, std::vector<LightPlan> plans)
        : scene_(scene),
          geom_(scene.geometry()),
          targets_(std::move(targets)),
          plans_(std::move(plans)),
          seed_key_(mix64(uint64_t(scene.settings().seed) + kPhotonSalt)),
          max_depth_(scene.settings().max_depth) {}

    // Photon i: appended to `out` wherever it lands on a diffuse surface.
    void shoot(size_t i, std::vector<Photon>& out, RayStats& stats) const {
        const LightPlan* plan = &plans_.front();
        for (const LightPlan& p : plans_)
            if (i >= p.first && i < p.first + p.total) plan = &p;
        size_t local = i - plan->first, target = 0;
        while (local >= plan->counts[target]) local -= plan->counts[target++];
        const Light& light = scene_.lights()[plan->light];
        const uint64_t key = mix64(seed_key_ ^ uint64_t(i));
        auto draw = [key](uint64_t n) { return uniform2(mix64(key ^ (n * kBranchSalt))); };

        Vec3 o = light.position;
        if (light.area) {
            const Uniform2 u = draw(1);
            o = light.corner + (u.u * double(light.nu)) * light.du + (u.v * double(light.nv)) * light.dv;
        }
        const Vec3 dir = sample_cone(cone_to(o, targets_[target]), draw(2));
        // Photons per steradian along dir, summed over every target whose cone holds it.
        double density = 0;
        for (size_t k = 0; k < targets_.size(); ++k) {
            if (plan->counts[k] == 0) continue;
            const Cone c = cone_to(o, targets_[k]);
            if (k == target || glm::dot(dir, c.axis) >= c.cos_half)
                density += double(plan->counts[k]) / c.solid_angle;
        }
        Color power = light.radiance;
        if (light.spot) power *= spot_factor(light, -dir);
        if (!(luminance(power) > 0) || !(density > 0)) return;

        Ray ray{o, dir};
        int medium = -1;
        for (int depth = 0;; ++depth) {
            const auto hit = geom_.intersect(ray, kInf, stats, RayFilter::All);
            if (!hit) return;
            const SurfaceHit s = geom_.surface(ray, *hit);
            const Material& m = scene_.materials()[s.material];
            const bool front = glm::dot(ray.d, s.ng) < 0;
            if (depth == 0) {
                if (!(m.reflection > 0) && !(m.transmission > 0)) return;  // the direct term's
                power *= hit->t * hit->t / density;
                // A light inside a transmissive object: the photon travelled inside it.
                if (m.transmission > 0 && !front) medium = int(s.material);
            } else if (medium >= 0) {
                power *= absorb(scene_.materials()[size_t(medium)], hit->t);
            }
            const Vec3 ng_v = front ? s.ng : -s.ng;
            const Color c = m.texture ? m.texture->eval(s, stats) : m.color;
            const double t = m.transmission;
            if (depth > 0 && (1.0 - t) * m.diffuse > 0) {
                out.push_back({s.p, Vec3f(power), Vec3f(ng_v)});
            }
            if (depth >= max_depth_ || (!(m.reflection > 0) && !(t > 0))) return;

            // The tracer's reflection and refraction directions and weights.
            const Vec3 N = glm::dot(s.ns, ng_v) < 0 ? -s.ns : s.ns;
            Vec3 refl = reflect(ray.d, N);
            double fresnel = 0;
            bool refracts = false;
            Vec3 refr{0};
            if (t > 0) {
                const double eta = front ? 1.0 / m.ior : m.ior;
                FresnelResult fr = fresnel_refract(ray.d, N, eta);
                if (N != ng_v && (glm::dot(refl, ng_v) <= 0 ||
                                  (!fr.total_internal && glm::dot(fr.refracted, ng_v) >= 0))) {
                    refl = reflect(ray.d, ng_v);
                    fr = fresnel_refract(ray.d, ng_v, eta);
                }
                fresnel = fr.reflectance;
                refracts = !fr.total_internal;
                refr = fr.refracted;
            } else if (glm::dot(refl, ng_v) <= 0) {
                refl = reflect(ray.d, ng_v);
            }
            const double w_refl = m.reflection + t * fresnel;
            const Color w_refr = refracts ? t * (1.0 - fresnel) * c : Color(0);
            const double p_refl = std::max(0.0, w_refl), p_refr = std::max(0.0, luminance(w_refr));
            const double scale = std::max(1.0, p_refl + p_refr);
            const double u = draw(3 + uint64_t(depth)).u * scale;
            Vec3 next;
            if (u < p_refl) {
                power *= w_refl * (scale / p_refl);
                next = refl;
            } else if (u < p_refl + p_refr) {
                power *= w_refr * (scale / p_refr);
                next = refr;
                medium = front ? int(s.material) : -1;  // media do not nest, as in the tracer
            } else {
                return;
            }
            if (!(luminance(power) > 0) || !finite3(power)) return;
            ray = Ray{Geometry::offset_origin(s, next), next};
        }
    }

private:
    const Scene& scene_;
    const Geometry& geom_;
    std::vector<Target> targets_;
    std::vector<LightPlan> plans_;
    uint64_t seed_key_;
    int max_depth_;
};

// Splits n photons over weights: floor of each share, then one more to the largest remainders
// (the earliest first among equal ones).
std::vector<size_t> apportion(size_t n, const std::vector<double>& weights) {
    double total = 0;
    for (double w : weights) total += w;
    std::vector<size_t> out(weights.size(), 0);
    if (!(total > 0)) return out;
    std::vector<std::pair<double, size_t>> rest;
    size_t given = 0;
    for (size_t i = 0; i < weights.size(); ++i) {
        const double share = double(n) * (weights[i] / total);
        out[i] = size_t(std::floor(share));
        given += out[i];
        rest.push_back({share - double(out[i]), i});
    }
    std::stable_sort(rest.begin(), rest.end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    for (size_t k = 0; given < n && k < rest.size(); ++k, ++given) ++out[rest[k].second];
    return out;
}

}  // namespace

CausticObjects caustic_objects(const SceneSpec& spec) {
    CausticObjects out;
    for (size_t i = 0; i < spec.shapes.size(); ++i) {
        const ShapeSpec& sh = spec.shapes[i];
        bool focus = false, receive = false;
        shape_materials(spec, sh, sh.material, [&](const MaterialSpec& m) {
            focus = focus || focuses(m);
            receive = receive || receives(m);
        });
        if (focus)
            (shape_bounds(spec, sh, sh.object_to_world) ? out.focusing : out.unbounded)
                .push_back(uint32_t(i));
        if (receive) out.receiving.push_back(uint32_t(i));
    }
    return out;
}

std::string caustics_skipped(const SceneSpec& spec, const CausticObjects& objects) {
    bool lit = false;
    for (const LightSpec& l : spec.lights) lit = lit || (l.intensity > 0 && luminance(l.color) > 0);
    if (!lit) return "no light";
    if (objects.focusing.empty())
        return objects.unbounded.empty() ? "no object can focus light" : "no bounded object can focus light";
    if (objects.receiving.empty()) return "no diffuse surface can receive light";
    return {};
}

CausticBuild build_caustics(const Scene& scene, const SceneSpec& spec, int threads,
                            const std::atomic<bool>* cancel) {
    const auto start = std::chrono::steady_clock::now();
    CausticBuild build;
    const size_t n = size_t(spec.settings.caustic_photons);
    if (n == 0) return build;
    const CausticObjects objects = caustic_objects(spec);
    build.skipped = caustics_skipped(spec, objects);
    if (!build.skipped.empty()) return build;

    std::vector<Box> boxes;
    for (uint32_t i : objects.focusing)
        boxes.push_back(*shape_bounds(spec, spec.shapes[i], spec.shapes[i].object_to_world));
    if (boxes.size() > kMaxTargets) {
        Box all;
        for (const Box& b : boxes) all.add(b);
        boxes.assign(1, all);
    }
    std::vector<Target> targets;
    for (const Box& b : boxes) {
        const Vec3 c = 0.5 * (b.lo + b.hi);
        // A little larger than the half-diagonal: rounding never leaves the object's edge outside.
        targets.push_back({c, 0.5 * glm::length(b.hi - b.lo) * (1 + 1e-6) + 1e-9});
    }
    // A sphere's own bound is tighter than its box's (√3 times smaller: three times the photons
    // reach it): its centre and its radius times the transform's largest stretch.
    if (targets.size() == objects.focusing.size()) {
        for (size_t k = 0; k < targets.size(); ++k) {
            const ShapeSpec& sh = spec.shapes[objects.focusing[k]];
            if (sh.kind != ShapeKind::Sphere) continue;
            const Mat4& m = sh.object_to_world;
            const double stretch =
                std::max({glm::length(Vec3(m[0])), glm::length(Vec3(m[1])), glm::length(Vec3(m[2]))});
            const Target own{Vec3(m * glm::dvec4(sh.center, 1.0)), sh.radius * stretch * (1 + 1e-6) + 1e-9};
            if (own.radius < targets[k].radius) targets[k] = own;
        }
    }

    // The budget over (light, target) pairs by light colour × intensity × solid angle.
    const auto& lights = scene.lights();
    std::vector<double> weights;
    for (const Light& l : lights)
        for (const Target& t : targets)
            weights.push_back(luminance(l.radiance) * cone_to(l.position, t).solid_angle);
    const std::vector<size_t> counts = apportion(n, weights);
    std::vector<LightPlan> plans;
    size_t first = 0;
    for (size_t li = 0; li < lights.size(); ++li) {
        LightPlan p{li, {}, first, 0};
        for (size_t k = 0; k < targets.size(); ++k) {
            p.counts.push_back(counts[li * targets.size() + k]);
            p.total += p.counts.back();
        }
        first += p.total;
        if (p.total > 0) plans.push_back(std::move(p));
    }
    if (plans.empty()) {
        build.skipped = "no light";
        return build;
    }

    const Shooter shooter(scene, targets, plans);
    const size_t chunks = (n + kChunk - 1) / kChunk;
    std::vector<std::vector<Photon>> stored(chunks);
    ParallelOptions options;
    options.threads = threads;
    options.cancel = cancel;
    if (!parallel_for(chunks, options, [&](size_t c, int) {
            RayStats stats;  // photon rays are not the render's
            for (size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i)
                shooter.shoot(i, stored[c], stats);
        })) {
        build.cancelled = true;
        return build;
    }
    std::vector<Photon> all;
    for (auto& v : stored) all.insert(all.end(), v.begin(), v.end());
    build.shot = n;
    build.stored = all.size();
    if (!all.empty()) {
        const int k = std::clamp(int(std::lround(std::sqrt(double(all.size())) / 4)), kMinGather, kMaxGather);
        double largest = 0;
        for (const Target& t : targets) largest = std::max(largest, t.radius);
        build.map = std::make_unique<PhotonMap>(std::move(all), k, kGatherRadius * largest);
    }
    build.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return build;
}

}  // namespace wsd::render
