// The renderer's entry points: build a scene from a SceneSpec, render it (or a region of it) with
// threads into a linear float film, and report statistics and progress.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "render/scene_spec.h"
#include "render/stats.h"

namespace wsd::render {

struct Film {
    int width = 0, height = 0;  // size of this film (a region's size for tiles)
    std::vector<float> rgb;     // linear RGB, row-major from the top row
};

// The auxiliary images (render/aov.h) of a film, same size and order: all three, or (unless
// requested) none.
struct AovFilm {
    std::vector<float> albedo;  // RGB
    std::vector<float> normal;  // XYZ
    std::vector<float> depth;   // one value a pixel; +∞ where no sample hit
    bool empty() const { return albedo.empty(); }
};

// Half-open pixel rectangle [x0, x1) × [y0, y1) of the full image.
struct Region {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

struct RenderOptions {
    int threads = 0;  // 0 = all cores
    bool use_bvh = true;
    std::optional<Region> region;  // unset: the whole image
    bool adaptive_lights = false;  // force adaptive sampling on every area light
    bool specialise = true;        // false: the unspecialised reference path (tests)
    bool aovs = false;             // also compute the auxiliary images (RenderResult::aovs)
    std::function<void(double fraction, const RayStats& so_far)> progress;  // may be empty
    const std::atomic<bool>* cancel = nullptr;  // set to stop early (render returns false)
};

struct RenderResult {
    Film film;
    AovFilm aovs;  // filled when RenderOptions::aovs
    RayStats stats;
    double build_seconds = 0;
    double render_seconds = 0;
    double photon_seconds = 0;  // building the caustic photon map (part of build_seconds)
    bool cancelled = false;
    std::vector<std::string> effects;  // the effects the scene calls for (see effects.h)
};

class Scene;       // geometry + lights + materials + textures, ready to render
class ImageCache;  // decoded texture images by path (texture.h)

// Builds everything the render needs; nullptr with errors appended on bad input. `images`, when
// given, keeps the decoded texture images for later builds (the frames of an animation read each
// file once); without it each build loads its own.
std::shared_ptr<const Scene> build_scene(const SceneSpec& spec, std::vector<SpecError>& errors,
                                         bool use_bvh = true, int threads = 0, ImageCache* images = nullptr);

RenderResult render(const Scene& scene, const RenderOptions& options);

}  // namespace wsd::render
