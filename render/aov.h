// Auxiliary images (AOVs) for denoisers and compositors: per camera sample, the albedo and
// shading normal at the first hit that is not a pure mirror or clear glass, and the distance to
// the first hit. They are traced by their own walk, apart from the colour, so that a render
// without them runs exactly the code and gives exactly the image it always did.
//
// Definitions (docs/wsd-cli.md "Auxiliary images"), c the surface colour at the hit:
// - a pure mirror: reflection 1 and no light of its own colour, diffuse·c = ambient·c = 0 in
//   every channel; the walk follows its mirror ray;
// - clear glass: transmission 1, c = <1, 1, 1> and no absorption; the walk follows the refracted
//   ray (the reflected one under total internal reflection);
// - anything else (a partly reflective or tinted surface) ends the walk with its own c and N.
// A walk that misses, or that would pass max_depth reflections and refractions (where the image
// is black too), gives albedo and normal 0.
#pragma once

#include <cstdint>
#include <limits>

#include "render/geometry.h"
#include "render/stats.h"

namespace wsd::render {

class Scene;
struct Material;

// One camera sample's auxiliary values.
struct AovSample {
    Color albedo{0};
    Vec3 normal{0};  // unit, turned to face the ray that reached the surface; 0 where no surface
    double depth = std::numeric_limits<double>::infinity();  // to the first hit; +∞ on a miss
};

// A pixel's samples summed in the order the colour sums them; mean() divides like the colour:
// albedo and normal by every sample, depth by the samples that hit (+∞ when none did).
struct AovSum {
    Color albedo{0};
    Vec3 normal{0};
    double depth = 0;
    int hits = 0;
    int samples = 0;

    void add(const AovSample& s) {
        albedo += s.albedo;
        normal += s.normal;
        if (s.depth < std::numeric_limits<double>::infinity()) {
            depth += s.depth;
            ++hits;
        }
        ++samples;
    }
    AovSample mean() const {
        AovSample m;
        if (samples == 0) return m;
        m.albedo = albedo / double(samples);
        m.normal = normal / double(samples);
        if (hits > 0) m.depth = depth / double(hits);
        return m;
    }
};

// Whether a hit on material m with surface colour c passes the AOV walk on (pure mirror or clear
// glass, as above).
bool aov_pure_mirror(const Material& m, const Color& c);
bool aov_clear_glass(const Material& m, const Color& c);

// One thread's AOV walk. Its rays are counted apart (the render's statistics describe the colour).
class AovTracer {
public:
    explicit AovTracer(const Scene& scene);
    // The auxiliary values of the camera sample at image position (px, py).
    AovSample sample(double px, double py);

private:
    const Scene& scene_;
    RayStats stats_;
};

}  // namespace wsd::render
