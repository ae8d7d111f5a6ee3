// Emitters: world-space sampling of emissive spheres, boxes, triangles, meshes and discs.
#include "render/emitters.h"

#include <algorithm>
#include <cmath>

#include "render/math.h"

namespace wsd::render {

namespace {

// A sampled point and the intersected surface are computed along different roundings (and the
// intersection through the shape's transform): the bound allows for both, relative to the size
// of the coordinates involved, far above either rounding and far below any feature of a scene.
constexpr double kRelError = 1e-9;

double mean(const Color& c) {
    return (c.x + c.y + c.z) / 3.0;
}

Vec3 apply(const Mat4& m, const Vec3& p) {
    return Vec3(m * glm::dvec4(p, 1.0));
}

Vec3 apply_dir(const Mat4& m, const Vec3& d) {
    return Vec3(m * glm::dvec4(d, 0.0));
}

// The scale of a matrix that scales every direction alike (a similarity), else nullopt: only then
// is a sphere's image a sphere.
std::optional<double> uniform_scale(const Mat4& m) {
    const Vec3 c0 = apply_dir(m, {1, 0, 0}), c1 = apply_dir(m, {0, 1, 0}), c2 = apply_dir(m, {0, 0, 1});
    const double l0 = glm::length(c0), l1 = glm::length(c1), l2 = glm::length(c2);
    const double tol = 1e-9 * l0;
    if (std::abs(l1 - l0) > tol || std::abs(l2 - l0) > tol) return std::nullopt;
    if (std::abs(glm::dot(c0, c1)) > tol * l0 || std::abs(glm::dot(c0, c2)) > tol * l0 ||
        std::abs(glm::dot(c1, c2)) > tol * l0)
        return std::nullopt;
    return l0;
}

// Two unit vectors perpendicular to the unit vector n and to each other.
void frame(const Vec3& n, Vec3& u, Vec3& v) {
    const Vec3 a = std::abs(n.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    u = glm::normalize(glm::cross(n, a));
    v = glm::cross(n, u);
}

// Index of the first cdf entry above u (u ∈ [0, 1)), within [first, first + n).
size_t pick(const std::vector<double>& cdf, size_t first, size_t n, double u) {
    const auto begin = cdf.begin() + std::ptrdiff_t(first);
    const auto it = std::upper_bound(begin, begin + std::ptrdiff_t(n), u);
    return std::min(size_t(it - cdf.begin()), first + n - 1);
}

}  // namespace

bool has_emission(const SceneSpec& spec) {
    for (const MaterialSpec& m : spec.materials)
        if (m.emission != Color(0)) return true;
    return false;
}

Emitters Emitters::build(const SceneSpec& spec, std::vector<SpecError>& errors) {
    Emitters out;
    out.shape_pdf_.assign(spec.shapes.size(), 0.0);
    if (!has_emission(spec)) return out;
    for (size_t i = 0; i < spec.shapes.size(); ++i) {
        const ShapeSpec& s = spec.shapes[i];
        if (s.material >= spec.materials.size()) continue;
        const Color e = spec.materials[s.material].emission;
        if (e == Color(0)) continue;
        const Mat4& m = s.object_to_world;
        Shape sh;
        sh.shape = uint32_t(i);
        sh.emission = e;
        auto add_tri = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
            const Vec3 e1 = b - a, e2 = c - a, x = glm::cross(e1, e2);
            const double len = glm::length(x);
            out.tris_.push_back({a, e1, e2, len > 0 ? x / len : Vec3(0)});
            out.tri_cdf_.push_back(0.5 * len);
        };
        switch (s.kind) {
            case ShapeKind::Sphere: {
                const auto scale = uniform_scale(m);
                if (!scale) continue;  // an ellipsoid: seen, not sampled
                sh.kind = Kind::Sphere;
                sh.center = apply(m, s.center);
                sh.radius = s.radius * *scale;
                sh.area = 4.0 * kPi * sh.radius * sh.radius;
                break;
            }
            case ShapeKind::Disc: {
                Vec3 u, v;
                frame(glm::normalize(s.normal), u, v);
                sh.kind = Kind::Disc;
                sh.center = apply(m, s.center);
                sh.du = apply_dir(m, u);
                sh.dv = apply_dir(m, v);
                const Vec3 x = glm::cross(sh.du, sh.dv);
                const double len = glm::length(x);
                sh.normal = len > 0 ? x / len : Vec3(0);
                sh.radius = s.radius;
                sh.hole = s.hole;
                sh.area = kPi * (s.radius * s.radius - s.hole * s.hole) * len;
                break;
            }
            case ShapeKind::Triangle:
            case ShapeKind::Box:
            case ShapeKind::Mesh: {
                sh.kind = Kind::Triangles;
                sh.first = out.tris_.size();
                if (s.kind == ShapeKind::Triangle) {
                    add_tri(apply(m, s.v[0]), apply(m, s.v[1]), apply(m, s.v[2]));
                } else if (s.kind == ShapeKind::Box) {
                    Vec3 c[8];
                    for (int k = 0; k < 8; ++k)
                        c[k] = apply(
                            m, {(k & 1) ? s.box_max.x : s.box_min.x, (k & 2) ? s.box_max.y : s.box_min.y,
                                (k & 4) ? s.box_max.z : s.box_min.z});
                    const int faces[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                             {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
                    for (const auto& f : faces) {
                        add_tri(c[f[0]], c[f[1]], c[f[2]]);
                        add_tri(c[f[0]], c[f[2]], c[f[3]]);
                    }
                } else if (s.mesh) {
                    const auto& vs = s.mesh->vertices;
                    for (const glm::uvec3& f : s.mesh->faces) {
                        if (f.x >= vs.size() || f.y >= vs.size() || f.z >= vs.size()) continue;
                        add_tri(apply(m, Vec3(vs[f.x])), apply(m, Vec3(vs[f.y])), apply(m, Vec3(vs[f.z])));
                    }
                }
                sh.n = out.tris_.size() - sh.first;
                double sum = 0;
                for (size_t k = sh.first; k < sh.first + sh.n; ++k) {
                    sum += out.tri_cdf_[k];
                    out.tri_cdf_[k] = sum;
                }
                for (size_t k = sh.first; k < sh.first + sh.n; ++k) out.tri_cdf_[k] /= sum;
                sh.area = sum;
                break;
            }
            default:
                continue;  // planes, cylinders, cones, tori, CSG solids, instances: seen, not sampled
        }
        if (!(sh.area > 0) || !std::isfinite(sh.area)) {
            errors.push_back(
                {SpecItem::Shape, i, s.tag,
                 std::string("an emissive ") + shape_word(s.kind) +
                     " must have a finite, non-zero area to be sampled as a light (its area is " +
                     (std::isfinite(sh.area) ? "0" : "not finite") + ")",
                 -1, "material"});
            continue;
        }
        out.shapes_.push_back(sh);
    }
    double total = 0;
    for (const Shape& sh : out.shapes_) {
        total += sh.area * mean(sh.emission);
        out.cdf_.push_back(total);
    }
    if (!(total > 0) || !std::isfinite(total)) {
        out.shapes_.clear();
        out.cdf_.clear();
        return out;
    }
    for (double& c : out.cdf_) c /= total;
    for (const Shape& sh : out.shapes_) out.shape_pdf_[sh.shape] = mean(sh.emission) / total;
    return out;
}

EmitterPoint Emitters::sample(double u0, double u1, double u2, double u3) const {
    const size_t k = pick(cdf_, 0, cdf_.size(), u0);
    const Shape& sh = shapes_[k];
    EmitterPoint out;
    out.emission = sh.emission;
    out.shape = sh.shape;
    out.pdf_area = shape_pdf_[sh.shape];
    switch (sh.kind) {
        case Kind::Sphere: {
            const double z = 1.0 - 2.0 * u1, r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = 2.0 * kPi * u2;
            out.n = {r * std::cos(phi), r * std::sin(phi), z};
            out.p = sh.center + sh.radius * out.n;
            out.p_error = kRelError * (glm::abs(sh.center) + Vec3(sh.radius));
            break;
        }
        case Kind::Disc: {
            const double r = std::sqrt(sh.hole * sh.hole + u1 * (sh.radius * sh.radius - sh.hole * sh.hole));
            const double phi = 2.0 * kPi * u2;
            out.p = sh.center + (r * std::cos(phi)) * sh.du + (r * std::sin(phi)) * sh.dv;
            out.n = sh.normal;
            out.p_error = kRelError * (glm::abs(sh.center) + sh.radius * (glm::abs(sh.du) + glm::abs(sh.dv)));
            break;
        }
        case Kind::Triangles: {
            const Tri& t = tris_[pick(tri_cdf_, sh.first, sh.n, u3)];
            const double su = std::sqrt(u1);  // uniform on the triangle
            const double b1 = 1.0 - su, b2 = u2 * su;
            out.p = t.a + b1 * t.e1 + b2 * t.e2;
            out.n = t.n;
            out.p_error = kRelError * (glm::abs(t.a) + glm::abs(t.e1) + glm::abs(t.e2));
            break;
        }
    }
    return out;
}

}  // namespace wsd::render
