// Emissive surfaces prepared for sampling as lights (wsd-language.md, "indirect light"): every
// shape whose material has an emission and whose surface can be sampled uniformly by area in
// world space — spheres (under a uniform scale), boxes, triangles, meshes and discs. One is chosen
// in proportion to its power (area × mean emission), then a point uniformly on its area, so the
// area density is the same on every point of a shape: mean emission / total power.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "render/scene_spec.h"

namespace wsd::render {

struct EmitterPoint {
    Vec3 p;           // the point on the surface
    Vec3 n;           // the unit geometric normal there (either side)
    Vec3 p_error;     // a bound on p's distance from the surface the geometry intersects
    Color emission;   // its radiance
    double pdf_area;  // the density of choosing it, per unit area
    uint32_t shape;   // the shape it lies on
};

class Emitters {
public:
    // The sampled emitters of `spec` (top-level shapes only). Appends an error for an emissive
    // shape of a sampled kind whose area is zero or not finite. Emissive planes, cylinders, cones,
    // tori, ellipsoids, CSG solids and instances are seen but not sampled (pdf_area() is 0).
    static Emitters build(const SceneSpec& spec, std::vector<SpecError>& errors);

    bool empty() const { return shapes_.empty(); }
    size_t count() const { return shapes_.size(); }
    // A point for the uniform numbers (u0, u1, u2, u3) ∈ [0, 1)⁴.
    EmitterPoint sample(double u0, double u1, double u2, double u3) const;
    // The area density sample() gives a point on shape `shape`, 0 if that shape is not sampled.
    double pdf_area(uint32_t shape) const { return shape < shape_pdf_.size() ? shape_pdf_[shape] : 0.0; }

private:
    enum class Kind : uint8_t { Sphere, Triangles, Disc };
    struct Shape {
        Kind kind = Kind::Triangles;
        uint32_t shape = 0;
        Color emission{0};
        double area = 0;
        Vec3 center{0};           // sphere, disc
        double radius = 0;        // sphere; disc: outer radius in its own frame
        double hole = 0;          // disc: inner radius in its own frame
        Vec3 du{0}, dv{0};        // disc: world images of the disc's own unit axes
        Vec3 normal{0};           // disc: unit world normal
        size_t first = 0, n = 0;  // triangles: range in tris_ / tri_cdf_
    };
    struct Tri {
        Vec3 a, e1, e2, n;  // a + s·e1 + t·e2; unit normal
    };
    std::vector<Shape> shapes_;
    std::vector<double> cdf_;  // over shapes_, by power, ending at 1
    std::vector<Tri> tris_;
    std::vector<double> tri_cdf_;    // per shape's range, by area, each range ending at 1
    std::vector<double> shape_pdf_;  // by SceneSpec shape index
};

// True when `spec` has a material with emission on some shape (or member) that can be seen.
bool has_emission(const SceneSpec& spec);

}  // namespace wsd::render
