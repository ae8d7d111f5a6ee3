// Light validation (robustness.md R45, R63) and preparation of the per-light shading constants.
#include "render/lights.h"

#include <cmath>

#include "render/math.h"

namespace wsd::render {

std::optional<std::string> validate_light(const LightSpec& spec) {
    if (!finite3(spec.position)) return "light position must be finite";
    if (!finite3(spec.color) || spec.color.x < 0 || spec.color.y < 0 || spec.color.z < 0)
        return "light color must be finite and non-negative";
    if (!std::isfinite(spec.intensity) || spec.intensity < 0)
        return "light intensity must be finite and non-negative";
    if (spec.kind == LightKind::Point) return std::nullopt;
    if (spec.kind == LightKind::Spot) {
        if (!finite3(spec.look_at)) return "spot light look_at must be finite";
        if (spec.look_at == spec.position) return "spot light look_at must differ from its position";
        if (!(spec.angle > 0 && spec.angle <= 90) || !(spec.falloff > 0 && spec.falloff <= 90))
            return "spot light angle and falloff must be in (0, 90] degrees";
        if (!(spec.angle <= spec.falloff)) return "spot light angle must not exceed its falloff";
        return std::nullopt;
    }
    if (!finite3(spec.u) || !finite3(spec.v)) return "area light edges u and v must be finite";
    const double lu = glm::length(spec.u), lv = glm::length(spec.v);
    if (!(lu > 0)) return "area light edge u must be non-zero";
    if (!(lv > 0)) return "area light edge v must be non-zero";
    // Parallel edges: the sine of the angle between u and v (dimensionless) vanishes.
    if (!(glm::length(glm::cross(spec.u / lu, spec.v / lv)) > kParallelSine))
        return "area light edges u and v must not be parallel";
    if (spec.samples_u < 1 || spec.samples_v < 1 || spec.samples_u > kMaxLightGridSide ||
        spec.samples_v > kMaxLightGridSide)
        return "area light samples must be between 1 and " + std::to_string(kMaxLightGridSide) +
               " in each direction";
    if (long(spec.samples_u) * long(spec.samples_v) > kMaxLightSamples)
        return "area light sample grid must have at most " + std::to_string(kMaxLightSamples) + " cells";
    return std::nullopt;
}

double cos_degrees(double degrees) {
    if (degrees == 0) return 1;
    if (degrees == 60) return 0.5;
    if (degrees == 90) return 0;
    return std::cos(degrees * (kPi / 180));
}

Light prepare_light(const LightSpec& spec) {
    Light l;
    l.position = spec.position;
    l.radiance = spec.color * spec.intensity;
    if (spec.kind == LightKind::Spot) {
        l.spot = true;
        l.axis = safe_normalize(spec.look_at - spec.position, Vec3(0, -1, 0));
        l.cos_angle = cos_degrees(spec.angle);
        l.cos_falloff = cos_degrees(spec.falloff);
    }
    if (spec.kind == LightKind::Area) {
        l.area = true;
        l.nu = spec.samples_u;
        l.nv = spec.samples_v;
        l.corner = spec.position - 0.5 * spec.u - 0.5 * spec.v;
        l.du = spec.u / double(l.nu);
        l.dv = spec.v / double(l.nv);
        l.uniform = spec.sampling == LightSampling::Uniform;
        l.adaptive = spec.adaptive;
        l.inv_count = 1.0 / double(l.nu * l.nv);
    }
    return l;
}

}  // namespace wsd::render
