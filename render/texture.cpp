// The texture kinds behind Texture::create (image, checker, Perlin) and the bump perturbation.
// Image decoding and bilinear lookup live in image_texture.cpp, the noise in noise.cpp. Every
// function here returns finite values for any input, NaN included (robustness.md R34, R37).
#include "render/texture.h"

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>

#include "render/noise.h"

namespace wsd::render {

namespace {

class ImageTexture final : public Texture {
public:
    explicit ImageTexture(std::shared_ptr<const Image> image) : image_(std::move(image)) {}
    Color eval(const SurfaceHit& s, RayStats& stats) const override {
        ++stats.texture_evals;
        // Only planes repeat their texture vertically; elsewhere v is clamped (wsd-language §4).
        return sample_image(*image_, s.uv, s.planar);
    }

private:
    std::shared_ptr<const Image> image_;
};

// Cell coordinates are biased by a small fixed fraction of a cell (in texture units, not ray
// space): a box face lying exactly on a cell boundary, like x = 1 for scale 1, then falls in
// one cell consistently instead of flickering with the last bit of the hit point. Valid while
// |coordinate / scale| stays below about 1e8.
constexpr double kCellBias = 0x1p-24;

// 1 if floor(t + bias) is odd, else 0; computed without integer conversion, so any finite t is
// safe. Non-finite coordinates count as even.
inline int cell_parity(double t) {
    if (!std::isfinite(t)) return 0;
    return std::fmod(std::floor(t + kCellBias), 2.0) != 0.0 ? 1 : 0;
}

class CheckerTexture final : public Texture {
public:
    CheckerTexture(double scale, Color c1, Color c2) : inv_scale_(1.0 / scale), c1_(c1), c2_(c2) {}
    // c1 where floor(x/s) + floor(y/s) (+ floor(z/s)) is even, so the cell at the origin is c1.
    Color eval(const SurfaceHit& s, RayStats& stats) const override {
        ++stats.texture_evals;
        int parity = 0;
        if (s.planar) {
            parity = cell_parity(s.plane_xy.x * inv_scale_) ^ cell_parity(s.plane_xy.y * inv_scale_);
        } else {
            const Vec3 t = s.p_object * inv_scale_;
            parity = cell_parity(t.x) ^ cell_parity(t.y) ^ cell_parity(t.z);
        }
        return parity == 0 ? c1_ : c2_;
    }

private:
    double inv_scale_;
    Color c1_, c2_;
};

class PerlinTexture final : public Texture {
public:
    explicit PerlinTexture(const TextureSpec& spec)
        : kind_(spec.perlin),
          scale_(spec.perlin_scale),
          octaves_(spec.octaves),
          c1_(spec.color1),
          c2_(spec.color2) {}
    Color eval(const SurfaceHit& s, RayStats& stats) const override {
        const double c = coef(s.p_object, stats);
        return c * c1_ + (1.0 - c) * c2_;
    }
    double coef(const Vec3& p, RayStats& stats) const override {
        return perlin_pattern(kind_, scale_, octaves_, p, stats.noise_evals);
    }

private:
    PerlinKind kind_;
    Vec3 scale_;
    int octaves_;
    Color c1_, c2_;
};

bool all_finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// v / |v|, scaled first by its largest component so that |v|² cannot overflow or underflow.
// False if v is zero or not finite.
bool safe_normalize(const Vec3& v, Vec3& out) {
    if (!all_finite(v)) return false;
    const double m = std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
    if (!(m > 0.0)) return false;
    const Vec3 w = v / m;
    out = w / std::sqrt(glm::dot(w, w));
    return all_finite(out);
}

}  // namespace

std::unique_ptr<Texture> Texture::create(const TextureSpec& spec, ImageCache& cache, std::string& error) {
    switch (spec.kind) {
        case TextureKind::Image: {
            auto image = cache.get(spec.image_path, error);
            if (!image) return nullptr;
            return std::make_unique<ImageTexture>(std::move(image));
        }
        case TextureKind::Checker:
            if (!(spec.checker_scale > 0.0) || !std::isfinite(spec.checker_scale) ||
                !std::isfinite(1.0 / spec.checker_scale)) {
                error = "checker scale must be a positive finite number";
                return nullptr;
            }
            return std::make_unique<CheckerTexture>(spec.checker_scale, spec.color1, spec.color2);
        case TextureKind::Perlin:
            if (spec.octaves < 0) {
                error = "perlin octaves must not be negative";
                return nullptr;
            }
            if (!all_finite(spec.perlin_scale)) {
                error = "perlin scale must be finite";
                return nullptr;
            }
            return std::make_unique<PerlinTexture>(spec);
    }
    error = "unknown texture kind";
    return nullptr;
}

Vec3 bump_normal(const Texture& bump, double strength, const SurfaceHit& s, const Vec3& n,
                 const Mat4& object_to_world, RayStats& stats) {
    Vec3 fallback;
    if (!safe_normalize(n, fallback) && !safe_normalize(s.ng, fallback)) fallback = Vec3(0, 0, 1);
    // n itself when nothing bends it, bit for bit (R33), provided it is the unit normal it should be.
    const double n2 = glm::dot(n, n);
    const Vec3 unbent = std::isfinite(n2) && std::fabs(n2 - 1.0) <= 0x1p-40 ? n : fallback;
    if (!(strength > 0.0)) return unbent;

    const Vec3& q = s.p_object;
    const Vec3 f(2.0 * bump.coef(q, stats) - 1.0, 2.0 * bump.coef(Vec3(q.y, q.z, q.x), stats) - 1.0,
                 2.0 * bump.coef(Vec3(q.z, q.x, q.y), stats) - 1.0);
    if (f == Vec3(0.0)) return unbent;

    // The perturbation is a gradient-like quantity, so it maps like a normal; keeping its
    // object-frame length makes bump_strength independent of the object's (uniform) scale.
    const glm::dmat3 linear(object_to_world);
    Vec3 d = glm::transpose(glm::inverse(linear)) * f;
    Vec3 dir;
    d = safe_normalize(d, dir) ? dir * std::sqrt(glm::dot(f, f)) : f;

    Vec3 out;
    if (safe_normalize(n + strength * d, out)) return out;
    // n + strength·d overflowed (an absurd strength): its direction tends to d's.
    if (std::isinf(strength) || !all_finite(strength * d)) {
        if (safe_normalize(d, out)) return out;
    }
    return fallback;
}

}  // namespace wsd::render
