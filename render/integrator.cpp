// Whitted `trace` exactly as wsd-language.md §4 writes it:
//   local  = (1 − t)·ambient·c + Σ_lights (1/n) Σ_s visible_s·light·[(1 − t)·c·diffuse·max(0, N·L_s)
//                                                                  + specular·max(0, R_s·V)^shininess]
//   colour = local + (r + t·F)·trace(reflected) + t·(1 − F)·c·trace(refracted)
// With caustic photons, local also holds (1 − t)·c·diffuse·E_caustic (photon_map.h).
// Specialised on two scene properties (template parameters): transmissive objects (coloured shadow
// transmittance, Fresnel, absorption) and adaptive area lights. The general tracer enables both and
// tests every runtime condition; the two give identical images because the specialised one only
// omits work whose result is exactly ×1 or +0.
#include "render/integrator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

#include "render/indirect.h"
#include "render/light_terms.h"
#include "render/media.h"
#include "render/photon_map.h"
#include "render/rect_light_integral.h"
#include "render/sampling.h"
#include "render/scene.h"
#include "render/sequence.h"
#include "render/shaft.h"

namespace wsd::render {

FresnelResult fresnel_refract(const Vec3& d, const Vec3& n, double eta) {
    FresnelResult out;
    const double cos_i = std::clamp(-glm::dot(d, n), -1.0, 1.0);
    if (eta == 1.0) {  // an interface between equal indices is invisible, exactly
        out.reflectance = 0;
        out.refracted = d;
        out.total_internal = false;
        return out;
    }
    const double sin2_t = eta * eta * std::max(0.0, 1.0 - cos_i * cos_i);
    if (sin2_t >= 1.0) return out;  // total internal reflection: F = 1
    const double cos_t = std::sqrt(std::max(0.0, 1.0 - sin2_t));
    const double rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    const double rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    out.reflectance = 0.5 * (rs * rs + rp * rp);
    const Vec3 t = eta * d + (eta * cos_i - cos_t) * n;
    out.refracted = t * (1.0 / std::sqrt(glm::dot(t, t)));
    out.total_internal = false;
    return out;
}

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// A shadow ray follows at most this many transmissive surfaces before it counts as blocked (only
// reached by pathological stacks of glass; it bounds the loop, it is not a tolerance).
constexpr int kMaxShadowCrossings = 1024;

struct Path {
    uint64_t key;
    int depth;           // reflections and refractions so far
    Vec3 weight;         // product of the coefficients along the path
    int medium;          // material index of the transmissive object the ray travels in, or −1
    uint64_t seq = 0;    // with sampled lights: the pixel half's sequence key for this branch
    uint32_t index = 0;  // and the sample's index in it
};

// kLight: 0 = no emission anywhere; 1 = emission, seen only; 2 = indirect light (indirect.h).
template <bool kTransmissive, bool kAdaptive, int kLight = 0>
class WhittedTracer final : public Tracer {
    // A shadow ray's transmittance: RGB when light can pass through glass, else 0 or 1.
    using Vis = std::conditional_t<kTransmissive, Color, double>;

public:
    WhittedTracer(const Scene& scene, const TracerOptions& options, RayStats& stats)
        : scene_(scene),
          geom_(scene.geometry()),
          materials_(scene.materials()),
          lights_(scene.lights()),
          stats_(stats),
          force_adaptive_(options.adaptive_lights),
          max_depth_(scene.settings().max_depth),
          bailout_(scene.settings().bailout),
          background_(scene.settings().background),
          indirect_(scene, stats, *this),
          caustics_(scene.caustics()),
          exact_area_(scene.settings().exact_area_lights),
          sampled_lights_(options.sampled_lights) {
        size_t most = 0;
        for (const Light& l : lights_) most = std::max(most, size_t(l.count()));
        cells_.resize(most);
        if constexpr (kAdaptive) {
            vis_.resize(most);
            state_.resize(most);
        }
    }

    Color camera_sample(double px, double py, uint64_t key) override {
        ++stats_.camera_rays;
        return trace(scene_.camera().ray(px, py), Path{key, 0, Vec3(1), -1});
    }

    void camera_samples(const double* px, const double* py, const uint64_t* key, int n, Color* out) override {
        trace_packet(px, py, n, out, [key](int k) { return Path{key[k], 0, Vec3(1), -1}; });
    }

    void sequence_samples(const double* px, const double* py, const uint64_t* key, const uint64_t* seq,
                          const uint32_t* index, int n, Color* out) override {
        trace_packet(px, py, n, out, [=](int k) { return Path{key[k], 0, Vec3(1), -1, seq[k], index[k]}; });
    }

    Color trace_ray(const Ray& ray, uint64_t key) override {
        ++stats_.camera_rays;
        return trace(ray, Path{key, 0, Vec3(1), -1});
    }

    // The direct term at a hit that an indirect path reaches (V: towards where the path came from).
    Color lights(const SurfaceHit& s, const Material& m, const Vec3& N, const Vec3& V, const Color& c,
                 double t, uint64_t key) {
        return direct(s, m, N, V, c, t, key, nullptr);
    }

private:
    // The camera rays through (px[k], py[k]) intersected as one packet, each shaded along the
    // path path_of(k) starts.
    template <class PathOf>
    void trace_packet(const double* px, const double* py, int n, Color* out, PathOf path_of) {
        Ray rays[Geometry::kMaxPacket];
        std::optional<HitRecord> hits[Geometry::kMaxPacket];
        for (int k = 0; k < n; ++k) rays[k] = scene_.camera().ray(px[k], py[k]);
        stats_.camera_rays += uint64_t(n);
        geom_.intersect_packet(rays, n, kInfinity, stats_, hits);
        for (int k = 0; k < n; ++k) out[k] = trace_hit(rays[k], hits[k], path_of(k));
    }

    Color trace(const Ray& ray, const Path& path) {
        return trace_hit(ray, geom_.intersect(ray, kInfinity, stats_, RayFilter::All), path);
    }

    // The colour along a ray whose closest hit is known.
    Color trace_hit(const Ray& ray, const std::optional<HitRecord>& hit, const Path& path) {
        if (!hit) {
            if constexpr (kTransmissive) {
                if (path.medium >= 0) return background_ * absorb_forever(materials_[path.medium]);
            }
            return background_;
        }
        const SurfaceHit s = geom_.surface(ray, *hit);
        const Material& m = materials_[s.material];
        int medium = path.medium;
        if constexpr (kTransmissive) {
            // A ray with no known medium that reaches the inside of a transmissive surface was
            // travelling inside that (closed) object, e.g. a camera placed inside glass.
            if (medium < 0 && m.transmission > 0 && glm::dot(ray.d, s.ng) > 0) medium = int(s.material);
        }
        Color c = shade(ray, s, m, path, medium);
        if constexpr (kTransmissive) {
            if (medium >= 0) c *= absorb(materials_[medium], hit->t);
        }
        return c;
    }

    Color shade(const Ray& ray, const SurfaceHit& s, const Material& m, const Path& path, int medium) {
        const Vec3 V = -ray.d;
        // Inside/outside and every validity check use the geometric normal.
        const bool front = glm::dot(ray.d, s.ng) < 0;
        const Vec3 ng_v = front ? s.ng : -s.ng;
        Vec3 ns = s.ns;
        if (m.bump) ns = bump_normal(*m.bump, m.bump_strength, s, ns, scene_.object_to_world(s), stats_);
        // The shading normal, turned to the viewer's side of the surface.
        const Vec3 N = glm::dot(ns, ng_v) < 0 ? -ns : ns;
        const Color c = m.texture ? m.texture->eval(s, stats_) : m.color;
        const double t = m.transmission;
        const double r = m.reflection;

        Color colour = (1.0 - t) * m.ambient * c;
        if constexpr (kLight > 0) colour += m.emission;
        colour += direct(s, m, N, V, c, t, path.key, sampled_lights_ ? &path : nullptr);
        if constexpr (kLight == 2) {
            const Color rho = (1.0 - t) * m.diffuse * c;
            if (max_component(rho) > 0) colour += rho * indirect_.gather(s, N, path.key, medium);
        }
        if (caustics_) [[unlikely]]
            colour += caustic(s.p, ng_v, m, c, t);
        if (path.depth >= max_depth_ || (r <= 0 && t <= 0)) return colour;

        double fresnel = 0;
        Vec3 refl_dir{0}, refr_dir{0};
        bool refracts = false;
        if (kTransmissive && t > 0) {
            ++stats_.fresnel_evals;
            const double eta = front ? 1.0 / m.ior : m.ior;
            // A bent normal may not send the reflected ray below the surface or the refracted ray
            // to the viewer's side (robustness.md, consistent shading normals); if so, use ng instead.
            Vec3 n_use = glm::dot(N, V) > 0 ? N : ng_v;
            refl_dir = reflect(ray.d, n_use);
            FresnelResult fr = fresnel_refract(ray.d, n_use, eta);
            if (n_use != ng_v && (glm::dot(refl_dir, ng_v) <= 0 ||
                                  (!fr.total_internal && glm::dot(fr.refracted, ng_v) >= 0))) {
                refl_dir = reflect(ray.d, ng_v);
                fr = fresnel_refract(ray.d, ng_v, eta);
            }
            fresnel = fr.reflectance;
            refracts = !fr.total_internal;
            refr_dir = fr.refracted;
        } else {
            refl_dir = reflect(ray.d, N);
            if (glm::dot(refl_dir, ng_v) <= 0) refl_dir = reflect(ray.d, ng_v);
        }

        const double w_refl = r + t * fresnel;
        if (w_refl > 0) {
            const Vec3 w = path.weight * w_refl;
            if (max_component(w) >= bailout_) {
                ++stats_.reflection_rays;
                const Ray rr{Geometry::offset_origin(s, refl_dir), refl_dir};
                colour += w_refl * trace(rr, Path{branch_key(path.key, 1), path.depth + 1, w, medium,
                                                  branch_key(path.seq, 1), path.index});
            }
        }
        if constexpr (kTransmissive) {
            if (refracts && t > 0 && fresnel < 1) {
                const Color coef = t * (1.0 - fresnel) * c;
                const Vec3 w = path.weight * coef;
                const double wmax = max_component(w);
                if (wmax > 0 && wmax >= bailout_) {
                    ++stats_.refraction_rays;
                    const Ray tr{Geometry::offset_origin(s, refr_dir), refr_dir};
                    // Media do not nest: entering puts the ray inside this object, leaving outside.
                    const int inside = front ? int(s.material) : -1;
                    colour += coef * trace(tr, Path{branch_key(path.key, 2), path.depth + 1, w, inside,
                                                    branch_key(path.seq, 2), path.index});
                }
            }
        }
        return colour;
    }

    // Σ_lights (1/n) Σ_s visible_s·light·[(1 − t)·c·diffuse·max(0, N·L_s) + specular·max(0, R_s·V)^p]
    // With `sampled` (progressive rendering), each area light's cell sum is estimated from one
    // point of the light instead, point `index` of the path's stratified sequence for that light.
    Color direct(const SurfaceHit& s, const Material& m, const Vec3& N, const Vec3& V, const Color& c,
                 double t, uint64_t key, const Path* sampled) {
        const double kd = (1.0 - t) * m.diffuse;
        if (lights_.empty() || (!(kd > 0) && !(m.specular > 0))) return Color(0);
        Shading sh;
        sh.p = s.p;
        sh.ng = s.ng;
        sh.prim = s.prim;
        sh.ng_v = glm::dot(V, s.ng) > 0 ? s.ng : -s.ng;
        sh.opaque = !(t > 0);
        sh.N = N;
        sh.V = V;
        sh.nv = glm::dot(N, V);
        sh.diffuse = kd > 0;
        sh.specular = m.specular;
        sh.shininess = m.shininess;
        sh.o_front = Geometry::offset_origin(s, s.ng);
        sh.o_back = Geometry::offset_origin(s, -s.ng);

        Color sum(0);
        for (size_t li = 0; li < lights_.size(); ++li) {
            const Light& light = lights_[li];
            Vis sd(0), ss(0);
            if (light.spot) [[unlikely]] {
                spot_light(sh, light, sd, ss);
            } else if (!light.area) {
                const Vec3 to_light = light.position - sh.p;
                const Term term = sample_term(sh, to_light);
                if (term.needed) {
                    const Vis v = visibility(sh, to_light, light.position);
                    sd += v * term.nl;
                    ss += v * term.sp;
                }
            } else {
                if (sampled) {
                    sampled_area(sh, light, sobol2(sampled->index, light_key(sampled->seq, uint32_t(li))), sd,
                                 ss);
                    sum += light.radiance * (kd * c * sd + m.specular * ss) * light.inv_count;
                    continue;
                }
                use_shaft_ = light.count() >= kShaftMinSamples && gather_shaft(sh, light);
                if (exact_area_ && use_shaft_ &&
                    exact_area(sh, light, light_key(key, uint32_t(li)), sd, ss)) {
                    // the closed form and the specular cells
                } else if (kAdaptive && (light.adaptive || force_adaptive_) && light.count() > 1)
                    adaptive_area(sh, light, light_key(key, uint32_t(li)), sd, ss);
                else
                    full_area(sh, light, light_key(key, uint32_t(li)), sd, ss);
                use_shaft_ = false;
            }
            sum += light.radiance * (kd * c * sd + m.specular * ss) * light.inv_count;
        }
        return sum;
    }

    // Caustic light on a diffuse surface: (1 − t)·c·diffuse times the photon map's irradiance,
    // as the direct term weighs a light's. Out of line: scenes without caustics run their code.
    [[gnu::noinline]] Color caustic(const Vec3& p, const Vec3& ng_v, const Material& m, const Color& c,
                                    double t) {
        const double kd = (1.0 - t) * m.diffuse;
        if (!(kd > 0)) return Color(0);
        return kd * c * caustics_->irradiance(p, ng_v, stats_);
    }

    // A spot light: a point light whose terms its cone scales (spot_factor); outside the cone it
    // needs no shadow ray. Out of line, so that scenes without spot lights run the code they ran.
    [[gnu::noinline]] void spot_light(const Shading& sh, const Light& light, Vis& sd, Vis& ss) {
        const Vec3 to_light = light.position - sh.p;
        const double cone = spot_factor(light, to_light);
        if (!(cone > 0)) return;
        const Term term = sample_term(sh, to_light);
        if (!term.needed) return;
        const Vis v = visibility(sh, to_light, light.position);
        sd += v * (term.nl * cone);
        ss += v * (term.sp * cone);
    }

    Vec3 cell_point(const Light& light, uint64_t lkey, int i, int j) const {
        const uint32_t cell = uint32_t(j * light.nu + i);
        const Uniform2 xi = cell_offset(light, lkey, cell);
        return light.cell_point(i, j, xi.u, xi.v);
    }

    // settings.exact_area_lights: where the shaft proves every shadow ray reaches the light and
    // the whole light lies above the tangent plane (and on the viewer's side of an opaque
    // surface), the diffuse sum is count × the exact average of N·L over the light, the limit of
    // the jittered cell sum; the specular term is still summed over the cells, where the
    // material has one and its lobe can reach the light (specular_lobe_reaches). False elsewhere.
    bool exact_area(const Shading& sh, const Light& light, uint64_t lkey, Vis& sd, Vis& ss) {
        if (shaft_.blocked || shaft_.count != 0 || (kTransmissive && shaft_.transmissive)) return false;
        const Vec3 u = light.du * double(light.nu), v = light.dv * double(light.nv);
        for (const Vec3& q : {light.corner, light.corner + u, light.corner + v, light.corner + u + v}) {
            const Vec3 d = q - sh.p;
            if (!(glm::dot(sh.N, d) >= 0) || (sh.opaque && !(glm::dot(sh.ng_v, d) > 0))) return false;
        }
        const double avg = rect_light_average_cosine(sh.p, sh.N, light.corner, u, v);
        if (!std::isfinite(avg)) return false;
        if (sh.diffuse) sd += Vis(avg * double(light.count()));
        if (sh.specular > 0 && specular_lobe_reaches(sh, light.corner, u, v)) {
            const int n = cells_.prepare(sh, light, lkey);
            uint64_t rays = 0;
            for (int k = 0; k < n; ++k) {
                const Term t = cells_.term(sh, k);
                if (!(t.sp > 0)) continue;
                ++rays;
                ss += Vis(t.sp);
            }
            stats_.shadow_rays += rays;
            stats_.shaft_answered_rays += rays;
        }
        return true;
    }

    // One point of an area light for the whole cell sum: xi ∈ [0, 1)² over the whole light (a
    // jittered grid's cell sum converges to this integral; a uniform grid's takes its cell's
    // centre), with one shadow ray. Neither the closed form (exact_area_lights) nor adaptive
    // sampling applies: the shaft that proves a point fully lit costs more than the one ray.
    void sampled_area(const Shading& sh, const Light& light, Uniform2 xi, Vis& sd, Vis& ss) {
        double s = xi.u * double(light.nu), t = xi.v * double(light.nv);
        if (light.uniform) {
            s = std::floor(s) + 0.5;
            t = std::floor(t) + 0.5;
        }
        const Vec3 P = light.corner + s * light.du + t * light.dv;
        const Term term = sample_term(sh, P - sh.p);
        if (!term.needed) return;
        const double n = double(light.count());
        const Vis v = visibility(sh, P - sh.p, P);
        sd += v * (term.nl * n);
        ss += v * (term.sp * n);
    }

    void full_area(const Shading& sh, const Light& light, uint64_t lkey, Vis& sd, Vis& ss) {
        const int n = cells_.prepare(sh, light, lkey);
        auto term = [&](int k) { return cells_.term(sh, k); };
        if (use_shaft_ &&
            (shaft_.blocked || (shaft_.count == 0 && !(kTransmissive && shaft_.transmissive)))) {
            // The shaft knows every ray's answer: 0 (the sums stay as they are) or 1.
            const bool lit = !shaft_.blocked;
            uint64_t rays = 0;
            for (int k = 0; k < n; ++k) {
                const Term t = term(k);
                if (!t.needed) continue;
                ++rays;
                if (lit) {
                    sd += Vis(t.nl);
                    ss += Vis(t.sp);
                }
            }
            stats_.shadow_rays += rays;
            stats_.shaft_answered_rays += rays;
            return;
        }
        for (int k = 0; k < n; ++k) {
            const Term t = term(k);
            if (!t.needed) continue;
            const Vec3 P = cells_.point(k);
            const Vis v = visibility(sh, P - sh.p, P);
            sd += v * t.nl;
            ss += v * t.sp;
        }
    }

    // Adaptive sampling, as POV-Ray's `adaptive`: shadow rays to the four corner cells and the
    // centre cell; if they agree, their visibility stands for every cell. Otherwise the grid is
    // refined recursively: a sub-rectangle whose four corner cells agree takes their visibility,
    // one whose corners disagree is split in two along each side longer than two cells. The
    // shading terms are then summed over every cell's own direction, in the same order as
    // full_area, so fully lit and fully shadowed points give exactly the full grid's value.
    void adaptive_area(const Shading& sh, const Light& light, uint64_t lkey, Vis& sd, Vis& ss) {
        const int nu = light.nu, nv = light.nv;
        std::fill(state_.begin(), state_.begin() + light.count(), uint8_t(0));
        auto probe = [&](int i, int j) -> const Vis& {
            const size_t cell = size_t(j * nu + i);
            if (state_[cell] != kProbed) {
                const Vec3 P = cell_point(light, lkey, i, j);
                vis_[cell] = visibility(sh, P - sh.p, P);
                state_[cell] = kProbed;
            }
            return vis_[cell];
        };
        const Vis a = probe(0, 0);
        const bool agree = probe(nu - 1, 0) == a && probe(0, nv - 1) == a && probe(nu - 1, nv - 1) == a &&
                           probe(nu / 2, nv / 2) == a;
        if (agree)
            fill(nu, 0, 0, nu - 1, nv - 1, a);
        else
            refine(probe, nu, 0, 0, nu - 1, nv - 1);
        const int n = cells_.prepare(sh, light, lkey);
        for (int k = 0; k < n; ++k) {
            const Term term = cells_.term(sh, k);
            if (!term.needed) continue;
            const Vis& v = vis_[size_t(k)];
            sd += v * term.nl;
            ss += v * term.sp;
        }
    }

    template <class Probe>
    void refine(Probe& probe, int nu, int i0, int j0, int i1, int j1) {
        // All four corners are probed (no short-circuit): a region of at most 2×2 cells is
        // then complete.
        const Vis a = probe(i0, j0), b = probe(i1, j0), c = probe(i0, j1), d = probe(i1, j1);
        if (b == a && c == a && d == a) {
            fill(nu, i0, j0, i1, j1, a);
            return;
        }
        if (i1 - i0 <= 1 && j1 - j0 <= 1) return;  // every cell is a corner
        const int im = (i0 + i1) / 2, jm = (j0 + j1) / 2;
        const bool split_i = i1 - i0 >= 2, split_j = j1 - j0 >= 2;
        const int is[3] = {i0, split_i ? im : i1, i1};
        const int js[3] = {j0, split_j ? jm : j1, j1};
        for (int jb = 0; jb < (split_j ? 2 : 1); ++jb)
            for (int ib = 0; ib < (split_i ? 2 : 1); ++ib)
                refine(probe, nu, is[ib], js[jb], split_i ? is[ib + 1] : i1, split_j ? js[jb + 1] : j1);
    }

    // Cells not probed yet take the visibility of the region's agreeing corners.
    void fill(int nu, int i0, int j0, int i1, int j1, const Vis& v) {
        for (int j = j0; j <= j1; ++j) {
            for (int i = i0; i <= i1; ++i) {
                const size_t cell = size_t(j * nu + i);
                if (state_[cell] == kUnknown) {
                    vis_[cell] = v;
                    state_[cell] = kFilled;
                }
            }
        }
    }

    // The opaque primitives that any shadow ray from this point to the light may meet, when
    // there are few of them: one BVH walk instead of one a sample.
    bool gather_shaft(const Shading& sh, const Light& light) {
        const double radius = std::max(glm::length(sh.o_front - sh.p), glm::length(sh.o_back - sh.p));
        const Vec3 u = light.du * double(light.nu), v = light.dv * double(light.nv);
        Shaft shaft;
        if (!shaft.init(sh.p, radius, light.corner, u, v)) return false;
        ShaftSelf self;
        self.prim = sh.prim;
        self.ng = sh.ng;
        // When the whole light lies clearly on one side of the surface, every shadow ray starts
        // at the same origin (visibility() picks it by the same sign), and the shaft can clear
        // primitives by which side of them that origin and the light lie on.
        const int side = surface_side(sh.p, sh.ng, light.corner, u, v);
        if (side != 0) {
            shaft.set_origin(side > 0 ? sh.o_front : sh.o_back);
            self.ng_side = side;
        }
        return shaft_.gather(geom_, shaft, self, stats_);
    }

    // The shadow ray from the spawn origin on the light's side to P (d = P − origin, tmax = 1).
    Vis visibility(const Shading& sh, const Vec3& to_light, const Vec3& P) {
        const Vec3 origin = glm::dot(to_light, sh.ng) < 0 ? sh.o_back : sh.o_front;
        const Ray ray{origin, P - origin};
        ++stats_.shadow_rays;
        bool blocked;
        if (!use_shaft_) {
            blocked = geom_.occluded(ray, 1.0, stats_, RayFilter::OpaqueOnly);
        } else if (shaft_.blocked || shaft_.count == 0) {
            ++stats_.shaft_answered_rays;  // the shaft knows the answer: no test needed
            blocked = shaft_.blocked;
        } else {
            blocked = shaft_.occluded(geom_, ray, 1.0, stats_);
        }
        if (blocked) return Vis(0);
        if constexpr (kTransmissive) {
            // Nor transmissive: the light arrives unfiltered (transmittance() would find no hit).
            if (use_shaft_ && !shaft_.transmissive) return Color(1);
            if (!scene_.may_cross_transmissive(origin, P)) return Color(1);
            return transmittance(origin, P);
        } else {
            return 1.0;
        }
    }

    // Light passing through transmissive surfaces, unbent: ×t·c at each surface crossed and
    // Beer–Lambert absorption along each segment inside an object.
    Color transmittance(const Vec3& origin, const Vec3& P) {
        Color T(1);
        Vec3 cur = origin, seg_start = origin;
        int inside = -1;  // the object entered last, if its exit has not been crossed yet
        for (int k = 0; k < kMaxShadowCrossings; ++k) {
            const Ray ray{cur, P - cur};
            ++stats_.shadow_rays;
            // Every segment lies inside the shaft: its list, when there is one, is complete.
            const auto hit = use_shaft_ && shaft_.transmissive_listed
                                 ? shaft_.intersect_transmissive(geom_, ray, 1.0, stats_)
                                 : geom_.intersect(ray, 1.0, stats_, RayFilter::TransmissiveOnly);
            if (!hit) {
                if (inside >= 0) T *= absorb(materials_[inside], glm::length(P - seg_start));
                return T;
            }
            const SurfaceHit s = geom_.surface(ray, *hit);
            const Material& m = materials_[s.material];
            const Color c = m.texture ? m.texture->eval(s, stats_) : m.color;
            T *= m.transmission * c;
            if (glm::dot(ray.d, s.ng) > 0) {  // leaving the object: the segment was inside it
                T *= absorb(m, glm::length(s.p - seg_start));
                inside = -1;
            } else {
                seg_start = s.p;
                inside = int(s.material);
            }
            if (T == Color(0)) return T;
            cur = Geometry::offset_origin(s, ray.d);
        }
        return Color(0);
    }

    // Area lights with fewer samples trace each shadow ray in full (gathering costs about one).
    static constexpr int kShaftMinSamples = 4;
    ShaftCandidates shaft_;  // valid while use_shaft_
    bool use_shaft_ = false;

    static constexpr uint8_t kUnknown = 0, kFilled = 1, kProbed = 2;

    const Scene& scene_;
    const Geometry& geom_;
    const std::vector<Material>& materials_;
    const std::vector<Light>& lights_;
    RayStats& stats_;
    bool force_adaptive_;
    int max_depth_;
    double bailout_;
    Color background_;
    IndirectGather<WhittedTracer> indirect_;  // used when kLight == 2
    const PhotonMap* caustics_;               // null without caustics
    bool exact_area_;                         // settings.exact_area_lights
    bool sampled_lights_;                     // TracerOptions::sampled_lights
    LightCells cells_;                        // area lights: the current point's cells and their terms
    std::vector<Vis> vis_;                    // adaptive lights: per-cell visibility of the current point
    std::vector<uint8_t> state_;              // adaptive lights: kUnknown, kFilled or kProbed per cell
};

}  // namespace

std::unique_ptr<Tracer> make_tracer(const Scene& scene, const TracerOptions& options, RayStats& stats) {
    // Emission and indirect light take the general tracer (their cost is elsewhere).
    if (scene.settings().indirect_samples > 0)
        return std::make_unique<WhittedTracer<true, true, 2>>(scene, options, stats);
    if (scene.effects().has(Effect::Emission))
        return std::make_unique<WhittedTracer<true, true, 1>>(scene, options, stats);
    if (!options.specialise) return std::make_unique<WhittedTracer<true, true>>(scene, options, stats);
    const bool transmissive = scene.geometry().has_transmissive() || scene.effects().has(Effect::Refraction);
    const bool adaptive = scene.effects().has(Effect::AdaptiveLights) ||
                          (options.adaptive_lights && scene.has_multi_cell_area_light());
    if (transmissive && adaptive) return std::make_unique<WhittedTracer<true, true>>(scene, options, stats);
    if (transmissive) return std::make_unique<WhittedTracer<true, false>>(scene, options, stats);
    if (adaptive) return std::make_unique<WhittedTracer<false, true>>(scene, options, stats);
    return std::make_unique<WhittedTracer<false, false>>(scene, options, stats);
}

}  // namespace wsd::render
