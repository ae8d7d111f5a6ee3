// Textures: image (bilinear, sRGB decoded to linear, each file loaded once), checker, and Perlin
// (noise, turbulence, marble, wood) evaluated in the object's frame; also the bump perturbation.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "render/geometry.h"
#include "render/limits.h"
#include "render/scene_spec.h"

namespace wsd::render {

struct Image {
    int width = 0, height = 0;
    std::vector<float> rgb;  // linear, row-major from the top row, 3 floats a pixel
};

// Loads PNG/JPEG/BMP/TGA (sRGB → linear) and HDR and PFM (linear). On failure returns nullptr and sets
// `error` to a message naming the path that was tried and the reason. Images above
// kMaxImagePixels are refused (a 20-byte header can claim 4 billion pixels).
inline constexpr long long kMaxImagePixels = kMaxTexturePixels;
std::shared_ptr<const Image> load_image(const std::string& path, std::string& error);

// Each file is loaded once and shared by every texture that names it.
class ImageCache {
public:
    std::shared_ptr<const Image> get(const std::string& path, std::string& error);

private:
    std::map<std::string, std::shared_ptr<const Image>> images_;
};

class Texture {
public:
    // nullptr + error for a missing/unreadable image.
    static std::unique_ptr<Texture> create(const TextureSpec& spec, ImageCache& cache, std::string& error);
    virtual ~Texture() = default;
    // Image and checker count stats.texture_evals; Perlin kinds count stats.noise_evals once per
    // perlin_noise call (turbulence and marble make L calls, a bump three patterns' worth).
    virtual Color eval(const SurfaceHit& s, RayStats& stats) const = 0;
    // The scalar coefficient in [0, 1] at an object-frame point (Perlin kinds; used by bumps).
    virtual double coef(const Vec3& p, RayStats& stats) const {
        (void)p;
        (void)stats;
        return 0.5;
    }
};

// The bumped shading normal: normalize(n + strength·(f(q), f(q.yzx), f(q.zxy))), f = 2·coef − 1,
// q the object-frame point; the perturbation is taken to world space with the object's rotation.
// Precisely: it is mapped like a normal (inverse transpose of the linear part of object_to_world)
// and then rescaled to its object-frame length, so a uniform scale does not change how far the
// normal bends. Always unit length and finite; returns n itself when strength is 0 or the
// perturbation vanishes (so a zero bump is bit-identical to no bump).
Vec3 bump_normal(const Texture& bump, double strength, const SurfaceHit& s, const Vec3& n,
                 const Mat4& object_to_world, RayStats& stats);

// Ken Perlin's improved noise (2002), range about [-1, 1]; 0 for non-finite input.
double perlin_noise(double x, double y, double z);

// Bilinear lookup with texel centres at ((i + ½)/w, (j + ½)/h): u = 0 is the left edge, v = 0 the
// top edge; u wraps, v is clamped unless wrap_v. Any uv (±0, 1, huge, Inf, NaN) reads only inside
// the image; a non-finite coordinate is treated as 0. An empty image gives black.
Color sample_image(const Image& image, Vec2 uv, bool wrap_v);

// The exact sRGB decoding curve for an 8-bit value (table lookup).
float srgb8_to_linear(uint8_t v);

}  // namespace wsd::render
