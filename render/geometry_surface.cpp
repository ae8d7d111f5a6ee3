// Geometry::surface: the hit point with its rounding-error bound, normals, UVs and object-frame
// point of each shape kind. Sphere points are reprojected onto the sphere and triangle points
// interpolated from barycentrics, so their error bounds are tight (robustness.md, offset origins).
#include <cmath>

#include "render/geometry_impl.h"
#include "render/other_prims.h"

namespace wsd::render {

using Impl = Geometry::Impl;

void triangle_surface_of(const Vec3 (&v)[3], const uint32_t (&local)[3], const ShapeInfo& info,
                         const TriExtra* extra, const Transform& x, const HitRecord& hit, SurfaceHit& s) {
    const Vec3 &v0 = v[0], &v1 = v[1], &v2 = v[2];
    const double b1 = hit.b1, b2 = hit.b2, b0 = 1 - b1 - b2;
    s.p = b0 * v0 + b1 * v1 + b2 * v2;
    s.p_error = gamma(7) * (abs3(b0 * v0) + abs3(b1 * v1) + abs3(b2 * v2));
    Vec3 ng = safe_normalize(glm::cross(v1 - v0, v2 - v0), Vec3(0, 0, 1));
    s.ng = info.mirrored ? -ng : ng;
    s.ns = s.ng;
    s.uv = Vec2(b1, b2);
    s.p_object = x.identity ? s.p : x.inv_point(s.p);

    if (extra != nullptr) {
        if (extra->has_uv) s.uv = b0 * extra->uv[0] + b1 * extra->uv[1] + b2 * extra->uv[2];
        return;
    }
    if (!info.mesh) return;
    const MeshData& m = *info.mesh;
    const uint32_t i0 = local[0], i1 = local[1], i2 = local[2];
    if (!m.uvs.empty()) s.uv = b0 * Vec2(m.uvs[i0]) + b1 * Vec2(m.uvs[i1]) + b2 * Vec2(m.uvs[i2]);
    if (!m.normals.empty()) {
        const Vec3 n0(m.normals[i0]), n1(m.normals[i1]), n2(m.normals[i2]);
        Vec3 n = b0 * n0 + b1 * n1 + b2 * n2;
        // Vertex normals that together point to the other side of the facet than its winding
        // (a mesh whose faces wind the other way round) describe the same surface seen from that
        // side: negate the whole field, so the shading normal is the interpolated one turned to
        // face the viewer, not its mirror image about the facet.
        const Vec3 sum = n0 + n1 + n2;
        if (glm::dot(x.identity ? sum : x.normal(sum), s.ng) < 0) n = -n;
        Vec3 ns = safe_normalize(x.identity ? n : x.normal(n), s.ng);
        // An interpolated normal on the far side of the facet would send reflections into it:
        // mirror it about the facet's plane (not negate it, which would jump from grazing one way
        // to grazing the other where the interpolation crosses the plane: a dark seam, R35).
        const double below = glm::dot(ns, s.ng);
        s.ns = below < 0 ? ns - (2.0 * below) * s.ng : ns;
    }
}

void sphere_surface_of(const SpherePrim& sp, const Transform& x, const Ray& ray, const HitRecord& hit,
                       SurfaceHit& s) {
    if (sp.xform == kNoTransform) {
        Vec3 rel = ray.o + hit.t * ray.d - sp.center;
        rel = safe_normalize(rel, Vec3(0, 1, 0)) * sp.radius;
        s.p = sp.center + rel;
        s.p_error = gamma(6) * abs3(rel) + gamma(2) * abs3(s.p);
        s.ng = safe_normalize(rel, Vec3(0, 1, 0));
        s.p_object = x.identity ? rel : x.inv_vector(rel);
    } else {
        Vec3 o = x.inv_point(ray.o), d = x.inv_vector(ray.d);
        Vec3 rel = safe_normalize(o + hit.t * d - sp.center, Vec3(0, 1, 0)) * sp.radius;
        Vec3 p_obj = sp.center + rel;
        s.p = x.point(p_obj);
        s.p_error = x.point_error(p_obj, gamma(6) * abs3(rel) + gamma(2) * abs3(p_obj));
        s.ng = safe_normalize(x.normal(rel), Vec3(0, 1, 0));
        s.p_object = rel;
    }
    s.ns = s.ng;
    s.uv = sphere_uv(safe_normalize(s.p_object, Vec3(0, 1, 0)));
}

void box_surface_of(const BoxPrim& bx, const Transform& x, const Ray& ray, const HitRecord& hit,
                    SurfaceHit& s) {
    const int face = static_cast<int>(hit.b1);
    const int axis = face >> 1;
    // The identity goes through the same formulas as any transform (exactly), so that scaling
    // a scene by 2^k scales every bound exactly.
    Vec3 o = x.inv_point(ray.o), d = x.inv_vector(ray.d);
    Vec3 p = o + hit.t * d;
    Vec3 e = gamma(3) * (abs3(o) + abs3(hit.t * d)) + x.inv_point_error(ray.o);
    p = glm::clamp(p, bx.lo, bx.hi);
    p[axis] = (face & 1) ? bx.hi[axis] : bx.lo[axis];  // exactly on the face
    e[axis] = 0;
    Vec3 n_obj(0);
    n_obj[axis] = (face & 1) ? 1.0 : -1.0;
    s.p = x.point(p);
    s.p_error = x.point_error(p, e);
    s.ng = safe_normalize(x.normal(n_obj), n_obj);
    s.ns = s.ng;
    s.p_object = p;
    s.uv = box_uv(p, bx.lo, bx.hi, face);
}

namespace {

void triangle_surface(const Impl& g, const ShapeInfo& info, const HitRecord& hit, SurfaceHit& s) {
    const TriPrim& tri = g.tris[hit.slot];
    const Vec3 v[3] = {Vec3(g.verts[tri.v[0]]), Vec3(g.verts[tri.v[1]]), Vec3(g.verts[tri.v[2]])};
    const uint32_t local[3] = {tri.v[0] - info.vertex_offset, tri.v[1] - info.vertex_offset,
                               tri.v[2] - info.vertex_offset};
    const TriExtra* extra = info.kind == ShapeKind::Triangle ? &g.tri_extra[info.extra] : nullptr;
    triangle_surface_of(v, local, info, extra, g.xforms[info.xform], hit, s);
}

void sphere_surface(const Impl& g, const ShapeInfo& info, const Ray& ray, const HitRecord& hit,
                    SurfaceHit& s) {
    sphere_surface_of(g.spheres[hit.slot], g.xforms[info.xform], ray, hit, s);
}

void box_surface(const Impl& g, const Ray& ray, const HitRecord& hit, SurfaceHit& s) {
    const BoxPrim& bx = g.boxes[hit.slot];
    box_surface_of(bx, g.xforms[bx.xform == kNoTransform ? 0 : bx.xform], ray, hit, s);
}

void plane_surface(const Impl& g, const ShapeInfo& info, const Ray& ray, const HitRecord& hit,
                   SurfaceHit& s) {
    const PlanePrim& pl = g.planes[hit.slot];
    const PlaneExtra& e = g.plane_extra[info.extra];
    Vec3 p = ray.o + hit.t * ray.d;
    p -= (glm::dot(pl.n, p) - pl.c) * pl.n;  // back onto the plane
    s.p = p;
    s.p_error = gamma(6) * (abs3(p) + Vec3(std::abs(pl.c)));
    s.ng = pl.n;
    s.ns = pl.n;
    const Transform& x = g.xforms[info.xform];
    s.p_object = x.identity ? p : x.inv_point(p);
    s.plane_xy = Vec2(glm::dot(s.p_object, e.u), glm::dot(s.p_object, e.v));
    s.uv = s.plane_xy / e.uv_scale;
    s.planar = true;
}

}  // namespace

SurfaceHit Geometry::surface(const Ray& ray, const HitRecord& hit) const {
    const Impl& g = *impl_;
    SurfaceHit s;
    const uint32_t shape = g.shape_of(hit.prim);
    const ShapeInfo& info = g.shapes[shape];
    s.shape = shape;
    s.prim = hit.prim;
    s.material = info.material;
    switch (info.kind) {
        case ShapeKind::Triangle:
        case ShapeKind::Mesh:
            triangle_surface(g, info, hit, s);
            break;
        case ShapeKind::Sphere:
            sphere_surface(g, info, ray, hit, s);
            break;
        case ShapeKind::Box:
            box_surface(g, ray, hit, s);
            break;
        case ShapeKind::Plane:
            plane_surface(g, info, ray, hit, s);
            break;
        case ShapeKind::Cylinder:
        case ShapeKind::Cone:
        case ShapeKind::Torus:
        case ShapeKind::Disc:
        case ShapeKind::Csg:
        case ShapeKind::Instance:
            other_surface(g, info, ray, hit, s);
            break;
    }
    return s;
}

}  // namespace wsd::render
