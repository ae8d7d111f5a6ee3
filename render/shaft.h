// Shaft culling for area-light shadow rays (Haines and Wallace, "Shaft Culling for Efficient
// Ray-Traced Radiosity", 1991): every shadow ray from one shading point to the cells of one area
// light lies in the convex shaft between the point and the light's parallelogram, so one walk of
// the BVH against the shaft finds the few primitives any of those rays can meet.
#pragma once

#include <algorithm>
#include <cmath>

#include "render/math.h"

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
        return true;
    }

    // True when no point of the float box [lo, hi] is in the shaft.
    bool outside(const float* lo, const float* hi) const {
        const double box_scale = std::max({std::abs(double(lo[0])), std::abs(double(lo[1])),
                                           std::abs(double(lo[2])), std::abs(double(hi[0])),
                                           std::abs(double(hi[1])), std::abs(double(hi[2]))});
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

private:
    static double max_abs(const Vec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

    Vec3 normal_[5];     // inward unit normals: inside means dot(n, x) ≥ offset
    double offset_[5] = {};
    double scale_ = 0;
    double margin_ = 0;  // the apex ball's radius plus the rounding margin
};

}  // namespace wsd::render
