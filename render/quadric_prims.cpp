// Cylinders, cones, tori and discs: validation, building, ray tests and surfaces. Each is stored
// in its canonical frame (render/quadric_prims.h), reached from world space by one composed
// transform, as boxes and non-similar spheres are; its crossings come from render/quadric_solve.h.
#include "render/quadric_prims.h"

#include <cmath>

#include "render/other_prims.h"
#include "render/quadric_solve.h"
#include "render/shapes.h"

namespace wsd::render {

namespace {

bool positive(double x) {
    return std::isfinite(x) && x > 0;
}

// The frame with +y along `axis` (unit) and +x the object's +x projected normal to it.
void set_axes(QuadricPrim& q, const Vec3& axis) {
    q.axis_y = axis;
    q.axis_x = plane_u_axis(axis);
    q.axis_z = glm::cross(q.axis_x, q.axis_y);
}

std::optional<std::string> axial(const ShapeSpec& s, QuadricPrim& q) {
    const std::string name = shape_word(s.kind);
    if (!is_finite(s.base) || !is_finite(s.cap)) return name + " base and cap must be finite";
    const Vec3 axis = s.cap - s.base;
    q.h = glm::length(axis);
    if (!(q.h > 0) || !std::isfinite(q.h)) return name + " 'base' and 'cap' must be different points";
    if (s.kind == ShapeKind::Cylinder) {
        if (!positive(s.radius)) return std::string("cylinder radius must be a positive number");
        q.r0 = q.r1 = s.radius;
    } else {
        if (!std::isfinite(s.radius) || !std::isfinite(s.cap_radius) || s.radius < 0 || s.cap_radius < 0)
            return std::string("cone radii must be finite and non-negative");
        if (s.radius == 0 && s.cap_radius == 0)
            return std::string("cone 'base_radius' and 'cap_radius' must not both be 0");
        q.r0 = s.radius;
        q.r1 = s.cap_radius;
    }
    q.open = s.open;
    q.origin = s.base;
    set_axes(q, axis / q.h);
    return std::nullopt;
}

// The canonical frame's extent: the box [-m, lo_y, -m] .. [m, hi_y, m].
void canonical_box(const QuadricPrim& q, double& m, double& lo_y, double& hi_y) {
    switch (q.kind) {
        case ShapeKind::Torus:
            m = q.r0 + q.r1;
            lo_y = -q.r1;
            hi_y = q.r1;
            return;
        case ShapeKind::Disc:
            m = q.r0;
            lo_y = hi_y = 0;
            return;
        default:
            m = std::max(q.r0, q.r1);
            lo_y = 0;
            hi_y = q.h;
            return;
    }
}

// u around the +y axis, as the sphere map's u (render/shapes.h: sphere_uv), in [0, 1).
double around(double x, double z) {
    double u = 0.5 + std::atan2(x, -z) / (2 * kPi);
    if (!(u < 1) || u < 0) u = 0;
    return u;
}

double clamp01(double v) {
    return v < 0 ? 0.0 : (v > 1 ? 1.0 : v);
}

// The point moved radially onto the circle of radius `target` around the y axis.
void onto_radius(Vec3& p, Vec3& e, double target) {
    const double rho = std::sqrt(p.x * p.x + p.z * p.z);
    if (rho > 0) {
        p.x *= target / rho;
        p.z *= target / rho;
    } else {
        p.x = target;
        p.z = 0;
    }
    e.x = gamma(6) * std::abs(p.x);
    e.z = gamma(6) * std::abs(p.z);
}

}  // namespace

std::optional<std::string> make_quadric(const ShapeSpec& s, QuadricPrim& q, Mat4& frame) {
    q.kind = s.kind;
    switch (s.kind) {
        case ShapeKind::Cylinder:
        case ShapeKind::Cone:
            if (auto problem = axial(s, q)) return problem;
            break;
        case ShapeKind::Torus:
            if (!positive(s.major)) return std::string("torus major radius must be a positive number");
            if (!positive(s.minor)) return std::string("torus minor radius must be a positive number");
            q.r0 = s.major;
            q.r1 = s.minor;
            q.h = 2 * s.minor;
            break;
        case ShapeKind::Disc: {
            if (!is_finite(s.center) || !is_finite(s.normal))
                return std::string("disc center and normal must be finite");
            const Vec3 n = safe_normalize(s.normal, Vec3(0));
            if (n == Vec3(0)) return std::string("disc 'normal' must not be the zero vector");
            if (!positive(s.radius)) return std::string("disc radius must be a positive number");
            if (!std::isfinite(s.hole) || s.hole < 0 || !(s.hole < s.radius))
                return std::string("disc 'hole' must be at least 0 and less than 'radius'");
            q.r0 = s.radius;
            q.r1 = s.hole;
            q.h = 0;
            q.origin = s.center;
            set_axes(q, n);
            break;
        }
        default:
            return std::string("not a cylinder, cone, torus or disc");
    }
    frame = Mat4(glm::dvec4(q.axis_x, 0), glm::dvec4(q.axis_y, 0), glm::dvec4(q.axis_z, 0),
                 glm::dvec4(q.origin, 1));
    return std::nullopt;
}

namespace detail {

bool test_quadric(const Impl& g, const QuadricPrim& q, const RayPre& r, double limit, Counters&,
                  HitRecord& h) {
    const Transform& x = g.xforms[q.xform];
    const Vec3 o = x.inv_point(r.o), d = x.inv_vector(r.d);
    const Vec3 oe = x.inv_point_error(r.o) + q.band;
    Crossing cr[kMaxCrossings];
    const int n = line_crossings(q, o, d, oe, cr);
    for (int i = 0; i < n; ++i) {
        if (!(cr[i].t > 0) || cr[i].self) continue;
        if (!(cr[i].t < limit)) return false;
        h.t = cr[i].t;
        h.prim = q.prim;
        h.b1 = cr[i].part;
        h.b2 = 0;
        return true;
    }
    return false;
}

}  // namespace detail

int quadric_crossings(const QuadricPrim& q, const Vec3& o, const Vec3& d, double* t, int* part, int max) {
    detail::Crossing cr[detail::kMaxCrossings];
    const int n = detail::line_crossings(q, o, d, Vec3(0), cr);
    int m = 0;
    for (int i = 0; i < n && m < max; ++i, ++m) {
        t[m] = cr[i].t;
        part[m] = cr[i].part;
    }
    return m;
}

QuadricPoint quadric_part_surface(const QuadricPrim& q, int part, const Vec3& o, const Vec3& d, double t) {
    QuadricPoint s;
    Vec3 p = o + t * d;
    Vec3 e = gamma(3) * (abs3(o) + abs3(t * d));
    if (q.kind == ShapeKind::Torus) {
        const double rho = std::sqrt(p.x * p.x + p.z * p.z);
        const Vec3 radial = rho > 0 ? Vec3(p.x / rho, 0, p.z / rho) : Vec3(1, 0, 0);
        const Vec3 centre = q.r0 * radial;
        const Vec3 w = safe_normalize(p - centre, radial);
        p = centre + q.r1 * w;
        s.p = p;
        s.p_error = gamma(8) * (abs3(p) + Vec3(q.r0 + q.r1));
        s.n = w;
        const double psi = std::atan2(w.y, glm::dot(w, radial));
        double v = psi / (2 * kPi);
        if (v < 0) v += 1;
        if (!(v < 1)) v = 0;
        s.uv = Vec2(around(radial.x, radial.z), v);
        return s;
    }
    const bool body = part == kQuadricBody && q.kind != ShapeKind::Disc;
    if (body) {
        p.y = std::clamp(p.y, 0.0, q.h);
        const double k = (q.r1 - q.r0) / q.h;
        onto_radius(p, e, q.r0 + k * p.y);
        e.x += std::abs(k) * e.y;
        e.z += std::abs(k) * e.y;
        const double rho = std::sqrt(p.x * p.x + p.z * p.z);
        const Vec3 radial = rho > 0 ? Vec3(p.x / rho, 0, p.z / rho) : Vec3(1, 0, 0);
        s.n = safe_normalize(Vec3(radial.x, q.kind == ShapeKind::Cone ? -k : 0.0, radial.z), Vec3(0, 1, 0));
        s.uv = Vec2(around(p.x, p.z), clamp01(p.y / q.h));
    } else {
        const double plane = part == kQuadricTopCap ? q.h : 0.0;
        const double radius = part == kQuadricTopCap ? q.r1 : q.r0;
        p.y = plane;
        e.y = 0;
        const double rho = std::sqrt(p.x * p.x + p.z * p.z);
        if (rho > radius) onto_radius(p, e, radius);
        s.n = Vec3(0, part == kQuadricBaseCap ? -1.0 : 1.0, 0);
        s.uv = Vec2(around(p.x, p.z), clamp01(std::min(rho, radius) / radius));
    }
    s.p = p;
    s.p_error = e + gamma(2) * abs3(p);
    return s;
}

void quadric_surface(const Geometry::Impl& g, const QuadricPrim& q, const ShapeInfo&, const Ray& ray,
                     const HitRecord& hit, SurfaceHit& s) {
    const Transform& x = g.xforms[q.xform];
    const Vec3 o = x.inv_point(ray.o), d = x.inv_vector(ray.d);
    const int part = static_cast<int>(hit.b1);
    const QuadricPoint qp = quadric_part_surface(q, part, o, d, hit.t);
    s.p = x.point(qp.p);
    s.p_error = x.point_error(qp.p, qp.p_error);
    s.ng = safe_normalize(x.normal(qp.n), qp.n);
    s.ns = s.ng;
    s.uv = qp.uv;
    s.p_object = quadric_to_object(q, qp.p);
    // Flat parts take the plane's path for checkers: their own 2-D coordinates, so that a face
    // lying on a cell boundary does not speckle.
    if (q.kind == ShapeKind::Disc || part != kQuadricBody) {
        s.planar = true;
        s.plane_xy = Vec2(qp.p.x, qp.p.z) + Vec2(glm::dot(q.origin, q.axis_x), glm::dot(q.origin, q.axis_z));
    }
}

std::optional<Bounds3f> build_quadric(const OtherBuild& b, const ShapeSpec& s, const Transform& x) {
    QuadricPrim q;
    Mat4 frame(1.0);
    if (auto problem = make_quadric(s, q, frame)) {
        b.error(*problem);
        return std::nullopt;
    }
    q.prim = b.prim;
    Transform composed;
    if (frame == Mat4(1.0)) {
        composed = x;
        q.xform = b.xform;
    } else {
        if (auto msg = make_transform(s.object_to_world * frame, composed)) {
            b.error(std::string(shape_word(s.kind)) + " " + *msg);
            return std::nullopt;
        }
        q.xform = static_cast<uint32_t>(b.g.xforms.size());
        b.g.xforms.push_back(composed);
    }
    double m, lo_y, hi_y;
    canonical_box(q, m, lo_y, hi_y);
    q.band = composed.resid_lin * std::max({m, std::abs(lo_y), std::abs(hi_y)}) + composed.resid_t;
    Vec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (int c = 0; c < 8; ++c) {
        const Vec3 corner((c & 1) ? m : -m, (c & 2) ? hi_y : lo_y, (c & 4) ? m : -m);
        const Vec3 w = composed.point(corner);
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
    }
    const Vec3 pad = gamma(8) * (abs3(lo) + abs3(hi) + (hi - lo));
    const Bounds3f bounds = Bounds3f::around(lo - pad, hi + pad);
    if (!is_finite(bounds.lo) || !is_finite(bounds.hi)) {
        b.error(std::string(shape_word(s.kind)) +
                " is out of range: its bounds, after any transform, must stay within ±3.4e38 (the largest "
                "float)");
        return std::nullopt;
    }
    b.g.quadrics.push_back(q);
    return bounds;
}

}  // namespace wsd::render
