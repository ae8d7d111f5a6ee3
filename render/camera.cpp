// Camera frame construction and validation (wsd-language.md §4 "camera"; robustness.md R46, R47).
#include "render/camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "render/math.h"

namespace wsd::render {

namespace {

// v as a unit vector, or 0 when it is zero or not finite. A length that would underflow or
// overflow (components near 1e-160 or 1e160) is taken after scaling v by a power of two, so that
// a tiny or huge vector keeps its direction; other vectors are divided by their length as is.
Vec3 direction_of(const Vec3& v) {
    const double len = glm::length(v);
    if (len > 0x1p-500 && len < 0x1p500) return v / len;
    const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
    if (!(m > 0) || !std::isfinite(m)) return Vec3(0.0);
    const int e = -std::ilogb(m);
    const Vec3 s(std::ldexp(v.x, e), std::ldexp(v.y, e), std::ldexp(v.z, e));
    return s / glm::length(s);
}

}  // namespace

std::optional<Camera> Camera::create(const CameraSpec& spec, int width, int height, std::string& error) {
    if (!finite3(spec.position) || !finite3(spec.look_at) || !finite3(spec.up)) {
        error = "camera position, look_at and up must be finite";
        return std::nullopt;
    }
    if (!(spec.fov_degrees > 0.0 && spec.fov_degrees < 180.0)) {
        error = "camera fov must be in (0, 180) degrees";
        return std::nullopt;
    }
    if (width < 1 || height < 1) {
        error = "image size must be at least 1×1";
        return std::nullopt;
    }
    const Vec3 view = spec.look_at - spec.position;
    const Vec3 forward = direction_of(view);
    if (forward == Vec3(0.0)) {
        error = "camera position and look_at must differ";
        return std::nullopt;
    }
    const Vec3 up = direction_of(spec.up);
    if (up == Vec3(0.0)) {
        error = "camera up must be a non-zero vector";
        return std::nullopt;
    }
    Camera cam;
    cam.origin_ = spec.position;
    cam.forward_ = forward;
    const Vec3 side = glm::cross(up, cam.forward_);
    const double side_len = glm::length(side);
    // The sine of the angle between up and the view direction: below this the frame would be
    // dominated by rounding (a validation threshold on a dimensionless quantity, not a ray epsilon).
    if (!(side_len > 1e-9)) {
        error = "camera up is parallel to the view direction (look_at - position)";
        return std::nullopt;
    }
    cam.right_ = side / side_len;
    cam.up_ = glm::cross(cam.forward_, cam.right_);
    cam.half_height_ = std::tan(spec.fov_degrees * std::numbers::pi / 360.0);
    cam.half_width_ = cam.half_height_ * double(width) / double(height);
    cam.inv_width_ = 1.0 / double(width);
    cam.inv_height_ = 1.0 / double(height);
    return cam;
}

}  // namespace wsd::render
