// Light inside transmissive objects: Beer–Lambert absorption along a segment. Internal to the
// integrator.
#pragma once

#include <algorithm>
#include <glm/glm.hpp>

#include "render/scene.h"

namespace wsd::render {

inline double max_component(const Vec3& v) {
    return std::max(v.x, std::max(v.y, v.z));
}

// Beer–Lambert transmittance along `distance` world units inside material m.
inline Color absorb(const Material& m, double distance) {
    if (!m.absorbs) return Color(1);
    return glm::exp(-m.absorption * distance);
}

// A ray that never leaves an absorbing medium: 0 where the medium absorbs, 1 where it does not
// (exp(−0·∞) would be NaN).
inline Color absorb_forever(const Material& m) {
    if (!m.absorbs) return Color(1);
    return {m.absorption.x > 0 ? 0.0 : 1.0, m.absorption.y > 0 ? 0.0 : 1.0, m.absorption.z > 0 ? 0.0 : 1.0};
}

}  // namespace wsd::render
