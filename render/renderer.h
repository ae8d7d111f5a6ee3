// The renderer's entry points: build a scene from a SceneSpec, render it (or a region of it) with
// threads into a linear float film, and report statistics and progress.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
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
// requested) none; and the map of samples per pixel, when asked for.
struct AovFilm {
    std::vector<float> albedo;   // RGB
    std::vector<float> normal;   // XYZ
    std::vector<float> depth;    // one value a pixel; +∞ where no sample hit
    std::vector<float> samples;  // samples per pixel, one value a pixel (progressive renders)
    bool empty() const { return albedo.empty() && samples.empty(); }
};

// Half-open pixel rectangle [x0, x1) × [y0, y1) of the full image.
struct Region {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// The units of work of a render's parallel_for: `r` cut into kRenderTile × kRenderTile squares
// (narrower at its right and bottom edges), row by row.
inline constexpr int kRenderTile = 16;
std::vector<Region> render_tiles(const Region& r);

// Progressive rendering (render/progressive.h): a first pass of `first_samples` stratified camera
// samples in every pixel, then passes that add samples where the estimated display-space error
// is largest. With a target, a pixel stops once its own estimate is at most the target and it has
// at least `min_samples` or a calm neighbourhood (planned_samples), so the image does not depend
// on threads or tiles; without
// one, each pass refines the pixels whose error is above the image's current estimate. Passes
// stop when no pixel needs more (or all have `max_samples`), or at the deadline, checked between
// passes.
struct Progressive {
    double target_error = 0;  // > 0: the per-pixel target; 0: none (refine until the deadline)
    std::optional<std::chrono::steady_clock::time_point> deadline;
    int first_samples = 4;
    int min_samples = 16;
    int max_samples = 1024;
};

// What a progressive render reached.
struct ProgressiveReport {
    bool used = false;
    int passes = 0;             // passes run, the first included
    double estimated_rmse = 0;  // display space, over the region's pixels and channels
    uint32_t samples_min = 0, samples_median = 0, samples_max = 0;  // per pixel
    uint64_t samples_total = 0;
    bool target_reached = false;    // every pixel's estimate and the image's at most the target
    bool deadline_reached = false;  // passes stopped because time was up
    bool first_pass_over = false;   // the first pass alone ended after the deadline
    std::vector<float> samples;     // samples per pixel, row-major over the region
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
    std::optional<Progressive> progressive;     // set: progressive passes instead of the grid
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
    ProgressiveReport progressive;     // with RenderOptions::progressive
};

class Scene;       // geometry + lights + materials + textures, ready to render
class ImageCache;  // decoded texture images by path (texture.h)

// Builds everything the render needs; nullptr with errors appended on bad input. `images`, when
// given, keeps the decoded texture images for later builds (the frames of an animation read each
// file once); without it each build loads its own. Once `*cancel` holds true no more caustic
// photons are shot and the build returns nullptr without an error.
std::shared_ptr<const Scene> build_scene(const SceneSpec& spec, std::vector<SpecError>& errors,
                                         bool use_bvh = true, int threads = 0, ImageCache* images = nullptr,
                                         const std::atomic<bool>* cancel = nullptr);

RenderResult render(const Scene& scene, const RenderOptions& options);

}  // namespace wsd::render
