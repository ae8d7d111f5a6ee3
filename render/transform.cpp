// Transform validation, inversion, classification and error propagation (see transform.h).
// The residual of inverse·forward is measured here once, so intersection routines that work in
// object space can widen their "origin on the surface" band by it instead of by a guess.
#include "render/transform.h"

#include <cmath>

namespace wsd::render {

namespace {

double abs_dot(const Vec3& a, const Vec3& b) {
    return std::abs(a.x * b.x) + std::abs(a.y * b.y) + std::abs(a.z * b.z);
}

Vec3 row(const Mat3& m, int i) {
    return {m[0][i], m[1][i], m[2][i]};
}

}  // namespace

Vec3 Transform::point_error(const Vec3& p) const {
    return {gamma(3) * (abs_dot(l[0], p) + std::abs(t.x)), gamma(3) * (abs_dot(l[1], p) + std::abs(t.y)),
            gamma(3) * (abs_dot(l[2], p) + std::abs(t.z))};
}

Vec3 Transform::point_error(const Vec3& p, const Vec3& e) const {
    Vec3 base = point_error(p);
    return {base.x + (1 + gamma(3)) * abs_dot(l[0], e), base.y + (1 + gamma(3)) * abs_dot(l[1], e),
            base.z + (1 + gamma(3)) * abs_dot(l[2], e)};
}

Vec3 Transform::inv_point_error(const Vec3& p) const {
    return {gamma(3) * (abs_dot(il[0], p) + std::abs(it.x)), gamma(3) * (abs_dot(il[1], p) + std::abs(it.y)),
            gamma(3) * (abs_dot(il[2], p) + std::abs(it.z))};
}

std::optional<std::string> make_transform(const Mat4& m, Transform& out) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return std::string("transform has a non-finite entry");
    if (m[0][3] != 0 || m[1][3] != 0 || m[2][3] != 0 || m[3][3] != 1)
        return std::string("transform is not affine");

    Mat3 lin(m);  // upper-left 3×3, column-major
    Vec3 trans(m[3][0], m[3][1], m[3][2]);
    double det = glm::determinant(lin);
    double col_product = glm::length(lin[0]) * glm::length(lin[1]) * glm::length(lin[2]);
    if (!std::isfinite(det) || !std::isfinite(col_product) || !(std::abs(det) > 1e-12 * col_product))
        return std::string("transform is singular (a zero scale or collapsed axes)");
    Mat3 inv = glm::inverse(lin);
    Vec3 inv_t = -(inv * trans);
    for (int c = 0; c < 3; ++c)
        if (!is_finite(inv[c])) return std::string("transform cannot be inverted");
    if (!is_finite(inv_t)) return std::string("transform cannot be inverted");

    Transform t;
    Mat3 normal = glm::transpose(inv);
    for (int i = 0; i < 3; ++i) {
        t.l[i] = row(lin, i);
        t.il[i] = row(inv, i);
        t.nl[i] = row(normal, i);
    }
    t.t = trans;
    t.it = inv_t;
    t.det = det;
    t.identity = (lin == Mat3(1.0)) && trans == Vec3(0.0);

    // Similarity: lᵀl = s²·I up to rounding (a classification tolerance, not a ray epsilon:
    // misclassifying changes the sphere's shape by 1e-10 relative at most).
    Mat3 g = glm::transpose(lin) * lin;
    double s2 = (g[0][0] + g[1][1] + g[2][2]) / 3;
    bool similar = true;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            if (std::abs(g[c][r] - (c == r ? s2 : 0.0)) > 1e-10 * s2) similar = false;
    t.similarity = similar;
    t.scale = std::sqrt(s2);

    // Residual of inv·lin − I and of the translations, each widened by the rounding of its own
    // evaluation so that the bound is conservative.
    Mat3 prod = inv * lin;
    Vec3 inv_of_t = inv * trans;
    for (int i = 0; i < 3; ++i) {
        double rsum = 0, mag = 0;
        for (int j = 0; j < 3; ++j) {
            rsum += std::abs(prod[j][i] - (i == j ? 1.0 : 0.0));
            for (int k = 0; k < 3; ++k) mag += std::abs(inv[k][i] * lin[j][k]);
        }
        t.resid_lin[i] = rsum + gamma(4) * mag;
        double tmag =
            std::abs(inv[0][i] * trans.x) + std::abs(inv[1][i] * trans.y) + std::abs(inv[2][i] * trans.z);
        t.resid_t[i] = std::abs(inv_of_t[i] + inv_t[i]) + gamma(4) * tmag;
    }
    out = t;
    return std::nullopt;
}

}  // namespace wsd::render
