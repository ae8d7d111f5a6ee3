// Shaft culling for area-light shadow rays (Haines and Wallace, "Shaft Culling for Efficient
// Ray-Traced Radiosity", 1991): every shadow ray from one shading point to the cells of one area
// light lies in the convex shaft between the point and the light's parallelogram, so one walk of
// the BVH against the shaft finds the few primitives any of those rays can meet
// (ShaftCandidates), and each ray then tests only them. For the renderer's shadow rays; geometry.h
// knows nothing of shafts.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>

#include "render/geometry.h"
#include "render/math.h"
#include "render/stats.h"

namespace wsd::render {

// The shaft from a ball (apex, radius) — which holds every spawn origin of the point — to the
// parallelogram corner + a·u + b·v, a, b ∈ [0, 1]: four side planes through the apex and the
// parallelogram's edges and the parallelogram's own plane as the far cap. `outside` is
// conservative: a box it rejects holds no point of any segment from the ball to the
// parallelogram, with a margin far above the rounding error of its own arithmetic.
class Shaft {
public:
    // False when the shaft is degenerate (the ball touches the light's plane): then no culling.
    bool init(const Vec3& apex, double radius, const Vec3& corner, const Vec3& u, const Vec3& v) {
        const Vec3 q[4] = {corner, corner + u, corner + u + v, corner + v};
        const Vec3 centre = corner + 0.5 * (u + v);
        Vec3 m = glm::cross(u, v);
        const double ml = glm::length(m);
        if (!(ml > 0) || !std::isfinite(ml)) return false;
        m /= ml;
        if (glm::dot(m, centre - apex) < 0) m = -m;
        // Rounding in these doubles is ~1e-16 relative; the margin is a million times that.
        scale_ = max_abs(apex) + radius + max_abs(corner) + max_abs(u) + max_abs(v);
        margin_ = 1e-9 * scale_ + radius;
        const double height = glm::dot(m, centre - apex);
        if (!(height > 2 * margin_)) return false;
        for (int k = 0; k < 4; ++k) {
            Vec3 n = glm::cross(q[(k + 1) % 4] - q[k], apex - q[k]);
            const double nl = glm::length(n);
            if (!(nl > 0) || !std::isfinite(nl)) return false;
            n /= nl;
            if (glm::dot(n, centre - apex) < 0) n = -n;
            normal_[k] = n;
            offset_[k] = glm::dot(n, apex);
        }
        normal_[4] = -m;  // the cap: points past the light's plane are outside
        offset_[4] = glm::dot(-m, centre);
        for (int k = 0; k < 4; ++k) corner_[k] = q[k];
        light_scale_ = max_abs(corner) + max_abs(u) + max_abs(v);
        has_origin_ = false;
        return true;
    }

    // Every shadow ray of this shaft starts exactly at `origin` (the light lies wholly on one
    // side of the surface): enables the plane-side tests below.
    void set_origin(const Vec3& origin) {
        origin_ = origin;
        has_origin_ = true;
    }

    // True when no point of the float box [lo, hi] is in the shaft.
    bool outside(const float* lo, const float* hi) const {
        const double box_scale =
            std::max({std::abs(double(lo[0])), std::abs(double(lo[1])), std::abs(double(lo[2])),
                      std::abs(double(hi[0])), std::abs(double(hi[1])), std::abs(double(hi[2]))});
        const double slack = margin_ + 1e-9 * box_scale;
        for (int k = 0; k < 5; ++k) {
            const Vec3& n = normal_[k];
            // The box corner farthest along n, i.e. the one most inside this plane.
            double best = 0;
            for (int a = 0; a < 3; ++a) best += n[a] * double(n[a] >= 0 ? hi[a] : lo[a]);
            if (best - offset_[k] < -slack) return true;
        }
        return false;
    }

    // True when all three vertices lie outside one of the shaft's planes.
    bool outside_triangle(const Vec3f& a, const Vec3f& b, const Vec3f& c) const {
        const double slack =
            margin_ + 1e-9 * std::max({max_abs(Vec3(a)), max_abs(Vec3(b)), max_abs(Vec3(c))});
        for (int k = 0; k < 5; ++k) {
            const double lim = offset_[k] - slack;
            if (glm::dot(normal_[k], Vec3(a)) < lim && glm::dot(normal_[k], Vec3(b)) < lim &&
                glm::dot(normal_[k], Vec3(c)) < lim)
                return true;
        }
        return false;
    }

    // True when the ball (centre, radius) lies outside one of the shaft's planes.
    bool outside_ball(const Vec3& centre, double radius) const {
        const double slack = margin_ + 1e-9 * (max_abs(centre) + radius) + radius;
        for (int k = 0; k < 5; ++k)
            if (glm::dot(normal_[k], centre) - offset_[k] < -slack) return true;
        return false;
    }

    // With an origin set: true when the origin and the whole light lie strictly on one side of
    // the plane through the triangle a, b, c, so that no shadow ray can meet it (its line meets
    // the plane before its start or beyond the light, and the triangle test's error bound δt
    // rejects a root at or behind the origin). `origin_side` is the origin's side of the plane
    // when it is known by construction (+1 along cross(b − a, c − a), −1 against it; the
    // triangle the shading point lies on), else 0: then it must be certain from the arithmetic.
    bool clear_of_triangle(const Vec3f& a, const Vec3f& b, const Vec3f& c, int origin_side) const {
        if (!has_origin_) return false;
        // A plane perpendicular to an axis: the origin's side is an exact comparison.
        for (int ax = 0; ax < 3; ++ax) {
            if (a[ax] != b[ax] || a[ax] != c[ax]) continue;
            const double k = a[ax];
            const int side = origin_[ax] > k ? 1 : (origin_[ax] < k ? -1 : 0);
            if (side == 0) return false;
            const double slack = 1e-9 * (light_scale_ + std::abs(k));
            for (const Vec3& q : corner_)
                if (!(side * (q[ax] - k) > slack)) return false;
            return true;
        }
        const Vec3 e1 = Vec3(b) - Vec3(a), e2 = Vec3(c) - Vec3(a);
        const Vec3 n = glm::cross(e1, e2);
        const double n_scale = l1(e1) * l1(e2);  // bounds every |n_i| and its rounding
        if (!(n_scale > 0) || !std::isfinite(n_scale)) return false;
        // Rounding of n, of x − a and of the dot product is a few ULPs of n_scale·(|x| + |a|);
        // the bound below is a thousand times that.
        auto side_of = [&](const Vec3& x, double extra) {
            const double s = glm::dot(n, x - Vec3(a));
            const double err = 1e-12 * n_scale * (l1(x) + l1(Vec3(a))) + extra;
            return s > err ? 1 : (s < -err ? -1 : 0);
        };
        int side = origin_side;
        if (side == 0) side = side_of(origin_, 0);
        if (side == 0) return false;
        // Light samples are rounded sums of the corner and edges: allow 1e-9 of their scale.
        const double light_slack = 1e-9 * n_scale * light_scale_;
        for (const Vec3& q : corner_)
            if (side_of(q, light_slack) != side) return false;
        return true;
    }

    // With an origin set: true when the ball (centre, radius) meets every segment from the
    // origin to the light, by a margin of 1e-6 of its radius that dwarfs any rounding, so that
    // each ray's own test must find it. The origin is well outside the ball; the ball lies wholly
    // on the origin's side of the light's plane (a ray entering it has not reached the light);
    // and each corner of the light is seen through the ball's shrunk silhouette: that is a
    // convex cone, so it holds the whole parallelogram when it holds the corners.
    bool blocks_all(const Vec3& centre, double radius) const {
        if (!has_origin_ || !(radius > 0)) return false;
        const Vec3 oc = centre - origin_;
        const double outer = radius * (1 + 1e-6), inner = radius * (1 - 1e-6);
        if (!(glm::dot(oc, oc) > outer * outer)) return false;
        const double slack = 1e-9 * (scale_ + max_abs(centre) + radius);
        if (!(glm::dot(normal_[4], centre) - offset_[4] > outer + slack)) return false;
        for (const Vec3& q : corner_) {
            const Vec3 w = q - origin_;
            if (!(glm::dot(w, oc) > 0)) return false;
            // The distance from the centre to the line through the corner, without cancellation.
            const Vec3 x = glm::cross(w, oc);
            if (!(glm::dot(x, x) < inner * inner * glm::dot(w, w))) return false;
        }
        return true;
    }

    // With an origin set: the same for the plane n·x = c (n unit), the origin's side known
    // (origin_side ≠ 0) or certain.
    bool clear_of_plane(const Vec3& n, double c, int origin_side) const {
        if (!has_origin_) return false;
        auto side_of = [&](const Vec3& x, double extra) {
            const double s = glm::dot(n, x) - c;
            const double err = 1e-12 * (l1(x) + std::abs(c)) + extra;
            return s > err ? 1 : (s < -err ? -1 : 0);
        };
        int side = origin_side;
        if (side == 0) side = side_of(origin_, 0);
        if (side == 0) return false;
        const double light_slack = 1e-9 * light_scale_;
        for (const Vec3& q : corner_)
            if (side_of(q, light_slack) != side) return false;
        return true;
    }

private:
    static double max_abs(const Vec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }
    static double l1(const Vec3& v) { return std::abs(v.x) + std::abs(v.y) + std::abs(v.z); }

    Vec3 normal_[5];  // inward unit normals: inside means dot(n, x) ≥ offset
    double offset_[5] = {};
    double scale_ = 0;
    double margin_ = 0;  // the apex ball's radius plus the rounding margin
    Vec3 corner_[4];     // the light's parallelogram
    double light_scale_ = 0;
    Vec3 origin_{0};
    bool has_origin_ = false;
};

// The surface the shadow rays of a shaft leave: its primitive and geometric normal, and which
// side of it the rays start on (+1 along ng, −1 against it, 0 when they do not share one origin).
struct ShaftSelf {
    uint32_t prim = 0xffffffffu;
    Vec3 ng{0};
    int ng_side = 0;
};

// The opaque primitives that the shadow rays of one shading point towards one area light may
// meet, gathered by one walk of the BVH, so that each of those rays tests only them.
struct ShaftCandidates {
    static constexpr int kMax = 32;  // more than this: not worth it, trace each ray in full
    uint32_t entries[kMax];
    int count = 0;
    bool transmissive = false;  // some transmissive primitive may meet the shaft
    bool blocked = false;       // an opaque sphere meets every ray: all are blocked (Shaft::blocks_all)
    // The transmissive primitives that may meet it, when there are at most kMaxTransmissive
    // (transmissive_listed): the walk through glass then tests only them.
    static constexpr int kMaxTransmissive = 8;
    uint32_t transmissive_entries[kMaxTransmissive];
    int transmissive_count = 0;
    bool transmissive_listed = false;

    // Collects the opaque primitives (planes included) that shadow rays inside `shaft` may meet:
    // those in BVH leaves that meet it, less those a finer test clears (Shaft::outside_*,
    // clear_of_*); `self` is the surface the rays leave. False when there is no BVH or more than
    // kMax of them: then use Geometry::occluded for each ray.
    bool gather(const Geometry& geom, const Shaft& shaft, const ShaftSelf& self, RayStats& stats);
    // geom.occluded(ray, tmax, stats, RayFilter::OpaqueOnly) for a ray that lies inside the
    // shaft these were gathered for: the same answer, testing only these primitives (none when
    // the shaft is known to be blocked).
    bool occluded(const Geometry& geom, const Ray& ray, double tmax, RayStats& stats) const;
    // geom.intersect(ray, tmax, stats, RayFilter::TransmissiveOnly) for a ray inside the shaft,
    // when transmissive_listed: the same hit, testing only the listed primitives.
    std::optional<HitRecord> intersect_transmissive(const Geometry& geom, const Ray& ray, double tmax,
                                                    RayStats& stats) const;
};

// The side of the surface through p with unit normal ng on which the whole parallelogram
// corner + a·u + b·v lies: +1 along ng, −1 against it, 0 when it is not clearly on one side.
// A shadow ray picks its origin by the sign of (P − p)·ng, so with ±1 every ray of the light
// starts at the same origin.
inline int surface_side(const Vec3& p, const Vec3& ng, const Vec3& corner, const Vec3& u, const Vec3& v) {
    auto max_abs = [](const Vec3& x) { return std::max({std::abs(x.x), std::abs(x.y), std::abs(x.z)}); };
    const double slack = 1e-9 * (max_abs(p) + max_abs(corner) + max_abs(u) + max_abs(v));
    const Vec3 q[4] = {corner, corner + u, corner + v, corner + u + v};
    int side = 0;
    for (const Vec3& c : q) {
        const double d = glm::dot(c - p, ng);
        const int s = d > slack ? 1 : (d < -slack ? -1 : 0);
        if (s == 0 || (side != 0 && s != side)) return 0;
        side = s;
    }
    return side;
}

}  // namespace wsd::render
