// Geometry::build: validates every shape (robustness.md, load-time validation: non-finite values,
// degenerate triangles, bad indices, singular transforms, the 2^24 primitive limit), converts it
// to world-space primitives, builds the BVH over the bounded ones and stores them in leaf order.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <thread>
#include <utility>

#include "render/geometry_impl.h"
#include "render/mesh_file.h"
#include "render/other_prims.h"
#include "render/parallel.h"

namespace wsd::render {

namespace {

constexpr int kMaxFaceErrorsPerMesh = 10;

struct Builder {
    const SceneSpec& spec;
    const std::vector<ShapeSpec>& shapes;  // spec.shapes, or a prototype's
    std::vector<SpecError>& errors;
    Geometry::Impl& g;
    bool prototype = false;  // members may inherit their material; no planes, no instances
    int threads = 0;
    std::vector<Bounds3f> bounds;      // per bounded primitive but triangles, canonical order
    HugePageVector<uint32_t> entries;  // encoded entries of every bounded primitive, same order
    std::vector<uint8_t> inherits;     // prototypes: 1 where the primitive inherits its material
    uint32_t next_prim = 0;
    size_t stored = 0, instances = 0;  // for the limits: primitives stored, instances
    std::vector<uint8_t> counted;      // per prototype: its primitives are in `stored`
    size_t shape_index = 0;
    int shape_errors = 0;

    void error(std::string message, long face = -1) {
        const ShapeSpec& s = shapes[shape_index];
        errors.push_back(SpecError{SpecItem::Shape, shape_index, s.tag, std::move(message), face});
        ++shape_errors;
    }

    // An inherited material counts as opaque here; Prototype::inherits marks those primitives.
    bool transmissive(uint32_t material) const {
        return material != kInheritMaterial && spec.materials[material].transmission > 0;
    }

    // Triangles' bounds are not stored: finish_bvh takes them from the vertices.
    void add_bounded(PrimKind kind, uint32_t slot, const Bounds3f& b, bool trans) {
        bounds.push_back(b);
        add_entry(kind, slot, trans);
    }
    void add_triangle(uint32_t slot, bool trans) { add_entry(PrimKind::Triangle, slot, trans); }
    void add_entry(PrimKind kind, uint32_t slot, bool trans) {
        entries.push_back(encode_entry(kind, slot, trans));
        if (prototype) inherits.push_back(shapes[shape_index].material == kInheritMaterial ? 1 : 0);
        ++next_prim;
    }

    uint32_t add_transform(const Transform& x) {
        if (x.identity) return 0;
        const Transform& last = g.xforms.back();
        bool same = true;
        for (int i = 0; i < 3; ++i) same = same && last.l[i] == x.l[i];
        if (same && last.t == x.t && g.xforms.size() > 1) return static_cast<uint32_t>(g.xforms.size() - 1);
        g.xforms.push_back(x);
        return static_cast<uint32_t>(g.xforms.size() - 1);
    }

    void sphere(const ShapeSpec& s, const Transform& x, ShapeInfo& info, bool trans);
    void box(const ShapeSpec& s, const Transform& x, ShapeInfo& info, bool trans);
    void triangle(const ShapeSpec& s, const Transform& x, ShapeInfo& info, bool trans);
    void plane(const ShapeSpec& s, const Transform& x, ShapeInfo& info, bool trans);
    void mesh(const ShapeSpec& s, const Transform& x, ShapeInfo& info, bool trans);
    void other(OtherKind kind, const ShapeSpec& s, const Transform& x, ShapeInfo& info, bool& trans);
    void shape(size_t i, bool& limit_reported);
    void finish_bvh();
    bool world_vertex(const Transform& x, const Vec3& p, Vec3f& out);
    bool degenerate(uint32_t i0, uint32_t i1, uint32_t i2) const;
};

// Widens a double box by its own rounding error before taking conservative float bounds, so
// that hits accepted at the very rim of a shape stay inside its node.
Bounds3f padded(const Vec3& lo, const Vec3& hi) {
    Vec3 pad = gamma(8) * (abs3(lo) + abs3(hi) + (hi - lo));
    return Bounds3f::around(lo - pad, hi + pad);
}

void Builder::sphere(const ShapeSpec& s, const Transform& x, ShapeInfo& info, bool trans) {
    if (!is_finite(s.center)) return error("sphere center has a non-finite coordinate");
    if (!std::isfinite(s.radius) || !(s.radius > 0)) return error("sphere radius must be a positive number");
    SpherePrim p{};
    p.prim = next_prim;
    Vec3 lo, hi;
    if (x.similarity) {
        // World space: the sphere is defined by its transformed centre and scaled radius.
        p.center = x.point(s.center);
        p.radius = s.radius * x.scale;
        p.xform = kNoTransform;
        lo = p.center - Vec3(p.radius);
        hi = p.center + Vec3(p.radius);
    } else {
        p.center = s.center;
        p.radius = s.radius;
        p.xform = info.xform;
        Vec3 c = x.point(s.center);
        Vec3 ext(s.radius * glm::length(x.l[0]), s.radius * glm::length(x.l[1]),
                 s.radius * glm::length(x.l[2]));
        lo = c - ext;
        hi = c + ext;
    }
    if (!is_finite(p.center) || !std::isfinite(p.radius) || !(p.radius > 0) || !is_finite(lo) ||
        !is_finite(hi))
        return error(
            "sphere is out of range: its bounds, after any transform, must stay within ±3.4e38 (the largest "
            "float)");
    Bounds3f b = padded(lo, hi);
    if (!is_finite(b.lo) || !is_finite(b.hi))
        return error(
            "sphere is out of range: its bounds, after any transform, must stay within ±3.4e38 (the largest "
            "float)");
    info.extra = static_cast<uint32_t>(g.spheres.size());
    add_bounded(PrimKind::Sphere, static_cast<uint32_t>(g.spheres.size()), b, trans);
    g.spheres.push_back(p);
}

void Builder::box(const ShapeSpec& s, const Transform& x, ShapeInfo& info, bool trans) {
    if (!is_finite(s.box_min) || !is_finite(s.box_max))
        return error("box corner has a non-finite coordinate");
    if (!(s.box_min.x < s.box_max.x && s.box_min.y < s.box_max.y && s.box_min.z < s.box_max.z))
        return error("box min must be below max on every axis (a flat box has no volume)");
    BoxPrim p{};
    p.lo = s.box_min;
    p.hi = s.box_max;
    p.prim = next_prim;
    p.xform = x.identity ? kNoTransform : info.xform;
    Vec3 m = glm::max(abs3(p.lo), abs3(p.hi));
    double mmax = std::max({m.x, m.y, m.z});
    p.band = x.resid_lin * mmax + x.resid_t;
    Vec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (int c = 0; c < 8; ++c) {
        Vec3 corner((c & 1) ? p.hi.x : p.lo.x, (c & 2) ? p.hi.y : p.lo.y, (c & 4) ? p.hi.z : p.lo.z);
        Vec3 w = x.point(corner);
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
    }
    Bounds3f b = padded(lo, hi);
    if (!is_finite(b.lo) || !is_finite(b.hi))
        return error(
            "box is out of range: its bounds, after any transform, must stay within ±3.4e38 (the largest "
            "float)");
    info.extra = static_cast<uint32_t>(g.boxes.size());
    add_bounded(PrimKind::Box, static_cast<uint32_t>(g.boxes.size()), b, trans);
    g.boxes.push_back(p);
}

bool Builder::world_vertex(const Transform& x, const Vec3& p, Vec3f& out) {
    out = world_vertex_of(x, p);
    return is_finite(out);
}

// Zero area in world space (after rounding to float): |e1 × e2| ≤ 1e-12·|e1||e2|.
bool Builder::degenerate(uint32_t i0, uint32_t i1, uint32_t i2) const {
    Vec3 v0(g.verts[i0]), v1(g.verts[i1]), v2(g.verts[i2]);
    Vec3 e1 = v1 - v0, e2 = v2 - v0;
    double cr = glm::length(glm::cross(e1, e2));
    return !(cr > 1e-12 * glm::length(e1) * glm::length(e2));
}

void Builder::triangle(const ShapeSpec& s, const Transform& x, ShapeInfo& info, bool trans) {
    for (const Vec3& v : s.v)
        if (!is_finite(v)) return error("triangle vertex has a non-finite coordinate");
    if (s.tri_uv)
        for (const Vec2& uv : *s.tri_uv)
            if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return error("triangle uv is not finite");
    uint32_t base = static_cast<uint32_t>(g.verts.size());
    for (const Vec3& v : s.v) {
        Vec3f w;
        if (!world_vertex(x, v, w)) {
            g.verts.resize(base);
            return error(
                "triangle is out of range: its bounds, after any transform, must stay within ±3.4e38 (the "
                "largest float)");
        }
        g.verts.push_back(w);
    }
    if (degenerate(base, base + 1, base + 2)) {
        g.verts.resize(base);
        return error("degenerate triangle: its vertices do not span an area");
    }
    info.vertex_offset = base;
    TriExtra extra;
    if (s.tri_uv) {
        extra.has_uv = true;
        for (int i = 0; i < 3; ++i) extra.uv[i] = (*s.tri_uv)[i];
    }
    info.extra = static_cast<uint32_t>(g.tri_extra.size());
    g.tri_extra.push_back(extra);
    add_triangle(static_cast<uint32_t>(g.tris.size()), trans);
    g.tris.push_back(TriPrim{{base, base + 1, base + 2}, next_prim - 1});
}

void Builder::plane(const ShapeSpec& s, const Transform& x, ShapeInfo& info, bool trans) {
    if (!is_finite(s.normal)) return error("plane normal has a non-finite coordinate");
    if (!std::isfinite(s.distance)) return error("plane distance is not finite");
    if (!std::isfinite(s.uv_scale) || !(s.uv_scale > 0))
        return error("plane uv_scale must be a positive number");
    Vec3 n = safe_normalize(s.normal, Vec3(0));
    if (n == Vec3(0)) return error("plane normal must not be zero");
    PlanePrim p{};
    p.n = safe_normalize(x.normal(n), Vec3(0));
    Vec3 on_plane = x.point(n * s.distance);
    p.c = glm::dot(p.n, on_plane);
    p.prim = next_prim++;
    p.transmissive = trans ? 1u : 0u;
    if (p.n == Vec3(0) || !std::isfinite(p.c))
        return error(
            "plane is out of range: its distance from the origin, after any transform, must stay within "
            "±3.4e38 (the largest float)");
    PlaneExtra extra;
    extra.u = plane_u_axis(n);
    extra.v = glm::cross(n, extra.u);
    extra.uv_scale = s.uv_scale;
    info.extra = static_cast<uint32_t>(g.planes.size());
    g.plane_extra.push_back(extra);
    g.planes.push_back(p);
}

void Builder::mesh(const ShapeSpec& s, const Transform& x, ShapeInfo& info, bool trans) {
    if (!s.mesh) return error("mesh has no data");
    const MeshData& m = *s.mesh;
    const size_t nv = m.vertices.size();
    if (!m.uvs.empty() && m.uvs.size() != nv)
        return error("mesh has " + std::to_string(m.uvs.size()) + " uvs for " + std::to_string(nv) +
                     " vertices (need one per vertex)");
    if (!m.normals.empty() && m.normals.size() != nv)
        return error("mesh has " + std::to_string(m.normals.size()) + " normals for " + std::to_string(nv) +
                     " vertices (need one per vertex)");
    if (g.verts.size() + nv > kSlotMask) return error("mesh has too many vertices");
    for (size_t i = 0; i < m.uvs.size(); ++i)
        if (!std::isfinite(m.uvs[i].x) || !std::isfinite(m.uvs[i].y))
            return error("mesh uv " + std::to_string(i) + " is not finite");
    for (size_t i = 0; i < m.normals.size(); ++i)
        if (!is_finite(m.normals[i])) return error("mesh normal " + std::to_string(i) + " is not finite");

    // Vertices and faces are checked in fixed chunks on every thread; each chunk keeps its first
    // face errors in face order, and the chunks' are reported in chunk order: the same messages,
    // in the same order, as one pass over the faces.
    constexpr size_t kChunk = size_t{1} << 14;
    const uint32_t base = static_cast<uint32_t>(g.verts.size());
    g.verts.resize(base + nv);
    std::vector<uint8_t> bad_vertex(nv, 0);
    parallel_chunks(nv, kChunk, threads, [&](size_t, size_t begin, size_t end, int) {
        for (size_t i = begin; i < end; ++i) {
            Vec3f w;
            bool ok = is_finite(m.vertices[i]) && world_vertex(x, Vec3(m.vertices[i]), w);
            g.verts[base + i] = ok ? w : Vec3f(0);
            bad_vertex[i] = ok ? 0 : 1;
        }
    });
    struct FaceErrors {
        std::vector<std::pair<size_t, std::string>> first;  // at most kMaxFaceErrorsPerMesh
        size_t count = 0;
    };
    const size_t nf = m.faces.size();
    std::vector<FaceErrors> chunk_errors((nf + kChunk - 1) / kChunk);
    parallel_chunks(nf, kChunk, threads, [&](size_t c, size_t begin, size_t end, int) {
        FaceErrors& fe = chunk_errors[c];
        auto face_error = [&fe](size_t f, std::string what) {
            if (fe.first.size() < kMaxFaceErrorsPerMesh) fe.first.emplace_back(f, std::move(what));
            ++fe.count;
        };
        for (size_t f = begin; f < end; ++f) {
            const glm::uvec3& face = m.faces[f];
            if (face.x >= nv || face.y >= nv || face.z >= nv) {
                face_error(f, "vertex index out of range (the mesh has " + std::to_string(nv) +
                                  (nv == 1 ? " vertex)" : " vertices)"));
                continue;
            }
            if (bad_vertex[face.x] || bad_vertex[face.y] || bad_vertex[face.z]) {
                size_t k = bad_vertex[face.x] ? face.x : (bad_vertex[face.y] ? face.y : face.z);
                face_error(f, is_finite(m.vertices[k])
                                  ? "vertex " + std::to_string(k) + " is out of range after the transform"
                                  : "vertex " + std::to_string(k) + " has a non-finite coordinate");
                continue;
            }
            if (degenerate(base + face.x, base + face.y, base + face.z))
                face_error(f, "degenerate triangle: its vertices do not span an area");
        }
    });
    size_t total = 0, reported = 0;
    for (const FaceErrors& fe : chunk_errors) {
        total += fe.count;
        for (const auto& [f, what] : fe.first)
            if (reported < kMaxFaceErrorsPerMesh) {
                error(face_name(m, f) + ": " + what, static_cast<long>(f));
                ++reported;
            }
    }
    const size_t more_errors = total - reported;
    if (more_errors > 0)
        error("mesh has " + std::to_string(more_errors) +
              (more_errors == 1 ? " more invalid face" : " more invalid faces"));
    if (shape_errors > 0) return;
    // Every face is valid: one triangle each, written by index.
    const size_t tri_base = g.tris.size(), entry_base = entries.size();
    const uint32_t prim_base = next_prim;
    g.tris.resize(tri_base + nf);
    entries.resize(entry_base + nf);
    if (prototype) inherits.resize(entry_base + nf, shapes[shape_index].material == kInheritMaterial ? 1 : 0);
    next_prim += static_cast<uint32_t>(nf);
    parallel_chunks(nf, kChunk, threads, [&](size_t, size_t begin, size_t end, int) {
        for (size_t f = begin; f < end; ++f) {
            const glm::uvec3& face = m.faces[f];
            const auto slot = static_cast<uint32_t>(tri_base + f);
            entries[entry_base + f] = encode_entry(PrimKind::Triangle, slot, trans);
            g.tris[slot] = TriPrim{{base + face.x, base + face.y, base + face.z}, prim_base + uint32_t(f)};
        }
    });
    info.vertex_offset = base;
    if (!m.normals.empty() || !m.uvs.empty()) info.mesh = s.mesh;
}

// Cylinders, cones, tori, discs, CSG solids and instances: built by their own modules
// (render/other_prims.h), one PrimKind::Other entry each.
void Builder::other(OtherKind kind, const ShapeSpec& s, const Transform& x, ShapeInfo& info, bool& trans) {
    const std::function<void(std::string)> report = [this](std::string m) { error(std::move(m)); };
    const OtherBuild ob{g, spec, report, next_prim, info.xform, &trans, threads};
    std::optional<Bounds3f> b;
    uint32_t index = 0;
    switch (kind) {
        case OtherKind::Quadric:
            index = static_cast<uint32_t>(g.quadrics.size());
            b = build_quadric(ob, s, x);
            break;
        case OtherKind::Csg:
            index = static_cast<uint32_t>(g.csgs.size());
            b = build_csg(ob, s, x);
            break;
        case OtherKind::Instance:
            index = static_cast<uint32_t>(g.instances.size());
            b = build_instance(ob, s, x);
            break;
    }
    if (!b || shape_errors > 0) return;
    info.extra = static_cast<uint32_t>(g.others.size());
    if (kind == OtherKind::Instance) {
        // One entry per InstancePrim, all with the instance's one canonical id: an instance with
        // opaque and transmissive members has an entry for each, so that ray filters apply to
        // the members (render/instance_prims.h).
        for (uint32_t k = index; k < g.instances.size(); ++k) {
            const bool member_trans = g.instances[k].transmissive;
            add_bounded(PrimKind::Other, static_cast<uint32_t>(g.others.size()), *b, member_trans);
            if (member_trans) g.has_transmissive = true;
            g.others.push_back(OtherPrim{kind, k});
            --next_prim;
        }
        ++next_prim;
        return;
    }
    add_bounded(PrimKind::Other, static_cast<uint32_t>(g.others.size()), *b, trans);
    g.others.push_back(OtherPrim{kind, index});
}

// One shape: its material and transform checked, then built by its kind's code.
void Builder::shape(size_t i, bool& limit_reported) {
    const ShapeSpec& s = shapes[i];
    shape_index = i;
    shape_errors = 0;
    // Members of an instanced object may take the instance's material; an instance without one
    // is checked against its members by build_instance.
    const bool inherit = (prototype || s.kind == ShapeKind::Instance) && s.material == kInheritMaterial;
    if (!inherit && s.material >= spec.materials.size()) {
        error("material index " + std::to_string(s.material) + " is out of range");
        return;
    }
    if (prototype && (s.kind == ShapeKind::Instance || s.kind == ShapeKind::Plane)) {
        error(s.kind == ShapeKind::Plane ? "a plane cannot be part of an instanced object (it has no bounds)"
                                         : "an instanced object cannot contain an instance");
        return;
    }
    Transform x;
    if (auto msg = make_transform(s.object_to_world, x)) {
        error(*msg);
        return;
    }
    ShapeInfo info;
    info.kind = s.kind;
    info.material = s.material;
    info.xform = add_transform(x);
    info.first_prim = next_prim;
    info.mirrored = x.det < 0;
    bool trans = transmissive(s.material);
    switch (s.kind) {
        case ShapeKind::Sphere:
            sphere(s, x, info, trans);
            break;
        case ShapeKind::Box:
            box(s, x, info, trans);
            break;
        case ShapeKind::Triangle:
            triangle(s, x, info, trans);
            break;
        case ShapeKind::Plane:
            plane(s, x, info, trans);
            break;
        case ShapeKind::Mesh:
            mesh(s, x, info, trans);
            break;
        case ShapeKind::Cylinder:
        case ShapeKind::Cone:
        case ShapeKind::Torus:
        case ShapeKind::Disc:
            other(OtherKind::Quadric, s, x, info, trans);
            break;
        case ShapeKind::Csg:
            other(OtherKind::Csg, s, x, info, trans);
            break;
        case ShapeKind::Instance:
            other(OtherKind::Instance, s, x, info, trans);
            break;
    }
    if (shape_errors > 0) return;
    // Stored primitives (each instanced object's once) and instances have a limit each.
    if (s.kind == ShapeKind::Instance) {
        ++instances;
        if (s.prototype < g.prototypes.size() && g.prototypes[s.prototype] && !counted[s.prototype]) {
            counted[s.prototype] = 1;
            stored += g.prototypes[s.prototype]->geometry->primitive_count;
        }
    } else {
        stored += next_prim - info.first_prim;
    }
    if (stored > kMaxPrimitives && !limit_reported) {
        error("the scene has more than 2^24 primitives (" + std::to_string(stored) + " so far)");
        limit_reported = true;
    }
    if (instances > kMaxPrimitives && !limit_reported) {
        error("the scene has more than 2^24 instances");
        limit_reported = true;
    }
    if (trans && s.kind != ShapeKind::Instance) g.has_transmissive = true;
    g.shapes.push_back(std::move(info));
    g.shape_first.push_back(g.shapes.back().first_prim);
}

// The BVH over the bounded primitives, which are then stored in leaf order so that a leaf's
// data is contiguous.
void Builder::finish_bvh() {
    BvhOptions opt;
    opt.threads = threads;
    // Bounds in canonical order: a triangle's from its vertices, the others' stored in turn.
    // Chunks are bounded in parallel, so each starts at the stored bounds of the entries before it.
    const auto kind_of = [&](uint32_t i) { return static_cast<PrimKind>((entries[i] >> kKindShift) & 3u); };
    const auto is_triangle = [&](uint32_t i) { return kind_of(i) == PrimKind::Triangle; };
    const size_t chunks = (entries.size() + kBvhChunk - 1) / kBvhChunk;
    std::vector<size_t> first_bounds(chunks, 0);
    if (!bounds.empty()) {
        parallel_chunks(entries.size(), kBvhChunk, threads, [&](size_t c, size_t begin, size_t end, int) {
            for (size_t i = begin; i < end; ++i) first_bounds[c] += is_triangle(uint32_t(i)) ? 0 : 1;
        });
        size_t sum = 0;
        for (size_t& f : first_bounds) sum += std::exchange(f, sum);
    }
    const auto bound = [&](uint32_t begin, uint32_t end, Bounds3f* out) {
        size_t next_bounds = first_bounds[begin / kBvhChunk];
        for (uint32_t i = begin; i < end; ++i) {
            if (!is_triangle(i)) {
                out[i - begin] = bounds[next_bounds++];
                continue;
            }
            const TriPrim& t = g.tris[entries[i] & kSlotMask];
            Bounds3f b;
            for (uint32_t v : t.v) b.extend(g.verts[v]);
            out[i - begin] = b;
        }
    };
    Bvh bvh = build_bvh(entries.size(), bound, opt);
    // Subtrees of triangles only may merge into one wide leaf; other primitives cost more.
    g.nodes = to_bvh_wide(
        bvh.nodes,
        [&](uint32_t first, uint32_t count) {
            for (uint32_t k = first; k < first + count; ++k)
                if (!is_triangle(bvh.order[k])) return false;
            return true;
        },
        threads);
    g.bvh_depth = bvh.depth;
    // Stored in leaf order in fixed chunks on every thread: each chunk's first slot of each kind
    // is the count of that kind in the chunks before it.
    if (prototype) g.inherits.resize(inherits.size());
    g.order = std::move(bvh.order);  // rewritten in place: entry k reads only bvh.order[k]
    const size_t n = g.order.size();
    std::vector<std::array<uint32_t, 4>> first((n + kBvhChunk - 1) / kBvhChunk, std::array<uint32_t, 4>{});
    parallel_chunks(n, kBvhChunk, threads, [&](size_t c, size_t begin, size_t end, int) {
        for (size_t k = begin; k < end; ++k) ++first[c][static_cast<size_t>(kind_of(g.order[k]))];
    });
    std::array<uint32_t, 4> sum{};
    for (auto& f : first)
        for (size_t kind = 0; kind < 4; ++kind) sum[kind] += std::exchange(f[kind], sum[kind]);
    HugePageVector<TriPrim> tris(g.tris.size());
    std::vector<SpherePrim> spheres(g.spheres.size());
    std::vector<BoxPrim> boxes(g.boxes.size());
    parallel_chunks(n, kBvhChunk, threads, [&](size_t c, size_t begin, size_t end, int) {
        std::array<uint32_t, 4> next = first[c];
        for (size_t k = begin; k < end; ++k) {
            const uint32_t from = g.order[k];
            const uint32_t e = entries[from];
            const uint32_t slot = e & kSlotMask;
            const PrimKind kind = kind_of(from);
            uint32_t ns = next[static_cast<size_t>(kind)]++;
            switch (kind) {
                case PrimKind::Triangle:
                    tris[ns] = g.tris[slot];
                    break;
                case PrimKind::Sphere:
                    spheres[ns] = g.spheres[slot];
                    break;
                case PrimKind::Box:
                    boxes[ns] = g.boxes[slot];
                    break;
                case PrimKind::Other:
                    ns = slot;  // Impl::others keeps its build order (ShapeInfo::extra points into it)
                    break;
            }
            g.order[k] = encode_entry(kind, ns, (e & kTransmissiveBit) != 0);
            if (prototype) g.inherits[k] = inherits[from];
        }
    });
    g.tris = std::move(tris);
    g.spheres = std::move(spheres);
    g.boxes = std::move(boxes);
    // Triangles alone are stored in the order of their entries: entry k is tris[k].
    g.tris_in_order =
        sum[static_cast<size_t>(PrimKind::Triangle)] == n &&
        std::none_of(g.order.begin(), g.order.end(), [](uint32_t e) { return (e & kTransmissiveBit) != 0; });
    // Entry k is then k itself (encode_entry of an opaque triangle at slot k): not stored, 4 bytes
    // a triangle less.
    if (g.tris_in_order) HugePageVector<uint32_t>().swap(g.order);
}

}  // namespace

bool build_geometry_into(Geometry::Impl& g, const SceneSpec& spec, const std::vector<ShapeSpec>& shapes,
                         std::vector<SpecError>& errors, bool use_bvh, int threads, bool prototype) {
    g.use_bvh = use_bvh;
    g.xforms.push_back(Transform{});
    Builder b{spec, shapes, errors, g, prototype, threads, {}, {}, {}, 0, 0, 0, {}, 0, 0};
    b.counted.assign(spec.prototypes.size(), 0);
    // Every buffer at its final size up front: a million-triangle mesh would otherwise copy
    // them while growing, and fault in fresh pages for each copy. The large ones are in huge
    // pages (render/huge_pages.h).
    size_t n_tris = 0, n_verts = 0, n_bounded = 0;
    for (const ShapeSpec& s : shapes) {
        const bool mesh = s.kind == ShapeKind::Mesh && s.mesh;
        n_tris += mesh ? s.mesh->faces.size() : (s.kind == ShapeKind::Triangle ? 1 : 0);
        n_verts += mesh ? s.mesh->vertices.size() : (s.kind == ShapeKind::Triangle ? 3 : 0);
        n_bounded += mesh ? s.mesh->faces.size() : (s.kind == ShapeKind::Plane ? 0 : 1);
    }
    g.tris.reserve(n_tris);  // with a BVH, replaced by the copy in leaf order below
    g.verts.reserve(n_verts);
    b.bounds.reserve(n_bounded - n_tris);
    b.entries.reserve(n_bounded);
    const size_t errors_before = errors.size();
    bool limit_reported = false;
    for (size_t i = 0; i < shapes.size(); ++i) b.shape(i, limit_reported);
    if (errors.size() > errors_before) return false;
    g.primitive_count = b.next_prim;

    if (use_bvh && !b.entries.empty()) {
        b.finish_bvh();
    } else {
        g.order = std::move(b.entries);
        if (prototype) g.inherits = std::move(b.inherits);
    }
    g.verts.shrink_to_fit();
    g.tris.shrink_to_fit();
    g.order.shrink_to_fit();
    return true;
}

std::unique_ptr<Geometry> Geometry::build(const SceneSpec& spec, std::vector<SpecError>& errors, bool use_bvh,
                                          int threads) {
    auto impl = std::make_unique<Impl>();
    if (!build_geometry_into(*impl, spec, spec.shapes, errors, use_bvh, threads, false)) return nullptr;
    return std::unique_ptr<Geometry>(new Geometry(std::move(impl)));
}

}  // namespace wsd::render
