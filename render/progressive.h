// Progressive rendering (RenderOptions::progressive): passes of stratified camera samples, each
// pixel's samples indexed 0, 1, 2 … so that a pixel's n-th sample is the same whatever happened
// before it, and a pixel's sample count decided by its own estimate (render/pixel_estimate.h),
// its neighbourhood's first pass and the pass's target alone. Even and odd samples are two
// independent scrambles of one (0,2)-sequence (render/sequence.h). A pixel sample is a camera
// sample with everything it shades (one stratified point of each area light, reflections,
// refractions), so more pixel samples refine all of them.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "render/parallel.h"
#include "render/pixel_estimate.h"
#include "render/renderer.h"

namespace wsd::render {

// The sample count a pixel with estimate `e` should reach in a pass whose target is `target`
// (display-space RMS error over its channels; 0 before any estimate exists): `first_samples`
// for a pixel without samples; its own count once it has at least `min_samples` and an error
// of at most the target, or `max_samples`; else about the count that would meet the target,
// between 1.25 and 2 times its count, at least `min_samples` and at most `max_samples`.
//
// Below `min_samples` a pixel may stop only if `calm` (the largest spread of first-pass samples,
// PixelEstimate::display_spread, over the pixel and its eight neighbours) is at most the target:
// a few samples that happen to agree do not prove a pixel flat, but a neighbourhood whose first
// samples all agree rarely hides an edge or a penumbra.
inline constexpr double kNotCalm = std::numeric_limits<double>::infinity();
uint32_t planned_samples(const PixelEstimate& e, double target, const Progressive& options,
                         double calm = kNotCalm);

// The estimated display-space RMSE of the pixels of `part`, a rectangle inside `grid` whose
// pixels `pixels` holds row by row: the root of the mean of their display variances from their
// reporting halves (0 for no pixels).
double estimated_rmse(const std::vector<PixelEstimate>& pixels, const Region& grid, const Region& part);
// The same over all of `pixels`.
inline double estimated_rmse(const std::vector<PixelEstimate>& pixels) {
    const Region all{0, 0, int(pixels.size()), pixels.empty() ? 0 : 1};
    return estimated_rmse(pixels, all, all);
}

class Scene;

// Renders `region` progressively into result.film (and result.aovs when options.aovs), adding
// the rays' counters to result.stats and filling result.progressive. False when cancelled.
bool render_progressive(const Scene& scene, const RenderOptions& options, const Region& region,
                        const ParallelOptions& parallel, RenderResult& result);

}  // namespace wsd::render
