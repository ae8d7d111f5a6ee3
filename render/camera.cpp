// Camera frame construction and validation (wsd-language.md §4 "camera"; robustness.md R46, R47).
#include "render/camera.h"

#include <cmath>
#include <numbers>

#include "render/math.h"

namespace wsd::render {

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
    // safe_normalize rescales a vector whose squared length underflows or overflows (a camera
    // at 1e-300, an up of 1e300): a tiny or huge vector keeps its direction.
    const Vec3 forward = safe_normalize(view, Vec3(0.0));
    if (forward == Vec3(0.0)) {
        error = "camera position and look_at must differ";
        return std::nullopt;
    }
    const Vec3 up = safe_normalize(spec.up, Vec3(0.0));
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
