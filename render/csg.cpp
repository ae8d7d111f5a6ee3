// CSG solids: building, ray tests and surfaces (csg_prims.h states the sweep and the
// coincident-surface rule).
#include <algorithm>
#include <cmath>
#include <limits>

#include "render/csg_members.h"
#include "render/csg_prims.h"
#include "render/mesh_topology.h"
#include "render/other_prims.h"

namespace wsd::render {

namespace {

// An axis-aligned box that may be unbounded (a half-space) or empty (an empty intersection).
struct Extent {
    Vec3 lo{std::numeric_limits<double>::infinity()}, hi{-std::numeric_limits<double>::infinity()};
    bool unbounded = false;
    bool empty() const { return !unbounded && !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
    void add_corners(const Mat4& m, const Vec3& a, const Vec3& b) {
        for (int k = 0; k < 8; ++k) {
            const Vec3 c{(k & 1) ? b.x : a.x, (k & 2) ? b.y : a.y, (k & 4) ? b.z : a.z};
            const Vec3 w = Vec3(m * glm::dvec4(c, 1.0));
            lo = glm::min(lo, w);
            hi = glm::max(hi, w);
        }
    }
};

Extent extent_of(const ShapeSpec& s, const Mat4& parent, const SceneSpec& spec);

// The extent of `op` over `members` written in the frame `m`.
Extent combined(CsgOp op, const std::vector<ShapeSpec>& members, const Mat4& m, const SceneSpec& spec) {
    if (members.empty()) return {};
    Extent e = extent_of(members[0], m, spec);
    for (size_t i = 1; i < members.size() && op != CsgOp::Difference; ++i) {
        const Extent o = extent_of(members[i], m, spec);
        if (op == CsgOp::Union) {
            e.unbounded = e.unbounded || o.unbounded;
            e.lo = glm::min(e.lo, o.lo);
            e.hi = glm::max(e.hi, o.hi);
        } else if (o.unbounded) {
            continue;
        } else if (e.unbounded) {
            e = o;
        } else {
            e.lo = glm::max(e.lo, o.lo);
            e.hi = glm::min(e.hi, o.hi);
        }
    }
    return e;
}

// The extent of shape `s` placed by `parent` (the frame it is written in).
Extent extent_of(const ShapeSpec& s, const Mat4& parent, const SceneSpec& spec) {
    const Mat4 m = parent * s.object_to_world;
    Extent e;
    switch (s.kind) {
        case ShapeKind::Sphere:
            e.add_corners(m, s.center - Vec3(s.radius), s.center + Vec3(s.radius));
            break;
        case ShapeKind::Box:
            e.add_corners(m, s.box_min, s.box_max);
            break;
        case ShapeKind::Mesh:
            if (s.mesh)
                for (const glm::vec3& v : s.mesh->vertices) e.add_corners(m, Vec3(v), Vec3(v));
            break;
        case ShapeKind::Cylinder:
        case ShapeKind::Cone:
        case ShapeKind::Torus: {
            QuadricPrim q;
            Mat4 frame(1.0);
            if (make_quadric(s, q, frame)) break;  // reported when built
            const bool torus = s.kind == ShapeKind::Torus;
            const double r = torus ? q.r0 + q.r1 : std::max(q.r0, q.r1);
            e.add_corners(m * frame, Vec3(-r, torus ? -q.r1 : 0, -r), Vec3(r, torus ? q.r1 : q.h, r));
            break;
        }
        case ShapeKind::Csg:
            if (s.csg) e = combined(s.csg->op, s.csg->members, m, spec);
            break;
        case ShapeKind::Instance:
            if (s.prototype < spec.prototypes.size())
                e = combined(CsgOp::Union, spec.prototypes[s.prototype].shapes, m, spec);
            break;
        default:  // planes; other kinds are rejected when built
            e.unbounded = true;
            break;
    }
    return e;
}

bool any_transmissive(const SceneSpec& spec, const ShapeSpec& s, uint32_t enclosing) {
    const uint32_t mat = s.material != kInheritMaterial ? s.material : enclosing;
    const std::vector<ShapeSpec>* inner = nullptr;
    if (s.kind == ShapeKind::Csg && s.csg) inner = &s.csg->members;
    if (s.kind == ShapeKind::Instance && s.prototype < spec.prototypes.size())
        inner = &spec.prototypes[s.prototype].shapes;
    if (inner) {
        for (const ShapeSpec& m : *inner)
            if (any_transmissive(spec, m, mat)) return true;
        return false;
    }
    return mat < spec.materials.size() && spec.materials[mat].transmission > 0;
}

// Builds the solid's members and tree from the spec, reporting every problem.
struct SolidBuilder {
    const OtherBuild& b;
    CsgSolid& solid;
    bool ok = true;

    void fail(const std::string& where, const std::string& what) {
        b.error(where + ": " + what);
        ok = false;
    }

    // Adds shape `s` written in the frame `parent`; returns its tree child (node ≥ 0, ~member).
    int32_t add(const ShapeSpec& s, const Mat4& parent, uint32_t enclosing, bool subtracted,
                const std::string& where) {
        const Mat4 m = parent * s.object_to_world;
        if (s.material != kInheritMaterial && s.material >= b.spec.materials.size()) {
            fail(where, "material index " + std::to_string(s.material) + " is out of range");
            return 0;
        }
        const uint32_t mat = s.material != kInheritMaterial ? s.material : enclosing;
        if (s.kind == ShapeKind::Csg) {
            if (!s.csg) return fail(where, "a CSG needs at least one member"), 0;
            return add_node(s.csg->op, s.csg->members, m, mat, subtracted, where);
        }
        if (s.kind == ShapeKind::Instance) {
            // An `object` of a solid value: its prototype's shapes, placed by the instance.
            if (s.prototype >= b.spec.prototypes.size())
                return fail(where, "prototype index " + std::to_string(s.prototype) + " is out of range"), 0;
            return add_node(CsgOp::Union, b.spec.prototypes[s.prototype].shapes, m, mat, subtracted, where);
        }
        CsgMember mem;
        mem.shape_kind = s.kind;
        mem.material = mat;
        mem.subtracted = subtracted;
        mem.tag = s.tag;
        if (auto msg = make_transform(m, mem.x)) {
            fail(where, *msg);
            return 0;
        }
        if (!leaf(s, m, mem, where)) return 0;
        const Extent e = extent_of(s, parent, b.spec);
        if (!e.unbounded && is_finite(e.lo) && is_finite(e.hi)) {
            // Padded like the BVH's boxes, so that a crossing accepted at a rim is inside.
            const Vec3 pad = gamma(8) * (abs3(e.lo) + abs3(e.hi) + (e.hi - e.lo));
            mem.bounded = true;
            mem.wlo = e.lo - pad;
            mem.whi = e.hi + pad;
        }
        solid.members.push_back(std::move(mem));
        return ~static_cast<int32_t>(solid.members.size() - 1);
    }

    // A node `op` over `members` written in the frame `m`; returns its index.
    int32_t add_node(CsgOp op, const std::vector<ShapeSpec>& members, const Mat4& m, uint32_t mat,
                     bool subtracted, const std::string& where) {
        if (members.empty()) {
            fail(where.empty() ? "CSG" : where, "a CSG needs at least one member");
            return 0;
        }
        const int32_t index = static_cast<int32_t>(solid.nodes.size());
        solid.nodes.push_back(CsgNode{op, {}});
        std::vector<int32_t> children;
        for (size_t i = 0; i < members.size(); ++i) {
            const bool sub = subtracted != (op == CsgOp::Difference && i > 0);
            const std::string at = (where.empty() ? "CSG member " : where + ".") + std::to_string(i + 1);
            children.push_back(add(members[i], m, mat, sub, at));
        }
        solid.nodes[size_t(index)].children = std::move(children);
        return index;
    }

    bool quadric(const ShapeSpec& s, const Mat4& m, CsgMember& mem, const std::string& where);

    bool leaf(const ShapeSpec& s, const Mat4& m, CsgMember& mem, const std::string& where) {
        auto band = [&](double extent) { return mem.x.resid_lin * extent + mem.x.resid_t; };
        switch (s.kind) {
            case ShapeKind::Sphere:
                if (!is_finite(s.center))
                    return fail(where, "sphere center has a non-finite coordinate"), false;
                if (!std::isfinite(s.radius) || !(s.radius > 0))
                    return fail(where, "sphere radius must be a positive number"), false;
                mem.kind = CsgMemberKind::Sphere;
                mem.center = s.center;
                mem.radius = s.radius;
                mem.band = band(std::max({std::abs(s.center.x), std::abs(s.center.y), std::abs(s.center.z)}) +
                                s.radius);
                return true;
            case ShapeKind::Box: {
                if (!is_finite(s.box_min) || !is_finite(s.box_max))
                    return fail(where, "box corner has a non-finite coordinate"), false;
                if (!(s.box_min.x < s.box_max.x && s.box_min.y < s.box_max.y && s.box_min.z < s.box_max.z))
                    return fail(where, "box min must be below max on every axis (a flat box has no volume)"),
                           false;
                mem.kind = CsgMemberKind::Box;
                mem.lo = s.box_min;
                mem.hi = s.box_max;
                const Vec3 mx = glm::max(abs3(s.box_min), abs3(s.box_max));
                mem.band = band(std::max({mx.x, mx.y, mx.z}));
                return true;
            }
            case ShapeKind::Plane: {
                if (!is_finite(s.normal) || !std::isfinite(s.distance))
                    return fail(where, "plane has a non-finite normal or distance"), false;
                const Vec3 n = safe_normalize(s.normal, Vec3(0));
                if (n == Vec3(0)) return fail(where, "plane normal must not be zero"), false;
                if (!std::isfinite(s.uv_scale) || !(s.uv_scale > 0))
                    return fail(where, "plane uv_scale must be a positive number"), false;
                mem.kind = CsgMemberKind::Plane;
                mem.n = n;
                mem.c = s.distance;
                mem.uv_scale = s.uv_scale;
                mem.band = band(std::abs(s.distance));
                return true;
            }
            case ShapeKind::Mesh: {
                if (!s.mesh) return fail(where, "mesh has no data"), false;
                if (auto problem = closed_mesh_problem(*s.mesh))
                    return fail(where, "a mesh in a CSG must be closed: " + *problem), false;
                std::string err;
                mem.mesh = detail::make_csg_mesh(s.mesh, mem.x, err);
                if (!mem.mesh) return fail(where, err), false;
                mem.kind = CsgMemberKind::Mesh;
                return true;
            }
            case ShapeKind::Cylinder:
            case ShapeKind::Cone:
            case ShapeKind::Torus:
                return quadric(s, m, mem, where);
            default:
                return fail(where, std::string("'") + shape_word(s.kind) +
                                       "' is not a solid; CSG needs closed shapes"),
                       false;
        }
    }
};

// A closed cylinder or cone, or a torus: the member's frame becomes the shape's canonical one.
bool SolidBuilder::quadric(const ShapeSpec& s, const Mat4& m, CsgMember& mem, const std::string& where) {
    if (s.open && s.kind != ShapeKind::Torus)
        return fail(where, std::string("an open ") + shape_word(s.kind) +
                               " is not a solid; CSG needs closed shapes"),
               false;
    Mat4 frame(1.0);
    if (auto problem = make_quadric(s, mem.quadric, frame)) return fail(where, *problem), false;
    if (auto msg = make_transform(m * frame, mem.x)) return fail(where, *msg), false;
    const QuadricPrim& q = mem.quadric;
    const double r = s.kind == ShapeKind::Torus ? q.r0 + q.r1 : std::max(q.r0, q.r1);
    mem.band = mem.x.resid_lin * std::max(r, q.h) + mem.x.resid_t;
    mem.kind = CsgMemberKind::Quadric;
    return true;
}

// The result's inside at the members' states (0 or 1 each).
bool eval(const CsgSolid& s, const int8_t* state, int32_t node) {
    const CsgNode& n = s.nodes[size_t(node)];
    auto child = [&](int32_t c) { return c < 0 ? state[~c] != 0 : eval(s, state, c); };
    switch (n.op) {
        case CsgOp::Union:
            for (int32_t c : n.children)
                if (child(c)) return true;
            return false;
        case CsgOp::Intersection:
            for (int32_t c : n.children)
                if (!child(c)) return false;
            return true;
        case CsgOp::Difference:
            if (!child(n.children[0])) return false;
            for (size_t i = 1; i < n.children.size(); ++i)
                if (child(n.children[i])) return false;
            return true;
    }
    return false;
}

// Per-thread scratch of the sweep (no allocation once warm).
struct Sweep {
    std::vector<CsgCrossing> xs;
    std::vector<int8_t> state, net;
    std::vector<uint32_t> touched;
};

}  // namespace

bool csg_transmissive(const SceneSpec& spec, const CsgSpec& csg, uint32_t solid_material) {
    for (const ShapeSpec& m : csg.members)
        if (any_transmissive(spec, m, solid_material)) return true;
    return false;
}

bool csg_local_bounds(const SceneSpec& spec, const CsgSpec& csg, Vec3& lo, Vec3& hi) {
    const Extent e = combined(csg.op, csg.members, Mat4(1.0), spec);
    if (e.unbounded || !is_finite(e.lo) || !is_finite(e.hi)) return false;
    lo = e.lo;
    hi = e.hi;
    return true;
}

namespace detail {

namespace {

constexpr uint32_t kNone = 0xffffffffu;

// Applies the event made of crossings xs[i, j) to the members' states, and returns the member
// whose surface the event shows (kNone when no member's state changed). `inside` is the result
// before the event.
uint32_t apply_event(const CsgSolid& solid, Sweep& sw, size_t i, size_t j, bool inside) {
    if (j == i + 1) {  // the common case: one crossing
        const CsgCrossing& x = sw.xs[i];
        const int v = sw.state[x.member] + x.delta;
        const int8_t after = static_cast<int8_t>(v < 0 ? 0 : (v > 1 ? 1 : v));
        if (after == sw.state[x.member]) return kNone;
        sw.state[x.member] = after;
        return x.member;
    }
    sw.touched.clear();
    for (size_t k = i; k < j; ++k) {
        const CsgCrossing& x = sw.xs[k];
        if (std::find(sw.touched.begin(), sw.touched.end(), x.member) == sw.touched.end())
            sw.touched.push_back(x.member);
        sw.net[x.member] = static_cast<int8_t>(sw.net[x.member] + x.delta);
    }
    // A member crossed several times in one event (a mesh edge or vertex shared by faces that
    // all report it) changes its state once: by the sign of the net crossing.
    auto after_of = [&](uint32_t m) {
        const int v = sw.state[m] + (sw.net[m] > 0 ? 1 : (sw.net[m] < 0 ? -1 : 0));
        return static_cast<int8_t>(v < 0 ? 0 : (v > 1 ? 1 : v));
    };
    // Candidates in priority order: subtracting members first, then the member written first.
    std::sort(sw.touched.begin(), sw.touched.end(), [&](uint32_t a, uint32_t b) {
        const bool sa = solid.members[a].subtracted, sb = solid.members[b].subtracted;
        return sa != sb ? sa : a < b;
    });
    uint32_t chosen = kNone, first = kNone;
    for (uint32_t m : sw.touched) {
        const int8_t after = after_of(m), before = sw.state[m];
        if (after == before) continue;
        if (first == kNone) first = m;
        sw.state[m] = after;
        const bool alone = eval(solid, sw.state.data(), 0) != inside;
        sw.state[m] = before;
        if (alone) {
            chosen = m;
            break;
        }
    }
    for (uint32_t m : sw.touched) {
        sw.state[m] = after_of(m);
        sw.net[m] = 0;
    }
    return chosen != kNone ? chosen : first;
}

}  // namespace

bool test_csg(const Impl&, const CsgPrim& q, const RayPre& r, double limit, Counters& c, HitRecord& h) {
    const CsgSolid& solid = *q.solid;
    thread_local Sweep sw;
    const size_t n = solid.members.size();
    sw.xs.clear();
    sw.state.assign(n, 0);
    sw.net.assign(n, 0);
    for (uint32_t i = 0; i < n; ++i)
        sw.state[i] = static_cast<int8_t>(member_crossings(solid.members[i], i, r, sw.xs, c));
    if (std::none_of(sw.xs.begin(), sw.xs.end(), [](const CsgCrossing& x) { return x.t > 0; })) return false;
    std::sort(sw.xs.begin(), sw.xs.end(), [](const CsgCrossing& a, const CsgCrossing& b) {
        if (a.t != b.t) return a.t < b.t;
        if (a.member != b.member) return a.member < b.member;
        return a.sub < b.sub;
    });
    bool inside = eval(solid, sw.state.data(), 0);
    for (size_t i = 0; i < sw.xs.size();) {
        if (!(sw.xs[i].t < limit)) return false;
        // One event: crossings chained by overlapping error bounds (the coincident-surface rule).
        size_t j = i + 1;
        while (j < sw.xs.size() && sw.xs[j].t - sw.xs[j - 1].t <= sw.xs[j].err + sw.xs[j - 1].err) ++j;
        const uint32_t chosen = apply_event(solid, sw, i, j, inside);
        const bool now = chosen != kNone ? eval(solid, sw.state.data(), 0) : inside;
        if (now != inside) {
            // The chosen member's crossing in its net direction, the first along the ray.
            const bool entering = sw.state[chosen] != 0;
            bool at_origin = false;
            for (size_t k = i; k < j; ++k) at_origin = at_origin || sw.xs[k].at_origin;
            size_t k = i;
            while (k < j && !(sw.xs[k].member == chosen && (sw.xs[k].delta > 0) == entering)) ++k;
            const CsgCrossing& x = sw.xs[k < j ? k : i];
            if (!at_origin && x.t > 0 && x.t < limit) {
                h.t = x.t;
                h.prim = q.prim;
                h.b1 = x.b1;
                h.b2 = x.b2;
                h.member = x.member | (entering != now ? kCsgFlipBit : 0u);
                h.member_slot = x.sub;
                return true;
            }
        }
        inside = now;
        i = j;
    }
    return false;
}

}  // namespace detail

void csg_surface(const Geometry::Impl&, const CsgPrim& q, const ShapeInfo&, const Ray& ray,
                 const HitRecord& hit, SurfaceHit& s) {
    const CsgMember& m = q.solid->members[hit.member & ~kCsgFlipBit];
    detail::member_surface(m, ray, hit.t, hit.member_slot, hit.b1, hit.b2, s);
    if (hit.member & kCsgFlipBit) {
        // The member's inside is the solid's outside here (a difference's cut surface).
        s.ng = -s.ng;
        s.ns = -s.ns;
    }
    s.p_object = q.solid->frame.inv_point(s.p);
    s.material = member_material(m, s.material);
}

std::optional<Bounds3f> build_csg(const OtherBuild& b, const ShapeSpec& s, const Transform& x) {
    auto solid = std::make_shared<CsgSolid>();
    solid->frame = x;
    SolidBuilder sb{b, *solid};
    if (!s.csg) {
        b.error("CSG has no members");
        return std::nullopt;
    }
    // Members without a material of their own keep kInheritMaterial: csg_surface gives them the
    // CSG's (or, inside a prototype, what the CSG itself inherits).
    sb.add_node(s.csg->op, s.csg->members, s.object_to_world, kInheritMaterial, false, "");
    if (!sb.ok) return std::nullopt;
    const Extent e = extent_of(s, Mat4(1.0), b.spec);
    if (e.unbounded || !is_finite(e.lo) || !is_finite(e.hi)) {
        b.error(
            "this CSG is unbounded: a plane member must be intersected with or subtracted from a bounded "
            "solid");
        return std::nullopt;
    }
    Extent use = e;
    if (use.empty()) use.lo = use.hi = Vec3(s.object_to_world[3]);  // never hit: any finite box will do
    const Vec3 pad = gamma(8) * (abs3(use.lo) + abs3(use.hi) + (use.hi - use.lo));
    const Bounds3f bounds = Bounds3f::around(use.lo - pad, use.hi + pad);
    if (!is_finite(bounds.lo) || !is_finite(bounds.hi)) {
        b.error(
            "CSG is out of range: its bounds, after any transform, must stay within ±3.4e38 (the largest "
            "float)");
        return std::nullopt;
    }
    if (b.transmissive) *b.transmissive = *b.transmissive || csg_transmissive(b.spec, *s.csg, s.material);
    CsgPrim p;
    p.op = s.csg->op;
    p.prim = b.prim;
    p.solid = std::move(solid);
    b.g.csgs.push_back(std::move(p));
    return bounds;
}

}  // namespace wsd::render
