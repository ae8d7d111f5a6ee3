// An object's affine transform with its inverse, normal matrix and error bounds: validated once
// (finite, affine, not singular), classified (identity, similarity), and applied to points with
// pbrt-v4's conservative rounding-error propagation (robustness.md: error bounds, offset origins).
#pragma once

#include <optional>
#include <string>

#include "render/math.h"

namespace wsd::render {

struct Transform {
    // Linear part and translation of object→world and world→object (row-major rows of the
    // 3×3 part: l[i] is row i, so x'_i = dot(l[i], x) + t[i]).
    Vec3 l[3]{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    Vec3 t{0, 0, 0};
    Vec3 il[3]{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    Vec3 it{0, 0, 0};
    Vec3 nl[3]{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // normal matrix: inverse transpose of l
    // How far world→object(object→world(p)) can stray from p, per object axis:
    // resid_lin[i]·max|p_j| + resid_t[i]. Grows with the condition number of l.
    Vec3 resid_lin{0, 0, 0};
    Vec3 resid_t{0, 0, 0};
    double det = 1;    // determinant of l
    double scale = 1;  // uniform scale when `similarity`
    bool identity = true;
    bool similarity = true;  // l = scale · orthogonal (rotation, possibly mirrored)

    Vec3 point(const Vec3& p) const { return {dot(l[0], p) + t.x, dot(l[1], p) + t.y, dot(l[2], p) + t.z}; }
    Vec3 vector(const Vec3& v) const { return {dot(l[0], v), dot(l[1], v), dot(l[2], v)}; }
    Vec3 normal(const Vec3& n) const { return {dot(nl[0], n), dot(nl[1], n), dot(nl[2], n)}; }
    Vec3 inv_point(const Vec3& p) const {
        return {dot(il[0], p) + it.x, dot(il[1], p) + it.y, dot(il[2], p) + it.z};
    }
    Vec3 inv_vector(const Vec3& v) const { return {dot(il[0], v), dot(il[1], v), dot(il[2], v)}; }
    // Error bound of point(p) for an exact p, and of point(p) when p carries error `e`.
    Vec3 point_error(const Vec3& p) const;
    Vec3 point_error(const Vec3& p, const Vec3& e) const;
    // Error bound of inv_point(p) for an exact p.
    Vec3 inv_point_error(const Vec3& p) const;

private:
    static double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
};

// Builds a Transform from a 4×4 matrix (GLM column-major). Returns an error message when the
// matrix is not finite, not affine, or singular (|det| ≤ 1e-12 × the product of the column
// lengths, robustness.md, load-time validation), and leaves `out` unspecified.
std::optional<std::string> make_transform(const Mat4& m, Transform& out);

}  // namespace wsd::render
