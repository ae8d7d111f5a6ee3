// The renderer's scene: geometry (with its BVH), prepared lights, materials with their textures,
// the camera and the settings, plus the effect analysis. Built once by build_scene (renderer.h),
// then shared read-only by every render thread.
#pragma once

#include <memory>
#include <vector>

#include "render/camera.h"
#include "render/effects.h"
#include "render/emitters.h"
#include "render/geometry.h"
#include "render/lights.h"
#include "render/photon_trace.h"
#include "render/renderer.h"
#include "render/texture.h"

namespace wsd::render {

struct Material {
    Color color{1};
    std::unique_ptr<Texture> texture;  // replaces color when set
    std::unique_ptr<Texture> bump;     // Perlin normal perturbation
    double bump_strength = 0;
    double ambient = 0.2;  // resolved: the material's own or settings.ambient
    double diffuse = 1, specular = 0, shininess = 50;
    double reflection = 0, transmission = 0, ior = 1.5;
    Color absorption{0};
    bool absorbs = false;  // transmissive with non-zero absorption
    Color emission{0};     // radiance emitted from both sides
    bool emits = false;    // emission ≠ 0
};

class Scene {
public:
    const Geometry& geometry() const { return *geometry_; }
    const Camera& camera() const { return camera_; }
    const Settings& settings() const { return settings_; }
    const std::vector<Light>& lights() const { return lights_; }
    const std::vector<Material>& materials() const { return materials_; }
    const Mat4& object_to_world(uint32_t shape) const { return object_to_world_[shape]; }
    // The matrix of the shape hit (for a member of an instance, instance · member).
    Mat4 object_to_world(const SurfaceHit& s) const {
        return s.member == SurfaceHit::kNoMember ? object_to_world_[s.shape] : geometry_->member_to_world(s);
    }
    const EffectSet& effects() const { return effects_; }
    // Emissive surfaces sampled as lights (empty unless indirect light is on).
    const Emitters& emitters() const { return emitters_; }
    bool has_multi_cell_area_light() const { return multi_cell_area_light_; }
    // False when the segment a→b certainly crosses no transmissive surface (it misses the
    // bounding boxes of every transmissive shape), so a shadow ray needs no transmissive walk.
    bool may_cross_transmissive(const Vec3& a, const Vec3& b) const;
    double build_seconds() const { return build_seconds_; }
    // The caustic photon map (null without caustics) and how it was built.
    const PhotonMap* caustics() const { return caustics_.map.get(); }
    const CausticBuild& caustic_build() const { return caustics_; }

private:
    friend std::shared_ptr<const Scene> build_scene(const SceneSpec&, std::vector<SpecError>&, bool, int,
                                                    ImageCache*, const std::atomic<bool>*);
    void compute_transmissive_bounds(const SceneSpec& spec);

    std::unique_ptr<Geometry> geometry_;
    Camera camera_;
    Settings settings_;
    std::vector<Light> lights_;
    std::vector<Material> materials_;
    std::vector<Mat4> object_to_world_;
    EffectSet effects_;
    Emitters emitters_;
    struct Bounds {
        Vec3 lo, hi;
    };
    std::vector<Bounds> transmissive_bounds_;  // world boxes, padded; merged when there are many
    bool transmissive_unbounded_ = false;      // a transmissive plane: always walk
    bool multi_cell_area_light_ = false;
    CausticBuild caustics_;
    double build_seconds_ = 0;
};

}  // namespace wsd::render
