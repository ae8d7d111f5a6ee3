// The pinhole camera of wsd-language.md §4: a left-handed frame (forward, right, up), vertical
// field of view, pixel (0, 0) at the top left; turns image-plane positions into unit-length rays.
#pragma once

#include <cmath>
#include <optional>
#include <string>

#include "render/geometry.h"
#include "render/scene_spec.h"

namespace wsd::render {

class Camera {
public:
    // nullopt + error for a camera that has no frame: position = look_at, up parallel to the view
    // direction or zero, fov outside (0, 180), a non-finite value, or a non-positive image size.
    static std::optional<Camera> create(const CameraSpec& spec, int width, int height, std::string& error);

    // The ray through image position (px, py) in pixels (pixel centres at half-integers).
    Ray ray(double px, double py) const {
        const double sx = (2.0 * px * inv_width_ - 1.0) * half_width_;
        const double sy = (1.0 - 2.0 * py * inv_height_) * half_height_;
        const Vec3 d = forward_ + sx * right_ + sy * up_;
        return {origin_, d * (1.0 / std::sqrt(glm::dot(d, d)))};
    }

    const Vec3& forward() const { return forward_; }
    const Vec3& right() const { return right_; }
    const Vec3& up() const { return up_; }
    const Vec3& origin() const { return origin_; }

private:
    Vec3 origin_{0}, forward_{0, 0, 1}, right_{1, 0, 0}, up_{0, 1, 0};
    double half_width_ = 1, half_height_ = 1;
    double inv_width_ = 1, inv_height_ = 1;
};

}  // namespace wsd::render
