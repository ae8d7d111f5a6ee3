// CSG members one at a time (csg_members.h). Every test works on the ray's whole line: the sweep
// in render/csg.cpp needs the inside state of each member everywhere, not just beyond the origin.
// Each crossing carries a bound on the error of its t (the origin's error projected on the
// surface, the rounding of the formula and of the transform); a crossing within its bound of
// t = 0 is the surface the origin lies on, as in the primitive tests of render/shapes.h.
#include "render/csg_members.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "render/shapes.h"

namespace wsd::render::detail {

namespace {

constexpr uint32_t kLeafTris = 4;

struct Local {
    Vec3 o, d, o_err;
};

// The ray in the member's frame, with the error of the mapped origin (transform rounding plus
// the residual of inverse·forward at the member's scale).
Local to_local(const CsgMember& m, const RayPre& r) {
    Local l;
    l.o = m.x.inv_point(r.o);
    l.d = m.x.inv_vector(r.d);
    const Vec3 ao = abs3(l.o);
    l.o_err = m.x.inv_point_error(r.o) + m.band + m.x.resid_lin * std::max({ao.x, ao.y, ao.z});
    return l;
}

void push(std::vector<CsgCrossing>& out, double t, double err, uint32_t member, uint32_t sub, double b1,
          double b2, int8_t delta, bool at_origin) {
    CsgCrossing x;
    x.t = t;
    x.err = err;
    x.member = member;
    x.sub = sub;
    x.b1 = b1;
    x.b2 = b2;
    x.delta = delta;
    x.at_origin = at_origin || std::abs(t) <= err;
    out.push_back(x);
}

int sphere_crossings(const CsgMember& m, uint32_t index, const Local& l, std::vector<CsgCrossing>& out) {
    const Vec3 f = l.o - m.center, &d = l.d;
    const double a = glm::dot(d, d), inv_a = 1.0 / a;
    const double b = glm::dot(f, d);
    const Vec3 lv = f - (b * inv_a) * d;
    const double r2 = m.radius * m.radius;
    const double disc = r2 - glm::dot(lv, lv);
    if (!(disc >= 0)) return 0;
    const double ff = glm::dot(f, f);
    const double cc = ff - r2;
    const double s = std::sqrt(a * disc);
    const double q = -(b + std::copysign(s, b));
    if (q == 0) return 0;  // tangent: enters and leaves at one point
    const double t_small = cc / q, t_big = q * inv_a;
    const Vec3& oe = l.o_err;
    const double err_o = std::abs(f.x) * oe.x + std::abs(f.y) * oe.y + std::abs(f.z) * oe.z;
    const double err_c = gamma(8) * (ff + r2) + 2 * err_o + glm::dot(oe, oe);
    const double err_b = gamma(5) * (std::abs(f.x * d.x) + std::abs(f.y * d.y) + std::abs(f.z * d.z)) +
                         oe.x * std::abs(d.x) + oe.y * std::abs(d.y) + oe.z * std::abs(d.z);
    // F(t) = a t² + 2 b t + c: a root moves by at most δF/|F'| = δF/(2s) and by at most √(δF/a).
    auto err = [&](double t) {
        const double dF = gamma(4) * a * t * t + 2 * err_b * std::abs(t) + err_c;
        const double first = s > 0 ? dF / (2 * s) : std::numeric_limits<double>::infinity();
        return std::min(first, std::sqrt(dF * inv_a)) + gamma(6) * std::abs(t);
    };
    const bool on = std::abs(cc) <= err_c;  // the origin lies on the sphere: t_small is that point
    const double t0 = std::min(t_small, t_big), t1 = std::max(t_small, t_big);
    push(out, t0, err(t0), index, 0, 0, 0, 1, on && t0 == t_small);
    push(out, t1, err(t1), index, 0, 0, 0, -1, on && t1 == t_small);
    return 0;
}

int box_crossings(const CsgMember& m, uint32_t index, const Local& l, std::vector<CsgCrossing>& out) {
    // A slab whose crossing is less certain than the ray's whole passage through the other slabs
    // is one the ray runs along (an origin on a face plane, a direction within rounding of it):
    // closed, like an exactly parallel one. Otherwise a ray along a face shared with another
    // member would see that face anywhere along it.
    double near[3], far[3];
    bool along[3];
    for (int i = 0; i < 3; ++i) {
        along[i] = l.d[i] == 0;
        if (along[i]) {
            if (l.o[i] < m.lo[i] - l.o_err[i] || l.o[i] > m.hi[i] + l.o_err[i]) return 0;
            continue;
        }
        const bool pos = l.d[i] > 0;
        near[i] = ((pos ? m.lo[i] : m.hi[i]) - l.o[i]) / l.d[i];
        far[i] = ((pos ? m.hi[i] : m.lo[i]) - l.o[i]) / l.d[i];
    }
    for (int i = 0; i < 3; ++i) {
        if (along[i]) continue;
        const double gap = std::min(std::abs(m.lo[i] - l.o[i]), std::abs(m.hi[i] - l.o[i]));
        if (!(gap <= l.o_err[i] + gamma(2) * gap)) continue;
        const double err = (l.o_err[i] + gamma(2) * gap) / std::abs(l.d[i]);
        double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
        for (int k = 0; k < 3; ++k)
            if (k != i && !along[k]) lo = std::max(lo, near[k]), hi = std::min(hi, far[k]);
        if (err >= hi - lo) along[i] = true;
    }
    double tn = -std::numeric_limits<double>::infinity(), tf = std::numeric_limits<double>::infinity();
    int fn = -1, ff = -1;
    double slack = 0;
    for (int i = 0; i < 3; ++i) {
        if (along[i]) continue;
        const bool pos = l.d[i] > 0;
        slack = std::max(slack, l.o_err[i] / std::abs(l.d[i]));
        if (near[i] > tn) tn = near[i], fn = 2 * i + (pos ? 0 : 1);
        if (far[i] < tf) tf = far[i], ff = 2 * i + (pos ? 1 : 0);
    }
    if (fn < 0 || ff < 0) return 0;
    if (!(tn <= tf + 2 * gamma(3) * std::abs(tf) + 2 * slack)) return 0;
    auto face_err = [&](int face, double t, bool& on) {
        const int axis = face >> 1;
        const double plane = (face & 1) ? m.hi[axis] : m.lo[axis];
        const double gap = std::abs(plane - l.o[axis]);
        on = gap <= l.o_err[axis] + gamma(2) * gap;
        return (l.o_err[axis] + gamma(2) * gap) / std::abs(l.d[axis]) + gamma(6) * std::abs(t);
    };
    bool on_n = false, on_f = false;
    const double en = face_err(fn, tn, on_n), ef = face_err(ff, tf, on_f);
    push(out, tn, en, index, uint32_t(fn), 0, 0, 1, on_n);
    push(out, std::max(tf, tn), ef, index, uint32_t(ff), 0, 0, -1, on_f);
    return 0;
}

// The half-space n·p ≤ c: inside before its one crossing when the line leaves through it.
int plane_crossings(const CsgMember& m, uint32_t index, const Local& l, std::vector<CsgCrossing>& out) {
    const Vec3& n = m.n;
    const double num = m.c - glm::dot(n, l.o);
    const double err_num =
        gamma(4) * (std::abs(m.c) + std::abs(n.x * l.o.x) + std::abs(n.y * l.o.y) + std::abs(n.z * l.o.z)) +
        std::abs(n.x) * l.o_err.x + std::abs(n.y) * l.o_err.y + std::abs(n.z) * l.o_err.z;
    const double den = glm::dot(n, l.d);
    if (den == 0) return num >= -err_num ? 1 : 0;  // along the plane: inside if on or below it
    const double t = num / den;
    const double err_den = gamma(4) * (std::abs(n.x * l.d.x) + std::abs(n.y * l.d.y) + std::abs(n.z * l.d.z));
    const double err = (err_num + err_den * std::abs(t)) / std::abs(den) + gamma(2) * std::abs(t);
    const bool leaving = den > 0;
    push(out, t, err, index, 0, 0, 0, leaving ? -1 : 1, std::abs(num) <= err_num);
    return leaving ? 1 : 0;
}

// A closed cylinder or cone, or a torus. The error
// of t is the origin's error (and the surface point's own) across the surface, over the
// direction's component along the normal.
int quadric_member_crossings(const CsgMember& m, uint32_t index, const Local& l,
                             std::vector<CsgCrossing>& out) {
    double t[4];
    int part[4];
    const int n = quadric_crossings(m.quadric, l.o, l.d, t, part, 4);
    const double scale = std::max(m.quadric.r0, m.quadric.r1) + m.quadric.h;
    const double len = std::sqrt(glm::dot(l.d, l.d));
    for (int i = 0; i < n; ++i) {
        const QuadricPoint qp = quadric_part_surface(m.quadric, part[i], l.o, l.d, t[i]);
        const Vec3 an = abs3(qp.n);
        const double across = glm::dot(an, l.o_err + qp.p_error);
        const double nd = std::abs(glm::dot(qp.n, l.d));
        const double err = (across + gamma(32) * (scale + glm::length(l.o))) / std::max(nd, gamma(4) * len) +
                           gamma(16) * std::abs(t[i]);
        // Entering or leaving from the side the line crosses the surface; from the alternation
        // where it barely crosses (near a tangent). A line through a rim may report the rim from
        // both parts, or from neither: the sides keep the count right, the alternation would not.
        const double side = glm::dot(qp.n, l.d);
        const int8_t delta = std::abs(side) > 1e-6 * len ? (side < 0 ? 1 : -1) : ((i % 2 == 0) ? 1 : -1);
        push(out, t[i], err, index, uint32_t(part[i]), 0, 0, delta, false);
    }
    return 0;
}

// The watertight test of render/shapes.h on the whole line: t of any sign, with the sign of the
// determinant (negative: the line meets the face's front, where the winding is counter-clockwise).
bool triangle_line(const RayPre& r, const Vec3f& v0, const Vec3f& v1, const Vec3f& v2, double& t_out,
                   double& err_out, double& b1_out, double& b2_out, bool& front) {
    TriangleEdges q;
    if (!triangle_edges(r, v0, v1, v2, q)) return false;
    t_out = q.t();
    err_out = q.t_error();
    b1_out = q.e1 / q.det;
    b2_out = q.e2 / q.det;
    front = q.det < 0;
    return true;
}

// The line's slab constants, made once per line: reciprocals of the direction's components.
struct Line {
    Vec3 o, inv;
    bool flat[3];  // the direction's component is 0: the line stays in its slab or misses it
    explicit Line(const RayPre& r) : o(r.o) {
        for (int i = 0; i < 3; ++i) {
            flat[i] = r.d[i] == 0;
            inv[i] = flat[i] ? 0.0 : 1.0 / r.d[i];
        }
    }

    // Whether the line meets the box anywhere (slabs over all t), widened by the rounding of the
    // slab distances (a subtraction and a multiplication by a rounded reciprocal).
    bool meets(const Vec3& lo, const Vec3& hi) const {
        double tn = -std::numeric_limits<double>::infinity(), tf = std::numeric_limits<double>::infinity();
        for (int i = 0; i < 3; ++i) {
            if (flat[i]) {
                if (o[i] < lo[i] || o[i] > hi[i]) return false;
                continue;
            }
            double t0 = (lo[i] - o[i]) * inv[i], t1 = (hi[i] - o[i]) * inv[i];
            if (t0 > t1) std::swap(t0, t1);
            tn = std::max(tn, t0);
            tf = std::min(tf, t1);
        }
        return tn <= tf + 2 * gamma(4) * std::max(std::abs(tn), std::abs(tf));
    }
};

int mesh_crossings(const CsgMember& m, uint32_t index, const RayPre& r, std::vector<CsgCrossing>& out,
                   Counters& c) {
    const CsgMesh& mesh = *m.mesh;
    const Line line(r);
    uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const CsgMesh::Node& node = mesh.nodes[stack[--top]];
        ++c.boxes;
        if (!line.meets(node.lo, node.hi)) continue;
        if (node.count == 0) {
            stack[top++] = node.first;
            stack[top++] = node.first + 1;
            continue;
        }
        for (uint32_t k = node.first; k < node.first + node.count; ++k) {
            const glm::uvec3& f = mesh.tris[k];
            double t, err, b1, b2;
            bool front;
            ++c.tri_tests;
            if (!triangle_line(r, mesh.verts[f.x], mesh.verts[f.y], mesh.verts[f.z], t, err, b1, b2, front))
                continue;
            ++c.tri_hits;
            const bool entering = front != mesh.flip;
            push(out, t, err, index, k, b1, b2, entering ? 1 : -1, false);
        }
    }
    return 0;
}

// Median-split BVH over faces ids[begin, end) into node `index`. Each split halves the range,
// so the depth stays far below the stack of mesh_crossings.
void build_node(CsgMesh& mesh, std::vector<uint32_t>& ids, const std::vector<Vec3>& centroid, uint32_t index,
                uint32_t begin, uint32_t end) {
    Vec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    Vec3 clo = lo, chi = hi;
    for (uint32_t i = begin; i < end; ++i) {
        const glm::uvec3& f = mesh.tris[ids[i]];
        for (uint32_t v : {f.x, f.y, f.z}) {
            lo = glm::min(lo, Vec3(mesh.verts[v]));
            hi = glm::max(hi, Vec3(mesh.verts[v]));
        }
        clo = glm::min(clo, centroid[ids[i]]);
        chi = glm::max(chi, centroid[ids[i]]);
    }
    const Vec3 pad = gamma(8) * (abs3(lo) + abs3(hi) + (hi - lo));
    mesh.nodes[index] = {lo - pad, hi + pad, begin, end - begin};
    if (end - begin <= kLeafTris) return;
    const Vec3 ext = chi - clo;
    const int axis = ext.x >= ext.y ? (ext.x >= ext.z ? 0 : 2) : (ext.y >= ext.z ? 1 : 2);
    const uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(ids.begin() + begin, ids.begin() + mid, ids.begin() + end,
                     [&](uint32_t a, uint32_t b) { return centroid[a][axis] < centroid[b][axis]; });
    const uint32_t children = static_cast<uint32_t>(mesh.nodes.size());
    mesh.nodes.resize(mesh.nodes.size() + 2);
    mesh.nodes[index].first = children;
    mesh.nodes[index].count = 0;
    build_node(mesh, ids, centroid, children, begin, mid);
    build_node(mesh, ids, centroid, children + 1, mid, end);
}

}  // namespace

int member_crossings(const CsgMember& m, uint32_t index, const RayPre& r, std::vector<CsgCrossing>& out,
                     Counters& c) {
    if (m.bounded && m.kind != CsgMemberKind::Mesh) {  // a mesh's own BVH starts with this test
        ++c.boxes;
        if (!Line(r).meets(m.wlo, m.whi)) return 0;
    }
    switch (m.kind) {
        case CsgMemberKind::Sphere: {
            ++c.sph_tests;
            const size_t before = out.size();
            const int inside = sphere_crossings(m, index, to_local(m, r), out);
            c.sph_hits += out.size() > before ? 1 : 0;  // as a mesh member counts the triangles it crosses
            return inside;
        }
        case CsgMemberKind::Box:
            ++c.shape_boxes;
            return box_crossings(m, index, to_local(m, r), out);
        case CsgMemberKind::Plane:
            ++c.planes;
            return plane_crossings(m, index, to_local(m, r), out);
        case CsgMemberKind::Mesh:
            return mesh_crossings(m, index, r, out, c);
        case CsgMemberKind::Quadric:
            return quadric_member_crossings(m, index, to_local(m, r), out);
    }
    return 0;
}

void member_surface(const CsgMember& m, const Ray& ray, double t, uint32_t sub, double b1, double b2,
                    SurfaceHit& s) {
    const Transform& x = m.x;
    switch (m.kind) {
        case CsgMemberKind::Sphere: {
            const Vec3 o = x.inv_point(ray.o), d = x.inv_vector(ray.d);
            const Vec3 rel = safe_normalize(o + t * d - m.center, Vec3(0, 1, 0)) * m.radius;
            const Vec3 p_obj = m.center + rel;
            s.p = x.point(p_obj);
            s.p_error = x.point_error(p_obj, gamma(6) * abs3(rel) + gamma(2) * abs3(p_obj) + m.band);
            s.ng = safe_normalize(x.normal(rel), Vec3(0, 1, 0));
            s.ns = s.ng;
            s.p_object = rel;
            s.uv = sphere_uv(safe_normalize(rel, Vec3(0, 1, 0)));
            return;
        }
        case CsgMemberKind::Box: {
            const int face = static_cast<int>(sub), axis = face >> 1;
            const Vec3 o = x.inv_point(ray.o), d = x.inv_vector(ray.d);
            Vec3 p = o + t * d;
            Vec3 e = gamma(3) * (abs3(o) + abs3(t * d)) + x.inv_point_error(ray.o) + m.band;
            p = glm::clamp(p, m.lo, m.hi);
            p[axis] = (face & 1) ? m.hi[axis] : m.lo[axis];
            e[axis] = 0;
            Vec3 n_obj(0);
            n_obj[axis] = (face & 1) ? 1.0 : -1.0;
            s.p = x.point(p);
            s.p_error = x.point_error(p, e);
            s.ng = safe_normalize(x.normal(n_obj), n_obj);
            s.ns = s.ng;
            s.p_object = p;
            s.uv = box_uv(p, m.lo, m.hi, face);
            return;
        }
        case CsgMemberKind::Plane: {
            const Vec3 o = x.inv_point(ray.o), d = x.inv_vector(ray.d);
            Vec3 p = o + t * d;
            p -= (glm::dot(m.n, p) - m.c) * m.n;
            s.p = x.point(p);
            s.p_error = x.point_error(p, gamma(6) * (abs3(p) + Vec3(std::abs(m.c))) + m.band);
            s.ng = safe_normalize(x.normal(m.n), m.n);
            s.ns = s.ng;
            s.p_object = p;
            const Vec3 u = plane_u_axis(m.n), v = glm::cross(m.n, u);
            s.plane_xy = Vec2(glm::dot(p, u), glm::dot(p, v));
            s.uv = s.plane_xy / m.uv_scale;
            s.planar = true;
            return;
        }
        case CsgMemberKind::Quadric: {
            const QuadricPrim& q = m.quadric;
            const Vec3 o = x.inv_point(ray.o), d = x.inv_vector(ray.d);
            const QuadricPoint qp = quadric_part_surface(q, static_cast<int>(sub), o, d, t);
            s.p = x.point(qp.p);
            s.p_error = x.point_error(qp.p, qp.p_error + m.band);
            s.ng = safe_normalize(x.normal(qp.n), qp.n);
            s.ns = s.ng;
            s.uv = qp.uv;
            s.p_object = quadric_to_object(q, qp.p);
            if (sub != kQuadricBody) {  // flat caps take the plane's path for checkers
                s.planar = true;
                s.plane_xy =
                    Vec2(qp.p.x, qp.p.z) + Vec2(glm::dot(q.origin, q.axis_x), glm::dot(q.origin, q.axis_z));
            }
            return;
        }
        case CsgMemberKind::Mesh: {
            const CsgMesh& mesh = *m.mesh;
            const glm::uvec3& f = mesh.tris[sub];
            const Vec3 v0(mesh.verts[f.x]), v1(mesh.verts[f.y]), v2(mesh.verts[f.z]);
            const double b0 = 1 - b1 - b2;
            s.p = b0 * v0 + b1 * v1 + b2 * v2;
            s.p_error = gamma(7) * (abs3(b0 * v0) + abs3(b1 * v1) + abs3(b2 * v2));
            const Vec3 ng = safe_normalize(glm::cross(v1 - v0, v2 - v0), Vec3(0, 0, 1));
            s.ng = mesh.flip ? -ng : ng;
            s.ns = s.ng;
            s.uv = Vec2(b1, b2);
            s.p_object = x.inv_point(s.p);
            const MeshData& data = *mesh.data;
            if (!data.uvs.empty())
                s.uv = b0 * Vec2(data.uvs[f.x]) + b1 * Vec2(data.uvs[f.y]) + b2 * Vec2(data.uvs[f.z]);
            if (!data.normals.empty()) {
                const Vec3 n0(data.normals[f.x]), n1(data.normals[f.y]), n2(data.normals[f.z]);
                Vec3 n = b0 * n0 + b1 * n1 + b2 * n2;
                // Vertex normals pointing, together, to the other side than the facet's outward
                // normal: negate the field (see triangle_surface_of in geometry_surface.cpp).
                if (glm::dot(x.normal(n0 + n1 + n2), s.ng) < 0) n = -n;
                const Vec3 ns = safe_normalize(x.normal(n), s.ng);
                const double below = glm::dot(ns, s.ng);
                s.ns = below < 0 ? ns - (2.0 * below) * s.ng : ns;
            }
            return;
        }
    }
}

std::shared_ptr<const CsgMesh> make_csg_mesh(const std::shared_ptr<const MeshData>& data, const Transform& x,
                                             std::string& error) {
    auto mesh = std::make_shared<CsgMesh>();
    mesh->data = data;
    const MeshData& m = *data;
    mesh->verts.reserve(m.vertices.size());
    for (size_t i = 0; i < m.vertices.size(); ++i) {
        const Vec3 w = x.point(Vec3(m.vertices[i]));
        const Vec3f wf(static_cast<float>(w.x), static_cast<float>(w.y), static_cast<float>(w.z));
        if (!is_finite(m.vertices[i]) || !is_finite(wf)) {
            error = "mesh vertex " + std::to_string(i) +
                    " is out of range: after any transform, it must stay within ±3.4e38 (the largest float)";
            return nullptr;
        }
        mesh->verts.push_back(wf);
    }
    // The signed volume says which way the (consistently oriented) faces wind in world space.
    double volume = 0;
    std::vector<Vec3> centroid;
    centroid.reserve(m.faces.size());
    for (size_t i = 0; i < m.faces.size(); ++i) {
        const glm::uvec3& f = m.faces[i];
        const Vec3 a(mesh->verts[f.x]), b(mesh->verts[f.y]), c(mesh->verts[f.z]);
        if (!(glm::length(glm::cross(b - a, c - a)) > 1e-12 * glm::length(b - a) * glm::length(c - a))) {
            error = "mesh face " + std::to_string(i) + " is degenerate: its vertices do not span an area";
            return nullptr;
        }
        volume += glm::dot(a, glm::cross(b, c));
        centroid.push_back((a + b + c) / 3.0);
    }
    mesh->flip = volume < 0;
    std::vector<uint32_t> ids(m.faces.size());
    std::iota(ids.begin(), ids.end(), 0u);
    mesh->tris = m.faces;
    mesh->nodes.resize(1);
    build_node(*mesh, ids, centroid, 0, 0, static_cast<uint32_t>(ids.size()));
    std::vector<glm::uvec3> tris(ids.size());
    for (size_t i = 0; i < ids.size(); ++i) tris[i] = m.faces[ids[i]];
    mesh->tris = std::move(tris);
    mesh->face = std::move(ids);
    return mesh;
}

}  // namespace wsd::render::detail
