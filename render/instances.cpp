// Instances: prototypes built once, each instance a transform and a reference (two-level BVH).
// The exactness argument is in render/instance_prims.h; the walk of a prototype's BVH is the one
// walk (render/traverse.h) with the ray in the prototype's frame and its boxes widened.
#include <cmath>
#include <limits>

#include "render/instance_prims.h"
#include "render/other_prims.h"
#include "render/traverse.h"

namespace wsd::render {

namespace {

using detail::Best;
using detail::Counters;

// 2^-20: a relative widening far above the float roundings it covers (2^-24 each).
constexpr double kRelPad = 0x1p-20;

Mat4 matrix_of(const Transform& x) {
    Mat4 m(1.0);
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) m[c][r] = x.l[r][c];
    m[3] = glm::dvec4(x.t, 1.0);
    return m;
}

Vec3 abs_mul(const Vec3 (&rows)[3], const Vec3& v) {
    Vec3 a = abs3(v), out;
    for (int i = 0; i < 3; ++i) out[i] = glm::dot(abs3(rows[i]), a);
    return out;
}

double max3(const Vec3& v) {
    return std::max({v.x, v.y, v.z});
}

// One instance's member shapes with the transforms of the flat scene (instance · member),
// composed once per shape met during one query. Triangles need only the matrix (l, t); spheres,
// boxes and surfaces the whole Transform, as make_transform gives it.
class Members {
public:
    Members(const Prototype& p, const Transform& xi) : p_(p), m_(matrix_of(xi)) {}

    const ShapeSpec& spec(uint32_t shape) const { return p_.shapes[shape]; }
    // The member shape of inner primitive `prim`.
    uint32_t shape_of(uint32_t prim) const {
        const Geometry::Impl& pg = *p_.geometry;
        return pg.shapes.size() == 1 ? 0 : pg.shape_of(prim);
    }
    const Transform& full(uint32_t shape) {
        if (shape != shape_ || !full_) {
            compose(shape);
            full_ = true;
            (void)make_transform(m_ * p_.shapes[shape].object_to_world, x_);  // valid: build_instance
        }
        return x_;
    }
    // The vertices of triangle `tri` of member `shape`, in world space as the flat build stores them.
    [[gnu::always_inline]] void triangle(uint32_t shape, const TriPrim& tri, Vec3f (&v)[3]) {
        if (shape != shape_) compose(shape);
        for (int k = 0; k < 3; ++k) {
            const uint32_t local = tri.v[k] - offset_;
            v[k] = world_vertex_of(x_, mesh_ != nullptr ? Vec3(mesh_[local]) : (*lone_)[local]);
        }
    }

private:
    const Prototype& p_;
    Mat4 m_;
    uint32_t shape_ = 0xffffffffu;
    bool full_ = false;
    Transform x_;
    // The member's own vertices: a mesh's, or a lone triangle's (in double).
    const glm::vec3* mesh_ = nullptr;
    const std::array<Vec3, 3>* lone_ = nullptr;
    uint32_t offset_ = 0;

    // The composed matrix's linear part and translation, as make_transform extracts them.
    void compose(uint32_t shape) {
        shape_ = shape;
        full_ = false;
        const Mat4 c = m_ * p_.shapes[shape].object_to_world;
        x_ = Transform{};
        for (int i = 0; i < 3; ++i) x_.l[i] = Vec3(c[0][i], c[1][i], c[2][i]);
        x_.t = Vec3(c[3][0], c[3][1], c[3][2]);
        const ShapeInfo& info = p_.geometry->shapes[shape];
        const ShapeSpec& s = p_.shapes[shape];
        offset_ = info.vertex_offset;
        mesh_ = s.kind == ShapeKind::Mesh ? s.mesh->vertices.data() : nullptr;
        lone_ = s.kind == ShapeKind::Triangle ? &p_.tri_src[info.extra] : nullptr;
    }
};

// The sphere and box of member `shape` as the flat build would store them under transform x.
SpherePrim flat_sphere(const ShapeSpec& s, const Transform& x) {
    SpherePrim p{};
    if (x.similarity) {
        p.center = x.point(s.center);
        p.radius = s.radius * x.scale;
        p.xform = kNoTransform;
    } else {
        p.center = s.center;
        p.radius = s.radius;
        p.xform = 0;  // any value but kNoTransform: the transform is passed alongside
    }
    return p;
}
BoxPrim flat_box(const ShapeSpec& s, const Transform& x) {
    BoxPrim p{};
    p.lo = s.box_min;
    p.hi = s.box_max;
    Vec3 m = glm::max(abs3(p.lo), abs3(p.hi));
    p.band = x.resid_lin * std::max({m.x, m.y, m.z}) + x.resid_t;
    p.xform = x.identity ? kNoTransform : 0;
    return p;
}

// A query's view of one instance: the world ray, the ray in the prototype's frame (its box test
// widened by `pad`), the member transforms.
struct InstanceRay {
    const Geometry::Impl& pg;
    const InstancePrim& q;
    const RayPre& r;  // world
    RayPre local;     // prototype frame
    Members members;
    Counters& c;

    InstanceRay(const Prototype& p, const InstancePrim& q_, const Transform& xi, const RayPre& r_,
                Counters& c_)
        : pg(*p.geometry),
          q(q_),
          r(r_),
          local(Ray{xi.inv_point(r_.o), xi.inv_vector(r_.d)}),
          members(p, xi),
          c(c_) {}

    // Widens the local ray's box test by the error of the local ray and q.pad; false when the
    // ray misses the prototype's bounds within `limit`.
    bool widen(const Transform& xi, const Bounds3f& root, double limit);

    bool passes(uint32_t k, uint32_t e) const {
        if (q.filter == 0) return true;
        bool trans = (e & kTransmissiveBit) != 0;
        if (q.inherit_transmissive && !pg.inherits.empty() && pg.inherits[k] != 0) trans = true;
        return trans == (q.filter == 2);
    }

    // Entry k of the prototype's order into the running closest hit.
    void test(uint32_t k, Best& best);
};

bool InstanceRay::widen(const Transform& xi, const Bounds3f& root, double limit) {
    const Vec3 o = local.o, d = local.d;
    const Vec3 e_o = xi.inv_point_error(r.o) + xi.resid_lin * max3(abs3(o)) + xi.resid_t;
    const Vec3 e_d = gamma(3) * abs_mul(xi.il, r.d) + xi.resid_lin * max3(abs3(d));
    // The ray's extent within the prototype's bounds (in double, boxes widened).
    const Vec3 w = q.pad + 2.0 * e_o;
    double t0 = 0, t1 = limit;
    for (int a = 0; a < 3; ++a) {
        const double lo = double(root.lo[a]) - w[a], hi = double(root.hi[a]) + w[a];
        if (d[a] == 0) {
            if (o[a] < lo || o[a] > hi) return false;
            continue;
        }
        const double inv = 1.0 / d[a];
        double n = (lo - o[a]) * inv, f = (hi - o[a]) * inv;
        if (n > f) std::swap(n, f);
        t0 = std::max(t0, n);
        t1 = std::min(t1, f * (1 + kRelPad));
    }
    if (!(t0 <= t1)) return false;
    const Vec3 pad = q.pad + e_o + t1 * e_d;
    RayBoxTest& b = local.box;
    for (int a = 0; a < 3; ++a) {
        const bool neg = std::signbit(d[a]);
        const float up = to_float_up(o[a] + pad[a]), down = to_float_down(o[a] - pad[a]);
        b.o_near[a] = neg ? down : up;
        b.o_far[a] = neg ? up : down;
#if defined(__SSE2__)
        b.o_near4[a] = _mm_set1_ps(b.o_near[a]);
        b.o_far4[a] = _mm_set1_ps(b.o_far[a]);
#endif
    }
    return true;
}

void InstanceRay::test(uint32_t k, Best& best) {
    const uint32_t e = detail::entry_at(pg, k);
    if (!passes(k, e)) return;
    const uint32_t slot = e & kSlotMask;
    double t = 0, b1 = 0, b2 = 0;
    switch (static_cast<PrimKind>((e >> kKindShift) & 3u)) {
        case PrimKind::Triangle: {
            const TriPrim& tri = pg.tris[slot];
            const uint32_t shape = members.shape_of(tri.prim);
            Vec3f v[3];
            members.triangle(shape, tri, v);
            if (detail::test_triangle(r, v[0], v[1], v[2], best.limit, c, t, b1, b2))
                best.offer(t, tri.prim, e, b1, b2);
            return;
        }
        case PrimKind::Sphere: {
            const uint32_t prim = pg.spheres[slot].prim;
            const uint32_t shape = members.shape_of(prim);
            const Transform& x = members.full(shape);
            const SpherePrim sp = flat_sphere(members.spec(shape), x);
            if (detail::test_sphere(sp, sp.xform == kNoTransform ? nullptr : &x, r, best.limit, c, t))
                best.offer(t, prim, e, 0, 0);
            return;
        }
        case PrimKind::Box: {
            const uint32_t prim = pg.boxes[slot].prim;
            const uint32_t shape = members.shape_of(prim);
            const Transform& x = members.full(shape);
            const BoxPrim bx = flat_box(members.spec(shape), x);
            int face = 0;
            if (detail::test_box(bx, bx.xform == kNoTransform ? nullptr : &x, r, best.limit, c, t, face))
                best.offer(t, prim, e, face, 0);
            return;
        }
        case PrimKind::Other: {
            HitRecord h;
            if (detail::test_other(pg, local, slot, best.limit, c, h)) best.offer(h, e);
            return;
        }
    }
}

// The closest-hit walk of a prototype's BVH: the top level's ClosestHit, on the local ray.
struct InnerClosest : OneRayTest {
    static constexpr WalkOrder kOrder = WalkOrder::NearestFirst;
    using Child = BvhChild;
    InstanceRay& ir;
    Best& best;

    bool leaf(const Child& e) {
        for (uint32_t k = e.first(); k < e.first() + e.count(); ++k) ir.test(k, best);
        limit = to_float_up(best.limit);
        return false;
    }
    bool open(float t) const { return t <= limit * RayBoxTest::kWiden; }
};

// The any-hit walk: depth first, ended by the first hit.
struct InnerAny : OneRayTest {
    static constexpr WalkOrder kOrder = WalkOrder::DepthFirst;
    using Child = BvhChild;
    InstanceRay& ir;
    Best& best;

    bool leaf(const Child& e) {
        for (uint32_t k = e.first(); k < e.first() + e.count(); ++k) {
            ir.test(k, best);
            if (best.hit) return true;
        }
        return false;
    }
};

}  // namespace

namespace detail {

bool test_instance(const Impl& g, const InstancePrim& q, const RayPre& r, double limit, Counters& c,
                   HitRecord& h) {
    const Prototype& p = *g.prototypes[q.prototype];
    const Transform& xi = g.xforms[q.xform];
    InstanceRay ir(p, q, xi, r, c);
    if (!ir.widen(xi, p.bounds, limit)) return false;
    Best best{limit};
    uint64_t boxes = 0;
    if (c.any_hit) {
        InnerAny walk{{&ir.local.box, to_float_up(limit)}, ir, best};
        walk_bvh_chosen(p.geometry->nodes.data(), walk, boxes);
    } else {
        InnerClosest walk{{&ir.local.box, to_float_up(limit)}, ir, best};
        walk_bvh_chosen(p.geometry->nodes.data(), walk, boxes);
    }
    c.boxes += boxes;
    if (!best.hit) return false;
    // The inner hit, seen from the top level: the instance's id, the member's in inner_*.
    h = best.h;
    h.prim = q.prim;
    h.inner_prim = best.h.prim;
    h.inner_slot = best.h.slot;
    return true;
}

}  // namespace detail

void instance_surface(const Geometry::Impl& g, const InstancePrim& q, const ShapeInfo&, const Ray& ray,
                      const HitRecord& hit, SurfaceHit& s) {
    const Prototype& p = *g.prototypes[q.prototype];
    const Geometry::Impl& pg = *p.geometry;
    const Transform& xi = g.xforms[q.xform];
    Members members(p, xi);
    const uint32_t e = hit.inner_slot, slot = e & kSlotMask;
    const uint32_t shape = members.shape_of(hit.inner_prim);
    const ShapeInfo& mi = pg.shapes[shape];
    const ShapeSpec& ms = p.shapes[shape];
    if (ms.material != kInheritMaterial) s.material = ms.material;  // else the instance's, as given
    s.member = shape;
    switch (static_cast<PrimKind>((e >> kKindShift) & 3u)) {
        case PrimKind::Triangle: {
            const TriPrim& tri = pg.tris[slot];
            Vec3f vf[3];
            members.triangle(shape, tri, vf);
            const Vec3 v[3] = {Vec3(vf[0]), Vec3(vf[1]), Vec3(vf[2])};
            const uint32_t local[3] = {tri.v[0] - mi.vertex_offset, tri.v[1] - mi.vertex_offset,
                                       tri.v[2] - mi.vertex_offset};
            const Transform& x = members.full(shape);
            ShapeInfo info = mi;
            info.mirrored = x.det < 0;
            info.mesh = ms.kind == ShapeKind::Mesh ? ms.mesh : nullptr;
            const TriExtra* extra = ms.kind == ShapeKind::Triangle ? &pg.tri_extra[mi.extra] : nullptr;
            return triangle_surface_of(v, local, info, extra, x, hit, s);
        }
        case PrimKind::Sphere: {
            const Transform& x = members.full(shape);
            return sphere_surface_of(flat_sphere(ms, x), x, ray, hit, s);
        }
        case PrimKind::Box: {
            const Transform& x = members.full(shape);
            const BoxPrim bx = flat_box(ms, x);
            return box_surface_of(bx, bx.xform == kNoTransform ? Transform{} : x, ray, hit, s);
        }
        case PrimKind::Other: {
            // In the prototype's frame, then carried to the world with the instance's transform.
            const Ray local{xi.inv_point(ray.o), xi.inv_vector(ray.d)};
            HitRecord ih = hit;
            ih.prim = hit.inner_prim;
            ih.slot = slot;
            SurfaceHit ls = s;
            other_surface(pg, mi, local, ih, ls);
            s.p = xi.point(ls.p);
            s.p_error = xi.point_error(ls.p, ls.p_error);
            s.ng = safe_normalize(xi.normal(ls.ng), ls.ng);
            s.ns = safe_normalize(xi.normal(ls.ns), s.ng);
            s.uv = ls.uv;
            s.plane_xy = ls.plane_xy;
            s.planar = ls.planar;
            s.p_object = ls.p_object;
            if (ls.material != kInheritMaterial) s.material = ls.material;
            return;
        }
    }
}

namespace {

// Builds SceneSpec::prototypes[index] into p, reporting its errors as the instance's.
void build_prototype(Prototype& p, const OtherBuild& b, uint32_t index) {
    const PrototypeSpec& spec = b.spec.prototypes[index];
    p.built = true;
    p.geometry = std::make_unique<Geometry::Impl>();
    std::vector<SpecError> errors;
    if (!build_geometry_into(*p.geometry, b.spec, spec.shapes, errors, true, b.threads, true)) {
        for (const SpecError& err : errors)
            b.error("in its object's shape " + std::to_string(err.index + 1) + ": " + err.message);
        p.failed = true;
        return;
    }
    const Geometry::Impl& pg = *p.geometry;
    p.shapes = spec.shapes;
    for (size_t i = 0; i < pg.shapes.size(); ++i) {
        const ShapeSpec& s = spec.shapes[i];
        if (s.kind == ShapeKind::Triangle) {
            if (p.tri_src.size() <= pg.shapes[i].extra) p.tri_src.resize(pg.shapes[i].extra + 1);
            p.tri_src[pg.shapes[i].extra] = {s.v[0], s.v[1], s.v[2]};
        }
        if (s.material == kInheritMaterial)
            p.has_inherit = true;
        else if (b.spec.materials[s.material].transmission > 0)
            p.has_transmissive = true;
        else
            p.has_opaque = true;
    }
    if (!pg.nodes.empty()) {
        const BvhWideNode& root = pg.nodes[0];
        for (int i = 0; i < kBvhWidth; ++i) {
            if (!(root.lo[0][i] <= root.hi[0][i])) continue;  // an unused lane
            p.bounds.extend(Vec3f(root.lo[0][i], root.lo[1][i], root.lo[2][i]));
            p.bounds.extend(Vec3f(root.hi[0][i], root.hi[1][i], root.hi[2][i]));
        }
    }
    p.triangles = pg.tris.size();
}

}  // namespace

std::optional<Bounds3f> build_instance(const OtherBuild& b, const ShapeSpec& s, const Transform& x) {
    if (s.prototype >= b.spec.prototypes.size()) {
        b.error("instance of object " + std::to_string(s.prototype) + ", but the scene has " +
                std::to_string(b.spec.prototypes.size()));
        return std::nullopt;
    }
    Geometry::Impl& g = b.g;
    if (g.prototypes.size() < b.spec.prototypes.size()) g.prototypes.resize(b.spec.prototypes.size());
    if (!g.prototypes[s.prototype]) {
        g.prototypes[s.prototype] = std::make_unique<Prototype>();
        build_prototype(*g.prototypes[s.prototype], b, s.prototype);
    }
    const Prototype& p = *g.prototypes[s.prototype];
    if (p.failed || p.bounds.empty()) return std::nullopt;  // errors reported once; or nothing to add

    Vec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (int k = 0; k < 8; ++k) {
        const Vec3 c((k & 1) ? p.bounds.hi.x : p.bounds.lo.x, (k & 2) ? p.bounds.hi.y : p.bounds.lo.y,
                     (k & 4) ? p.bounds.hi.z : p.bounds.lo.z);
        const Vec3 w = x.point(c);
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
    }
    const Vec3 pw = kRelPad * (abs3(lo) + abs3(hi) + (hi - lo));
    const Bounds3f world = Bounds3f::around(lo - pw, hi + pw);
    if (!is_finite(world.lo) || !is_finite(world.hi)) {
        b.error(
            "instance is out of range: its bounds, after any transform, must stay within ±3.4e38 (the "
            "largest float)");
        return std::nullopt;
    }
    // Every member's composed transform, as the flat scene's would be, must be valid.
    const Mat4 m = s.object_to_world;
    const Mat4* last = nullptr;
    for (size_t k = 0; k < p.shapes.size(); ++k) {
        const Mat4& own = p.shapes[k].object_to_world;
        if (own == Mat4(1.0) || (last != nullptr && own == *last)) continue;
        last = &own;
        Transform composed;
        if (auto msg = make_transform(m * own, composed)) {
            b.error("with its object's shape " + std::to_string(k + 1) + ": " + *msg);
            return std::nullopt;
        }
    }
    const double pm = max3(glm::max(abs3(Vec3(p.bounds.lo)), abs3(Vec3(p.bounds.hi))));
    const double wm = max3(glm::max(abs3(lo), abs3(hi)));

    InstancePrim q;
    q.prototype = s.prototype;
    q.prim = b.prim;
    q.xform = b.xform;
    q.material = s.material;
    if (p.has_inherit && s.material >= b.spec.materials.size()) {
        b.error("an instanced object has members without a material, and the instance gives none");
        return std::nullopt;
    }
    q.inherit_transmissive =
        s.material < b.spec.materials.size() && b.spec.materials[s.material].transmission > 0;
    q.pad = kRelPad * (Vec3(pm) + abs_mul(x.il, Vec3(wm)));
    const bool any_trans = p.has_transmissive || (p.has_inherit && q.inherit_transmissive);
    const bool any_opaque = p.has_opaque || (p.has_inherit && !q.inherit_transmissive);
    if (any_trans && any_opaque) {
        q.filter = 1;
        g.instances.push_back(q);
        q.filter = 2;
        q.transmissive = true;
        g.instances.push_back(q);
    } else {
        q.transmissive = any_trans;
        g.instances.push_back(q);
    }
    return world;
}

Mat4 Geometry::member_to_world(const SurfaceHit& s) const {
    const Impl& g = *impl_;
    const InstancePrim& q = g.instances[g.others[g.shapes[g.shape_of(s.prim)].extra].index];
    return matrix_of(g.xforms[q.xform]) * g.prototypes[q.prototype]->shapes[s.member].object_to_world;
}

size_t Prototype::memory_bytes() const {
    size_t n =
        sizeof(Prototype) + shapes.capacity() * sizeof(ShapeSpec) + tri_src.capacity() * sizeof(tri_src[0]);
    return geometry ? n + geometry_memory_bytes(*geometry) : n;
}

}  // namespace wsd::render
